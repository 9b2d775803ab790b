"""EN 15595-style assessment (hand-computed dS %, Kwet), Sobol indices of a known function, the
HTML/Markdown report of a real campaign, and a short resumable WSP tuning."""

import json
import types
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import qmc

from railbrake.campaign import execute, report, study, tune
from railbrake.campaign.assess import assess, worst
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
