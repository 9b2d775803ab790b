"""One client at a time on a campaign folder (railbrake.campaign.lock), and dataset files' errors
that name the file:
- a second holder of a folder's lock is refused naming the first's host and PID; a lock whose
  holder was SIGKILLed is taken over;
- two `campaign run` clients on one folder, the second started while the first holds it (paused
  there with SIGSTOP, so that the overlap is certain) and then both at once: every run of the
  study is in the dataset exactly once, the refused client says who holds the folder, neither
  prints a traceback, and the refused one run again afterwards finds nothing left to run;
- a damaged study.json is refused naming it."""

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from railbrake.campaign import dataset, lock
from railbrake.errors import InputError

SMALL = Path(__file__).parent / "data" / "small.yaml"
HOLD = "import sys, time; from railbrake.campaign import lock\nwith lock.holding(sys.argv[1]):\n" \
       "    print('held', flush=True); time.sleep(60)"


def _holder_process(folder: Path) -> subprocess.Popen:
    process = subprocess.Popen([sys.executable, "-c", HOLD, str(folder)], stdout=subprocess.PIPE, text=True)
    assert process.stdout.readline().strip() == "held"
    return process


def test_a_second_holder_is_refused_naming_the_first(tmp_path):
    first = _holder_process(tmp_path)
    try:
        with pytest.raises(InputError) as refused:
            with lock.holding(tmp_path):
                pass
        assert f"host {socket.gethostname()}, PID {first.pid}" in str(refused.value)
        assert str(tmp_path / lock.LOCK) in str(refused.value)
    finally:
        first.kill()
        first.wait()


def test_the_lock_of_a_killed_holder_is_taken_over(tmp_path):
    first = _holder_process(tmp_path)
    first.send_signal(signal.SIGKILL)
    first.wait()
    assert json.loads((tmp_path / lock.LOCK).read_text())["pid"] == first.pid   # left behind
    with lock.holding(tmp_path):
        assert json.loads((tmp_path / lock.LOCK).read_text())["pid"] == os.getpid()


def test_a_damaged_study_json_is_refused_naming_it(tmp_path):
    for damaged in ('{"study": "x", "factors": {', "[1, 2]", '{"factors": "speed"}', "\xff\xfe"):
        (tmp_path / dataset.MANIFEST).write_text(damaged, encoding="latin-1")
        with pytest.raises(InputError, match=str(tmp_path / dataset.MANIFEST)):
            dataset.read_manifest(tmp_path)


def _client(study_file: Path, out: Path, scheduler: str) -> subprocess.Popen:
    command = [sys.executable, "-c", "from railbrake.cli import main; main()", "campaign", "run", str(study_file),
               "--out", str(out), "--scheduler", scheduler, "--batch-size", "1", "--json"]
    return subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _holder_pid(out: Path) -> int | None:
    try:
        return json.loads((out / lock.LOCK).read_text() or "{}").get("pid")
    except (OSError, ValueError):
        return None


def _each_run_once(out: Path, runs: int) -> None:
    keys = dataset.read(out).column("key").to_pylist()
    assert len(keys) == len(set(keys)) == runs


@pytest.mark.slow
def test_two_clients_on_one_folder_run_each_run_once(two_workers, tmp_path):
    study_file = tmp_path / "study.yaml"
    study_file.write_text(SMALL.read_text().replace("seeds: 2", "seeds: 4"))   # 16 runs
    out = tmp_path / "shared"
    first = _client(study_file, out, two_workers)
    deadline = time.monotonic() + 120
    while _holder_pid(out) != first.pid and first.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    assert _holder_pid(out) == first.pid, first.communicate()
    first.send_signal(signal.SIGSTOP)   # holds the folder while the second client comes
    try:
        second = _client(study_file, out, two_workers)
        _, refusal = second.communicate(timeout=120)
    finally:
        first.send_signal(signal.SIGCONT)
    done, errors = first.communicate(timeout=300)
    assert first.returncode == 0 and "Traceback" not in errors, errors
    assert second.returncode == 2 and "Traceback" not in refusal, refusal
    assert f"host {socket.gethostname()}, PID {first.pid}" in refusal
    assert json.loads(done)["done"] == 16
    _each_run_once(out, 16)
    again = _client(study_file, out, two_workers)
    summary, errors = again.communicate(timeout=300)
    assert again.returncode == 0, errors
    assert (json.loads(summary)["done"], json.loads(summary)["skipped"]) == (0, 16)
    _each_run_once(out, 16)

    # both at once: whichever comes second is refused, or finds the study done
    out = tmp_path / "together"
    clients = [_client(study_file, out, two_workers) for _ in range(2)]
    ended = [c.communicate(timeout=300) for c in clients]
    assert sorted(c.returncode for c in clients) in ([0, 0], [0, 2]), ended
    assert not any("Traceback" in errors for _, errors in ended), ended
    done = [json.loads(text)["done"] for (text, _), c in zip(ended, clients) if c.returncode == 0]
    assert sum(done) == 16, ended
    _each_run_once(out, 16)
