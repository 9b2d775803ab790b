"""`railbrake hil --out`: the same run folder as `run --out` (time series, kpis.json, run.json, plots,
report.html), with the HIL counters and the provenance; readable by `plot` and `compare`; `compare` of
a MIL run and its HIL run reports their stopping-distance difference."""

import json

import pytest
from typer.testing import CliRunner

from railbrake import _core, simulation
from railbrake.cli import app
from railbrake.resolve import resolve
from railbrake.results import files, from_simulation
from railbrake.results.files import write_run
from railbrake.units import kmh_to_ms

SCENARIO = "emergency-250-dry"


def test_hil_out_writes_the_run_folder(bcu_process, hil_key, tmp_path):
    _, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "0.5")
    out = tmp_path / "hil"
    result = CliRunner().invoke(app, ["hil", SCENARIO, "--cars", "1", "--bcu", f"udp://127.0.0.1:{port}",
                                      "--key", str(hil_key),
                                      "--duration", "1", "--priority", "0", "--out", str(out),
                                      "--format", "mf4,parquet", "--json"])
    assert result.exit_code == 0, result.output
    report = json.loads(result.output[result.output.index("{"):result.output.rindex("}") + 1])
    kpis = json.loads((out / "kpis.json").read_text())
    assert kpis == report["kpis"]
    assert set(simulation.kpi_dict(_core.Kpis(), 1e5)) <= set(kpis)   # every KPI of `railbrake run`
    assert kpis["safety_timer_trips"] is None           # the external BCU's, unknown to the plant
    assert kpis["adhesion_utilisation"] > 0 and kpis["air_balance_error"] < 1e-9
    for name in ("timeseries.mf4", "timeseries.parquet", "run.json", "report.html", "braking_curve.png",
                 "cylinders.png", "reservoirs.png", "slip.png"):
        assert (out / name).is_file(), name
    assert list(out.glob("wsp_cycle_c1a*.png"))
    record = files.load(out / "timeseries.mf4")
    assert record.kind == "HIL" and record.kpis == kpis
    assert record.meta["hil"]["counters"]["steps"] == report["counters"]["steps"] == 1000
    command = record.meta["provenance"]["command_line"]   # rebuilt from the parsed options, in their order
    assert command.startswith(f"railbrake hil {SCENARIO} --bcu udp://127.0.0.1:{port}")
    assert "--cars 1" in command and f"--out {out}" in command
    html = (out / "report.html").read_text()
    assert "HIL steps" in html and 'id="provenance"' in html
    same = CliRunner().invoke(app, ["compare", str(out / "timeseries.mf4"), str(out / "timeseries.parquet"), "--json"])
    assert same.exit_code == 0 and json.loads(same.stdout)["identical"]


SHORT_STOP = ("--set", "initial_speed=40 km/h")   # a dry stop of 8.6 s: cheap to pace in real time


@pytest.mark.slow
def test_compare_of_a_mil_run_and_its_hil_run_reports_their_stopping_distance_difference(bcu_process, hil_key,
                                                                                        tmp_path):
    """A MIL run and its HIL run (paced against the reference BCU process; 1 car, dry, from 40 km/h so
    the WSP stays idle): `compare` reports B - A of the two stops, and the stops differ by less than
    the train travels in one 1 ms step (the transport delay of the frames; braking is timed from the
    first step whose commands apply pressure, so the delay itself cancels)."""
    _, port = bcu_process(SCENARIO, "--cars", "1", *SHORT_STOP, "--idle-timeout", "1")
    resolved = resolve(SCENARIO, 1, [SHORT_STOP[1]])
    write_run(from_simulation(simulation.run(resolved), resolved.scenario), tmp_path / "mil")   # no plots: faster
    result = CliRunner().invoke(app, ["hil", SCENARIO, "--cars", "1", *SHORT_STOP, "--bcu", f"udp://127.0.0.1:{port}",
                                      "--key", str(hil_key),
                                      "--priority", "0", "--record", str(tmp_path / "hil.mf4"), "--json"])
    assert result.exit_code == 0, result.output
    mil = json.loads((tmp_path / "mil" / "kpis.json").read_text())
    hil = files.load(tmp_path / "hil.mf4").kpis
    assert mil["stopped"] and hil["stopped"]
    report = CliRunner().invoke(app, ["compare", str(tmp_path / "mil"), str(tmp_path / "hil.mf4"), "--json"])
    assert report.exit_code == 0, report.output
    row = json.loads(report.stdout)["kpis"]["stopping_distance_m"]
    assert row["values"] == [mil["stopping_distance_m"], hil["stopping_distance_m"]]
    assert row["differences"] == [hil["stopping_distance_m"] - mil["stopping_distance_m"]]
    one_step = kmh_to_ms(40.0) * 1e-3
    assert abs(row["differences"][0]) < one_step
