"""How long `railbrake --help` takes (issue 40: under 0.5 s): `python -m railbrake --help` in its own
process, start-up included, and, for comparison, `python -c pass` (the interpreter alone) and
`railbrake run --help` (a command's own help, which imports its module). Prints the best and the
median wall time of each over ROUNDS rounds, the CPU time of the best (which other jobs on the
machine do not inflate) and the load average. The tests check only what the help imports
(tests/unit/cli/test_lazy_root.py). Usage: bench_cli_start.py [ROUNDS]."""

import os
import resource
import statistics
import subprocess
import sys
import time

CASES = {"python -c pass": ["-c", "pass"], "railbrake --help": ["-m", "railbrake", "--help"],
         "railbrake run --help": ["-m", "railbrake", "run", "--help"]}


def timed(args: list[str]) -> tuple[float, float]:
    """(wall s, CPU s of the child) of one run of the interpreter with args."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    print(f"load average {os.getloadavg()[0]:.2f}; {rounds} rounds")
    for name, args in CASES.items():
        times = [timed(args) for _ in range(rounds)]
        best = min(times)
        print(f"{name:22s} best {best[0]:.3f} s wall ({best[1]:.3f} s CPU), "
              f"median {statistics.median(t[0] for t in times):.3f} s wall")


if __name__ == "__main__":
    main()
