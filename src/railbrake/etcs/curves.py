"""The ETCS braking curves of a train on a track (UNISIG SUBSET-026 3.13, docs/etcs.md).

This is the specification's supervision arithmetic on the train data, not a physical law: the
train's deceleration comes from its braking model (the JSON `etcs braking-model` writes, from
whole-train runs in the C core) and its service data (railbrake.etcs.service).

- EBD (3.13.8.3): from the SvL at speed 0 backwards with A_safe(V, d) = A_brake_safe(V) +
  A_gradient(d); A_brake_safe = A_brake_emergency Kdry_rst(M_NVEBCL) (Kwet_rst + M_NVAVADH
  (1 - Kwet_rst)) (3.13.6.2.1); A_gradient = g grad / (1000 + 10 M_rotating_nom) (3.13.4.3).
  Speed steps and gradient sections make it piecewise of constant deceleration, so it is
  integrated exactly: V^2 is linear in distance on each piece.
- EBI (3.13.9.3.2): d_EBI(V) = d_EBD(V_bec) - D_bec with V_delta0 = V_ura (SUBSET-041 5.3.1.2,
  unless Q_NVINHSMICPERM), T_traction = max(0, T_traction_cut_off - (T_warning + T_bs2)) when the
  on-board cuts the traction (else T_traction_cut_off), T_berem = max(0, T_be - T_traction),
  V_delta2 = A_est2 T_berem, V_bec = V + V_delta0 + V_delta1 + V_delta2, D_bec = (V + V_delta0 +
  V_delta1/2) T_traction + (V + V_delta0 + V_delta1 + V_delta2/2) T_berem. For a gamma train T_be
  = T_brake_emergency (Kt_int is the conversion model's).
- SBD (3.13.8.4): from the EoA at 0 with A_expected = A_brake_service + A_gradient, when
  Q_NVSBTSMPERM; SBI1 = d_SBD - V T_bs1, SBI2 = d_EBI - V T_bs2 (3.13.9.3.3); the most
  restrictive SBI supervises.
- W = SBI - V T_warning (3.13.9.3.4), P = SBI - V T_driver (3.13.9.3.5; with Q_NVGUIPERM the
  guidance curve from the EoA on A_normal_service = A_brake_normal_service + A_gradient - Kn
  grad/1000 caps it), I = P - V (max(0.8 T_bs, 5 s) + T_driver) (3.13.9.3.6; the constants in the
  national values file).

The gradient is read at the train's front (the track files give it as sections; a profile whose
gradient rises towards the EoA would need the lowest gradient under the whole train). Release
speeds are not modelled: every curve ends at speed 0.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np

from railbrake.errors import InputError
from railbrake.etcs.national import National, Track
from railbrake.units import G_STANDARD, KMH

NAMES = ("EBD", "EBI", "SBD", "SBI1", "SBI2", "W", "P", "I")
OVERSPEED_KMH = 50.0     # the EBD reaches this far above the top speed, so the EBI reaches it (as OSRD)
SAMPLES = 400            # speeds per curve (plus every speed step's boundary)
MAX_PIECES = 100_000     # pieces of one integration: bounded before anything grows with the track


@dataclass(frozen=True)
class Step:
    """A step function of speed: lower speeds (m/s, the first 0) and values."""
    lower: tuple
    values: tuple

    def at(self, v: float) -> float:
        return self.values[bisect.bisect_right(self.lower, v) - 1]


def _steps(lower_kmh: list, values: list) -> Step:
    return Step(tuple(v * KMH for v in lower_kmh), tuple(float(a) for a in values))


def braking_distances(decel, track: Track, x_end: float, v_top: float, speed_marks: tuple) -> tuple[np.ndarray, np.ndarray]:
    """(x, V) of the braking curve that reaches x_end at speed 0 with deceleration decel(V, grad)
    (m/s^2, grad in per mille), from 0 up to v_top, integrated backwards exactly piece by piece."""
    starts = [g.from_m for g in track.gradients]
    grads = [g.permille for g in track.gradients]
    marks = sorted(v for v in speed_marks if 0.0 < v < v_top) + [v_top]
    xs, vs = [x_end], [0.0]
    x, v = x_end, 0.0
    while v < v_top:
        if len(xs) > MAX_PIECES:
            raise InputError(f"track {track.name}: more than {MAX_PIECES} pieces in one braking curve")
        k = max(bisect.bisect_left(starts, x) - 1, 0)   # the section just before x
        a = decel(v, grads[k])
        if not a > 0.0:
            raise InputError(f"track {track.name}: at {x:.0f} m ({grads[k]:g} per mille) the train does not "
                             f"brake from {v / KMH:.1f} km/h (deceleration {a:.3f} m/s^2): no braking curve")
        vb = next(m for m in marks if m > v)
        dx_v = (vb * vb - v * v) / (2.0 * a)
        dx_x = x - starts[k] if k > 0 else math.inf
        if dx_v <= dx_x:
            x, v = x - dx_v, vb
        else:
            x, v = starts[k], math.sqrt(v * v + 2.0 * a * dx_x)
        xs.append(x)
        vs.append(v)
    return np.asarray(xs), np.asarray(vs)


def position_at(curve: tuple, v):
    """The curve's position at speed v (exact: V^2 is linear in distance between its points)."""
    xs, vs = curve
    return np.interp(np.square(v), np.square(vs), xs)


def v_ura(national: National, v):
    u = national.V_ura_kmh
    return np.interp(v, [u.at_low_kmh * KMH, u.at_high_kmh * KMH], [u.low_kmh * KMH, u.high_kmh * KMH])


