"""What a better brake buys (railbrake.etcs.buys) on a 1-car train from 80 km/h: each WSP
controller's Kwet_rst from its own EN 15595 test pairs; limiting cases: on dry rail (M_NVAVADH 1)
Kwet_rst has no effect, so every controller gives the same curves; a smaller Kwet_rst never gives
a shorter EBI distance; the time along a constant-deceleration curve is v0 / a."""

import json

import pytest

from railbrake import jsonio
from railbrake.etcs import buys, export, model, national, service
from railbrake.units import KMH

RELIABILITY = """schema: railbrake.reliability/1
name: t
source: test
failures: []
"""


@pytest.fixture(scope="module")
def rows(tmp_path_factory):
    rel = tmp_path_factory.mktemp("buys") / "rel.yaml"
    rel.write_text(RELIABILITY)
    data = json.loads(jsonio.dumps(export.to_json(model.braking_model(model.spec("crh380a-8", rel, None, 1, 80.0, force_conditions=True)))))
    return buys.study(data, service.service_data(data), national.load_track("flat-10km"), national.load_national())


def test_every_controller_on_both_adhesions(rows):
    assert {(r["controller"], r["adhesion"]) for r in rows} == {(c, a) for c in buys.CONTROLLERS for a in buys.ADHESION}
    for r in rows:
        assert 0.0 < r["Kwet_rst"] <= r["Kwet_before_rounding"] <= 1.0
        assert r["EBI_to_EoA_m"] > 0.0 and r["time_lost_s"] > 0.0


def test_dry_rail_does_not_see_kwet_and_a_lower_kwet_costs_metres(rows):
    dry = [r for r in rows if r["adhesion"].startswith("dry")]
    wet = [r for r in rows if not r["adhesion"].startswith("dry")]
    assert len({round(r["EBI_to_EoA_m"], 9) for r in dry}) == 1
    for d, w in zip(dry, wet):
        assert w["EBI_to_EoA_m"] >= d["EBI_to_EoA_m"] and w["time_lost_s"] >= d["time_lost_s"]
    ranked = sorted(wet, key=lambda r: -r["Kwet_rst"])
    assert [r["EBI_to_EoA_m"] for r in ranked] == sorted(r["EBI_to_EoA_m"] for r in ranked)


def test_time_along_a_constant_deceleration_curve():
    a, v0, eoa = 0.8, 200.0 * KMH, 5000.0
    speeds = [v0 * (1.0 - i / 50) for i in range(51)]
    points = [[eoa - v * v / (2.0 * a), v / KMH] for v in speeds]
    assert buys.time_following(points) == pytest.approx(v0 / a, rel=1e-12)


def test_the_study_has_no_sander_case_because_no_preset_can_run_one():
    """docs/etcs.md leaves sanders out of the study: no preset train carries them, and the
    reduced-adhesion condition of the Kwet_rst pairs is not cleaned cell by cell (sand acts only
    there). When either changes, the sander case belongs in railbrake.etcs.buys."""
    from railbrake import vehicle
    from railbrake.adhesion.conditions import load_condition
    assert [t for t in vehicle.preset_names() if vehicle.load_train(t).spec.sanders is not None] == []
    reduced = load_condition(model.method().reduced_condition)
    assert reduced.conditioning is None or reduced.conditioning.reference_energy == 0.0
