"""The pads' heat fading and the two-node disc in dynamometer stops (rb_dyno_stop_run through
railbrake.vehicle.dynamometer_stop) and in the train: heat balance, limiting cases, the law, and
the fit recovering a fading it was given (railbrake.pad_fade)."""

import numpy as np
import pytest

from railbrake import pad_fade, simulation, vehicle
from railbrake.errors import InputError
from railbrake.units import KMH

AMBIENT = 293.15
CONDITIONS = {"deceleration": 0.9, "ambient_temperature": AMBIENT, "dt": 1e-2}


@pytest.fixture(scope="module")
def car():
    train = vehicle.load_train("crh380a-8")
    return next(c for c in train.cars if c.type_name == "motor")


def _flat(car, value: float, onset: float = 0.0, rate: float = 0.0):
    pad = pad_fade.pad_with(car, 0.0, onset, rate)
    for i in range(pad.table.n):
        pad.table.value[i] = value
    return pad


def test_heat_into_the_disc_is_the_kinetic_energy_and_the_disc_keeps_or_cools_it(car):
    stop = vehicle.dynamometer_stop(car, 300 * KMH, **CONDITIONS)
    mass = car.c.mass / (car.axles * car.equipment.discs.per_axle)
    kinetic = 0.5 * mass * (300 * KMH) ** 2
    assert stop.heat == pytest.approx(kinetic, rel=1e-9)
    assert stop.cooled > 0.0
    assert stop.stored + stop.cooled == pytest.approx(stop.heat, rel=1e-9)
    assert stop.max_surface_temperature > stop.max_mean_temperature > AMBIENT


def test_without_fading_the_stop_is_one_of_constant_deceleration(car):
    # a flat table and no fade: a = 2 mu F r / (R m) constant, s = v0^2 / 2a, mean friction mu
    stop = vehicle.dynamometer_stop(car, 250 * KMH, pad=_flat(car, 0.38), **CONDITIONS)
    assert stop.mean_friction == pytest.approx(0.38, rel=1e-12)
    assert stop.distance == pytest.approx((250 * KMH) ** 2 / (2 * 0.9), rel=1e-9)
    assert stop.time == pytest.approx(250 * KMH / 0.9, rel=1e-9)


def test_fading_law_divides_the_table_above_the_onset(car):
    pad = car.c.brake.pad
    cold = vehicle.pad_friction_of(car, 200 * KMH)
    assert vehicle.pad_friction_at_temperature(car, 200 * KMH, pad.fade_onset - 50.0) == cold
    hot = pad.fade_onset + 100.0
    assert vehicle.pad_friction_at_temperature(car, 200 * KMH, hot) == pytest.approx(
        cold / (1.0 + pad.fade_rate * 100.0), rel=1e-14)


def test_hotter_stops_fade_more_and_a_cool_one_not_at_all(car):
    pad = _flat(car, 0.38, AMBIENT + 150.0, 0.002)
    means = [vehicle.dynamometer_stop(car, v * KMH, pad=pad, **CONDITIONS) for v in (100, 250, 380)]
    assert means[0].max_surface_temperature < AMBIENT + 150.0
    assert means[0].mean_friction == pytest.approx(0.38, rel=1e-12)
    assert 0.38 > means[1].mean_friction > means[2].mean_friction


def test_fit_recovers_the_fading_that_made_its_data(car):
    # stop averages made with a known law; the fit given them finds that law again
    onset = vehicle.dynamometer_stop(car, 300 * KMH, pad=pad_fade.pad_with(car), **CONDITIONS).max_surface_temperature
    truth = pad_fade.pad_with(car, 0.01, onset, 0.002)
    made = {v: vehicle.dynamometer_stop(car, v * KMH, pad=truth, **CONDITIONS).mean_friction for v in (250, 380)}
    fit = pad_fade.fit(car, CONDITIONS, onset_speed=300 * KMH, level_speed=250 * KMH, level_mean=made[250],
                       rate_speed=380 * KMH, rate_mean=made[380])
    assert fit.onset == pytest.approx(onset, rel=1e-12)
    assert fit.rate == pytest.approx(0.002, rel=1e-4)
    assert fit.shift == pytest.approx(0.01, abs=1e-6)


def test_ratio_fit_and_rate_for_recover_the_fading_that_made_their_data(car):
    # a ratio of two stop averages (another pad's figures, pad-friction-stop-cross-pad) and a single
    # stop average with the level refitted (the diagnosis of that case) both find the law's rate
    onset = vehicle.dynamometer_stop(car, 300 * KMH, pad=pad_fade.pad_with(car), **CONDITIONS).max_surface_temperature
    truth = pad_fade.pad_with(car, 0.0, onset, 0.002)
    made = {v: vehicle.dynamometer_stop(car, v * KMH, pad=truth, **CONDITIONS).mean_friction for v in (200, 250, 350, 380)}
    fit = pad_fade.fit(car, CONDITIONS, onset_speed=300 * KMH, level_speed=250 * KMH, level_mean=made[250],
                       ratio_speeds=(200 * KMH, 350 * KMH), rate_ratio=made[350] / made[200])
    assert fit.rate == pytest.approx(0.002, rel=1e-4)
    rate = pad_fade.rate_for(car, CONDITIONS, onset=onset, level_speed=250 * KMH, level_mean=made[250],
                             speed=380 * KMH, mean=made[380])
    assert rate == pytest.approx(0.002, rel=1e-4)


def test_dynamometer_refuses_a_stop_it_cannot_make(car):
    with pytest.raises(InputError, match=r"^initial_speed = 0"):
        vehicle.dynamometer_stop(car, 0.0, **CONDITIONS)


def test_train_stop_reports_the_faded_stop_average_and_the_surface_temperature():
    # one car from 300 km/h with pads fading from 100 K above the ambient: the stop average falls
    # below the same run's without fading, and the stop lengthens
    scenario = simulation.emergency_scenario("crh380a-8", 300 * KMH)
    runs = {}
    for rate in (0.0, 0.002):
        train = vehicle.load_train("crh380a-8")
        for car in train.cars:
            car.c.brake.pad.fade_onset, car.c.brake.pad.fade_rate = AMBIENT + 100.0, rate
        runs[rate] = simulation.run(scenario, cars=1, record=False, train=train).kpis
    cold, hot = runs[0.0], runs[0.002]
    assert hot["max_disc_surface_temperature_c"] > hot["max_disc_temperature_c"]
    assert cold["mean_pad_friction"] > hot["mean_pad_friction"] > 0.3
    assert hot["stopping_distance_m"] > cold["stopping_distance_m"]
    assert np.isfinite(hot["max_disc_surface_temperature_c"])
