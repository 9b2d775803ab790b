"""Result for scripts: DataFrame and Arrow with units, the standard figures, save / load_result bit for
bit; a run folder's config.yaml reproduces its KPIs bit for bit from another folder, its train file gone."""

import json
import shutil
from importlib.resources import files

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

import railbrake
from railbrake.cli import app
from railbrake.errors import InputError
from railbrake.resolve import resolve
from railbrake.results.scripting import PLOT_KINDS

SHORT = {"stop.max_time": "6 s"}    # the first 6 s of a stop: a few WSP-free seconds, fast


@pytest.fixture(scope="module")
def result():
    return railbrake.run(resolve("emergency-250-dry", 2, SHORT))


def _same_bits(a, b) -> bool:
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def test_the_dataframe_has_one_column_per_channel_with_its_unit(result):
    df = result.to_dataframe()
    pressures = [n for n, u in result.units.items() if u == "Pa"]
    assert pressures and [c for c in df.columns if not c.endswith("_bar_g")] == list(result.outputs)
    assert {n: df.attrs["units"][n] for n in result.outputs} == result.units and df.attrs["units"]["speed"] == "m/s"
    assert all(_same_bits(df[name].to_numpy(), values) for name, values in result.outputs.items())
    assert df.attrs["kpis"] == result.kpis


def test_the_dataframe_gives_each_pressure_in_bar_gauge_beside_it(result):
    """As the CLI, the plots and the KPIs (min_main_reservoir_bar, bar g) show pressures."""
    df = result.to_dataframe()
    columns = list(df.columns)
    for name in (n for n, u in result.units.items() if u == "Pa"):
        gauge = name + "_bar_g"
        assert columns.index(gauge) == columns.index(name) + 1 and df.attrs["units"][gauge] == "bar g"
        assert np.allclose(df[gauge] * 1e5 + result.atmosphere, df[name], rtol=1e-12, atol=1e-6)
    train = result.resolved.train.spec
    assert df["main_reservoir_bar_g"].iloc[0] == pytest.approx(train.air_supply.charged_bar)   # charged at start
    assert df["cylinder_c1a1_bar_g"].iloc[0] == pytest.approx(0.0, abs=1e-9)                  # released at start
    assert df["main_reservoir_bar_g"].min() == pytest.approx(result.kpis["min_main_reservoir_bar"], abs=1e-9)
    assert not any(c.endswith("_bar_g") for c in result.to_arrow().column_names)   # files: SI only


def test_the_arrow_table_carries_each_unit_in_its_field(result):
    table = result.to_arrow()
    assert table.column_names == list(result.outputs)
    for field in table.schema:
        assert field.metadata[b"unit"].decode() == result.units[field.name]
    assert _same_bits(table.column("cylinder_c1a1").to_numpy(), result.outputs["cylinder_c1a1"])


def test_save_and_load_result_round_trip_bit_for_bit(result, tmp_path):
    result.save(tmp_path / "run")
    loaded = railbrake.load_result(tmp_path / "run")
    assert (loaded.scenario, loaded.cars, loaded.wsp) == (result.scenario, result.cars, result.wsp)
    assert _same_bits(loaded.atmosphere, result.atmosphere)
    assert list(loaded.outputs) == list(result.outputs) and loaded.units == result.units
    assert all(_same_bits(loaded.outputs[n], v) for n, v in result.outputs.items())
    assert _same_bits(loaded.time, result.time)
    assert loaded.kpis == result.kpis    # JSON floats read back to the same bits
    loaded.save(tmp_path / "again")      # and a loaded result saves to the same again
    again = railbrake.load_result(tmp_path / "again")
    assert all(_same_bits(again.outputs[n], v) for n, v in result.outputs.items()) and again.kpis == result.kpis


def test_plot_returns_the_figure_or_writes_the_file(result, tmp_path):
    from matplotlib.figure import Figure
    for kind in PLOT_KINDS:
        assert isinstance(result.plot(kind), Figure), kind
    path = result.plot("braking_curve", tmp_path / "curve.svg")
    assert path.read_text().lstrip().startswith("<?xml")
    with pytest.raises(InputError, match="plot kind = 'speed'.*braking_curve"):
        result.plot("speed")
    with pytest.raises(InputError, match="axle = 'c9a1'"):
        result.plot("wsp_cycle", axle="c9a1")


