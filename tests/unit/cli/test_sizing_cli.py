"""`railbrake size` and `railbrake stopping-distance`."""

import json

import pytest
from typer.testing import CliRunner

from railbrake.cli import app

runner = CliRunner()


def test_size_json_and_plot(tmp_path):
    plot = tmp_path / "size.png"
    out = runner.invoke(app, ["size", "--train", "crh380a-8", "--profile", "emergency", "--json",
                              "--plot", str(plot)])
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    assert set(data) == {"speed_kmh", "target_pressure_bar", "adhesion_demand", "ed_blending", "brakes", "warnings"}
    assert set(data["target_pressure_bar"]) == {"motor", "trailer"}
    assert len(data["target_pressure_bar"]["trailer"]) == len(data["speed_kmh"])
    assert 0.0 < max(data["target_pressure_bar"]["trailer"]) < 4.5
    assert plot.stat().st_size > 10_000


def test_readme_size_command_is_pneumatic_only_and_says_so():
    """README: `size --train crh380a-8 --profile emergency`: the profile is none of the train's brake
    steps, so no ED brake is counted (docs/vehicle.md's pneumatic-only pressures); --ed blends it."""
    from railbrake import sizing, vehicle
    command = ["size", "--train", "crh380a-8", "--profile", "emergency"]
    data = json.loads(runner.invoke(app, command + ["--json"]).stdout)
    assert data["ed_blending"] is False and data["brakes"].startswith("pneumatic brake only")
    train = vehicle.load_train("crh380a-8")
    alone = sizing.target_pressure(train, "emergency", ed=False)
    assert data["target_pressure_bar"]["motor"] == pytest.approx(list(alone.gauge_bar(alone.p_motor)), rel=1e-12)
    blended = json.loads(runner.invoke(app, command + ["--ed", "--json"]).stdout)
    assert blended["ed_blending"] is True
    # the ED brake takes load off the motor cars' cylinders wherever it acts; trailers unchanged
    assert max(blended["target_pressure_bar"]["motor"]) < max(data["target_pressure_bar"]["motor"])
    assert blended["target_pressure_bar"]["trailer"] == pytest.approx(data["target_pressure_bar"]["trailer"])
    text = runner.invoke(app, command).stdout
    assert "brakes: pneumatic brake only (ED brake not counted)" in text


def test_size_with_a_bad_profile_csv(tmp_path):
    csv = tmp_path / "p.csv"
    csv.write_text("speed_kmh,deceleration_ms2\n0,1.0\n100,1.0\n90,1.0\n")
    out = runner.invoke(app, ["size", "--profile-csv", str(csv)])
    assert out.exit_code == 2
    assert "speed_kmh[2] = 90.0" in out.output


def test_stopping_distance_hand_check():
    out = runner.invoke(app, ["stopping-distance", "--v0-kmh", "250", "--deceleration-ms2", "0.9",
                              "--response-time-s", "2", "--json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    v0 = 250 / 3.6
    assert data["stopping_distance_m"] == pytest.approx(v0 * 2 + v0**2 / 1.8, rel=1e-9)
    assert data["stopping_time_s"] == pytest.approx(2 + v0 / 0.9, rel=1e-9)


def test_stopping_distance_train():
    out = runner.invoke(app, ["stopping-distance", "--train", "crh380a-8", "--v0-kmh", "250", "--json"])
    assert out.exit_code == 0, out.output
    assert 1500 < json.loads(out.stdout)["stopping_distance_m"] < 2430  # TSI 250 km/h [T]


def test_size_counts_the_ed_brake_of_a_brake_step_whose_profile_is_a_file(tmp_path):
    # issue 38: velaro-8 blends its ED brake in emergency; with its emergency profile named as a
    # file (the same data) `size` blends it as with the preset name (3.98 against 1.29 bar before)
    from importlib import resources
    from railbrake.units import KMH
    data = resources.files("railbrake") / "data"
    profile = tmp_path / "my-emergency.yaml"
    profile.write_text((data / "profiles" / "emergency.yaml").read_text())
    train = tmp_path / "velaro-file.yaml"
    train.write_text((data / "trains" / "velaro-8.yaml").read_text().replace(
        "    profile: emergency\n    ed_blending: true", f"    profile: {profile}\n    ed_blending: true", 1))
    cases = []
    for name in ("velaro-8", str(train)):
        out = runner.invoke(app, ["size", "--train", name, "--json"])
        assert out.exit_code == 0, out.output
        cases.append(json.loads(out.stdout))
    assert str(profile) in train.read_text() and all(c["ed_blending"] for c in cases)
    at_50 = [c["speed_kmh"].index(50.0) for c in cases]
    motor = [c["target_pressure_bar"]["motor"][i] for c, i in zip(cases, at_50)]
    assert motor[1] == pytest.approx(motor[0], rel=1e-12)
    from railbrake import sizing
    alone = sizing.target_pressure("velaro-8", speeds=[50 * KMH], ed=False)
    assert motor[0] < alone.gauge_bar(alone.p_motor)[0] - 1.0   # the ED brake takes bars off the motor cars
