"""Adhesion conditions (presets as data files), peak adhesion and the Polach parameter fit.

A *condition* is Polach's five parameters plus, optionally, a rolling-speed factor on mu0 (wet
rail: mu0 / (1 + v / v_ref), the file's params.v_ref_kmh) and rail conditioning by the axles
ahead (heavy rain: the leading wheels clean the rail for those behind). Wherever a condition
is accepted, so are a preset name, a path to a preset file, a :class:`PolachParams`, or a
mapping with the five parameters.
"""

from __future__ import annotations

import ctypes
import math
import warnings
from dataclasses import dataclass, field, replace
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Mapping, Union

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from railbrake import _core, config
from railbrake._args import instance, name_or_path, real, reals, whole
from railbrake.config import parse_yaml, read_text
from railbrake.contact import (
    HertzContact,
    PolachParams,
    default_contact,
    polach_coefficient,
    polach_peak,
)
from railbrake.errors import InputError
from railbrake.units import KMH, ms_to_kmh

AXLES_PER_CAR = 4
SCHEMA = "railbrake.adhesion/1"


@dataclass(frozen=True)
class RailConditioning:
    """mu0 factor for axle n (0 = leading): 1 - (1 - leading_factor) exp(-n / recovery_axles).

    With reference_energy (J/m^2) the plant conditions the rail cell by cell instead
    (core/src/rail_conditioning.c): each cell's factor is 1 - (1 - leading_factor) exp(-E /
    reference_energy), E the contact energy the axles ahead left on it; cells of cell_length (m).
    The axle-count law stays the static curve's (and the plant's with rail_conditioning "axles").
    """

    leading_factor: float
    recovery_axles: float
    reference_energy: float = 0.0
    cell_length: float = 0.0
    energy_source: str = ""
    calibration_scenario: str | None = None
    calibration_above_kmh: float | None = None

    def factor(self, axle: float) -> float:
        return _core.rb_conditioning_factor(float(axle), self.leading_factor, self.recovery_axles)


class AdhesionRangeWarning(UserWarning):
    """A condition used outside the speed range of the measurements it was identified from."""


@dataclass(frozen=True)
class Validity:
    """Where a preset holds: the speed range (km/h) and conditions of its measurements, and why."""

    speed_min_kmh: float
    speed_max_kmh: float
    conditions: str
    source: str
    origin: str = ""            # the condition's file, and the line of validity.speed_kmh
    line: int | None = None
    creep: tuple | None = None  # (min, max) creep (fraction) of the measurements, if the file gives it
    creep_line: int | None = None

    def contains(self, speed_kmh: float) -> bool:
        return self.speed_min_kmh <= speed_kmh <= self.speed_max_kmh

    def where(self, key: str = "speed_kmh") -> str:
        line = self.line if key == "speed_kmh" else self.creep_line
        return f"{self.origin}{f', line {line}' if line else ''}: validity.{key}"


@dataclass(frozen=True)
class Fit:
    """How a preset's parameters were obtained: the data sets (validation case ids, in
    validation/validation/) fitted and those only checked, each fitted parameter's bounds in the fit,
    the findings where one ends at a bound, and what was searched where no data set was found."""

    fitted_on: tuple = ()       # case ids the parameters were fitted on
    checked_on: tuple = ()      # case ids not used in the fit: the validation proper
    bounds: dict = field(default_factory=dict)     # fitted parameter -> (low, high)
    at_bound: dict = field(default_factory=dict)   # parameter -> the finding (which data disagree)
    no_data: str = ""           # where fitted_on is empty: what was searched and not found
    creep: str = ""             # the creep the data cover

    FITTABLE = ("mu0", "A", "B", "kA", "kS", "v_ref_kmh", "leading_factor", "recovery_axles")


