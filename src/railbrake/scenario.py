"""Scenario files for the whole-train simulation (versioned YAML schema ``railbrake.scenario/1``).

Every physical quantity carries its unit ("300 km/h", "2 s", "300 m"); a missing or unknown unit,
an unknown key, a wrong type or a fault on a car that does not exist is an InputError naming the
key and its line in the file. Presets live in railbrake/data/scenarios/. Schema reference:
docs/simulation.md.
"""

from __future__ import annotations

import copy
import re
from importlib import resources
from pathlib import Path
from typing import Annotated, ClassVar, Literal

from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from railbrake import _changes, config
from railbrake._args import name_or_path, text as _text
from railbrake.errors import InputError
from railbrake.units import ms_to_kmh

SCHEMA = "railbrake.scenario/1"

# unit -> (dimension, factor to SI)
_UNITS = {
    "km/h": ("speed", 1 / 3.6), "m/s": ("speed", 1.0),
    "s": ("time", 1.0), "ms": ("time", 1e-3), "min": ("time", 60.0),
    "m": ("length", 1.0), "km": ("length", 1e3),
    "m/s^2": ("acceleration", 1.0), "m/s2": ("acceleration", 1.0),
    "bar": ("pressure", 1e5), "kPa": ("pressure", 1e3), "Pa": ("pressure", 1.0),
    "bar/s": ("pressure rate", 1e5), "kPa/s": ("pressure rate", 1e3), "Pa/s": ("pressure rate", 1.0),
    "mm^2": ("area", 1e-6), "m^2": ("area", 1.0),
    "‰": ("gradient", 1e-3), "permille": ("gradient", 1e-3), "%": ("gradient", 1e-2),
}
# ASCII digits only: Python's float() and \d also take other scripts' digits (Arabic-Indic ٣ is 3)
_QUANTITY = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S+)\s*$", re.ASCII)


def _quantity(dimension: str, bound: str | None = None):
    """A quantity with a unit of `dimension`, in SI; with `bound` (a name of the C plausibility
    table, core/src/bounds.c) it must lie inside it, and the error gives the range in the unit
    the user wrote."""
    allowed = [u for u, (d, _) in _UNITS.items() if d == dimension]

    def parse(value):
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            raise ValueError(f"a unit is required ({dimension}: {', '.join(allowed)}), e.g. '{value} {allowed[0]}'")
        if not isinstance(value, str):
            raise ValueError(f"expected a quantity with a unit ({', '.join(allowed)})")
        if _is_number(value):
            raise ValueError(f"a unit is required ({dimension}: {', '.join(allowed)}), e.g. '{value.strip()} "
                             f"{allowed[0]}'")
        match = _QUANTITY.match(value)
        if not match:
            raise ValueError(f"expected '<number> <unit>' with a unit among {', '.join(allowed)}")
        number, unit = float(match.group(1)), match.group(2)
        if unit not in allowed:
            raise ValueError(f"unit {unit!r} is not a {dimension} unit ({', '.join(allowed)})")
        factor = _UNITS[unit][1]
        if bound is not None and not config.within(bound, number * factor):
            raise ValueError(config.range_text(bound, unit, factor))
        return number * factor

    return Annotated[float, BeforeValidator(parse)]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _bounded(bound: str):
    """A plain number (a fraction) inside the C plausibility bound `bound`."""
    def check(value: float) -> float:
        if not config.within(bound, value):
            raise ValueError(config.range_text(bound, ""))
        return value

    return Annotated[float, AfterValidator(check)]


Speed = _quantity("speed")
Time = _quantity("time")
Length = _quantity("length")
Acceleration = _quantity("acceleration")
Pressure = _quantity("pressure")
Area = _quantity("area")
Gradient = _quantity("gradient")

