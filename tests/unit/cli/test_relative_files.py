"""A file names other files from where it lies: a user's train file with its own deceleration
profile beside it (`profile: my-emergency.yaml`) loads from any current folder in every command
that takes a train (run, size, stopping-distance, export-fmu, etcs), and a run folder holds every
file its config.yaml needs, so `railbrake run OUT/config.yaml` repeats the run from another folder
and from a copy of the folder."""

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

import railbrake
from railbrake.cli import app

DATA = Path(railbrake.__file__).parent / "data"
runner = CliRunner()


@pytest.fixture
def project(tmp_path, monkeypatch) -> Path:
    """project/trains/my-train.yaml (crh380a-8 braking on its own emergency profile, a copy of the
    preset's with 10 % less deceleration, beside it) and project/stop.yaml naming it; the current
    folder is elsewhere."""
    trains = tmp_path / "project" / "trains"
    trains.mkdir(parents=True)
    profile = (DATA / "profiles" / "emergency-crh380a.yaml").read_text(encoding="utf-8")
    (trains / "my-emergency.yaml").write_text(profile.replace("name: emergency-crh380a", "name: my-emergency"),
                                              encoding="utf-8")
    train = (DATA / "trains" / "crh380a-8.yaml").read_text(encoding="utf-8")
    assert "profile: emergency-crh380a\n" in train
    (trains / "my-train.yaml").write_text(train.replace("profile: emergency-crh380a\n", "profile: my-emergency.yaml\n")
                                          .replace("name: crh380a-8", "name: my-train"), encoding="utf-8")
    scenario = (DATA / "scenarios" / "emergency-250-dry.yaml").read_text(encoding="utf-8")
    (tmp_path / "project" / "stop.yaml").write_text(
        scenario.replace("train: {preset: crh380a-8}", "train: {preset: trains/my-train.yaml, cars: 1}")
        .replace("initial_speed: 250 km/h", "initial_speed: 80 km/h"), encoding="utf-8")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    return tmp_path / "project"


def invoke(*args):
    out = runner.invoke(app, [str(a) for a in args])
    assert out.exit_code == 0, out.output
    return out


def test_the_train_s_profile_is_found_beside_it_from_another_folder(project):
    train = project / "trains" / "my-train.yaml"
    assert "my-emergency.yaml" not in [p.name for p in Path.cwd().iterdir()]
    invoke("size", "--train", train, "--json")
    sd = json.loads(invoke("stopping-distance", "--train", train, "--v0-kmh", 200, "--json").stdout)
    preset = json.loads(invoke("stopping-distance", "--train", "crh380a-8", "--v0-kmh", 200, "--json").stdout)
    assert sd == preset   # the same profile under another name: the same stop
    invoke("export-fmu", train, "--fmi", 2, "--cars", 1, "-o", "plant.fmu")
    assert Path("plant.fmu").stat().st_size > 10_000


@pytest.mark.slow   # a whole ETCS analysis: 23 s plain, 210 s under the sanitizers, which add nothing to a path test
def test_etcs_braking_model_takes_the_train_file_from_another_folder(project):
    invoke("etcs", "braking-model", project / "trains" / "my-train.yaml", "--cars", 4, "--speed", 80,
           "--samples", 2, "--rare-samples", 2, "--out", "etcs", "--workers", 1,
           "--run-budget", 0, "--force-conditions")   # EN 15595's test condition holds from 120 km/h: forced at 80, recorded
    assert (Path("etcs") / "braking-model.json").is_file()


def test_a_run_folder_and_its_copy_rerun_from_another_folder(project, tmp_path, monkeypatch):
    first = json.loads(invoke("run", project / "stop.yaml", "--out", "run1", "--json").stdout)
    folder = Path("run1").resolve()
    assert (folder / "my-emergency.yaml").is_file()   # the file its config names, copied in
    config = (folder / "config.yaml").read_text(encoding="utf-8")
    assert "profile: my-emergency.yaml" in config and str(project) not in config.split("provenance:")[0]
    listed = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))["files"]
    assert {"my-emergency.yaml", "my-train.yaml", "config.yaml"} <= set(listed)   # the rerun needs each
    shutil.rmtree(project)   # nothing points back to the files it was made from
    copy = tmp_path / "colleague" / "run-copy"
    shutil.copytree(folder, copy)
    third = tmp_path / "third"
    third.mkdir()
    monkeypatch.chdir(third)
    for config_file in (folder / "config.yaml", copy / "config.yaml"):
        again = json.loads(invoke("run", config_file, "--json").stdout)
        assert again == first   # the KPIs, bit for bit
        assert railbrake.load_result(config_file.parent).kpis["stopping_distance_m"] == first["stopping_distance_m"]
