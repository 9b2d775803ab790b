"""MDF4 recordings carry what happened as events and name the states of enumerated channels:
`run fault-vent-valve-stuck --format mf4` writes the scenario's fault as a fault_on event at its
start and the safety-timer trip it causes (the stuck vent empties the cylinder without command:
the BCU isolates the axle) as a wsp_trip event; a `hil` recording of the same scenario names the
scheduled fault and the safe state; every enumerated channel reads as text in asammdf, its raw
value kept."""

import json
import secrets

import numpy as np
import pytest
from asammdf import MDF
from typer.testing import CliRunner

from railbrake import hil
from railbrake import scenario as scenarios
from railbrake.cli import app
from railbrake.hil import mdf as hil_mdf
from railbrake.hil.mdf import recording_events
from railbrake.resolve import resolve
from railbrake.results import channel_info, files
from railbrake.simulation.parameters import wsp_params

SCENARIO = "fault-vent-valve-stuck"


def _events(path):
    with MDF(path) as mdf:
        return [(e.name, e.sync_base * e.sync_factor, e.comment) for e in mdf.events]


def test_run_writes_the_scenario_s_fault_and_the_wsp_trip_as_mdf4_events(tmp_path):
    out = CliRunner().invoke(app, ["run", SCENARIO, "--cars", "3", "--out", str(tmp_path / "run"),
                                   "--format", "mf4"])
    assert out.exit_code == 0, out.output
    fault = scenarios.load(SCENARIO).spec.faults[0]
    safety_time = wsp_params(resolve(SCENARIO, 3, []).scenario).safety_time   # s, the run's
    events = _events(tmp_path / "run" / "timeseries.mf4")
    assert [name for name, _, _ in events] == ["fault_on", "wsp_trip"]
    assert events[0][1] == pytest.approx(fault.start)
    assert events[0][2] == f"{fault.type} on car {fault.car}, axle {fault.axle} (scheduled by the scenario)"
    # the timer runs from the cylinder seen low without command, after the fault: not sooner
    print(f"fault at {events[0][1]:g} s, WSP trip at {events[1][1]:g} s (safety time {safety_time:g} s)")
    assert events[1][1] >= fault.start + safety_time
    assert events[1][2].startswith(f"car {fault.car}, axle {fault.axle}: isolated: safety timer tripped")
    kpis = json.loads((tmp_path / "run" / "kpis.json").read_text())
    assert kpis["safety_timer_trips"] == 1
    with MDF(tmp_path / "run" / "timeseries.mf4") as mdf:   # the trip as the channel reads it
        mode = mdf.get(f"wsp_mode_c{fault.car}a{fault.axle}")
        text = [s.decode() for s in mode.samples]
    assert text[0] == "apply" and text[-1].startswith("isolated")


def test_a_hil_recording_names_the_scheduled_fault_and_the_safe_state(tmp_path):
    """An unpaced run without BCU (the safe state from the start), written as `hil --record` writes."""
    sc = scenarios.load(SCENARIO)
    result = hil.run(SCENARIO, ("127.0.0.1", 9), cars=3, duration=2.5, paced=False, priority=0,
                     key=secrets.token_bytes(16))
    path = hil_mdf.write_mdf(result, tmp_path / "hil.mf4", sc)
    events = _events(path)
    assert [(name, pytest.approx(t)) for name, t, _ in events] == [("safe_on", 0.0),
                                                                    ("fault_on", sc.spec.faults[0].start)]
    assert "first valid BCU frame" in events[0][2] and "scheduled by the scenario" in events[1][2]


class _HilResult:   # what recording_events reads of a hil.Result
    time = np.arange(0.0, 4.0, 0.5)
    outputs = {"brake_demand": np.array([0.0, 0.0, 0.4, 2.0, 2.0, 2.0, 0.0, 0.0]),
               "safe_state": np.array([0, 0, 0, 1, 1, 1, 0, 1])}
    fault_changes = []
    events = [(1.3, "safe_on", "no valid BCU frame within the hold time: safe state"),
              (2.9, "safe_off", "valid BCU frames: safe state left")]


