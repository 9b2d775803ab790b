"""The live dashboard's server against a paced run without BCU (the safe state): the page and its
scripts ship with the package (nothing from the network), the API refuses calls without the token,
the live speed is the recorded one at the same plant time, a fault injected through the page's API
is in the recording at its time, and the page's stop ends the run. Assertions read the recording."""

import json
import re
import urllib.error
import urllib.request
from importlib import resources

import numpy as np
import pytest

from conftest import run_with_dashboard
from railbrake import _core
from railbrake.hil.dashboard import Dashboard


def get(url):
    with urllib.request.urlopen(url, timeout=30) as r:
        return r.status, r.read()


def post(url, data, token=None):
    """A POST as the page sends it: the token in `Authorization: Bearer`, checked before the body."""
    headers = {"Content-Type": "application/json"}
    if token is not None:
        headers["Authorization"] = f"Bearer {token}"
    request = urllib.request.Request(url, json.dumps(data).encode(), headers)
    try:
        with urllib.request.urlopen(request, timeout=30) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as exc:
        return exc.code, json.loads(exc.read())


def test_static_files_fetch_nothing_from_the_network():
    folder = resources.files("railbrake.hil.dashboard") / "static"
    for name in ("index.html", "dashboard.js", "dashboard.css"):
        text = (folder / name).read_text()
        assert not re.search(r"(https?:)?//[a-z0-9.-]+\.[a-z]{2,}", text, re.I), name   # no external address
        assert "@import" not in text


def test_dashboard_api_during_a_paced_run(tmp_path):
    board = Dashboard(cars=1)
    base, token = f"http://{board.host}:{board.port}", board.token
    seen, errors = {}, []

    def page():
        """What the page does: snapshots, a fault injected, bad calls refused, then stop."""
        try:
            assert get(base + "/")[0] == 200 and b"dashboard.js" in get(base + "/")[1]
            with pytest.raises(urllib.error.HTTPError):
                get(base + "/api/snapshot")
            snapshot = None
            while snapshot is None or snapshot["time"] < 0.5:
                snapshot = json.loads(get(f"{base}/api/snapshot?token={token}")[1])["snapshot"]
            seen["snapshot"] = snapshot
            seen["info"] = json.loads(get(f"{base}/api/info?token={token}")[1])
            fault = {"type": "vent_stuck_open", "car": 1, "axle": 3}
            seen["nokey"] = post(base + "/api/fault", {"command": "inject", "fault": fault})
            seen["bodykey"] = post(base + "/api/fault", {"token": token, "command": "inject", "fault": fault})
            seen["bad"] = post(base + "/api/fault", {"command": "inject",
                                                      "fault": {"type": "vent_stuck_open", "car": 4}}, token)
            seen["inject"] = post(base + "/api/fault", {"command": "inject", "fault": fault}, token)
            late = None   # null while the loop writes faster than a (slow, sanitized) reader can copy
            while late is None or late["time"] < seen["inject"][1]["time_s"] + 0.3:
                late = json.loads(get(f"{base}/api/snapshot?token={token}")[1])["snapshot"]
            seen["late"] = late
            seen["stop"] = post(f"{base}/api/stop?token={token}", {})
        except Exception as exc:   # noqa: BLE001 - reported by the test
            errors.append(repr(exc))
            board.request_stop()

    result = run_with_dashboard(board, page, 60.0)
    assert not errors, errors
    assert seen["nokey"][0] == 401 and "token" in seen["nokey"][1]["error"]
    assert seen["bodykey"][0] == 401    # a token in the body only: the body is not read before the token
    assert seen["bad"][0] == 400 and "cars 1..1" in seen["bad"][1]["error"]
    assert seen["inject"][0] == 200 and seen["stop"][0] == 200
    # every kind of the plant offered, with the value it reads (the page's value field)
    assert seen["info"]["fault_kinds"] == list(_core.FAULT_KINDS)
    assert seen["info"]["fault_values"]["relay_valve_failed"] == "pressure"
    assert "axle_isolated" not in seen["info"]["fault_values"]
    assert result.interrupted and result.time[-1] < 60.0          # the page stopped the run
    # the live speed is the recorded one at that plant time (recorded every 20 ms: interpolated)
    s = seen["snapshot"]
    recorded = np.interp(s["time"], result.time, result.outputs["speed"])
    assert s["speed"] == pytest.approx(recorded, rel=0.01)
    assert s["speed"] == pytest.approx(recorded, rel=1e-4)        # (in fact much closer)
    # the fault from the page: in the report and the recording at its time
    change = result.fault_changes[0]
    assert change.time_s == seen["inject"][1]["time_s"] and change.fault["axle"] == 3
    vent = result.outputs["vent_c1a3"]
    assert not vent[result.time <= change.time_s].any() and vent[result.time > change.time_s + 0.01].all()
    assert seen["late"]["vent"][2] == 1 and seen["late"]["vent"][1] == 0
