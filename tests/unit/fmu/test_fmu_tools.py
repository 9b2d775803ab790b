"""The FMU in other tools, compared with `railbrake run` channel by channel through `railbrake
compare`: FMPy's CSV always; fmusim's CSV (modelica/Reference-FMUs v0.0.39) and the FMI 2 compliance
checker (modelica-tools/FMUComplianceChecker) when they are provided: their sources cannot be
fetched offline, so tools/build_fmusim.py and tools/build_fmu_checker.py build them where they can
be had, and RAILBRAKE_FMUSIM and RAILBRAKE_FMU_CHECKER name the executables (docs/fmu.md)."""

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
    scenario, _ = _native_run(folder, 1, STOP_TIME)
    fmu = export_fmu(str(scenario), folder / "plant.fmu", "2", cars=1)
    return folder, fmu


def _native_run(folder, cars, max_time=None):
    """`railbrake run` of SCENARIO with `cars`, recorded every 0.01 s (to `max_time`, else the whole stop)."""
    import yaml
    from importlib.resources import files
    spec = yaml.safe_load((files("railbrake") / "data" / "scenarios" / f"{SCENARIO}.yaml").read_text())
    if max_time is not None:
        spec["stop"]["max_time"] = f"{max_time} s"
    spec.setdefault("outputs", {})["record_interval"] = "0.01 s"
    scenario = folder / f"{SCENARIO}.yaml"
    scenario.write_text(yaml.safe_dump(spec))
    report = json.loads(_invoke("run", scenario, "--cars", cars, "--out", folder / "native", "--format", "parquet",
                                "--json"))
    return scenario, report


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


@pytest.mark.skipif(not FMUSIM, reason="fmusim (Reference-FMUs v0.0.39) is not provided: build it with "
                    "`python tools/build_fmusim.py` and set RAILBRAKE_FMUSIM to the executable it prints")
@pytest.mark.parametrize("cars", [1, 8, 16])
def test_fmusim_runs_the_whole_stop_as_the_native_run(cars, tmp_path):
    """fmusim steps the FMI 2 export (co-simulation, 10 ms) over the whole stop; every channel is
    within 1e-9 of its largest value from `railbrake run` (the coupled cars' last bits part near
    standstill, docs/fmu.md; fmusim writes 16 significant digits)."""
    scenario, report = _native_run(tmp_path, cars)
    fmu = export_fmu(str(scenario), tmp_path / "plant.fmu", "2", cars=cars)
    stop = np.floor(report["stopping_time_s"] * 100) / 100
    csv = tmp_path / "fmusim.csv"
    done = subprocess.run([FMUSIM, "--interface-type", "cs", "--stop-time", f"{stop:.2f}", "--output-interval", "0.01",
                           "--output-file", str(csv), str(fmu)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    relative = _compare(tmp_path / "native", csv)
    assert len(relative) == 3 + cars * 9 and all(value <= 1e-9 for value in relative.values()), relative


@pytest.mark.skipif(not CHECKER, reason="the FMI 2 compliance checker (FMUComplianceChecker) is not provided: build "
                    "it with `python tools/build_fmu_checker.py` and set RAILBRAKE_FMU_CHECKER to the executable "
                    "it prints")
def test_fmi2_compliance_checker_finds_no_error(native_and_fmu, tmp_path):
    _, fmu = native_and_fmu
    done = subprocess.run([CHECKER, "-h", "0.01", "-s", "5", "-o", str(tmp_path / "out.csv"), str(fmu)],
                          capture_output=True, text=True, timeout=600)
    report = done.stdout + done.stderr
    assert done.returncode == 0, report
    summary = re.findall(r"Checker reported:\s+(\d+) Warning\(s\)\s+(\d+) Error\(s\)", report)
    fmu_reported = re.findall(r"FMU reported:\s+(\d+) warning\(s\) and error\(s\)", report)
    assert summary and all(s == ("0", "0") for s in summary), report
    assert fmu_reported and set(fmu_reported) == {"0"}, report
    assert np.loadtxt(tmp_path / "out.csv", delimiter=",", skiprows=1, ndmin=2).shape[0] > 100
