"""The console as a user meets it: --version, flags without a type, every plot's path printed,
help and tables within 80 columns."""

from typer.testing import CliRunner

import railbrake
from railbrake import _core
from railbrake.cli import app


def _invoke(*args):
    result = CliRunner().invoke(app, [str(a) for a in args], terminal_width=80, env={"COLUMNS": "80"})
    assert result.exit_code == 0, result.output
    return result.output


def test_version_names_package_core_and_build():
    out = _invoke("--version")
    assert out.startswith(f"railbrake {railbrake.__version__} (core {_core.rb_version().decode()}, build ")
    assert _core.rb_build_hash().decode()[:12] in out


def test_plain_flags_show_no_bool_type_and_help_fits_80_columns():
    for command in ([], ["run"], ["hil"], ["compare"], ["plot"], ["stopping-distance"]):
        out = _invoke(*command, "--help")
        assert "<bool>" not in out, command
        assert max(len(line) for line in out.splitlines()) <= 80, command


def test_stopping_distance_prints_the_plot_path(tmp_path):
    out = _invoke("stopping-distance", "--v0-kmh", "200", "--plot", tmp_path / "sd.png")
    assert f"plot: {tmp_path / 'sd.png'}" in out
    assert (tmp_path / "sd.png").stat().st_size > 1000


def test_the_compare_table_fits_80_columns(tmp_path):
    """Three runs side by side (the widest common case), from saved files."""
    from railbrake import scenario, simulation
    from railbrake.results import from_simulation
    from railbrake.results.files import write_run
    sc = scenario.load("emergency-250-dry")
    write_run(from_simulation(simulation.run(sc, cars=1), sc), tmp_path / "a")
    out = _invoke("compare", tmp_path / "a", tmp_path / "a", tmp_path / "a")
    assert "stopping_distance_m" in out and "identical" in out
    assert max(len(line) for line in out.splitlines()) <= 80