# bounded quantities of the schema: (dimension, C bound)
Q_WSP_DECEL_THRESHOLD = _quantity("acceleration", "wsp.decel_threshold")
Q_WSP_REACCEL_THRESHOLD = _quantity("acceleration", "wsp.reaccel_threshold")
Q_WSP_REF_DECEL_MAX = _quantity("acceleration", "wsp.ref_decel_max")
Q_SCENARIO_FAULT_LEAK_AREA = _quantity("area", "scenario.fault_leak_area")
Q_SCENARIO_GRADIENT = _quantity("gradient", "scenario.gradient")
Q_SCENARIO_TRACK_POSITION = _quantity("length", "scenario.track_position")
Q_INITIAL_SPEED = _quantity("speed", "initial_speed")
Q_SCENARIO_FAULT_NOISE = _quantity("speed", "scenario.fault_noise")
Q_SCENARIO_FAULT_PRESSURE = _quantity("pressure", "scenario.fault_pressure")
Q_SCENARIO_STOP_SPEED = _quantity("speed", "scenario.stop_speed")
Q_WSP_SPEED_THRESHOLD = _quantity("speed", "wsp.speed_threshold")
Q_BCU_CYCLE = _quantity("time", "bcu.cycle")
Q_SCENARIO_EVENT_TIME = _quantity("time", "scenario.event_time")
Q_SCENARIO_MAX_TIME = _quantity("time", "scenario.max_time")
Q_SCENARIO_RECORD_INTERVAL = _quantity("time", "scenario.record_interval")
Q_WSP_SAFETY_TIME = _quantity("time", "wsp.safety_time")
Q_WSP_SLIP_THRESHOLD = _bounded("wsp.slip_threshold")
Q_WSP_SETPOINT_SPEED = _quantity("speed", "wsp.setpoint_speed")
Q_WSP_SETPOINT_SLIP = _bounded("wsp.setpoint_slip")
Q_WSP_SETPOINT_BAND = _bounded("wsp.setpoint_band")
Q_WSP_LEAD_TIME = _quantity("time", "wsp.lead_time")
Q_WSP_REF_DECEL_MARGIN = _quantity("acceleration", "wsp.ref_decel_margin")
Q_WSP_SETPOINT_RELEASE = _quantity("time", "wsp.setpoint_release")
Q_WSP_SETPOINT_MEMORY = _bounded("wsp.setpoint_memory")
Q_WSP_SETPOINT_RAMP = _quantity("pressure rate", "wsp.setpoint_ramp")
Q_WSP_DS_SPEED_THRESHOLD = _quantity("speed", "wsp.ds_speed_threshold")
Q_WSP_DS_SLIP_THRESHOLD = _bounded("wsp.ds_slip_threshold")
Q_WSP_DS_DECEL_THRESHOLD = _quantity("acceleration", "wsp.ds_decel_threshold")
Q_WSP_DS_REACCEL_THRESHOLD = _quantity("acceleration", "wsp.ds_reaccel_threshold")
Q_WSP_CONDITIONING_RATIO = _bounded("wsp.conditioning_ratio")
Position = Q_SCENARIO_TRACK_POSITION   # along the track, the front at 0 m at t = 0
EventTime = Q_SCENARIO_EVENT_TIME


class _Strict(_changes.ReadOnlyModel, BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)   # frozen: a change goes through Scenario.with_
    OWNER: ClassVar[str] = "scenario"


class Train(_Strict):
    preset: str = "crh380al-16"   # railbrake.vehicle preset name or train YAML file
    cars: int | None = Field(default=None, ge=1, le=16)
    load_case: Literal["tare", "normal", "crush"] | None = None   # None: the train file's load_case


class GradientStep(_Strict):
    """From `start` (along the track, the train's front at 0 m at t = 0) on, the track rises by
    `gradient` (rise over run, "5 ‰" or "0.5 %"; uphill positive, within +-100 ‰); the first
    step also applies before its start."""
    start: Position
    gradient: Q_SCENARIO_GRADIENT


