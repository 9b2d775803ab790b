"""Faults injected and cleared while the paced plant runs, over the control socket: bad commands
refused with a clear error while the loop keeps running; each change in the recording (MDF4 events
at the plant time the loop applied it, the valve channel stuck in between) and in the report.
Assertions read the recording, never the wall clock."""

import json
import socket
import threading

import numpy as np
import pytest

from railbrake import hil
from railbrake.hil.control import ControlServer
from railbrake.hil.mdf import write_mdf
from conftest import SECRET

DURATION = 3.0   # s paced, 1 car, no BCU: the safe state (valves de-energised) throughout


class Client:
    def __init__(self, port):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=30)
        self.lines = self.sock.makefile("rb")

    def send(self, payload) -> dict:
        data = payload if isinstance(payload, bytes) else json.dumps(payload).encode()
        self.sock.sendall(data + b"\n")
        return json.loads(self.lines.readline())


BAD = [  # command, words the refusal must hold
    (b"{not json", "not JSON"),
    ({"command": "inject", "fault": {"type": "vent_stuck_open", "car": 1, "axle": 2}}, "token missing or wrong"),
    ({"token": "wrong", "command": "inject", "fault": {"type": "vent_stuck_open", "car": 1}}, "token"),
    ({"command": "explode"}, "command = 'explode'"),
    ({"command": "inject", "fault": {"type": "valve_on_fire", "car": 1}}, "fault.type"),
    ({"command": "inject", "fault": {"type": "vent_stuck_open", "car": 1, "axle": 5}}, "fault.axle"),
    ({"command": "inject", "fault": {"type": "vent_stuck_open", "car": 2, "axle": 1}}, "cars 1..1"),
    ({"command": "inject", "fault": {"type": "sensor_noisy", "car": 1, "axle": 1}}, "needs noise"),
    ({"command": "clear", "fault": {"type": "hold_stuck_open", "car": 1, "axle": 1}}, "not present"),
    ({"command": "inject", "fault": {"type": "ed_lost", "car": 1, "axle": 1}}, "remove axle"),
    ({"command": "inject", "fault": {"type": "relay_valve_failed", "car": 1}}, "must lie in [0, 10] bar"),
    ({"command": "inject", "fault": {"type": "axle_isolated", "car": 1, "pressure": "1 bar"}}, "does not use pressure"),
    ({"command": "clear", "fault": {"type": "pressure_limiter_failed", "car": 1, "pressure": "2 bar"}},
     "named by type, car and axle only"),
]


def test_a_fault_s_pressure_reaches_the_plant_in_si():
    """The emergency path's kinds as a scenario file writes them: a gauge pressure in its unit,
    rb_fault.value in Pa; a car-level kind on every axle (-1)."""
    from railbrake import _core
    from railbrake.hil.faults import parse_fault
    spec, fault = parse_fault({"type": "pressure_limiter_failed", "car": 2, "pressure": "80 kPa"}, "inject", 2, "api")
    assert (fault.kind, fault.car, fault.axle) == (_core.FAULT_KINDS.index("pressure_limiter_failed"), 1, -1)
    assert fault.value == pytest.approx(0.8e5) and spec.pressure == pytest.approx(0.8e5)
    _, cleared = parse_fault({"type": "pressure_limiter_failed", "car": 2}, "clear", 2, "api")
    assert (cleared.kind, cleared.car, cleared.axle) == (fault.kind, fault.car, fault.axle)


def drive(server, outcome):
    """The test engineer: bad commands first, then vent stuck on car 1, axle 2, cleared 0.5 s later."""
    try:
        client = Client(server.port)
        token = server.token
        for command, words in BAD:
            if isinstance(command, dict) and "token" not in command and words != "token missing or wrong":
                command = {"token": token, **command}
            outcome.setdefault("refused", []).append((words, client.send(command)))
        fault = {"type": "vent_stuck_open", "car": 1, "axle": 2}
        outcome["on"] = client.send({"token": token, "command": "inject", "fault": fault})
        outcome["again"] = client.send({"token": token, "command": "inject", "fault": fault})
        threading.Event().wait(0.5)
        outcome["off"] = client.send({"token": token, "command": "clear", "fault": fault})
        outcome["listed"] = client.send({"token": token, "command": "faults"})
    except Exception as exc:   # noqa: BLE001 - reported by the test
        outcome["error"] = repr(exc)


