"""ETCS emergency-brake confidence levels and the coding of the correction factors.

UNISIG SUBSET-026 3.13.2.2.9 and 7.5.1 (M_NVEBCL): the emergency brake confidence level the
on-board uses, coded 0-9 as 50 %, 90 %, 99 %, 99.9 %, ... 99.9999999 %.

Kdry_rst(V, EBCL) and Kwet_rst(V) are train data of a train with its own braking model
(SUBSET-026 3.13.2.2.9): dimensionless factors on A_brake_emergency per speed step. They are not
variables of SUBSET-026's chapter 7 (no packet carries them), so the specification gives them no
bit coding; what this module writes is the project's own grid [T]: 0 to 1 (above 1 a train brakes
better than its nominal curve: coded as 1, the safe side; OSRD's k_dry and k_wet take [0, 1]) in
steps of 0.05, every factor rounded down so the coded value never promises more deceleration than
was computed.
"""

from __future__ import annotations

import math

from railbrake._args import real, whole

# M_NVEBCL -> probability that the emergency brake achieves at least A_brake_emergency x Kdry_rst
EBCL = (0.5, 0.9, 0.99, 0.999, 0.9999, 0.99999, 0.999999, 0.9999999, 0.99999999, 0.999999999)
CODES_PER_UNIT = 20           # the grid's resolution: 0.05
K_STEP = 1 / CODES_PER_UNIT
K_MAX = 1.0                   # the largest coded value
# each variable's unit, range, resolution, rounding and clause, as written into braking-model.json
CODINGS = {
    "A_brake_emergency": {"unit": "m/s^2", "range": [0.0, None], "resolution": 0.01, "rounding": "down",
                          "clause": "SUBSET-026 3.13.2.2.9 (train data: A_brake_emergency(V), a step function)",
                          "grid": "[T] this project's"},
    "T_brake_emergency": {"unit": "s", "range": [0.0, None], "resolution": 0.1, "rounding": "up",
                          "clause": "SUBSET-026 3.13.2.2.9 (train data: T_brake_emergency)",
                          "grid": "[T] this project's"},
    "Kdry_rst": {"unit": "1", "range": [0.0, K_MAX], "resolution": K_STEP, "rounding": "down",
                 "clause": "SUBSET-026 3.13.2.2.9 (train data: Kdry_rst(V, EBCL)); not a chapter 7 variable",
                 "grid": "[T] this project's"},
    "Kwet_rst": {"unit": "1", "range": [0.0, K_MAX], "resolution": K_STEP, "rounding": "down",
                 "clause": "SUBSET-026 3.13.2.2.9 (train data: Kwet_rst(V)); not a chapter 7 variable",
                 "grid": "[T] this project's"},
}


def ebcl_text(index: int) -> str:
    """The confidence level of M_NVEBCL = index written exactly: "50 %", "90 %", "99.9999999 %"."""
    ebcl(index)
    if index < 2:
        return ("50 %", "90 %")[index]
    return "99" + ("." + "9" * (index - 2) if index > 2 else "") + " %"


def on_grid(x: float, resolution: float, rounding: str) -> float:
    """x rounded onto a grid of `resolution`, "down" or "up" (the safe side of the variable)."""
    steps = x / resolution
    n = math.floor(steps + 1e-9) if rounding == "down" else math.ceil(steps - 1e-9)
    return round(n * resolution, 10)


def ebcl(index: int) -> float:
    """The confidence level of M_NVEBCL = index (0-9)."""
    return EBCL[whole("index (M_NVEBCL)", index, 0, len(EBCL) - 1)]


def coded(k: float) -> float:
    """k rounded down onto the 0.05 grid (0 to 1; above 1, 1: a train that brakes better than its
    nominal curve is not credited with it)."""
    k = real("k (correction factor)", k, 0.0)
    steps = math.floor(min(k, 2.0) * CODES_PER_UNIT + 1e-9)   # 0.95 * 20 may fall a rounding below 19
    return min(steps, CODES_PER_UNIT) / CODES_PER_UNIT
