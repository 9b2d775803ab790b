"""EN 15595-style assessment (hand-computed dS %, Kwet), Sobol indices of a known function, the
HTML/Markdown report of a real campaign, and a short resumable WSP tuning."""

import json
import types
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import qmc

from railbrake.campaign import execute, report, study, tune
from railbrake.campaign.assess import assess, rank, worst
from railbrake.campaign.study import Assessment
from railbrake.errors import InputError

DATA = Path(__file__).parent / "data"


def _row(case, speed, s, te=None, locks=0, util=0.9, seed=1, point=0):
    return {"adhesion_case": case, "initial_speed": speed, "seed": seed, "point": point, "status": "ok",
            "stopping_distance_m": s, "equivalent_response_time_s": te, "wheel_lock_events": locks,
            "adhesion_utilisation": util, "safety_timer_trips": 0, "air_consumed_kg": 1.0, "stopped": 1.0}


def test_delta_s_and_kwet_from_the_deceleration_distances():
    a = Assessment(reference={"adhesion_case": "dry"}, criteria={"utilisation_cases": ["low"]})
    v0 = 100 / 3.6
    rows = [_row("dry", v0, 500.0, te=2.0), _row("low", v0, 800.0, te=9.0, util=0.8),
            _row("patch", v0, 600.0, locks=1, util=0.3)]
    cases = {c["adhesion_case"]: c for c in assess(rows, ["adhesion_case", "initial_speed"], a, lambda r: v0)}
    s_d_ref = 500.0 - v0 * 2.0          # the reference's te for every case
    assert cases["low"]["deceleration_distance_m"] == pytest.approx(800.0 - v0 * 2.0)
    ds = 100 * (800.0 - 500.0) / s_d_ref
    assert cases["low"]["delta_s_pct"] == pytest.approx(ds)
    assert cases["low"]["kwet"] == pytest.approx(100 / (100 + ds))
    assert cases["dry"]["delta_s_pct"] == 0.0 and cases["dry"]["passed"]
    assert not cases["low"]["passed"] and "utilisation 0.800 < 0.85" in cases["low"]["reasons"][0]
    assert not cases["patch"]["passed"] and cases["patch"]["reasons"] == ["1 lock events > 0"]
    w = worst(list(cases.values()))
    assert w["worst_delta_s_pct"] == pytest.approx(ds) and w["locks"] == 1


def test_each_controller_is_matched_with_its_own_dry_run_and_ranked():
    """Two controllers, each with its own dry reference; the ranking's figures by hand: worst dS %
    and its Kwet, utilisation on the utilisation cases, air and valve switchings per assessed stop,
    the worst axle's sliding energy, timer trips; mean ranks tied at 1.5, so the worst dS decides."""
    a = Assessment(reference={"adhesion_case": "dry"}, criteria={"utilisation_cases": ["low"]}, rank="wsp.controller")
    v0, te = 100 / 3.6, 2.0

    def row(controller, case, s, util=0.9, air=1.0, switches=0, sliding=0.0, trips=0):
        return {**_row(case, v0, s, te=te if case == "dry" else None, util=util), "wsp.controller": controller,
                "air_drawn_kg": air, "valve_switchings": switches, "max_sliding_energy_kj": sliding,
                "safety_timer_trips": trips}
    rows = [row("a", "dry", 500.0), row("a", "low", 800.0, util=0.8, air=3.0, switches=100, sliding=10.0),
            row("a", "patch", 600.0, util=0.3, air=2.0, switches=50, sliding=30.0),
            row("b", "dry", 450.0), row("b", "low", 700.0, util=0.9, air=4.0, switches=200, sliding=5.0, trips=1),
            row("b", "patch", 500.0, util=0.3, air=4.0, switches=100, sliding=8.0)]
    cases = assess(rows, ["wsp.controller", "adhesion_case"], a, lambda r: v0)
    low = {c["wsp.controller"]: c["delta_s_pct"] for c in cases if c["adhesion_case"] == "low"}
    assert low == {"a": pytest.approx(100 * 300 / (500 - v0 * te)), "b": pytest.approx(100 * 250 / (450 - v0 * te))}
    best, second = rank(cases, "wsp.controller", a)
    assert (best["wsp.controller"], second["wsp.controller"]) == ("b", "a")
    assert best["rank"] == second["rank"] == 1.5
    assert best["worst_delta_s_pct"] == pytest.approx(low["b"]) and best["kwet"] == pytest.approx(100 / (100 + low["b"]))
    assert (second["adhesion_utilisation"], second["air_drawn_kg"], second["valve_switchings"],
            second["max_sliding_energy_kj"], second["safety_timer_trips"]) == (0.8, 2.5, 75, 30.0, 0)
    assert (best["adhesion_utilisation"], best["air_drawn_kg"], best["valve_switchings"],
            best["max_sliding_energy_kj"], best["safety_timer_trips"]) == (0.9, 4.0, 150, 8.0, 1)
    assert best["failed_cases"] == second["failed_cases"] == 1   # b: its trip; a: utilisation 0.8 (the patch is no utilisation case)


