"""The run's own KPI table fits an 80-column terminal (the compare table and
the help texts: tests/unit/cli/test_console.py). Warnings go to stderr, each on a line of its own
however long (tests/unit/cli/test_warnings_cli.py), so only the table on stdout is measured."""

from typer.testing import CliRunner

from railbrake.cli import app


def test_the_run_table_fits_80_columns(saved_run):
    out, _ = saved_run
    scenario = out.parent / "fault-vent-valve-stuck.yaml"      # 3 cars, 10 s (conftest)
    result = CliRunner().invoke(app, ["run", str(scenario), "--cars", "3"], terminal_width=80,
                                env={"COLUMNS": "80"})
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert "stopping_distance_m" in result.stdout and "safety_timer_trips" in result.stdout
    assert max(len(line) for line in lines) <= 80
