"""The reference BCU as a separate process (`railbrake bcu`), as a user would start it."""

import subprocess
import sys
from pathlib import Path

import pytest

RAILBRAKE = str(Path(sys.executable).parent / "railbrake")


def start_bcu(*args):
    """Starts `railbrake bcu ... --listen udp://127.0.0.1:0`; returns the process and its port."""
    proc = subprocess.Popen([RAILBRAKE, "bcu", *args, "--listen", "udp://127.0.0.1:0", "--priority", "0",
                             "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
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
