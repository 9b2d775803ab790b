"""The ETCS braking model of the 16-car preset (issue 36's must-hold: crh380al-16 with the shipped
reliability and scatter files, every level, its bounds and Kwet_rst, in under 15 minutes on 2 idle
cores, and the same result on an external Dask scheduler; issue 26: resumable after SIGKILL with
identical results).

`python bench/bench_etcs.py` runs the full analysis into OUT (default out/bench-etcs) on --workers
local worker processes (the campaign engine's local Dask cluster) and prints the wall and CPU time
(this process and its workers), the runs, the machine's load before and after (other processes
share the cores: a wall time is only the figure asked for when the load stays near 0), and the
coded factors. `--external` then runs the same analysis again into OUT-external on a `dask
scheduler` with a `dask worker` of --workers processes started (and stopped) here, and compares
the two braking-model JSONs' Kdry_rst values, bounds and codes and Kwet_rst: they must be equal.
`--scheduler ADDRESS` runs on an existing scheduler instead of local workers. `--kill-after S`
first starts the analysis in a child process, kills it with SIGKILL after S seconds, then resumes
it into the same folder (compare with `--compare` a clean run's folder). Figures are printed, never
asserted.
"""

import argparse
import json
import logging
import os
import resource
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

TRAIN = "crh380al-16"
BIN = Path(sys.executable).parent


def analyse(out: Path, workers: int, settings: dict, scheduler: str | None = None) -> dict:
    from railbrake import jsonio
    from railbrake.etcs import export, model
    m = model.braking_model(model.spec(TRAIN, **settings), out, workers, scheduler=scheduler, connect_timeout=120.0)
    data = json.loads(jsonio.dumps(export.to_json(m)))
    (out / "braking-model.json").write_text(json.dumps(data, indent=1))
    return data


def cpu_s() -> float:
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def workers_cpu_s(scheduler: str | None) -> float:
    """CPU time of the analysis' Dask workers so far (a local cluster's workers are not children
    that have ended, so getrusage does not count them)."""
    if scheduler is None:
        return 0.0
    from dask.distributed import Client
    with Client(scheduler, timeout=60) as client:
        return sum(client.run(lambda: sum(os.times()[:2])).values())


def key_figures(data: dict) -> dict:
    return {"Kdry_rst": [(x["value"], x["bound_95"], x["coded"]) for x in data["Kdry_rst"]],
            "Kwet_rst": (data["Kwet_rst"]["value"], data["Kwet_rst"]["coded_per_step"]), "runs": data["runs"]}


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def external_cluster(workers: int) -> tuple[str, list]:
    address = f"tcp://127.0.0.1:{free_port()}"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    processes = [subprocess.Popen([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port",
                                   address.rsplit(":", 1)[1], "--no-dashboard"], **quiet)]
    processes.append(subprocess.Popen([str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers",
                                       str(workers), "--no-dashboard"], **quiet))
    return address, processes


def timed(label: str, out: Path, workers: int, settings: dict, scheduler: str | None) -> dict:
    load0 = os.getloadavg()
    wall, cpu = time.perf_counter(), cpu_s()
    data = analyse(out, workers, settings, scheduler)
    wall, cpu = time.perf_counter() - wall, cpu_s() - cpu + workers_cpu_s(scheduler)
    load1 = os.getloadavg()
    print(f"{TRAIN} {label}: {data['runs']} runs, {wall:.0f} s wall ({wall / 60:.1f} min), {cpu:.0f} s CPU "
          f"(load {load0[0]:.1f}/{load0[1]:.1f} before, {load1[0]:.1f}/{load1[1]:.1f} after)", flush=True)
    return data


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("out/bench-etcs"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--samples", type=int, default=None, help="runs of the likely states (method.yaml's)")
    parser.add_argument("--rare-samples", type=int, default=None, help="first runs of the rare states (method.yaml's)")
    parser.add_argument("--state-floor", type=float, default=None,
                        help="a shortened analysis: states down to this (method.yaml's); not the must-hold's figure")
    parser.add_argument("--scheduler", default=None, help="an existing Dask scheduler instead of local workers")
    parser.add_argument("--external", action="store_true",
                        help="then the same on a dask scheduler and worker started here, compared")
    parser.add_argument("--kill-after", type=float, default=None, help="SIGKILL a first attempt after S s")
    parser.add_argument("--compare", type=Path, default=None, help="a clean run's folder to compare with")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = parser.parse_args()
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(message)s")   # the analysis' rounds
    settings = {k: v for k, v in (("samples", a.samples), ("rare_samples", a.rare_samples),
                                  ("state_floor", a.state_floor)) if v is not None}
    if a.child:
        analyse(a.out, a.workers, settings, a.scheduler)
        return
    if a.kill_after is not None:
        shutil.rmtree(a.out, ignore_errors=True)
        child = subprocess.Popen([sys.executable, __file__, "--child", "--out", str(a.out), "--workers",
                                  str(a.workers)] + [f"--{k.replace('_', '-')}={v}" for k, v in settings.items()],
                                 start_new_session=True)
        time.sleep(a.kill_after)
        os.killpg(child.pid, signal.SIGKILL)   # the analysis and its workers, as a crash would
        child.wait()
        done = len(list((a.out / "batches").glob("*.json"))) if (a.out / "batches").exists() else 0
        print(f"killed after {a.kill_after:g} s with {done} batches written", flush=True)
    label = (f"on {a.workers} local workers" if a.scheduler is None else f"on {a.scheduler}") + \
        (f" (shortened: {settings})" if settings else "")
    data = timed(label, a.out, a.workers, settings, a.scheduler)
    for level in data["Kdry_rst"]:
        print(f"  M_NVEBCL {level['M_NVEBCL']}: Kdry_rst {level['coded']}, worst bound "
              f"{max(max(b) for b in level['bound_95']):.4f}")
    print(f"  Kwet_rst {data['Kwet_rst']['coded']}, T_brake_emergency {data['T_brake_emergency_s']:.2f} s, "
          f"step allowance {data['Kdry_rst'][0]['step_allowance']}")
    if a.external:
        address, processes = external_cluster(a.workers)
        try:
            other = timed(f"on an external dask scheduler with {a.workers} workers", Path(f"{a.out}-external"),
                          a.workers, settings, address)
        finally:
            for p in reversed(processes):
                p.terminate()
            for p in reversed(processes):
                p.wait(timeout=60)
        same = key_figures(other) == key_figures(data)
        print(f"external scheduler against local workers: {'identical' if same else 'DIFFERENT'}")
    if a.compare is not None:
        other = json.loads((a.compare / "braking-model.json").read_text())
        same = key_figures(other) == key_figures(data)
        print(f"against {a.compare}: {'identical' if same else 'DIFFERENT'}")


if __name__ == "__main__":
    main()
