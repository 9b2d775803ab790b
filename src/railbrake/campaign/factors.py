"""Factors of a study: a list of levels or a range {low, high[, levels]}, values with units.

A level keeps its file form ("300 km/h") for the resolved configuration and its SI value for the
dataset. Faults and adhesion zones are factors too, by their parts: ``fault.type``,
``fault.car``, ... add one fault to the run; ``zone.start``, ``zone.length``, ``zone.condition``
add one adhesion patch (the sudden adhesion changes of WSP tests). A factor whose levels are
mappings ``{name: dry, adhesion.condition: dry-medium, ...}`` is a named case: each level sets
several keys at once, and the dataset's column holds the level's name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from railbrake.campaign.budget import MAX_RUNS
from railbrake.config import named_unit_hint
from railbrake.errors import InputError
from railbrake.scenario import _QUANTITY, _UNITS

# the parts of the composite factors; a run gets one fault / one zone built from them
COMPOSITES = {
    "fault": ("type", "car", "axle", "start", "noise", "leak_area", "pressure"),
    "zone": ("start", "length", "condition"),
}
NO_FAULT = "none"   # fault.type level for the healthy train
SI_UNIT = {"speed": "m/s", "time": "s", "length": "m", "acceleration": "m/s^2", "pressure": "Pa", "pressure rate": "Pa/s",
           "area": "m^2"}


def quantity(value) -> tuple[float, str, str] | None:
    """'300 km/h' -> (83.33, 'km/h', 'speed'); None when the value is not a quantity."""
    if not isinstance(value, str):
        return None
    match = _QUANTITY.match(value)
    if not match or match.group(2) not in _UNITS:
        return None
    dimension, scale = _UNITS[match.group(2)]
    return float(match.group(1)) * scale, match.group(2), dimension


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


@dataclass
class Factor:
    name: str
    kind: str                       # quantity | integer | number | category
    unit: str = ""                  # SI unit of the dataset column (quantities)
    levels: list | None = None      # file values
    low: float | None = None        # range, SI (quantities) or plain number
    high: float | None = None
    file_unit: str = ""             # unit the range is written back in

    @property
    def bundle(self) -> bool:
        return self.kind == "case"

    def si(self, value):
        """SI value of a file value, for the dataset."""
        if self.kind == "case":
            return str(value["name"])
        if self.kind == "quantity":
            return quantity(value)[0]
        if self.kind == "integer":
            return int(value)
        if self.kind == "number":
            return float(value)
        return str(value)

    def at(self, u: float):
        """File value at the unit-cube coordinate u in [0, 1): a level, or a point of the range."""
        if self.levels is not None and self.low is None:
            return self.levels[min(int(u * len(self.levels)), len(self.levels) - 1)]
        if self.kind == "integer":   # every integer of [low, high] equally likely
            return int(min(self.high, math.floor(self.low + u * (self.high - self.low + 1))))
        x = self.low + u * (self.high - self.low)
        return self.file_value(x)

    def file_value(self, x: float):
        if self.kind == "integer":
            return int(round(x))
        if self.kind == "quantity":
            return f"{x / _UNITS[self.file_unit][1]:.12g} {self.file_unit}"
        return float(x)


def _level_kind(levels: list, where: str) -> tuple[str, str]:
    if all(isinstance(v, dict) for v in levels):
        names = [v.get("name") for v in levels]
        if None in names or len(set(names)) < len(names):
            raise InputError(f"{where}: every case (mapping) needs its own 'name'")
        return "case", ""
    parsed = [quantity(v) for v in levels]
    if all(p is not None for p in parsed):
        dims = {p[2] for p in parsed}
        if len(dims) > 1:
            raise InputError(f"{where}: levels mix {', '.join(sorted(dims))}")
        return "quantity", SI_UNIT[dims.pop()]
    if any(p is not None for p in parsed):
        raise InputError(f"{where} = {levels!r}: give every level with a unit or none")
    if all(isinstance(v, int) and not isinstance(v, bool) for v in levels):
        return "integer", ""
    if all(_number(v) for v in levels):
        return "number", ""
    return "category", ""


def _range(name: str, value: dict, where: str, max_levels: int) -> Factor:
    extra = set(value) - {"low", "high", "levels"}
    if extra or not {"low", "high"} <= set(value):
        raise InputError(f"{where}: a range is {{low: .., high: .., levels: N (grid, zip)}}, got keys "
                         f"{', '.join(map(str, value))}")
    low, high = value["low"], value["high"]
    ql, qh = quantity(low), quantity(high)
    if ql and qh:
        if ql[2] != qh[2]:
            raise InputError(f"{where}: low {low!r} and high {high!r} are not the same kind of quantity")
        f = Factor(name, "quantity", SI_UNIT[ql[2]], low=ql[0], high=qh[0], file_unit=ql[1])
    elif _number(low) and _number(high):
        kind = "integer" if isinstance(low, int) and isinstance(high, int) else "number"
        f = Factor(name, kind, low=float(low), high=float(high))
    else:
        raise InputError(f"{where}: low {low!r} and high {high!r} must both be numbers or quantities with units")
    if not f.low < f.high:
        raise InputError(f"{where}: low {low!r} >= high {high!r}; a range needs low < high")
    if "levels" in value:
        n = value["levels"]
        if not isinstance(n, int) or isinstance(n, bool) or n < 1:
            raise InputError(f"{where}.levels = {n!r}: a design with no runs (levels >= 1)")
        if n > max_levels:   # before the levels are made
            raise InputError(f"{where}.levels = {n}: more levels than the limit of {max_levels:,} runs "
                             "(raise it with --max-runs N)")
        points = [f.low] if n == 1 else np.linspace(f.low, f.high, n)
        f.levels = [f.file_value(float(x)) for x in points]
    return f


def make_factor(name: str, value: Any, where: str, max_levels: int = MAX_RUNS) -> Factor:
    given = [value.get("low"), value.get("high")] if isinstance(value, dict) else value if isinstance(value, list) else []
    for level in given:   # '60 t' for a key naming its unit (train.car_types.motor.tare_t): a bare number
        hint = named_unit_hint(name, level)
        if hint:
            raise InputError(f"{where} = {level!r}: {hint}")
    if isinstance(value, dict):
        return _range(name, value, where, max_levels)
    if not isinstance(value, list):
        raise InputError(f"{where} = {value!r}: a factor is a list of levels or a range {{low, high}}")
    if not value:
        raise InputError(f"{where}: an empty list of levels gives a design with no runs")
    kind, unit = _level_kind(value, where)
    for level in value:
        if isinstance(level, float) and not math.isfinite(level):
            raise InputError(f"{where}: level {level!r} is not finite")
    return Factor(name, kind, unit, levels=list(value))
