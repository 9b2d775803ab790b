"""identify_polach recovers known parameters from noisy synthetic curves and refuses bad data."""

import numpy as np
import pytest

from railbrake.adhesion import identify_polach
from railbrake.contact import PolachParams, default_contact, polach_coefficient
from railbrake.errors import InputError
from railbrake.units import kmh_to_ms

CONTACT = default_contact()


def synthetic(params, speeds_kmh, noise, seed, creep_max=0.3, n=40):
    rng = np.random.default_rng(seed)
    creep = np.tile(np.geomspace(creep_max / 300, creep_max, n), len(speeds_kmh))
    speed = np.repeat(kmh_to_ms(np.array(speeds_kmh, dtype=float)), n)
    clean = polach_coefficient(creep, speed, CONTACT.normal_force, CONTACT, params)
    return creep, clean + rng.normal(0.0, noise, creep.size), speed


@pytest.mark.parametrize("true, speeds", [
    (PolachParams(0.55, 0.40, 0.60, 1.00, 0.40), [20, 60, 120]),   # Polach 2005 dry
    (PolachParams(0.30, 0.40, 0.20, 0.30, 0.10), [40, 120, 250]),  # Polach 2005 wet
])
def test_fit_recovers_known_parameters(true, speeds):
    creep, measured, speed = synthetic(true, speeds, noise=0.004, seed=7)
    fit = identify_polach(creep, measured, speed, CONTACT)
    for name, value in true.as_dict().items():
        estimate = getattr(fit.params, name)
        # Within 4 standard deviations, and the uncertainty itself is informative (< 25 %).
        assert abs(estimate - value) < 4 * fit.std[name] + 1e-3, name
        assert fit.std[name] < 0.25 * value, name
    assert fit.rms == pytest.approx(0.004, rel=0.25)
    assert fit.residuals.shape == creep.shape


def test_fit_works_on_braking_data_with_negative_creep():
    true = PolachParams(0.30, 0.40, 0.20, 0.30, 0.10)
    creep, measured, speed = synthetic(true, [40, 120, 250], noise=0.003, seed=3)
    fit = identify_polach(-creep, -measured, speed, CONTACT)
    assert fit.params.mu0 == pytest.approx(0.30, rel=0.05)


def test_fit_refuses_too_few_points():
    creep, measured, speed = synthetic(PolachParams(0.3, 0.4, 0.2, 0.3, 0.1), [60], 0.0, 1, n=6)
    with pytest.raises(InputError, match="6 points"):
        identify_polach(creep, measured, speed)


def test_fit_refuses_curves_without_a_peak():
    true = PolachParams(0.55, 0.4, 0.6, 1.0, 0.4)
    creep, measured, speed = synthetic(true, [20, 60], noise=0.0, seed=1, creep_max=0.005)
    with pytest.raises(InputError, match="no peak"):
        identify_polach(creep, measured, speed)


def test_fit_refuses_nan_and_mismatched_data():
    creep, measured, speed = synthetic(PolachParams(0.3, 0.4, 0.2, 0.3, 0.1), [60], 0.0, 1)
    measured[3] = np.nan
    with pytest.raises(InputError, match=r"coefficient\[3\] = nan"):
        identify_polach(creep, measured, speed)
    with pytest.raises(InputError, match="values for"):
        identify_polach(creep, measured[:-1], speed)
