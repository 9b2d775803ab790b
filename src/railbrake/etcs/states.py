"""Failure states of a train of brake units, enumerated with its symmetry.

Equal units that fail independently with probability p per demand: the states that differ only in
which units failed are one state, "k of n lost", with probability C(n, k) p^k (1 - p)^(n - k)
(the binomial law). States are listed from k = 0 up while the probability of the rest is still
above `floor` (the highest confidence level's 1 - c, with a margin): what is left out counts as no
brake at all in the quantiles (railbrake.etcs.mixture.quantile), the safe side.
"""

from __future__ import annotations

from dataclasses import dataclass

from scipy.stats import binom

from railbrake._args import real, whole


@dataclass(frozen=True)
class LostUnits:
    lost: int
    probability: float


def equal_units(n: int, p: float, floor: float = 1e-12) -> list[LostUnits]:
    """The states of n equal units, each lost with probability p, down to a rest below `floor`."""
    n = whole("n (units)", n, 1, 1024)
    p = real("p (probability per demand)", p, 0.0, 1.0)
    floor = real("floor", floor, 0.0, 1.0, low_open=True)
    states = []
    for k in range(n + 1):
        states.append(LostUnits(k, float(binom.pmf(k, n, p))))
        if binom.sf(k, n, p) < floor:   # P(more than k lost)
            break
    return states
