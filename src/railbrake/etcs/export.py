"""A braking model's outputs: SUBSET-026's variables with their train-data codings (JSON) and the
ETCS brake parameters of OSRD's rolling-stock JSON."""

from __future__ import annotations

from dataclasses import asdict

from railbrake.etcs import confidence
from railbrake.etcs.model import BrakingModel, braking_distance
from railbrake.units import KMH


def code(k: float) -> int:
    """The 5-bit train-data code of a factor already on the grid (0..31 for 0..1.55)."""
    return int(round(confidence.coded(k) / confidence.K_STEP))


def to_json(m: BrakingModel) -> dict:
    levels = range(len(confidence.EBCL))
    return {
        "train": m.train,
        "brake_configuration": "emergency brake as the train file's brake_steps.emergency",
        "A_brake_emergency": {"V_lower_kmh": m.speed_steps_kmh, "A_m_s2": m.a_brake_emergency},
        "T_brake_emergency_s": m.t_brake_emergency,
        "Kdry_rst": [{"M_NVEBCL": i, "EBCL": confidence.EBCL[i],
                      "value": [step[i] for step in m.kdry],
                      "coded": [step[i] for step in m.kdry_coded()],
                      "code": [code(step[i]) for step in m.kdry],
                      "deciding_state": [step[i] for step in m.deciding]} for i in levels],
        "Kwet_rst": {"value": m.kwet, "coded": m.kwet_coded(), "code": code(m.kwet), "test_pairs": m.kwet_pairs},
        "emergency_braking_distance_m": [{"M_NVEBCL": i, "M_NVAVADH_0": braking_distance(m, i, 0.0),
                                          "M_NVAVADH_1": braking_distance(m, i, 1.0)} for i in levels],
        "failure_states": m.states,
        "unenumerated_probability": m.unenumerated_probability,
        "failure_effects": m.effects,
        "warnings": m.warnings,
        "runs": m.runs,
        "analysis": asdict(m.spec),
    }


def to_osrd(m: BrakingModel, level: int) -> dict:
    """OSRD's etcs_brake_params entries this analysis gives (speed-interval curves: `boundaries` in
    m/s between the intervals, one more `values`): gamma_emergency, k_dry at M_NVEBCL = level,
    k_wet (one value over all speeds), t_be. The service-brake entries are not computed here."""
    confidence.ebcl(level)
    boundaries = [v * KMH for v in m.speed_steps_kmh[1:]]
    return {"etcs_brake_params": {
        "gamma_emergency": {"boundaries": boundaries, "values": m.a_brake_emergency},
        "k_dry": {"boundaries": boundaries, "values": [step[level] for step in m.kdry_coded()]},
        "k_wet": {"boundaries": boundaries, "values": [m.kwet_coded()] * len(m.a_brake_emergency)},
        "t_be": m.t_brake_emergency,
    }}
