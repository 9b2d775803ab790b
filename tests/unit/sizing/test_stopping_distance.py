"""Stopping distance: closed forms (constant deceleration, linear build-up, coast-down) and the
braking-distance figures of EN 14531-1 and the measured stops in docs/references.md."""

import math

import numpy as np
import pytest

from railbrake import sizing, vehicle
from railbrake.errors import InputError


@pytest.mark.parametrize("v0_kmh, a, te", [(250, 0.9, 2.0), (300, 1.1, 0.0), (120, 1.35, 3.5)])
def test_constant_deceleration_after_response_time(v0_kmh, a, te):
    v0 = v0_kmh / 3.6
    r = sizing.stopping_distance(v0, deceleration=a, response_time=te)
    assert r.distance == pytest.approx(v0 * te + v0**2 / (2 * a), rel=1e-9)
    assert r.time == pytest.approx(te + v0 / a, rel=1e-9)
    assert sizing.stopping_distance_constant(v0, a, te)[0] == pytest.approx(r.distance, rel=1e-9)
    assert r.curve_speed[0] == v0 and r.curve_speed[-1] == 0.0
    assert np.all(np.diff(r.curve_distance) >= 0.0)


def test_linear_build_up_against_hand_integration():
    # effort ramps over tb after ta: s = v0 (ta + tb) - a tb^2 / 6 + (v0 - a tb / 2)^2 / (2 a)
    v0, a, ta, tb = 250 / 3.6, 1.0, 0.5, 2.5
    r = sizing.stopping_distance(v0, deceleration=a, delay=ta, build_up=tb, equivalent_response=False)
    expected = v0 * (ta + tb) - a * tb**2 / 6 + (v0 - a * tb / 2) ** 2 / (2 * a)
    assert r.distance == pytest.approx(expected, rel=1e-9)
    te = sizing.stopping_distance(v0, deceleration=a, delay=ta, build_up=tb)  # EN 14531 te
    assert te.distance == pytest.approx(v0 * (ta + tb / 2) + v0**2 / (2 * a), rel=1e-9)


@pytest.mark.parametrize("gradient", [0.0, 0.012])
def test_coast_down_matches_closed_form_with_a_b_c(gradient):
    # M_eff dv/dt = -(A + B v + C v^2), D = 4AC - B^2 > 0: closed forms of t(v) and s(v);
    # an uphill gradient i adds the constant m g i / sqrt(1 + i^2) to A
    train = vehicle.load_train("crh380al-16")
    A, B, C = train.c.resistance.A, train.c.resistance.B, train.c.resistance.C
    A += train.mass * 9.80665 * gradient / math.sqrt(1 + gradient**2)
    M = train.mass + train.rotating_mass
    v0, v1 = 300 / 3.6, 100 / 3.6
    r = sizing.coast_down(train, v0, v1, gradient=gradient)
    D = 4 * A * C - B * B
    atan = lambda v: math.atan((2 * C * v + B) / math.sqrt(D))  # noqa: E731
    t = 2 * M / math.sqrt(D) * (atan(v0) - atan(v1))
    prim = lambda v: math.log(A + B * v + C * v * v) / (2 * C) - B / (C * math.sqrt(D)) * atan(v)  # noqa: E731
    s = M * (prim(v0) - prim(v1))
    assert r.time == pytest.approx(t, rel=1e-6)
    assert r.distance == pytest.approx(s, rel=1e-6)


@pytest.mark.parametrize("train", ["crh380a-8", "crh380al-16", "velaro-8"])
def test_emergency_stops_within_the_published_limits(train):
    # Chinese EMU limits 2000 / 3200 / 3800 m and TSI 1500 / 2430 / 3650 m from 200/250/300 km/h
    # [T]; EP-brake design requirement < 3000 m from 250 km/h [P] (README s. 3)
    for v0_kmh, limit in ((200, 1500), (250, 2430), (300, 3650)):
        r = sizing.stopping_distance(v0_kmh / 3.6, train=train, profile="emergency")
        assert r.distance < limit
        assert r.warnings == []


def test_train_stop_is_shorter_than_the_profile_alone_by_resistance():
    # with cold pads (no fading) the brakes give the profile and the resistance adds to it
    v0 = 300 / 3.6
    alone = sizing.stopping_distance(v0, profile="emergency")
    cold = vehicle.load_train("crh380al-16")
    for car in cold.cars:
        car.c.brake.pad.fade_rate = 0.0
    train = sizing.stopping_distance(v0, train=cold, profile="emergency")
    assert 0.95 * alone.distance < train.distance < alone.distance


def test_fading_pads_lengthen_a_hot_stop():
    # the generic emergency profile heats the crh380al-16's discs past the pads' fade onset: the
    # pads lose friction the BCU's pressures (sized for cold pads) do not make up
    v0 = 300 / 3.6
    hot = sizing.stopping_distance(v0, train="crh380al-16", profile="emergency")
    cold = vehicle.load_train("crh380al-16")
    onset = cold.cars[0].c.brake.pad.fade_onset
    for car in cold.cars:
        car.c.brake.pad.fade_rate = 0.0
    assert hot.max_disc_surface_temperature > onset
    assert hot.distance > sizing.stopping_distance(v0, train=cold, profile="emergency").distance


def test_bad_stopping_input_is_named():
    with pytest.raises(InputError, match=r"v0 = -5"):
        sizing.stopping_distance(-5.0, deceleration=1.0)
    with pytest.raises(InputError, match=r"gradient = 0\.5"):
        sizing.stopping_distance(50.0, train="crh380a-8", gradient=0.5)