def test_safe_state_changes_from_the_log_and_those_it_dropped_from_the_channel():
    """The log's entries as logged; the channel's last entry (at 3.5 s), which the log no longer
    holds, from the channel; demand changes as text."""
    events = recording_events(_HilResult(), scenarios.load(SCENARIO))
    assert [(t, name) for t, name, _ in events] == [(1.0, "demand"), (1.3, "safe_on"), (1.5, "demand"),
                                                   (2.0, "fault_on"), (2.9, "safe_off"), (3.0, "demand"),
                                                   (3.5, "safe_on")]
    assert "recorded safe_state channel" in events[-1][2]
    assert [text for _, name, text in events if name == "demand"] == [
        "brake demand release -> service 40 %", "brake demand service 40 % -> emergency",
        "brake demand emergency -> release"]


@pytest.mark.parametrize("name", ["hold_c1a1", "vent_c2a3", "compressor_on", "safe_state", "wsp_mode_c1a2",
                                  "brake_demand"])
def test_every_enumerated_channel_reads_as_text_with_its_raw_value_kept(tmp_path, name):
    states = channel_info.STATES.get(channel_info.base_name(name))
    values = np.array(list(states) if states else [0.0, 0.5, 1.0, 2.0], dtype=float)
    mdf = MDF(version="4.10")
    mdf.append([files._mdf_signal(name, values, np.arange(float(len(values))), "1")])
    mdf.save(tmp_path / "d.mf4", overwrite=True)
    with MDF(tmp_path / "d.mf4") as back:
        text = [s.decode() for s in back.get(name).samples]
        raw = back.get(name, raw=True).samples
    if states:
        assert text == list(states.values())
    else:   # ranges of a number
        assert [t.split(" ")[0] for t in text] == ["release", "service", "service", "emergency"]
    assert raw.tolist() == values.tolist()


def test_every_integer_channel_of_run_and_hil_has_its_states():
    """Each channel of `run` and `hil` recorded with unit 1 is a ratio (slip, adhesion), a counter
    (bcu_frames) or a state channel with its text: none left bare."""
    from railbrake.hil.runs import channels as hil_channels
    from railbrake.simulation.parameters import channels as run_channels
    numbers = {"slip", "adhesion", "bcu_frames"}
    for name, unit in list(run_channels(2)) + list(hil_channels(2)):
        if unit == "1" and channel_info.base_name(name) not in numbers:
            assert channel_info.conversion(name) is not None, name


def test_a_fault_event_gives_the_fault_s_value_in_the_unit_its_range_is_given_in():
    """The value a fault kind reads (a gauge pressure, a leak's area, a sensor's noise) as the
    scenario's error messages give its range: bar, mm^2, km/h; in what was run (SI) too."""
    from railbrake.results.events import scheduled_faults
    from railbrake.results.record import _scenario_meta
    sc = scenarios.parse("""schema: railbrake.scenario/1
name: t
train: {preset: crh380a-8}
initial_speed: 250 km/h
demand: [{time: 0 s, emergency: true}]
faults:
  - {type: relay_valve_failed, car: 1, start: 1 s, pressure: 150 kPa}
  - {type: cylinder_leak, car: 2, axle: 3, leak_area: 1 mm^2}
  - {type: sensor_noisy, car: 3, axle: 1, noise: 0.5 m/s}
  - {type: emergency_valve_failed, car: 4}
""", "t.yaml")
    assert [comment for _, _, comment in scheduled_faults(sc)] == [
        "relay_valve_failed on car 1, pressure 1.5 bar (scheduled by the scenario)",
        "cylinder_leak on car 2, axle 3, leak_area 1 mm^2 (scheduled by the scenario)",
        "sensor_noisy on car 3, axle 1, noise 1.8 km/h (scheduled by the scenario)",
        "emergency_valve_failed on car 4 (scheduled by the scenario)"]
    faults = _scenario_meta(sc)["faults"]
    assert faults[0] == {"type": "relay_valve_failed", "car": 1, "axle": None, "start": 1.0, "pressure": 1.5e5}
    assert faults[3] == {"type": "emergency_valve_failed", "car": 4, "axle": None, "start": 0.0}
    # the run's report words them from what was run as the events do
    from railbrake.results.events import fault_text
    assert [fault_text(f) for f in faults] == [fault_text(f) for f in sc.spec.faults]
