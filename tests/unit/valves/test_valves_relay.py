"""Relay valve with membrane, WSP hold/vent valves and brake cylinder."""

import numpy as np
import pytest

from railbrake import valves
from railbrake.units import BAR


def test_output_follows_control_pressure_by_membrane_balance():
    """Steady state at lap: (p_c - p_a) A_eff(0) = (p_o - p_a) A_eff(0) + preload, A_eff = dV/dx."""
    p = valves.load_relay()
    res = valves.relay_step(p, t_end=1.5)
    m = p["membrane"]
    a_eff = np.interp(0.0, np.array(m["x_mm"]) * 1e-3, np.gradient(np.array(m["volume_cm3"]) * 1e-6,
                                                                    np.array(m["x_mm"]) * 1e-3))
    expected = p["control_step_bar"] * BAR - m["spring_preload"] / a_eff
    assert res["cylinder"].p[-1] - p["ambient_pa"] == pytest.approx(expected, rel=0.02)
    assert res["cylinder"].x[-1] > 0.99 * p["cylinder"]["stroke_mm"] * 1e-3


def test_wsp_vent_releases_cylinder_after_its_delay():
    p = valves.load_relay()
    res = valves.relay_step(p, t_end=1.5, hold=[(0.8, 1.0), (0.8, 0.0)], vent=[(0.8, 0.0), (0.8, 1.0)])
    i = np.searchsorted(res.time, 0.8 + p["wsp"]["response_delay_s"] - 1e-9)
    assert res["wsp_vent"].mdot[i - 1] == 0.0
    assert res["cylinder"].p[-1] - p["ambient_pa"] < 0.1 * BAR < res["cylinder"].p[i] - p["ambient_pa"]
