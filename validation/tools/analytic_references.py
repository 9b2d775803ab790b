"""Write the reference.csv of the analytic verification cases from their closed forms.

Run from the repository root: python validation/tools/analytic_references.py
Pure numpy: no railbrake code is used, so the references are independent of the model.
Each formula is stated again in its case.yaml with its source.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

BASE = Path(__file__).resolve().parents[1]
ROOT = BASE / "verification"
GAMMA, R_AIR = 1.4, 287.05             # ideal air (ISO 6358 reference conditions)
RHO0, T0_REF = 1.185, 293.15           # ISO 6358 reference density and temperature


def write(case: str, header: str, rows, comment: str, kind: str = "verification") -> None:
    path = BASE / kind / case / "reference.csv"
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [f"# {comment}", header] + [",".join(f"{v:.10g}" for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")


def hertz_sphere():
    """Johnson (1985) eq. 4.22-4.23: a = (3 Q R / (4 E*))^(1/3), p0 = 3 Q / (2 pi a^2)."""
    e, nu, r = 2.1e11, 0.3, 0.46
    e_star = e / (2.0 * (1.0 - nu ** 2))
    loads = [10e3, 30e3, 60e3, 83.4e3, 120e3]
    a = [(3.0 * q * r / (4.0 * e_star)) ** (1.0 / 3.0) for q in loads]
    write("hertz-sphere-radius", "normal_force_N,a_m", zip(loads, a), "Johnson 1985 eq. 4.22, R = 0.46 m")
    write("hertz-sphere-pressure", "normal_force_N,p0_Pa",
          [(q, 3.0 * q / (2.0 * math.pi * ai ** 2)) for q, ai in zip(loads, a)], "Johnson 1985 eq. 4.23")


def orifice():
    """ISO 6358-1: qm = C p1 rho0 sqrt(T0/T1) [choked]; times sqrt(1 - ((r - b)/(1 - b))^2) above b."""
    c, b, p1, t1 = 5e-9, 0.528, 6e5, 313.15
    choked = c * p1 * RHO0 * math.sqrt(T0_REF / t1)
    ratios = [0.1, 0.2, 0.3, 0.4, 0.5, 0.528]
    write("orifice-choked", "pressure_ratio,mass_flow_kg_s", [(r, choked) for r in ratios],
          "ISO 6358-1:2013 eq. (choked), C = 5e-9 m^3/(s Pa), b = 0.528, p1 = 6 bar abs, T1 = 313.15 K")
    sub = [0.6, 0.7, 0.8, 0.9, 0.95]
    write("orifice-subsonic", "pressure_ratio,mass_flow_kg_s",
          [(r, choked * math.sqrt(1.0 - ((r - b) / (1.0 - b)) ** 2)) for r in sub],
          "ISO 6358-1:2013 eq. (subsonic), same orifice")


def tank_fill():
    """Adiabatic filling at a constant choked inflow: d(pV/(g-1))/dt = cp Ts qm -> dp/dt = g R Ts qm / V."""
    c, b, ps, ts, v, p0 = 1e-8, 0.528, 10e5, 293.15, 0.01, 1.01325e5
    qm = c * ps * RHO0 * math.sqrt(T0_REF / ts)
    rate = GAMMA * R_AIR * ts * qm / v
    times = np.linspace(0.0, 2.5, 11)
    assert p0 + rate * times[-1] <= b * ps, "must stay choked"
    write("tank-fill-choked", "time_s,pressure_Pa", [(t, p0 + rate * t) for t in times],
          "energy balance of an adiabatic volume, constant choked inflow (linear rise)")


def tank_discharge():
    """Isentropic discharge through a choked orifice: (p/p0)^(-k/2) = 1 + (k/2) g R C rho0 sqrt(Tref T0) t / V,
    k = (g - 1)/g; valid while p_atm / p <= b."""
    c, b, p0, t0, v, p_atm = 1e-8, 0.528, 10e5, 293.15, 0.01, 1.01325e5
    k = (GAMMA - 1.0) / GAMMA
    rate = 0.5 * k * GAMMA * R_AIR * c * RHO0 * math.sqrt(T0_REF * t0) / v
    times = np.linspace(0.0, 12.0, 13)
    p = p0 * (1.0 + rate * times) ** (-2.0 / k)
    assert p_atm / p[-1] <= b, "must stay choked"
    write("tank-discharge-choked", "time_s,pressure_Pa", zip(times, p),
          "isentropic blow-down through a choked orifice")


def stops():
    """s = v0 te + v0^2 / (2 a); with a linear build-up over tb after ta: s = v0 (ta + tb/2) + v0^2/(2a) - a tb^2 / 24."""
    speeds = [100.0, 200.0, 250.0, 300.0, 350.0]
    a, te = 1.0, 2.0
    write("stop-constant-deceleration", "v0_kmh,distance_m",
          [(v, v / 3.6 * te + (v / 3.6) ** 2 / (2 * a)) for v in speeds], "a = 1.0 m/s^2, te = 2.0 s")
    ta, tb = 1.0, 3.0
    write("stop-en14531-build-up", "v0_kmh,distance_m",
          [(v, v / 3.6 * (ta + tb / 2) + (v / 3.6) ** 2 / (2 * a) - a * tb ** 2 / 24) for v in speeds],
          "a = 1.0 m/s^2, ta = 1.0 s, tb = 3.0 s (linear build-up)")


def crh380al_published_curves():
    """TB/T 1407.2 traction-calculation data of the CRH380AL, whole train: ED brake force
    F = min(509.6, 544.34 - 1.787 v, 42942.9/v - 121, 33033/v) kN (v in m/s) and running
    resistance R = 3.3 + 0.0469 V + 0.000921 V^2 kN (V in km/h, open track)."""
    speeds = [20.0, 50.0, 100.0, 150.0, 200.0, 250.0, 300.0, 350.0]
    ed = [min(509.6, 544.34 - 1.787 * v / 3.6, 42942.9 / (v / 3.6) - 121.0, 33033.0 / (v / 3.6)) for v in speeds]
    write("crh380al-ed-brake", "speed_kmh,force_kN", zip(speeds, ed), "TB/T 1407.2 CRH380AL ED brake", "code-to-code")
    write("crh380al-running-resistance", "speed_kmh,force_kN",
          [(v, 3.3 + 0.0469 * v + 0.000921 * v * v) for v in [0.0] + speeds],
          "TB/T 1407.2 CRH380AL running resistance, open track", "code-to-code")


def kdry_equal_units():
    """Kdry_rst of 8 equal brake units, each lost with p = 1e-4 per demand, friction factor normal
    (mean 1, sd 0.05): the ratio given k lost is normal with mean (8 - k) / 8 and sd
    sqrt(8 - k) 0.05 / 8; k is binomial (8, p). Kdry at confidence c solves
    sum_k P(k) Phi((x - mu_k) / sd_k) = 1 - c (scipy.stats, brentq)."""
    from scipy.optimize import brentq
    from scipy.stats import binom, norm
    n, p, sd = 8, 1e-4, 0.05
    levels = [0.5, 0.9, 0.99, 0.999, 0.9999, 0.99999, 0.999999, 0.9999999, 0.99999999, 0.999999999]

    def cdf(x):
        total = binom.pmf(n, n, p) * (x >= 0.0)   # all lost: the ratio is 0
        for k in range(n):
            total += binom.pmf(k, n, p) * norm.cdf((x - (n - k) / n) / (math.sqrt(n - k) * sd / n))
        return total

    rows = [(i, brentq(lambda x: cdf(x) - (1.0 - c), 0.01, 2.0, xtol=1e-14)) for i, c in enumerate(levels)]
    write("kdry-equal-units", "ebcl_index,kdry", rows,
          "binomial mixture of normals, 8 units, p = 1e-4, friction N(1, 0.05); scipy.stats + brentq")


# OSRD's ETCS test rolling stock (OpenRailAssociation/osrd, tests/data/rolling_stocks/
# etcs_level2_rolling_stock.json at commit 143f77aabdd1666887824744bb9869e94a8fb919): boundaries m/s
OSRD_GAMMA_E = ([8.333333, 16.666667, 55.555556, 61.111111], [1.11, 1.25, 1.34, 1.17, 0.94])
OSRD_K_DRY = ([8.333333, 61.111111], [0.72, 0.69, 0.7])
OSRD_K_WET, OSRD_T_BE, OSRD_MAX_SPEED = 0.89, 2.5, 80.0
G = 9.80665
ETCS_SPEEDS_KMH = [5.0, 20.0, 30.0, 45.0, 60.0, 80.0, 100.0, 130.0, 160.0, 200.0, 220.0, 240.0, 280.0]


def _osrd_value(curve, v):
    """OSRD's SpeedIntervalValueCurve.getValue: the first interval whose boundary is >= v."""
    for bound, value in zip(*curve):
        if v <= bound:
            return value
    return curve[1][-1]


