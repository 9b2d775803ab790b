"""The detailed train model itself: air mass conservation, static valve force balances in closed
form, the EP drive's static inverse, the no-demand limit (free rolling against the running
resistance), and bad input.

References: ideal gas and orifice laws (ISO 6358-1:2013; docs/pneumatics.md);
Newton's second law for the valve bodies at rest (spring, preload, pressure faces, Coulomb
friction, solenoid force table); Davis running resistance A + B v + C v^2 with the rotating mass
J / r^2 per wheelset (TB/T 1407.2; docs/simulation.md).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import PchipInterpolator, RegularGridInterpolator

from railbrake import scenario as scenarios
from railbrake.errors import InputError
from railbrake.simulation import plant_params
from railbrake.simulation import detailed as D

ATM = 1.01325e5
BAR = 1e5


@pytest.mark.parametrize("name, cars", [("emergency-250-dry", 1),
                                        # 65 s under the sanitizers, which the dry case covers
                                        pytest.param("emergency-300-heavy-rain", 1, marks=pytest.mark.slow),
                                        pytest.param("emergency-250-dry", 8, marks=pytest.mark.slow)])
def test_air_mass_is_conserved_across_the_train(compared, name, cars):
    # in volumes + vented - compressed = initial, to round-off; 8 cars: air flows along the MR
    # pipe into every car's supply reservoir
    det = compared(name, cars).detailed
    assert det.kpis["air_balance_error"] < 1e-10
    assert det.kpis["air_consumed_kg"] > 0.0
    if name == "emergency-300-heavy-rain":   # hundreds of WSP vents draw the MR below 8.5 bar
        assert det.outputs["compressor_on"].max() == 1.0


def _valves_closed_form(current):
    """Pressures (Pa) of the nozzle chamber, control and relay output from each body's force
    balance at rest, given the positions the model settled at."""
    v = D.load_valves()
    e, a, k, m = v["epv"], v["epv"]["armature"], v["epv"]["piston"], v["relay"]["membrane"]
    run = D.valve_run(current, t_end=4.0)
    gap, cur, force = D.solenoid_table(v)
    table = RegularGridInterpolator((gap, cur), force)
    nozzle = math.pi * (e["nozzle_diameter_mm"] * 1e-3) ** 2 / 4
    x = run["armature"]
    solenoid = table([[a["airgap_mm"] * 1e-3 - x, current]])[0]
    pilot = ATM + (solenoid - a["spring_preload"] - a["spring_rate"] * x) / nozzle
    piston = math.pi * (k["diameter_mm"] * 1e-3) ** 2 / 4
    piston_gap = (k["spring_preload"] + k["spring_rate"] * run["piston"]) / piston   # pilot - control
    a_eff = PchipInterpolator(np.array(m["x_mm"]) * 1e-3, np.array(m["volume_cm3"]) * 1e-6).derivative()
    membrane_gap = (m["spring_preload"] + m["spring_rate"] * run["membrane"]) / a_eff(run["membrane"])
    return run, pilot, piston_gap, k["friction"] / piston, membrane_gap


@pytest.mark.parametrize("current", [0.7, 0.76, 0.82])
def test_static_epv_and_relay_match_the_closed_form_force_balance(current):
    run, pilot, piston_gap, friction_band, membrane_gap = _valves_closed_form(current)
    assert run["pilot"] == pytest.approx(pilot, abs=0.01 * BAR)
    # the piston rests anywhere inside its friction band
    assert abs(run["pilot"] - run["control"] - piston_gap) <= friction_band + 0.002 * BAR
    assert run["control"] - run["relay"] == pytest.approx(membrane_gap, abs=0.005 * BAR)
    assert run["cylinder"] == pytest.approx(run["relay"], abs=0.001 * BAR)   # hold valve open, no flow
    assert run["control"] > ATM + 1.0 * BAR


@pytest.mark.parametrize("pressure_bar", [2.0, 3.5, 5.5])
def test_ep_drive_static_inverse_gives_the_demanded_pressure(pressure_bar):
    # the current from the static inverse, held, settles at the demand within 1.5 %: the inverse
    # takes the piston at mid-lap and the flapper at rest (it keeps a small flutter)
    current = D.epv_current(pressure_bar * BAR)
    assert 0.0 < current <= D.load_valves()["epv"]["current_max_a"]
    run = D.valve_run(current, t_end=4.0)
    assert run["control"] == pytest.approx(pressure_bar * BAR, rel=0.015)


def test_ep_drive_refuses_what_the_valve_cannot_reach():
    with pytest.raises(InputError, match="current_max"):
        D.epv_current(5.0 * BAR, valves=D.load_valves({"epv": {"current_max_a": 0.5}}))
    with pytest.raises(InputError, match="not below the supply"):
        D.epv_current(9.4 * BAR)


def test_no_demand_no_pressure_and_free_rolling_against_resistance(tmp_path):
    path = tmp_path / "coast.yaml"
    path.write_text("schema: railbrake.scenario/1\nname: coast\ntrain: {preset: crh380a-8}\n"
                    "initial_speed: 250 km/h\ndemand:\n  - {time: 0 s, service: 0}\n"
                    "adhesion: {condition: dry-medium}\nstop: {speed: 0.05 m/s, max_time: 20 s}\n"
                    "coast: true\nsource: test\n")
    det = D.run_detailed(path, cars=1)
    for name in det.axle_channels("cylinder"):
        assert np.max(np.abs(det.outputs[name] - ATM)) < 1e-3 * BAR
    # closed form: (m + 4 J / r^2) dv/dt = -(A + B v + C v^2)
    p = plant_params(scenarios.load(path), 1)
    car, r = p.car[0].vehicle, p.resistance
    mass = car.mass + 4 * car.wheelset.inertia / car.wheelset.wheel_radius**2
    ref = solve_ivp(lambda t, v: -(r.A + r.B * v + r.C * v * v) / mass, (0, det.time[-1]), [250 / 3.6],
                    rtol=1e-10, atol=1e-10)
    assert det.outputs["speed"][-1] == pytest.approx(ref.y[0, -1], rel=2e-4)
    assert det.outputs["speed"][-1] < 250 / 3.6 - 0.5   # it did slow down


def test_bad_valve_parameter_names_the_field():
    with pytest.raises(InputError, match="detailed.piston_mass"):
        D.detailed_params(D.load_valves({"epv": {"piston": {"mass": -1.0}}}))
    with pytest.raises(InputError, match="unknown parameter"):
        D.load_valves({"epv": {"pistn": {}}})


def test_a_scenario_fault_acts_from_its_start_time():
    # fault-vent-valve-stuck: car 3 axle 2's vent valve stuck open from 2 s (the fault kinds'
    # effects: test_detailed_faults.py); shortened to 3 cars from 80 km/h
    det = D.run_detailed(scenarios.load("fault-vent-valve-stuck").with_(initial_speed="80 km/h"), 3)
    vent, t = det.outputs["vent_c3a2"], det.time
    assert vent[t < 1.99].max() == 0.0 and vent[t > 2.05].min() == 1.0
    # the relay feeds it through the open hold port as the vent port lets it out (0.7 bar against 2.6)
    stuck, sound = (det.outputs[f"cylinder_c3a{a}"][t > 3.0].max() - ATM for a in (2, 1))
    assert stuck < 0.5 * sound and sound > 2.0 * BAR


@pytest.mark.slow
def test_the_trains_compressors_feed_the_line_as_in_the_plant(compared):
    # crh380al-16 on 8 cars: compressors on cars 1 and 8, the second delivering into its car's MR
    # pipe with its own governor (plant_train.c). Delivering both into the main reservoir, as the
    # detailed model once did, drew the pipe end 0.3 to 0.45 bar further below the MR than in the
    # plant at 60 to 100 s; with the same compressors the drops along the line agree
    c = compared("emergency-300-heavy-rain", 8)
    t = np.arange(40.0, 140.0, 10.0)

    def drop(r):
        return np.interp(t, r.time, r.outputs["main_reservoir"] - r.outputs["pipe_end"])

    assert c.detailed.outputs["compressor_on"][np.searchsorted(c.detailed.time, 40.0)] == 1.0
    assert np.max(np.abs(drop(c.rt) - drop(c.detailed))) < 0.1 * BAR


def test_air_drawn_from_the_line_is_booked_as_in_the_plant(compared):
    # air drawn = MR and pipes at t = 0 + compressed - MR and pipes now (both models): it starts at
    # 0, never falls below it, and the two models' figures differ by what they vent differently
    # (the same cylinders fill; the detailed EP valve's nozzle also bleeds)
    c = compared("emergency-250-dry", 1)
    rt, det = c.rt.outputs, c.detailed.outputs
    assert det["air_drawn"][0] == pytest.approx(0.0, abs=1e-12) and det["air_drawn"].min() >= -1e-12
    assert det["air_drawn"][-1] > 0.0
    vented_apart = abs(det["air_vented"][-1] - rt["air_vented"][-1])
    assert abs(det["air_drawn"][-1] - rt["air_drawn"][-1]) <= vented_apart + 0.1 * rt["air_drawn"][-1]