@dataclass(frozen=True)
class EnergyConditioning:
    """Rail conditioning by dissipated energy (option; law in core/src/contact_conditioning.c).

    An axle leaves on the rail e = abs(F w) / (2 b v) J/m^2; the axles behind see mu0 scaled by
    1 - (1 - leading_factor) exp(-E / reference_energy), E the energy left by those ahead. The plant
    applies it cell by cell along the track (RailConditioning.reference_energy, rail_conditioning.c).
    reference_energy (J/m^2) has no published value: an input [T].
    """

    leading_factor: float
    reference_energy: float
    source: str = "user input [T]"

    def __post_init__(self):
        real("leading_factor", self.leading_factor)
        real("reference_energy", self.reference_energy)
        _core.call(_core.rb_conditioning_energy_check, ctypes.byref(self._c()))

    def _c(self) -> _core.ConditioningEnergy:
        return _core.ConditioningEnergy(float(self.leading_factor), float(self.reference_energy))

    @staticmethod
    def energy_density(creep_force: float, slip_velocity: float, speed: float, contact_width: float) -> float:
        """J/m^2 an axle leaves on the rail (0 at standstill)."""
        return _core.rb_dissipated_energy_density(float(creep_force), float(slip_velocity), float(speed),
                                                  float(contact_width))

    def factor(self, energy: float) -> float:
        """mu0 factor on rail that the axles ahead left `energy` (J/m^2) on."""
        return _core.rb_conditioning_energy_factor(ctypes.byref(self._c()), float(energy))


@dataclass(frozen=True)
class AdhesionCondition:
    name: str
    title: str
    params: PolachParams
    conditioning: RailConditioning | None = None
    source: str = "user parameters"
    targets: tuple = ()
    validity: Validity | None = None
    fit: Fit | None = None

    def fit_values(self) -> dict:
        """The parameters a fit block names, in the file's units (v_ref_kmh in km/h, where set)."""
        values = {k: getattr(self.params, k) for k in ("mu0", "A", "B", "kA", "kS")}
        if self.params.v_ref is not None:
            values["v_ref_kmh"] = ms_to_kmh(self.params.v_ref)
        if self.conditioning is not None:
            values.update(leading_factor=self.conditioning.leading_factor,
                          recovery_axles=self.conditioning.recovery_axles)
        return values

    def params_at_axle(self, axle: int = 0) -> PolachParams:
        """Polach parameters seen by the given axle (counted from the front of the train)."""
        axle = whole("axle", axle)
        if axle < 0:
            raise InputError(f"axle = {axle}: must be >= 0 (0 is the leading axle)")
        if self.conditioning is None:
            return self.params
        return replace(self.params, mu0=self.params.mu0 * self.conditioning.factor(axle))


# ------------------------------------------------------------------ preset files

class _ParamsModel(BaseModel):
    model_config = ConfigDict(extra="forbid")
    mu0: float
    A: float
    B: float
    kA: float
    kS: float
    # the rolling speed (km/h) at which mu0 is halved, mu0 / (1 + v / v_ref); absent: none
    v_ref_kmh: float | None = Field(default=None, ge=ms_to_kmh(config.bound_in("adhesion.v_ref")[0]),
                                    le=ms_to_kmh(config.bound_in("adhesion.v_ref")[1]))

    def polach(self) -> dict:
        """PolachParams' arguments, in SI."""
        values = self.model_dump(exclude={"v_ref_kmh"})
        return values if self.v_ref_kmh is None else {**values, "v_ref": self.v_ref_kmh * KMH}


class _CellsModel(BaseModel):
    """Rail conditioning cell by cell by the energy the axles dissipate (rail_conditioning.c)."""
    model_config = ConfigDict(extra="forbid")
    # null: the sliding wheels do not clean the contaminant (the cells are for sand alone)
    reference_energy_J_m2: float | None = Field(ge=config.bound_in("adhesion.reference_energy")[0],
                                                le=config.bound_in("adhesion.reference_energy")[1])
    cell_length_m: float = Field(ge=config.bound_in("adhesion.rail_cell_length")[0],
                                 le=config.bound_in("adhesion.rail_cell_length")[1])
    source: str
    # how the calibration measured the targets: the stop it ran and the speed above which each
    # axle's largest adhesion used counts (tools/calibrate_rail_conditioning.py)
    calibration_scenario: str | None = None
    calibration_above_kmh: float | None = Field(default=None, ge=0.0, le=600.0)


