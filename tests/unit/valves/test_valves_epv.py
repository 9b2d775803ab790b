"""EP valve: steady control pressure against an independent static force balance, hysteresis from
sealing friction, oscillation detection, bad force tables."""

import math

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator
from scipy.optimize import brentq

from railbrake import valves
from railbrake.errors import InputError
from railbrake.pneumatics import orifice_mass_flow
from railbrake.units import BAR

MM = 1e-3


def static_control_pressure(p, current, piston_x=0.0):
    """Static balance of the EPV with the relay piston resting at piston_x within its lap (both
    seats shut, no flow):
    armature: F_sol(g0 - x, I) = preload + k x + (p_pilot - p_a) A_nozzle;
    pilot:    flow in through the pilot orifice = flow out through the flapper gap (travel - x);
    piston:   (p_pilot - p_a) A = (p_c - p_a) A + preload + k piston_x.
    Solved here with scipy, independently of the dynamic model."""
    a, k, pa, cd = p["armature"], p["piston"], p["ambient_pa"], p["discharge_coefficient"]
    gap, cur, force = valves.read_force_table(p["solenoid_table"])
    f_sol = RegularGridInterpolator((gap, cur), force)
    ps = pa + p["supply_bar"] * BAR
    d_n = p["nozzle_diameter_mm"] * MM
    a_n, travel = math.pi * d_n ** 2 / 4, a["flapper_travel_mm"] * MM
    a_pilot = math.pi * (p["pilot_orifice_diameter_mm"] * MM) ** 2 / 4

    def pilot_pressure(x):  # flow continuity through the pilot chamber
        curtain = min(math.pi * d_n * (travel - x), a_n)
        return brentq(lambda pp: orifice_mass_flow(ps, 293.15, pp, a_pilot, cd)
                      - orifice_mass_flow(pp, 293.15, pa, curtain, cd), pa * 1.0000001, ps)

    def armature(x):
        return (f_sol([[a["airgap_mm"] * MM - x, current]])[0] - a["spring_preload"] - a["spring_rate"] * x
                - (pilot_pressure(x) - pa) * a_n)

    x = brentq(armature, 0.0, travel * (1 - 1e-6))
    area = math.pi * (k["diameter_mm"] * MM) ** 2 / 4
    spring = k["spring_preload"] + k["spring_rate"] * piston_x
    return pa + ((pilot_pressure(x) - pa) * area - spring) / area


@pytest.mark.parametrize("current", [0.6, 0.9])
def test_steady_control_pressure_equals_static_force_balance(current):
    p = valves.load_epv({"piston": {"friction": 0.0}})
    res = valves.epv_step(p, current=current, t_end=1.5)
    gauge = res["control"].p[-1] - p["ambient_pa"]
    x = res["piston"].x[-1]
    # At rest with both seats shut.
    assert abs(x) <= 1.001 * p["seat_lap_mm"] * 1e-3 and abs(res["piston"].v[-1]) < 1e-6
    expected = static_control_pressure(p, current, x) - p["ambient_pa"]
    assert gauge == pytest.approx(expected, rel=0.01)


def test_hysteresis_grows_with_friction_and_vanishes_without():
    h = [valves.epv_characteristic({"piston": {"friction": f}}).hysteresis_bar for f in (0.0, 0.5, 1.0, 2.0)]
    assert all(b > a for a, b in zip(h, h[1:])), h
    # the friction band 2 F / A_piston in pressure, plus the seat lap's dead band
    p = valves.load_epv()
    area = math.pi * (p["piston"]["diameter_mm"] * MM) ** 2 / 4
    lap_band = 2 * p["piston"]["spring_rate"] * p["seat_lap_mm"] * MM / area / BAR
    # at most the full friction band 2 F / A; the regularised friction (tanh(v / friction_velocity))
    # is not fully mobilised at the slow piston speeds of a quasi-static ramp
    assert 0.3 * 2 * 2.0 / area / BAR < h[3] - h[0] <= 1.02 * 2 * 2.0 / area / BAR
    # without friction only the lap's dead band and the lag are left; a slower ramp shrinks the lag
    slow = valves.epv_characteristic({"piston": {"friction": 0.0}}, ramp_time=400.0)
    assert slow.hysteresis_bar < lap_band + 0.005 < h[2]