def test_sobol_indices_of_a_function_of_the_first_factor_only():
    n, d = 256, 2
    base = qmc.Sobol(2 * d, seed=1).random(n)
    a, b = base[:, :d], base[:, d:]
    rows = []

    def add(block, points):
        rows.extend({"block": block, "sample": i, "status": "ok", "y": 3 * x[0] + 0.0 * x[1]}
                    for i, x in enumerate(points))
    add("A", a)
    add("B", b)
    for i in range(d):
        ab = a.copy()
        ab[:, i] = b[:, i]
        add(f"AB{i}", ab)
    fake = types.SimpleNamespace(manifest={"design": "sobol", "samples": n}, factors=["x1", "x2"],
                                 ok=lambda: rows)
    indices = report.sobol(fake, ["y"])["y"]
    assert indices["x1"]["first"] == pytest.approx(1.0, abs=0.05)
    assert indices["x1"]["total"] == pytest.approx(1.0, abs=0.05)
    assert abs(indices["x2"]["total"]) < 0.01


ASSESSED = """schema: railbrake.study/1
name: tiny-assessment
base: emergency-250-dry
set: {train.cars: 1, stop.max_time: "60 s", initial_speed: "60 km/h"}
factors:
  adhesion_case:
    - {name: dry, adhesion.condition: dry-medium}
    - {name: low, adhesion.condition: oil-film}
design: {kind: grid}
assessment:
  reference: {adhesion_case: dry}
tuning:
  params:
    wsp.decel_threshold: {low: "1.5 m/s^2", high: "4 m/s^2"}
"""


@pytest.fixture(scope="module")
def assessed(tmp_path_factory, two_workers):
    out = tmp_path_factory.mktemp("assessed")
    s = study.parse(ASSESSED, "tiny.yaml")
    summary = execute.run_study(s, out, scheduler=two_workers)
    assert summary.done == 2
    return s, out


@pytest.mark.slow   # a Dask cluster: separate processes, not under the sanitizers
def test_report_is_self_contained_and_shows_the_cases(assessed):
    _, out = assessed
    summary = report.write(out, out / "report.html")
    page = (out / "report.html").read_text()
    assert "Assessed cases" in page and "data:image/png;base64," in page and "src='http" not in page
    md = (out / "report.md").read_text()
    assert "| low |" in md and "Failed runs" in md
    low = summary["assessment"]
    assert low["worst_delta_s_pct"] > 0 and low["failed_runs"] == 0   # low adhesion stops longer


@pytest.mark.slow   # a Dask cluster: separate processes, not under the sanitizers
def test_tuning_stores_its_trials_and_resumes(assessed, two_workers, tmp_path):
    s, _ = assessed
    first = tune.tune(s, ["decel_threshold"], "worst-delta-s", 1, tmp_path, scheduler=two_workers)
    assert first["evaluations"] == 1                     # the default WSP
    default = tune.default_values(tune.parameters(s, ["decel_threshold"]))["wsp.decel_threshold"]
    assert first["tuned"] == {**first["default"], "params": {"decel_threshold": default}}
    start = tmp_path / "start.yaml"
    start.write_text("wsp:\n  decel_threshold: 3.5 m/s^2\n")
    again = tune.tune(s, ["decel_threshold"], "worst-delta-s", 2, tmp_path, scheduler=two_workers, start=start)
    assert again["evaluations"] == 2            # one more trial (the start fragment), the first from the storage
    assert again["tuned"]["params"]["decel_threshold"] in (pytest.approx(default), pytest.approx(3.5))
    assert again["default"] == first["default"]
    assert again["default"]["worst_delta_s_pct"] >= again["tuned"]["worst_delta_s_pct"]
    assert (tmp_path / "wsp-fragment.yaml").read_text().count("decel_threshold") == 1
    assert json.loads((tmp_path / "summary.json").read_text())["evaluations"] == 2
    assert (tmp_path / "convergence.png").stat().st_size > 0
    assert 1.5 <= again["tuned"]["params"]["decel_threshold"] <= 4.0
    assert np.isfinite(again["tuned"]["worst_delta_s_pct"])


