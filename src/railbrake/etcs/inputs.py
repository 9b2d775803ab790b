"""The ETCS braking model's input files: reliability (which brake faults, on which units, how
likely at a demand) and scatter (the tolerances of the brake's components), each validated in full
before any run, an error naming the file, line, key, value and what is allowed.

Reliability (schema railbrake.reliability/1): per fault kind of the plant (rb_fault_kind) and the
unit it hits, a probability per demand and/or a latent failure rate with the interval of the test
that finds it; common-cause groups fail several units at once.

Scatter (schema railbrake.scatter/1): per quantity a factor on the train file's nominal value,
drawn normal, truncated normal or uniform, once for the train or once per car (the plant's
parameters are per car).
"""

from __future__ import annotations

import functools
import math
from importlib import resources
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from railbrake import _core, config
from railbrake._args import name_or_path
from railbrake.errors import InputError

RELIABILITY_SCHEMA = "railbrake.reliability/1"
SCATTER_SCHEMA = "railbrake.scatter/1"

# the unit a fault kind of the plant hits (rb_plant.h, rb_fault_kind): a car's (EP valve, isolating
# cock, ED brake; the emergency path's: emergency valve, the loop's command to the car, relay valve,
# load-weighing valve / pressure limiter; a leak of its main-reservoir pipe, the train having no
# brake pipe), an axle's (WSP valves, speed sensor, cylinder, its isolating cock), or the train's
# (the air supply); "bogie" hits both axles
CAR_KINDS = ("ep_valve_failed", "car_isolated", "ed_lost", "emergency_valve_failed", "emergency_loop_lost",
             "relay_valve_failed", "pressure_limiter_failed", "pipe_leak")
AXLE_KINDS = ("hold_stuck_open", "hold_stuck_closed", "vent_stuck_open", "vent_stuck_closed", "sensor_lost",
              "sensor_noisy", "cylinder_leak", "axle_isolated")
TRAIN_KINDS = ("compressor_off",)
UNITS = {**{k: ("car",) for k in CAR_KINDS}, **{k: ("axle", "bogie") for k in AXLE_KINDS},
         **{k: ("train",) for k in TRAIN_KINDS}}
assert set(UNITS) == set(_core.FAULT_KINDS), "every fault kind of the plant has its units"
# the value a kind needs: a leak's area, a sensor's noise, the pressure (bar gauge) a failed relay
# holds its output at most at (0: no output) or a failed limiter limits the emergency pressure to
VALUE_KEYS = {"cylinder_leak": "leak_area_mm2", "pipe_leak": "leak_area_mm2", "sensor_noisy": "noise_kmh",
              "relay_valve_failed": "pressure_bar", "pressure_limiter_failed": "pressure_bar"}

# A normal factor without bounds must keep zero this many standard deviations below its mean
# (P < 1e-23): a factor on friction, pressure or mass cannot be negative.
UNBOUNDED_SIGMAS = 10.0
QUANTITIES = ("pad_friction", "pressure_control", "rigging_efficiency", "wheel_diameter", "load", "valve_response",
              "emergency_choke", "limiter_setting")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)


class Failure(_Strict):
    kind: str
    unit: str
    per_demand: float = Field(0.0, ge=0.0, le=1.0)              # probability per demand, per unit
    latent_rate_per_h: float = Field(0.0, ge=0.0, le=1.0)       # per unit and hour
    test_interval_h: float | None = Field(None, gt=0.0, le=1e6)   # the test that finds a latent failure
    leak_area_mm2: float | None = Field(None, gt=0.0, le=1e3)
    noise_kmh: float | None = Field(None, gt=0.0, le=100.0)
    pressure_bar: float | None = Field(None, ge=0.0, le=20.0)   # gauge
    source: str

    @model_validator(mode="after")
    def _consistent(self):
        if self.kind not in UNITS:
            raise ValueError(f"kind = {self.kind!r}: not a fault kind of the plant; one of {', '.join(UNITS)}")
        if self.unit not in UNITS[self.kind]:
            raise ValueError(f"unit = {self.unit!r}: a {self.kind} fault hits a {' or '.join(UNITS[self.kind])}")
        if self.latent_rate_per_h > 0.0 and self.test_interval_h is None:
            raise ValueError("latent_rate_per_h needs test_interval_h (the test that finds the latent failure)")
        needed = VALUE_KEYS.get(self.kind)
        for key in dict.fromkeys(VALUE_KEYS.values()):
            given = getattr(self, key) is not None
            if given and key != needed:
                users = " or ".join(k for k, v in VALUE_KEYS.items() if v == key)
                raise ValueError(f"{key}: only for a {users} fault, not {self.kind}")
            if key == needed and not given:
                raise ValueError(f"{key}: needed by a {self.kind} fault")
        return self

    def probability(self) -> float:
        """The probability that one unit has this fault at a demand: failing at the demand, or
        failed since the last test (a latent failure at rate l found by a test every T: its mean
        unavailability 1 - (1 - exp(-l T)) / (l T))."""
        latent = 0.0
        if self.latent_rate_per_h > 0.0:
            x = self.latent_rate_per_h * self.test_interval_h
            latent = 1.0 + math.expm1(-x) / x
        return 1.0 - (1.0 - self.per_demand) * (1.0 - latent)

    def value_si(self) -> float:
        if self.leak_area_mm2 is not None:
            return self.leak_area_mm2 * 1e-6
        if self.pressure_bar is not None:
            return self.pressure_bar * 1e5
        return (self.noise_kmh or 0.0) / 3.6


