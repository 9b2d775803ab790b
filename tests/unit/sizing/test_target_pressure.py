"""Target pressure by inverse computation: forward check, lambda(v), adhesion, warnings."""

import numpy as np
import pytest

from railbrake import sizing, vehicle
from railbrake.errors import InputError
from railbrake.units import G_STANDARD

PRESETS = ["crh380a-8", "crh380al-16", "velaro-8"]


@pytest.mark.parametrize("train_name", PRESETS)
@pytest.mark.parametrize("profile_name", ["emergency", "service-max"])
def test_forward_simulation_reproduces_the_demand_within_1_percent(train_name, profile_name):
    train = vehicle.load_train(train_name)
    result = sizing.target_pressure(train, profile_name)
    assert result.p_motor.max() <= train.supply_pressure  # the presets are sized within supply
    achieved = sizing.forward_deceleration(train, result.speed, result.p_motor, result.p_trailer,
                                           ed_demand=result.deceleration if result.ed_blending else None)
    assert np.all(np.abs(achieved / result.deceleration - 1.0) < 0.01)
    assert result.warnings == []


def test_rail_forces_balance_translational_mass_and_resistance():
    # sum over axles of adhesion * Q = brake force - rotating part = M a - R(v) (Newton, level track)
    train = vehicle.load_train("crh380al-16")
    r = sizing.target_pressure(train, "emergency")
    rail = (r.adhesion * np.array([car.mass for car in train.cars]) * G_STANDARD).sum(axis=1)
    expected = train.mass * r.deceleration - train.running_resistance(r.speed)
    assert rail == pytest.approx(expected, rel=1e-9)


def test_pad_friction_rise_lowers_the_trailer_pressure_below_100_kmh():
    # constant 1.0 m/s^2: (p - p_threshold) scales with demand / lambda, lambda from the preset's
    # pad table at 0 and 100 km/h; the demand differs only by the trailers' share of resistance.
    train = vehicle.load_train("crh380a-8")
    v = np.array([0.0, 100.0 / 3.6])
    r = sizing.target_pressure(train, 1.0, speeds=v)
    trailers = [car for car in train.cars if not car.motor]
    m_eff = sum(car.mass + car.equivalent_rotating_mass for car in trailers)
    share = sum(car.mass for car in trailers) / train.mass
    demand = m_eff * 1.0 - share * train.running_resistance(v)
    threshold = vehicle.P_ATM + 700.0 / 0.020  # return spring over cylinder area (preset)
    ratio = (r.p_trailer[0] - threshold) / (r.p_trailer[1] - threshold)
    pad = vehicle.pad_friction_of(trailers[0], v)
    assert pad[0] > pad[1]
    assert ratio == pytest.approx(demand[0] / demand[1] * pad[1] / pad[0], rel=1e-9)
    frozen = sizing.target_pressure(vehicle.with_constant_pad_friction(train), 1.0, speeds=v)
    assert frozen.p_trailer[0] > r.p_trailer[0]


def test_emergency_step_of_the_presets_is_pneumatic_only():
    # the train files say ed_blending: false for emergency: no ED force, motor cars braked by air
    r = sizing.target_pressure("crh380al-16", speeds=[50 / 3.6, 300 / 3.6])
    assert not r.ed_blending and np.all(r.ed_force == 0.0)
    assert np.all(r.p_motor > sizing.target_pressure("crh380al-16", speeds=[50 / 3.6, 300 / 3.6], ed=True).p_motor)


def test_ed_first_on_motor_cars():
    train = vehicle.load_train("crh380al-16")
    r = sizing.target_pressure(train, "emergency", speeds=[50 / 3.6, 300 / 3.6], ed=True)
    assert r.ed_force == pytest.approx(train.ed_brake_force(r.speed), rel=1e-12)  # ED saturated
    r = sizing.target_pressure(train, 0.2, speeds=[150 / 3.6], ed=True)  # ED alone suffices on motor cars
    assert r.gauge_bar(r.p_motor[0]) == 0.0 and r.p_trailer[0] > r.atmospheric_pressure


def test_warnings_for_adhesion_and_supply():
    r = sizing.target_pressure("crh380a-8", "emergency", adhesion_limit=0.1)
    assert any("adhesion demand" in w and "design limit 0.1" in w for w in r.warnings)
    r = sizing.target_pressure("crh380a-8", 2.5)
    assert any("trailer cylinder pressure" in w and "exceeds the supply" in w for w in r.warnings)


def test_profile_not_monotonic_in_speed_is_named(tmp_path):
    with pytest.raises(InputError, match=r"speed_kmh\[2\] = 50\.0: the profile must be monotonic"):
        sizing.make_profile([0, 100, 50], [1.0, 1.0, 1.0])
    csv = tmp_path / "bad.csv"
    csv.write_text("speed_kmh,deceleration_ms2\n0,1.0\n200,0.9\n200,0.8\n")
    with pytest.raises(InputError, match=r"speed_kmh\[2\] = 200\.0"):
        sizing.load_profile(csv)


def test_pressure_beyond_supply_is_refused_by_name():
    train = vehicle.load_train("crh380a-8")
    too_high = train.supply_pressure + 0.5e5
    with pytest.raises(InputError, match=r"p_trailer\[0\] = .* supply pressure"):
        sizing.forward_deceleration(train, [50.0], train.atmospheric_pressure + 1e5, too_high)


@pytest.mark.parametrize("gradient", [-0.02, 0.02])
def test_forward_check_holds_on_a_gradient(gradient):
    # downhill the brakes must also hold the slope force, uphill the slope helps
    train = vehicle.load_train("velaro-8")
    level = sizing.target_pressure(train, "emergency", ed=True)
    r = sizing.target_pressure(train, "emergency", gradient=gradient, ed=True)
    achieved = sizing.forward_deceleration(train, r.speed, r.p_motor, r.p_trailer,
                                           ed_demand=r.deceleration, gradient=gradient)
    assert np.all(np.abs(achieved / r.deceleration - 1.0) < 0.01)
    assert np.all((r.p_trailer > level.p_trailer) == (gradient < 0))


def test_a_shipped_profile_is_read_once_and_cannot_be_changed_by_a_caller():
    """Studies set up thousands of runs from the same preset profile: it is read once, read-only,
    so one run's caller cannot change the next run's demand."""
    import numpy as np
    from railbrake import sizing
    first = sizing.load_profile(sizing.profile_names()[0])
    assert sizing.load_profile(sizing.profile_names()[0]) is first
    with pytest.raises(ValueError, match="read-only"):
        first.deceleration[0] = 0.0
    assert np.all(first.deceleration > 0.0)
