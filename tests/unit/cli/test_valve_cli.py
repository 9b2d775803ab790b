"""`railbrake valve` commands: JSON shape, units and error reporting."""

import json

import numpy as np
import yaml
from typer.testing import CliRunner

from railbrake import valves
from railbrake.cli import app

runner = CliRunner()


def test_epv_characteristic_json(tmp_path):
    plot = str(tmp_path / "c.png")
    out = runner.invoke(app, ["valve", "epv", "--characteristic", "--json", "--plot", plot])
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    assert {"current_up", "pressure_up", "current_down", "pressure_down", "hysteresis_bar", "quasi_static",
            "max_drop_up_bar", "pressure_down_at_0_a_bar"} <= set(data)
    assert max(data["current_up"]) == 1.0 and data["hysteresis_bar"] > 0 and data["quasi_static"]
    assert (tmp_path / "c.png").stat().st_size > 0


def test_step_commands_and_currents_above_the_rating(tmp_path):
    out = runner.invoke(app, ["valve", "epv", "--step", "--current", "0.8"])
    assert out.exit_code == 0 and "overshoot" in out.output and "settling" in out.output
    assert runner.invoke(app, ["valve", "relay", "--step", "--plot", str(tmp_path / "r.png")]).exit_code == 0
    for current in ("5", "1.2"):
        bad = runner.invoke(app, ["valve", "epv", "--step", "--current", current])
        assert bad.exit_code == 2 and f"current = {current} A: must lie in [0, 1] A" in bad.output


def test_solenoid_table_is_what_the_epv_reads(tmp_path):
    path = tmp_path / "t.csv"
    out = runner.invoke(app, ["valve", "solenoid", "--table", str(path), "--json"])
    assert out.exit_code == 0, out.output
    g, c, f = valves.read_force_table(path, 1.0)
    data = json.loads(out.stdout)
    assert np.allclose(f, data["force_n_table"], atol=1e-5) and data["force_n"] > 0


def test_solenoid_thermal_and_bad_duty():
    out = runner.invoke(app, ["valve", "solenoid", "--thermal", "--duty", "0.8", "--ambient-c", "70", "--json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    assert data["ambient_c"] == 70 and data["steady_c"] > 70 and "within_class" in data
    bad = runner.invoke(app, ["valve", "solenoid", "--thermal", "--duty", "1.5"])
    assert bad.exit_code == 2 and "must lie in [0, 1]" in bad.output


def test_reduce_prints_a_train_file_fragment():
    out = runner.invoke(app, ["valve", "epv", "--reduce"])
    assert out.exit_code == 0, out.output
    doc = yaml.safe_load(out.stdout)
    assert set(doc) == {"ep_valve", "relay_valve", "wsp_valves"}
    assert 0 < doc["ep_valve"]["response_s"] < 0.5 and doc["relay_valve"]["supply_area_mm2"] > 0
