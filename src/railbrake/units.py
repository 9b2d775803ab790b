"""Explicit conversions between human units (edges: config, CLI, plots) and SI (inside)."""

G_STANDARD = 9.80665  # m/s^2
BAR = 1.0e5  # Pa
KMH = 1.0 / 3.6  # m/s
TONNE = 1000.0  # kg
KN = 1000.0  # N


def kmh_to_ms(v_kmh):
    return v_kmh * KMH


def ms_to_kmh(v_ms):
    return v_ms / KMH


def bar_to_pa(p_bar):
    return p_bar * BAR


def pa_to_bar(p_pa):
    return p_pa / BAR


def tonne_to_kg(m_t):
    return m_t * TONNE


def kn_to_n(f_kn):
    return f_kn * KN


def cars_text(n: int) -> str:
    """A train's length for titles and tables: '1 car', '8 cars'."""
    return f"{n} car{'s' if n != 1 else ''}"
