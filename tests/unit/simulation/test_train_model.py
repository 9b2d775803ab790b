"""The train model against the sizing it is built from, conservation laws and the measured stop.

- The BCU's per-car tables invert the same brake law as railbrake.sizing: at their nodes they
  give the sizing's target pressure exactly.
- run vs stopping-distance (EN 14531-1 integration, its defaults: the build-up measured toward the
  first step's demand, issue 38) within 3 % for every preset, both load cases (normal, crush) and
  every 20 km/h from 160 km/h to its maximum on dry level rail; the distance never falls as the
  initial speed rises (5 km/h steps).
- CRH380A-8 from 300 km/h on dry rail: within 10 % of the measured 3760 m (its emergency profile
  is calibrated on that figure: a consistency check, see data/profiles/emergency-crh380a.yaml).
- Energy: the friction brake energy equals the kinetic energy less the work of the running
  resistance; the parameters of the train file reach the C core.
"""

import numpy as np
import pytest

from railbrake import _core, sizing, simulation, vehicle
from railbrake.units import KMH

PRESETS = ["crh380a-8", "crh380al-16", "velaro-8"]


def test_bcu_tables_give_the_sizing_target_pressure():
    sc = simulation.emergency_scenario("crh380a-8", 300 * KMH)
    train = simulation.scenario_train(sc)
    plant = simulation.plant_params(sc, 8, train=train)
    bcu = simulation.bcu_params(plant, sc, True, train)
    profile, ed = sizing.brake_step(train, "emergency")
    assert not ed and bcu.ed_in_emergency == 0 and bcu.ed_in_service == 1
    for car in (0, 1):   # trailer, motor
        table = bcu.emergency_force[car]
        speed = np.array(table.speed[:table.n])
        per_n = np.array(bcu.pressure_per_newton[car].value[:table.n])
        pressure = bcu.pressure_offset[car] + per_n * np.array(table.value[:table.n])
        sized = sizing.target_pressure(train, profile, speeds=speed, ed=False)
        expected = sized.p_motor if train.cars[car].motor else sized.p_trailer
        assert pressure == pytest.approx(expected, rel=1e-9)


def _stop(train: str, kmh: float, load: str | None = None):
    r = simulation.run(simulation.emergency_scenario(train, kmh * KMH, max_time=400.0, load=load))
    ta, tb = simulation.response_times(r)
    calc = sizing.stopping_distance(kmh * KMH, train=vehicle.load_train(train, load or True), delay=ta, build_up=tb)
    return r, calc, ta, tb


def _sweep_speeds(train, step: float) -> list:
    """km/h from 160 to the train's maximum every `step`, the maximum included."""
    top = train.max_speed / KMH
    return [*np.arange(160.0, top - 1e-6, step), top]


@pytest.mark.slow
@pytest.mark.parametrize("train", vehicle.preset_names())
def test_run_and_stopping_distance_agree_within_3_percent_at_every_speed(train):
    # issue 38: every 20 km/h from 160 km/h to the maximum, both load cases, dry rail; the
    # stopping-distance calculation with its defaults (the build-up measured toward the first
    # step's demand on a short run of the plant), the runs in one batch of the C core
    for load in ("normal", "crush"):
        t = vehicle.load_train(train, load)
        speeds = _sweep_speeds(t, 20.0)
        runs = simulation.run_batch([simulation.emergency_scenario(train, v * KMH, load=load) for v in speeds])
        for v, kpis in zip(speeds, runs):
            calc = simulation.stopping_distance(v * KMH, train=t)
            assert calc.simulated_response and kpis["stopped"] and kpis["wheel_lock_events"] == 0
            assert calc.distance == pytest.approx(kpis["stopping_distance_m"], rel=0.03), (train, load, v)


@pytest.mark.slow
@pytest.mark.parametrize("train", vehicle.preset_names())
def test_stopping_distance_never_falls_as_the_initial_speed_rises(train):
    # every 5 km/h, so that the speeds cross the steps and ramps of the emergency profiles
    for load in ("normal", "crush"):
        t = vehicle.load_train(train, load)
        distances = [simulation.stopping_distance(v * KMH, train=t).distance for v in _sweep_speeds(t, 5.0)]
        assert np.all(np.diff(distances) >= 0.0), (train, load, distances)


def test_crh380a_from_300_within_10_percent_of_the_measured_3760_m():
    r, calc, _, _ = _stop("crh380a-8", 300)
    assert r.kpis["stopping_distance_m"] == pytest.approx(3760.0, rel=0.10)
    assert r.kpis["stopping_distance_m"] == pytest.approx(calc.distance, rel=0.03)


def test_brake_energy_is_kinetic_energy_less_resistance_work():
    sc = simulation.emergency_scenario("crh380a-8", 200 * KMH)
    r = simulation.run(sc)
    train = simulation.scenario_train(sc)
    v = r.outputs["speed"]
    kinetic = 0.5 * (train.mass + train.rotating_mass) * (200 * KMH) ** 2
    power = train.running_resistance(v) * v
    resistance = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(r.time)))
    # what is left: creep (slip) losses at the rails and the coupler damping, well below 1 %
    assert r.kpis["brake_energy_mj"] * 1e6 == pytest.approx(kinetic - resistance, rel=0.01)
    hottest = max(r.outputs[n].max() for n in r.axle_channels("disc_temperature"))
    assert r.kpis["max_disc_temperature_c"] == pytest.approx(hottest - 273.15, abs=0.5)
    assert r.kpis["max_disc_temperature_c"] > 100.0


