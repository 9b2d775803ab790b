"""Whole-train runs of the ETCS analysis: in batches through the C core (simulation.run_structs, one
C call per batch), on worker processes, each batch written to the output folder as soon as it is
done so that a rerun after a kill skips it. A run's inputs depend only on the analysis (Spec) and
its (state, sample) indices, so a resumed analysis gives the same results bit for bit.
"""

from __future__ import annotations

import concurrent.futures
import functools
import hashlib
import json
import multiprocessing
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from railbrake import atomic, simulation, sizing
from railbrake.errors import InputError
from railbrake.etcs import failures, inputs, scatter
from railbrake.resolve import resolve
from railbrake.units import KMH

BATCH = 32            # runs per C call and per file: bounds what a kill loses
# A run ends at this many times the nominal stopping time: a state with (almost) no brake would
# otherwise run to the scenario's 3600 s; the steps it has not reached by then count as no brake.
MAX_TIME_FACTOR = 10.0
MANIFEST = "etcs-analysis.json"


@dataclass(frozen=True)
class Spec:
    """What an analysis runs: its train, files and settings (hashable, sent to the workers)."""
    train: str
    reliability: str
    scatter: str | None
    cars: int | None
    speed_steps_kmh: tuple
    dry_condition: str
    reduced_condition: str
    kwet_test_speed_kmh: float
    initial_speed_kmh: float | None   # None: the train's maximum speed
    samples: int
    rare_samples: int           # also the size of a block of scatter draws (scatter.block_draws)
    likely_state: float
    state_floor: float
    seed: int
    kdry_bound: float = 0.005   # runs are added until every level's bound is at most this
    run_budget: int = 100_000   # or the analysis has run this many
    replicates: int = 200       # bootstrap replicates (railbrake.etcs.bound)
    force_conditions: bool = False   # run an adhesion condition outside its validity (recorded as a warning)

    def key(self) -> str:
        return hashlib.sha256(json.dumps(asdict(self), sort_keys=True).encode()).hexdigest()[:16]


