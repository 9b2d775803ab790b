"""Scenario files for the whole-train simulation (versioned YAML schema ``railbrake.scenario/1``).

Every physical quantity carries its unit ("300 km/h", "2 s", "300 m"); a missing or unknown unit,
an unknown key, a wrong type or a fault on a car that does not exist is an InputError naming the
key and its line in the file. Presets live in railbrake/data/scenarios/. Schema reference:
docs/simulation.md.
"""

from __future__ import annotations

import re
from importlib import resources
from pathlib import Path
from typing import Annotated, Literal

import yaml
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from railbrake import config
from railbrake.errors import InputError

SCHEMA = "railbrake.scenario/1"

# unit -> (dimension, factor to SI)
_UNITS = {
    "km/h": ("speed", 1 / 3.6), "m/s": ("speed", 1.0),
    "s": ("time", 1.0), "ms": ("time", 1e-3), "min": ("time", 60.0),
    "m": ("length", 1.0), "km": ("length", 1e3),
    "m/s^2": ("acceleration", 1.0), "m/s2": ("acceleration", 1.0),
    "bar": ("pressure", 1e5), "kPa": ("pressure", 1e3), "Pa": ("pressure", 1.0),
    "mm^2": ("area", 1e-6), "m^2": ("area", 1.0),
    "‰": ("gradient", 1e-3), "permille": ("gradient", 1e-3), "%": ("gradient", 1e-2),
}
_QUANTITY = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S+)\s*$")


def _quantity(dimension: str):
    allowed = [u for u, (d, _) in _UNITS.items() if d == dimension]

    def parse(value):
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            raise ValueError(f"a unit is required ({dimension}: {', '.join(allowed)}), e.g. '{value} {allowed[0]}'")
        if not isinstance(value, str):
            raise ValueError(f"expected a quantity with a unit ({', '.join(allowed)})")
        match = _QUANTITY.match(value)
        if not match:
            raise ValueError(f"expected '<number> <unit>' with a unit among {', '.join(allowed)}")
        number, unit = float(match.group(1)), match.group(2)
        if unit not in allowed:
            raise ValueError(f"unit {unit!r} is not a {dimension} unit ({', '.join(allowed)})")
        return number * _UNITS[unit][1]

    return Annotated[float, BeforeValidator(parse)]


Speed = _quantity("speed")
Time = _quantity("time")
Length = _quantity("length")
Acceleration = _quantity("acceleration")
Pressure = _quantity("pressure")
Area = _quantity("area")
Gradient = _quantity("gradient")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Train(_Strict):
    preset: str = "crh380al-16"   # railbrake.vehicle preset name or train YAML file
    cars: int | None = Field(default=None, ge=1, le=16)
    load_case: Literal["tare", "normal", "crush"] | None = None   # None: the train file's load_case


class GradientStep(_Strict):
    """From `start` (along the track, the train's front at 0 m at t = 0) on, the track rises by
    `gradient` (rise over run, "5 ‰" or "0.5 %"; uphill positive, within +-100 ‰); the first
    step also applies before its start."""
    start: Length
    gradient: Gradient = Field(ge=-0.1, le=0.1)


class Track(_Strict):
    gradients: list[GradientStep] = Field(default_factory=list, max_length=16)

    @model_validator(mode="after")
    def _increasing(self):
        for i in range(1, len(self.gradients)):
            if not self.gradients[i].start > self.gradients[i - 1].start:
                raise ValueError(f"gradients[{i}].start = {self.gradients[i].start} m: starts must increase")
        return self


class DemandStep(_Strict):
    time: Time = Field(ge=0.0)
    emergency: bool = False
    service: float = Field(default=0.0, ge=0.0, le=1.0, description="fraction of full service")


class Zone(_Strict):
    start: Length
    end: Length
    condition: str

    @model_validator(mode="after")
    def _ordered(self):
        if not self.end > self.start:
            raise ValueError(f"end = {self.end} m must exceed start = {self.start} m")
        return self


class Adhesion(_Strict):
    condition: str = "dry-medium"
    zones: list[Zone] = Field(default_factory=list, max_length=8)


class WspSettings(_Strict):
    enabled: bool = True
    per_bogie: bool = False   # valves per bogie (both axles share the commands) instead of per axle
    speed_threshold: Speed | None = None
    slip_threshold: float | None = Field(default=None, ge=0.0, le=0.5)
    decel_threshold: Acceleration | None = None
    reaccel_threshold: Acceleration | None = None
    ref_decel_max: Acceleration | None = None
    safety_time: Time | None = None
    cycle: Time = 0.01


FaultType = Literal["hold_stuck_open", "hold_stuck_closed", "vent_stuck_open", "vent_stuck_closed",
                    "sensor_lost", "sensor_noisy", "cylinder_leak", "ep_valve_failed", "ed_lost",
                    "car_isolated", "compressor_off"]