CONTROLLERS = """schema: railbrake.study/1
name: tiny-controllers
base: emergency-250-dry
set: {train.cars: 1, stop.max_time: "60 s", initial_speed: "60 km/h"}
factors:
  wsp.controller: all
  adhesion_case:
    - {name: dry, adhesion.condition: dry-medium}
    - {name: low, adhesion.condition: oil-film}
design: {kind: grid}
assessment:
  reference: {adhesion_case: dry}
tuning:
  params:
    wsp.setpoint_speed: {low: "0.03 m/s", high: "1.5 m/s"}
"""


@pytest.mark.slow   # a Dask cluster: separate processes, not under the sanitizers
def test_tuning_reaches_the_slip_setpoint_controllers_parameters(two_workers, tmp_path):
    """wsp tune on a parameter of another controller than the default one: its value reaches the
    runs of that controller (a macro-slip set-point stops otherwise than the micro-slip default),
    the first trial is the core's default, and the Pareto front of worst dS against air is reported."""
    s = study.parse(CONTROLLERS, "tiny.yaml")
    params = tune.parameters(s, ["setpoint_speed"])
    default = tune.default_values(params)["wsp.setpoint_speed"]
    keep = tune.select(s, ["wsp.controller=slip_setpoint"])
    client, _ = execute.connect(two_workers, None)
    try:
        evaluate = tune.Evaluator(s, tmp_path, client, keep)
        micro, macro = (evaluate({"wsp.setpoint_speed": v}, params) for v in (default, 1.5))
    finally:
        client.close()
    assert {c["wsp.controller"] for c in micro["cases"]} == {"slip_setpoint"}
    assert micro["worst_delta_s_pct"] != macro["worst_delta_s_pct"]
    summary = tune.tune(s, ["setpoint_speed"], "pareto", 3, tmp_path / "tuning", scheduler=two_workers,
                        only=["wsp.controller=slip_setpoint"])
    assert summary["evaluations"] == 3 and summary["front"]
    assert summary["default"]["worst_delta_s_pct"] == pytest.approx(micro["worst_delta_s_pct"])
    assert all(0.03 <= f["params"]["setpoint_speed"] <= 1.5 for f in summary["front"])
    assert (tmp_path / "tuning" / "front.png").stat().st_size > 0


def test_a_start_fragment_is_read_in_si_and_checked_against_the_tuning_range(tmp_path):
    s = study.parse(ASSESSED, "tiny.yaml")
    params = tune.parameters(s, ["decel_threshold"])
    fragment = tmp_path / "wsp-fragment.yaml"
    fragment.write_text("wsp:\n  decel_threshold: 3 m/s^2\n")
    assert tune.start_values(fragment, params) == {"wsp.decel_threshold": pytest.approx(3.0)}
    fragment.write_text("wsp:\n  decel_threshold: 5 m/s^2\n")
    with pytest.raises(InputError, match=r"wsp.decel_threshold = 5 m/s\^2 outside its tuning range \[1.5 m/s\^2, 4 m/s\^2\]"):
        tune.start_values(fragment, params)
    fragment.write_text("wsp:\n  speed_threshold: 0.5 m/s\n")
    with pytest.raises(InputError, match="wsp.decel_threshold missing"):
        tune.start_values(fragment, params)
    fragment.write_text("wsp:\n  decel_threshold: 3 m/s^2\n  speed_threshold: 0.5 m/s\n")
    with pytest.raises(InputError, match=r"wsp.speed_threshold: not tuned here \(a fragment gives wsp.decel_threshold\)"):
        tune.start_values(fragment, params)   # read or refused: never dropped


def test_a_tuning_interrupted_during_the_default_trial_queues_the_default_again(tmp_path):
    import optuna
    from optuna.trial import TrialState
    storage = tune._storage(tmp_path)
    trials = optuna.create_study(study_name="t", storage=storage)
    tune._recover(trials, storage, {"wsp.decel_threshold": 2.5})
    trials.ask()                                # the default trial starts ... and the process is killed
    storage = tune._storage(tmp_path)           # the rerun opens the folder's database again
    trials = optuna.load_study(study_name="t", storage=storage)
    tune._recover(trials, storage, {"wsp.decel_threshold": 2.5})
    states = [t.state for t in trials.get_trials(deepcopy=False)]
    assert states == [TrialState.FAIL, TrialState.WAITING]
    assert trials.trials[1].user_attrs == {"default": True}
    tune._recover(trials, storage, {"wsp.decel_threshold": 2.5})   # queued already: not twice
    assert len(trials.trials) == 2
