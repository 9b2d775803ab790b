"""`railbrake run` and `railbrake bench` from the command line."""

import json

import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from railbrake.cli import app


def test_run_writes_parquet_with_units_kpis_and_plots(tmp_path):
    result = CliRunner().invoke(app, ["run", "emergency-250-dry", "--cars", "2", "--out", str(tmp_path), "--json"])
    assert result.exit_code == 0, result.output
    kpis = json.loads(result.stdout)
    assert kpis["stopping_distance_m"] < 3000.0
    assert json.loads((tmp_path / "kpis.json").read_text()) == kpis
    table = pq.read_table(tmp_path / "timeseries.parquet")
    assert table.schema.field("cylinder_c2a4").metadata[b"unit"] == b"Pa"
    assert table.schema.field("speed").metadata[b"unit"] == b"m/s"
    # min_supply_bar (gauge) is the lowest supply channel of the file (KPI every 1 ms, file every 20 ms)
    supply = min(min(table.column(n).to_pylist()) for n in table.column_names if n.startswith("supply_c"))
    assert kpis["min_supply_bar"] == pytest.approx((supply - 101325.0) / 1e5, abs=1e-3)
    for plot in ("braking_curve", "speed_time", "slip", "reservoirs", "cylinders"):
        assert (tmp_path / f"{plot}.png").stat().st_size > 1000
    assert list(tmp_path.glob("wsp_cycle_c*.png")), "no WSP cycle figure"
    assert (tmp_path / "report.html").is_file()


def test_no_wsp_flag_turns_the_wsp_off():
    result = CliRunner().invoke(app, ["run", "emergency-300-leaves-patch", "--cars", "1", "--no-wsp", "--json"])
    assert result.exit_code == 0, result.output
    kpis = json.loads(result.stdout)
    with_wsp = json.loads(CliRunner().invoke(app, ["run", "emergency-300-leaves-patch", "--cars", "1", "--json"]).stdout)
    # no WSP: the wheels lock on the leaves; only the valves let air out (the EP pilot stage's bleed,
    # the relay exhausting as the demand steps down with speed): far less than with the WSP venting
    assert kpis["wheel_lock_events"] >= 1 and kpis["worst_axle"].startswith("c1a")
    assert with_wsp["wheel_lock_events"] == 0
    assert kpis["air_vented_kg"] < 0.6 * with_wsp["air_vented_kg"]


def test_bench_json():
    result = CliRunner().invoke(app, ["bench", "emergency-250-dry", "--cars", "1", "--runs", "1", "--json"])
    assert result.exit_code == 0, result.output
    figures = json.loads(result.stdout)
    assert figures["cars"] == 1 and figures["scenario"] == "emergency-250-dry" and figures["runs"] == 1
    assert figures["realtime_factor"] > 1.0 and figures["ratio"] > 0.0


def test_bench_plant_json():
    result = CliRunner().invoke(app, ["bench", "--plant", "--cars", "2", "--steps", "1000", "--seconds", "0.05",
                                      "--json"])
    assert result.exit_code == 0, result.output
    figures = json.loads(result.stdout)
    assert figures["cars"] == 2 and figures["realtime_factor"] > 1.0 and figures["runs"] >= 3
    assert figures["substeps"] == 1 and "step_us_max" in figures


def test_bench_text_and_bad_counts():
    result = CliRunner().invoke(app, ["bench", "emergency-250-dry", "--cars", "1", "--runs", "1"])
    assert result.exit_code == 0, result.output
    assert "plant alone" in result.output and "ratio" in result.output and "real time" in result.output
    result = CliRunner().invoke(app, ["bench", "--plant", "--cars", "1", "--steps", "100", "--runs", "2"])
    assert result.exit_code == 0, result.output
    assert "fastest of 2 runs" in result.output and "slowest" in result.output
    for bad in (["--runs", "0"], ["--seconds", "0"], ["--plant", "--steps", "0"]):
        result = CliRunner().invoke(app, ["bench", *bad])
        assert result.exit_code == 2 and bad[-2].lstrip("-") in result.output


def test_bench_portable_kernel_and_a_wrong_one():
    result = CliRunner().invoke(app, ["bench", "--plant", "--cars", "1", "--steps", "100", "--runs", "1",
                                      "--kernel", "portable", "--json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["kernel"] == "portable"
    result = CliRunner().invoke(app, ["bench", "--kernel", "fast"])
    assert result.exit_code == 2 and "kernel = 'fast'" in result.output


def test_unknown_scenario_exits_non_zero():
    result = CliRunner().invoke(app, ["run", "no-such-scenario"])
    assert result.exit_code == 2
    assert "no-such-scenario" in result.output


def test_set_reaches_the_run():
    """From 100 km/h instead of 250 km/h: the stopping distance falls roughly with v^2."""
    args = ["run", "emergency-250-dry", "--cars", "1", "--json"]
    base = CliRunner().invoke(app, args)
    slow = CliRunner().invoke(app, args + ["--set", "initial_speed=100 km/h"])
    assert base.exit_code == 0 and slow.exit_code == 0, slow.output
    ratio = json.loads(slow.stdout)["stopping_distance_m"] / json.loads(base.stdout)["stopping_distance_m"]
    assert 0.1 < ratio < 0.3   # (100/250)^2 = 0.16, plus the response time's share


def test_set_with_an_unknown_key_exits_2_naming_close_keys():
    result = CliRunner().invoke(app, ["run", "emergency-250-dry", "--set", "wsp.speed_treshold=1 m/s"])
    assert result.exit_code == 2
    assert "wsp.speed_threshold" in result.output
