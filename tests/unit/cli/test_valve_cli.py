"""`railbrake valve` commands: JSON shape, units and error reporting."""

import json

from typer.testing import CliRunner

from railbrake.cli import app

runner = CliRunner()


def test_epv_characteristic_json(tmp_path):
    plot = str(tmp_path / "c.png")
    out = runner.invoke(app, ["valve", "epv", "--characteristic", "--json", "--plot", plot])
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    assert set(data) == {"current_up", "pressure_up", "current_down", "pressure_down", "hysteresis_bar"}
    assert max(data["current_up"]) == 1.0 and data["hysteresis_bar"] > 0
    assert (tmp_path / "c.png").stat().st_size > 0


def test_step_commands_and_bad_current(tmp_path):
    assert runner.invoke(app, ["valve", "epv", "--step", "--current", "0.8"]).exit_code == 0
    assert runner.invoke(app, ["valve", "relay", "--step", "--plot", str(tmp_path / "r.png")]).exit_code == 0
    bad = runner.invoke(app, ["valve", "epv", "--step", "--current", "5"])
    assert bad.exit_code == 2 and "current = 5" in bad.output
