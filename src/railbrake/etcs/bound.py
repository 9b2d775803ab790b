"""The sampling uncertainty of Kdry_rst: a bootstrap within the failure states.

Each state's scatter sample is its own (independent of every other state's, railbrake.etcs.scatter
.block_draws), so the states' estimates of F_s are independent and the mixture's quantile can be
resampled state by state: every state's runs drawn again with replacement (the states'
probabilities are exact, not sampled), the quantile found again, `replicates` times (Efron &
Tibshirani 1993, ch. 6 and 13: the percentile bootstrap of a quantile). The bound of a level is the
larger distance from the estimate to the 2.5 % and 97.5 % points of the replicates; the coded value
takes the estimate less the lower distance (the conservative side).

Only the states that carry the quantile are resampled: those whose share of the mixture's CDF
changes by at least 1e-4 of the level across the window the quantile may move in; the others,
whose contribution does not move there, are held (their resampling could not move the quantile by
more than that share, a small fraction of the bound). The quantiles are read on a grid of the window
(GRID points: its resolution well below the 0.005 target), linear between its points.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import norm

GRID = 801
CARRY = 1e-4          # a state carries the quantile if its CDF share moves by this x level
COVERAGE = 0.95


def _probits(n: int, cache: dict) -> np.ndarray:
    if n not in cache:
        cache[n] = norm.ppf((np.arange(n) + 0.5) / n)
    return cache[n]


def state_cdf(ratios: np.ndarray, xs: np.ndarray, cache: dict) -> np.ndarray:
    """A state's CDF (railbrake.etcs.mixture.State.cdf) at every x of xs, its sample sorted."""
    r = ratios
    if r[0] == r[-1]:
        return (xs >= r[0]).astype(float)
    z = _probits(r.size, cache)
    sd = float(r.std(ddof=1))
    inside = np.interp(xs, r, z)
    below = z[0] + (xs - r[0]) / sd
    above = z[-1] + (xs - r[-1]) / sd
    return norm.cdf(np.where(xs < r[0], below, np.where(xs > r[-1], above, inside)))


def _quantile(xs: np.ndarray, cdf: np.ndarray, level: float) -> float:
    i = int(np.searchsorted(cdf, level))
    if i == 0:
        return float(xs[0])
    if i >= xs.size:
        return float(xs[-1])
    f0, f1 = cdf[i - 1], cdf[i]
    return float(xs[i - 1] + (xs[i] - xs[i - 1]) * ((level - f0) / (f1 - f0) if f1 > f0 else 1.0))


def bound(states: list, level: float, estimate: float, missing: float, rng: np.random.Generator,
          replicates: int, window: float) -> tuple[float, float, list[int]]:
    """(lower distance, upper distance, carrying states) of the quantile at `level` of the
    states' mixture (railbrake.etcs.mixture.State, missing: the probability of the states left
    out, as no brake), estimate its value on the full samples."""
    if estimate <= 0.0 or missing >= level:
        return 0.0, 0.0, []
    xs = np.linspace(estimate - window, estimate + window, GRID)
    cache: dict = {}
    fixed = np.full(GRID, missing)
    carrying = []
    for i, s in enumerate(states):
        f = s.probability * state_cdf(s.ratios, xs, cache)
        if s.ratios[0] != s.ratios[-1] and f[-1] - f[0] >= CARRY * level:
            carrying.append(i)
        else:
            fixed += f
    if not carrying:
        return 0.0, 0.0, []
    qs = np.empty(replicates)
    for b in range(replicates):
        cdf = fixed.copy()
        for i in carrying:
            s = states[i]
            sample = np.sort(s.ratios[rng.integers(0, s.ratios.size, s.ratios.size)])
            cdf += s.probability * state_cdf(sample, xs, cache)
        qs[b] = _quantile(xs, cdf, level)
    low, high = np.quantile(qs, [(1 - COVERAGE) / 2, (1 + COVERAGE) / 2])
    return max(0.0, estimate - float(low)), max(0.0, float(high) - estimate), carrying

