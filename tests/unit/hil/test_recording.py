"""Crash-safe recordings (docs/hil.md, recording): `railbrake hil --record` writes its MDF4 file chunk
by chunk as the run goes, so SIGKILL at any moment leaves a file asammdf opens with every sample up
to 1 s before the kill; two Ctrl-C 0.3 s apart keep the recording and the summary; Ctrl-C at any
moment, from the command's start on, gives no traceback."""

import random
import signal
import subprocess
import threading
import time

import numpy as np
import pytest
from asammdf import MDF

from conftest import KEY_FILE, RAILBRAKE
from test_watchdog import Peer

SCENARIO = "emergency-300-heavy-rain"


def start_plant(port, record, *args):
    # Ctrl-C as from a terminal: a background job (make test run with &) ignores SIGINT, which
    # Python keeps; the plant gets the default disposition back
    return subprocess.Popen([RAILBRAKE, "hil", SCENARIO, "--cars", "1", "--bcu", f"udp://127.0.0.1:{port}",
                             "--priority", "0", "--key", str(KEY_FILE), "--record", str(record), *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def wait_until_running(plant):
    while "session 0x" not in plant.stderr.readline():
        assert plant.poll() is None, plant.stderr.read()


class Witness(Peer):
    """The Python BCU (answers every 10th step), noting when each plant step reached it: what the
    plant had computed at any moment of the wall clock."""

    def __init__(self):
        super().__init__(valid=lambda t: True, hostile=self.saw)
        self.seen = []   # (monotonic time, plant time)

    @staticmethod
    def saw(peer, t):
        peer.seen.append((time.monotonic(), t))

    def plant_time_at(self, moment):
        times = [t for when, t in list(self.seen) if when <= moment]
        return max(times) if times else 0.0


@pytest.mark.slow   # a process killed again and again: the recorder's files, not the core's memory
def test_sigkill_at_random_moments_leaves_every_sample_up_to_1_s_before(tmp_path):
    moments = random.Random(32).sample([round(0.2 + 0.1 * k, 1) for k in range(30)], 5)   # 0.2 .. 3.1 s
    for moment in moments:
        witness = Witness()
        witness.start()
        record = tmp_path / f"killed-{moment}.mf4"
        try:
            plant = start_plant(witness.port, record)
            wait_until_running(plant)
            time.sleep(moment)
            killed = time.monotonic()
            plant.kill()
            _, err = plant.communicate(timeout=30)
        finally:
            witness.done = True
            witness.join()
        assert plant.returncode == -signal.SIGKILL and "Traceback" not in err
        due = witness.plant_time_at(killed - 1.0)
        with MDF(record) as mdf:
            speed = mdf.get("speed")
            cylinder = mdf.get("cylinder_c1a1")
        t = speed.timestamps
        print(f"killed {moment} s after the start: recorded to {t[-1] if len(t) else None} s, "
              f"the plant was at {due:.3f} s one second before the kill")
        step = t[1] - t[0] if len(t) > 1 else 0.0
        assert len(t) == len(cylinder.samples) and np.all(np.isfinite(speed.samples))
        assert due == 0.0 or (len(t) > 0 and t[0] == 0.0 and t[-1] >= due - step)
        assert len(t) < 2 or np.allclose(np.diff(t), step)   # every sample in between


@pytest.mark.slow   # signals to the recorder: its files, not the core's memory
def test_two_ctrl_c_keep_the_recording_and_the_summary(bcu_process, tmp_path):
    bcu, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "0.5")
    record, out = tmp_path / "twice.mf4", tmp_path / "twice"
    plant = start_plant(port, record, "--out", str(out))   # the folder's plots: a final phase of seconds
    wait_until_running(plant)
    time.sleep(2.0)   # the cylinder plot's running mean needs more than 1 s of samples
    plant.send_signal(signal.SIGINT)
    time.sleep(0.3)
    plant.send_signal(signal.SIGINT)
    stdout, err = plant.communicate(timeout=120)
    assert plant.returncode == 130, err
    assert "Traceback" not in err and "interrupted at t = " in err
    assert f"recording: {record}" in stdout and "frames sent" in stdout     # the summary table
    assert open(record, "rb").read(8) == b"MDF     "                          # finalised
    with MDF(record) as mdf:
        assert mdf.get("speed").timestamps[-1] > 1.0
    assert (out / "kpis.json").is_file() and (out / "report.html").is_file()
    bcu.communicate(timeout=60)


def test_ctrl_c_at_any_moment_gives_no_traceback(tmp_path):
    """From the process's start (imports included) to well into the run, against a BCU that is not
    there: status 130, never a traceback. A SIGINT that arrives before the interpreter has installed
    its handler (the first tens of ms, longer on a loaded machine) ends the process by the signal
    itself (-SIGINT here, 130 in a shell), silently: no program can answer a signal before it runs."""
    for k, moment in enumerate((0.05, 0.15, 0.3, 0.5, 0.8, 1.2, 2.0)):
        plant = start_plant(9, tmp_path / f"early-{k}.mf4", "--duration", "30")
        time.sleep(moment)
        plant.send_signal(signal.SIGINT)
        _, err = plant.communicate(timeout=60)
        assert "Traceback" not in err, (moment, err)
        assert plant.returncode == 130 or (plant.returncode == -signal.SIGINT and not err), \
            (moment, plant.returncode, err)
