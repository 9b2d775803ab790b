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


# The unit a file key names at the end of its name (tare_t, max_speed_kmh, A_kN): such keys take a
# bare number in that unit. Longest suffixes first.
NAME_UNITS = (("_kN_per_kmh2", "kN/(km/h)²"), ("_kN_per_kmh", "kN/(km/h)"), ("_kN_per_mm", "kN/mm"),
              ("_kN_s_per_m", "kN s/m"), ("_J_per_kgK", "J/(kg K)"), ("_W_per_K", "W/K"), ("_m_per_s", "m/s"),
              ("_J_m2", "J/m²"), ("_per_h", "1/h"), ("_kg_s", "kg/s"), ("_kgm2", "kg m²"), ("_mm2", "mm²"),
              ("_m2", "m²"), ("_ms2", "m/s²"), ("_kmh", "km/h"), ("_bar", "bar"), ("_kN", "kN"), ("_kg", "kg"),
              ("_mm", "mm"), ("_ms", "ms"), ("_t", "t"), ("_m", "m"), ("_s", "s"), ("_l", "l"), ("_c", "°C"),
              ("_K", "K"), ("_h", "h"), ("_percent", "%"), ("_permille", "‰"))


def unit_in_name(key: str) -> str | None:
    """The unit a key's name ends with ('tare_t' -> 't', 'B_kN_per_kmh' -> 'kN/(km/h)'), else None."""
    return next((unit for suffix, unit in NAME_UNITS if key.endswith(suffix)), None)


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
