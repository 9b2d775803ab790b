"""The ETCS braking model from whole-train runs (railbrake.etcs.model), on a short, cheap
configuration: the 8-car CRH380A from 160 km/h, few samples. Limiting cases: no scatter and no
failure gives Kdry_rst 1; a car certain to be lost takes its share of the brake force; the
factors' ranges, grid and order; Kwet_rst from the worse EN 15595 pair."""

import numpy as np
import pytest

from railbrake import sizing
from railbrake.etcs import confidence, model, runs
from railbrake.units import KMH
from railbrake.vehicle import load_train

TRAIN, SPEED = "crh380a-8", 160.0

NO_FAILURES = """schema: railbrake.reliability/1
name: none
source: test
failures: []
"""

CAR_3_LOST = NO_FAILURES + """common_cause:
  - {name: car 3 isolated, kind: car_isolated, cars: [3], per_demand: 1.0, source: test}
"""


@pytest.fixture(scope="module")
def shipped():
    # states down to 1e-9 and no runs added for the bounds: a short analysis (the levels above
    # 1e-9 then read the states left out as no brake, the safe side)
    return model.braking_model(model.spec(TRAIN, initial_speed_kmh=SPEED, samples=8, rare_samples=2,
                                          state_floor=1e-9, run_budget=0))


@pytest.mark.slow   # hundreds of whole-train runs: 2-3 min each under the sanitizers
def test_kdry_is_coded_on_the_grid_and_does_not_rise_with_the_level(shipped):
    assert len(shipped.kdry) == len(shipped.a_brake_emergency) == len(shipped.speed_steps_kmh)
    assert shipped.speed_steps_kmh == [0.0, 50.0, 100.0, 150.0]
    assert len(shipped.step_allowance) == len(shipped.kdry) and all(a >= 0.0 for a in shipped.step_allowance)
    for raw, coded, bounds, allowance in zip(shipped.kdry, shipped.kdry_coded(), shipped.kdry_bounds,
                                             shipped.step_allowance):
        assert all(0.0 <= k <= confidence.K_MAX for k in raw)
        assert all(a >= b for a, b in zip(raw, raw[1:]))
        assert all(a >= b for a, b in zip(coded, coded[1:]))
        for k, c, (low, _) in zip(raw, coded, bounds):   # the bound's lower end less the step allowance, rounded down
            safe = max(0.0, k - low - allowance)
            assert c <= safe + 1e-12 and safe - c < confidence.K_STEP
            assert abs(c / confidence.K_STEP - round(c / confidence.K_STEP)) < 1e-9
    assert all(a > 0.0 for a in shipped.a_brake_emergency) and shipped.t_brake_emergency > 0.0


@pytest.mark.slow   # hundreds of whole-train runs: 2-3 min each under the sanitizers
def test_kwet_is_the_worse_pairs(shipped):
    assert [p["speed_kmh"] for p in shipped.kwet_pairs] == [120.0, SPEED]
    assert shipped.kwet == min(p["kwet"] for p in shipped.kwet_pairs)
    assert 0.0 < shipped.kwet <= 1.0 and 0.0 < shipped.kwet_coded() <= shipped.kwet
    for p in shipped.kwet_pairs:   # 100 / (100 + increase in %) of the deceleration distance
        ratio = p["dry_deceleration_distance_m"] / p["reduced_deceleration_distance_m"]
        assert p["kwet"] == pytest.approx(min(ratio, 1.0), rel=1e-12)


def test_no_scatter_and_no_failure_gives_one_at_every_level(tmp_path):
    path = tmp_path / "none.yaml"
    path.write_text(NO_FAILURES)
    m = model.braking_model(model.spec(TRAIN, reliability=path, scatter=None, initial_speed_kmh=SPEED))
    assert m.runs == 1
    assert all(k == 1.0 for step in m.kdry for k in step)
    assert all(k == 1.0 for step in m.kdry_coded() for k in step)


@pytest.mark.slow   # 16 s under the sanitizers; the no-failure case covers the same code
def test_a_car_certain_to_be_lost_takes_its_share_of_the_brake_force(tmp_path):
    """The ratio of each speed step drops by car 3's share of the train's emergency brake force
    (the BCU's per-car demand, railbrake.sizing) over the step, within 1 %."""
    path = tmp_path / "car3.yaml"
    path.write_text(CAR_3_LOST)
    m = model.braking_model(model.spec(TRAIN, reliability=path, scatter=None, initial_speed_kmh=SPEED))
    train = load_train(TRAIN)
    demands = sizing.car_demands(train, sizing.brake_step(train, "emergency")[0])
    edges = [*m.speed_steps_kmh, SPEED]
    for j, step in enumerate(m.kdry):
        v = np.linspace(edges[j], edges[j + 1], 50) * KMH
        forces = np.array([np.interp(v, d.speed, d.force) for d in demands])
        share = float(np.mean(forces[2] / forces.sum(axis=0)))
        assert all(k == pytest.approx(1.0 - share, rel=0.01) for k in step), (j, step, 1 - share)


@pytest.mark.slow   # hundreds of whole-train runs: 2-3 min each under the sanitizers
def test_a_resumed_analysis_gives_the_same_result(tmp_path):
    """Batches already in the folder are read back, the others run: equal results."""
    path = tmp_path / "none.yaml"
    path.write_text(NO_FAILURES)
    spec = model.spec(TRAIN, reliability=path, initial_speed_kmh=SPEED, samples=runs.BATCH + 4, run_budget=0)
    out = tmp_path / "analysis"
    first = model.braking_model(spec, out=out)
    batches = sorted((out / "batches").iterdir())
    assert len(batches) == 2
    batches[-1].unlink()   # as if killed before the last batch was written
    again = model.braking_model(spec, out=out)
    assert again.kdry == first.kdry and again.runs == first.runs == runs.BATCH + 4
    other = model.spec(TRAIN, reliability=path, initial_speed_kmh=SPEED, samples=8, seed=2, run_budget=0)
    with pytest.raises(model.InputError, match="another analysis"):
        runs.run_all(other, [(0, 0)], out)