def _ebd_distance(v, grad_permille=0.0, m_rotating_percent=2.0):
    """Distance (m) from v (m/s) to standstill at A_brake_safe + A_gradient (SUBSET-026 3.13.6.2.1,
    M_NVAVADH = 0: A_brake_emergency Kdry Kwet; 3.13.4.3: g grad / (1000 + 10 M_rotating)), summed
    over the intervals between all boundaries, each of constant deceleration."""
    edges = sorted(set(OSRD_GAMMA_E[0]) | set(OSRD_K_DRY[0]))
    lower, upper = [0.0] + edges, edges + [math.inf]
    total = 0.0
    for lo, hi in zip(lower, upper):
        if v <= lo:
            break
        mid = lo + 1e-6
        a = _osrd_value(OSRD_GAMMA_E, mid) * _osrd_value(OSRD_K_DRY, mid) * OSRD_K_WET
        a += G * grad_permille / (1000.0 + 10.0 * m_rotating_percent)
        total += (min(v, hi) ** 2 - lo ** 2) / (2.0 * a)
    return total


def etcs_osrd_test_stock():
    """EBD and EBI distances to the SvL of OSRD's ETCS test rolling stock (SUBSET-026 3.13)."""
    kmh = 1.0 / 3.6
    write("etcs-osrd-test-stock-ebd-flat", "speed_kmh,distance_m",
          [(v, _ebd_distance(v * kmh)) for v in ETCS_SPEEDS_KMH],
          "EBD distance to the SvL, level track: sum of (V_hi^2 - V_lo^2) / (2 A_brake_safe) per interval")
    write("etcs-osrd-test-stock-ebd-descent", "speed_kmh,distance_m",
          [(v, _ebd_distance(v * kmh, -10.0, 2.0)) for v in ETCS_SPEEDS_KMH],
          "EBD distance to the SvL on a 10 per-mille descent: A_brake_safe - g 10 / (1000 + 10 M_rotating_min 2 %)")

    def ebi(v):
        # T_traction = max(0, T_traction_cut_off 1 s - (T_warning 2 s + T_bs2 2 s)) = 0: T_berem = T_be
        ura = (2.0 + (12.0 - 2.0) * min(max(v / kmh - 30.0, 0.0), 470.0) / 470.0) * kmh   # SUBSET-041 5.3.1.2
        v_bec = v + ura + 0.4 * OSRD_T_BE
        d_bec = (v + ura + 0.4 * OSRD_T_BE / 2.0) * OSRD_T_BE
        return _ebd_distance(v_bec) + d_bec

    write("etcs-osrd-test-stock-ebi-flat", "speed_kmh,distance_m", [(v, ebi(v * kmh)) for v in ETCS_SPEEDS_KMH],
          "EBI distance to the SvL, level track: d_EBD(V_bec) + D_bec, V_bec = V + V_ura + A_est2 T_be, "
          "D_bec = (V + V_ura + A_est2 T_be / 2) T_be")


if __name__ == "__main__":
    etcs_osrd_test_stock()
    crh380al_published_curves()
    hertz_sphere()
    orifice()
    tank_fill()
    tank_discharge()
    stops()
    kdry_equal_units()
