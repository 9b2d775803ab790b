"""Running a study on dask.distributed: a LocalCluster (one single-threaded worker process per
core) or an existing scheduler (``--scheduler tcp://HOST:PORT`` or DASK_SCHEDULER_ADDRESS).

Runs go in batches, several per worker, so that scheduling stays a small share of the run time
(bench/bench_campaign.py measures it) while a kill loses only the batches in flight. The batches
are planned and handed out as the workers need them, so the client holds the study's keys and
the batches in flight, never the whole study. Each batch is written to the dataset as soon as it
returns; a rerun skips the keys already there.
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import signal
import threading
import time
import warnings
from dataclasses import asdict, dataclass, field
from pathlib import Path

from railbrake import atomic
from railbrake._args import whole
from railbrake.campaign import dataset, identity, lock
from railbrake.campaign.plan import Run, iter_plan
from railbrake.campaign.study import Study
from railbrake.errors import InputError

BATCHES_PER_WORKER = 8      # enough for the load to balance at the end of a study
IN_FLIGHT_PER_WORKER = 3    # batches handed out ahead per worker: none waits for the next one
MAX_BATCH = 32              # runs; bounds what a kill loses
CONNECT_TIMEOUT = 10.0      # s for a scheduler to answer
START_ATTEMPTS = 3          # a local cluster whose worker was lost while starting is started again
RETRIES = 2                 # a batch whose worker died is rerun by Dask; these are for other errors


@dataclass
class Summary:
    runs: int
    done: int
    skipped: int
    failed: int
    dataset: str
    interrupted: bool = False
    workers: int = 0
    batches: int = 0
    elapsed_s: float = 0.0          # from the first batch submitted to the last written
    compute_s: float = 0.0          # sum of the batches' time on the workers (wall clock)
    compute_cpu_s: float = 0.0      # and their CPU time
    scheduler_share: float | None = None   # of the workers' time until their last batch: waiting
    #                                        for a batch (dispatch, transfer), not running one
    tail_share: float | None = None        # of workers x elapsed: idle after their last batch
    extra: dict = field(default_factory=dict)

    def json(self) -> dict:
        return {k: v for k, v in asdict(self).items() if k != "extra"}


def scheduling_figures(submitted: float, ended: float, spans: list[tuple[str, float, float]]) -> tuple:
    """(scheduler share, tail share) from the (worker, began, ended) of each batch (wall clock).
    Scheduling: a worker's gaps between its batches (result sent, next batch dispatched) over its
    time from its first batch's start to its last one's end; a worker's start-up (imports before
    its first batch) is not scheduling and is left out. Tail: idle after a worker's last batch."""
    by_worker: dict = {}
    for worker, began, end in spans:
        by_worker.setdefault(worker, []).append((began, end))
    span = waiting = tail = 0.0
    for items in by_worker.values():
        first, last = min(b for b, _ in items), max(e for _, e in items)
        span += last - first
        waiting += (last - first) - sum(e - b for b, e in items)
        tail += max(0.0, ended - last)
    if span <= 0:
        return None, None
    return max(0.0, waiting / span), tail / (span + tail)


def scheduler_address(option: str | None) -> str | None:
    return option or os.environ.get("DASK_SCHEDULER_ADDRESS") or None


def connect(scheduler: str | None, workers: int | None, timeout: float = CONNECT_TIMEOUT,
            dashboard: str | None = None):
    """(client, cluster or None). A scheduler that does not answer is an InputError. dashboard:
    the local cluster's dashboard address (e.g. "127.0.0.1:8787", ":0" for any free port; None:
    none): client.dashboard_link then names it."""
    from dask.distributed import Client, LocalCluster
    if scheduler:
        try:
            client = Client(scheduler, timeout=timeout)
            client.wait_for_workers(1, timeout=timeout)
        except (OSError, TimeoutError) as exc:
            raise InputError(f"--scheduler {scheduler}: no Dask scheduler with workers answers within "
                             f"{timeout:g} s ({exc.__class__.__name__}); start one with 'dask scheduler' "
                             "and 'dask worker' (docs/campaigns.md)") from None
        return client, None
    n = workers or os.cpu_count() or 1
    # the scheduler's HTTP routes move to a free port by themselves; the warning only alarms
    warnings.filterwarnings("ignore", message="Port .* is already in use")
    if n < 1:
        raise InputError(f"--workers {n}: must be at least 1")
    # one thread per worker process, numpy's BLAS included: the workers share the cores already
    single = {name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")}
    for attempt in range(1, START_ATTEMPTS + 1):
        try:
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=dashboard,
                                   worker_dashboard_address=None, silence_logs=logging.ERROR, env=single)
            return Client(cluster), cluster
        except Exception as exc:   # noqa: BLE001 - e.g. "Nanny failed to start worker process"
            # a worker process lost while it starts: LocalCluster has closed what it had started
            if attempt == START_ATTEMPTS:
                raise InputError(f"--workers {n}: the local Dask cluster failed to start {START_ATTEMPTS} times "
                                 f"({exc.__class__.__name__}: {exc})") from None
            warnings.warn(f"a Dask worker was lost while the local cluster started ({exc.__class__.__name__}: "
                          f"{exc}); starting it again ({attempt + 1} of {START_ATTEMPTS})", RuntimeWarning,
                          stacklevel=2)


