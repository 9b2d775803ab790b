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
    h = [valves.epv_characteristic({"piston": {"friction": f}}).hysteresis_bar for f in (0.0, 1.0, 2.0, 4.0)]
    assert all(b > a for a, b in zip(h, h[1:])), h
    # Without friction what is left is the lag behind the ramp: it shrinks with a slower ramp.
    slow = valves.epv_characteristic({"piston": {"friction": 0.0}}, ramp_time=200.0).hysteresis_bar
    assert slow < 0.01 < h[2]


def test_oscillating_design_is_detected():
    """An armature spring weaker than the solenoid's negative magnetic stiffness hunts."""
    steady = valves.epv_step(current=0.8, t_end=1.0)
    assert not valves.oscillates(steady.time, steady["control"].p)
    weak = valves.epv_step({"armature": {"spring_rate": 1500.0}}, current=0.8, t_end=1.0)
    assert valves.oscillates(weak.time, weak["control"].p)


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


def test_characteristic_rises_with_current():
    c = valves.epv_characteristic()
    assert c.pressure_up[-1] > 2.0 and np.all(np.diff(c.pressure_up[c.current_up > 0.4]) > -0.02)
