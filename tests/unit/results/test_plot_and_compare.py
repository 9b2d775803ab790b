"""`railbrake plot` redraws a saved run's figures exactly (byte for byte: same data, same channels)
from Parquet and from an MDF4 file alone; `railbrake compare` of a run with itself reports zero
differences, and against another run the KPI differences themselves."""

import json
import shutil

import pytest
from typer.testing import CliRunner

import railbrake
from railbrake import scenario, simulation
from railbrake.cli import app
from railbrake.results import from_simulation
from railbrake.results.files import write_run


def _invoke(*args):
    result = CliRunner().invoke(app, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return result.output


@pytest.mark.slow
def test_plot_reproduces_the_runs_own_figures(saved_run, tmp_path):
    """From the folder (its Parquet) and from the MDF4 file alone (its own metadata, no run.json or
    kpis.json beside it); the MDF4 and CSV hold the same samples (test_exports)."""
    out, _ = saved_run
    own = {p.name: p.read_bytes() for p in out.glob("*.png")}
    assert "wsp_cycle_c3a2.png" in own            # the faulty axle is always shown
    alone = tmp_path / "alone"
    alone.mkdir()
    shutil.copy(out / "timeseries.mf4", alone)
    for source, target in ((out, tmp_path / "folder"), (alone / "timeseries.mf4", tmp_path / "mf4")):
        printed = _invoke("plot", source, "--out", target)
        redrawn = {p.name: p.read_bytes() for p in target.glob("*.png")}
        assert redrawn == own, source
        assert printed.count("plot: ") == len(own)


@pytest.mark.slow
def test_plot_options_axles_window_channels_and_format(saved_run, tmp_path):
    out, _ = saved_run
    _invoke("plot", out, "--out", tmp_path, "--axles", "c1a1,c2a4", "--window", "1:4",
            "--channels", "speed,supply_c*", "--format", "svg")
    names = {p.name for p in tmp_path.iterdir()}
    assert {"wsp_cycle_c1a1.svg", "wsp_cycle_c2a4.svg", "wsp_cycle_c3a2.svg", "channels.svg"} <= names
    assert "1.0" in (tmp_path / "wsp_cycle_c1a1.svg").read_text()   # the window's first tick


def test_figures_redrawn_into_the_run_folder_leave_it_complete(saved_run, tmp_path):
    """`railbrake plot RUN` writes into the run's folder: the manifest follows the redrawn figures,
    so the folder still loads (and `compare` still reads it), as the README's commands do."""
    out, _ = saved_run
    copy = tmp_path / "run"
    shutil.copytree(out, copy)
    _invoke("plot", copy, "--axles", "c1a1", "--window", "1:4")
    assert (copy / "wsp_cycle_c1a1.png").is_file()
    assert railbrake.load_result(copy).kpis == railbrake.load_result(out).kpis


def test_plot_rejects_unknown_axles_channels_and_windows(saved_run):
    out, _ = saved_run
    for args, words in ((["--axles", "c4a1"], "'c4a1' is not an axle of this run"),
                        (["--window", "50:40"], "T1 must be finite and greater than T0"),
                        (["--window", "500:600"], "outside the recorded time"),
                        (["--channels", "nope*"], "'nope*' names no recorded channel"),
                        (["--format", "jpg"], "must be one of png, svg, pdf")):
        result = CliRunner().invoke(app, ["plot", str(out), *args])
        assert result.exit_code == 2 and words in result.output, (args, result.output)


def test_compare_of_a_run_with_itself_reports_zero_differences(saved_run, tmp_path):
    out, kpis = saved_run
    report = json.loads(_invoke("compare", out, out / "timeseries.mf4", out / "timeseries.csv", "--json"))
    assert report["identical"]
    for key, row in report["kpis"].items():
        assert row["values"] == [kpis[key]] * 3
        assert all(d in (0.0, None) for d in row["differences"]), key
    assert all(v == 0.0 for diffs in report["channels"] for v in diffs.values())
    assert "identical" in _invoke("compare", out, out, "--plot", tmp_path)
    assert (tmp_path / "compare_braking_curves.png").is_file() and (tmp_path / "compare_cylinders.png").is_file()


def test_compare_reports_the_kpi_differences_of_two_runs(saved_run, tmp_path):
    out, kpis = saved_run
    sc = scenario.load(str(out.parent / "fault-vent-valve-stuck.yaml"))
    write_run(from_simulation(simulation.run(sc, cars=3, wsp=False), sc), tmp_path)   # no plots: faster
    other = json.loads((tmp_path / "kpis.json").read_text())
    report = json.loads(_invoke("compare", out, tmp_path, "--json"))
    assert not report["identical"]
    row = report["kpis"]["mean_deceleration"]   # the 10 s runs have not stopped: no stopping distance
    assert row["differences"] == [other["mean_deceleration"] - kpis["mean_deceleration"]]
    assert report["kpis"]["stopping_distance_m"]["differences"] == [None]   # both null
    assert report["kpis"]["air_vented_kg"]["differences"][0] != 0.0


def test_compare_needs_two_runs(saved_run):
    out, _ = saved_run
    result = CliRunner().invoke(app, ["compare", str(out)])
    assert result.exit_code == 2 and "needs at least two" in result.output


def test_compare_reads_an_fmu_result_saved_by_fmpy(saved_run, tmp_path):
    """FMPy's CSV (quoted names, Booleans as True/False) of the same samples: no KPIs, but the
    common channels compare to zero and the braking curves overlay."""
    import numpy as np
    from fmpy.util import write_csv

    from railbrake.results import files
    out, _ = saved_run
    run = files.load(out)
    names = ["time", "speed", "position", "cylinder_c3a2", "hold_c3a2"]
    table = np.zeros(len(run.time), dtype=[(n, np.bool_ if n.startswith("hold") else np.float64) for n in names])
    for n in names:
        table[n] = run.outputs[n] > 0.5 if n.startswith("hold") else run.outputs[n]
    write_csv(tmp_path / "fmu.csv", table)
    fmu = files.load(tmp_path / "fmu.csv")
    assert fmu.kind == "FMU" and np.array_equal(fmu.outputs["hold_c3a2"], run.outputs["hold_c3a2"])
    printed = _invoke("compare", out, tmp_path / "fmu.csv", "--json", "--plot", tmp_path)
    report = json.loads("\n".join(line for line in printed.splitlines() if not line.startswith("plot: ")))
    assert set(report["channels"][0]) == {"speed", "position", "cylinder_c3a2"}
    assert all(v == 0.0 for v in report["channels"][0].values())
    assert report["kpis"]["stopping_distance_m"]["values"][1] is None
