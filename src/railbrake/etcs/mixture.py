"""The distribution of the deceleration ratio over failure states, and its quantiles.

Each failure state (which brake units are lost) has a probability and, within it, a sample of the
deceleration ratio over the tolerances (pad friction, pressure control, rigging, wheel diameter,
load). The ratio's distribution is the mixture sum_s P(s) F_s(x). Kdry_rst at a confidence level
c is its quantile at 1 - c: the ratio the train reaches or exceeds with probability c.

Within a state the sample gives F_s: its plotting positions (i - 1/2) / n, on the normal
probability scale, linear in x between the sample's points, and beyond them, where the highest
levels (1e-9) may reach, straight on with the slope of a normal law of the sample's standard
deviation. The ratio within a state sums many small independent tolerances, so it is near normal
and this scale interpolates its tails well (exact for a normal sample; checked against a
brute-force Monte Carlo of the whole train). A state without scatter is a step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.stats import norm

from railbrake._args import items, real
from railbrake.errors import InputError


@dataclass(frozen=True)
class State:
    probability: float
    ratios: np.ndarray          # sorted sample of the deceleration ratio within the state
    label: str = ""
    probits: np.ndarray = None  # its plotting positions on the normal scale
    sd: float = 0.0

    @classmethod
    def of(cls, probability: float, ratios, label: str = "") -> "State":
        ratios = np.sort(np.asarray(ratios, dtype=float).ravel())
        if not (0.0 <= probability <= 1.0):
            raise InputError(f"state {label or '?'}: probability = {probability!r}: must lie in [0, 1]")
        if ratios.size == 0 or not np.all(np.isfinite(ratios)):
            raise InputError(f"state {label or '?'}: needs a sample of finite deceleration ratios")
        probits = norm.ppf((np.arange(ratios.size) + 0.5) / ratios.size)
        return cls(float(probability), ratios, label, probits, float(ratios.std(ddof=1)) if ratios.size > 1 else 0.0)

    def cdf(self, x: float) -> float:
        r, z, sd = self.ratios, self.probits, self.sd
        if r[0] == r[-1]:
            return 1.0 if x >= r[0] else 0.0
        if x < r[0]:
            return _phi(z[0] + (x - r[0]) / sd)
        if x > r[-1]:
            return _phi(z[-1] + (x - r[-1]) / sd)
        return _phi(float(np.interp(x, r, z)))


def _phi(z: float) -> float:
    """The standard normal CDF (scipy's, without its per-call cost: the quantile search calls it
    for every state at every step)."""
    return 0.5 * math.erfc(-z / math.sqrt(2.0))


def mixture_cdf(states: list[State], x: float) -> float:
    states, x = items("states", states, State), real("x", x, allow_inf=True)
    return sum(s.probability * s.cdf(x) for s in states)


def quantile(states: list[State], level: float) -> float:
    """The ratio x with P(ratio < x) = level (0 < level < 1) over the states' mixture. The states
    need not be every state of the train: those left out (their total probability well below the
    smallest level asked for) count as ratio 0, the safe side."""
    states = items("states", states, State)
    level = real("level", level, 0.0, 1.0, low_open=True, high_open=True)
    covered = sum(s.probability for s in states)
    if covered > 1.0 + 1e-9:
        raise InputError(f"the states' probabilities add up to {covered:.12g}: at most 1")
    missing = max(0.0, 1.0 - covered)   # states not enumerated: taken as no brake at all
    if missing >= level:
        return 0.0
    def excess(x: float) -> float:
        return missing + mixture_cdf(states, x) - level

    for x in sorted({float(s.ratios[0]) for s in states if s.ratios[0] == s.ratios[-1]}):
        if excess(math.nextafter(x, -math.inf)) < 0.0 <= excess(x):   # the level falls in a step's jump
            return x
    spread = max(float(np.ptp(s.ratios)) for s in states) + 1.0
    low = min(float(s.ratios[0]) for s in states) - 40.0 * spread    # normal tails: far below any level
    high = max(float(s.ratios[-1]) for s in states) + 40.0 * spread
    return brentq(excess, low, high, xtol=1e-12, rtol=1e-12)


def k_dry(states: list[State], confidence: float) -> float:
    """Kdry_rst at a confidence level: the ratio reached or exceeded with that probability."""
    return quantile(items("states", states, State), 1.0 - real("confidence", confidence, 0.0, 1.0, low_open=True,
                                                                  high_open=True))