class _ConditioningModel(BaseModel):
    model_config = ConfigDict(extra="forbid")
    leading_factor: float = Field(gt=0.0, le=1.0)
    recovery_axles: float = Field(ge=config.bound_in("adhesion.recovery_axles")[0],
                                  le=config.bound_in("adhesion.recovery_axles")[1])
    cells: _CellsModel | None = None


class _TargetModel(BaseModel):
    model_config = ConfigDict(extra="forbid")
    speed_kmh: float = Field(ge=0.0, le=600.0)
    peak: float = Field(ge=config.bound_in("adhesion.target_peak")[0],      # an adhesion coefficient F/Q
                        le=config.bound_in("adhesion.target_peak")[1])
    rel_tolerance: float = Field(ge=config.bound_in("adhesion.target_tolerance")[0],
                                 le=config.bound_in("adhesion.target_tolerance")[1])
    source: str
    peak_creep: float | None = Field(default=None, gt=0.0, le=1.0)
    car: int | None = Field(default=None, ge=1, le=16)


class _ValidityModel(BaseModel):
    model_config = ConfigDict(extra="forbid")
    speed_kmh: list[float] = Field(min_length=2, max_length=2)   # [min, max]
    creep: list[float] | None = Field(default=None, min_length=2, max_length=2)   # [min, max], fractions
    conditions: str
    source: str


class _FitModel(BaseModel):
    model_config = ConfigDict(extra="forbid")
    fitted_on: list[str] = []
    checked_on: list[str] = []
    parameters: dict[str, list[float]] = {}     # name -> [low, high] of the fit
    at_bound: dict[str, str] = {}
    no_data: str | None = None
    creep: str


class _ConditionFile(BaseModel):
    model_config = ConfigDict(extra="forbid")
    schema_: str = Field(alias="schema")
    name: str
    title: str
    params: _ParamsModel
    conditioning: _ConditioningModel | None = None
    source: str
    validity: _ValidityModel | None = None
    fit: _FitModel | None = None
    targets: list[_TargetModel] = []


def _preset_dir():
    return resources.files("railbrake") / "data" / "adhesion"


def preset_names() -> list[str]:
    return sorted(p.name[:-5] for p in _preset_dir().iterdir() if p.name.endswith(".yaml"))


def _parse_condition_file(text: str, origin: str) -> AdhesionCondition:
    model = parse_yaml(text, _ConditionFile, origin)
    if model.schema_ != SCHEMA:
        raise InputError(f"{origin}: schema = {model.schema_!r}: expected {SCHEMA!r}")
    cond, valid = model.conditioning, model.validity
    if valid is not None and not (len(valid.speed_kmh) == 2 and valid.speed_kmh[0] < valid.speed_kmh[1]
                                  and all(config.within("train.table_speed", v * KMH) for v in valid.speed_kmh)):
        line = _config_lines(text).get(("validity", "speed_kmh"))
        raise InputError(f"{origin}{f', line {line}' if line else ''}: validity.speed_kmh = {list(valid.speed_kmh)}: "
                         f"give [min, max] with min < max, each {config.range_text('train.table_speed', 'km/h', KMH)}")
    if valid is not None and valid.creep is not None and not 0.0 <= valid.creep[0] < valid.creep[1] <= 1.0:
        line = _config_lines(text).get(("validity", "creep"))
        raise InputError(f"{origin}{f', line {line}' if line else ''}: validity.creep = {list(valid.creep)}: "
                         "give [min, max] with 0 <= min < max <= 1 (creep as a fraction)")
    validity = None if valid is None else Validity(valid.speed_kmh[0], valid.speed_kmh[1],
                                                   " ".join(valid.conditions.split()),
                                                   " ".join(valid.source.split()), _file_of(origin),
                                                   _config_lines(text).get(("validity", "speed_kmh")),
                                                   None if valid.creep is None else tuple(valid.creep),
                                                   _config_lines(text).get(("validity", "creep")))
    try:
        return AdhesionCondition(
            name=model.name, title=model.title,
            params=_located(PolachParams, model.params, "params", text, origin, values=model.params.polach()),
            conditioning=_conditioning(cond, text, origin) if cond else None,
            source=" ".join(model.source.split()), targets=tuple(t.model_dump() for t in model.targets),
            validity=validity, fit=_fit(model, text, origin))
    except InputError as exc:
        raise InputError(f"{origin}: {exc}") if origin not in str(exc) else exc from None


