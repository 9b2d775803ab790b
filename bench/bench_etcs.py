"""The ETCS braking model of the 16-car preset (issue 26: all ten levels and Kwet_rst with the shipped
reliability and scatter files in under 20 minutes on 2 cores, resumable after SIGKILL with
identical results).

`python bench/bench_etcs.py` runs the full analysis of crh380al-16 into OUT (default
out/bench-etcs) on --workers processes and prints the wall and CPU time, the runs and the coded
factors. `--kill-after S` first starts the same analysis in a child process, kills it with SIGKILL
after S seconds, then resumes it into the same folder and compares the result with a clean run in a
second folder (`--compare`): they must be equal. Figures are printed, never asserted.
"""

import argparse
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

TRAIN = "crh380al-16"


def analyse(out: Path, workers: int, samples: int | None) -> dict:
    from railbrake.etcs import export, model
    settings = {} if samples is None else {"samples": samples}
    m = model.braking_model(model.spec(TRAIN, **settings), out, workers)
    return export.to_json(m)


def cpu_s() -> float:
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("out/bench-etcs"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--samples", type=int, default=None, help="runs of the likely states (method.yaml's)")
    parser.add_argument("--kill-after", type=float, default=None, help="SIGKILL a first attempt after S s")
    parser.add_argument("--compare", type=Path, default=None, help="a clean run's folder to compare with")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = parser.parse_args()
    if a.kill_after is not None:
        shutil.rmtree(a.out, ignore_errors=True)
        child = subprocess.Popen([sys.executable, __file__, "--child", "--out", str(a.out), "--workers",
                                  str(a.workers)] + ([] if a.samples is None else ["--samples", str(a.samples)]),
                                 start_new_session=True)
        time.sleep(a.kill_after)
        os.killpg(child.pid, signal.SIGKILL)   # the analysis and its workers, as a crash would
        child.wait()
        done = len(list((a.out / "batches").glob("*.json"))) if (a.out / "batches").exists() else 0
        print(f"killed after {a.kill_after:g} s with {done} batches written", flush=True)
    wall, cpu = time.perf_counter(), cpu_s()
    data = analyse(a.out, a.workers, a.samples)
    wall, cpu = time.perf_counter() - wall, cpu_s() - cpu
    if a.child:
        return
    print(f"{TRAIN}: {data['runs']} runs, {wall:.0f} s wall, {cpu:.0f} s CPU on {a.workers} workers "
          f"(load {os.getloadavg()[0]:.1f})")
    for level in data["Kdry_rst"]:
        print(f"  M_NVEBCL {level['M_NVEBCL']}: Kdry_rst {level['coded']}")
    print(f"  Kwet_rst {data['Kwet_rst']['coded']}, T_brake_emergency {data['T_brake_emergency_s']:.2f} s")
    (a.out / "bench.json").write_text(json.dumps(data, indent=1, default=str))
    if a.compare is not None:
        other = json.loads((a.compare / "braking-model.json").read_text()) if (a.compare / "braking-model.json").exists() \
            else json.loads((a.compare / "bench.json").read_text())
        same = all(x["value"] == y["value"] for x, y in zip(data["Kdry_rst"], other["Kdry_rst"])) and \
            data["Kwet_rst"]["value"] == other["Kwet_rst"]["value"]
        print(f"resumed against clean run {a.compare}: {'identical' if same else 'DIFFERENT'}")


if __name__ == "__main__":
    main()
