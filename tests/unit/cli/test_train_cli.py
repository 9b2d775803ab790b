"""`railbrake train new --from PRESET`: a commented train file that reads back as the preset."""

import pytest
from typer.testing import CliRunner

from railbrake import resolve, vehicle
from railbrake.cli import app

runner = CliRunner()


@pytest.mark.parametrize("preset", vehicle.preset_names())
def test_template_reads_back_as_the_preset(tmp_path, preset):
    path = tmp_path / "mine.yaml"
    out = runner.invoke(app, ["train", "new", "--from", preset, "--name", "mine", "-o", str(path)])
    assert out.exit_code == 0, out.output
    text = path.read_text()
    assert "# tare_t: [" in text and " t (" in text          # ranges in the key's unit, with why
    assert "# load_case: one of tare, normal, crush" in text
    mine, original = vehicle.load_train(path), vehicle.load_train(preset)
    assert mine.name == "mine"
    assert (mine.mass, mine.rotating_mass, mine.max_speed) == (original.mass, original.rotating_mass,
                                                                original.max_speed)
    assert mine.spec.model_dump(exclude={"name"}) == original.spec.model_dump(exclude={"name"})


def test_template_to_stdout_and_refusals(tmp_path):
    out = runner.invoke(app, ["train", "new", "--from", "crh380a-8"])
    assert out.exit_code == 0 and "name: my-crh380a-8" in out.stdout
    bad = runner.invoke(app, ["train", "new", "--from", "crh999"])
    assert bad.exit_code == 2 and "not a preset" in bad.output
    path = tmp_path / "t.yaml"
    path.write_text("x")
    exists = runner.invoke(app, ["train", "new", "--from", "crh380a-8", "-o", str(path)])
    assert exists.exit_code == 2 and "exists" in exists.output and path.read_text() == "x"
    named = runner.invoke(app, ["train", "new", "--from", "crh380a-8", "--name", "a b"])
    assert named.exit_code == 2 and "--name 'a b'" in named.output


def test_scenario_runs_on_the_template(tmp_path):
    path = tmp_path / "mine.yaml"
    assert runner.invoke(app, ["train", "new", "--from", "crh380a-8", "-o", str(path)]).exit_code == 0
    resolved = resolve.resolve("emergency-250-dry", sets={"train.preset": str(path)})
    assert resolved.train.name == "my-crh380a-8"