def _fit(model: _ConditionFile, text: str, origin: str) -> Fit | None:
    """The file's fit block, each fitted parameter's value inside its bounds (at a bound only with
    the finding that says why), a data set fitted or the search that found none."""
    fit = model.fit
    if fit is None:
        return None
    line = _config_lines(text).get(("fit",))
    where = f"{origin}{f', line {line}' if line else ''}: fit"
    if not fit.fitted_on and not (fit.no_data and fit.no_data.strip()):
        raise InputError(f"{where}: fitted_on is empty: name the data sets fitted, or say in no_data what was searched")
    values = {k: v for k, v in model.params.model_dump().items() if v is not None}
    if model.conditioning is not None:
        values.update(leading_factor=model.conditioning.leading_factor,
                      recovery_axles=model.conditioning.recovery_axles)
    bounds = {}
    for name, pair in fit.parameters.items():
        if name not in Fit.FITTABLE:
            raise InputError(f"{where}.parameters.{name}: unknown (known: {', '.join(Fit.FITTABLE)})")
        if len(pair) != 2 or not pair[0] < pair[1]:
            raise InputError(f"{where}.parameters.{name} = {pair}: give [low, high] with low < high")
        if pair[0] < 0:   # every fittable parameter is a friction level, a rate, a factor or a count
            raise InputError(f"{where}.parameters.{name} = {pair}: the bounds of a parameter that is never "
                             f"negative lie in [0, inf)")
        if name not in values:
            raise InputError(f"{where}.parameters.{name}: the file has no such parameter (no conditioning)")
        low, high = pair
        if not low <= values[name] <= high:
            raise InputError(f"{where}.parameters.{name}: the value {values[name]:g} lies outside the fit's "
                             f"bounds [{low:g}, {high:g}]")
        bounds[name] = (float(low), float(high))
    for name in fit.at_bound:
        if name not in bounds:
            raise InputError(f"{where}.at_bound.{name}: not a fitted parameter (fit.parameters)")
    for name, (low, high) in bounds.items():
        if name not in fit.at_bound and at_fit_bound(values[name], low, high):
            raise InputError(f"{where}.parameters.{name}: the value {values[name]:g} sits at a bound of the fit "
                             f"[{low:g}, {high:g}]: move it off or give the finding in fit.at_bound.{name}")
    return Fit(tuple(fit.fitted_on), tuple(fit.checked_on), bounds,
               {k: " ".join(v.split()) for k, v in fit.at_bound.items()},
               " ".join((fit.no_data or "").split()), " ".join(fit.creep.split()))


def at_fit_bound(value: float, low: float, high: float) -> bool:
    """True if value lies within 0.1 % of the range's width of either bound."""
    tol = 1e-3 * (high - low)
    return value <= low + tol or value >= high - tol


def _file_of(origin: str) -> str:
    """A preset's file (inside the package) or the file the condition was read from."""
    if origin.startswith("preset "):
        return f"railbrake/data/adhesion/{origin.removeprefix('preset ')}.yaml"
    return origin


def _conditioning(cond: _ConditioningModel, text: str, origin: str) -> RailConditioning:
    base = _located(RailConditioning, cond, "conditioning", text, origin, exclude={"cells"})
    if cond.cells is None:
        return base
    cells = cond.cells
    energy = math.inf if cells.reference_energy_J_m2 is None else cells.reference_energy_J_m2
    return replace(base, reference_energy=energy, cell_length=cells.cell_length_m,
                   energy_source=" ".join(cells.source.split()), calibration_scenario=cells.calibration_scenario,
                   calibration_above_kmh=cells.calibration_above_kmh)


