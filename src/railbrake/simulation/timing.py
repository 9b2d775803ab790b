"""What runs cost: a whole run of a real scenario against its plant alone, and the plant's steps.

``bench`` times what users run (BCU, WSP, KPIs, no recording) and the plant alone on the same
scenario, all in this process; ``bench_plant`` times the plant's steps with constant inputs (the
1 ms real-time budget of an HIL target). CPU time and wall-clock time keep their own names; a
real-time factor is simulated time over wall-clock time.

A shared virtual machine runs the same steps up to 1.6x slower for seconds at a time
(docs/simulation.md), so each figure is the fastest of several runs over a span of wall-clock time,
with the spread over the runs beside it.
"""

from __future__ import annotations

import ctypes
import math
import os
import time

import numpy as np

from railbrake import _core
from railbrake._args import real, whole
from railbrake.resolve import resolve
from railbrake.scenario import load

DEFAULT_SCENARIO = "emergency-300-heavy-rain"
SECONDS = 10.0   # the default span of a bench's runs (s of wall-clock time)
MIN_RUNS = 3
MAX_RUNS = 10_000        # timed runs of one bench: a count beyond this is a typo, not a benchmark
MAX_STEPS = 10_000_000   # steps of one timed run of the plant (10 000 s of it)
MAX_SECONDS = 3600.0     # wall-clock span of a bench's runs
MAX_PASSES = 1000        # passes of rb_run_bench (its own limit)


def _check_counts(runs, seconds):
    """(runs, seconds) checked before anything runs: bench(runs=2**70) would never end."""
    return (None if runs is None else whole("runs", runs, 1, MAX_RUNS),
            real("seconds", seconds, 0.0, MAX_SECONDS, low_open=True))


def _repeat(measure, runs, seconds) -> list:
    """measure() `runs` times, or (runs None) until `seconds` of wall-clock time have passed and
    at least MIN_RUNS were made."""
    end = time.monotonic() + seconds
    made = []
    while len(made) < (runs or MIN_RUNS) or (runs is None and time.monotonic() < end):
        made.append(measure())
    return made


def bench(scenario=DEFAULT_SCENARIO, cars: int | None = 16, kernel: str | None = None, runs: int | None = None,
          seconds: float = SECONDS) -> dict:
    """A whole run of `scenario` (preset or file, as `railbrake run` makes it without recording)
    against its plant alone, in CPU microseconds per simulated millisecond.

    run_cpu_us_per_ms: simulation.run from the resolved configuration (setting the C structs up,
    BCU, WSP, KPIs; CPU time of this process); core_run_cpu_us_per_ms: the same run inside C alone;
    plant_cpu_us_per_ms: a fresh plant stepped through the inputs the BCU gave it in that run
    (rb_run_bench, alternating passes); ratio = run / plant. realtime_factor: simulated time over
    the run's wall-clock time. resolve_cpu_s: reading and checking the files once (kept for the next
    runs). `runs` of each, or as many whole runs as fit in half of `seconds` (at least 3) and as many
    passes inside C as fit in the other half; each figure is its fastest, the whole runs' median
    beside it."""
    from railbrake.simulation import parameters, runs as running
    runs, seconds = _check_counts(runs, seconds)
    cars = None if cars is None else whole("cars", cars, 1, _core.PLANT_MAX_CARS)
    t0 = time.process_time()
    resolved = resolve(scenario, cars)
    resolve_cpu = time.process_time() - t0
    n_cars = resolved.cars
    plant = parameters.plant_params(resolved.scenario, n_cars, kernel=kernel, train=resolved.train)

    def whole_run() -> tuple[float, float]:
        c0, w0 = time.process_time(), time.perf_counter()
        running.run(resolved, kernel=kernel, record=False)
        return time.process_time() - c0, time.perf_counter() - w0

    made = _repeat(whole_run, runs, seconds / 2)
    # as many passes of the run and its plant alone inside C as fill the other half of the span:
    # each figure is the fastest of many, so neither gains from a faster stretch of the machine
    fit = int(seconds / 2 / (2 * min(w for _, w in made)))
    passes = min(runs, MAX_PASSES) if runs else max(MIN_RUNS, min(MAX_PASSES, fit))
    core = _core_bench(resolved, plant, passes)
    simulated_ms = core["steps"] * plant.dt * 1e3
    cpu, wall = min(made)
    per_ms = [c * 1e6 / simulated_ms for c, _ in made]
    return {"scenario": resolved.scenario.name, "cars": n_cars, "kernel": core["kernel"],
            "simulated_s": simulated_ms / 1e3, "runs": len(made),
            "run_cpu_us_per_ms": cpu * 1e6 / simulated_ms,
            "run_cpu_us_per_ms_median": float(np.median(per_ms)),
            "core_run_cpu_us_per_ms": core["run_us"] / (plant.dt * 1e3),
            "plant_cpu_us_per_ms": core["plant_us"] / (plant.dt * 1e3),
            "ratio": cpu * 1e6 / simulated_ms / (core["plant_us"] / (plant.dt * 1e3)),
            "core_ratio": core["run_us"] / core["plant_us"],
            "run_wall_s": wall, "realtime_factor": simulated_ms / 1e3 / wall,
            "resolve_cpu_s": resolve_cpu, "load_average": _load_average()}


