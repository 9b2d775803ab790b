"""`railbrake compare-rt` from the command line."""

import json

from typer.testing import CliRunner

from railbrake.cli import app


def test_compare_rt_json_and_plots(tmp_path):
    result = CliRunner().invoke(app, ["compare-rt", "emergency-250-dry", "--cars", "1", "--json",
                                      "--plot", str(tmp_path)])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert abs(data["summary"]["stopping_distance_difference_pct"]) < 1.0
    # 5 ms twice: with its default 3 sub-steps and bare (where the single step fails)
    assert [(r["dt_ms"], r["substeps"]) for r in data["step_study"]] == [(0.25, 1), (0.5, 1), (1.0, 1), (2.0, 1),
                                                                        (5.0, 3), (5.0, 1)]
    assert set(data["axles"]) == {"c1a1", "c1a2", "c1a3", "c1a4"}
    assert data["axles"]["c1a1"]["detailed"]["vent_commands"] == 0
    for plot in ("cylinder_rt_vs_detailed", "cylinder_zoom", "speed_rt_vs_detailed", "step_study"):
        assert (tmp_path / f"{plot}.png").stat().st_size > 1000


def test_compare_rt_table_without_steps():
    result = CliRunner().invoke(app, ["compare-rt", "emergency-250-dry", "--cars", "1", "--no-steps"])
    assert result.exit_code == 0, result.output
    assert "stopping distance detailed" in result.output and "step-size" not in result.output


def test_compare_rt_compares_a_faulty_scenario():
    # the detailed model takes the scenario's faults (the vent valve of car 3, axle 2 stuck open
    # from 2 s): both models vent that axle and stop alike
    result = CliRunner().invoke(app, ["compare-rt", "fault-vent-valve-stuck", "--cars", "3", "--no-steps", "--json",
                                      "--set", "initial_speed=80 km/h"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert abs(data["summary"]["stopping_distance_difference_pct"]) < 2.0
    for model in ("rt", "detailed"):
        assert data["axles"]["c3a2"][model]["vent_open_s"] > 5.0
        assert data["axles"]["c3a1"][model]["vent_open_s"] == 0.0