def car_max_adhesion(result, above_kmh: float) -> dict:
    """Car (1-based) -> the mean over its axles of the largest adhesion F/Q each used while the
    train ran above above_kmh: a car's 'maximum adhesion' as a test train measures it."""
    running = result.outputs["speed"] > above_kmh * KMH
    per_car: dict = {}
    for name in result.axle_channels("adhesion"):
        car = int(name.split("_c")[-1].split("a")[0])
        per_car.setdefault(car, []).append(float(np.max(np.abs(result.outputs[name][running]))))
    return {car: float(np.mean(v)) for car, v in sorted(per_car.items())}


def _located(kind, block, section: str, text: str, origin: str, exclude=None, values=None):
    """kind(**block) (or kind(**values), the block's values converted) with the core's range error
    located: file, line and the key under `section`."""
    try:
        return kind(**(block.model_dump(exclude=exclude) if values is None else values))
    except InputError as exc:
        key = str(exc).split(" = ", 1)[0].split(":", 1)[0].strip()
        line = _config_lines(text).get((section, key))
        raise InputError(f"{origin}{f', line {line}' if line else ''}: {section}.{exc}") from None


def _config_lines(text: str) -> dict:
    return config.line_index(text)


ConditionLike = Union[str, Path, PolachParams, Mapping, AdhesionCondition]


def load_condition(condition: ConditionLike) -> AdhesionCondition:
    """A preset name, a preset file, PolachParams, a mapping of the five parameters (and v_ref, m/s,
    optional), or a condition."""
    if isinstance(condition, AdhesionCondition):
        return condition
    if isinstance(condition, PolachParams):
        return AdhesionCondition("user", "User parameters", condition)
    if isinstance(condition, Mapping):
        missing = {"mu0", "A", "B", "kA", "kS"} - set(condition)
        if missing:
            raise InputError(f"condition = {dict(condition)}: missing {sorted(missing)}")
        keys = ("mu0", "A", "B", "kA", "kS") + (("v_ref",) if "v_ref" in condition else ())
        return load_condition(PolachParams(**{k: float(condition[k]) for k in keys}))
    name = name_or_path("condition", condition)
    if name in preset_names():
        return _preset(name)
    path = Path(name)
    if path.suffix in (".yaml", ".yml"):   # read_text names a missing or unreadable file
        try:
            text = read_text(path)
        except InputError as exc:
            raise InputError(f"condition = {name!r}: {exc}") from None
        return _parse_condition_file(text, str(path))
    raise InputError(f"condition = {name!r}: not a preset ({', '.join(preset_names())}) nor a YAML file")


@cache
def _preset(name: str) -> AdhesionCondition:
    """A shipped preset, read once per process (the package's files do not change under it)."""
    return _parse_condition_file((_preset_dir() / f"{name}.yaml").read_text(), f"preset {name}")


def conditions() -> list[AdhesionCondition]:
    return [load_condition(n) for n in preset_names()]


# ------------------------------------------------------------------ range of validity

def run_outside_validity(condition: AdhesionCondition, initial_speed_kmh: float) -> str | None:
    """Why a run from initial_speed_kmh uses the condition outside its validity, else None.

    A stop passes every speed below the initial one: it is outside when it starts above the
    range, or when it never reaches the range (starts below it). Conditions without a declared
    range hold everywhere."""
    instance("condition", condition, AdhesionCondition)
    speed = real("initial_speed_kmh", initial_speed_kmh)
    valid = condition.validity
    slack = 1e-9 * max(speed, 1.0)   # km/h -> m/s -> km/h rounding
    if valid is None or valid.speed_min_kmh - slack <= speed <= valid.speed_max_kmh + slack:
        return None
    side = "above" if speed > valid.speed_max_kmh else "below"
    return (f"adhesion condition {condition.name!r} run from {speed:g} km/h, {side} its validity "
            f"({valid.where()} = [{valid.speed_min_kmh:g}, {valid.speed_max_kmh:g}] km/h: "
            f"{valid.conditions})")


def creep_outside_validity(condition: AdhesionCondition, creep: float) -> str | None:
    """Why a creep (fraction) lies outside the creep range the condition's file gives, else None."""
    instance("condition", condition, AdhesionCondition)
    creep = real("creep", creep)
    valid = condition.validity
    if valid is None or valid.creep is None or valid.creep[0] <= abs(creep) <= valid.creep[1]:
        return None
    return (f"adhesion condition {condition.name!r} at creep {abs(creep):.3g}, outside its validity "
            f"({valid.where('creep')} = [{valid.creep[0]:g}, {valid.creep[1]:g}])")


