"""`railbrake config show`: the resolved configuration, overrides and their errors."""

import json

import yaml
from typer.testing import CliRunner

from railbrake.cli import app


def _invoke(*args):
    return CliRunner().invoke(app, ["config", "show", *args])


def test_show_prints_the_resolved_train_and_scenario_with_overrides():
    result = _invoke("emergency-250-dry", "--set", "train.car_types.motor.cylinder.stroke_mm=45",
                     "--set", "initial_speed=300 km/h", "--set", "train.load_case=crush")
    assert result.exit_code == 0, result.output
    tree = yaml.safe_load(result.stdout)
    assert tree["initial_speed"] == "300 km/h"
    assert tree["train"]["car_types"]["motor"]["cylinder"]["stroke_mm"] == 45
    assert tree["train"]["load_case"] == "crush" and tree["train"]["cars"] == 8
    assert tree["train"]["brake_steps"]["emergency"]["profile"] == "emergency-crh380a"


def test_show_json_and_keys():
    result = _invoke("emergency-250-dry", "--json", "--cars", "4")
    body = json.loads(result.stdout)
    assert len(body["digest"]) == 64 and body["config"]["train"]["cars"] == 4
    keys = _invoke("emergency-250-dry", "--keys").stdout.split()
    assert "train.car_types.trailer.wsp_valves.vent_area_mm2" in keys and "track.gradients" in keys


def test_bad_overrides_exit_non_zero_without_traceback():
    result = _invoke("emergency-250-dry", "--set", "train.car_types.motor.cylinder.volume=2 l")
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "no such key; closest valid keys: train.car_types.motor.cylinder" in result.output
    result = _invoke("emergency-250-dry", "--set", "initial_speed=300")
    assert result.exit_code == 2 and "a unit is required" in result.output
    result = _invoke("emergency-250-dry", "--set", "train.car_types.trailer.tare_t=40100")
    assert result.exit_code == 2
    assert "--set train.car_types.trailer.tare_t: car_types.trailer.tare_t = 40100: must lie in [5, 100] t" in result.output