def test_faults_changed_over_the_control_socket_are_in_the_recording(tmp_path):
    outcome, servers, threads = {}, [], []

    def on_faults(switch):
        server = ControlServer(switch)
        servers.append(server)
        threads.append(threading.Thread(target=drive, args=(server, outcome)))
        threads[-1].start()

    result = hil.run("emergency-300-heavy-rain", ("127.0.0.1", 9), cars=1, duration=DURATION, priority=0,
                     key=SECRET, on_faults=on_faults)
    threads[0].join()
    servers[0].stop()
    assert "error" not in outcome, outcome
    for words, reply in outcome["refused"]:
        assert reply["ok"] is False and words in reply["error"], (words, reply)
    assert outcome["on"]["ok"] and outcome["off"]["ok"], outcome
    assert not outcome["again"]["ok"] and "already active" in outcome["again"]["error"]
    assert result.counters["steps"] == round(DURATION / hil.DT)   # the loop ran on to its end
    t_on, t_off = outcome["on"]["time_s"], outcome["off"]["time_s"]
    assert 0.0 < t_on < t_off < DURATION
    assert [(c.action, c.time_s) for c in result.fault_changes] == [("inject", t_on), ("clear", t_off)]
    assert [c["action"] for c in outcome["listed"]["changes"]] == ["inject", "clear"]

    from asammdf import MDF
    path = write_mdf(result, tmp_path / "run.mf4")
    with MDF(path) as mdf:
        events = [(e.name, e.sync_base * e.sync_factor, e.comment) for e in mdf.events]
        vent = mdf.get("vent_c1a2", raw=True)
        other = mdf.get("vent_c1a1", raw=True)
        comment = mdf.header.comment
    faults = [e for e in events if e[0].startswith("fault")]
    assert [(name, pytest.approx(t, abs=1e-9)) for name, t, _ in faults] == [("fault_on", t_on), ("fault_off", t_off)]
    assert "vent_stuck_open on car 1, axle 2: injected" in faults[0][2]
    # the fault acts on the step it is applied in: stuck from the first sample after t_on to t_off
    stuck = (vent.timestamps > t_on + 1e-9) & (vent.timestamps <= t_off + 1e-9)
    assert stuck.any() and (~stuck).any()
    np.testing.assert_array_equal(vent.samples, np.where(stuck, 1.0, 0.0))
    assert not other.samples.any()
    assert "vent_stuck_open" in comment and "fault_changes" in comment


def test_recording_has_comments_state_texts_attachments_and_railbrake_as_its_tool(tmp_path):
    """A short unpaced run against no BCU: the safe state applies from the start (demand 2)."""
    from asammdf import MDF
    result = hil.run("emergency-300-heavy-rain", ("127.0.0.1", 9), cars=1, duration=0.3, paced=False,
                     priority=0, key=SECRET)
    path = write_mdf(result, tmp_path / "run.mf4")
    with MDF(path) as mdf:
        cylinder = mdf.get("cylinder_c1a2")
        vent = mdf.get("vent_c1a2")
        raw = mdf.get("vent_c1a2", raw=True)
        safe = mdf.get("safe_state")
        attachments = {a.file_name: mdf.extract_attachment(i)[0] for i, a in enumerate(mdf.attachments)}
        history = [fh.comment for fh in mdf.file_history]
    assert cylinder.comment == "brake cylinder pressure of the wheelset, absolute (car 1, axle 2)"
    assert raw.samples.dtype == np.uint8 and set(vent.samples) == {b"shut"}
    assert set(safe.samples) == {b"safe state"}   # no BCU answered: the safe state throughout
    assert json.loads(attachments["kpis.json"]) == json.loads(json.dumps(result.kpis))
    assert json.loads(attachments["scenario.json"])["scenario"] == "emergency-300-heavy-rain"
    assert len(history) == 1 and "<tool_id>railbrake</tool_id>" in history[0] and "asammdf" not in history[0]
    # railbrake's own reader gets the states back as numbers
    from railbrake.results import files
    outputs, *_ = files._read_mdf(path)
    assert outputs["vent_c1a2"].dtype == np.float64 and not outputs["vent_c1a2"].any()


@pytest.mark.parametrize("control, words", [("127.0.0.1:99999", "port = '99999'"), ("here", "port = 'here'")])
def test_bad_control_address_is_refused_before_the_run(railbrake_cli, hil_key, control, words):
    import subprocess
    done = subprocess.run([railbrake_cli, "hil", "emergency-300-heavy-rain", "--cars", "1", "--bcu",
                           "udp://127.0.0.1:9", "--key", str(hil_key), "--duration", "0.1", "--priority", "0",
                           "--control", control], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and "--control" in done.stderr and words in done.stderr, done.stderr
