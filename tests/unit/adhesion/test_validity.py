"""A condition run outside its validity (speed range of its measurements) is refused, or run when
the scenario forces it and then flagged in the run's KPIs, report and JSON."""

import json
import re
import secrets

import pytest
from typer.testing import CliRunner

from railbrake import scenario, simulation
from railbrake.adhesion import load_condition, run_outside_validity
from railbrake.campaign import configuration, plan, study
from railbrake.cli import app
from railbrake.errors import InputError
from railbrake.resolve import resolve
from railbrake.results import kpis as kpi_info
from railbrake.results import record
from railbrake.results.report import write_report

ONE_CAR = """schema: railbrake.scenario/1
name: one-car
train: {preset: crh380a-8, cars: 1}
initial_speed: %s
demand: [{time: 0 s, emergency: true}]
adhesion: {condition: %s%s}
"""


def _forced(text: str) -> bool:
    return bool(re.search(r"allow_outside_validity: true", text))


def test_a_stop_from_above_or_below_the_range_is_outside_and_inside_is_not():
    wet, heavy = load_condition("wet"), load_condition("heavy-rain")   # 0-120, 100-300 km/h
    assert run_outside_validity(wet, 120.0) is None and run_outside_validity(heavy, 100.0) is None
    assert "above" in run_outside_validity(wet, 121.0)
    assert "below" in run_outside_validity(heavy, 99.0)   # the stop never reaches the range


def test_outside_its_validity_a_run_is_refused_naming_file_key_value_and_range():
    with pytest.raises(InputError) as err:
        scenario.parse(ONE_CAR % ("200 km/h", "wet", ""), "s.yaml")
    text = str(err.value)
    assert "s.yaml, line 6: adhesion.condition = 'wet'" in text
    assert "line 4: initial_speed = '200 km/h'" in text
    assert re.search(r"railbrake/data/adhesion/wet\.yaml, line \d+: validity\.speed_kmh = \[0, 120\] km/h", text)
    assert "allow_outside_validity: true" in text


def test_a_zone_outside_its_validity_is_refused_too():
    text = ONE_CAR.replace("adhesion: {condition: %s%s}", "adhesion:\n  condition: %s%s\n  zones:\n"
                           "    - {start: 100 m, end: 200 m, condition: leaves}") % ("300 km/h", "dry-medium", "")
    with pytest.raises(InputError, match=r"adhesion\.zones\.0\.condition = 'leaves'.*\[40, 200\] km/h"):
        scenario.parse(text, "z.yaml")


def test_a_forced_run_carries_the_flag_in_kpis_report_warnings_and_json(tmp_path):
    path = tmp_path / "forced.yaml"
    path.write_text(ONE_CAR % ("150 km/h", "wet", ", allow_outside_validity: true"))
    with pytest.warns(UserWarning, match="forced outside validity"):
        result = simulation.run(str(path))
    flag = result.kpis["adhesion_outside_validity"]
    assert "'wet' run from 150 km/h" in flag and "[0, 120] km/h" in flag
    assert any("forced outside" in w for w in kpi_info.warnings(result.kpis))
    report = write_report(record.from_simulation(result, result.resolved.scenario), [], tmp_path / "r.html")
    html = report.read_text()
    assert 'data-kpi="adhesion_outside_validity"' in html and "forced outside" in html
    cli = CliRunner().invoke(app, ["run", str(path), "--json"])
    assert cli.exit_code == 0, cli.output
    assert "[0, 120] km/h" in json.loads(cli.stdout)["adhesion_outside_validity"]


def test_inside_its_validity_a_forcing_run_carries_no_flag():
    sc = scenario.parse(ONE_CAR % ("100 km/h", "wet", ", allow_outside_validity: true"), "inside")
    assert sc.outside_validity() == []
    assert simulation.outside_validity_kpi(sc) == {}


@pytest.mark.parametrize("name", scenario.preset_names())
def test_no_shipped_scenario_runs_a_condition_outside_its_validity_unforced(name):
    """Resolution only: each resolves (refused otherwise); one outside says so in its file."""
    sc = resolve(name).scenario
    text = (scenario._preset_dir() / f"{name}.yaml").read_text()
    assert not sc.outside_validity() or (_forced(text) and sc.spec.adhesion.allow_outside_validity)


@pytest.mark.parametrize("name", study.preset_names())
def test_every_run_of_a_shipped_study_resolves_and_forces_only_explicitly(name):
    """Resolution only, once per speed and adhesion of the runs (what the validity depends on)."""
    s = study.load(name)
    seen, forced = {}, 0
    for run in plan.iter_plan(s):
        what = json.dumps({k: v for k, v in run.sets.items() if k.startswith(("adhesion", "initial_speed"))},
                          sort_keys=True)
        seen.setdefault(what, run.sets)
    for sets in seen.values():
        sc = configuration.resolve(s.base, sets).scenario   # refused outside unless forced
        if sc.outside_validity():
            assert sets.get("adhesion.allow_outside_validity") is True
            forced += 1
    assert forced < len(seen)


def test_a_forced_hil_run_carries_the_flag_too(tmp_path):
    from railbrake import hil
    path = tmp_path / "forced.yaml"
    path.write_text(ONE_CAR % ("150 km/h", "wet", ", allow_outside_validity: true"))
    result = hil.run(str(path), ("127.0.0.1", 9), duration=0.05, paced=False, priority=0, key=secrets.token_bytes(16))
    assert "[0, 120] km/h" in result.kpis["adhesion_outside_validity"]


def _oil_with_creep(tmp_path, creep: str) -> str:
    from importlib import resources
    text = (resources.files("railbrake") / "data" / "adhesion" / "oil-film.yaml").read_text()
    path = tmp_path / "oil-creep.yaml"
    path.write_text(text.replace("  speed_kmh: [40, 200]\n", f"  speed_kmh: [40, 200]\n  creep: {creep}\n"))
    return str(path)


def test_a_creep_range_given_refuses_a_run_that_left_it_unless_forced(tmp_path):
    """Creep is known once run: a run whose largest creep (max_slip) left the file's creep range is
    refused, or flagged when forced; without WSP the wheels lock (creep near 1)."""
    condition = _oil_with_creep(tmp_path, "[0, 0.05]")
    text = ONE_CAR.replace("demand:", "wsp: {enabled: false}\ndemand:")
    with pytest.raises(InputError, match=r"oil-creep\.yaml, line \d+: validity\.creep = \[0, 0\.05\]"):
        simulation.run(scenario.parse(text % ("100 km/h", condition, ""), "no-wsp"))
    forced = simulation.run(scenario.parse(text % ("100 km/h", condition, ", allow_outside_validity: true"), "f"))
    assert forced.kpis["max_slip"] > 0.05 and "validity.creep" in forced.kpis["adhesion_outside_validity"]


def test_a_bad_creep_range_is_refused_with_its_line(tmp_path):
    with pytest.raises(InputError, match=r"line \d+: validity\.creep = \[0\.2, 0\.1\]: give \[min, max\]"):
        load_condition(_oil_with_creep(tmp_path, "[0.2, 0.1]"))


def test_creep_curves_outside_the_creep_range_warn(tmp_path):
    from railbrake.adhesion import AdhesionRangeWarning, creep_curves
    condition = load_condition(_oil_with_creep(tmp_path, "[0, 0.05]"))
    with pytest.warns(AdhesionRangeWarning, match=r"creep 0\.3, outside its validity"):
        creep_curves(condition, [20.0], creep=[0.0, 0.3])
