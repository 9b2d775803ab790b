"""Running studies on Dask: same dataset for 1 and 2 workers, on an external scheduler, after a
SIGKILL and a resume; failed runs recorded; a silent scheduler refused before any run."""

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from railbrake.campaign import dataset, execute, study, worker
from railbrake.campaign.plan import plan
from railbrake.errors import InputError

DATA = Path(__file__).parent / "data"
SMALL = DATA / "small.yaml"
BIN = Path(sys.executable).parent
TIMING = {"wall_time_s"}   # the one column that may differ between two runs of a study


def content(folder: Path) -> dict:
    table = dataset.read(folder)
    return {name: table.column(name).to_pylist() for name in table.column_names if name not in TIMING}


@pytest.fixture(scope="module")
def reference(tmp_path_factory, one_worker) -> Path:
    """The study run once, uninterrupted, by one worker."""
    out = tmp_path_factory.mktemp("one-worker")
    summary = execute.run_study(study.load(SMALL), out, scheduler=one_worker)
    assert (summary.runs, summary.done, summary.skipped, summary.failed) == (8, 8, 0, 0)
    return out


def test_one_and_two_workers_give_identical_datasets(reference, two_workers, tmp_path):
    summary = execute.run_study(study.load(SMALL), tmp_path, scheduler=two_workers, batch_size=1)
    assert summary.workers == 2 and summary.batches == 8
    assert content(tmp_path) == content(reference)
    data = content(reference)
    assert sorted(data["key"]) == data["key"] and len(set(data["key"])) == 8
    assert set(data["status"]) == {"ok"}
    # physics, not bookkeeping: a lower adhesion stops longer, from each speed
    rows = list(zip(data["initial_speed"], data["adhesion.condition"], data["stopping_distance_m"]))
    for v in {r[0] for r in rows}:
        dry = [s for (u, c, s) in rows if u == v and c == "dry-medium"]
        oil = [s for (u, c, s) in rows if u == v and c == "oil-film"]
        assert min(oil) > max(dry)


def test_rerun_skips_every_key_already_there(reference):
    from typer.testing import CliRunner
    from railbrake.cli import app
    result = CliRunner().invoke(app, ["campaign", "run", str(SMALL), "--out", str(reference), "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert {k: summary[k] for k in ("runs", "done", "skipped", "failed", "dataset")} == \
        {"runs": 8, "done": 0, "skipped": 8, "failed": 0, "dataset": str(reference)}
    assert len(dataset.read(reference)) == 8


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_scheduler_that_does_not_answer_fails_before_any_run(tmp_path):
    address = f"tcp://127.0.0.1:{_free_port()}"
    with pytest.raises(InputError, match=f"--scheduler {address}: no Dask scheduler"):
        execute.run_study(study.load(SMALL), tmp_path / "out", scheduler=address, connect_timeout=2.0)
    assert not (tmp_path / "out").exists()


@pytest.mark.slow   # separate processes and clusters: not under the sanitizers
def test_the_study_runs_on_a_dask_scheduler_and_worker_started_here(reference, tmp_path):
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = dict(os.environ)
    processes = [subprocess.Popen([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                                   "--no-dashboard"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        processes.append(subprocess.Popen([str(BIN / "dask"), "worker", address, "--nthreads", "1",
                                           "--nworkers", "1", "--no-dashboard"], env=env,
                                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        summary = execute.run_study(study.load(SMALL), tmp_path, scheduler=address, connect_timeout=60.0)
        assert summary.workers == 1 and summary.done == 8
        assert content(tmp_path) == content(reference)
    finally:
        for p in reversed(processes):
            p.terminate()
        for p in reversed(processes):
            p.wait(timeout=30)


@pytest.mark.slow   # separate processes and clusters: not under the sanitizers
def test_sigkill_part_way_then_rerun_holds_each_key_once_with_the_same_kpis(reference, one_worker, tmp_path):
    command = [sys.executable, "-c", "from railbrake.cli import main; main()", "campaign", "run", str(SMALL),
               "--out", str(tmp_path), "--workers", "1", "--batch-size", "1", "--json"]
    process = subprocess.Popen(command, start_new_session=True, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while len(dataset.existing_keys(tmp_path)) < 2 and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGKILL)   # the client and its worker processes, at once
    process.wait()
    partial = dataset.existing_keys(tmp_path)
    assert 2 <= len(partial) < 8, "the kill came too late to test a resume"
    summary = execute.run_study(study.load(SMALL), tmp_path, scheduler=one_worker)
    assert summary.skipped == len(partial) and summary.done == 8 - len(partial)
    assert content(tmp_path) == content(reference)


def test_a_run_that_raises_is_recorded_and_the_batch_goes_on(monkeypatch):
    s = study.load(SMALL)
    runs = [execute._payload(r) for r in plan(s)[:3]]
    real = worker.configuration.run

    def flaky(resolved, record):
        if resolved.scenario.spec.adhesion.condition == "oil-film":
            raise RuntimeError("valve model diverged")
        return real(resolved, record=record)

    monkeypatch.setattr(worker.configuration, "run", flaky)
    rows = worker.execute_batch(s.base, runs, {})["rows"]
    assert [r["status"] for r in rows] == ["ok", "ok", "failed"]
    assert rows[2]["error"] == "RuntimeError: valve model diverged"
    sch = dataset.schema(s.factors, list(rows[0]["kpis"]), {"name": s.name})
    table = dataset.table(rows, sch)
    assert table.column("stopping_distance_m").to_pylist()[2] is None


def test_scheduling_share_counts_the_gaps_between_a_workers_batches():
    spans = [("a", 10.0, 11.0), ("a", 11.1, 12.0), ("b", 10.5, 12.5)]
    share, tail = execute.scheduling_figures(9.0, 13.0, spans)
    assert share == pytest.approx(0.1 / (2.0 + 2.0))
    assert tail == pytest.approx((1.0 + 0.5) / (4.0 + 1.5))


@pytest.mark.slow   # separate processes and clusters: not under the sanitizers
def test_a_lost_workers_batch_is_run_again(reference, two_workers, tmp_path):
    from dask.distributed import Client
    with Client(two_workers) as client:
        pids = sorted(client.run(os.getpid).values())
    killed = []

    def kill_a_worker(done, total, failed):
        if done >= 1 and not killed:   # a batch is in flight on each worker: kill one worker process
            os.kill(pids[0], signal.SIGKILL)
            killed.append(pids[0])

    summary = execute.run_study(study.load(SMALL), tmp_path, scheduler=two_workers, batch_size=1,
                                progress=kill_a_worker, connect_timeout=60.0)
    assert killed and summary.done == 8 and summary.failed == 0
    assert content(tmp_path) == content(reference)
