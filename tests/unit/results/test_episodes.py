"""What the plots pick out of a run, on constructed samples with known answers, and the WSP cycle
window of a heavy-rain run (the demo's condition) with at least three complete cycles."""

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from railbrake.cli import app
from railbrake.results import episodes, files
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
    """Vent openings in [t0, t1) each followed, before the next opening, by a hold (hold closed,
    vent closed) and a reapply (both valves open to the relay valve)."""
    t = record.time
    hold, vent = record.channel("hold", axle) > 0.5, record.channel("vent", axle) > 0.5
    openings = [x for x in episodes.vent_openings(record, axle) if t0 <= x < t1]
    cycles = 0
    for a, b in zip(openings, openings[1:] + [t1]):
        between = (t > a) & (t < b)
        if (between & hold & ~vent).any() and (between & ~hold & ~vent).any():
            cycles += 1
    return cycles


@pytest.mark.slow
def test_the_automatic_window_shows_three_complete_wsp_cycles_in_heavy_rain(tmp_path):
    spec = {"schema": "railbrake.scenario/1", "name": "heavy-rain-10s", "train": {"preset": "crh380al-16", "cars": 2},
            "initial_speed": "300 km/h", "demand": [{"time": "0 s", "emergency": True}],
            "adhesion": {"condition": "heavy-rain"}, "stop": {"speed": "0.05 m/s", "max_time": "12 s"}}
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(spec))
    result = CliRunner().invoke(app, ["run", str(tmp_path / "s.yaml"), "--out", str(tmp_path / "out"), "--json"])
    assert result.exit_code == 0, result.output
    record = files.load(tmp_path / "out")
    axle = episodes.worst_axle(record)
    t0, t1 = episodes.wsp_window(record, axle)
    assert episodes.WINDOW_MIN <= t1 - t0 <= episodes.WINDOW_MAX
    assert _complete_cycles(record, axle, t0, t1) >= 3
    assert (tmp_path / "out" / f"wsp_cycle_{axle}.png").is_file()
