"""What moves Kdry_rst most (the engineer's "what to improve"), from the runs already made.

For each entry of the reliability file (a failure of a unit, or a common-cause group) and each
tolerance of the scatter file, per speed step and M_NVEBCL: the gain of Kdry_rst (unrounded) if it
were removed, that is Kdry_rst with it minus Kdry_rst without it, the larger the more it costs.

- A failure with probability zero: the states it is in drop out and every other state's
  probability is divided by the probability that none of its sites failed ((1 - q)^n over its n
  sites in the train; 1 - p for a common-cause group): exact, as the states' probabilities are
  products over the sites (railbrake.etcs.failures). The states' samples stay as they are.
- A tolerance fixed at its nominal: each run's ratio less the tolerance's first-order share,
  beta (mean over the cars of f_c - 1), with the slope beta fitted by least squares on the
  no-failure state's runs (its many samples) and scaled per state by the state's mean ratio to the
  no-failure state's (a state that lost brakes has less brake force for a tolerance to act on).
  A first-order estimate: a ranking, not a safety figure.

The quantiles are read on a grid of GRID points over the ratios' range (linear between them),
each variant against the same grid's reading of the analysis itself, so that the differences
carry no grid error of their own.
"""

from __future__ import annotations

import numpy as np

from railbrake.etcs import bound, confidence
from railbrake.etcs.inputs import QUANTITIES

GRID = 4001
TOP = 5   # entries per level in the report


def _grid(ratios: list, j: int) -> np.ndarray:
    high = max(float(r[:, j].max()) for r in ratios)
    return np.linspace(0.0, max(high, 1.0) + 0.05, GRID)


def _cdfs(ratios: list, j: int, xs: np.ndarray) -> np.ndarray:
    cache: dict = {}
    return np.array([bound.state_cdf(np.sort(r[:, j]), xs, cache) for r in ratios])


def _levels(xs: np.ndarray, cdfs: np.ndarray, weights: np.ndarray, missing: float) -> list[float]:
    total = missing + weights @ cdfs
    return [0.0 if missing >= 1.0 - c else bound._quantile(xs, total, 1.0 - c) for c in confidence.EBCL]


def _in_state(ctx, state, failure: int) -> bool:
    """Whether failure `failure` of the reliability file is among the state's failed sites."""
    for c, o in zip(ctx.classes, state.outcome):
        counts = c.options[o][0]
        if any(k and any(s.failure == failure for s in config) for config, k in zip(c.configurations, counts)):
            return True
    return False


def _failure_name(f) -> str:
    value = (f" {f.pressure_bar:g} bar" if f.pressure_bar is not None else
             f" {f.leak_area_mm2:g} mm2" if f.leak_area_mm2 is not None else "")
    return f"{f.kind}{value} ({f.unit})"


def _failure_weights(ctx) -> list[tuple[str, str, np.ndarray]]:
    """(name, type, state probabilities with it removed) of every failure and common-cause group."""
    from railbrake.etcs.failures import _sites
    rel, n_cars = ctx.reliability, len(ctx.train.cars)
    car_sites, train_sites = _sites(rel)
    p = np.array([s.probability for s in ctx.states])
    out = []
    for i, f in enumerate(rel.failures):
        q = f.probability()
        if q == 0.0 or q >= 1.0:
            continue
        n = sum(s.failure == i for s in car_sites) * n_cars + sum(s.failure == i for s in train_sites)
        if f.unit == "train":
            where = len(ctx.classes) + [s.failure for s in train_sites].index(i)
            hit = np.array([s.outcome[where] == 1 for s in ctx.states])
        else:
            hit = np.array([_in_state(ctx, s, i) for s in ctx.states])
        out.append((_failure_name(f), "failure", np.where(hit, 0.0, p / (1.0 - q) ** n)))
    start = len(ctx.classes) + len(train_sites)
    for g_index, g in enumerate(rel.common_cause):
        if not 0.0 < g.per_demand < 1.0:
            continue
        hit = np.array([s.outcome[start + g_index] == 1 for s in ctx.states])
        out.append((g.name, "common cause", np.where(hit, 0.0, p / (1.0 - g.per_demand))))
    return out


def _regressors(draws: np.ndarray, columns: list) -> np.ndarray:
    """(runs, len(columns)): each column's factors' mean deviation from nominal over its cars."""
    return np.column_stack([draws[:, q, list(cars)].mean(axis=1) - 1.0 for q, cars in columns])


def _tolerance_ratios(ctx, ratios: list, samples: list) -> list[tuple[str, list]]:
    """(name, ratios with that tolerance at nominal) of every tolerance of the scatter file."""
    if ctx.scatter is None or not ctx.scatter.quantities():
        return []
    reference = int(np.argmax([len(r) for r in ratios]))   # the no-failure state: the most runs
    n_cars = len(ctx.train.cars)
    draws = [np.array([ctx.draw(s, i) for i in idx]) for s, idx in enumerate(samples)]
    given = ctx.scatter.quantities()
    # one slope per tolerance on its mean over the cars: a slope per car would fit the other
    # tolerances' scatter too (dozens of columns on a long train) and so credit each tolerance
    # with a share of the rest
    columns = [(QUANTITIES.index(q), tuple(range(n_cars))) for q in given]
    x = np.column_stack([np.ones(len(ratios[reference])), _regressors(draws[reference], columns)])
    beta = np.linalg.lstsq(x, ratios[reference], rcond=None)[0][1:]
    mean0 = ratios[reference].mean(axis=0)
    out = []
    for q in given:
        mine = [k for k, (qi, _) in enumerate(columns) if qi == QUANTITIES.index(q)]
        adjusted = []
        for r, d in zip(ratios, draws):
            scale = r.mean(axis=0) / np.where(mean0 > 0.0, mean0, 1.0)
            adjusted.append(r - (_regressors(d, [columns[k] for k in mine]) @ beta[mine]) * scale)
        out.append((q, adjusted))
    return out


def ranking(ctx, ratios: list, samples: list, missing: float) -> list[dict]:
    """Per M_NVEBCL: every failure, common-cause group and tolerance with its Kdry_rst gain per
    speed step (lowest first) if removed, the largest gain first. ratios: per state, (runs, steps);
    samples: per state, its runs' sample indices (for their scatter draws)."""
    n_steps = ratios[0].shape[1]
    p = np.array([s.probability for s in ctx.states])
    gains: dict = {}
    variants = _failure_weights(ctx)
    tolerances = _tolerance_ratios(ctx, ratios, samples)
    for j in range(n_steps):
        xs = _grid(ratios, j)
        cdfs = _cdfs(ratios, j, xs)
        base = _levels(xs, cdfs, p, missing)
        for name, kind, w in variants:
            moved = _levels(xs, cdfs, w, max(0.0, 1.0 - float(w.sum())))
            gains.setdefault((name, kind), []).append([m - b for m, b in zip(moved, base)])
        for name, adjusted in tolerances:
            moved = _levels(xs, _cdfs(adjusted, j, xs), p, missing)
            gains.setdefault((name, "tolerance"), []).append([m - b for m, b in zip(moved, base)])
    out = []
    for level in range(len(confidence.EBCL)):
        entries = [{"name": name, "type": kind, "kdry_gain": [float(step[level]) for step in per_step],
                    "largest_gain": float(max(step[level] for step in per_step))}
                   for (name, kind), per_step in gains.items()]
        entries.sort(key=lambda e: -e["largest_gain"])
        out.append({"M_NVEBCL": level, "EBCL": confidence.ebcl_text(level), "ranking": entries})
    return out
