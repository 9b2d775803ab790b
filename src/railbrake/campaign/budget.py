"""How large a study is before any of it is drawn: its run count from the design alone, and the time
and memory to plan and to run it, estimated from one run of the study measured on this machine.

A design above the limit (MAX_RUNS unless raised with --max-runs) is refused before its points, its
levels or its noise seeds are allocated: a typo such as `samples: 1000000000` ends in a message
with the figures, not in a machine out of memory.
"""

from __future__ import annotations

import math
import time
import tracemalloc

from railbrake.errors import InputError

# runs a study may have unless raised (--max-runs, max_runs=): 20 times the EN 15595 preset's grid
# repeated over 1000 seeds is far beyond any study in docs/campaigns.md; planning alone resolves
# each run (about as long as loading a scenario), so this many take minutes, not days.
MAX_RUNS = 100_000


def design_runs(kind: str, samples: int | None, levels: list[int], points: int) -> int:
    """Design points of a design of `kind` (exact integers, nothing allocated)."""
    if kind == "grid":
        return math.prod(levels)
    if kind == "zip":
        return levels[0] if levels else 1
    if kind == "latin-hypercube":
        return samples or 0
    if kind == "sobol":   # Saltelli: A, B and one AB_i per factor
        return (samples or 0) * (len(levels) + 2)
    return points


def describe(kind: str, samples: int | None, levels: list[int], seeds: int) -> str:
    if kind == "grid":
        shape = " x ".join(str(n) for n in levels) or "1"
        design = f"grid of {shape} levels"
    elif kind == "zip":
        design = f"zip of {levels[0] if levels else 1} levels"
    elif kind == "sobol":
        design = f"sobol, {samples} samples x ({len(levels)} factors + 2)"
    else:
        design = f"{kind} of {samples} samples" if samples is not None else kind
    return f"{design} x {seeds} seed{'s' if seeds != 1 else ''}"


def refuse(where: str, runs: int, detail: str, max_runs: int, measure) -> None:
    """InputError: `runs` runs over the limit, with the estimate of measure() -> (plan s, plan bytes,
    run s per run)."""
    plan_s, plan_bytes, run_s = measure()
    raise InputError(f"{where}: {runs:,} runs ({detail}) exceed the limit of {max_runs:,} runs: planning them "
                     f"would take about {_duration(plan_s * runs)} and {_size(plan_bytes * runs)} of memory, "
                     f"running them up to {_duration(run_s * runs)} of CPU time (estimated from one run "
                     "measured here); make the design smaller, or raise the limit with --max-runs N "
                     "(campaign plan, campaign run, wsp tune) or study.load(..., max_runs=N)")


def measure_one(base: str, sets: dict) -> tuple[float, float, float]:
    """(s, bytes) to plan one run of `base` with `sets`, and the CPU time (s) to run it, up to its
    stop.max_time: the plant's step time measured by a short bench of the run's train length."""
    from railbrake import simulation
    from railbrake.campaign import configuration
    tracemalloc.start()
    start = time.perf_counter()
    try:
        resolved = configuration.resolve(base, sets)
        plan_s = time.perf_counter() - start
        plan_bytes = tracemalloc.get_traced_memory()[0]
    finally:
        tracemalloc.stop()
    steps = resolved.scenario.spec.stop.max_time / simulation.DT
    step_s = simulation.bench_plant(cars=resolved.cars, steps=1000, runs=1)["step_us_cpu_mean"] * 1e-6
    return plan_s, plan_bytes, steps * step_s


def _duration(seconds: float) -> str:
    for unit, size in (("years", 3.15e7), ("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


def _size(nbytes: float) -> str:
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if nbytes >= size:
            return f"{nbytes / size:.3g} {unit}"
    return f"{nbytes:.3g} bytes"