def test_tripled_cylinder_volume_with_set_reaches_the_c_core():
    """--set of the cylinder's stroke and dead volume (volume = area x stroke + dead volume, per
    disc) triples the volume the plant gets; more air is drawn and the brake builds up later."""
    from railbrake.resolve import resolve
    sets = ["train.car_types.motor.cylinder.stroke_mm=45", "train.car_types.motor.cylinder.dead_volume_l=0.75",
            "train.car_types.trailer.cylinder.stroke_mm=45", "train.car_types.trailer.cylinder.dead_volume_l=0.75",
            "initial_speed=200 km/h"]
    base = resolve("emergency-250-dry", cars=2, sets=sets[-1:])
    big = resolve("emergency-250-dry", cars=2, sets=sets)
    plant = simulation.plant_params(big.scenario, 2, train=big.train)
    assert plant.car[0].cylinder_volume == pytest.approx(3 * 3 * (0.020 * 0.015 + 0.25e-3))  # trailer, 3 discs
    assert plant.car[1].cylinder_volume == pytest.approx(3 * 2 * (0.020 * 0.015 + 0.25e-3))  # motor, 2 discs
    r0, r1 = simulation.run(base, record=False), simulation.run(big, record=False)
    assert r1.kpis["air_drawn_kg"] > 1.5 * r0.kpis["air_drawn_kg"]
    assert r1.kpis["stopping_time_s"] > r0.kpis["stopping_time_s"] + 0.1
    assert r1.kpis["air_balance_error"] < 1e-9


def test_load_case_changes_the_mass_and_the_pressure_not_the_distance():
    tare = vehicle.load_train("crh380a-8", "tare")
    crush = vehicle.load_train("crh380a-8", "crush")
    assert tare.mass == pytest.approx(388.4e3 - 8 * 5.0e3) and crush.mass == pytest.approx(388.4e3 + 8 * 4.0e3)
    light = sizing.target_pressure(tare, speeds=[100 * KMH]).p_trailer[0]
    heavy = sizing.target_pressure(crush, speeds=[100 * KMH]).p_trailer[0]
    assert heavy > light   # load-weighed
    runs = [simulation.run(simulation.emergency_scenario("crh380a-8", 200 * KMH, load=case), cars=2,
                           record=False) for case in ("tare", "crush")]
    assert runs[0].kpis["stopping_distance_m"] == pytest.approx(runs[1].kpis["stopping_distance_m"], rel=0.01)


def test_gradient_lengthens_a_downhill_stop_as_the_calculation_does():
    from railbrake.scenario import parse
    text = """schema: railbrake.scenario/1
name: downhill
train: {preset: crh380a-8, cars: 8}
initial_speed: 200 km/h
demand: [{time: 0 s, emergency: true}]
track: {gradients: [{start: 0 m, gradient: -12 ‰}]}
"""
    r = simulation.run(parse(text, "downhill"))
    level = simulation.run(simulation.emergency_scenario("crh380a-8", 200 * KMH))
    ta, tb = simulation.response_times(r)
    calc = sizing.stopping_distance(200 * KMH, train="crh380a-8", delay=ta, build_up=tb, gradient=-0.012)
    assert r.kpis["stopping_distance_m"] > 1.05 * level.kpis["stopping_distance_m"]
    assert r.kpis["stopping_distance_m"] == pytest.approx(calc.distance, rel=0.03)


def test_piecewise_gradient_of_the_run_and_the_calculation_agree():
    from railbrake.scenario import parse
    text = """schema: railbrake.scenario/1
name: descent
train: {preset: crh380a-8}
initial_speed: 200 km/h
demand: [{time: 0 s, emergency: true}]
track: {gradients: [{start: 0 m, gradient: 5 ‰}, {start: 600 m, gradient: -15 ‰}]}
"""
    r = simulation.run(parse(text, "descent"))
    ta, tb = simulation.response_times(r)
    calc = sizing.stopping_distance(200 * KMH, train="crh380a-8", delay=ta, build_up=tb,
                                    gradients=[(0.0, 0.005), (600.0, -0.015)])
    assert r.kpis["stopping_distance_m"] == pytest.approx(calc.distance, rel=0.03)


def test_compressors_of_the_train_file_feed_the_pipe():
    sc = simulation.emergency_scenario("crh380al-16", 300 * KMH)
    plant = simulation.plant_params(sc, 16)
    assert plant.n_compressors == 4 and list(plant.compressor_position[:4]) == [0, 7, 8, 15]
    assert plant.governor_on == pytest.approx(plant.atmosphere + 7.5e5)
    assert _core.MAX_COMPRESSORS == 4