_warned: set = set()


def warn_outside_range(condition: AdhesionCondition, speed_kmh: float, what: str = "used") -> bool:
    """Warn (once per condition and process) if speed_kmh lies outside the condition's validity.

    Returns True if the speed is outside. Conditions without a declared range never warn.
    """
    instance("condition", condition, AdhesionCondition)
    speed_kmh = real("speed_kmh", speed_kmh)
    valid = condition.validity
    if valid is None or valid.contains(speed_kmh):
        return False
    if condition.name not in _warned:
        _warned.add(condition.name)
        warnings.warn(
            f"adhesion condition {condition.name!r} {what} at {speed_kmh:.0f} km/h, outside "
            f"{valid.speed_min_kmh:.0f}-{valid.speed_max_kmh:.0f} km/h where it holds "
            f"({valid.conditions}; {valid.source})", AdhesionRangeWarning, stacklevel=3)
    return True


# ------------------------------------------------------------------ peaks and curves

@dataclass(frozen=True)
class Peak:
    coefficient: float  # maximum of F/Q over creep
    creep: float  # creep (fraction) where it occurs


def _contact(contact: HertzContact | None) -> HertzContact:
    return default_contact() if contact is None else instance("contact", contact, HertzContact)


def peak_adhesion(condition: ConditionLike, speed: float, axle: int = 0,
                  contact: HertzContact | None = None) -> Peak:
    """Maximum of F/Q over creep at `speed` (m/s) for the given axle (0 = leading axle).

    contact=None: the default high-speed wheelset (railbrake.contact.default_contact).
    """
    contact = _contact(contact)
    cond = load_condition(condition)
    speed = real("speed", speed, *_core.BOUNDS["initial_speed"][:2])
    warn_outside_range(cond, ms_to_kmh(speed))
    params = cond.params_at_axle(axle)
    coefficient, creep = polach_peak(speed, contact.normal_force, contact, params)
    return Peak(coefficient, creep)


@dataclass(frozen=True)
class CreepCurve:
    speed: float  # m/s
    creep: np.ndarray
    coefficient: np.ndarray
    peak: Peak


def creep_curves(condition: ConditionLike, speeds, axle: int = 0,
                 contact: HertzContact | None = None, creep=None) -> list[CreepCurve]:
    """Creep-force curves F/Q(creep) at each speed (m/s); creep defaults to 0..40 %."""
    contact = _contact(contact)
    cond = load_condition(condition)
    speeds = reals("speeds", speeds, *_core.BOUNDS["initial_speed"][:2]).ravel()
    for v in speeds:
        warn_outside_range(cond, ms_to_kmh(float(v)))
    params = cond.params_at_axle(axle)
    if creep is not None:
        creep = reals("creep", creep)
        if creep.size == 0:
            raise InputError("creep: an empty array; give the creep values of the curves (or None for 0 to 0.4)")
        outside = [why for why in (creep_outside_validity(cond, float(x)) for x in (creep.min(), creep.max())) if why]
        if outside:
            warnings.warn(outside[0], AdhesionRangeWarning, stacklevel=2)
    creep = np.linspace(0.0, 0.4, 401) if creep is None else creep
    curves = []
    for v in speeds:
        coefficient = polach_coefficient(creep, v, contact.normal_force, contact, params)
        peak = polach_peak(v, contact.normal_force, contact, params)
        curves.append(CreepCurve(float(v), creep, coefficient, Peak(*peak)))
    return curves


def car_of_axle(axle: int, axles_per_car: int = AXLES_PER_CAR) -> int:
    return whole("axle", axle, 0) // whole("axles_per_car", axles_per_car, 1) + 1


def car_axles(car: int, axles_per_car: int = AXLES_PER_CAR) -> range:
    car, axles_per_car = whole("car", car, 1), whole("axles_per_car", axles_per_car, 1)
    return range((car - 1) * axles_per_car, car * axles_per_car)
