"""docs/robustness.md's fuzz figures come from docs/results/fuzz.json, which `make fuzz` writes
through tools/fuzz_record.py: a passing target replaces its entry (with date and command), a failing
one leaves the file as it was; the file holds every target the page reads."""

import json
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
RECORD = ROOT / "tools" / "fuzz_record.py"
RESULTS = ROOT / "docs" / "results" / "fuzz.json"


def record(results, *command):
    return subprocess.run([sys.executable, str(RECORD), str(results), "make fuzz-x", "--", *command],
                          capture_output=True, text=True)


def test_a_passing_target_is_recorded_with_date_and_command(tmp_path):
    results = tmp_path / "fuzz.json"
    results.write_text(json.dumps({"other": {"calls": 1}}))
    line = '..fuzz-result {"target": "x", "calls": 12, "violations": 0}'   # after pytest's dots
    done = record(results, sys.executable, "-c", f"print('noise'); print({line!r})")
    assert done.returncode == 0, done.stderr
    assert line in done.stdout                                   # the output passes through
    kept = json.loads(results.read_text())
    assert kept["other"] == {"calls": 1}
    assert kept["x"]["calls"] == 12 and kept["x"]["command"] == "make fuzz-x" and "target" not in kept["x"]
    assert re.fullmatch(r"\d{4}-\d\d-\d\d \d\d:\d\d UTC", kept["x"]["date"])


def test_a_failing_target_records_nothing_and_keeps_its_status(tmp_path):
    results = tmp_path / "fuzz.json"
    line = 'fuzz-result {"target": "x", "calls": 12}'
    done = record(results, sys.executable, "-c", f"print({line!r}); raise SystemExit(3)")
    assert done.returncode == 3 and not results.exists()
    done = record(results, sys.executable, "-c", "print('no result line')")
    assert done.returncode == 1 and not results.exists()


def test_the_results_hold_every_target_the_page_reads():
    page = (ROOT / "docs" / "robustness.md").read_text()
    read = set(re.findall(r"\{glue:text\}`([a-z0-9]+(?:_single|_random)?)_", page))
    results = json.loads(RESULTS.read_text())
    assert read and read <= set(results), read - set(results)
    for target in read:
        assert results[target]["date"] and results[target]["command"].startswith("make fuzz")
        assert all(results[target].get(k, 0) == 0 for k in ("violations", "problems", "past_stop_accepted"))
