"""Orifice law (reference README sec. 4: ISO 6358, ideal nozzle b = 0.528) through the Python API."""

import math

import numpy as np
import pytest

from railbrake.errors import InputError
from railbrake.pneumatics import AIR_GAMMA as G, AIR_R as R, orifice_mass_flow, sonic_conductance


def nozzle_choked(p1, T1, cd_area):
    """Closed-form choked flow of an ideal nozzle."""
    return cd_area * p1 * math.sqrt(G / (R * T1)) * (2 / (G + 1)) ** ((G + 1) / (2 * (G - 1)))


def test_choked_flow_equals_nozzle_formula():
    assert orifice_mass_flow(8e5, 300.0, 1e5, area=2e-5, discharge_coefficient=0.7) == \
        pytest.approx(nozzle_choked(8e5, 300.0, 1.4e-5), rel=1e-12)


def test_iso_form_matches_area_form():
    c = sonic_conductance(2e-5, 0.7)
    p_down = np.linspace(1e5, 8e5, 15)
    np.testing.assert_allclose(orifice_mass_flow(8e5, 300.0, p_down, sonic_conductance=c),
                               orifice_mass_flow(8e5, 300.0, p_down, area=2e-5, discharge_coefficient=0.7),
                               rtol=1e-12)


def test_continuous_at_critical_ratio_and_antisymmetric():
    b = 0.528
    below, above = orifice_mass_flow(5e5, 293.15, [5e5 * b * (1 - 1e-9), 5e5 * b * (1 + 1e-9)], area=1e-6)
    assert above == pytest.approx(below, rel=1e-7)
    p = np.linspace(2e5, 9e5, 8)
    np.testing.assert_allclose(orifice_mass_flow(5e5, 293.15, p, area=1e-6),
                               -orifice_mass_flow(p, 293.15, 5e5, area=1e-6), rtol=1e-14)


def test_zero_flow_and_finite_slope_at_equal_pressures():
    assert orifice_mass_flow(5e5, 293.15, 5e5, area=1e-6) == 0.0
    slope = orifice_mass_flow(5e5, 293.15, 5e5 - 1.0, area=1e-6)
    assert 0 < slope < 1e-6  # kg/s per Pa: finite


@pytest.mark.parametrize("kwargs, word", [
    ({"p_up": 5e5, "area": -1e-6}, "area"),
    ({"p_up": 0.0, "area": 1e-6}, "p_up = 0"),   # the caller's name, not the core's p1
    ({"p_up": 5e5, "area": 1e-6, "discharge_coefficient": 1.5}, "discharge_coefficient"),
])
def test_bad_input_is_named(kwargs, word):
    p_up = kwargs.pop("p_up")
    with pytest.raises(InputError, match=word):
        orifice_mass_flow(p_up, 293.15, 1e5, **kwargs)
