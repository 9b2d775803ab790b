"""A sequence file (format railbrake.sequence/1, docs/sequences.md) read and checked: its tests,
steps, conditions and thresholds; every error names the file, the line and the key."""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from railbrake import config, scenario
from railbrake import _args
from railbrake._args import name_or_path
from railbrake.errors import InputError

FORMAT = "railbrake.sequence/1"
MAX_TESTS = 50
MAX_STEPS = 200

# the units a threshold or a time may carry: the scenario file's (pressures are gauge here: the
# caller adds the plant's atmosphere), by dimension
UNITS = scenario._UNITS
_QUANTITY = scenario._QUANTITY
# the SI unit of a recorded channel or KPI -> the dimension its thresholds are written in
CHANNEL_DIMENSION = {"m/s": "speed", "m": "length", "s": "time", "m/s^2": "acceleration", "m/s²": "acceleration",
                     "Pa": "pressure", "1": None, "": None}
COMPARISONS = ("below", "above", "at_most", "at_least")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Condition(_Strict):
    """A signal or a KPI against a threshold. signal: a recorded channel, or a pattern (slip_*) for
    the largest absolute value of the channels it matches; kpi: a KPI of the run so far."""
    signal: str | None = None
    kpi: str | None = None
    below: float | str | None = None
    above: float | str | None = None
    at_most: float | str | None = None
    at_least: float | str | None = None


class Expect(Condition):
    name: str | None = None
    within: str | None = None   # becomes true at a sample within this time from the step
    during: str | None = None   # holds at every sample for this time from the step


class WaitUntil(_Strict):
    until: Condition
    timeout: str


class WaitAt(_Strict):
    at: str                     # the plant time to wait for (from the test's start)


class Demand(_Strict):
    emergency: bool = False
    service: float = Field(default=0.0, ge=0.0, le=1.0)


class RecordKpi(_Strict):
    name: str
    signal: str | None = None
    kpi: str | None = None
    stat: Literal["max", "min", "final"] = "final"   # of the signal over the test so far


class Step(_Strict):
    set_demand: Demand | None = None
    set_adhesion: str | None = None     # an adhesion condition (railbrake adhesion list) everywhere
    inject: dict | None = None          # a fault as in a scenario file's faults (no start)
    clear: dict | None = None
    wait: str | WaitUntil | WaitAt | None = None
    expect: Expect | None = None
    kpi: RecordKpi | None = None

    @property
    def action(self) -> str:
        return next(name for name in type(self).model_fields if getattr(self, name) is not None)


class Test(_Strict):
    name: str
    steps: list[Step] = Field(min_length=1, max_length=MAX_STEPS)


class SequenceFile(_Strict):
    format: Literal["railbrake.sequence/1"]
    name: str
    title: str = ""
    scenario: str                       # preset or scenario file: train, speed, adhesion, demand at start
    cars: int | None = Field(default=None, ge=1, le=16)
    tests: list[Test] = Field(min_length=1, max_length=MAX_TESTS)


@dataclass(frozen=True)
class Threshold:
    """A checked comparison: `comparison` against `value` (SI, absolute pressure), as written."""
    comparison: str
    value: float
    written: str

    def holds(self, x):
        """Whether x (a number or an array) meets the threshold (NaN never does)."""
        return {"below": np.less, "above": np.greater, "at_most": np.less_equal,
                "at_least": np.greater_equal}[self.comparison](x, self.value)


@dataclass
class Sequence:
    spec: SequenceFile
    origin: str
    locate: object   # key path -> "file, line N"

    def where(self, *key) -> str:
        return f"{self.locate(key)}: {'.'.join(map(str, key))}"


def presets() -> list[str]:
    folder = resources.files("railbrake") / "data" / "sequences"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".yaml"))


def load(name: str | Path) -> Sequence:
    """A shipped preset by name, or a sequence file; checked in full (InputError: file, line, key)."""
    text = name_or_path("name (sequence)", name)
    if text in presets():
        origin = f"sequence preset {text}"
        source = (resources.files("railbrake") / "data" / "sequences" / f"{text}.yaml").read_text()
    elif Path(text).is_file():
        origin, source = text, config.read_text(text)
    else:
        raise InputError(f"name (sequence) = {_args.show(text)}: not a preset ({', '.join(presets())}) nor a file")
    return parse(source, origin)


def parse(text: str, origin: str) -> Sequence:
    _args.text("text", text), _args.text("origin", origin)
    data, lines = config._checked_mapping(text, origin)
    locate = config.locator(origin, lines)
    spec = config.validate_data(data, SequenceFile, locate)
    sequence = Sequence(spec, origin, locate)
    for i, test in enumerate(spec.tests):
        for j, step in enumerate(test.steps):
            given = [name for name in Step.model_fields if getattr(step, name) is not None]
            if len(given) != 1:
                raise InputError(f"{sequence.where('tests', i, 'steps', j)}: {len(given)} actions "
                                 f"({', '.join(given) or 'none'}): a step has exactly one of "
                                 f"{', '.join(Step.model_fields)}")
    return sequence


def quantity(text, dimension: str | None, where: str) -> float:
    """A threshold or time as written -> SI (pressures absolute: bar gauge + atmosphere is done by
    the caller, who knows the plant's atmosphere). Dimensionless: a plain number."""
    if dimension is None:
        if isinstance(text, (int, float)) and not isinstance(text, bool):
            return float(text)
        raise InputError(f"{where} = {text!r}: expected a plain number (the signal has no unit)")
    _args.text("where", where)
    if dimension is not None:
        _args.choice("dimension", dimension, sorted({d for d, _ in UNITS.values()}))
    allowed = [u for u, (d, _) in UNITS.items() if d == dimension]
    if isinstance(text, str) and any(ch.isdigit() and not ch.isascii() for ch in text):
        raise InputError(f"{where} = {text!r}: digits must be ASCII 0-9 (not another script's digits)")
    match = _QUANTITY.match(text) if isinstance(text, str) else None
    if not match or match.group(2) not in allowed:
        raise InputError(f"{where} = {text!r}: expected '<number> <unit>', unit one of {', '.join(allowed)}")
    return float(match.group(1)) * UNITS[match.group(2)][1]


def duration(text, where: str, low: float = 0.0, high: float = 3600.0) -> float:
    low, high = _args.real("low", low), _args.real("high", high)
    value = quantity(text, "time", where)
    if not low <= value <= high:
        raise InputError(f"{where} = {text!r}: must lie in [{low:g}, {high:g}] s")
    return value


def matching(pattern: str, channels: dict, where: str) -> list[str]:
    """The recorded channels a signal names (a name, or a pattern with * and ?)."""
    _args.text("pattern", pattern), _args.mapping("channels", channels), _args.text("where", where)
    names = [n for n in channels if n != "time" and fnmatch.fnmatchcase(n, pattern)]
    if not names:
        raise InputError(f"{where} = {pattern!r}: no recorded channel matches (e.g. speed, slip_*, "
                         "cylinder_c3a2)")
    units = {channels[n] for n in names}
    if len(units) > 1:
        raise InputError(f"{where} = {pattern!r}: matches channels of different units ({', '.join(sorted(units))})")
    return names