def _core_bench(resolved, plant, passes: int) -> dict:
    """rb_run_bench: the whole run inside C against the plant alone on its recorded inputs, the
    fastest of `passes` alternating passes."""
    from railbrake.simulation import parameters
    sc = resolved.scenario
    _, bcu, wsp, spec = parameters.structs(resolved)
    state = ctypes.create_string_buffer(_core.rb_run_state_size())
    max_steps = int(math.ceil(sc.spec.stop.max_time / plant.dt)) + 2
    trace = (_core.PlantInputs * max_steps)()   # 384 B a step: 0.35 GB for a 900 s run, 1.4 GB at 3600 s
    result = _core.RunBenchResult()
    _core.call(_core.rb_run_bench, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(wsp), ctypes.byref(spec),
               passes, state, trace, max_steps, ctypes.byref(result))
    return {"steps": result.steps, "run_us": result.run_us, "plant_us": result.plant_us,
            "kernel": result.kernel.decode()}


def bench_plant(cars: int = 16, steps: int = 20000, kernel: str | None = None, runs: int | None = None,
                seconds: float = SECONDS) -> dict:
    """The plant alone at 1 ms with the brakes applied on dry rail, timed in C (rb_plant_bench).

    The plant is timed in runs of `steps` steps (the figures: the fastest run's, by CPU time;
    realtime_factor_median and _slowest the spread). step_us_cpu_mean: the timing thread's CPU time
    per step (other processes do not count); step_us_wall_mean: wall-clock; realtime_factor: 1 ms
    over the wall-clock step; p99 and max: wall-clock times of single steps; load_average: the
    machine's 1-minute load when the runs ended."""
    from railbrake.simulation import parameters
    runs, seconds = _check_counts(runs, seconds)
    cars = whole("cars", cars, 1, _core.PLANT_MAX_CARS)
    steps = whole("steps", steps, 1, MAX_STEPS)
    sc = load("emergency-250-dry")
    plant = parameters.plant_params(sc, cars, kernel=kernel)
    timed = _repeat(lambda: _plant_run(plant, steps), runs, seconds)
    best = min(timed, key=lambda f: f["step_us_cpu_mean"])
    factors = sorted(plant.dt * 1e6 / f["step_us_wall_mean"] for f in timed)
    return {"cars": cars, "realtime_factor": plant.dt * 1e6 / best["step_us_wall_mean"], **best,
            "substeps": plant.substeps, "runs": len(timed), "realtime_factor_median": float(np.median(factors)),
            "realtime_factor_slowest": factors[0], "load_average": _load_average()}


def _plant_run(plant: _core.PlantParams, steps: int) -> dict:
    """One run of rb_plant_bench (its own initial state): the step times in us and the kernel used."""
    mean, p99, largest, wall = ctypes.c_double(), ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
    used = ctypes.create_string_buffer(32)
    supply = plant.car[0].vehicle.supply_pressure
    _core.call(_core.rb_plant_bench, ctypes.byref(plant), supply, steps, ctypes.byref(mean),
               ctypes.byref(p99), ctypes.byref(largest), ctypes.byref(wall), used, ctypes.sizeof(used))
    return {"step_us_cpu_mean": mean.value, "step_us_p99": p99.value, "step_us_max": largest.value,
            "step_us_wall_mean": wall.value, "kernel": used.value.decode()}


def _load_average() -> float | None:
    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):   # not on every system
        return None
