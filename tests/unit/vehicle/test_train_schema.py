"""Train files (railbrake.train/2): strict numbers, plausible ranges in the file's units, old
schema refused, load cases; errors name file, line, key, value and the allowed range."""

import copy

import pytest
from typer.testing import CliRunner

from railbrake import vehicle
from railbrake.cli import app
from railbrake.errors import InputError


def _with(path, value, name="crh380a-8"):
    text, origin = vehicle.train_file_text(name)
    data, lines = vehicle.read_train_data(text, origin)
    data = copy.deepcopy(data)
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return data, origin, lines


@pytest.mark.parametrize("path, value, message", [
    (("car_types", "motor", "tare_t"), 44700.0, r"line \d+: car_types\.motor\.tare_t = 44700\.0: must lie in \[5, 100\] t"),
    (("car_types", "motor", "wheelset_inertia_kgm2"), 0.0, r"wheelset_inertia_kgm2 = 0\.0: must lie in \[10, 1000\] kg m\^2"),
    (("car_types", "trailer", "supply_reservoir", "volume_l"), 0.1, r"volume_l = 0\.1: must lie in \[5, 1000\] l \(5 to 1000 l of supply reservoir"),
    (("car_types", "trailer", "wsp_valves", "vent_area_mm2"), 4e4, r"vent_area_mm2 = 40000\.0: must lie in \[0\.1, 1000\] mm\^2"),
    (("car_types", "motor", "wheel_radius_m"), 430, r"wheel_radius_m = 430: must lie in \[0\.3, 0\.65\] m"),
    (("car_types", "trailer", "cylinder", "area_m2"), True, r"cylinder\.area_m2 = True: Input should be a valid number"),
    (("car_types", "motor", "discs", "mean_radius_m"), 1e12, r"mean_radius_m = 1000000000000\.0: must lie in \[0\.1, 0\.5\] m"),
    (("car_types", "motor", "wheelset_inertia_kgm2"), 1e29, r"wheelset_inertia_kgm2 = 1e\+29: must lie in \[10, 1000\] kg m\^2"),
    (("car_types", "motor", "tare_t"), "1e29", r"tare_t = '1e29': text, not a number .*: write 1\.0e\+29"),
    (("car_types", "motor", "payload_t", "crush"), "1_000", r"crush = '1_000': text, not a number"),
    (("max_speed_kmh",), -300.0, r"max_speed_kmh = -300\.0: must lie in \[50, 500\] km/h"),
    (("supply_pressure_bar",), 80.0, r"line \d+: supply_pressure_bar = 80: must lie in \[0\.187, 9\.99\] bar gauge"),
    (("supply_pressure_bar",), 8.0, r"supply_pressure_bar = 8: must stay below air_supply\.min_working_bar = 5\.5"),
    (("air_supply", "charged_bar"), 9.5, r"charged_bar = 9\.5 must not exceed governor_off_bar = 9\.0"),
    (("car_types", "motor", "pad_friction"), {"table": {"speed_kmh": [0, 100], "value": [0.4, 30]}},
     r"pad_friction\.table: .*value\[1\] = 30: must lie in \[0\.1, 0\.6\]"),
    (("car_types", "motor", "discs", "cooling_W_per_K"), {"speed_kmh": [-1e12, 100], "value": [1, 2]},
     r"speed_kmh\[0\] = -1e\+12: must lie in \[0, 540\] km/h"),
    (("air_supply", "pipe", "diameter_mm"), "25", r"diameter_mm = '25': text, not a number .*: write 25"),
    (("air_supply", "governor_off_bar"), 7.0, r"governor_off_bar = 7\.0 must exceed governor_on_bar = 7\.5"),
    (("air_supply", "compressors", 1, "car"), 9, r"compressors\[1\]\.car = 9: the formation has cars 1\.\.8"),
])
def test_implausible_values_are_named_with_their_range(path, value, message):
    data, origin, lines = _with(path, value)
    with pytest.raises(InputError, match=message) as err:
        vehicle.parse_train_data(data, origin, lines)
    assert str(err.value).startswith("train crh380a-8")


def test_train_1_files_are_refused_naming_the_new_schema():
    data, origin, lines = _with(("schema",), "railbrake.train/1")
    with pytest.raises(InputError, match=r"line 1: schema = 'railbrake.train/1': no longer read; .*'railbrake.train/2'"):
        vehicle.parse_train_data(data, origin, lines)


def test_load_cases():
    normal = vehicle.load_train("crh380a-8")
    assert normal.load_case == "normal" and normal.mass == pytest.approx(388.4e3)
    assert vehicle.load_train("crh380a-8", False).load_case == "tare"
    with pytest.raises(InputError, match=r"loaded = 'full': must be a load case \(tare, normal, crush\)"):
        vehicle.load_train("crh380a-8", "full")


def test_run_refuses_a_speed_above_the_trains_maximum(tmp_path):
    path = tmp_path / "fast.yaml"
    path.write_text("schema: railbrake.scenario/1\nname: fast\ntrain: {preset: crh380a-8}\n"
                    "initial_speed: 400 km/h\ndemand: [{time: 0 s, emergency: true}]\n")
    result = CliRunner().invoke(app, ["run", str(path), "--json"])
    assert result.exit_code != 0 and "Traceback" not in result.output
    assert f"{path}, line 4: initial_speed = 400 km/h: above the maximum speed of train crh380a-8, 350 km/h" in result.output


def test_gradient_needs_a_unit(tmp_path):
    path = tmp_path / "hill.yaml"
    path.write_text("schema: railbrake.scenario/1\nname: hill\ntrain: {preset: crh380a-8}\n"
                    "initial_speed: 200 km/h\ndemand: [{time: 0 s, emergency: true}]\n"
                    "track: {gradients: [{start: 0 m, gradient: 12}]}\n")
    result = CliRunner().invoke(app, ["run", str(path)])
    assert result.exit_code != 0 and "Traceback" not in result.output
    assert "line 6: track.gradients.0.gradient = 12: a unit is required" in result.output


def test_every_preset_names_its_minimum_working_pressure_below_the_governor():
    for name in ("velaro-8", "crh380al-16", "crh380a-8", "class387-4"):
        spec = vehicle.load_train(name).spec
        assert spec.supply_pressure_bar < spec.air_supply.min_working_bar < spec.air_supply.governor_on_bar


@pytest.mark.parametrize("value, message", [
    (20.0, r"line \d+: air_supply\.min_working_bar = 20\.0: must lie in \[1, 10\] bar"),
    (8.0, r"min_working_bar = 8\.0 must lie below governor_on_bar = 7\.5 \(bar gauge\)"),
    (4.0, r"supply_pressure_bar = 4\.5: must stay below air_supply\.min_working_bar = 4 \(bar gauge; train crh380a-8, line \d+\)"),
])
def test_a_bad_minimum_working_pressure_is_named_with_file_line_and_range(value, message):
    data, origin, lines = _with(("air_supply", "min_working_bar"), value)
    with pytest.raises(InputError, match=message) as err:
        vehicle.parse_train_data(data, origin, lines)
    assert str(err.value).startswith("train crh380a-8")


def test_a_train_file_without_it_is_refused():
    data, origin, lines = _with(("air_supply", "min_working_bar"), None)
    del data["air_supply"]["min_working_bar"]
    with pytest.raises(InputError, match=r"air_supply\.min_working_bar"):
        vehicle.parse_train_data(data, origin, lines)
