"""Explicit conversions between human units (edges: config, CLI, plots) and SI (inside). They
convert numbers and arrays as they are (NaN stays NaN); anything else is a TypeError naming it."""

import numbers

import numpy as np

G_STANDARD = 9.80665  # m/s^2
BAR = 1.0e5  # Pa
KMH = 1.0 / 3.6  # m/s
TONNE = 1000.0  # kg
KN = 1000.0  # N


def kmh_to_ms(v_kmh):
    return _number('v_kmh', v_kmh) * KMH


def ms_to_kmh(v_ms):
    return _number('v_ms', v_ms) / KMH


def bar_to_pa(p_bar):
    return _number('p_bar', p_bar) * BAR


def pa_to_bar(p_pa):
    return _number('p_pa', p_pa) / BAR


def tonne_to_kg(m_t):
    return _number('m_t', m_t) * TONNE


def kn_to_n(f_kn):
    return _number('f_kn', f_kn) * KN


def _number(name: str, value):
    """value if a number or an array (numpy, pandas); not a Boolean, a string, a list or None."""
    if isinstance(value, (bool, np.bool_)) or not (isinstance(value, numbers.Number) or hasattr(value, "__array__")):
        raise TypeError(f"{name} = {value!r}: must be a number or an array of numbers")
    return value


def cars_text(n: int) -> str:
    """A train's length for titles and tables: '1 car', '8 cars'."""
    if isinstance(n, bool) or not isinstance(n, numbers.Integral):
        raise TypeError(f"n = {n!r}: must be a whole number of cars")
    return f"{n} car{'s' if n != 1 else ''}"
