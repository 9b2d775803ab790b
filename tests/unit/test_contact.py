"""Hertz, Kalker and Polach against published and analytic references."""

import csv
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from railbrake.contact import (
    PolachParams,
    default_contact,
    hertz_contact,
    kalker_c11,
    kalker_c22,
    kalker_c23,
    polach_coefficient,
    polach_peak,
    relative_radius,
)
from railbrake.errors import InputError

DATA = Path(__file__).resolve().parents[1] / "data"
E, NU = 2.1e11, 0.3


def read_csv(path):
    with open(path) as handle:
        rows = [line for line in handle if not line.startswith("#")]
    return list(csv.DictReader(rows))


# ---------------------------------------------------------------- Hertz

@pytest.mark.parametrize("row", read_csv(DATA / "hertz_m_n.csv"), ids=lambda r: f"theta{r['theta_deg']}")
def test_hertz_matches_classical_m_n_coefficients(row):
    """Timoshenko & Goodier, Theory of Elasticity (1951) sec. 140: a = m c, b = n c with
    c = (3 P (1 - nu^2) / (2 E (A + B)))^(1/3) and cos(theta) = (B - A) / (A + B)."""
    theta = math.radians(float(row["theta_deg"]))
    curv_sum = 1.0 / 0.46  # A + B
    curv_a = 0.5 * curv_sum * (1 - math.cos(theta))  # smaller curvature: major axis
    curv_b = curv_sum - curv_a
    load = 80e3
    contact = hertz_contact(load, 0.5 / curv_a, 0.5 / curv_b, E, NU)
    scale = (3 * load * (1 - NU**2) / (2 * E * curv_sum)) ** (1 / 3)
    assert contact.a / scale == pytest.approx(float(row["m"]), rel=4e-3)
    assert contact.b / scale == pytest.approx(float(row["n"]), rel=4e-3)


def hertz_displacement(contact, x0, y0):
    """Sum of both bodies' normal surface displacements (Boussinesq) under the Hertz pressure,
    integrated numerically in polar coordinates around (x0, y0) (the 1/r kernel cancels)."""
    a, b, p0 = contact.a, contact.b, contact.p0
    alpha = 1 - x0**2 / a**2 - y0**2 / b**2

    def along_ray(phi):
        c, s = math.cos(phi), math.sin(phi)
        gamma = c**2 / a**2 + s**2 / b**2
        beta = x0 * c / a**2 + y0 * s / b**2
        rho_max = (-beta + math.sqrt(beta**2 + gamma * alpha)) / gamma
        value, _ = quad(lambda r: math.sqrt(max(alpha - 2 * beta * r - gamma * r * r, 0.0)), 0, rho_max)
        return value

    integral, _ = quad(along_ray, 0, 2 * math.pi, limit=200)
    return 2 * (1 - contact.poisson**2) / (math.pi * contact.youngs_modulus) * p0 * integral


def test_hertz_satisfies_contact_condition_by_numerical_integration():
    """Inside the ellipse the displacements close the initial gap A x^2 + B y^2 exactly."""
    rx, ry = 0.46, 0.3
    contact = hertz_contact(83e3, rx, ry, E, NU)
    u0 = hertz_displacement(contact, 0.0, 0.0)
    for frac in (0.4, 0.8):
        x, y = frac * contact.a, frac * contact.b
        assert u0 - hertz_displacement(contact, x, 0.0) == pytest.approx(x**2 / (2 * rx), rel=2e-4)
        assert u0 - hertz_displacement(contact, 0.0, y) == pytest.approx(y**2 / (2 * ry), rel=2e-4)
    # Load equilibrium: P = (2/3) pi a b p0.
    assert 2 / 3 * math.pi * contact.a * contact.b * contact.p0 == pytest.approx(83e3, rel=1e-12)


def test_hertz_equal_curvatures_give_a_circle():
    contact = hertz_contact(50e3, 0.4, 0.4)
    assert contact.a == pytest.approx(contact.b, rel=1e-12)