class Track(_Strict):
    gradients: list[GradientStep] = Field(default_factory=list, max_length=16)

    @model_validator(mode="after")
    def _increasing(self):
        for i in range(1, len(self.gradients)):
            if not self.gradients[i].start > self.gradients[i - 1].start:
                raise ValueError(f"gradients[{i}].start = {self.gradients[i].start} m: starts must increase")
        return self


class DemandStep(_Strict):
    time: EventTime
    emergency: bool = False
    service: float = Field(default=0.0, ge=0.0, le=1.0, description="fraction of full service")


class Zone(_Strict):
    start: Position
    end: Position
    condition: str

    @model_validator(mode="after")
    def _ordered(self):
        if not self.end > self.start:
            raise ValueError(f"end = {self.end} m must exceed start = {self.start} m")
        return self


class Adhesion(_Strict):
    condition: str = "dry-medium"
    zones: list[Zone] = Field(default_factory=list, max_length=8)
    # how a condition's rail conditioning acts in the plant: "axles", the fixed factor by axle
    # index, or "cells", the rail under the train cleaned cell by cell by the energy each axle
    # dissipates (where the condition's file gives conditioning.cells; core/src/rail_conditioning.c)
    rail_conditioning: Literal["axles", "cells"] = "axles"
    # true: a condition run outside its validity (its file's validity.speed_kmh) is run anyway, and
    # the run's KPIs, report and JSON say so (adhesion_outside_validity); false: refused
    allow_outside_validity: bool = False


class WspSettings(_Strict):
    enabled: bool = True
    per_bogie: bool = False   # valves per bogie (both axles share the commands) instead of per axle
    # overrides of the C defaults (rb_wsp_default_params), each inside its C bound (rb_wsp_check)
    speed_threshold: Q_WSP_SPEED_THRESHOLD | None = None
    slip_threshold: Q_WSP_SLIP_THRESHOLD | None = None
    decel_threshold: Q_WSP_DECEL_THRESHOLD | None = None
    reaccel_threshold: Q_WSP_REACCEL_THRESHOLD | None = None
    ref_decel_max: Q_WSP_REF_DECEL_MAX | None = None
    safety_time: Q_WSP_SAFETY_TIME | None = None
    cycle: Q_BCU_CYCLE = 0.01
    # the controller (rb_wsp_controller, docs/simulation.md): the threshold state machine, the slip
    # set-point controller or the deceleration and slip-speed controller, each with its overrides of
    # the C defaults (CONTROLLER_KEYS: the keys each one reads)
    controller: Literal["threshold", "slip_setpoint", "decel_slip_speed"] = "threshold"
    setpoint_speed: Q_WSP_SETPOINT_SPEED | None = None
    setpoint_slip: Q_WSP_SETPOINT_SLIP | None = None
    setpoint_band: Q_WSP_SETPOINT_BAND | None = None
    lead_time: Q_WSP_LEAD_TIME | None = None
    ref_decel_margin: Q_WSP_REF_DECEL_MARGIN | None = None
    setpoint_release: Q_WSP_SETPOINT_RELEASE | None = None
    setpoint_memory: Q_WSP_SETPOINT_MEMORY | None = None
    setpoint_ramp: Q_WSP_SETPOINT_RAMP | None = None
    ds_speed_threshold: Q_WSP_DS_SPEED_THRESHOLD | None = None
    ds_slip_threshold: Q_WSP_DS_SLIP_THRESHOLD | None = None
    ds_decel_threshold: Q_WSP_DS_DECEL_THRESHOLD | None = None
    ds_reaccel_threshold: Q_WSP_DS_REACCEL_THRESHOLD | None = None
    # every controller: the trailing axle of each bogie slides at conditioning_ratio times the
    # leading one's slip criterion (valves per axle only)
    conditioning_mode: bool = False
    conditioning_ratio: Q_WSP_CONDITIONING_RATIO | None = None


