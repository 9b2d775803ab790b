"""A study's runs: design points x noise seeds, keyed before anything runs (one at a time).

The seeds come from one ``numpy.random.SeedSequence(study.seed)``: one child draws the design,
the other gives the noise seeds, the same for every point (common random numbers, so points
differ by their factors only). One run per factor value is resolved up front, so a bad value (a
fault on a car the train lacks) fails before the first simulation.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

from railbrake.campaign import configuration, designs, identity
from railbrake.campaign.points import point_sets
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


def _describe(values: dict) -> str:
    return ", ".join(f"{k}={v['name'] if isinstance(v, dict) else v}" for k, v in values.items())


def plan(study: Study, keep=None) -> list[Run]:
    """Every run of the study, keyed (iter_plan), as a list; keep(factors) -> bool leaves points
    out (wsp tune --only)."""
    return list(iter_plan(study, keep))


def iter_plan(study: Study, keep=None):
    """The study's runs one at a time, each keyed without being resolved: the key is the digest of
    the resolved base configuration with the run's overrides (so a study of 10^5 runs is keyed in
    seconds and never held whole). Before the first run, one run per level of each factor (and the
    first of each noise seed) is resolved, so that a bad value fails before anything runs; a bad
    combination of good values fails in its own run, recorded with its error."""
    base = configuration.resolve(study.base)
    base_tree, base_canonical = configuration.tree(base), base.canonical()
    derived = "te: en14531 total brake force" if study.spec.assessment else ""   # how te is measured
    checked: set = set()
    index = 0
    for p_index, point, sets, factors, noise in _points(study, base_tree, keep):
        for r, seed in enumerate(noise):
            run_sets = dict(sets, **{SEED_KEY: seed})
            _check_once(study, p_index, point, run_sets, r, checked)
            key = identity.run_key(base_canonical + "\n" + json.dumps(run_sets, sort_keys=True, default=str), derived)
            yield Run(index, p_index, r, seed, run_sets, factors, point.block, point.sample, key)
            index += 1


def _points(study: Study, base_tree: dict, keep):
    design_seq, noise_seq = np.random.SeedSequence(study.spec.seed).spawn(2)
    noise = [int(s) for s in noise_seq.generate_state(study.spec.seeds)]
    for p_index, point in enumerate(designs.points(study, np.random.default_rng(design_seq))):
        factors = {f.name: (f.si(point.values[f.name]) if f.name in point.values else None)
                   for f in study.factors}
        if keep is not None and not keep(factors):
            continue
        yield p_index, point, point_sets(study, point.values, base_tree), factors, noise


def _check_once(study: Study, p_index: int, point, run_sets: dict, replicate: int, checked: set) -> None:
    """Resolve the run if it is the first with one of its factors' levels, or of its seed (a
    factor drawn from a range has its range checked with the study file)."""
    listed = {f.name for f in study.factors if f.low is None}
    firsts = {(name, json.dumps(value, sort_keys=True, default=str)) for name, value in point.values.items()
              if name in listed}
    firsts.add(("seed", replicate))
    if firsts <= checked:
        return
    checked |= firsts
    try:
        configuration.resolve(study.base, run_sets)
    except InputError as exc:
        raise InputError(f"{study.origin}: design point {p_index} ({_describe(point.values)}): {exc}") from None
