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


# ------------------------------------------------------------------ physically meaningless values (issue 15)

@pytest.mark.parametrize("old, new, message, line", [
    ("initial_speed: 250 km/h", "initial_speed: -100 km/h",
     r"initial_speed = '-100 km/h': must lie in \[0, 540\] km/h", 4),
    ("demand:", "stop: {speed: -1 m/s}\ndemand:", r"stop\.speed = '-1 m/s': must lie in \[0, 10\] m/s", 5),
    ("demand:", "stop: {speed: 1e12 m/s}\ndemand:", r"stop\.speed = '1e12 m/s': must lie in \[0, 10\] m/s", 5),
    ("initial_speed: 250 km/h", "initial_speed: 10 km/h\nstop: {speed: 20 km/h}",
     r"stop\.speed = '20 km/h': must be below initial_speed = '10 km/h'", 5),
    ("demand:", "outputs: {record_interval: 1e-9 s}\ndemand:",
     r"outputs\.record_interval = '1e-9 s': must lie in \[0\.001, 1\] s", 5),
    ("demand:", "stop: {max_time: 3600 s}\noutputs: {record_interval: 1 ms}\ndemand:",
     r"outputs\.record_interval = '1 ms': .* recorded values .* must be at least", 6),
    ("{time: 0 s, emergency: true}", "{time: 0 s, emergency: true, service: 0.5}",
     r"demand\[0\] has emergency: true and service = 0\.5", 6),
    ("{time: 0 s, emergency: true}", "{time: 0 s, service: 0}", r"demand: no demand step brakes", 5),
    ("{time: 0 s, emergency: true}", "{time: 0 s, emergency: true}\n  - {time: 400 s, service: 0.3}",
     r"demand\.1\.time = '400 s': at or after stop\.max_time = 300 s", 7),
    ("start: 2 s}", "start: 2 s, leak_area: 10 mm^2}",
     r"faults\.0\.leak_area: a vent_stuck_open fault does not use leak_area", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2, start: 2 s}", "{type: ed_lost, car: 8}",
     r"faults\.0\.car = 8: an ed_lost fault on a trailer \(trailer\) of train crh380a-8", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2,", "{type: compressor_off, car: 3,",
     r"faults\.0\.car = 3: a compressor_off fault stops every compressor of the train", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2,", "{type: vent_stuck_open, axle: 2,",
     r"faults\.0\.type: a vent_stuck_open fault needs car", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2,", "{type: car_isolated, car: 3, axle: 2,",
     r"faults\.0\.axle = 2: a car_isolated fault acts on the whole car", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2, start: 2 s}", "{type: cylinder_leak, car: 3, leak_area: 1e12 mm^2}",
     r"faults\.0\.leak_area = '1e12 mm\^2': must lie in \[0\.01, 1000\] mm\^2", 8),
    # the emergency path's kinds (issue 36): a pressure only where the kind reads one, in its range
    ("start: 2 s}", "start: 2 s, pressure: 1 bar}",
     r"faults\.0\.pressure: a vent_stuck_open fault does not use pressure \(only a relay_valve_failed or "
     r"pressure_limiter_failed fault does\): remove it", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2, start: 2 s}", "{type: relay_valve_failed, car: 3}",
     r"faults\.0\.type: a relay_valve_failed fault needs pressure, the most the relay valve gives, gauge \(0 bar: "
     r"no output\); it must lie in \[0, 10\] bar", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2, start: 2 s}", "{type: pressure_limiter_failed, car: 3}",
     r"faults\.0\.type: a pressure_limiter_failed fault needs pressure, .*; it must lie in \[0, 10\] bar", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2, start: 2 s}", "{type: relay_valve_failed, car: 3, pressure: 12 bar}",
     r"faults\.0\.pressure = '12 bar': must lie in \[0, 10\] bar", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2, start: 2 s}", "{type: pressure_limiter_failed, car: 3, pressure: -5 kPa}",
     r"faults\.0\.pressure = '-5 kPa': must lie in \[0, 1000\] kPa", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2, start: 2 s}", "{type: relay_valve_failed, car: 3, pressure: 1.5}",
     r"faults\.0\.pressure = 1\.5: a unit is required \(pressure: bar, kPa, Pa\), e\.g\. '1\.5 bar'", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2,", "{type: emergency_valve_failed, car: 3, axle: 2,",
     r"faults\.0\.axle = 2: an emergency_valve_failed fault acts on the whole car", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2,", "{type: relay_valve_failed, car: 3, axle: 2, pressure: 1 bar,",
     r"faults\.0\.axle = 2: a relay_valve_failed fault acts on the whole car", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2,", "{type: axle_isolated, axle: 2,",
     r"faults\.0\.type: an axle_isolated fault needs car", 8),
    ("{type: vent_stuck_open, car: 3, axle: 2,", "{type: axle_isolated, car: 9, axle: 2,",
     r"faults\.0\.car = 9: the train has cars 1\.\.8", 8),
    ("demand:", "wsp: {safety_time: 0 s}\ndemand:", r"wsp\.safety_time = '0 s': must lie in \[0\.5, 30\] s", 5),
    ("demand:", "wsp: {speed_threshold: -1 m/s}\ndemand:",
     r"wsp\.speed_threshold = '-1 m/s': must lie in \[0\.01, 10\] m/s", 5),
    ("demand:", "wsp: {speed_threshold: -3.6 km/h}\ndemand:",
     r"wsp\.speed_threshold = '-3\.6 km/h': must lie in \[0\.036, 36\] km/h", 5),
    ("demand:", "wsp: {slip_threshold: 5}\ndemand:", r"wsp\.slip_threshold = 5: must lie in \[0, 0\.5\]", 5),
    ("demand:", "wsp: {cycle: 5 s}\ndemand:", r"wsp\.cycle = '5 s': must lie in \[0\.0001, 0\.1\] s", 5),
    ("demand:", "wsp: {cycle: 1e-9}\ndemand:", r"wsp\.cycle = '1e-9': a unit is required", 5),
    ("demand:", "track: {gradients: [{start: 0 m, gradient: 50 %}]}\ndemand:",
     r"gradient = '50 %': must lie in \[-10, 10\] %", 5),
    ("faults:", "adhesion:\n  zones:\n    - {start: 1500 m, end: 1800 m, condition: leaves}\n"
     "    - {start: 1700 m, end: 1900 m, condition: wet}\nfaults:",
     r"line 10: adhesion\.zones\.1: adhesion\.zones\[1\] \(1700 to 1900 m, wet\) overlaps adhesion\.zones\[0\] "
     r"\(1500 to 1800 m, leaves; good, line 9: adhesion\.zones\.0\)", 10),
])
def test_meaningless_values_are_refused_in_the_users_unit(old, new, message, line):
    assert old in GOOD
    with pytest.raises(InputError, match=message) as err:
        scenario.parse(GOOD.replace(old, new, 1), "good")
    assert f"good, line {line}:" in str(err.value) and "Value error" not in str(err.value)


