"""`campaign plan` of a design far above the run limit (issue 31, part 4): the wall-clock time and
the peak memory (max RSS) of the whole process until it refuses, for a 10^9-sample latin
hypercube and a 1000^3 grid. The issue asks for under 2 s and 200 MB.

    python bench/bench_plan_limit.py [--repeat 3]
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HEAD = "schema: railbrake.study/1\nname: big\nbase: emergency-250-dry\n"
DESIGNS = {
    "latin-hypercube, 10^9 samples": HEAD + "factors:\n  initial_speed: {low: 100 km/h, high: 250 km/h}\n"
                                     "design: {kind: latin-hypercube, samples: 1000000000}\n",
    "grid, 1000^3 levels": HEAD + "factors:\n  initial_speed: {low: 100 km/h, high: 250 km/h, levels: 1000}\n"
                                  "  wsp.slip_threshold: {low: 0.002, high: 0.05, levels: 1000}\n"
                                  "  wsp.safety_time: {low: 1 s, high: 5 s, levels: 1000}\ndesign: {kind: grid}\n",
}
PROBE = ("import resource, subprocess, sys, time; t = time.perf_counter(); "
         "r = subprocess.run(sys.argv[1:], capture_output=True); "
         "print(r.returncode, time.perf_counter() - t, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    railbrake = str(Path(sys.executable).parent / "railbrake")
    with tempfile.TemporaryDirectory() as folder:
        for label, text in DESIGNS.items():
            path = Path(folder) / "big.yaml"
            path.write_text(text)
            runs = []
            for _ in range(args.repeat):
                out = subprocess.run([sys.executable, "-c", PROBE, railbrake, "campaign", "plan", str(path)],
                                     capture_output=True, text=True, check=True).stdout.split()
                runs.append((int(out[0]), float(out[1]), int(out[2]) / 1024))
            best = min(runs, key=lambda r: r[1])
            print(f"{label}: exit {best[0]}, {best[1]:.2f} s (best of {args.repeat}; slowest "
                  f"{max(r[1] for r in runs):.2f} s), max RSS {max(r[2] for r in runs):.0f} MB, "
                  f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