def test_a_run_folder_reproduces_its_kpis_from_another_folder_without_its_train_file(tmp_path):
    """A user's train file (the preset with heavier motor cars) and overrides: config.yaml alone
    (with the train copied beside it) reruns it bit for bit elsewhere, after the train file is gone; titles name the train, not its path."""
    train = yaml.safe_load((files("railbrake") / "data" / "trains" / "crh380a-8.yaml").read_text())
    train["name"] = "heavy-a8"
    train["car_types"]["motor"]["tare_t"] += 2.0
    home = tmp_path / "home" / "someone"
    home.mkdir(parents=True)
    (home / "heavy-a8.yaml").write_text(yaml.safe_dump(train))
    scenario = yaml.safe_load((files("railbrake") / "data" / "scenarios" / "emergency-250-dry.yaml").read_text())
    scenario["train"] = {"preset": "heavy-a8.yaml"}
    (home / "stop.yaml").write_text(yaml.safe_dump(scenario))
    out = tmp_path / "out"
    first = CliRunner().invoke(app, ["run", str(home / "stop.yaml"), "--cars", "2", "--set", "initial_speed=120 km/h",
                                     "--out", str(out), "--json"])
    assert first.exit_code == 0, first.output
    config = (out / "config.yaml").read_text()
    assert str(tmp_path) not in config.split("provenance:")[0]
    assert "initial_speed=120 km/h" in config and "heavy-a8" in config
    elsewhere = tmp_path / "elsewhere"
    shutil.copytree(out, elsewhere)
    shutil.rmtree(home)
    second = CliRunner().invoke(app, ["run", str(elsewhere / "config.yaml"), "--json"])
    assert second.exit_code == 0, second.output
    assert json.loads(second.stdout) == json.loads(first.stdout)
    assert json.loads(first.stdout)["stopping_distance_m"] is not None
    meta = json.loads((out / "run.json").read_text())["meta"]
    report = (out / "report.html").read_text()
    assert meta["train"] == "heavy-a8" and "<h1>emergency-250-dry (MIL): heavy-a8, 2 cars" in report
    assert str(tmp_path) not in report.split("<h2>Provenance")[0]    # the command line as typed follows
    shown = CliRunner().invoke(app, ["config", "show", str(elsewhere / "config.yaml"), "--json"])
    assert json.loads(shown.stdout)["digest"] == yaml.safe_load(config)["provenance"]["digest"]


def test_save_refuses_a_folder_with_files_unless_told(result, tmp_path):
    from railbrake.errors import InputError
    folder = tmp_path / "run"
    result.save(folder)
    before = (folder / "kpis.json").read_bytes()
    with pytest.raises(InputError, match="exists and is not empty: save\\(folder, overwrite=True\\)"):
        result.save(folder)
    assert (folder / "kpis.json").read_bytes() == before
    result.save(folder, overwrite=True)
    assert railbrake.load_result(folder).kpis == result.kpis
    (tmp_path / "empty").mkdir()
    result.save(tmp_path / "empty")       # an empty folder is no run to lose


def test_compare_takes_results_and_saved_runs_as_the_cli_does(result, tmp_path):
    """railbrake.compare(a, b) is `railbrake compare A B --json`: the same report from a Result and
    its saved folder, no difference between a run and itself."""
    import json
    from typer.testing import CliRunner
    from railbrake.cli import app
    result.save(tmp_path / "a")
    report = railbrake.compare(result, tmp_path / "a")
    assert all(d in (None, 0, 0.0, "same") for k in report["kpis"].values() for d in k["differences"])
    cli = CliRunner().invoke(app, ["compare", str(tmp_path / "a"), str(tmp_path / "a"), "--json"])
    assert cli.exit_code == 0, cli.output
    assert set(json.loads(cli.stdout)) == set(report)
    with pytest.raises(railbrake.InputError, match="needs at least two"):
        railbrake.compare(result)


@pytest.mark.parametrize("bad, kind", [(None, TypeError), (7, TypeError), (b"a", TypeError), ("", ValueError),
                                       ("x" * 10_000, ValueError), ("no-such-folder", ValueError)])
def test_compare_names_the_bad_run_by_its_position(result, bad, kind):
    """compare(*runs) has no argument names: a refusal names the run as runs[i], and a long value is
    cut, not echoed."""
    with pytest.raises(kind) as caught:
        railbrake.compare(result, bad)
    assert str(caught.value).startswith("runs[1]") and len(str(caught.value)) < 300, caught.value


def test_kpis_are_read_only_and_save_writes_them(result, tmp_path):
    import copy
    import pickle
    before = dict(result.kpis)
    for change in (lambda k: k.__setitem__("stopping_distance_m", 1.0), lambda k: k.update(x=1),
                   lambda k: k.pop("stopped"), lambda k: k.clear(), lambda k: k.__delitem__("stopped")):
        with pytest.raises(TypeError, match=r"Result.kpis is read-only.*dict\(result.kpis\)"):
            change(result.kpis)
    with pytest.raises(TypeError, match="read-only"):
        result.kpis = {}
    assert result.kpis == before
    mine = dict(result.kpis)          # the way to change them: a copy
    mine["stopping_distance_m"] = 1.0
    assert result.kpis["stopping_distance_m"] == before["stopping_distance_m"]
    assert pickle.loads(pickle.dumps(result.kpis)) == before and copy.deepcopy(result.kpis) == before
    result.save(tmp_path / "run")
    assert json.loads((tmp_path / "run" / "kpis.json").read_text()).keys() == before.keys()
    assert railbrake.load_result(tmp_path / "run").kpis == before
    with pytest.raises(TypeError, match="read-only"):
        railbrake.load_result(tmp_path / "run").kpis["stopped"] = False