@pytest.mark.parametrize("ratio", [1e-3, 0.2, 5.0, 1e3])
def test_hertz_either_axis_the_longer(ratio):
    along, across = hertz_contact(80e3, 0.3 * ratio, 0.3), hertz_contact(80e3, 0.3, 0.3 * ratio)
    assert along.a == pytest.approx(across.b, rel=1e-10)
    assert (along.a > along.b) == (ratio > 1)


def test_relative_radius_allows_a_flat_body():
    assert relative_radius(0.46, math.inf) == pytest.approx(0.46)
    assert relative_radius(0.5, 0.5) == pytest.approx(0.25)


@pytest.mark.parametrize("kwargs, name", [
    (dict(normal_force=-1.0, rx=0.46, ry=0.3), "normal_force = -1"),
    (dict(normal_force=1e4, rx=0.46, ry=0.3, poisson=0.5), "poisson = 0.5"),
    (dict(normal_force=1e4, rx=math.nan, ry=0.3), "rx = nan"),
    (dict(normal_force=1e4, rx=0.46, ry=math.inf), "ry = inf"),
])
def test_hertz_bad_input_names_argument(kwargs, name):
    with pytest.raises(InputError, match=name):
        hertz_contact(**kwargs)


# ---------------------------------------------------------------- Kalker

KALKER_TABLE = Path(__file__).resolve().parents[2] / "validation" / "code-to-code" / "kalker-creepage-table" / "reference.csv"


def test_kalker_reproduces_table_e3():
    """Every node of Kalker (1990) Table E.3 (the validation case kalker-creepage-table holds it)."""
    functions = {"c11": kalker_c11, "c22": kalker_c22, "c23": kalker_c23}
    for row in read_csv(KALKER_TABLE):
        for name, function in functions.items():
            for nu, column in ((0.0, "nu0"), (0.25, "nu025"), (0.5, "nu05")):
                expected = float(row[f"{name}_{column}"])
                assert function(float(row["a_over_b"]), nu) == pytest.approx(expected, rel=1e-12)


def test_kalker_asymptote_and_continuity():
    """a/b -> 0: C11 -> pi^2/(4(1-nu)), C22 -> pi^2/4 (Kalker 1990); continuous at the table edges."""
    assert kalker_c11(1e-8, 0.3) == pytest.approx(math.pi**2 / (4 * 0.7), rel=1e-6)
    assert kalker_c22(1e-8, 0.3) == pytest.approx(math.pi**2 / 4, rel=1e-6)
    for function in (kalker_c11, kalker_c22, kalker_c23):
        for edge in (0.1, 10.0):
            assert function(edge * (1 - 1e-9), 0.3) == pytest.approx(function(edge * (1 + 1e-9), 0.3), rel=1e-6)
        assert function(100.0, 0.3) > function(10.0, 0.3)  # grows beyond the table


def test_kalker_interpolates_between_nodes_and_poisson_values():
    mid = kalker_c11(0.75, 0.25)
    assert 3.81 < mid < 3.91
    assert kalker_c11(1.0, 0.0) < kalker_c11(1.0, 0.3) < kalker_c11(1.0, 0.5)


# ---------------------------------------------------------------- Polach

def test_polach_linear_limit_has_kalker_slope():
    """kA = kS = 1 and constant mu (A = 1): dF/ds at s -> 0 equals G a b c11 (Kalker's linear theory)."""
    contact = default_contact()
    params = PolachParams(mu0=0.5, A=1.0, B=0.0, kA=1.0, kS=1.0)
    s = 1e-8
    force = polach_coefficient(s, 30.0, contact.normal_force, contact, params) * contact.normal_force
    slope = contact.shear_modulus * contact.a * contact.b * contact.c11
    assert force / s == pytest.approx(slope, rel=1e-6)