def a_gradient(grad: float, m_rot_percent: float | None, national: National) -> float:
    """g grad / (1000 + 10 M_rotating) (3.13.4.3): the train's M_rotating_nom, else the fixed
    values on the safe side (the largest uphill, the smallest downhill)."""
    if m_rot_percent is None:
        m_rot_percent = national.M_rotating_max_percent if grad >= 0 else national.M_rotating_min_percent
    return G_STANDARD * grad / (1000.0 + 10.0 * m_rot_percent)


def safe_deceleration(model: dict, national: National) -> Step:
    """A_brake_safe(V) at the national M_NVEBCL and M_NVAVADH (coded factors)."""
    kdry = model["Kdry_rst"][national.M_NVEBCL]["coded"]
    kwet = model["Kwet_rst"]["coded"]
    a = model["A_brake_emergency"]["A_m_s2"]
    wet = kwet + national.M_NVAVADH * (1.0 - kwet)
    return _steps(model["A_brake_emergency"]["V_lower_kmh"], [ai * k * wet for ai, k in zip(a, kdry)])


def times(model: dict, service: dict, national: National) -> dict:
    t_be = model["T_brake_emergency_s"]
    t_bs = service["T_bs_s"]
    t_bs1, t_bs2 = (service["T_bs1_s"], service["T_bs2_s"]) if national.Q_NVSBFBPERM else (t_bs, t_bs)
    cut = service["T_traction_cut_off_s"]
    t_traction = max(0.0, cut - (national.T_warning_s + t_bs2)) if service["traction_cut_off_implemented"] else cut
    return {"T_be": t_be, "T_bs": t_bs, "T_bs1": t_bs1, "T_bs2": t_bs2, "T_traction": t_traction,
            "T_berem": max(0.0, t_be - t_traction),
            "T_indication": max(national.T_indication.bs_factor * t_bs, national.T_indication.min_s) + national.T_driver_s}


def compute(model: dict, service: dict, track: Track, national: National) -> dict:
    """Every curve as [distance m, speed km/h] pairs, highest speed first, and what they used."""
    t = times(model, service, national)
    if t["T_traction"] > 0.0:
        raise InputError(f"T_traction = {t['T_traction']:.2f} s > 0 (T_traction_cut_off "
                         f"{service['T_traction_cut_off_s']:g} s): the EBI then needs the train's traction "
                         "acceleration (A_est1), which its files do not give")
    m_rot = service.get("M_rotating_nom_percent")
    v_max = (track.line_speed_kmh or service["initial_speed_kmh"]) * KMH
    if v_max > service["initial_speed_kmh"] * KMH * (1.0 + 1e-12):
        raise InputError(f"track {track.name}: line_speed_kmh = {v_max / KMH:g} above the braking model's initial "
                         f"speed {service['initial_speed_kmh']:g} km/h: the model holds up to that speed only")
    v_top = v_max + OVERSPEED_KMH * KMH
    steps = model["A_brake_emergency"]["V_lower_kmh"]
    marks = tuple(v * KMH for v in steps)
    safe = safe_deceleration(model, national)
    ebd = braking_distances(lambda v, g: safe.at(v) + a_gradient(g, m_rot, national), track, track.svl_m, v_top, marks)
    v = np.unique(np.concatenate([np.linspace(0.0, v_max, SAMPLES), [m for m in marks if m < v_max]]))
    d0 = np.zeros_like(v) if national.Q_NVINHSMICPERM else v_ura(national, v)
    d2 = national.A_est2_m_s2 * t["T_berem"]
    v_bec = v + d0 + d2
    d_bec = (v + d0 + d2 / 2.0) * t["T_berem"]
    keep = v_bec <= v_top
    if not keep.all():
        raise InputError(f"the EBD does not reach {v_bec.max() / KMH:.0f} km/h: raise OVERSPEED_KMH")
    curves = {"EBD": (position_at(ebd, v), v), "EBI": (position_at(ebd, v_bec) - d_bec, v)}
    curves["SBI2"] = (curves["EBI"][0] - v * t["T_bs2"], v)
    sbi = curves["SBI2"][0]
    if national.Q_NVSBTSMPERM:
        service_steps = _steps(service["V_lower_kmh"], service["A_brake_service"])
        sbd = braking_distances(lambda s, g: service_steps.at(s) + a_gradient(g, m_rot, national), track,
                                track.eoa_m, v_top, marks)
        curves["SBD"] = (position_at(sbd, v), v)
        curves["SBI1"] = (curves["SBD"][0] - v * t["T_bs1"], v)
        sbi = np.minimum(sbi, curves["SBI1"][0])
    curves["W"] = (sbi - v * national.T_warning_s, v)
    p = sbi - v * national.T_driver_s
    if national.Q_NVGUIPERM:
        normal = _steps(service["V_lower_kmh"], service["A_brake_normal_service"])

        def a_normal(s, g):
            kn = service["Kn_plus_m_s2"] if g > 0 else service["Kn_minus_m_s2"]
            return normal.at(s) + a_gradient(g, m_rot, national) - kn * g / 1000.0

        gui = braking_distances(a_normal, track, track.eoa_m, v_top, marks)
        curves["GUI"] = (position_at(gui, v), v)
        p = np.minimum(p, curves["GUI"][0])
    curves["P"] = (p, v)
    curves["I"] = (p - v * t["T_indication"], v)
    out = {name: [[float(x), float(s / KMH)] for x, s in zip(*c)][::-1] for name, c in curves.items()}
    return {"train": model["train"], "track": track.name, "eoa_m": track.eoa_m, "svl_m": track.svl_m,
            "target_speed_kmh": 0.0, "top_speed_kmh": v_max / KMH,
            "national_values": national.model_dump(by_alias=True), "times_s": t,
            "A_brake_safe_m_s2": {"V_lower_kmh": steps, "values": list(safe.values)},
            "M_rotating_nom_percent": m_rot, "curves": out}
