"""The FMU in other tools, compared with `railbrake run` channel by channel through `railbrake
compare`: FMPy's CSV always; fmusim's CSV (modelica/Reference-FMUs v0.0.39) and the FMI 2 compliance
checker (modelica-tools/FMUComplianceChecker) when they are provided, since neither can be fetched
here: RAILBRAKE_FMUSIM and RAILBRAKE_FMU_CHECKER name their executables (docs/fmu.md tells how to
build them)."""

import json
import os
import re
import subprocess

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.util import write_csv
from typer.testing import CliRunner

from railbrake.cli import app
from railbrake.fmu import export_fmu

SCENARIO, STOP_TIME = "emergency-250-dry", 20.0
CHANNELS = ["speed", "position", "main_reservoir", "supply_c1"] + [
    f"{kind}_c1a{a}" for kind in ("cylinder", "wheel_speed") for a in range(1, 5)]
FMUSIM = os.environ.get("RAILBRAKE_FMUSIM")
CHECKER = os.environ.get("RAILBRAKE_FMU_CHECKER")


def _invoke(*args):
    result = CliRunner().invoke(app, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return result.stdout


@pytest.fixture(scope="module")
def native_and_fmu(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tools")
    scenario = folder / f"{SCENARIO}.yaml"
    import yaml
    from importlib.resources import files
    spec = yaml.safe_load((files("railbrake") / "data" / "scenarios" / f"{SCENARIO}.yaml").read_text())
    spec["stop"]["max_time"] = f"{STOP_TIME} s"
    spec.setdefault("outputs", {})["record_interval"] = "0.01 s"
    scenario.write_text(yaml.safe_dump(spec))
    _invoke("run", scenario, "--cars", "1", "--out", folder / "native", "--format", "parquet")
    fmu = export_fmu(str(scenario), folder / "plant.fmu", "2", cars=1)
    return folder, fmu


def _compare(native, csv):
    report = json.loads(_invoke("compare", native, csv, "--json"))
    relative = report["channels_relative"][0]
    assert set(CHANNELS) <= set(relative), sorted(relative)
    return relative


def test_fmpy_csv_compares_channel_by_channel(native_and_fmu):
    folder, fmu = native_and_fmu
    result = simulate_fmu(str(fmu), stop_time=STOP_TIME - 0.01, output_interval=0.01, output=CHANNELS)
    write_csv(folder / "fmpy.csv", result)
    relative = _compare(folder / "native", folder / "fmpy.csv")
    assert all(value <= 1e-9 for value in relative.values()), relative
    printed = _invoke("compare", folder / "native", folder / "fmpy.csv", "--channels")
    assert "cylinder_c1a1" in printed and "relative" in printed


@pytest.mark.skipif(not FMUSIM, reason="fmusim (Reference-FMUs v0.0.39) is not provided: set RAILBRAKE_FMUSIM "
                    "to its executable (docs/fmu.md, 'Other tools')")
def test_fmusim_runs_the_fmu_as_the_native_run(native_and_fmu):
    folder, fmu = native_and_fmu
    csv = folder / "fmusim.csv"
    done = subprocess.run([FMUSIM, "--interface-type", "cs", "--stop-time", str(STOP_TIME - 0.01),
                           "--output-interval", "0.01", "--output-file", str(csv), str(fmu)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    relative = _compare(folder / "native", csv)
    assert all(value <= 1e-9 for value in relative.values()), relative   # fmusim writes 16 digits


@pytest.mark.skipif(not CHECKER, reason="the FMI 2 compliance checker (FMUComplianceChecker) is not provided: set "
                    "RAILBRAKE_FMU_CHECKER to its fmuCheck executable (docs/fmu.md, 'Other tools')")
def test_fmi2_compliance_checker_finds_no_error(native_and_fmu, tmp_path):
    _, fmu = native_and_fmu
    done = subprocess.run([CHECKER, "-h", "0.01", "-s", "5", "-o", str(tmp_path / "out.csv"), str(fmu)],
                          capture_output=True, text=True, timeout=600)
    report = done.stdout + done.stderr
    assert done.returncode == 0, report
    counts = re.findall(r"(\d+)\s+error", report, re.IGNORECASE)
    assert counts and all(c == "0" for c in counts), report
    assert np.loadtxt(tmp_path / "out.csv", delimiter=",", skiprows=1, ndmin=2).shape[0] > 100
