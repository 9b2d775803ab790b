"""The importance ranking (railbrake.etcs.importance) against independent references:
- a failure's probability set to zero: the states' probabilities equal those of the states enumerated
  again from the file without it (railbrake.etcs.failures, exactly);
- without scatter, a car-level failure that alone lowers Kdry_rst: its removal gives Kdry_rst 1 at
  every level (the gain is 1 - Kdry_rst);
- a tolerance that alone makes the scatter: at nominal, the ratio is 1 again (the gain is 1 -
  Kdry_rst, within the first-order estimate's accuracy); a tolerance with no effect on this brake
  gains nothing."""

import numpy as np
import pytest

from railbrake.etcs import confidence, failures, importance, inputs, model, runs

SPEED = 80.0

RELIABILITY = """schema: railbrake.reliability/1
name: importance-test
source: test
failures:
  - {kind: hold_stuck_closed, unit: axle, per_demand: 1.0e-2, source: test}
  - {kind: relay_valve_failed, unit: car, pressure_bar: 0.0, per_demand: 1.0e-3, source: test}
  - {kind: cylinder_leak, unit: bogie, leak_area_mm2: 50.0, per_demand: 2.0e-3, source: test}
common_cause:
  - {name: both emergency valves, kind: emergency_valve_failed, cars: [1, 2], per_demand: 1.0e-3, source: test}
"""

CAR_LOST = """schema: railbrake.reliability/1
name: car-lost
source: test
failures:
  - {kind: car_isolated, unit: car, per_demand: 0.05, source: test}
"""

SCATTER = """schema: railbrake.scatter/1
name: pads-only
title: test
source: test
pad_friction: {distribution: truncated_normal, mean: 1.0, sd: 0.05, bounds: [0.85, 1.15], per: car, source: test}
valve_response: {distribution: uniform, bounds: [0.8, 1.2], per: car, source: test}
"""


def test_a_failure_removed_weighs_the_states_as_an_enumeration_without_it(tmp_path):
    path = tmp_path / "rel.yaml"
    path.write_text(RELIABILITY)
    floor = 1e-9
    ctx = runs.context(model.spec("crh380a-8", reliability=path, scatter=None, cars=2, initial_speed_kmh=SPEED,
                                  state_floor=floor, force_conditions=True))
    rel = ctx.reliability
    variants = importance._failure_weights(ctx)
    assert [kind for _, kind, _ in variants] == ["failure"] * 3 + ["common cause"]
    for k, (name, _, weights) in enumerate(variants):
        if k < len(rel.failures):
            changed = rel.failures[k].model_copy(update={"per_demand": 0.0})
            without = rel.model_copy(update={"failures": [changed if i == k else f
                                                          for i, f in enumerate(rel.failures)]})
        else:
            changed = rel.common_cause[0].model_copy(update={"per_demand": 0.0})
            without = rel.model_copy(update={"common_cause": [changed]})
        # the states of the file without it, to well below the floor: none of ours is missed
        _, _, states = failures.enumerate_states(without, ctx.train, floor * 1e-3)
        reference = {s.label: s.probability for s in states}
        for state, w in zip(ctx.states, weights):
            if w == 0.0:
                assert state.label not in reference or reference[state.label] == 0.0, (name, state.label)
            else:
                assert w == pytest.approx(reference[state.label], rel=1e-12), (name, state.label)


def test_without_scatter_removing_the_one_failure_gives_kdry_one(tmp_path):
    path = tmp_path / "rel.yaml"
    path.write_text(CAR_LOST)
    m = model.braking_model(model.spec("crh380a-8", reliability=path, scatter=None, cars=2,
                                       initial_speed_kmh=SPEED, force_conditions=True))
    assert m.kdry[0][2] < 0.6   # at 99 %, a car lost decides (about half the brake force)
    for level, entry in enumerate(m.importance):
        (only,) = entry["ranking"]
        assert only["name"] == "car_isolated (car)" and only["type"] == "failure"
        for gain, step in zip(only["kdry_gain"], m.kdry):
            assert gain == pytest.approx(1.0 - step[level], abs=1e-3)


@pytest.mark.slow   # 48 whole-train runs of one car, one process
def test_a_tolerance_at_nominal_removes_its_scatter(tmp_path):
    rel, scatter = tmp_path / "rel.yaml", tmp_path / "scatter.yaml"
    rel.write_text(CAR_LOST.replace("per_demand: 0.05", "per_demand: 0.0"))
    scatter.write_text(SCATTER)
    m = model.braking_model(model.spec("crh380a-8", reliability=rel, scatter=scatter, cars=1,
                                       initial_speed_kmh=SPEED, samples=48, run_budget=0, force_conditions=True))
    assert inputs.load_scatter(str(scatter)).pad_friction.per == "car"
    for level, entry in enumerate(m.importance):
        gains = {e["name"]: e["kdry_gain"] for e in entry["ranking"]}
        for j, step in enumerate(m.kdry):
            if confidence.EBCL[level] > 0.5:   # below the median the pads' scatter lowers Kdry_rst
                assert step[level] < 1.0 - 0.01
            assert gains["pad_friction"][j] == pytest.approx(1.0 - step[level], abs=0.005)
            assert abs(gains["valve_response"][j]) < 0.002
        assert entry["ranking"][0]["name"] == "pad_friction" or confidence.EBCL[level] == 0.5
