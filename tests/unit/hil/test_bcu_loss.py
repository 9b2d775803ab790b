"""A safe state that is safe (docs/hil.md, watchdog): when the reference BCU process dies in an
emergency stop from 300 km/h on heavy rain, the plant applies the BCU's own emergency demand at the
speed, no more, with the WSP valves de-energised; the report and the exit status (3) say the BCU
was lost, when, and what it cost."""

import json
import signal
import subprocess
import time

import numpy as np
import pytest
from asammdf import MDF

from conftest import KEY_FILE, RAILBRAKE
from test_watchdog import safe_pressure

SCENARIO = "emergency-300-heavy-rain"


def test_bcu_killed_mid_stop(bcu_process, tmp_path):
    bcu, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "5")
    record = tmp_path / "lost.mf4"
    plant = subprocess.Popen([RAILBRAKE, "hil", SCENARIO, "--cars", "1", "--bcu", f"udp://127.0.0.1:{port}",
                              "--priority", "0", "--key", str(KEY_FILE), "--record", str(record), "--duration", "4",
                              "--record-interval", "0.001", "--json"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    while "session 0x" not in plant.stderr.readline():
        assert plant.poll() is None
    time.sleep(1.5)
    bcu.send_signal(signal.SIGKILL)
    out, err = plant.communicate(timeout=120)
    assert plant.returncode == 3, err
    report = json.loads(out)
    loss = report["bcu_loss"]
    assert loss["lost"] and loss["losses"] == 1 and "Traceback" not in err
    assert f"BCU lost at t = {loss['at_s']:.3f} s (its last valid frame at t = {loss['last_valid_s']:.3f} s)" \
        in " ".join(err.split())
    assert 0.09 < loss["at_s"] - loss["last_valid_s"] < 0.12          # the hold time (0.1 s), then lost
    assert loss["safe_s"] == pytest.approx(report["counters"]["steps"] * 1e-3 - loss["at_s"])
    with MDF(record) as mdf:
        t = mdf.get("speed").timestamps
        speed, safe = mdf.get("speed").samples, mdf.get("safe_state", raw=True).samples   # raw: 0/1, not texts
        demand = mdf.get("pressure_demand_c1").samples
        all_wheels = [mdf.get(f"wheel_speed_c1a{k}").samples for k in range(1, 5)]
        wheels = np.max(all_wheels, axis=0)
        hold = np.array([mdf.get(f"hold_c1a{k}", raw=True).samples for k in range(1, 5)])
        vent = np.array([mdf.get(f"vent_c1a{k}", raw=True).samples for k in range(1, 5)])
    before = (t > 0.5) & (t < loss["last_valid_s"])
    after = t >= loss["at_s"] + 0.002
    assert not safe[before].any() and safe[after].all()
    # what the BCU demanded before it died, and what the plant applies after: the same law, at the speed
    # (WSP off: no venting), never the 38 % more the demand at standstill would be
    assert demand[before].max() <= safe_pressure(wheels[before].min()) * 1.01
    assert np.allclose(demand[after], safe_pressure(wheels[after]), rtol=1e-2)
    first, last = np.argmax(after), np.flatnonzero(before)[-1]
    assert demand[first] <= demand[last] * 1.01 and demand[first] < 0.9 * safe_pressure(0.0)
    settled = t >= loss["at_s"] + 0.1   # the recorded valve states are the valves', which take time to move
    assert not hold[:, settled].any() and not vent[:, settled].any()
    # what it cost: the distance run while lost, from the recording
    i = np.searchsorted(t, loss["at_s"])
    assert loss["distance_m"] == pytest.approx(np.trapezoid(speed[i:], t[i:]), rel=0.02)
    locked = (wheels_min := np.min([wheel for wheel in all_wheels], axis=0)) < 0.1 * speed
    print(f"BCU lost at {loss['at_s']} s: {loss}; slowest wheel below 10 % of the speed for "
          f"{locked[i:].sum() * 1e-3:.3f} s")
