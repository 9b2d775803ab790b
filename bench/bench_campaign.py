"""Campaign throughput (issue 13): runs per minute per core for 4, 8 and 16 cars, and the
scheduler's share: the workers' time spent waiting for a batch (dispatch, transfer) rather than
running one, until their last batch; the idle time at the end of a study is given apart.

Each study is a latin-hypercube of emergency stops from 60-120 km/h on dry to oil-film rail, run
on a LocalCluster with one single-threaded worker per core; the 200-run 4-car study is the one the
issue asks to finish (then killed and resumed in tests/unit/campaign/test_execute.py on a small
scale). On a shared machine the figures are noisy: run it twice and take the best.

    python bench/bench_campaign.py [--runs 40] [--workers 2] [--cars 4,8,16] [--big]
    python bench/bench_campaign.py --stops 1000     # issue 25: 1000 16-car stops from 300 km/h
    python bench/bench_campaign.py --huge 100000    # issue 25: 10^5 runs planned, killed, resumed
"""

import argparse
import os
import tempfile
import time
from pathlib import Path

from railbrake.campaign import dataset, execute, study

STUDY = """schema: railbrake.study/1
name: bench-{cars}
base: emergency-250-dry
set: {{train.cars: {cars}, stop.max_time: "200 s"}}
factors:
  initial_speed: {{low: "60 km/h", high: "120 km/h"}}
  adhesion.condition: [dry-medium, wet, oil-film]
design: {{kind: latin-hypercube, samples: {runs}}}
seed: 13
"""


def bench(cars: int, runs: int, workers: int) -> dict:
    s = study.parse(STUDY.format(cars=cars, runs=runs), f"bench-{cars}")
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        summary = execute.run_study(s, Path(folder), workers=workers)
        total = time.perf_counter() - start
    assert summary.done == runs and summary.failed == 0, summary.json()
    return {"cars": cars, "runs": runs, "workers": summary.workers,
            "runs_per_min_per_core": runs / (summary.elapsed_s / 60) / summary.workers,
            "mean_run_s": summary.compute_s / runs, "scheduler_share": summary.scheduler_share,
            "tail_share": summary.tail_share, "batches": summary.batches, "elapsed_s": summary.elapsed_s,
            "total_s": total}