# The controller-specific keys of WspSettings each controller reads (a key set for another
# controller would change nothing: refused); every controller reads the others (ref_decel_max,
# safety_time, cycle, the conditioning mode).
CONTROLLER_KEYS = {
    "threshold": ("speed_threshold", "slip_threshold", "decel_threshold", "reaccel_threshold"),
    # the threshold controller's detection engages it on an axle
    "slip_setpoint": ("speed_threshold", "slip_threshold", "decel_threshold", "setpoint_speed", "setpoint_slip",
                      "setpoint_band", "lead_time", "ref_decel_margin", "setpoint_release", "setpoint_memory",
                      "setpoint_ramp"),
    "decel_slip_speed": ("ds_speed_threshold", "ds_slip_threshold", "ds_decel_threshold", "ds_reaccel_threshold",
                         "ref_decel_margin"),
}


FaultType = Literal["hold_stuck_open", "hold_stuck_closed", "vent_stuck_open", "vent_stuck_closed",
                    "sensor_lost", "sensor_noisy", "cylinder_leak", "ep_valve_failed", "ed_lost",
                    "car_isolated", "compressor_off", "pipe_leak", "emergency_valve_failed", "emergency_loop_lost",
                    "relay_valve_failed", "pressure_limiter_failed", "axle_isolated"]


class FaultSpec(_Strict):
    type: FaultType
    car: int | None = Field(default=None, ge=1, description="1-based; every fault but compressor_off needs it")
    axle: int | None = Field(default=None, ge=1, le=4, description="1-based; omitted: every axle of the car")
    start: EventTime = 0.0
    noise: Q_SCENARIO_FAULT_NOISE | None = None         # sensor_noisy only
    leak_area: Q_SCENARIO_FAULT_LEAK_AREA | None = None  # cylinder_leak and pipe_leak only
    # gauge, as the ETCS reliability file's pressure_bar: relay_valve_failed and pressure_limiter_failed only
    pressure: Q_SCENARIO_FAULT_PRESSURE | None = None


# the parameter each fault kind reads (rb_plant.h, rb_fault_kind); every other is refused
FAULT_VALUE = {"sensor_noisy": "noise", "cylinder_leak": "leak_area", "pipe_leak": "leak_area",
               "relay_valve_failed": "pressure", "pressure_limiter_failed": "pressure"}
# what each value means to its kind, its C bound and the unit its range is given in
VALUE_MEANING = {
    "sensor_noisy": "the standard deviation of the sensor's noise",
    "cylinder_leak": "the leak's orifice area", "pipe_leak": "the leak's orifice area",
    "relay_valve_failed": "the most the relay valve gives, gauge (0 bar: no output)",
    "pressure_limiter_failed": "the gauge pressure the failed limiter holds the emergency control pressure at "
                               "(below its setting: failed low; above: failed high)",
}
VALUE_RANGE = {"noise": ("scenario.fault_noise", "km/h"), "leak_area": ("scenario.fault_leak_area", "mm^2"),
               "pressure": ("scenario.fault_pressure", "bar")}
# no axle (as railbrake.etcs.inputs.CAR_KINDS); pipe_leak: the car's main-reservoir pipe (the train
# has no brake pipe); the emergency path's valves are one per car
CAR_FAULTS = ("ep_valve_failed", "ed_lost", "car_isolated", "compressor_off", "pipe_leak", "emergency_valve_failed",
              "emergency_loop_lost", "relay_valve_failed", "pressure_limiter_failed")


def fault_value(fault: FaultSpec) -> float:
    """The value the plant's fault reads (rb_fault.value, SI): noise, leak area or gauge pressure."""
    key = FAULT_VALUE.get(fault.type)
    return 0.0 if key is None else getattr(fault, key)


def _a(kind: str) -> str:
    """'an axle_isolated', 'a car_isolated'."""
    return f"{'an' if kind[0] in 'aeio' else 'a'} {kind}"