class Context:
    """An analysis set up once per process: the dry emergency stop's C structs with its speed marks,
    the failure states and the scatter draws."""

    def __init__(self, spec: Spec):
        self.spec = spec
        self.reliability = inputs.load_reliability(spec.reliability)
        self.scatter = inputs.load_scatter(spec.scatter) if spec.scatter else None
        base = simulation.emergency_scenario(spec.train, 1.0, spec.dry_condition)
        train = simulation.scenario_train(base, spec.cars)
        self.train = train
        self.v0 = train.max_speed if spec.initial_speed_kmh is None else spec.initial_speed_kmh * KMH
        self.marks = tuple(v * KMH for v in sorted(spec.speed_steps_kmh, reverse=True) if 0 < v * KMH < self.v0)
        self.structs = self.stop(self.v0, spec.dry_condition)
        nominal = simulation.run_structs([self.structs])[0]
        if isinstance(nominal, Exception) or nominal["stopping_time_s"] is None:
            raise InputError(f"train {spec.train}: the nominal emergency stop from {self.v0 / KMH:.0f} km/h "
                             f"did not stop ({nominal})")
        self.structs[3].max_time = min(self.structs[3].max_time, MAX_TIME_FACTOR * nominal["stopping_time_s"])
        scatter.check_against(self.scatter, self.structs[0], f"scatter file {spec.scatter}")
        self.classes, self.common, self.states = failures.enumerate_states(self.reliability, train, spec.state_floor)
        self._blocks: dict = {}

    def stop(self, v0: float, condition: str) -> tuple:
        """The C structs of an emergency stop from v0 (m/s) on `condition`, with the speed marks."""
        # the reduced-adhesion condition is EN 15595's test level, run at Table 5's test speeds (up
        # to the maximum speed) whatever its validity: forced, and so warned (AdhesionRangeWarning)
        sc = simulation.emergency_scenario(self.spec.train, v0, condition,
                                           allow_outside_validity=condition == self.spec.reduced_condition)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sizing.SupplyWarning)
            plant, bcu, wsp, scen = simulation.structs(resolve(sc, self.spec.cars or len(self.train.cars)))
        scen.n_speed_marks = len(self.marks)
        for i, v in enumerate(self.marks):
            scen.speed_mark[i] = v
        return plant, bcu, wsp, scen

    def samples_of(self, state) -> int:
        if not self.scatter or not self.scatter.quantities():
            return 1
        return self.spec.samples if state.probability >= self.spec.likely_state else self.spec.rare_samples

    def jobs(self) -> list[tuple[int, int]]:
        """The first runs of every state: (state, sample) pairs."""
        return [(s, i) for s, state in enumerate(self.states) for i in range(self.samples_of(state))]

    def draw(self, state: int, sample: int) -> np.ndarray:
        """The scatter factors of a state's sample: from its own blocks of draws."""
        size = self.spec.rare_samples
        key = (state, sample // size)
        if key not in self._blocks:
            if len(self._blocks) > 4096:
                self._blocks.clear()
            self._blocks[key] = scatter.block_draws(self.scatter, len(self.train.cars), size, self.spec.seed,
                                                    state, sample // size)
        return self._blocks[key][sample % size]

    def prepared(self, state: int, sample: int) -> tuple:
        plant, bcu, wsp, scen = self.structs
        plant, bcu = scatter.apply(plant, bcu, self.draw(state, sample))
        failures.set_faults(plant, failures.plant_faults(self.states[state]))
        return plant, bcu, wsp, scen


@functools.lru_cache(maxsize=4)
def context(spec: Spec) -> Context:
    return Context(spec)


def _row(kpis) -> dict:
    if isinstance(kpis, Exception):
        return {"error": str(kpis)}
    marks = kpis["speed_marks"]["distance_m"] if "speed_marks" in kpis else []   # none: one speed step
    return {"stopping_distance_m": kpis["stopping_distance_m"], "marks_m": marks}


def run_batch(spec: Spec, jobs: list) -> list[dict]:
    """The rows of a batch of (state, sample) runs, in one C call."""
    ctx = context(spec)
    return [_row(k) for k in simulation.run_structs([ctx.prepared(s, i) for s, i in jobs])]


def _write_json(path: Path, data) -> None:
    atomic.write_text(path, json.dumps(data))   # all or nothing: a kill leaves no half-written batch


def _open_folder(out: Path, spec: Spec) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    manifest = out / MANIFEST
    if manifest.exists():
        old = json.loads(manifest.read_text())
        if old.get("key") != spec.key():
            raise InputError(f"{out}: holds another analysis ({old.get('spec')}); use an empty folder")
    else:
        _write_json(manifest, {"key": spec.key(), "spec": asdict(spec)})
    (out / "batches").mkdir(exist_ok=True)
    return out / "batches"


def run_all(spec: Spec, jobs: list, out: Path | None = None, workers: int = 1, progress=None) -> dict:
    """{(state, sample): row} of every job, batches already in `out` read back, the others run on
    `workers` processes (1: in this process)."""
    folder = _open_folder(Path(out), spec) if out is not None else None
    groups = [jobs[i:i + BATCH] for i in range(0, len(jobs), BATCH)]
    names = [hashlib.sha256(f"{spec.key()}{g}".encode()).hexdigest()[:20] + ".json" for g in groups]
    rows, pending = {}, []
    for g, name in zip(groups, names):
        if folder is not None and (folder / name).exists():
            rows.update(zip(g, json.loads((folder / name).read_text())))
        else:
            pending.append((g, name))

    def done(g, name, result):
        rows.update(zip(g, result))
        if folder is not None:
            _write_json(folder / name, result)
        if progress is not None:
            progress(len(rows), len(jobs))

    if workers <= 1 or len(pending) <= 1:
        for g, name in pending:
            done(g, name, run_batch(spec, g))
        return rows
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(workers, mp_context=ctx) as pool:
        futures = {pool.submit(run_batch, spec, g): (g, name) for g, name in pending}
        for f in concurrent.futures.as_completed(futures):
            done(*futures[f], f.result())
    return rows