def test_a_coast_down_run_is_said_so():
    text = GOOD.replace("{time: 0 s, emergency: true}", "{time: 0 s, service: 0}") + "coast: true\n"
    assert scenario.parse(text, "good").spec.coast


def test_an_error_inside_an_adhesion_file_names_that_file(tmp_path):
    from importlib import resources
    bad = tmp_path / "wet-bad.yaml"
    bad.write_text((resources.files("railbrake") / "data" / "adhesion" / "wet.yaml").read_text()
                   .replace("mu0: ", "mu0: -", 1))
    text = GOOD + f"adhesion: {{condition: {bad}}}\n"
    with pytest.raises(InputError, match=rf"good, line 9: adhesion\.condition = .*: {bad}, line \d+: params\.mu0 = -"):
        scenario.parse(text, "good")
    with pytest.raises(InputError, match=rf"adhesion\.condition = .*: {tmp_path}/nope\.yaml: no such file"):
        scenario.parse(GOOD + f"adhesion: {{condition: {tmp_path}/nope.yaml}}\n", "good")


def test_a_train_slower_than_the_scenario_is_refused(tmp_path):
    from importlib import resources
    slow = tmp_path / "slow.yaml"
    slow.write_text((resources.files("railbrake") / "data" / "trains" / "crh380a-8.yaml").read_text()
                    .replace("max_speed_kmh: 350", "max_speed_kmh: 100"))
    with pytest.raises(InputError, match=r"good, line 4: initial_speed = 250 km/h: above the maximum speed of "
                                         r"train crh380a-8, 100 km/h"):
        scenario.parse(GOOD.replace("preset: crh380a-8", f"preset: {slow}"), "good")


def test_every_fault_kind_of_the_plant_is_writable():
    """The scenario's fault types are the plant's (rb_plant.h, rb_fault_kind), each with the units
    of the ETCS reliability file (a car-level kind takes no axle; the same kinds read a value)."""
    from typing import get_args

    from railbrake import _core
    from railbrake.etcs import inputs
    assert sorted(get_args(scenario.FaultType)) == sorted(_core.FAULT_KINDS)
    assert set(scenario.CAR_FAULTS) == set(inputs.CAR_KINDS) | set(inputs.TRAIN_KINDS)
    assert set(scenario.FAULT_VALUE) == set(inputs.VALUE_KEYS)


def test_every_bound_used_by_the_files_is_in_the_c_table():
    """One definition: the schemas name bounds of core/src/bounds.c, none of their own."""
    import re
    from pathlib import Path

    from railbrake import _core
    root = Path(scenario.__file__).parent
    used = set()
    for path in [root / "scenario.py", root / "vehicle.py", root / "sizing.py", root / "adhesion" / "conditions.py",
                 root / "adhesion" / "fit.py", root / "valves" / "params.py"]:
        used |= set(re.findall(r'"((?:train|scenario|wsp|bcu|car|profile|adhesion|valve|coupler)\.[a-z_0-9]+)"',
                               path.read_text()))
    assert len(used) > 60 and used <= set(_core.BOUNDS), sorted(used - set(_core.BOUNDS))
