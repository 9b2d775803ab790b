"""The brake calculation (railbrake.brakecalc): its formulae against analytic limiting cases and
the published anchor, the train report's figures against each other and the TSI table."""

import math

import numpy as np
import pytest

from railbrake import brakecalc, sizing
from railbrake.errors import InputError
from railbrake.units import kmh_to_ms


def test_constant_deceleration_gives_the_textbook_distance_and_decelerations():
    """A constant deceleration a after te: s = v0 te + v0^2 / (2 a) (C stop, no resistance); the
    EN 14531 equivalent deceleration of that stop and its mean deceleration over every speed
    interval of the braking part (after te) are a."""
    v0, a, te = kmh_to_ms(200.0), 0.9, 1.4
    stop = sizing.stopping_distance(v0, deceleration=a, response_time=te, dt=0.001, dt_out=0.01)
    assert stop.distance == pytest.approx(v0 * te + v0 ** 2 / (2 * a), rel=1e-4)
    assert brakecalc.equivalent_deceleration(v0, stop.distance, te) == pytest.approx(a, rel=1e-3)
    curve = brakecalc.braking_curve(stop.curve_time, stop.curve_speed, stop.curve_distance, te)
    assert curve[1][0] == pytest.approx(v0 * te, rel=1e-4)
    rows = brakecalc.interval_decelerations(*curve, [[200, 160], [160, 120], [120, 40], [40, 0]])
    assert [r["from_kmh"] for r in rows] == pytest.approx([200, 160, 120, 40], abs=0.01)
    for r in rows:
        assert r["deceleration_ms2"] == pytest.approx(a, rel=2e-3)
        v1, v2 = kmh_to_ms(r["from_kmh"]), kmh_to_ms(r["to_kmh"])
        assert r["distance_m"] == pytest.approx((v1 ** 2 - v2 ** 2) / (2 * a), rel=2e-3)


def test_interval_decelerations_of_a_two_step_stop():
    """Braking at 0.6 m/s2 above 100 km/h and 1.2 m/s2 below (analytic curve): each interval inside
    one step gives that step's deceleration; one across the step the distance-weighted mean; an
    interval above the initial speed is left out."""
    v0, vs, a1, a2 = kmh_to_ms(160.0), kmh_to_ms(100.0), 0.6, 1.2
    v = np.linspace(v0, 0.0, 20001)
    s = np.where(v >= vs, (v0 ** 2 - v ** 2) / (2 * a1), (v0 ** 2 - vs ** 2) / (2 * a1) + (vs ** 2 - v ** 2) / (2 * a2))
    rows = brakecalc.interval_decelerations(v, s, [[200, 160], [160, 100], [100, 0], [120, 80]])
    assert [r["from_kmh"] for r in rows] == pytest.approx([160, 100, 120])
    assert rows[0]["deceleration_ms2"] == pytest.approx(a1, rel=1e-6)
    assert rows[1]["deceleration_ms2"] == pytest.approx(a2, rel=1e-6)
    v1, v2 = kmh_to_ms(120.0), kmh_to_ms(80.0)
    mixed = (v1 ** 2 - v2 ** 2) / ((v1 ** 2 - vs ** 2) / a1 + (vs ** 2 - v2 ** 2) / a2)
    assert rows[2]["deceleration_ms2"] == pytest.approx(mixed, rel=1e-6)
    with pytest.raises(InputError, match=r"speed interval \[80, 120\] km/h"):
        brakecalc.interval_decelerations(v, s, [[80, 120]])


def test_equivalent_deceleration_refuses_a_stop_shorter_than_its_response_distance():
    with pytest.raises(InputError, match="must exceed the response distance"):
        brakecalc.equivalent_deceleration(50.0, 100.0, 2.0)


def test_brake_percentage_against_the_published_anchor_and_its_inversion():
    """UIC 544-1, position P (data file): 80 % stops from 120 km/h in 1000 m; 160 % is a mean
    deceleration of about 1.12 m/s2 (the source's own figure, to its 2 digits); the inverse gives
    back the distance; braked weight = lambda m / 100."""
    uic = brakecalc.settings()["uic544"]
    assert brakecalc.brake_percentage(uic["anchor"]["stopping_distance_m"]) == pytest.approx(80.0, rel=1e-12)
    v = kmh_to_ms(uic["reference_speed_kmh"])
    assert brakecalc.brake_percentage(v ** 2 / (2 * 1.12)) == pytest.approx(160.0, rel=0.01)
    for s in (400.0, 731.5, 1800.0):
        assert brakecalc.uic_stopping_distance(brakecalc.brake_percentage(s)) == pytest.approx(s, rel=1e-12)
    assert brakecalc.braked_weight(100.0, 192.0) == pytest.approx(192.0)
    assert brakecalc.braked_weight(150.0, 200.0) == pytest.approx(300.0)
    with pytest.raises(InputError, match="distance"):
        brakecalc.brake_percentage(0.0)


def test_report_of_a_train_below_and_above_200_kmh():
    """class387-4 (177 km/h): lambda from its own stop from 120 km/h, no TSI value applies. velaro-8
    (350 km/h): lambda refused outside UIC 544-1's validity, TSI rows from 200 to 350 km/h, each
    margin the limit less the distance, passed exactly when the distance is within the limit."""
    slow = brakecalc.calculate("class387-4")
    assert slow.uic["within_validity"] and slow.tsi == [] and slow.passed is None
    assert slow.uic["brake_percentage"] == pytest.approx(
        brakecalc.brake_percentage(slow.uic["stopping_distance_m"]))
    assert slow.uic["braked_weight_t"] == pytest.approx(slow.uic["brake_percentage"] * slow.mass_t / 100)
    e = slow.en14531
    assert e["initial_speed_kmh"] == pytest.approx(177.0)
    assert e["response_time_s"] == pytest.approx(e["delay_s"] + e["build_up_s"] / 2)
    v0 = kmh_to_ms(177.0)
    assert v0 * e["response_time_s"] + v0 ** 2 / (2 * e["equivalent_deceleration_ms2"]) == \
        pytest.approx(e["stopping_distance_m"])
    # the stop from 120 km/h is shorter than from 177 km/h and its mean deceleration is in the range
    # of the interval decelerations (resistance adds a little at high speed)
    assert slow.uic["stopping_distance_m"] < e["stopping_distance_m"]
    lows = [r["deceleration_ms2"] for r in e["intervals"]]
    assert min(lows) * 0.98 < kmh_to_ms(120.0) ** 2 / (2 * (slow.uic["stopping_distance_m"] - kmh_to_ms(120.0)
                                                              * slow.uic["response_time_s"])) < max(lows) * 1.02

    fast = brakecalc.calculate("velaro-8", force_lambda=False)
    assert not fast.uic["within_validity"] and fast.uic["brake_percentage"] is None
    assert "--force-lambda" in fast.uic["note"]
    assert [r["speed_kmh"] for r in fast.tsi] == [200, 250, 300, 350]
    for r in fast.tsi:
        assert r["margin_m"] == pytest.approx(r["limit_m"] - r["stopping_distance_m"])
        assert r["passed"] == (r["stopping_distance_m"] <= r["limit_m"])
        v = kmh_to_ms(r["speed_kmh"])
        assert v * r["response_time_s"] + v ** 2 / (2 * r["equivalent_deceleration_ms2"]) == \
            pytest.approx(r["stopping_distance_m"])
    assert fast.passed == all(r["passed"] for r in fast.tsi)
    distances = [r["stopping_distance_m"] for r in fast.tsi]
    assert distances == sorted(distances) and not math.isclose(distances[0], distances[-1])