class CommonCause(_Strict):
    name: str
    kind: str
    cars: list[int] | Literal["all"]          # 1-based cars; every unit of the kind on them fails
    per_demand: float = Field(ge=0.0, le=1.0)
    source: str

    @model_validator(mode="after")
    def _known(self):
        if self.kind not in UNITS:
            raise ValueError(f"kind = {self.kind!r}: not a fault kind of the plant; one of {', '.join(UNITS)}")
        if self.kind in VALUE_KEYS:
            raise ValueError(f"kind = {self.kind!r}: needs a value per unit; give it as a failure instead")
        if self.cars != "all" and (not self.cars or any(c < 1 or c > _core.PLANT_MAX_CARS for c in self.cars)):
            raise ValueError(f"cars = {self.cars!r}: 'all' or 1-based car numbers in [1, {_core.PLANT_MAX_CARS}]")
        return self


class _File(_Strict):
    name: str
    title: str = ""
    source: str


class ReliabilityFile(_File):
    schema_: Literal["railbrake.reliability/1"] = Field(alias="schema")
    failures: list[Failure] = Field(max_length=64)
    common_cause: list[CommonCause] = Field(default_factory=list, max_length=16)

    @field_validator("common_cause")
    @classmethod
    def _groups_once(cls, groups):
        """A group given twice would fail its units twice as often: refused, by name and by what it fails."""
        seen: dict = {}
        for i, group in enumerate(groups):
            cars = "all" if group.cars == "all" else tuple(sorted(set(group.cars)))
            for key, what in ((("name", group.name), f"name {group.name!r}"),
                              (("fails", group.kind, cars), f"{group.kind} on cars {group.cars}")):
                if key in seen:
                    raise ValueError(f"common_cause[{i}] ({what}) is given twice (also common_cause[{seen[key]}]): "
                                     "a common cause is counted once")
                seen[key] = i
        return groups

    @model_validator(mode="after")
    def _once(self):
        seen = set()
        for f in self.failures:   # one kind on one unit may come with different values (a relay
            key = (f.kind, f.unit, f.value_si())   # with no output, one stuck at a partial pressure)
            if key in seen:
                raise ValueError(f"failures: {f.kind} on the {f.unit}" + (f" with value {f.value_si():g} (SI)"
                                 if f.value_si() else "") + " given twice")
            seen.add(key)
        # a group given twice (by name, or the same kind on the same cars) would count one
        # cause twice: refused, not summed
        names, groups = set(), set()
        for g in self.common_cause:
            cars = "all" if g.cars == "all" else tuple(sorted(set(g.cars)))
            if g.name in names or (g.kind, cars) in groups:
                raise ValueError(f"common_cause: the group {g.name!r} ({g.kind} on cars {g.cars}) is given twice: "
                                 "give each common cause once")
            if g.cars != "all" and len(set(g.cars)) != len(g.cars):
                raise ValueError(f"common_cause {g.name!r}: cars = {g.cars}: a car named twice")
            names.add(g.name)
            groups.add((g.kind, cars))
        return self