def test_polach_finite_and_continuous_everywhere():
    contact = default_contact()
    params = PolachParams(0.55, 0.4, 0.6, 1.0, 0.4)
    creep = np.linspace(-1.0, 1.0, 20001)
    # Steepest slope is at zero creep: (kA + kS)/2 * G a b c11 / Q (small-creep limit of Polach).
    max_slope = (params.kA + params.kS) / 2 * contact.shear_modulus * contact.a * contact.b \
        * contact.c11 / contact.normal_force
    for speed in (0.0, 1.0, 30.0, 97.0):
        f = polach_coefficient(creep, speed, contact.normal_force, contact, params)
        assert np.all(np.isfinite(f))
        assert np.max(np.abs(np.diff(f))) <= 1.001 * max_slope * (creep[1] - creep[0])  # no jump
        assert f[10000] == 0.0
        np.testing.assert_allclose(f[::-1], -f, atol=1e-15)  # braking mirrors traction
        assert np.all(np.abs(f) <= params.mu0)


def test_polach_broadcasts_over_creep_and_speed():
    contact = default_contact()
    params = PolachParams(0.3, 0.4, 0.2, 0.3, 0.1)
    grid = polach_coefficient(np.array([[0.01], [0.05]]), np.array([10.0, 50.0, 80.0]),
                              contact.normal_force, contact, params)
    assert grid.shape == (2, 3)
    assert grid[0, 1] == polach_coefficient(0.01, 50.0, contact.normal_force, contact, params)


def test_polach_bad_input_names_argument():
    contact = default_contact()
    params = PolachParams(0.3, 0.4, 0.2, 0.3, 0.1)
    with pytest.raises(InputError, match=r"creep\[1\] = nan"):
        polach_coefficient([0.01, math.nan], 10.0, contact.normal_force, contact, params)
    with pytest.raises(InputError, match="speed"):
        polach_coefficient(0.01, -3.0, contact.normal_force, contact, params)
    with pytest.raises(InputError, match="normal_force = -5"):
        polach_coefficient(0.01, 3.0, -5.0, contact, params)
    with pytest.raises(InputError, match="kA = 0"):
        PolachParams(0.3, 0.4, 0.2, 0.0, 0.1)
    with pytest.raises(InputError, match="mu0 = nan"):
        PolachParams(math.nan, 0.4, 0.2, 0.3, 0.1)


def test_polach_peak_is_the_maximum():
    contact = default_contact()
    params = PolachParams(0.55, 0.4, 0.6, 1.0, 0.4)
    peak, at = polach_peak(10.0, contact.normal_force, contact, params)
    creep = np.geomspace(1e-6, 1.0, 20001)
    dense = polach_coefficient(creep, 10.0, contact.normal_force, contact, params)
    assert peak >= dense.max() - 1e-12
    assert at == pytest.approx(creep[np.argmax(dense)], rel=2e-3)


def test_polach_rolling_speed_factor_scales_mu0_with_the_train_speed():
    """mu0 / (1 + v / v_ref): at each speed the law of mu0 scaled by the factor (the C core's, through
    the bindings); without v_ref Polach's law itself; a v_ref below 1 m/s is refused by name."""
    contact = default_contact()
    q = contact.normal_force
    wet = PolachParams(0.30, 0.40, 0.20, 0.30, 0.10)
    film = PolachParams(0.30, 0.40, 0.20, 0.30, 0.10, v_ref=25.0)
    creep = -np.logspace(-6, 0, 61)
    for v in (0.0, 10.0, 25.0, 80.0):
        scaled = PolachParams(0.30 / (1.0 + v / 25.0), 0.40, 0.20, 0.30, 0.10)
        assert np.allclose(polach_coefficient(creep, v, q, contact, film),
                           polach_coefficient(creep, v, q, contact, scaled), rtol=1e-14, atol=0.0)
    assert polach_peak(25.0, q, contact, film)[0] == pytest.approx(
        polach_peak(25.0, q, contact, PolachParams(0.15, 0.40, 0.20, 0.30, 0.10))[0], rel=1e-9)
    assert np.array_equal(polach_coefficient(creep, 80.0, q, contact, wet),
                          polach_coefficient(creep, 80.0, q, contact, PolachParams(0.30, 0.40, 0.20, 0.30, 0.10, None)))
    with pytest.raises(InputError, match="v_ref = 0.5"):
        PolachParams(0.30, 0.40, 0.20, 0.30, 0.10, v_ref=0.5)
