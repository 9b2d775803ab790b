"""Warnings on the command line: each on one line of its own starting `warning: ` (not wrapped at
the terminal's width, not run together, no empty line from a progress bar never shown), and a run
the command makes in code (a train's simulated build-up) is told as what it is, never by the name
of a scenario the user did not give (emergency-160-dry-medium)."""

import os
import subprocess
import sys

import yaml

from railbrake import vehicle


def railbrake(*args: str, cwd=None) -> subprocess.CompletedProcess:
    env = dict(os.environ, COLUMNS="60")   # a narrow terminal: a wrapped warning would show
    return subprocess.run([sys.executable, "-m", "railbrake", *args], capture_output=True, text=True, env=env,
                          cwd=cwd, timeout=300)


def test_a_run_s_warnings_one_line_each():
    done = railbrake("run", "fault-vent-valve-stuck", "--cars", "3", "--set", "stop.max_time=10 s")
    assert done.returncode == 0, done.stderr
    lines = done.stderr.splitlines()
    assert lines and all(line.startswith("warning: ") for line in lines), lines
    assert any("did not stop" in line and line.endswith("to the end of the run") for line in lines)
    assert len(lines) == len(set(lines))


def test_stopping_distance_tells_the_simulated_build_up_not_an_internal_scenario(tmp_path):
    data = yaml.safe_load(vehicle._preset_dir().joinpath("class387-4.yaml").read_text())
    data["supply_pressure_bar"] = 2.8   # below the motor cars' emergency demand (2.9 bar), within 90 % of it: a warning
    (tmp_path / "weak.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    done = railbrake("stopping-distance", "--train", "weak.yaml", "--v0-kmh", "160", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    said = (done.stdout + done.stderr).splitlines()
    warnings = [line for line in said if "warning" in line]
    assert warnings and all(line.startswith("warning: ") for line in warnings)
    assert "scenario" not in done.stdout + done.stderr and "dry-medium:" not in done.stdout + done.stderr
    assert any(line.startswith("warning: the simulated build-up of weak.yaml (its emergency brake from 160 km/h "
                               "on dry-medium): emergency brake: motor cylinder pressure") for line in warnings)