def _needs(kind: str) -> str:
    """': a relay_valve_failed fault needs pressure (...): it must lie in [0, 10] bar (...)'."""
    key = FAULT_VALUE[kind]
    bound, unit = VALUE_RANGE[key]
    return f": {_a(kind)} fault needs {key}, {VALUE_MEANING[kind]}; it {config.range_text(bound, unit, _UNITS[unit][1])}"


def fault_problem(fault: FaultSpec, needs_value: bool = True) -> tuple[str, str] | None:
    """(key, what is wrong after the key's location) for a fault whose fields do not fit its kind,
    else None. needs_value=False: the fault is named only (to be cleared), a value is refused."""
    needed = FAULT_VALUE.get(fault.type) if needs_value else None
    for key in VALUE_RANGE:
        if getattr(fault, key) is not None and key != needed:
            users = " or ".join(kind for kind, k in FAULT_VALUE.items() if k == key)
            why = f"only a {users} fault does" if needs_value else "a fault cleared is named by type, car and axle only"
            return key, f": {_a(fault.type)} fault does not use {key} ({why}): remove it"
    if needed and getattr(fault, needed) is None:
        return "type", _needs(fault.type)
    if fault.type == "compressor_off":
        if fault.car is not None:
            return "car", (f" = {fault.car}: a compressor_off fault stops every compressor of the train (one "
                           "compressor failing alone is not modelled): remove car")
    elif fault.car is None:
        return "type", f": {_a(fault.type)} fault needs car (1-based)"
    if fault.axle is not None and fault.type in CAR_FAULTS:
        return "axle", (f" = {fault.axle}: {_a(fault.type)} fault acts on the whole car (or train), not on one "
                        "axle: remove axle")
    return None


class Stop(_Strict):
    speed: Q_SCENARIO_STOP_SPEED = 0.05
    max_time: Q_SCENARIO_MAX_TIME = 300.0


class Outputs(_Strict):
    record_interval: Q_SCENARIO_RECORD_INTERVAL = 0.02


class ScenarioFile(_Strict):
    schema_: str = Field(alias="schema")
    name: str
    title: str = ""
    train: Train = Field(default_factory=Train)
    initial_speed: Q_INITIAL_SPEED
    demand: list[DemandStep] = Field(min_length=1, max_length=16)
    adhesion: Adhesion = Field(default_factory=Adhesion)
    track: Track = Field(default_factory=Track)
    wsp: WspSettings = Field(default_factory=WspSettings)
    faults: list[FaultSpec] = Field(default_factory=list, max_length=16)
    stop: Stop = Field(default_factory=Stop)
    outputs: Outputs = Field(default_factory=Outputs)
    seed: int = Field(default=1, ge=0)
    coast: bool = False   # true: a run without braking is meant (coast-down against the running resistance)
    source: str = ""


