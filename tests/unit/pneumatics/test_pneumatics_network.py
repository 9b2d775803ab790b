"""Network simulations against conservation laws and closed forms of tank discharge and filling.

Closed forms (ideal gas, reference README sec. 4; choked orifice mdot = G p / sqrt(T) with
G = Cd A sqrt(gamma/R) (2/(gamma+1))^((gamma+1)/(2(gamma-1)))):
- isothermal discharge: p = p0 exp(-t / tau), tau = V / (G R sqrt(T));
- adiabatic discharge: p / p0 = (1 + (gamma-1)/2 t / tau0)^(-2 gamma/(gamma-1)), tau0 = V/(G R sqrt(T0));
- adiabatic filling from a supply at Ts: p = p0 + gamma R Ts mdot t / V with constant mdot.
"""

import math

import numpy as np
import pytest

from railbrake.errors import InputError
from railbrake.pneumatics import AIR_GAMMA as GAMMA, AIR_R as R, Network

CV = R / (GAMMA - 1)
AREA, CD = 1e-6, 0.9
G = CD * AREA * math.sqrt(GAMMA / R) * (2 / (GAMMA + 1)) ** ((GAMMA + 1) / (2 * (GAMMA - 1)))


def discharge(heat_transfer):
    net = Network()
    net.add_volume("tank", volume=1e-3, pressure=8e5, temperature=293.15, heat_transfer=heat_transfer)
    net.add_reservoir("atm", pressure=1e5)
    net.add_orifice("out", "tank", "atm", area=AREA, discharge_coefficient=CD)
    return net


def test_isothermal_discharge_through_choked_orifice():
    """A very large wall heat transfer holds T at the wall temperature."""
    res = discharge(heat_transfer=1e3).simulate(t_end=1.0, n_points=11)
    tau = 1e-3 / (G * R * math.sqrt(293.15))
    np.testing.assert_allclose(res["tank"].p, 8e5 * np.exp(-res.time / tau), rtol=2e-3)
    assert res["tank"].p[-1] / 1e5 > 1 / 0.528  # still choked


def test_adiabatic_discharge_through_choked_orifice():
    res = discharge(heat_transfer=0.0).simulate(t_end=1.0, n_points=11)
    tau0 = 1e-3 / (G * R * math.sqrt(293.15))
    expected = 8e5 * (1 + (GAMMA - 1) / 2 * res.time / tau0) ** (-2 * GAMMA / (GAMMA - 1))
    np.testing.assert_allclose(res["tank"].p, expected, rtol=1e-4)
    # Isentropic expansion: T / T0 = (p / p0)^((gamma-1)/gamma).
    np.testing.assert_allclose(res["tank"].T, 293.15 * (res["tank"].p / 8e5) ** ((GAMMA - 1) / GAMMA),
                               rtol=1e-4)


def test_adiabatic_filling():
    net = Network()
    net.add_reservoir("supply", pressure=9e5, temperature=310.0)
    net.add_volume("tank", volume=2e-3, pressure=1e5, temperature=293.15)
    net.add_orifice("fill", "supply", "tank", area=AREA, discharge_coefficient=CD)
    res = net.simulate(t_end=1.0, n_points=11)
    mdot = G * 9e5 / math.sqrt(310.0)
    assert res["tank"].p[-1] < 0.528 * 9e5  # choked throughout
    np.testing.assert_allclose(res["fill"].mdot, mdot, rtol=1e-10)
    np.testing.assert_allclose(res["tank"].p, 1e5 + GAMMA * R * 310.0 * mdot * res.time / 2e-3, rtol=1e-5)


def two_volumes():
    net = Network()
    net.add_volume("a", volume=1e-3, pressure=7e5, temperature=330.0)
    net.add_volume("b", volume=3e-3, pressure=1e5, temperature=280.0)
    net.add_orifice("ab", "a", "b", area=3e-6, discharge_coefficient=0.8)
    return net


def test_closed_network_keeps_mass_and_adiabatic_energy():
    res = two_volumes().simulate(t_end=2.0, n_points=51)
    mass = res["a"].m + res["b"].m
    energy = CV * (res["a"].m * res["a"].T + res["b"].m * res["b"].T)
    np.testing.assert_allclose(mass, mass[0], rtol=1e-12)
    np.testing.assert_allclose(energy, energy[0], rtol=1e-5)
    assert res["a"].p[-1] == pytest.approx(res["b"].p[-1], rel=1e-3)  # equalised


def test_pipe_valve_and_cylinder_network_keeps_mass():
    """A closed circuit with every element kind: the total mass stays constant."""
    net = Network()
    net.add_volume("reservoir", volume=5e-3, pressure=8e5)
    net.add_volume("junction", volume=1e-4, pressure=1e5)
    net.add_pipe("pipe", "reservoir", "junction", length=2.0, diameter=8e-3, pressure=8e5)
    net.add_cylinder("cylinder", piston_area=0.01, stroke=0.01, dead_volume=2e-4, spring_rate=2e4,
                     spring_preload=300.0, piston_mass=2.0)
    net.add_valve("hold", "junction", "cylinder", area=2e-5, opening=[(0.1, 0), (0.1, 1)], delay=0.02)
    res = net.simulate(t_end=1.0, n_points=21)
    mass = sum(res[n].m for n in ("reservoir", "pipe", "junction", "cylinder"))
    np.testing.assert_allclose(mass, mass[0], rtol=1e-10)
    assert 0.01 <= res["cylinder"].x[-1] < 0.0107  # on the end stop (penalty 1e7 N/m)
    assert res["hold"].mdot[2] == 0.0 and res["hold"].mdot[3] > 0.0  # opens at 0.1 s + 0.02 s delay


@pytest.mark.parametrize("build, word", [
    (lambda n: n.add_orifice("o", "a", "b", area=-1e-6), "area"),
    (lambda n: n.add_volume("c", volume=0.0, pressure=1e5), "volume"),
    (lambda n: n.add_volume("c", volume=1e-3, pressure=0.0), "pressure"),
    (lambda n: n.add_volume("a", volume=1e-3, pressure=1e5), "used twice"),
    (lambda n: n.add_orifice("o", "a", "nowhere", area=1e-6), "nowhere"),
])
def test_bad_input_is_named(build, word):
    net = two_volumes()
    with pytest.raises(InputError, match=word):
        build(net)


def test_unconnected_node_is_named():
    net = two_volumes()
    net.add_volume("lonely", volume=1e-3, pressure=1e5)
    with pytest.raises(InputError, match="lonely.*unconnected"):
        net.simulate(t_end=0.1)


def test_moving_boundary_adiabatic_compression():
    """A closed volume halved at a prescribed rate follows the isentrope p V^gamma = const."""
    net = Network()
    net.add_volume("chamber", volume=1e-3, pressure=1e5, volume_rate=-1e-3)
    net.add_body("stop", 1.0, [("chamber", 0.0, 1.0)])  # a zero-area face connects the node
    res = net.simulate(t_end=0.5, n_points=6, rtol=1e-8)
    volume = 1e-3 * (1 - res.time)
    np.testing.assert_allclose(res["chamber"].p, 1e5 * (1e-3 / volume) ** GAMMA, rtol=1e-5)
