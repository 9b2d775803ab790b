"""Every key in every file is read or refused, and only regular files under the size limit are read
(issue 32, part 5): a scenario's train: keys, FIFOs, devices and directories named as files, study
files over 1 MiB, and the values of a study's assessment: and tuning: blocks."""

import os
import subprocess
import sys
from importlib import resources
from pathlib import Path

import pytest
from typer.testing import CliRunner

from railbrake import config, resolve, scenario
from railbrake.campaign import study
from railbrake.cli import app
from railbrake.errors import InputError

runner = CliRunner()
RAILBRAKE = str(Path(sys.executable).parent / "railbrake")
SCENARIO = ("schema: railbrake.scenario/1\nname: x\ntrain: {{{train}}}\ninitial_speed: 100 km/h\n"
            "demand: [{{time: 0 s, emergency: true}}]\nadhesion: {{condition: {condition}}}\n")


def _scenario(tmp_path, train="preset: crh380a-8, cars: 2", condition="dry-medium") -> Path:
    path = tmp_path / "sc.yaml"
    path.write_text(SCENARIO.format(train=train, condition=condition))
    return path


@pytest.mark.parametrize("train, key, hint", [
    ("presett: crh380a-8", "train.presett", "did you mean preset?"),
    ("preset: crh380a-8, car: 2", "train.car", "did you mean cars?"),
    ("preset: crh380a-8, max_speed_kmh: 100", "train.max_speed_kmh", "--set train.max_speed_kmh=VALUE"),
])
def test_scenario_train_keys_other_than_preset_cars_load_case_are_refused(tmp_path, train, key, hint):
    path = _scenario(tmp_path, train)
    out = runner.invoke(app, ["run", str(path)])
    assert out.exit_code == 2
    message = " ".join(out.output.split())
    assert f"{path}, line 3: {key}: unknown key" in message and hint in message
    assert "takes preset, cars, load_case" in message
    with pytest.raises(InputError, match=rf"line 3: {key}: unknown key"):
        resolve.resolve(str(path))
    with pytest.raises(InputError, match=rf"line 3: {key}: unknown key"):
        scenario.load(path)


def _refused_quickly(path: Path) -> str:
    """`railbrake run` of `path` in its own process: refused (exit 2), never hanging; its stderr."""
    out = subprocess.run([RAILBRAKE, "run", str(path)], capture_output=True, text=True, timeout=60)
    assert out.returncode == 2, out.stderr
    return out.stderr


def test_a_fifo_as_adhesion_condition_is_refused_at_once(tmp_path):
    fifo = tmp_path / "rain.yaml"
    os.mkfifo(fifo)
    error = _refused_quickly(_scenario(tmp_path, condition=str(fifo)))
    assert f"line 6: adhesion.condition = '{fifo}'" in error and "a FIFO (named pipe)" in error


def test_a_symlink_to_dev_zero_as_adhesion_condition_is_refused_at_once(tmp_path):
    zero = tmp_path / "zero.yaml"
    zero.symlink_to("/dev/zero")
    error = _refused_quickly(_scenario(tmp_path, condition=str(zero)))
    assert f"line 6: adhesion.condition = '{zero}'" in error and "a character device" in error


@pytest.mark.parametrize("kind", ["directory", "fifo", "device", "big"])
def test_read_text_reads_only_regular_files_under_the_limit(tmp_path, kind):
    path = tmp_path / "f.yaml"
    if kind == "directory":
        path.mkdir()
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "device":
        path.symlink_to("/dev/null")
    else:
        path.write_bytes(b"#" * (config.MAX_BYTES + 1))
    with pytest.raises(InputError, match=rf"^{path}: (a directory|a FIFO|a character device|over 1048576 bytes)"):
        config.read_text(path)


def test_a_50_mb_study_file_is_refused(tmp_path):
    path = tmp_path / "huge.yaml"
    with path.open("wb") as handle:
        handle.write(b"schema: railbrake.study/1\n")
        handle.truncate(50 * 2**20)   # sparse: 50 MB without writing them
    with pytest.raises(InputError, match=rf"^{path}: over 1048576 bytes"):
        study.load(path)
    out = runner.invoke(app, ["campaign", "plan", str(path)])
    assert out.exit_code == 2 and "over 1048576 bytes" in out.output


STUDY = (resources.files("railbrake") / "data" / "studies" / "wsp-en15595.yaml").read_text()


def _line(text: str, fragment: str) -> int:
    return text[:text.index(fragment)].count("\n") + 1


@pytest.mark.parametrize("old, new, expected", [
    ("air_limit_kg: 20.0", "air_limit_kg: 1.0e+300", "tuning.air_limit_kg = 1e+300: must lie in (0, 1000] kg"),
    ("air_limit_kg: 20.0", "air_limit_kg: 20.0\n  colour: red", "tuning.colour: unknown key"),
    ("wsp.slip_threshold: {low: 0.002, high: 0.05}", "wsp.slip_threshold: {}",
     "tuning.params.wsp.slip_threshold: a range is {low: .., high: .., levels: N (grid, zip)}"),
    ("wsp.slip_threshold: {low: 0.002, high: 0.05}", "wsp.slip_threshold: {low: 0.002, high: 1.0e+300}",
     "tuning.params.wsp.slip_threshold: low 0.002 to high 1e+300: must lie in [0, 0.5]"),
    ("wsp.slip_threshold: {low: 0.002, high: 0.05}", "wsp.slipp: {low: 0.002, high: 0.05}",
     "tuning.params.wsp.slipp: not a WSP parameter"),
    # te is EN 14531's on the total brake force (data/response/en14531.yaml): the study sets no fractions
    ("rank: wsp.controller", "rank: wsp.controller\n  build_up: {delay: 0.10, complete: 0.90}",
     "assessment.build_up: unknown key"),
    ("min_utilisation: 0.85", "min_utilisation: 1.0e+300", "assessment.criteria.min_utilisation = 1e+300: must lie in [0, 1]"),
    ("max_lock_events: 0", "max_lock_events: 0, max_delta_s_pct: 1.0e+300",
     "assessment.criteria.max_delta_s_pct = 1e+300: must lie in [0, 1000] %"),
    ("max_lock_events: 0", "max_lock_events: 0, max_lockups: 1", "assessment.criteria.max_lockups: unknown key"),
    ("reference: {adhesion_case: dry}", "reference: {}", "assessment.reference"),
    ("reference: {adhesion_case: dry}", "reference: {adhesion: dry}", "assessment.reference.adhesion: not a factor"),
    ("reference: {adhesion_case: dry}", "reference: {adhesion_case: damp}",
     "assessment.reference.adhesion_case = 'damp': not a level of factor adhesion_case (dry, low, very-low"),
    ("utilisation_cases: [low, very-low, hs-wet]", "utilisation_cases: [low, very-lo, hs-wet]",
     "assessment.criteria.utilisation_cases.1 = 'very-lo': not a level"),
])
def test_study_values_are_checked_whole(tmp_path, old, new, expected):
    assert old in STUDY
    text = STUDY.replace(old, new)
    path = tmp_path / "study.yaml"
    path.write_text(text)
    out = runner.invoke(app, ["campaign", "plan", str(path)])
    assert out.exit_code == 2, out.output
    message = " ".join(out.output.split())
    line = _line(text, new.split("\n")[-1].strip())
    assert f"{path}, line {line}" in message and expected in message, message
