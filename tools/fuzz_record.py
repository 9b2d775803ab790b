#!/usr/bin/env python3
"""Runs one target of the fuzz suite and keeps its figures for docs/robustness.md.

    fuzz_record.py RESULTS "make fuzz-fmi FUZZ_FMI_CALLS=1000000" -- COMMAND ...

COMMAND's output passes through unchanged. Each fuzzer prints one `fuzz-result {json}` line per
target it ran (tests/fuzz/fmi_fuzz.c, core/tests/fuzz_hil_frame.c, tests/unit/fuzz/); libFuzzer's
own `Done N runs` line stands for the frame target when clang built it. If COMMAND succeeds, each
target's entry in RESULTS (JSON) is replaced by its figures with the date, the command, how long it
took and the machine's load, which the docs build reads: the page's figures are never typed.
A failing run records nothing and keeps its status."""

import datetime
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

RESULT = re.compile(r"fuzz-result (\{.*\})$")
LIBFUZZER_DONE = re.compile(r"^Done (\d+) runs in (\d+) second")


def figures(line: str):
    """The target's figures a fuzzer's output line carries, or None."""
    result = RESULT.search(line)   # anywhere in the line: pytest's progress dots may come first
    if result:
        return json.loads(result[1])
    done = LIBFUZZER_DONE.match(line)
    if done:
        return {"target": "frames", "inputs": int(done[1]), "violations": 0, "engine": "libFuzzer"}
    return None


def compiler() -> str:
    try:
        return subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    except (OSError, IndexError):
        return "unknown"


def run(command: list[str]) -> tuple[int, list[dict], float]:
    """Runs `command`, echoing its output; its status, the figures it printed and its wall time."""
    start = time.monotonic()
    found = []
    with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True) as process:
        for line in process.stdout:
            sys.stdout.write(line)
            sys.stdout.flush()
            result = figures(line.strip())
            if result:
                found.append(result)
    return process.returncode, found, time.monotonic() - start


def main() -> int:
    if len(sys.argv) < 5 or sys.argv[3] != "--":
        sys.exit(__doc__)
    results, described, command = Path(sys.argv[1]), sys.argv[2], sys.argv[4:]
    load_before = os.getloadavg()[0]
    status, found, seconds = run(command)
    if status != 0:
        print(f"fuzz_record: {described} failed (status {status}): {results} left as it was", file=sys.stderr)
        return status
    if not found:
        print(f"fuzz_record: {described} printed no fuzz-result line", file=sys.stderr)
        return 1
    kept = json.loads(results.read_text()) if results.is_file() else {}
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    machine = {"cores": os.cpu_count(), "load_before": round(load_before, 2),
               "load_after": round(os.getloadavg()[0], 2), "compiler": compiler()}
    for result in found:
        target = result.pop("target")
        kept[target] = {**result, "date": when, "command": described, "seconds": round(seconds), "machine": machine}
    results.parent.mkdir(parents=True, exist_ok=True)
    results.write_text(json.dumps(kept, indent=2, sort_keys=True) + "\n")
    print(f"fuzz_record: {len(found)} target(s) of {described} recorded in {results}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
