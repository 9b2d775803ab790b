"""Shell completion (`railbrake --install-completion`) completes scenario arguments with the preset
names (and export-fmu's with the train presets too), train, study, profile, adhesion condition and
sequence arguments with theirs, then the YAML files of the current folder."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

RAILBRAKE = str(Path(sys.executable).parent / "railbrake")


def complete(words: str, cwd: Path) -> list[str]:
    env = dict(os.environ, _RAILBRAKE_COMPLETE="complete_bash", COMP_WORDS=words,
               COMP_CWORD=str(len(words.split()) - 1))
    done = subprocess.run([RAILBRAKE], env=env, cwd=cwd, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return done.stdout.split()


@pytest.mark.parametrize("command", ["run", "hil", "bcu", "config show", "compare-rt", "bench"])
def test_scenario_arguments_complete_preset_names(command, tmp_path):
    (tmp_path / "emergency-mine.yaml").write_text("x")
    got = complete(f"railbrake {command} emergency-2", tmp_path)
    assert got == ["emergency-200-descent-crush", "emergency-250-dry"]
    assert "emergency-mine.yaml" in complete(f"railbrake {command} emergency-m", tmp_path)


def test_export_fmu_completes_train_presets_too(tmp_path):
    assert complete("railbrake export-fmu crh380a", tmp_path) == ["crh380a-8", "crh380al-16"]


def complete_here(words: str) -> list[str]:
    """As complete(), in this process: the bash protocol through typer's test runner."""
    from typer.testing import CliRunner
    from railbrake.cli import app
    cword = len(words.split()) - (0 if words.endswith(" ") else 1)
    env = {"_RAILBRAKE_COMPLETE": "complete_bash", "COMP_WORDS": words, "COMP_CWORD": str(cword)}
    done = CliRunner().invoke(app, [], env=env, prog_name="railbrake")
    assert done.exit_code == 0, done.output
    return done.output.split()


@pytest.mark.parametrize("words, presets", [
    ("railbrake size --train crh", ["crh380a-8", "crh380al-16"]),
    ("railbrake stopping-distance --train crh", ["crh380a-8", "crh380al-16"]),
    ("railbrake report brake crh", ["crh380a-8", "crh380al-16"]),
    ("railbrake etcs braking-model crh", ["crh380a-8", "crh380al-16"]),
    ("railbrake etcs curves crh", ["crh380a-8", "crh380al-16"]),
    ("railbrake train new --from crh", ["crh380a-8", "crh380al-16"]),
    ("railbrake campaign run wsp", ["wsp-en15595"]),
    ("railbrake campaign plan wsp", ["wsp-en15595"]),
    ("railbrake wsp tune wsp", ["wsp-en15595"]),
    ("railbrake size --profile emergency", ["emergency", "emergency-crh380a"]),
    ("railbrake adhesion curves --condition dry-", ["dry-high", "dry-medium"]),
    ("railbrake sequence run wsp", ["wsp-vent-stuck"]),
])
def test_train_study_and_other_preset_arguments_complete(words, presets, tmp_path, monkeypatch):
    from railbrake import adhesion, profiles, vehicle
    from railbrake.campaign import study
    from railbrake.sequence import schema
    shipped = (set(vehicle.preset_names()) | set(study.preset_names()) | set(profiles.profile_names())
               | set(adhesion.preset_names()) | set(schema.presets()))
    assert set(presets) <= shipped           # the expectation names real presets
    monkeypatch.chdir(tmp_path)
    prefix = words.split()[-1]
    (tmp_path / f"{prefix}-mine.yaml").write_text("x")
    assert complete_here(words) == presets + [f"{prefix}-mine.yaml"]   # presets first, then the files