class Scenario:
    """A validated scenario plus where each key sits in its file (for later error messages).

    ``data`` is the scenario as read (file units), ``overrides`` the key paths set on the command
    line (``--set``): their errors name the override instead of a line of the file. A Scenario is
    immutable: ``with_(...)`` returns a changed copy, validated as ``--set`` validates."""

    def __init__(self, spec: ScenarioFile, origin: str, lines: dict, data: dict | None = None,
                 overrides: dict | None = None):
        for key, value in (("spec", spec), ("origin", origin), ("_lines", lines),
                           ("_data", copy.deepcopy(data) if data is not None else {}),
                           ("overrides", dict(overrides or {}))):
            object.__setattr__(self, key, value)

    def __setattr__(self, name, value):
        _changes.refuse_assignment("scenario", name)

    def __delattr__(self, name):
        _changes.refuse_assignment("scenario", name)

    @property
    def data(self) -> dict:
        """The scenario as read, in file units (a copy: changing it changes nothing)."""
        return copy.deepcopy(self._data)

    def with_(self, changes=None, /, **kwargs) -> "Scenario":
        """A copy with keys changed, e.g. ``with_(initial_speed="300 km/h")`` or
        ``with_({'wsp.enabled': False, 'train.cars': 4})``: dotted keys and values as ``--set``
        takes them (quantities with their unit), validated as a whole as ``--set`` is."""
        merged = _changes.merge(changes, kwargs, "Scenario.with_")
        for key in merged:
            head, _, rest = key.partition(".")
            if head == "train" and rest and rest not in ("preset", "cars", "load_case"):
                raise InputError(f"Scenario.with_: {key}: a key of the train file, not of the scenario; change "
                                 "it with railbrake.resolve.resolve(scenario, sets={...}) or Train.with_")
        if not self._data:
            raise InputError(f"scenario {self.name}: built in code (no file data behind it), so it cannot be "
                             "changed with with_; load it from a file or preset")
        data = self.data
        labels = _changes.apply_changes(data, merged, ScenarioFile)   # as --set: unknown keys refused
        return from_data(data, self.origin, self._lines, labels)

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

    def condition_keys(self) -> list[tuple[tuple, str]]:
        """(key, condition name) of the run's condition and of each adhesion zone's."""
        adhesion = self.spec.adhesion
        return [(("adhesion", "condition"), adhesion.condition)] + [
            (("adhesion", "zones", i, "condition"), z.condition) for i, z in enumerate(adhesion.zones)]

    def outside_validity(self) -> list[str]:
        """Each condition the run uses outside its validity, said in words (a zone is met at the
        initial speed at most: judged at it)."""
        from railbrake.adhesion import load_condition, run_outside_validity
        out = []
        for key, name in self.condition_keys():
            why = run_outside_validity(load_condition(name), ms_to_kmh(self.spec.initial_speed))
            if why:
                out.append(f"{'.'.join(str(k) for k in key)}: {why}")
        return out

    def creep_outside_validity(self, max_slip: float) -> list[str]:
        """The run's conditions whose file gives a creep range that max_slip (the run's largest
        creep of any axle, KPI max_slip) left, said in words."""
        from railbrake.adhesion import creep_outside_validity, load_condition
        out = []
        for key, name in self.condition_keys():
            why = creep_outside_validity(load_condition(name), max_slip)
            if why:
                out.append(f"{'.'.join(str(k) for k in key)}: {why}")
        return out

    def check_validity(self) -> None:
        """A condition outside its validity is refused unless adhesion.allow_outside_validity."""
        if self.spec.adhesion.allow_outside_validity:
            return
        from railbrake.adhesion import load_condition, run_outside_validity
        for key, name in self.condition_keys():
            why = run_outside_validity(load_condition(name), ms_to_kmh(self.spec.initial_speed))
            if why:
                raise InputError(f"{self.where(*key)} = {name!r} with {self.where('initial_speed')} = "
                                 f"{self._as_written('initial_speed')}: {why}; give a condition valid there, "
                                 "or force the run with adhesion.allow_outside_validity: true")

    def check_faults_on(self, train) -> None:
        """An ED-brake fault on a car without an ED brake (a trailer) changes nothing: refused."""
        for i, fault in enumerate(self.spec.faults):
            if fault.type != "ed_lost":
                continue
            car = train.cars[(fault.car - 1) % len(train.cars)]   # the formation repeats with --cars
            if not car.motor:
                raise InputError(f"{self.where('faults', i, 'car')} = {fault.car}: an ed_lost fault on a trailer "
                                 f"({car.type_name}) of train {train.name}, which has no ED brake: name a motor car")

    def check_cars(self, n_cars: int) -> None:
        """Faults must name cars of the train, and the recording must fit the bound on its size."""
        for i, fault in enumerate(self.spec.faults):
            if fault.car is not None and fault.car > n_cars:
                raise InputError(f"{self.where('faults', i, 'car')} = {fault.car}: the train has cars 1..{n_cars}")
        self._check_recording(n_cars)

    def _check_recording(self, n_cars: int) -> None:
        from railbrake import _core
        stop, interval = self.spec.stop, self.spec.outputs.record_interval
        channels = _core.rb_run_channel_count(n_cars)
        values = (stop.max_time / interval + 3) * channels
        if not config.within("scenario.recorded_values", values):
            _, most, why = config.bound_in("scenario.recorded_values")
            shortest = stop.max_time * channels / (most - 3 * channels)
            raise InputError(f"{self.where('outputs', 'record_interval')} = {self._as_written('outputs', 'record_interval')}: "
                             f"{values:.3g} recorded values ({channels} channels of {n_cars} cars over stop.max_time = "
                             f"{stop.max_time:g} s) exceed {most:.3g} ({why}): with this max_time it must be at "
                             f"least {shortest:.3g} s")

    def _as_written(self, *key) -> str:
        """The value of `key` as the file (or the override) gave it, e.g. '250 km/h'."""
        node = self._data
        for part in key:
            try:
                node = node[part]
            except (KeyError, IndexError, TypeError):
                return "(default)"
        return repr(node)

    def check_consistency(self) -> None:
        """Values that are each plausible but meaningless together (each error names both keys)."""
        self._check_demand()
        self._check_faults()
        self._check_zones()
        self._check_wsp()
        spec = self.spec
        if not spec.stop.speed < spec.initial_speed:
            raise InputError(f"{self.where('stop', 'speed')} = {self._as_written('stop', 'speed')}: must be below "
                             f"initial_speed = {self._as_written('initial_speed')} ({spec.initial_speed * 3.6:g} "
                             "km/h): the run would end before it starts")

    def _check_demand(self) -> None:
        spec = self.spec
        for i, step in enumerate(spec.demand):
            if step.emergency and step.service > 0.0:
                raise InputError(f"{self.where('demand', i)}: demand[{i}] has emergency: true and service = "
                                 f"{step.service:g}: give one of them (emergency is the full brake; service "
                                 "a fraction of full service in [0, 1])")
            if i and not step.time > spec.demand[i - 1].time:
                raise InputError(f"{self.where('demand', i, 'time')} = {self._as_written('demand', i, 'time')}: "
                                 f"demand times must increase (demand[{i - 1}].time = "
                                 f"{self._as_written('demand', i - 1, 'time')})")
            if step.time >= spec.stop.max_time:
                raise InputError(f"{self.where('demand', i, 'time')} = {self._as_written('demand', i, 'time')}: "
                                 f"at or after stop.max_time = {spec.stop.max_time:g} s, so never applied")
        if not spec.coast and not any(step.emergency or step.service > 0.0 for step in spec.demand):
            raise InputError(f"{self.where('demand')}: no demand step brakes (every step has emergency: false "
                             "and service: 0): the run would measure no braking; give emergency: true or "
                             "service in (0, 1], or coast: true if a run without braking is meant")

    def _check_faults(self) -> None:
        spec = self.spec
        for i, fault in enumerate(spec.faults):
            problem = fault_problem(fault)
            if problem is not None:
                raise InputError(f"{self.where('faults', i, problem[0])}{problem[1]}")
            if fault.start >= spec.stop.max_time:
                raise InputError(f"{self.where('faults', i, 'start')} = {self._as_written('faults', i, 'start')}: "
                                 f"at or after stop.max_time = {spec.stop.max_time:g} s, so never applied")

    def _check_wsp(self) -> None:
        wsp = self.spec.wsp
        read = set(CONTROLLER_KEYS[wsp.controller])
        for controller, keys in CONTROLLER_KEYS.items():
            for key in keys:
                if key not in read and getattr(wsp, key) is not None:
                    users = [c for c, ks in CONTROLLER_KEYS.items() if key in ks]
                    raise InputError(f"{self.where('wsp', key)} = {self._as_written('wsp', key)}: the {wsp.controller} "
                                     f"controller (wsp.controller) does not read it, only {' and '.join(users)}: "
                                     "remove it or choose that controller")
        if wsp.conditioning_ratio is not None and not wsp.conditioning_mode:
            raise InputError(f"{self.where('wsp', 'conditioning_ratio')} = {self._as_written('wsp', 'conditioning_ratio')}"
                             ": acts only with wsp.conditioning_mode: true")
        if wsp.conditioning_mode and wsp.per_bogie:
            raise InputError(f"{self.where('wsp', 'conditioning_mode')}: true with wsp.per_bogie: true: the "
                             "conditioning mode sets the two axles of a bogie apart, so it needs valves per axle "
                             "(wsp.per_bogie: false)")

    def _check_zones(self) -> None:
        zones = sorted(enumerate(self.spec.adhesion.zones), key=lambda iz: iz[1].start)
        for (i, a), (j, b) in zip(zones, zones[1:]):
            if b.start < a.end:
                raise InputError(f"{self.where('adhesion', 'zones', j)}: adhesion.zones[{j}] ({b.start:g} to "
                                 f"{b.end:g} m, {b.condition}) overlaps adhesion.zones[{i}] ({a.start:g} to "
                                 f"{a.end:g} m, {a.condition}; {self.where('adhesion', 'zones', i)}): zones "
                                 "must not overlap (which one holds would be undefined)")


