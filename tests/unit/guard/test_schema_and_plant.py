"""Guard rails where a file's schema and the plant disagree (issue 31, part 4): each case is refused
when the file loads, naming the user's file, the line, the key and what is allowed, and the CLI
exits with status 2 (never a crash in the middle of a run, never a silently different train)."""

import subprocess
import sys
from importlib import resources
from pathlib import Path

import pytest
from typer.testing import CliRunner

from railbrake import resolve, sizing, vehicle
from railbrake.cli import app
from railbrake.errors import InputError

runner = CliRunner()
PRESET = (resources.files("railbrake") / "data" / "trains" / "crh380a-8.yaml").read_text()
MOTOR = PRESET.index("  motor:")
TRAILER = PRESET.index("  trailer:")


def _line(text: str, fragment: str) -> int:
    return text[:text.index(fragment)].count("\n") + 1


def _scenario(tmp_path: Path, train_text: str, cars: str = "") -> Path:
    train = tmp_path / "my-train.yaml"
    train.write_text(train_text)
    scenario = tmp_path / "my-scenario.yaml"
    scenario.write_text("schema: railbrake.scenario/1\nname: x\n"
                        f"train: {{preset: my-train.yaml{cars}}}\ninitial_speed: 100 km/h\n"
                        "demand: [{time: 0 s, emergency: true}]\n")
    return scenario


def _refused(tmp_path, train_text, *expected, command=("config", "show")):
    scenario = _scenario(tmp_path, train_text)
    out = runner.invoke(app, [*command, str(scenario)])
    assert out.exit_code == 2, out.output
    assert str(tmp_path / "my-train.yaml") in out.output     # the user's file, not the packaged one
    for text in expected:
        assert text in out.output, out.output
    assert "Error" not in out.output and "vehicle." not in out.output   # no internal class or struct names
    return out.output


def test_a_six_axle_car_is_refused_at_load(tmp_path):
    six = PRESET[:TRAILER].replace("axles: 4", "axles: 6", 1).replace(
        "axle_positions_m: [2.5, 5.0, 20.0, 22.5]", "axle_positions_m: [2.5, 5.0, 7.5, 17.5, 20.0, 22.5]", 1) \
        + PRESET[TRAILER:]
    line = _line(six, "axles: 6")
    for command in (("config", "show"), ("run",)):
        _refused(tmp_path, six, f"line {line}: car_types.motor.axles = 6", "allowed: 4", command=command)
    with pytest.raises(InputError, match="axles"):   # `size` reads the same file: refused too
        vehicle.load_train(tmp_path / "my-train.yaml")


@pytest.mark.parametrize("old, new", [
    ("    - {c0: 509.6}\n    - {c0: 544.34, c1: -1.787}\n    - {c0: -121.0, c2: 42942.9}\n"
     "    - {c0: 0.0, c2: 33033.0}", "    - {c0: -509.6}"),
    ("scale: 0.428571", "scale: 0.0"),
])
def test_an_ed_curve_that_gives_no_force_is_refused(tmp_path, old, new):
    text = PRESET.replace(old, new)
    _refused(tmp_path, text, f"line {_line(text, 'ed_brake:')}: ed_brake", "zero or negative",
             "must lie in (0, 2000] kN")


def test_an_ed_brake_without_motor_cars_or_blending_without_ed_is_refused(tmp_path):
    trailers = PRESET.replace("kind: motor", "kind: trailer")
    _refused(tmp_path, trailers, f"line {_line(trailers, 'ed_brake:')}: ed_brake: the formation has no motor car")
    no_ed = PRESET[:PRESET.index("ed_brake:")] + PRESET[PRESET.index("brake_steps:"):]
    no_ed = no_ed.replace("ed_blending: true", "ed_blending: true ", 1)
    _refused(tmp_path, no_ed, f"line {_line(no_ed, 'ed_blending: true ')}: brake_steps.service.ed_blending = true",
             "no ed_brake to blend")


def test_a_crush_payload_below_the_normal_one_is_refused(tmp_path):
    text = PRESET.replace("payload_t: {normal: 5.0, crush: 9.0}", "payload_t: {normal: 5.0, crush: 2.0}", 1)
    _refused(tmp_path, text, f"line {_line(text, 'crush: 2.0')}: car_types.motor.payload_t.crush = 2.0",
             "must lie in [5, 60] t")


