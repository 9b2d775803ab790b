"""A braking model's outputs: SUBSET-026's variables with their train-data codings (JSON) and the
ETCS brake parameters of OSRD's rolling-stock JSON."""

from __future__ import annotations

import hashlib
from dataclasses import asdict
from pathlib import Path

from railbrake.etcs import confidence, inputs
from railbrake.etcs.model import BrakingModel, braking_distance
from railbrake.units import KMH


def _coded(name: str, x: float) -> float:
    c = confidence.CODINGS[name]
    return confidence.on_grid(x, c["resolution"], c["rounding"])


def inputs_of(m: BrakingModel) -> dict:
    """The analysis' input files with their digests."""
    out = {}
    for kind, name in (("reliability", m.spec.reliability), ("scatter", m.spec.scatter)):
        if name is None:
            out[kind] = None
            continue
        path = inputs._path(kind, name)
        out[kind] = {"name": str(name), "sha256": hashlib.sha256(Path(path).read_bytes()).hexdigest()}
    return out


def to_json(m: BrakingModel) -> dict:
    levels = range(len(confidence.EBCL))
    coded = m.kdry_coded()
    return {
        "train": m.train,
        "brake_configuration": "emergency brake as the train file's brake_steps.emergency",
        "initial_speed_kmh": m.initial_speed_kmh,
        "inputs": inputs_of(m),
        "codings": confidence.CODINGS,
        "A_brake_emergency": {"V_lower_kmh": m.speed_steps_kmh, "A_m_s2": m.a_brake_emergency,
                              "coded": [_coded("A_brake_emergency", a) for a in m.a_brake_emergency]},
        "T_brake_emergency_s": m.t_brake_emergency,
        "T_brake_emergency_coded_s": _coded("T_brake_emergency", m.t_brake_emergency),
        "Kdry_rst": [{"M_NVEBCL": i, "EBCL": confidence.ebcl_text(i),
                      "value": [step[i] for step in m.kdry],
                      "bound_95": [list(b[i]) for b in m.kdry_bounds] if m.kdry_bounds else None,
                      "step_allowance": m.step_allowance or None,
                      "coded": [step[i] for step in coded],
                      "deciding_state": [step[i] for step in m.deciding]} for i in levels],
        "Kdry_rst_bound_method": m.bound_method,
        "Kwet_rst": {"value": m.kwet, "coded": m.kwet_coded(), "value_per_step": m.kwet_steps,
                     "coded_per_step": m.kwet_steps_coded(), "test_pairs": m.kwet_pairs,
                     "reduced_condition": m.spec.reduced_condition},
        "emergency_braking_distance_m": [{"M_NVEBCL": i, "M_NVAVADH_0": braking_distance(m, i, 0.0),
                                          "M_NVAVADH_1": braking_distance(m, i, 1.0)} for i in levels],
        "failure_states": m.states,
        "unenumerated_probability": m.unenumerated_probability,
        "failure_effects": m.effects,
        "importance": m.importance,
        "warnings": m.warnings,
        "runs": m.runs,
        "analysis": asdict(m.spec),
    }


def to_osrd(m: BrakingModel, level: int) -> dict:
    """OSRD's etcs_brake_params entries this analysis gives (speed-interval curves: `boundaries` in
    m/s between the intervals, one more `values`): gamma_emergency, k_dry at M_NVEBCL = level,
    k_wet (per speed step), t_be. The service-brake entries are not computed here."""
    confidence.ebcl(level)
    boundaries = [v * KMH for v in m.speed_steps_kmh[1:]]
    return {"etcs_brake_params": {
        "gamma_emergency": {"boundaries": boundaries, "values": m.a_brake_emergency},
        "k_dry": {"boundaries": boundaries, "values": [step[level] for step in m.kdry_coded()]},
        "k_wet": {"boundaries": boundaries, "values": m.kwet_steps_coded()},
        "t_be": m.t_brake_emergency,
    }}