def batch_size_for(pending: int, workers: int, size: int | None = None) -> int:
    return size or max(1, min(MAX_BATCH, math.ceil(pending / (workers * BATCHES_PER_WORKER))))


def batches(runs, size: int):
    """The runs (any iterable) in lists of `size`, one list at a time."""
    group = []
    for run in runs:
        group.append(run)
        if len(group) == size:
            yield group
            group = []
    if group:
        yield group


def _manifest(study: Study, out: Path, kpis: list[str] | None, n_runs: int) -> dict:
    old = dataset.read_manifest(out) or {}
    factors = {f.name: f.unit for f in study.factors}
    if old and (old.get("factors") != factors or old.get("study") != study.name):
        raise InputError(f"--out {out}: holds study {old.get('study')!r} with factors "
                         f"{', '.join(old.get('factors', {}))}; use another folder")
    return {"schema": "railbrake.campaign/1", "study": study.name, "base": study.spec.base,
            "factors": factors, "factor_order": list(factors), "kinds": {f.name: f.kind for f in study.factors},
            "kpis": kpis if kpis is not None else old.get("kpis"), "kpi_kinds": old.get("kpi_kinds"),
            "runs": n_runs,
            "design": study.spec.design.kind, "samples": study.spec.design.samples,
            "railbrake_version": identity.railbrake_version(), "core_build_hash": identity.core_build_hash()}


def _options(study: Study, out: Path, timeseries: bool) -> dict:
    options = {"out": str(out), "timeseries": timeseries or study.spec.timeseries}
    if study.spec.assessment is not None:
        from railbrake.campaign.assess import reference_values
        options["build_up"] = True   # te measured on the reference runs (worker.equivalent_response_time)
        options["build_up_reference"] = reference_values(study.spec.assessment)
    return options


def _payload(run: Run) -> dict:
    return {"key": run.key, "index": run.index, "point": run.point, "replicate": run.replicate,
            "seed": run.seed, "block": run.block, "sample": run.sample, "sets": run.sets,
            "factors": run.factors}


class _Writer:
    """Writes finished batches; the KPI columns are fixed by the first successful run."""

    def __init__(self, study: Study, out: Path, manifest: dict):
        self.study, self.out, self.manifest = study, out, manifest
        self.waiting: list[dict] = []
        self.failed = self.written = 0

    def _schema(self):
        return dataset.schema(self.study.factors, self.manifest["kpis"], {"name": self.study.name},
                              self.manifest.get("kpi_kinds"))

    def add(self, rows: list[dict]) -> None:
        self.failed += sum(r["status"] != dataset.STATUS_OK for r in rows)
        if self.manifest.get("kpis") is None:
            ok = next((r for r in rows if r["status"] == dataset.STATUS_OK), None)
            if ok is None:
                self.waiting.append(rows)
                return
            self.manifest["kpis"] = list(ok["kpis"])
            self.manifest["kpi_kinds"] = dataset.kpi_kinds(ok["kpis"])
            dataset.write_manifest(self.out, self.manifest)
        for batch in [b for b in self.waiting + [rows] if b]:
            dataset.write_batch(self.out, batch, self._schema())
            self.written += len(batch)
        self.waiting = []

    def finish(self) -> None:
        if self.waiting:   # every run failed: no KPI columns to be had
            self.manifest["kpis"] = []
            dataset.write_manifest(self.out, self.manifest)
            self.add([])


def _check_counts(**counts) -> None:
    """Worker and batch counts are None (automatic) or at least 1 (0 would silently mean automatic)."""
    for name, value in counts.items():
        if value is not None:
            whole(name, value, 1)


def run_study(study: Study, out: Path, workers: int | None = None, scheduler: str | None = None,
              batch_size: int | None = None, timeseries: bool = False, progress=None,
              connect_timeout: float = CONNECT_TIMEOUT, dashboard: str | None = None,
              on_connect=None) -> Summary:
    """Run what the dataset in `out` lacks. progress(done, total, failed) after each batch;
    dashboard: the local cluster's dashboard address (connect); on_connect(client) once connected
    (e.g. to show client.dashboard_link). One client at a time on out (campaign.lock): a second
    is refused naming the first's host and PID."""
    _check_counts(workers=workers, batch_size=batch_size)
    out = Path(out)
    with lock.holding(out):
        return _run_held(study, out, workers, scheduler, batch_size, timeseries, progress, connect_timeout,
                         dashboard, on_connect)