def _preset_dir():
    return resources.files("railbrake") / "data" / "scenarios"


def preset_names() -> list[str]:
    return sorted(p.name[:-5] for p in _preset_dir().iterdir() if p.name.endswith(".yaml"))


def parse(text: str, origin: str) -> Scenario:
    data = config.load_mapping(_text("text", text), _text("origin", origin))
    lines = config.line_index(text)
    return from_data(data, origin, lines)


def from_data(data: dict, origin: str, lines: dict, overrides: dict | None = None) -> Scenario:
    """Validate a scenario mapping (file units); lines and overrides say where each key came from."""
    spec = config.validate_data(data, ScenarioFile, config.locator(origin, lines, overrides))
    scenario = Scenario(spec, origin, lines, data, overrides)
    if spec.schema_ != SCHEMA:
        raise InputError(f"{scenario.where('schema')} = {spec.schema_!r}: expected {SCHEMA!r}")
    from railbrake.adhesion import load_condition
    from railbrake.vehicle import load_train
    scenario.check_consistency()
    for key, name in [(("adhesion", "condition"), spec.adhesion.condition)] + [
            (("adhesion", "zones", i, "condition"), z.condition) for i, z in enumerate(spec.adhesion.zones)]:
        try:
            load_condition(name)
        except InputError as exc:   # an error inside the adhesion file names that file and line
            detail = str(exc).removeprefix(f"condition = {name!r}: ")
            raise InputError(f"{scenario.where(*key)} = {name!r}: {detail}") from None
    try:
        train = load_train(spec.train.preset)
    except InputError as exc:
        raise InputError(f"{scenario.where('train', 'preset')}: {exc}") from None
    scenario.check_speed(train)       # a speed the train never runs at first, then the rail's validity there
    scenario.check_validity()
    scenario.check_faults_on(train)
    scenario.check_cars(spec.train.cars if spec.train.cars is not None else len(train.cars))
    return scenario


def load(scenario: str | Path | Scenario) -> Scenario:
    """A preset name, a YAML file, or a Scenario."""
    if isinstance(scenario, Scenario):
        return scenario
    name = name_or_path("scenario", scenario)
    if name in preset_names():
        return parse((_preset_dir() / f"{name}.yaml").read_text(), f"preset {name}")
    path = Path(name)
    if path.is_file():
        return parse(config.read_text(path), str(path))
    raise InputError(f"scenario = {name!r}: not a preset ({', '.join(preset_names())}) nor a file")
