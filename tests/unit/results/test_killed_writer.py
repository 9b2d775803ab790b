"""`railbrake run --out` SIGKILLed at random moments (kill_writer.py: 22 kills of a 1-car run,
uniform over the time a whole run takes, half of them over a complete earlier folder): every file
present under its final name is whole (it parses, holds every sample, ends where its format ends)
or absent, and railbrake.load_result refuses each folder whose writing was cut short, naming what
is missing; a folder the kill spared loads with every sample."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

import railbrake
from railbrake import atomic
from railbrake.errors import InputError

KILLS = 22   # kills that landed before the run ended (trials that ended first do not count)
# 22 CLI processes killed mid-write (over 2 min under the sanitizers): the writer's files, not the core
pytestmark = pytest.mark.slow

SEED = int(os.environ.get("RAILBRAKE_KILL_SEED", "41"))
RUN = ["run", "emergency-250-dry", "--cars", "1", "--format", "parquet,csv,mf4"]


def _whole(path: Path, reference: Path, samples: int) -> str | None:
    """None when path is a whole output of its kind, else what is wrong with it."""
    data = path.read_bytes()
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq
        rows = pq.read_table(path).num_rows
        return None if rows == samples else f"{rows} rows of {samples}"
    if path.suffix == ".mf4":
        from asammdf import MDF
        with MDF(path) as mdf:
            n = len(mdf.get("speed").samples)
        return None if n == samples else f"{n} samples of {samples}"
    if path.suffix == ".csv":
        lines = data.decode().split("\n")
        expected = len(reference.read_text().split("\n"))
        return None if data.endswith(b"\n") and len(lines) == expected else f"{len(lines)} lines of {expected}"
    if path.suffix == ".json":
        json.loads(data)
        return None
    if path.suffix == ".yaml":
        yaml.safe_load(data)
        return None if data == reference.read_bytes() or len(data) > 0.9 * reference.stat().st_size else "short"
    if path.suffix == ".html":
        return None if data.endswith(b"</html>\n") else "no </html> at its end"
    if path.suffix == ".png":   # matplotlib writes the same figure to the same bytes
        return None if data == reference.read_bytes() else f"{len(data)} bytes of {reference.stat().st_size}"
    return f"unexpected file {path.name}"


@pytest.fixture(scope="module")
def killed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("killed")
    driver = Path(__file__).with_name("kill_writer.py")
    done = subprocess.run([sys.executable, str(driver), str(folder), str(KILLS), str(SEED), *RUN],
                          capture_output=True, text=True, timeout=300, env=dict(os.environ))
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["reference"] == "exit 0", report
    return folder / "ref", report


def test_every_file_present_after_a_kill_is_whole(killed):
    ref, report = killed
    samples = len(railbrake.load_result(ref).time)
    bad, checked = [], 0
    for trial in report["trials"]:
        folder = Path(trial["folder"])
        for path in folder.iterdir() if folder.exists() else ():
            if atomic.is_temporary(path):
                continue
            checked += 1
            problem = _whole(path, ref / path.name, samples)
            if problem:
                bad.append(f"{path} (killed at {trial['moment']:.3f} s): {problem}")
    assert not bad, "\n".join(bad)
    assert checked > 0
    print("kill-result", json.dumps({"files_checked_whole": checked, "partial_files": len(bad)}))


def test_load_result_refuses_a_folder_cut_short(killed):
    ref, report = killed
    names = {p.name for p in ref.iterdir()}
    samples = len(railbrake.load_result(ref).time)
    killed_while_writing = 0
    for trial in report["trials"]:
        folder = Path(trial["folder"])
        present = {p.name for p in folder.iterdir() if not atomic.is_temporary(p)} if folder.exists() else set()
        if not present:
            continue
        if (folder / "manifest.json").is_file():   # the kill came after the last file
            assert present == names, trial
            assert len(railbrake.load_result(folder).time) == samples
            continue
        killed_while_writing += 1
        with pytest.raises(InputError, match="manifest.json is missing"):
            railbrake.load_result(folder)
    kills = sum(t["ended"] == "killed" for t in report["trials"])
    print("kill-result", json.dumps({"trials": len(report["trials"]), "killed": kills, "cut_short_refused": killed_while_writing,
                                     "run_s": round(report["duration"], 2)}))
    # the moments hit the writing: most folders were cut short, not merely never begun or finished
    assert killed_while_writing >= KILLS // 3, report
    assert kills >= 20, report