class FaultSpec(_Strict):
    type: FaultType
    car: int = Field(ge=1, description="1-based")
    axle: int | None = Field(default=None, ge=1, le=4, description="1-based; omitted: every axle of the car")
    start: Time = Field(default=0.0, ge=0.0)
    noise: Speed | None = None
    leak_area: Area | None = None


class Stop(_Strict):
    speed: Speed = 0.05
    max_time: Time = 300.0


class Outputs(_Strict):
    record_interval: Time = 0.02


class ScenarioFile(_Strict):
    schema_: str = Field(alias="schema")
    name: str
    title: str = ""
    train: Train = Field(default_factory=Train)
    initial_speed: Speed
    demand: list[DemandStep] = Field(min_length=1, max_length=16)
    adhesion: Adhesion = Field(default_factory=Adhesion)
    track: Track = Field(default_factory=Track)
    wsp: WspSettings = Field(default_factory=WspSettings)
    faults: list[FaultSpec] = Field(default_factory=list, max_length=16)
    stop: Stop = Field(default_factory=Stop)
    outputs: Outputs = Field(default_factory=Outputs)
    seed: int = Field(default=1, ge=0)
    source: str = ""


class Scenario:
    """A validated scenario plus where each key sits in its file (for later error messages).

    ``data`` is the scenario as read (file units), ``overrides`` the key paths set on the command
    line (``--set``): their errors name the override instead of a line of the file."""

    def __init__(self, spec: ScenarioFile, origin: str, lines: dict, data: dict | None = None,
                 overrides: dict | None = None):
        self.spec = spec
        self.origin = origin
        self._lines = lines
        self.data = data if data is not None else {}
        self.overrides = overrides or {}

    @property
    def name(self) -> str:
        return self.spec.name

    def where(self, *key) -> str:
        dotted = ".".join(str(k) for k in key)
        return f"{config.locator(self.origin, self._lines, self.overrides)(key)}: {dotted}"

    def cars(self, override: int | None = None) -> int:
        from railbrake.vehicle import load_train
        if override is not None:
            if not 1 <= override <= 16:
                raise InputError(f"cars = {override}: must be in [1, 16]")
            return override
        if self.spec.train.cars is not None:
            return self.spec.train.cars
        return len(load_train(self.spec.train.preset).cars)

    def check_speed(self, train) -> None:
        """The initial speed must not exceed the train's maximum speed."""
        if self.spec.initial_speed > train.max_speed * (1 + 1e-9):
            raise InputError(f"{self.where('initial_speed')} = {self.spec.initial_speed * 3.6:g} km/h: above the "
                             f"maximum speed of train {train.name}, {train.max_speed * 3.6:g} km/h "
                             f"(allowed: 0 to {train.max_speed * 3.6:g} km/h)")

    def check_cars(self, n_cars: int) -> None:
        """Faults must name cars of the train."""
        for i, fault in enumerate(self.spec.faults):
            if fault.car > n_cars:
                raise InputError(f"{self.where('faults', i, 'car')} = {fault.car}: the train has cars 1..{n_cars}")


def _preset_dir():
    return resources.files("railbrake") / "data" / "scenarios"


def preset_names() -> list[str]:
    return sorted(p.name[:-5] for p in _preset_dir().iterdir() if p.name.endswith(".yaml"))


def parse(text: str, origin: str) -> Scenario:
    data = config.load_mapping(text, origin)
    lines = config._line_index(yaml.compose(text))
    return from_data(data, origin, lines)


def from_data(data: dict, origin: str, lines: dict, overrides: dict | None = None) -> Scenario:
    """Validate a scenario mapping (file units); lines and overrides say where each key came from."""
    spec = config.validate_data(data, ScenarioFile, config.locator(origin, lines, overrides))
    scenario = Scenario(spec, origin, lines, data, overrides)
    if spec.schema_ != SCHEMA:
        raise InputError(f"{scenario.where('schema')} = {spec.schema_!r}: expected {SCHEMA!r}")
    from railbrake.adhesion import load_condition
    from railbrake.vehicle import load_train
    for key, name in [(("adhesion", "condition"), spec.adhesion.condition)] + [
            (("adhesion", "zones", i, "condition"), z.condition) for i, z in enumerate(spec.adhesion.zones)]:
        try:
            load_condition(name)
        except InputError:
            raise InputError(f"{scenario.where(*key)} = {name!r}: not an adhesion preset or file") from None
    try:
        train = load_train(spec.train.preset)
    except InputError as exc:
        raise InputError(f"{scenario.where('train', 'preset')}: {exc}") from None
    scenario.check_speed(train)
    scenario.check_cars(scenario.cars())
    return scenario


def load(scenario: str | Path | Scenario) -> Scenario:
    """A preset name, a YAML file, or a Scenario."""
    if isinstance(scenario, Scenario):
        return scenario
    name = str(scenario)
    if name in preset_names():
        return parse((_preset_dir() / f"{name}.yaml").read_text(), f"preset {name}")
    path = Path(name)
    if path.is_file():
        return parse(config.read_text(path), str(path))
    raise InputError(f"scenario = {name!r}: not a preset ({', '.join(preset_names())}) nor a file")
