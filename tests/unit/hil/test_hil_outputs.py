"""`railbrake hil --out`: the same run folder as `run --out` (time series, kpis.json, run.json, plots,
report.html), with the HIL counters and the provenance; readable by `plot` and `compare`."""

import json

from typer.testing import CliRunner

from railbrake import _core, simulation
from railbrake.cli import app
from railbrake.results import files

SCENARIO = "emergency-250-dry"


def test_hil_out_writes_the_run_folder(bcu_process, tmp_path):
    _, port = bcu_process(SCENARIO, "--cars", "1", "--idle-timeout", "0.5")
    out = tmp_path / "hil"
    result = CliRunner().invoke(app, ["hil", SCENARIO, "--cars", "1", "--bcu", f"udp://127.0.0.1:{port}",
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
