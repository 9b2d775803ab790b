"""Scenario files: every preset loads; bad files name the key and its line."""

import pytest
from typer.testing import CliRunner

from railbrake import scenario
from railbrake.cli import app
from railbrake.errors import InputError

GOOD = """schema: railbrake.scenario/1
name: t
train: {preset: crh380a-8}
initial_speed: 250 km/h
demand:
  - {time: 0 s, emergency: true}
faults:
  - {type: vent_stuck_open, car: 3, axle: 2, start: 2 s}
"""


def test_every_preset_loads():
    names = scenario.preset_names()
    assert {"emergency-250-dry", "emergency-300-heavy-rain", "service-200-wet",
            "emergency-300-leaves-patch", "fault-vent-valve-stuck"} <= set(names)
    for name in names:
        assert scenario.load(name).name == name


def test_units_convert_to_si():
    sc = scenario.parse(GOOD, "good")
    assert sc.spec.initial_speed == pytest.approx(250 / 3.6)
    assert sc.spec.faults[0].start == 2.0


@pytest.mark.parametrize("old, new, key, line", [
    ("name: t", "name: t\ncolour: red", "colour: unknown key", 3),
    ("initial_speed: 250 km/h", "initial_speed: fast", "initial_speed", 4),
    ("initial_speed: 250 km/h", "initial_speed: 250", "a unit is required", 4),
    ("initial_speed: 250 km/h", "initial_speed: 250 bar", "not a speed unit", 4),
    ("car: 3,", "car: 9,", "faults.0.car = 9", 8),
    ("{time: 0 s, emergency: true}", "{time: 0 s, emergency: maybe}", "demand.0.emergency", 6),
])
def test_bad_files_name_key_and_line(old, new, key, line):
    with pytest.raises(InputError) as info:
        scenario.parse(GOOD.replace(old, new), "bad.yaml")
    message = str(info.value)
    assert key in message
    assert f"line {line}" in message


def test_cli_rejects_a_bad_file(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text(GOOD.replace("car: 3,", "car: 12,"))
    result = CliRunner().invoke(app, ["run", str(path), "--json"])
    assert result.exit_code != 0
    assert "faults.0.car" in result.output and "line 8" in result.output