def test_a_formation_longer_than_the_plant_names_the_train_file(tmp_path):
    text = PRESET[:PRESET.index("formation:")] + "formation: [" + ", ".join(["motor"] * 20) + "]\n"
    _refused(tmp_path, text, f"line {_line(text, 'formation:')}: formation has 20 cars",
             "a run simulates 1 to 16 cars")
    scenario = _scenario(tmp_path, text, cars=", cars: 8")   # a part of it runs
    assert resolve.resolve(str(scenario)).cars == 8


def test_an_override_inside_a_block_names_the_override():
    with pytest.raises(InputError, match=r"^--set train.car_types.motor.length_m \(train crh380a-8, line \d+\): "
                                         r"car_types.motor: axle_positions_m\[3\] = 22.5"):
        resolve.resolve("emergency-250-dry", sets=["train.car_types.motor.length_m=20"])


@pytest.mark.parametrize("option", ["--workers", "--batch-size"])
def test_zero_workers_or_batch_size_exit_2(option):
    out = runner.invoke(app, ["campaign", "run", "wsp-en15595", option, "0"])
    assert out.exit_code == 2 and f"Invalid value for '{option}'" in out.output
    assert "greater than or equal to 1" in out.output


def test_zero_workers_from_python_names_the_argument(tmp_path):
    from railbrake.campaign import execute, study
    with pytest.raises(InputError, match=r"workers = 0: must be >= 1"):
        execute.run_study(study.load("wsp-en15595"), tmp_path, workers=0)
    with pytest.raises(TypeError, match=r"batch_size = 2.5: must be a whole number"):
        execute.run_study(study.load("wsp-en15595"), tmp_path, batch_size=2.5)


def test_run_warns_like_size_when_the_demand_exceeds_the_supply(tmp_path):
    """A supply of 2 bar cannot give the emergency pressures `size` computes (above 2.4 bar): the run
    says so, as size does, with the speeds where the cylinders stay below the target."""
    text = PRESET.replace("supply_pressure_bar: 4.5", "supply_pressure_bar: 2.0")
    train = tmp_path / "my-train.yaml"
    train.write_text(text)
    sized = sizing.target_pressure(vehicle.load_train(train))
    assert any("exceeds the supply 2.00 bar" in w for w in sized.warnings)
    scenario = _scenario(tmp_path, text, cars=", cars: 1")
    with pytest.warns(sizing.SupplyWarning) as shown:
        out = runner.invoke(app, ["run", str(scenario), "--set", "initial_speed=40 km/h", "--json"])
    assert out.exit_code == 0, out.output
    texts = [str(w.message) for w in shown]
    assert any(t.startswith("scenario x: emergency brake: trailer cylinder pressure up to") and
               "exceeds the supply 2.00 bar at 0-40 km/h" in t for t in texts), texts
    shown_by_cli = subprocess.run([str(Path(sys.executable).parent / "railbrake"), "run", str(scenario), "--set",
                                   "initial_speed=40 km/h", "--json"], capture_output=True, text=True, timeout=120)
    assert "warning: scenario x: emergency brake: trailer cylinder pressure" in shown_by_cli.stderr
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", sizing.SupplyWarning)   # the preset's supply suffices: no warning
        assert runner.invoke(app, ["run", "emergency-250-dry", "--cars", "1", "--set", "initial_speed=40 km/h",
                                   "--json"]).exit_code == 0


def test_an_unexpected_error_names_no_internal_class(monkeypatch):
    from railbrake.cli import sizing as sizing_cli

    def broken(*args, **kwargs):
        raise KeyError("motor")
    monkeypatch.setattr(sizing_cli.sizing, "target_pressure", broken)
    out = runner.invoke(app, ["size"])
    assert out.exit_code == 2 and "KeyError" not in out.output and "unexpected" in out.output


def test_a_closed_pipe_is_quiet():
    """`railbrake config show ... | head -1`: no 'Broken pipe', no traceback."""
    command = [str(Path(sys.executable).parent / "railbrake"), "config", "show", "emergency-250-dry"]
    with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, bufsize=0) as process:
        process.stdout.readline()
        process.stdout.close()
        error = process.stderr.read()
        process.wait(timeout=60)
    assert error == b"" and process.returncode in (0, 141)
