"""The `railbrake adhesion` commands: JSON contracts, plots and error exits."""

import json

import pytest
from typer.testing import CliRunner

from railbrake.cli import app

runner = CliRunner()


def run(*args):
    return runner.invoke(app, list(args))


def test_curves_json_contract(tmp_path):
    plot = tmp_path / "wet.png"
    result = run("adhesion", "curves", "--condition", "wet", "--speed-kmh", "20,60,300",
                 "--plot", str(plot), "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert [c["speed_kmh"] for c in data["curves"]] == pytest.approx([20, 60, 300])
    for curve in data["curves"]:
        assert len(curve["creep"]) == len(curve["coefficient"])
        assert max(curve["creep"]) <= 1.0  # a fraction, not %
        assert curve["peak_coefficient"] >= max(curve["coefficient"]) - 1e-9
    assert data["curves"][2]["peak_coefficient"] == pytest.approx(0.18, abs=0.01)
    assert plot.stat().st_size > 10_000


def test_curves_axle_option_shows_rain_conditioning():
    lead = json.loads(run("adhesion", "curves", "--condition", "heavy-rain", "--speed-kmh", "300",
                          "--json").stdout)
    fourth_car = json.loads(run("adhesion", "curves", "--condition", "heavy-rain", "--speed-kmh", "300",
                                "--axle", "12", "--json").stdout)
    assert fourth_car["curves"][0]["peak_coefficient"] > 2 * lead["curves"][0]["peak_coefficient"]


def test_conditions_lists_presets_with_sources():
    result = run("adhesion", "conditions", "--json")
    assert result.exit_code == 0
    names = {c["name"]: c for c in json.loads(result.stdout)["conditions"]}
    assert names["dry-high"]["params"]["mu0"] == 0.55
    assert "Polach" in names["wet"]["source"]
    # each preset's fit: the data sets (validation cases) and the findings at a bound
    assert names["dry-medium"]["fit"]["fitted_on"] == ["curtius-kniffler-dry"]
    assert names["hs-wet"]["fit"]["bounds"]["A"] == [0.05, 1.0] and "A" in names["hs-wet"]["fit"]["at_bound"]


def test_fit_command_on_example(tmp_path):
    from pathlib import Path
    example = Path(__file__).resolve().parents[3] / "examples" / "measured_creep.csv"
    result = run("adhesion", "fit", str(example), "--plot", str(tmp_path / "fit.png"), "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["params"]["mu0"] == pytest.approx(0.30, rel=0.1)  # generated from Polach's wet set
    assert (tmp_path / "fit.png").exists()


@pytest.mark.parametrize("args, message", [
    (("adhesion", "curves", "--condition", "ice-age"), "condition = 'ice-age'"),
    (("adhesion", "curves", "--speed-kmh", "20,fast"), "'fast' is not a number"),
    (("adhesion", "curves", "--speed-kmh", "-20"), "speeds must be >= 0"),
    (("adhesion", "fit", "no-such-file.csv"), "no-such-file.csv"),
])
def test_bad_input_exits_non_zero_with_named_argument(args, message):
    result = run(*args)
    assert result.exit_code == 2
    assert message in result.output


def test_fit_rejects_csv_without_columns(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("s,f\n0.1,0.2\n")
    result = run("adhesion", "fit", str(path))
    assert result.exit_code == 2
    assert "needs ['coefficient', 'creep', 'speed_kmh']" in result.output


@pytest.mark.parametrize("command", [[], ["adhesion"], ["adhesion", "curves"], ["adhesion", "fit"],
                                     ["adhesion", "conditions"], ["demo"]])
def test_every_command_has_help(command):
    result = run(*command, "--help")
    assert result.exit_code == 0
    assert "Usage" in result.output
