"""Whole-train runs of the ETCS analysis: in batches through the C core (simulation.run_structs, one
C call per batch), as a study on the campaign engine (railbrake.campaign.execute: a local Dask
cluster of `workers` processes or an existing scheduler; one worker and no scheduler: in this
process), each batch written to the output folder as soon as it is done so that a rerun after a
kill skips it. A run's inputs depend only on the analysis (Spec) and its (state, sample) indices,
so a resumed analysis gives the same results bit for bit, whatever the workers.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
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
    step_ms: float = 1.0        # the plant's step in the runs of the mixture (data/etcs/method.yaml)

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
        self.structs = self.stop(self.v0, spec.dry_condition, spec.step_ms * 1e-3)
        nominal = simulation.run_structs([self.structs])[0]
        if isinstance(nominal, Exception) or nominal["stopping_time_s"] is None:
            raise InputError(f"train {spec.train}: the nominal emergency stop from {self.v0 / KMH:.0f} km/h "
                             f"did not stop ({nominal})")
        self.structs[3].max_time = min(self.structs[3].max_time, MAX_TIME_FACTOR * nominal["stopping_time_s"])
        scatter.check_against(self.scatter, self.structs[0], f"scatter file {spec.scatter}")
        self.classes, self.common, self.states = failures.enumerate_states(self.reliability, train, spec.state_floor)
        self._blocks: dict = {}

    def stop(self, v0: float, condition: str, dt: float = simulation.DT) -> tuple:
        """The C structs of an emergency stop from v0 (m/s) on `condition` at the plant step dt (s),
        with the speed marks."""
        # the reduced-adhesion condition is EN 15595's test level, run at Table 5's test speeds (up
        # to the maximum speed) whatever its validity: forced, and so warned (AdhesionRangeWarning)
        sc = simulation.emergency_scenario(self.spec.train, v0, condition,
                                           allow_outside_validity=condition == self.spec.reduced_condition)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sizing.SupplyWarning)
            plant, bcu, wsp, scen = simulation.structs(resolve(sc, self.spec.cars or len(self.train.cars)), dt=dt)
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

    def train_draws(self, state: int, samples: list, quantity: str) -> np.ndarray:
        """A tolerance drawn per train: its factor in each of a state's samples (those its runs had)."""
        q = scatter.QUANTITIES.index(quantity)
        return np.array([self.draw(state, i)[q, 0] for i in samples])

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


class Runner:
    """Runs an analysis' jobs: in this process (one worker, no scheduler) or on the campaign
    engine's Dask client (railbrake.campaign.execute.connect, handed_out), held open for the whole
    analysis (its rounds of added runs); the output folder locked as a campaign's is (campaign.lock).
    Use as a context manager."""

    def __init__(self, spec: Spec, out: Path | None = None, workers: int = 1, scheduler: str | None = None,
                 progress=None, connect_timeout: float | None = None):
        from railbrake.campaign import execute
        execute._check_counts(workers=workers)
        self.spec, self.out, self.workers, self.progress = spec, out, workers, progress
        self.scheduler = execute.scheduler_address(scheduler)
        self.timeout = connect_timeout or execute.CONNECT_TIMEOUT
        self.client = self.cluster = self.folder = None
        self.done = self.total = 0
        self._stack = contextlib.ExitStack()

    def __enter__(self) -> "Runner":
        from railbrake.campaign import lock
        if self.out is not None:
            self._stack.enter_context(lock.holding(Path(self.out), "railbrake etcs braking-model"))
        return self

    def __exit__(self, *exc) -> None:
        from railbrake.campaign import execute
        try:
            if self.client is not None:
                with execute._no_interrupt():   # a second Ctrl-C must not break the cluster's shutdown
                    self.client.close()
                    if self.cluster is not None:
                        self.cluster.close()
        finally:
            self._stack.close()

    def _connected(self):
        if self.client is None:
            from railbrake.campaign import execute
            self.client, self.cluster = execute.connect(self.scheduler, self.workers, self.timeout)
        return self.client

    def run(self, jobs: list) -> dict:
        """{(state, sample): row} of every job, batches already in the folder read back."""
        if self.out is not None and self.folder is None:   # at the first runs: inputs refused before leave none
            self.folder = _open_folder(Path(self.out), self.spec)
        groups = [jobs[i:i + BATCH] for i in range(0, len(jobs), BATCH)]
        names = [hashlib.sha256(f"{self.spec.key()}{g}".encode()).hexdigest()[:20] + ".json" for g in groups]
        rows, pending = {}, []
        for g, name in zip(groups, names):
            if self.folder is not None and (self.folder / name).exists():
                rows.update(zip(g, json.loads((self.folder / name).read_text())))
            else:
                pending.append((g, name))
        self.done += len(rows)
        self.total += len(jobs)
        for (g, name), result in self._results(pending):
            rows.update(zip(g, result))
            if self.folder is not None:
                _write_json(self.folder / name, result)
            self.done += len(g)
            if self.progress is not None:
                self.progress(self.done, self.total)
        return rows

    def _results(self, pending: list):
        """(group, rows) of each pending batch as it completes."""
        if not pending:
            return
        if self.workers <= 1 and self.scheduler is None:
            for item in pending:
                yield item, run_batch(self.spec, item[0])
            return
        from railbrake.campaign import execute
        client = self._connected()
        ahead = max(1, len(client.scheduler_info()["workers"])) * execute.IN_FLIGHT_PER_WORKER
        tasks = ((run_batch, (self.spec, g), f"railbrake-etcs-{name[:20]}", (g, name)) for g, name in pending)
        results = execute.handed_out(client, tasks, ahead)
        with contextlib.closing(results):
            yield from results


def run_all(spec: Spec, jobs: list, out: Path | None = None, workers: int = 1, progress=None,
            scheduler: str | None = None) -> dict:
    """{(state, sample): row} of every job (Runner.run, its own Runner)."""
    with Runner(spec, out, workers, scheduler, progress) as runner:
        return runner.run(jobs)