def test_too_fast_a_ramp_reports_lag_not_hysteresis():
    fast = valves.epv_characteristic(ramp_time=2.0)
    assert not fast.quasi_static and fast.hysteresis_bar is None and fast.lag_bar > 0.05
    assert "too fast" in fast.note
    assert valves.epv_characteristic().quasi_static


def test_default_characteristic_meets_the_trains_it_serves():
    """Monotone rising branch, 1.1 x the largest emergency target of the presets at the rated
    current, no residual pressure at 0 A, hysteresis from friction within 0-0.3 bar, and the ramp
    starts at the 0 A equilibrium (no start-up transient)."""
    from railbrake import sizing, vehicle
    targets = []
    for name in ("crh380a-8", "crh380al-16", "velaro-8"):
        r = sizing.target_pressure(vehicle.load_train(name), sizing.load_profile("emergency"))
        targets += [np.max(r.gauge_bar(r.p_motor)), np.max(r.gauge_bar(r.p_trailer))]
    c = valves.epv_characteristic()
    assert c.max_drop_up_bar <= 0.02 and np.all(np.diff(c.pressure_up) >= -0.02)
    assert c.pressure_up.max() >= 1.1 * max(targets)
    assert abs(c.pressure_down[-1]) <= 0.05 and abs(c.pressure_up[0]) <= 0.005
    assert c.quasi_static and 0.0 < c.hysteresis_bar < 0.3
    assert np.all(c.pressure_up[c.current_up < 0.2] < 0.005)   # no start-up transient


def test_currents_above_the_rating_are_refused():
    with pytest.raises(InputError, match=r"current = 1.2 A: must lie in \[0, 1\] A"):
        valves.epv_step(current=1.2)


@pytest.mark.parametrize("current", [0.5, 0.7, 0.9, 1.0])
def test_step_responses_over_the_rated_range_are_stable(current):
    p = valves.load_epv()
    res = valves.epv_step(p, current=current, t_end=1.5)
    m = valves.step_metrics(res.time, (res["control"].p - p["ambient_pa"]) / BAR)
    assert not valves.oscillates(res.time, res["control"].p)
    assert m["overshoot_bar"] < 0.2 and m["settling_time_s"] < 1.0


def test_step_from_a_held_current_starts_at_rest():
    p = valves.load_epv()
    res = valves.epv_step(p, current=0.9, start_current=0.7, t_end=1.0)
    before = res["control"].p[res.time < 0.05]
    assert np.ptp(before) < 0.002 * BAR and before[0] > p["ambient_pa"] + 1.0 * BAR


def test_underdamped_flapper_is_detected():
    """A flapper stage with too little damping hunts (the pilot pressure keeps swinging)."""
    steady = valves.epv_step(current=0.8, t_end=1.0)
    assert not valves.oscillates(steady.time, steady["pilot"].p)
    weak = valves.epv_step({"armature": {"spring_rate": 1500.0, "damping": 2.0}}, current=0.8, t_end=1.0)
    assert valves.oscillates(weak.time, weak["pilot"].p)


def test_unsorted_force_table_is_refused(tmp_path):
    lines = (valves.params.DATA / "epv_solenoid_force.csv").read_text().splitlines()
    rows = [i for i, line in enumerate(lines) if line and line[0].isdigit()]
    lines[rows[1]], lines[rows[2]] = lines[rows[2]], lines[rows[1]]
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines))
    with pytest.raises(InputError, match="sorted by airgap"):
        valves.read_force_table(path)
    with pytest.raises(InputError, match="unknown parameter 'armatur'"):
        valves.load_epv({"armatur": {}})


def _table(tmp_path, rows, currents="0,0.5,1.0"):
    path = tmp_path / "t.csv"
    path.write_text(f"airgap_mm,{currents}\n" + "\n".join(rows) + "\n")
    return path


def test_force_table_falling_with_current_or_short_of_the_rating_is_refused(tmp_path):
    with pytest.raises(InputError, match=r"must not fall with current"):
        valves.read_force_table(_table(tmp_path, ["0.2,0,1.0,0.9", "0.4,0,0.5,0.8"]))
    short = _table(tmp_path, ["0.2,0,0.4,0.9", "0.4,0,0.3,0.6"], "0,0.4,0.8")
    with pytest.raises(InputError, match=r"cover the rated current current_max_a = 1 A"):
        valves.read_force_table(short, rated_current=1.0)
    with pytest.raises(InputError, match="cover the rated current"):
        valves.epv_step({"solenoid_table": str(short)}, current=0.5)
