"""Vehicle laws against hand calculations (TB/T 1407.2, EN 14531-1; docs/references.md)."""

import numpy as np
import pytest

from railbrake import vehicle
from railbrake.errors import InputError

P_ATM = vehicle.P_ATM


def test_caliper_force_follows_en14531():
    # EN 14531 [P]: F = (p_C A_C - F_spring) i eta, here (4 bar * 0.02 m^2 - 700 N) * 2.8 * 0.95
    force = vehicle.caliper_pad_force(P_ATM + 4e5, 0.02, 700.0, 2.8, 0.95)
    assert force == pytest.approx((4e5 * 0.02 - 700.0) * 2.8 * 0.95, rel=1e-12)
    assert vehicle.caliper_pad_force(P_ATM + 0.3e5, 0.02, 700.0, 2.8, 0.95) == 0.0  # spring wins


def test_lever_ratio_zero_is_refused_by_name():
    with pytest.raises(InputError, match=r"^lever_ratio = 0"):
        vehicle.caliper_pad_force(P_ATM + 4e5, 0.02, 700.0, 0.0, 0.95)


def test_sintered_pad_friction_rises_below_100_kmh():
    # [T] README s. 2: mean 0.35, rising at low speed; default parabola to 0.42 at standstill
    v = np.array([0.0, 50.0, 100.0, 200.0, 350.0]) / 3.6
    expected = [0.42, 0.35 + 0.07 * 0.25, 0.35, 0.35, 0.35]
    assert vehicle.pad_friction_sintered(v) == pytest.approx(expected, rel=1e-12)


def test_equivalent_mass_is_sum_of_j_over_r_squared():
    wheelsets = [(0.43, 120.0, 11e3), (0.43, 161.7, 14e3), (0.46, 150.0, 15e3)]
    expected = sum(j / r**2 for r, j, _ in wheelsets)
    assert vehicle.equivalent_rotating_mass(wheelsets) == pytest.approx(expected, rel=1e-12)
    with pytest.raises(InputError, match=r"wheelsets\[0\] axle_load = -1"):
        vehicle.equivalent_rotating_mass([(0.43, 120.0, -1.0)])


def test_coupler_slack_then_spring_and_damper():
    k, k3, c, slack = 2e7, 5e9, 3e4, 0.03
    assert vehicle.coupler_force(0.014, 0.5, slack, k, k3, c) == 0.0  # inside the free play
    e = 0.02 - slack / 2
    assert vehicle.coupler_force(0.02, 0.1, slack, k, k3, c) == pytest.approx(k * e + k3 * e**3 + c * 0.1)
    assert vehicle.coupler_force(-0.02, -0.1, slack, k, k3, c) == pytest.approx(-(k * e + k3 * e**3 + c * 0.1))
    with pytest.raises(InputError, match=r"^stiffness = 0"):
        vehicle.coupler_force(0.02, 0.0, slack, 0.0)
