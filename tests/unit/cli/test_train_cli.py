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


def test_a_new_formation_and_top_speed_give_a_consistent_train(tmp_path):
    """--cars / --formation / --max-speed: the formation asked for, its mass the sum of its cars'
    (the preset's car types), the title saying what it is, compressors only on cars it has."""
    path = tmp_path / "four.yaml"
    out = runner.invoke(app, ["train", "new", "--from", "crh380a-8", "--name", "four", "--cars", "4",
                              "--max-speed", "300", "-o", str(path)])
    assert out.exit_code == 0, out.output
    four, preset = vehicle.load_train(path), vehicle.load_train("crh380a-8")
    assert [c.type_name for c in four.cars] == [c.type_name for c in preset.cars][:4]
    assert four.mass == pytest.approx(sum(c.tare + c.load for c in preset.cars[:4]))
    assert four.max_speed == pytest.approx(300 / 3.6)
    assert "title: four, 4 cars (3M1T)" in path.read_text()
    assert [c.car for c in four.spec.air_supply.compressors] == [1]          # the preset's car 8 is gone
    long = runner.invoke(app, ["train", "new", "--from", "crh380a-8", "--cars", "16"])
    assert long.exit_code == 0, long.output
    assert "- {car: 16, delivery_kg_s: 0.016}" in long.stdout and "- {car: 9, delivery_kg_s: 0.016}" in long.stdout
    shaped = runner.invoke(app, ["train", "new", "--from", "crh380al-16", "--formation", "trailer,motor,trailer"])
    assert shaped.exit_code == 0 and "formation: [trailer, motor, trailer]" in shaped.stdout, shaped.output
    for args, message in ((["--formation", "trailer,tender"], "unknown: tender"),
                          (["--cars", "3", "--formation", "motor,motor"], "disagree"),
                          (["--max-speed", "900"], "max_speed_kmh")):
        bad = runner.invoke(app, ["train", "new", "--from", "crh380a-8", *args])
        assert bad.exit_code == 2 and message in bad.output, (args, bad.output)