def kill_and_resume(runs: int = 200, workers: int = 2, at: float = 0.4) -> dict:
    """The issue's check: a `runs`-run 4-car study run uninterrupted, then again killed with
    SIGKILL (client and workers) once `at` of it is in the dataset, and resumed; the resumed dataset
    must hold every key once with the same KPIs."""
    import signal
    import subprocess
    import sys
    from railbrake.campaign import dataset
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "study.yaml"
        path.write_text(STUDY.format(cars=4, runs=runs))
        whole, killed = Path(folder) / "whole", Path(folder) / "killed"
        start = time.perf_counter()
        execute.run_study(study.load(path), whole, workers=workers)
        uninterrupted = time.perf_counter() - start
        process = subprocess.Popen([sys.executable, "-c", "from railbrake.cli import main; main()", "campaign", "run",
                                    str(path), "--out", str(killed), "--workers", str(workers), "--json"],
                                   start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        while len(dataset.existing_keys(killed)) < at * runs and process.poll() is None:
            time.sleep(0.2)
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
        before = len(dataset.existing_keys(killed))
        summary = execute.run_study(study.load(path), killed, workers=workers)
        a, b = dataset.read(whole).drop(["wall_time_s"]), dataset.read(killed).drop(["wall_time_s"])
        keys = b.column("key").to_pylist()
        return {"runs": runs, "uninterrupted_s": uninterrupted, "in_dataset_at_kill": before,
                "resumed_done": summary.done, "keys_once": len(keys) == len(set(keys)) == runs,
                "identical": a.equals(b)}


STOPS = """schema: railbrake.study/1
name: stops-{runs}
base: emergency-300-heavy-rain
set: {{train.cars: 16, stop.max_time: "900 s"}}
factors:
  adhesion.condition: [dry-medium, hs-wet, heavy-rain, oil-film]
  train.load_case: [normal, crush]
design: {{kind: grid}}
seeds: {seeds}
seed: 25
"""


def stops(runs: int, workers: int) -> dict:
    """Issue 25: `runs` 16-car emergency stops from 300 km/h (4 adhesion conditions x 2 loads x
    seeds) on `workers` workers: wall time, runs per minute per core, scheduling and I/O share
    (the workers' time not spent in batches, from the first batch to the last written), and the
    workers' CPU per simulated ms against the plant alone (railbrake bench on the heavy-rain stop)."""
    from railbrake import simulation
    seeds = max(1, runs // 8)
    s = study.parse(STOPS.format(runs=8 * seeds, seeds=seeds), "stops")
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        summary = execute.run_study(s, Path(folder), workers=workers)
        total = time.perf_counter() - start
        simulated = sum(r or 0.0 for r in dataset.read(Path(folder)).column("stopping_time_s").to_pylist())
    assert summary.done == 8 * seeds and summary.failed == 0, summary.json()
    plant = simulation.bench("emergency-300-heavy-rain", 16, runs=1)["plant_cpu_us_per_ms"]
    busy = summary.workers * summary.elapsed_s
    return {"runs": summary.done, "workers": summary.workers, "elapsed_s": summary.elapsed_s, "total_s": total,
            "runs_per_min_per_core": summary.done / (summary.elapsed_s / 60) / summary.workers,
            "cpu_us_per_simulated_ms": summary.compute_cpu_s * 1e6 / (simulated * 1e3),
            "plant_cpu_us_per_ms": plant, "overhead_share": max(0.0, 1.0 - summary.compute_s / busy),
            "scheduler_share": summary.scheduler_share, "tail_share": summary.tail_share}


HUGE = """schema: railbrake.study/1
name: huge
base: emergency-250-dry
set: {{train.cars: 4, stop.max_time: "30 s"}}
factors:
  initial_speed: {{low: "30 km/h", high: "60 km/h"}}
  adhesion.condition: [dry-medium, wet, oil-film]
design: {{kind: latin-hypercube, samples: {runs}}}
seed: 11
"""


def _peak_rss_mb(pid: int) -> float:
    with open(f"/proc/{pid}/status") as status:
        line = next(x for x in status if x.startswith("VmHWM:"))
    return int(line.split()[1]) / 1024


def huge(runs: int = 100_000, workers: int = 2, seconds: float = 60.0) -> dict:
    """Issue 25: a study of `runs` short 4-car stops planned and started (`campaign run` in a
    process of its own), its client's peak memory read while it runs, killed with SIGKILL after
    `seconds`, resumed for as long and killed again; then every key in the dataset once, and the
    KPIs of the runs done equal those of the same runs made again here in one uninterrupted batch."""
    import signal
    import subprocess
    import sys
    from railbrake.campaign import worker
    from railbrake.campaign.plan import iter_plan
    with tempfile.TemporaryDirectory() as folder:
        path, out = Path(folder) / "huge.yaml", Path(folder) / "out"
        path.write_text(HUGE.format(runs=runs))
        figures = {"runs": runs}
        for attempt in ("first", "resumed"):
            process = subprocess.Popen([sys.executable, "-c", "from railbrake.cli import main; main()", "campaign",
                                        "run", str(path), "--out", str(out), "--workers", str(workers), "--json"],
                                       start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            start, peak = time.monotonic(), 0.0
            while time.monotonic() - start < seconds and process.poll() is None:
                peak = max(peak, _peak_rss_mb(process.pid))
                time.sleep(0.5)
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            figures[f"{attempt}_client_peak_mb"] = peak
            figures[f"{attempt}_in_dataset"] = len(dataset.existing_keys(out))
        table = dataset.read(out)
        keys = table.column("key").to_pylist()
        figures["keys_once"] = len(keys) == len(set(keys))
        s = study.load(path)
        wanted = set(keys)
        done = [r for r in iter_plan(s) if r.key in wanted]
        rows = worker.execute_batch(s.base, [execute._payload(r) for r in done], {})["rows"]
        again = {r["key"]: r["kpis"] for r in rows}
        stored = {k: {name: table.column(name)[i].as_py() for name in again[k]} for i, k in enumerate(keys)}
        figures["kpis_equal"] = all(stored[k] == again[k] for k in keys)
        return figures


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=40)
    parser.add_argument("--workers", type=int, default=os.cpu_count())
    parser.add_argument("--cars", default="4,8,16")
    parser.add_argument("--big", action="store_true", help="also the 200-run 4-car study")
    parser.add_argument("--kill-resume", action="store_true", help="only the 200-run SIGKILL-and-resume check")
    parser.add_argument("--stops", type=int, default=0, help="only the issue-25 study of this many 16-car "
                        "stops from 300 km/h (1000: the issue's)")
    parser.add_argument("--huge", type=int, default=0, help="only the issue-25 check of a study of this many "
                        "short 4-car stops (100000: the issue's): planned, started, killed, resumed, killed")
    args = parser.parse_args()
    if args.huge:
        print(huge(args.huge, args.workers), flush=True)
        return
    if args.stops:
        f = stops(args.stops, args.workers)
        print(f"{f['runs']} 16-car stops from 300 km/h on {f['workers']} workers: {f['elapsed_s']:.1f} s "
              f"({f['total_s']:.1f} s with planning and cluster start), {f['runs_per_min_per_core']:.1f} runs/min/core; "
              f"{f['cpu_us_per_simulated_ms']:.3f} us CPU per simulated ms on the workers against "
              f"{f['plant_cpu_us_per_ms']:.3f} for the plant alone; workers' time not simulating "
              f"{100 * f['overhead_share']:.1f} % (scheduling {100 * (f['scheduler_share'] or 0):.2f} %, "
              f"idle at the end {100 * (f['tail_share'] or 0):.1f} %)", flush=True)
        return
    if args.kill_resume:
        print(kill_and_resume(workers=args.workers), flush=True)
        return
    cases = [(int(c), args.runs) for c in args.cars.split(",")] + ([(4, 200)] if args.big else [])
    for cars, runs in cases:
        f = bench(cars, runs, args.workers)
        print(f"{f['cars']:2d} cars, {f['runs']:3d} runs on {f['workers']} workers: "
              f"{f['runs_per_min_per_core']:6.1f} runs/min/core, {f['mean_run_s']:.2f} s per run, "
              f"{f['batches']} batches, scheduling {100 * f['scheduler_share']:.2f} % of the workers' time "
              f"(idle at the end {100 * f['tail_share']:.1f} %); "
              f"{f['elapsed_s']:.1f} s running, {f['total_s']:.1f} s with planning and cluster start", flush=True)


if __name__ == "__main__":
    main()
