"""What the plots pick out of a run, on constructed samples with known answers, and the WSP cycle
window of the default demo with at least three complete cycles."""

from pathlib import Path

import numpy as np
import pytest

from railbrake import simulation
from railbrake.cli.simulation import DEFAULT_SCENARIO
from railbrake.resolve import resolve
from railbrake.results import episodes, from_simulation
from railbrake.results.record import RunRecord
from railbrake.plots.simulation import slip_range


def _record(slips: dict, locked: tuple[float, float] | None = None) -> RunRecord:
    t = np.arange(0.0, 10.0, 0.01)
    v = np.full_like(t, 50.0)
    outputs = {"time": t, "speed": v}
    for axle, s in slips.items():
        slip = np.full_like(t, s)
        if locked and axle == "c1a2":
            slip[(t >= locked[0]) & (t <= locked[1])] = -1.0
        outputs[f"slip_{axle}"] = slip
        outputs[f"wheel_speed_{axle}"] = v * (1 + slip)
        for q in ("hold", "vent", "cylinder"):
            outputs[f"{q}_{axle}"] = np.zeros_like(t)
    return RunRecord(t, outputs, {n: "" for n in outputs}, {}, {"cars": 1})


def test_lock_episodes_and_the_worst_axle():
    r = _record({"c1a1": -0.02, "c1a2": -0.01, "c1a3": -0.03, "c1a4": -0.02}, locked=(2.0, 3.5))
    assert episodes.lock_episodes(r, "c1a2") == [(2.0, 3.5)]
    assert episodes.lock_episodes(r, "c1a1") == []
    assert episodes.worst_axle(r) == "c1a2"          # the lock beats the largest slip
    assert episodes.worst_axle(_record({"c1a1": -0.02, "c1a2": -0.05})) == "c1a2"


def test_the_slip_range_leaves_the_lock_out():
    r = _record({"c1a1": -0.02, "c1a2": -0.01}, locked=(2.0, 3.5))
    low, high = slip_range(r)
    assert low == pytest.approx(-100 * 0.02 * 1.3) and high > 0


def test_faulty_axles_are_always_plotted():
    r = _record({"c1a1": -0.02, "c1a2": -0.05, "c1a3": -0.01})
    r.meta["faults"] = [{"type": "vent_stuck_open", "car": 1, "axle": 3, "start": 0.0}]
    assert episodes.plotted_axles(r, ["c1a1"]) == ["c1a2", "c1a3", "c1a1"]


def _complete_cycles(record, axle, t0, t1) -> int:
    """Complete vent-hold-reapply cycles in [t0, t1], counted from the valve channels: a vent opening
    in [t0, t1) whose cylinder pressure falls while the vent is open, then a hold (hold valve closed,
    vent shut) and a reapply (both valves passing air from the relay valve) that raises the pressure
    again, ended by the next vent opening no later than t1 (a cycle cut off by the window's end is
    not complete)."""
    t = record.time
    hold, vent = record.channel("hold", axle) > 0.5, record.channel("vent", axle) > 0.5
    cylinder = record.channel("cylinder", axle)
    openings = [x for x in episodes.vent_openings(record, axle) if t0 <= x <= t1 + 1e-9]
    cycles = 0
    for a, b in zip(openings, openings[1:]):
        between = (t > a) & (t < b)
        venting = between & vent
        after = between & ~vent & (t > t[venting].max()) if venting.any() else between
        vented = venting.any() and cylinder[venting].min() < cylinder[np.searchsorted(t, a) - 1]
        reapplied = after.any() and cylinder[after].max() > cylinder[after].min()
        if vented and reapplied and (between & hold & ~vent).any() and (between & ~hold & ~vent).any():
            cycles += 1
    return cycles


def test_the_cycle_count_needs_vent_hold_and_reapply():
    """The counter itself on a constructed axle: vents at 1, 3, 5 and 7 s, each dropping the cylinder
    from 2.5 to 1.5 bar and held for 1 s, then reapplied to 2.5 bar, except the third one, held until
    the fourth vent: cycles 1-3 and 3-5 complete, 5-7 not (no reapply), 7- cut off by the end."""
    r = _record({"c1a1": -0.02})
    t = r.time
    vent, hold = r.outputs["vent_c1a1"], r.outputs["hold_c1a1"]
    cylinder = np.full_like(t, 2.5e5)
    for a in (1.0, 3.0, 5.0, 7.0):
        vent[(t >= a) & (t < a + 0.1)] = 1.0
        hold[(t >= a) & (t < a + 1.0)] = 1.0
        cylinder[(t >= a) & (t < a + 1.0)] = 1.5e5
    hold[(t >= 5.0) & (t < 7.0)] = 1.0
    cylinder[(t >= 5.0) & (t < 7.0)] = 1.5e5
    r.outputs["cylinder_c1a1"] = cylinder
    assert _complete_cycles(r, "c1a1", 0.5, 9.9) == 2
    assert _complete_cycles(r, "c1a1", 2.0, 9.9) == 1
    assert _complete_cycles(r, "c1a1", 0.5, 2.9) == 0     # the first cycle ends at 3 s, after the window


@pytest.mark.slow
def test_the_default_demo_shows_three_complete_wsp_cycles_of_its_worst_axle():
    """The default demo as `railbrake run` runs it (emergency-300-heavy-rain, 16 cars, to the stop; no
    files, the figure's own window and axle): the WSP cycle figure of the worst axle holds >= 3
    complete cycles (the figure of docs/simulation.md's worked example)."""
    resolved = resolve(DEFAULT_SCENARIO)
    record = from_simulation(simulation.run(resolved), resolved.scenario)
    axle = episodes.worst_axle(record)
    assert axle == record.kpis["worst_axle"] and axle in episodes.plotted_axles(record)
    t0, t1 = episodes.wsp_window(record, axle)
    assert episodes.WINDOW_MIN <= t1 - t0 <= episodes.WINDOW_MAX
    assert _complete_cycles(record, axle, t0, t1) >= 3
    docs = (Path(__file__).resolve().parents[3] / "docs" / "simulation.md").read_text(encoding="utf-8")
    assert 'default.plot("wsp_cycle")' in docs   # the executed worked example draws this axle's figure
