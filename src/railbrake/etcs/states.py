"""Failure states of a train of brake units, enumerated with its symmetry.

Equal units that fail independently with probability p per demand: the states that differ only in
which units failed are one state, "k of n lost", with probability C(n, k) p^k (1 - p)^(n - k)
(the binomial law). States are listed from k = 0 up while the probability of the rest is still
above `floor` (the highest confidence level's 1 - c, with a margin): what is left out counts as no
brake at all in the quantiles (railbrake.etcs.mixture.quantile), the safe side.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.stats import binom

from railbrake.errors import InputError


@dataclass(frozen=True)
class LostUnits:
    lost: int
    probability: float


def equal_units(n: int, p: float, floor: float = 1e-12) -> list[LostUnits]:
    """The states of n equal units, each lost with probability p, down to a rest below `floor`."""
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 1024:
        raise InputError(f"units = {n!r}: must be a whole number in [1, 1024]")
    if not (isinstance(p, (int, float)) and math.isfinite(p) and 0.0 <= p <= 1.0):
        raise InputError(f"probability per demand = {p!r}: must lie in [0, 1]")
    states = []
    for k in range(n + 1):
        states.append(LostUnits(k, float(binom.pmf(k, n, p))))
        if binom.sf(k, n, p) < floor:   # P(more than k lost)
            break
    return states