class Distribution(_Strict):
    distribution: Literal["normal", "truncated_normal", "uniform"]
    mean: float | None = Field(None, gt=0.0, le=10.0)
    sd: float | None = Field(None, ge=0.0, le=1.0)
    bounds: list[float] | None = Field(None, min_length=2, max_length=2)   # [low, high]
    # the tolerance's correlation: drawn once per train, per car, or per unit (each axle's brake,
    # the car's factor the mean of its units'); none given: its quantity's default
    # (data/etcs/factor-ranges.yaml, with its reasoning)
    per: Literal["train", "car", "unit"] | None = None
    source: str

    @model_validator(mode="after")
    def _complete(self):
        d = self.distribution
        if d != "uniform" and (self.mean is None or self.sd is None):
            raise ValueError(f"a {d} distribution needs mean and sd")
        if d == "uniform" and (self.mean is not None or self.sd is not None):
            raise ValueError("a uniform distribution takes bounds only (no mean, no sd)")
        if d != "normal" and self.bounds is None:
            raise ValueError(f"a {d} distribution needs bounds: [low, high]")
        if d == "normal" and self.bounds is not None:
            raise ValueError("a normal distribution has no bounds: use truncated_normal")
        if d == "normal" and self.mean <= UNBOUNDED_SIGMAS * self.sd:
            raise ValueError(f"mean = {self.mean:g}, sd = {self.sd:g}: a factor must stay above 0; a normal "
                             f"without bounds needs mean > {UNBOUNDED_SIGMAS:g} sd, else use truncated_normal")
        if self.bounds is not None:
            low, high = self.bounds
            if not 0.0 < low < high <= 10.0:
                raise ValueError(f"bounds = [{low:g}, {high:g}]: need 0 < low < high <= 10 (factors on the nominal)")
            if d == "truncated_normal" and not low <= self.mean <= high:
                raise ValueError(f"mean = {self.mean:g}: must lie within bounds [{low:g}, {high:g}]")
        return self


class ScatterFile(_File):
    schema_: Literal["railbrake.scatter/1"] = Field(alias="schema")
    # each a factor on the train file's nominal value (1 = nominal); missing: no scatter
    pad_friction: Distribution | None = None          # pad/disc friction coefficient
    pressure_control: Distribution | None = None      # cylinder pressure the BCU's control gives
    rigging_efficiency: Distribution | None = None    # caliper (rigging) efficiency
    wheel_diameter: Distribution | None = None
    load: Distribution | None = None                  # the car's mass against the mass the BCU weighs
    valve_response: Distribution | None = None        # EP and relay valve response times
    emergency_choke: Distribution | None = None       # the emergency valve's choke area (its filling rate)
    limiter_setting: Distribution | None = None       # the load-weighing valve's limit (gauge pressure)

    @field_validator(*QUANTITIES)
    @classmethod
    def _in_range(cls, d, info):
        """Every value the factor can take inside its quantity's range (data/etcs/factor-ranges.yaml)."""
        if d is None:
            return d
        low, high = scatter_ranges()[info.field_name]["range"]
        span = d.bounds if d.bounds is not None else [d.mean - UNBOUNDED_SIGMAS * d.sd, d.mean + UNBOUNDED_SIGMAS * d.sd]
        what = "bounds" if d.bounds is not None else f"mean +- {UNBOUNDED_SIGMAS:g} sd"
        if span[0] < low or span[1] > high:
            raise ValueError(f"{what} = [{span[0]:g}, {span[1]:g}]: a factor on the nominal {info.field_name} must "
                             f"lie in [{low:g}, {high:g}] ({scatter_ranges()[info.field_name]['source'].strip()})")
        correlation = scatter_ranges()[info.field_name]["correlation"]
        if d.per is None:
            return d.model_copy(update={"per": correlation["default"]})
        if d.per not in correlation["allowed"]:
            raise ValueError(f"per = {d.per!r}: {info.field_name} is drawn per "
                             f"{' or per '.join(correlation['allowed'])} ({correlation['source'].strip()})")
        return d

    def quantities(self) -> dict[str, Distribution]:
        return {q: getattr(self, q) for q in QUANTITIES if getattr(self, q) is not None}


@functools.lru_cache(maxsize=1)
def scatter_ranges() -> dict:
    """quantity -> {range: [low, high] factor, source} (data/etcs/factor-ranges.yaml)."""
    import yaml
    return yaml.safe_load((_data_dir() / "factor-ranges.yaml").read_text())


def _data_dir():
    return resources.files("railbrake") / "data" / "etcs"


def preset_names(kind: str) -> list[str]:
    return sorted(p.name[len(kind) + 1:-5] for p in _data_dir().iterdir() if p.name.startswith(kind + "-"))


def _path(kind: str, name: str | Path) -> Path:
    name = name_or_path(kind, name)
    if isinstance(name, str) and name in preset_names(kind):
        return Path(str(_data_dir() / f"{kind}-{name}.yaml"))
    if Path(name).suffix in (".yaml", ".yml") or Path(name).exists():
        return Path(name)
    raise InputError(f"{kind} = {name!r}: not a file nor a preset ({', '.join(preset_names(kind))})")


def load_reliability(name: str | Path) -> ReliabilityFile:
    """A reliability file (preset name or path), validated: InputError names file, line and key."""
    return config.load_yaml(_path("reliability", name), ReliabilityFile)


def load_scatter(name: str | Path) -> ScatterFile:
    """A scatter file (preset name or path), validated: InputError names file, line and key."""
    return config.load_yaml(_path("scatter", name), ScatterFile)
