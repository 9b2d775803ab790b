"""A study's runs: design points x noise seeds, each resolved and keyed before anything runs.

The seeds come from one ``numpy.random.SeedSequence(study.seed)``: one child draws the design,
the other gives the noise seeds, the same for every point (common random numbers, so points
differ by their factors only). Resolving every run up front means a bad combination (a fault on
a car the train lacks) fails before the first simulation.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

from railbrake.campaign import configuration, designs, identity
from railbrake.campaign.factors import NO_FAULT, quantity
from railbrake.campaign.study import Study
from railbrake.errors import InputError

SEED_KEY = "seed"


@dataclass
class Run:
    index: int
    point: int
    replicate: int
    seed: int
    sets: dict                   # dotted key -> value in file units, as for --set
    factors: dict                # factor name -> SI value (dataset columns)
    block: str = ""
    sample: int = -1
    key: str = ""
    meta: dict = field(default_factory=dict)


def _fault(parts: dict) -> dict | None:
    if parts.get("type", NO_FAULT) == NO_FAULT:
        return None
    return {k: v for k, v in parts.items()}


def _zone(parts: dict, where: str) -> dict:
    missing = [p for p in ("start", "length", "condition") if p not in parts]
    if missing:
        raise InputError(f"{where}: an adhesion zone needs {', '.join('zone.' + m for m in missing)}")
    start, length = quantity(parts["start"]), quantity(parts["length"])
    if not start or not length or start[2] != "length" or length[2] != "length":
        raise InputError(f"{where}: zone.start and zone.length are lengths with units, e.g. '1500 m'")
    end = start[0] + length[0]
    scale = quantity(f"1 {start[1]}")[0]
    return {"start": parts["start"], "end": f"{end / scale:.12g} {start[1]}", "condition": parts["condition"]}


def point_sets(study: Study, values: dict, base_tree: dict) -> dict:
    """The --set overrides of one design point: fixed sets, factor values, one fault, one zone."""
    sets = dict(study.fixed)
    parts = {"fault": {}, "zone": {}}
    items = list(study.fixed_parts.items())
    for name, value in values.items():
        if isinstance(value, dict):   # a named case sets several keys
            items += [(k, v) for k, v in value.items() if k != "name"]
        else:
            items.append((name, value))
    for key, value in items:
        head, _, part = key.partition(".")
        if head in parts:
            parts[head][part] = value
        else:
            sets[key] = value
    if parts["fault"]:
        fault = _fault(parts["fault"])
        if fault is not None:
            sets["faults"] = list(base_tree.get("faults") or []) + [fault]
    if parts["zone"]:
        zones = list((base_tree.get("adhesion") or {}).get("zones") or [])
        sets["adhesion.zones"] = zones + [_zone(parts["zone"], study.where("factors"))]
    return sets


def _describe(values: dict) -> str:
    return ", ".join(f"{k}={v['name'] if isinstance(v, dict) else v}" for k, v in values.items())


def plan(study: Study, keep=None) -> list[Run]:
    """Every run of the study, resolved and keyed; keep(factors) -> bool leaves points out before
    they are resolved (wsp tune --only)."""
    design_seq, noise_seq = np.random.SeedSequence(study.spec.seed).spawn(2)
    points = designs.points(study, np.random.default_rng(design_seq))
    noise = [int(s) for s in noise_seq.generate_state(study.spec.seeds)]
    base_tree = configuration.tree(configuration.resolve(study.base))
    derived = json.dumps(study.spec.assessment.build_up, sort_keys=True) if study.spec.assessment else ""
    runs: list[Run] = []
    for p_index, point in enumerate(points):
        sets = point_sets(study, point.values, base_tree)
        factors = {f.name: (f.si(point.values[f.name]) if f.name in point.values else None)
                   for f in study.factors}
        if keep is not None and not keep(factors):
            continue
        for r, seed in enumerate(noise):
            run_sets = dict(sets, **{SEED_KEY: seed})
            try:
                resolved = configuration.resolve(study.base, run_sets)
            except InputError as exc:
                raise InputError(f"{study.origin}: design point {p_index} ({_describe(point.values)}): {exc}") from None
            runs.append(Run(len(runs), p_index, r, seed, run_sets, factors, point.block, point.sample,
                            identity.run_key(resolved.canonical(), derived)))
    return runs
