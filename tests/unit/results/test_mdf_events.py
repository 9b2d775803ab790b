"""MDF4 recordings carry what happened as events and name the states of enumerated channels:
`run fault-vent-valve-stuck --format mf4` writes the scenario's fault as a fault_on event at its
start (as `hil` does for the same scenario's scheduled fault), which asammdf reads; brake_demand
reads as release / service / emergency, its raw value kept."""

import numpy as np
import pytest
from asammdf import MDF
from typer.testing import CliRunner

from railbrake import scenario as scenarios
from railbrake.cli import app
from railbrake.hil.mdf import recording_events
from railbrake.results import files


def test_run_writes_the_scenario_s_fault_as_an_mdf4_event(tmp_path):
    out = CliRunner().invoke(app, ["run", "fault-vent-valve-stuck", "--cars", "3", "--out", str(tmp_path / "run"),
                                   "--format", "mf4"])
    assert out.exit_code == 0, out.output
    fault = scenarios.load("fault-vent-valve-stuck").spec.faults[0]
    with MDF(tmp_path / "run" / "timeseries.mf4") as mdf:
        events = [(e.name, e.sync_base * e.sync_factor, e.comment) for e in mdf.events]
    assert [(name, pytest.approx(t)) for name, t, _ in events] == [("fault_on", fault.start)]
    assert events[0][2] == f"{fault.type} on car {fault.car}, axle {fault.axle} (scheduled by the scenario)"


class _HilResult:   # what recording_events reads of a hil.Result
    time = np.array([0.0, 1.0, 2.0, 3.0])
    outputs = {"brake_demand": np.array([0.0, 2.0, 2.0, 2.0])}
    fault_changes = []
    events = [(2.5, "safe_on", "BCU silent for 0.1 s")]


def test_hil_recordings_name_the_scheduled_fault_too():
    events = recording_events(_HilResult(), scenarios.load("fault-vent-valve-stuck"))
    assert [(t, name) for t, name, _ in events] == [(1.0, "demand"), (2.0, "fault_on"), (2.5, "safe_on")]


def test_brake_demand_reads_as_text_with_its_raw_value_kept(tmp_path):
    demand = np.array([0.0, 0.5, 1.0, 2.0])
    mdf = MDF(version="4.10")
    mdf.append([files._mdf_signal("brake_demand", demand, np.arange(4.0), "1")])
    mdf.save(tmp_path / "d.mf4", overwrite=True)
    with MDF(tmp_path / "d.mf4") as back:
        text = [s.decode() for s in back.get("brake_demand").samples]
        raw = back.get("brake_demand", raw=True).samples
    assert [t.split(" ")[0] for t in text] == ["release", "service", "service", "emergency"]
    assert raw.tolist() == demand.tolist()
