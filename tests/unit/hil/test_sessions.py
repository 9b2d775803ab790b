"""The session handshake (ICD versions 2 and 3) with the real processes (`railbrake hil`, `railbrake
bcu`): a BCU set up for another train refuses the plant and both say why, a forged frame cannot
silence the BCU, and Ctrl-C / SIGTERM keep the recording and the summary."""

import json
import signal
import socket
import subprocess
import time

import numpy as np

from asammdf import MDF

from railbrake import hil, scenario
from railbrake.hil.frames import crc32, siphash24
from conftest import KEY_FILE, SECRET

SCENARIO = "emergency-300-heavy-rain"


def plant(railbrake, port, *args, **kwargs):
    return subprocess.Popen([railbrake, "hil", SCENARIO, "--bcu", f"udp://127.0.0.1:{port}", "--priority", "0",
                             "--key", str(KEY_FILE), *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, **kwargs)


def test_bcu_of_another_train_both_say_why(bcu_process, railbrake_cli):
    bcu, port = bcu_process(SCENARIO, "--cars", "4", "--idle-timeout", "0.5")
    run = plant(railbrake_cli, port, "--cars", "8", "--duration", "5")
    out, err = run.communicate(timeout=120)
    err = " ".join(err.split())   # rich wraps long lines
    assert run.returncode == 1, err
    assert "set up for configuration" in err and "4 cars, 16 axles" in err and "8 cars, 32 axles" in err
    served_out, served_err = bcu.communicate(timeout=60)    # reaches its idle timeout without a valid frame
    served_err = " ".join(served_err.split())
    assert bcu.returncode == 1
    assert served_err.count("its frames are refused") == 1 and "8 cars, 32 axles" in served_err
    counters = json.loads(served_out)
    assert counters["refused"] >= 1 and counters["received"] == 0 and counters["cycles"] == 0


def forged_frame(step):
    """A CRC-valid plant hello of this train (1 car) with the given step, in session 1, tagged under
    a key that is not the session's (the forger has no key file)."""
    forged = bytearray(48 + 4 * (3 + 2 * 4 + 1))
    forged[0:8] = bytes([0x52, 0x42, 0x52, 0x4B, 4, 1, 48, 0])
    forged[8:12] = (1).to_bytes(4, "little")
    forged[12:16] = hil.config_digest(scenario.load(SCENARIO), 1).to_bytes(4, "little")
    forged[20:28] = step.to_bytes(8, "little")
    forged[28:30] = bytes([1, 4])
    forged[40:48] = (0xF00D).to_bytes(8, "little")   # a plant nonce: a hello
    return (bytes(forged) + crc32(bytes(forged)).to_bytes(4, "little")
            + siphash24(bytes(16), bytes(forged)).to_bytes(8, "little"))


def test_forged_step_does_not_silence_the_bcu(bcu_process):
    """A CRC-valid plant frame with step 2^64 - 1 from another address, sent while the plant runs:
    the BCU counts it as foreign and goes on answering its plant."""
    bcu, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "0.5")
    sent = []

    def forge_once(t, v):   # after the first 0.5 s chunk: the plant's session is open
        if not sent:
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as hostile:
                hostile.sendto(forged_frame(2 ** 64 - 1), ("127.0.0.1", port))
            sent.append(t)

    result = hil.run(SCENARIO, ("127.0.0.1", port), cars=1, duration=1.5, priority=0, progress=forge_once,
                     key=SECRET)
    c = result.counters
    assert sent and c["received"] >= 140 and c["safe_state_steps"] < 100   # answers throughout (every 10 ms)
    t, frames = result.time, result.outputs["bcu_frames"]
    assert frames[-1] - frames[np.searchsorted(t, 1.0)] >= 40               # still answered after the forgery
    served = json.loads(bcu.communicate(timeout=60)[0])
    assert served["stale"] == 0 and served["received"] + served["challenges"] == c["frames_sent"]
    assert served["forged"] == 1 and served["foreign"] == 0 and served["refused"] == 0


def test_ctrl_c_keeps_the_recording_and_the_summary(bcu_process, railbrake_cli, tmp_path):
    bcu, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "0.5")
    record = tmp_path / "interrupted.mf4"
    # Ctrl-C as from a terminal: a shell's background job (make test run with &) ignores SIGINT, and
    # Python keeps an ignored SIGINT, so the plant gets the default disposition back
    run = plant(railbrake_cli, port, "--cars", "1", "--record", str(record),
                preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    while "session 0x" not in run.stderr.readline():   # the plant is running
        assert run.poll() is None
    time.sleep(1.0)
    run.send_signal(signal.SIGINT)
    out, err = run.communicate(timeout=60)
    assert run.returncode == 130, err
    assert "interrupted at t = " in err and "Traceback" not in err
    assert f"recording: {record}" in out and "frames sent" in out      # the summary table
    with MDF(record) as mdf:
        speed = mdf.get("speed")
    assert 0.4 < speed.timestamps[-1] < 3.0 and len(speed.samples) > 10
    bcu.communicate(timeout=60)


def test_sigterm_ends_the_bcu_with_its_counters(bcu_process):
    bcu, port = bcu_process(SCENARIO, "--cars", "1")
    time.sleep(0.5)
    bcu.send_signal(signal.SIGTERM)
    out, err = bcu.communicate(timeout=30)
    assert bcu.returncode == 130, err
    assert json.loads(out)["received"] == 0 and "interrupted" in err and "Traceback" not in err
