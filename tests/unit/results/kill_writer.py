"""Driver of test_killed_writer: `railbrake run --out` SIGKILLed at random moments.

python kill_writer.py FOLDER KILLS SEED [RUN ARGS...] imports the command line once, then forks
one `railbrake run ... --out FOLDER/ref` that it lets finish (its duration D), then more, each
into FOLDER/kill-N (every other one over a copy of the complete folder, as when a run is repeated
into the same folder), each SIGKILLed at a moment drawn uniformly in [0, D] after its fork, until
KILLS of them were killed before they ended (at most 2 KILLS trials). Prints one JSON line: D and,
per trial, its folder, the moment and how it ended."""

from __future__ import annotations

import json
import os
import random
import shutil
import signal
import sys
import time
from pathlib import Path


def _child(args: list[str]) -> None:
    """The forked `railbrake run`: never returns."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)
    code = 0
    try:
        from railbrake.cli import main
        sys.argv = ["railbrake", *args]
        main()
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 1
    except BaseException:   # noqa: BLE001 - the status says it
        code = 1
    os._exit(code)


def _run(args: list[str], kill_after: float | None) -> tuple[str, float]:
    start = time.monotonic()
    pid = os.fork()
    if pid == 0:
        _child(args)
    if kill_after is not None:
        time.sleep(kill_after)
        os.kill(pid, signal.SIGKILL)
    _, status = os.waitpid(pid, 0)
    ended = "killed" if os.WIFSIGNALED(status) else f"exit {os.waitstatus_to_exitcode(status)}"
    return ended, time.monotonic() - start


def main() -> None:
    folder, kills, seed, run_args = Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4:]
    import asammdf  # noqa: F401 - imported once here, not in each child
    import pyarrow.parquet  # noqa: F401
    import railbrake.cli  # noqa: F401
    import railbrake.plots.simulation  # noqa: F401
    import railbrake.results.outputs  # noqa: F401
    rng = random.Random(seed)
    ended, duration = _run([*run_args, "--out", str(folder / "ref")], None)
    report = {"reference": ended, "duration": duration, "trials": []}
    for n in range(2 * kills):
        if sum(t["ended"] == "killed" for t in report["trials"]) >= kills:
            break
        out = folder / f"kill-{n}"
        if n % 2:
            shutil.copytree(folder / "ref", out)
        moment = rng.uniform(0.0, duration)
        ended, _ = _run([*run_args, "--out", str(out)], moment)
        report["trials"].append({"folder": str(out), "moment": moment, "ended": ended, "over": bool(n % 2)})
    print(json.dumps(report))


if __name__ == "__main__":
    main()
