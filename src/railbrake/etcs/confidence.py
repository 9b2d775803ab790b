"""ETCS emergency-brake confidence levels and the coding of the correction factors.

UNISIG SUBSET-026 3.13.2.2.9 and 7.5.1.81 (M_NVEBCL): the emergency brake confidence level the
on-board uses, coded 0-9 as 50 %, 90 %, 99 %, 99.9 %, ... 99.9999999 %. Kdry_rst and Kwet_rst are
train data coded in 5 bits from 0 to 1.55 in steps of 0.05 (SUBSET-026 7.5.1, train data
packet); a factor is rounded down onto that grid so the coded value never promises more
deceleration than was computed.
"""

from __future__ import annotations

import math

from railbrake._args import real, whole

# M_NVEBCL -> probability that the emergency brake achieves at least A_brake_emergency x Kdry_rst
EBCL = (0.5, 0.9, 0.99, 0.999, 0.9999, 0.99999, 0.999999, 0.9999999, 0.99999999, 0.999999999)
CODES_PER_UNIT = 20           # the 5-bit coding's resolution: 0.05
K_STEP = 1 / CODES_PER_UNIT
K_MAX = 31 / CODES_PER_UNIT   # 1.55: the largest coded value


def ebcl(index: int) -> float:
    """The confidence level of M_NVEBCL = index (0-9)."""
    return EBCL[whole("index (M_NVEBCL)", index, 0, len(EBCL) - 1)]


def coded(k: float) -> float:
    """k rounded down onto the 0.05 grid of the train data (0 to 1.55; above 1.55, the largest
    code: a train that brakes that much better than its nominal curve is coded as 1.55)."""
    k = real("k (correction factor)", k, 0.0)
    steps = math.floor(min(k, 2.0) * CODES_PER_UNIT + 1e-9)   # 0.95 * 20 may fall a rounding below 19
    return min(steps, 31) / CODES_PER_UNIT
