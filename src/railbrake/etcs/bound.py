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
(GRID points: its spacing, 0.0005, a tenth of the 0.005 target), linear between its points: first on a
quarter of the window at that resolution (where almost every bound lies; the work goes with the
grid's points), then, for a bound that reaches its edge, on the whole window.
"""

from __future__ import annotations

import numpy as np
from scipy.special import ndtr
from scipy.stats import norm

GRID = 401
CARRY = 1e-4          # a state carries the quantile if its CDF share moves by this x level
COVERAGE = 0.95
NARROW = 4            # the first reading's window: this fraction of the whole
EDGE = 0.9            # a bound beyond this share of its window is read on the whole window
PASS_ELEMENTS = 4_000_000   # samples and grid values of one pass of state_cdfs (its memory: a few of these)


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


def state_cdfs(samples: np.ndarray, xs: np.ndarray, cache: dict) -> np.ndarray:
    """state_cdf of many samples at once: (B, len(xs)) for the sorted rows of samples (B, n), as
    B calls of state_cdf give (the bootstrap's replicates of one state in one pass)."""
    b, n = samples.shape
    z = _probits(n, cache)
    low, high = samples[:, :1], samples[:, -1:]
    if n == 1:
        return (xs[None, :] >= low).astype(float)
    sd = samples.std(axis=1, ddof=1)[:, None]
    # every row's interpolation in one searchsorted: the rows shifted apart by more than any span
    span = float(max(samples.max(), xs.max()) - min(samples.min(), xs.min())) + 1.0
    shift = (np.arange(b) * span)[:, None]
    k = np.searchsorted((samples + shift).ravel(), (xs[None, :] + shift).ravel(), side="right")
    k = np.clip(k.reshape(b, xs.size) - np.arange(b)[:, None] * n, 1, n - 1)
    x0, x1 = np.take_along_axis(samples, k - 1, axis=1), np.take_along_axis(samples, k, axis=1)
    gap = x1 - x0
    t = np.divide(xs[None, :] - x0, gap, out=np.ones_like(gap), where=gap > 0.0)
    inside = z[k - 1] + t * (z[k] - z[k - 1])
    safe_sd = np.where(sd > 0.0, sd, 1.0)
    probit = np.where(xs < low, z[0] + (xs - low) / safe_sd, np.where(xs > high, z[-1] + (xs - high) / safe_sd, inside))
    out = ndtr(probit)
    step = (low == high).ravel()
    if step.any():   # a sample of one value: a step (state_cdf)
        out[step] = (xs[None, :] >= low[step]).astype(float)
    return out


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
    # first on a quarter of the window at the same resolution; a bound that reaches its edge (a
    # replicate there may lie beyond it) is read again on the whole window
    for width, points in ((window / NARROW, (GRID - 1) // NARROW + 1), (window, GRID)):
        low, high, carrying = _bound_on(states, level, estimate, missing, rng, replicates, width, points)
        if max(low, high) < width * EDGE:
            break
    return low, high, carrying


def _bound_on(states: list, level: float, estimate: float, missing: float, rng: np.random.Generator,
              replicates: int, window: float, points: int) -> tuple[float, float, list[int]]:
    xs = np.linspace(estimate - window, estimate + window, points)
    cache: dict = {}
    fixed = np.full(points, missing)
    carrying = []
    for i, s in enumerate(states):
        f = s.probability * state_cdf(s.ratios, xs, cache)
        if s.ratios[0] != s.ratios[-1] and f[-1] - f[0] >= CARRY * level:
            carrying.append(i)
        else:
            fixed += f
    if not carrying:
        return 0.0, 0.0, []
    cdfs = np.tile(fixed, (replicates, 1))
    by_size: dict[int, list] = {}
    for i in carrying:   # each state's replicates drawn in the states' order, then
        s = states[i]
        samples = np.sort(s.ratios[rng.integers(0, s.ratios.size, (replicates, s.ratios.size))], axis=1)
        by_size.setdefault(s.ratios.size, []).append((s.probability, samples))
    for n, group in by_size.items():   # those of one sample size in few passes of state_cdfs
        per_pass = max(1, PASS_ELEMENTS // (replicates * (n + points)))
        for k in range(0, len(group), per_pass):
            part = group[k:k + per_pass]
            found = state_cdfs(np.concatenate([r for _, r in part]), xs, cache).reshape(len(part), replicates, points)
            cdfs += np.tensordot(np.array([p for p, _ in part]), found, axes=1)
    qs = np.array([_quantile(xs, cdf, level) for cdf in cdfs])
    low, high = np.quantile(qs, [(1 - COVERAGE) / 2, (1 + COVERAGE) / 2])
    return max(0.0, estimate - float(low)), max(0.0, float(high) - estimate), carrying

