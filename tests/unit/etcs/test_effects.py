"""Every failure reaches the brake it fails (issue 36): each failure of the shipped reliability
file, run alone on the CRH380A-8's emergency stop from its maximum speed, lowers the deceleration
ratio by at least half of its unit's share of the train's emergency brake force (the BCU's per-car
demand, railbrake.sizing) at every speed step, or is reported as "no effect on this brake"; the
EP valve's failure, which the emergency valve bypasses, is reported so; and so is a scatter factor
that moves nothing."""

import pytest

from railbrake.etcs import model, runs

NO_EFFECT = """schema: railbrake.reliability/1
name: t
source: test
failures:
  - {kind: ep_valve_failed, unit: car, per_demand: 1.0e-5, source: test}
  - {kind: emergency_valve_failed, unit: car, per_demand: 1.0e-5, source: test}
"""

SCATTER = """schema: railbrake.scatter/1
name: t
source: test
valve_response: {distribution: uniform, bounds: [0.5, 2.0], per: car, source: test}
emergency_choke: {distribution: uniform, bounds: [0.5, 2.0], per: car, source: test}
"""


def _screen(spec):
    ctx = runs.context(spec)
    t_be = model.nominal_build_up(ctx)
    return model.screen(ctx, t_be, model.nominal_decelerations(ctx, t_be, ctx.structs[3].stop_speed))


@pytest.mark.slow   # 20 runs of 8 cars from 350 km/h: about 20 s
def test_every_shipped_failure_lowers_the_ratio_by_half_its_share_at_least():
    effects, warnings = _screen(model.spec("crh380a-8", scatter=None, samples=2, rare_samples=2))
    kinds = set()
    for e in effects:
        kinds.add(e["kind"])
        print(e.get("common_cause") or e["kind"], e["unit"], e["car_type"], [round(r, 4) for r in e["ratio"]],
              round(e.get("drop_of_share", float("nan")), 3), "no effect" if e["no_effect"] else "")
        if e["no_effect"]:
            assert any(e["kind"] in w and "no effect on this brake" in w for w in warnings)
        elif "drop_of_share" in e:
            assert e["drop_of_share"] >= 0.5, e
        else:   # a common-cause group: at least half of one car's share
            assert max(e["ratio"]) <= 1.0 - 0.5 * 0.05
    assert {"emergency_valve_failed", "relay_valve_failed", "pressure_limiter_failed", "axle_isolated",
            "cylinder_leak"} <= kinds


def test_the_ep_valve_in_emergency_is_reported_as_no_effect(tmp_path):
    path = tmp_path / "rel.yaml"
    path.write_text(NO_EFFECT)
    effects, warnings = _screen(model.spec("crh380a-8", reliability=path, cars=2, initial_speed_kmh=80,
                                           samples=2, rare_samples=2))
    by_kind = {}
    for e in effects:
        by_kind.setdefault(e["kind"], []).append(e)
    assert all(e["no_effect"] for e in by_kind["ep_valve_failed"])
    assert all(e["ratio"] == [1.0] * len(e["ratio"]) for e in by_kind["ep_valve_failed"])
    assert not any(e["no_effect"] for e in by_kind["emergency_valve_failed"])
    assert any("ep_valve_failed" in w and "no effect on this brake" in w for w in warnings)
    assert not any("emergency_valve_failed" in w for w in warnings)
    # a scatter factor that cannot move the emergency stop (the EP and relay valves' response: the
    # emergency valve's choke sets the filling) is reported; the choke's area is not
    scatter = tmp_path / "scatter.yaml"
    scatter.write_text(SCATTER)
    _, warnings = _screen(model.spec("crh380a-8", reliability=path, scatter=scatter, cars=2, initial_speed_kmh=80,
                                     samples=2, rare_samples=2))
    assert any(w.startswith("scatter valve_response: no effect on this brake") for w in warnings), warnings
    assert not any(w.startswith("scatter emergency_choke") for w in warnings), warnings
