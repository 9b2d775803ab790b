"""Shell completion (`railbrake --install-completion`) completes scenario arguments with the preset
names (and export-fmu's with the train presets too), then the YAML files of the current folder."""

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