def _run_held(study, out, workers, scheduler, batch_size, timeseries, progress, connect_timeout, dashboard,
              on_connect) -> Summary:
    # the study's keys are the one list held whole (identical configurations run once); the runs
    # are planned again one at a time as they are handed out
    keys = list(dict.fromkeys(r.key for r in iter_plan(study)))
    done = dataset.existing_keys(out, keys)   # verified; the study's keys recorded
    n_pending = sum(k not in done for k in keys)
    summary = Summary(len(keys), 0, len(keys) - n_pending, 0, str(out))
    if not n_pending and dataset.read_manifest(out):
        return summary
    client, cluster = connect(scheduler_address(scheduler), workers, connect_timeout, dashboard)
    if on_connect is not None:
        on_connect(client)
    try:
        out.mkdir(parents=True, exist_ok=True)
        dataset.record_study_keys(out, keys)
        del keys
        dataset.clean(out)
        manifest = _manifest(study, out, None, summary.runs)
        dataset.write_manifest(out, manifest)
        atomic.write_text(out / "study.yaml", study.text)
        summary.workers = len(client.scheduler_info()["workers"])
        if progress:
            progress(0, n_pending, 0)
        size = batch_size_for(n_pending, summary.workers, batch_size)
        _execute(client, study, out, manifest, batches(_pending(study, done), size),
                 _options(study, out, timeseries), summary, progress, n_pending)
        return summary
    finally:
        with _no_interrupt():   # a second Ctrl-C must not break the cluster's shutdown
            client.close()
            if cluster is not None:
                cluster.close()


@contextlib.contextmanager
def _no_interrupt():
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _pending(study: Study, done: set):
    """The study's runs not in the dataset, each key once, planned one at a time."""
    seen = set(done)
    for run in iter_plan(study):
        if run.key not in seen:
            seen.add(run.key)
            yield run


def handed_out(client, tasks, ahead: int):
    """(tag, result) of each task as it completes. tasks: an iterator of (function, args, key, tag),
    submitted `ahead` at a time and the next one as each completes, so that the client holds only
    those in flight. Interrupted (KeyboardInterrupt, or the consumer stops), the tasks in flight
    are cancelled. The one dispatch loop of the campaign engine: studies (run_study) and the ETCS
    analysis (railbrake.etcs.runs) both run through it."""
    from dask.distributed import as_completed
    futures = as_completed()
    in_flight: dict = {}

    def submit_next() -> None:
        item = next(tasks, None)
        if item is None:
            return
        function, args, key, tag = item
        future = client.submit(function, *args, key=key, pure=False, retries=RETRIES)
        futures.add(future)
        in_flight[future] = tag

    for _ in range(max(1, ahead)):
        submit_next()
    try:
        for future in futures:
            tag = in_flight.pop(future)
            result = future.result()
            submit_next()
            yield tag, result
    finally:
        if in_flight:
            with _no_interrupt():
                client.cancel(list(in_flight))


def _execute(client, study, out, manifest, groups, options, summary, progress, total) -> None:
    """Hands the batches out as the workers finish them, IN_FLIGHT_PER_WORKER per worker at a time:
    the client holds those and the dataset's index, not the study."""
    writer = _Writer(study, out, manifest)
    start, submitted, spans = time.perf_counter(), time.time(), []

    def tasks():
        for group in groups:
            summary.batches += 1
            yield (_batch_task, (study.base, [_payload(r) for r in group], options),
                   f"railbrake-{dataset.batch_name([r.key for r in group])[5:25]}", None)

    results = handed_out(client, tasks(), max(1, summary.workers) * IN_FLIGHT_PER_WORKER)
    try:
        with contextlib.closing(results):   # an error here cancels the batches in flight
            for _, result in results:
                _pass_on_warnings(result["rows"], summary)
                writer.add(result["rows"])
                summary.compute_s += result["compute_s"]
                summary.compute_cpu_s += result.get("cpu_s", 0.0)
                spans.append((result["worker"], result["began"], result["ended"]))
                summary.done += len(result["rows"])
                if progress:
                    progress(summary.done, total, writer.failed)
        writer.finish()
    except KeyboardInterrupt:
        summary.interrupted = True
    finally:
        summary.failed = writer.failed
        summary.elapsed_s = time.perf_counter() - start
        summary.scheduler_share, summary.tail_share = scheduling_figures(submitted, time.time(), spans)


def _pass_on_warnings(rows: list[dict], summary: Summary) -> None:
    """The warnings the runs raised on their workers, each once to the user (with its count in
    summary.extra["warnings"]); they are not dataset columns."""
    seen = summary.extra.setdefault("warnings", {})
    for row in rows:
        for message in row.pop("warnings", ()):
            if message not in seen:
                warnings.warn(f"on a worker, run {row['key']}: {message}", RuntimeWarning, stacklevel=2)
            seen[message] = seen.get(message, 0) + 1


def _batch_task(base, runs, options):
    from railbrake.campaign.worker import execute_batch
    return execute_batch(base, runs, options)
