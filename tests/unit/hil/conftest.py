"""The reference BCU as a separate process (`railbrake bcu`), as a user would start it, and the key
file plant and BCU share (ICD v3: every frame authenticated)."""

import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from railbrake.hil.keys import read_key, write_key

RAILBRAKE = str(Path(sys.executable).parent / "railbrake")
KEY_FILE = Path(tempfile.mkdtemp(prefix="railbrake-hil-key-")) / "hil.key"   # one per test process
write_key(KEY_FILE)
SECRET = read_key(KEY_FILE)


def start_bcu(*args):
    """Starts `railbrake bcu ... --listen udp://127.0.0.1:0`; returns the process and its port."""
    proc = subprocess.Popen([RAILBRAKE, "bcu", *args, "--listen", "udp://127.0.0.1:0", "--priority", "0",
                             "--key", str(KEY_FILE), "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    line = proc.stdout.readline()
    if not line.startswith("listening on udp://127.0.0.1:"):
        proc.kill()
        raise RuntimeError(f"railbrake bcu did not start: {line!r} {proc.stderr.read()}")
    return proc, int(line.rsplit(":", 1)[1])


@pytest.fixture
def bcu_process():
    started = []

    def start(*args):
        proc, port = start_bcu(*args)
        started.append(proc)
        return proc, port

    yield start
    for proc in started:
        if proc.poll() is None:
            proc.kill()
        proc.wait()


@pytest.fixture
def railbrake_cli():
    """The installed `railbrake` command of this environment."""
    return RAILBRAKE


@pytest.fixture
def hil_key():
    """The key file every plant and BCU of these tests share."""
    return KEY_FILE


def run_with_dashboard(board, visitor, duration):
    """A paced 1-car run without BCU (the safe state) with `board` attached, while visitor() (a
    page, a browser) runs in a thread of its own until it stops the run; the run's result."""
    import threading

    from railbrake import hil
    worker = threading.Thread(target=visitor)
    worker.start()
    try:
        return hil.run("emergency-300-heavy-rain", ("127.0.0.1", 9), cars=1, duration=duration, priority=0,
                       key=SECRET, on_live=lambda view: board.attach(view=view),
                       on_faults=lambda switch: board.attach(switch=switch), stop=board.stop_requested)
    finally:
        worker.join()
        board.close()
