"""Rolling stock: train presets (data files), cars, wheelsets, foundation brake, resistance, ED brake.

The laws live in the C core (``core/src/vehicle_*.c``, ``rb_vehicle.h``); this module reads and
validates train files (schema ``railbrake.train/1``), converts their human units to SI and builds
the C structs. Sources: ``shared/reference/README.md`` sections 2 and 3; every preset marks its
assumptions [T].

Pressures: the YAML files give gauge pressures in bar; inside, pressures are absolute in Pa.
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import Literal, Optional, Union

import numpy as np
import yaml
from pydantic import BaseModel, ConfigDict, Field, model_validator

from railbrake import _core, config
from railbrake.errors import InputError
from railbrake.units import KMH, bar_to_pa, kn_to_n, tonne_to_kg

SCHEMA = "railbrake.train/1"
P_ATM = 101325.0  # Pa
SINTERED_LOW_SPEED = 0.42  # lambda at standstill of the default sintered pad [T]


# ------------------------------------------------------------------ file schema

class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class _Resistance(_Strict):
    A_kN: float = Field(ge=0.0)
    B_kN_per_kmh: float = Field(ge=0.0)
    C_kN_per_kmh2: float = Field(ge=0.0)
    source: str


class _Branch(_Strict):
    c0: float  # kN
    c1: float = 0.0  # kN s/m
    c2: float = 0.0  # kN m/s


class _Table(_Strict):
    speed_kmh: list[float]
    value: list[float]

    @model_validator(mode="after")
    def _increasing(self):
        if len(self.speed_kmh) != len(self.value) or not 1 <= len(self.speed_kmh) <= _core.MAX_TABLE:
            raise ValueError(f"speed_kmh ({len(self.speed_kmh)} points) and value "
                             f"({len(self.value)}) need equal lengths, 1 to {_core.MAX_TABLE}")
        for i in range(1, len(self.speed_kmh)):
            if not self.speed_kmh[i] > self.speed_kmh[i - 1]:
                raise ValueError(f"speed_kmh[{i}] = {self.speed_kmh[i]}: speeds must increase strictly")
        return self


class _EdBrake(_Strict):
    branches_kN: list[_Branch] = Field(default=[], max_length=_core.MAX_ED_TERMS)
    table_kN: Optional[_Table] = None
    scale: float = Field(default=1.0, ge=0.0)
    fade_kmh: float = Field(default=0.0, ge=0.0)
    source: str


class _Discs(_Strict):
    per_axle: int = Field(ge=1, le=8)
    mounting: Literal["axle", "wheel"]
    mean_radius_m: float = Field(gt=0.0)


class _Caliper(_Strict):
    cylinder_area_m2: float = Field(gt=0.0)
    return_spring_kN: float = Field(ge=0.0)
    lever_ratio: float = Field(gt=0.0)
    efficiency: float = Field(gt=0.0, le=1.0)


class _PadFriction(_Strict):
    sintered_low_speed: Optional[float] = None
    table: Optional[_Table] = None

    @model_validator(mode="after")
    def _one_form(self):
        if (self.sintered_low_speed is None) == (self.table is None):
            raise ValueError("give exactly one of sintered_low_speed, table")
        return self


class _CarType(_Strict):
    kind: Literal["motor", "trailer"]
    tare_t: float = Field(gt=0.0)
    load_t: float = Field(ge=0.0)
    axles: int = Field(ge=1, le=8)
    wheel_radius_m: float = Field(gt=0.0)
    wheelset_inertia_kgm2: float = Field(ge=0.0)
    discs: _Discs
    caliper: _Caliper
    pad_friction: _PadFriction = _PadFriction(sintered_low_speed=SINTERED_LOW_SPEED)


class _TrainFile(_Strict):
    schema_: str = Field(alias="schema")
    name: str
    title: str
    source: str
    assumptions: list[str] = []
    max_speed_kmh: float = Field(gt=0.0)
    supply_pressure_bar: float = Field(gt=0.0, le=10.0)
    atmospheric_pressure_bar: float = Field(default=P_ATM / 1e5, gt=0.5, lt=1.2)
    running_resistance: _Resistance
    ed_brake: Optional[_EdBrake] = None
    car_types: dict[str, _CarType]
    formation: list[str] = Field(min_length=1, max_length=_core.MAX_CARS)

    @model_validator(mode="after")
    def _known_types(self):
        for i, name in enumerate(self.formation):
            if name not in self.car_types:
                raise ValueError(f"formation[{i}] = {name!r}: not one of car_types "
                                 f"({', '.join(self.car_types)})")
        return self


# ------------------------------------------------------------------ the train

@dataclass(frozen=True)
class Car:
    """One car (SI). ``c`` is its rb_car struct."""

    index: int
    type_name: str
    motor: bool
    tare: float  # kg
    load: float  # kg
    axles: int
    wheel_radius: float  # m
    wheelset_inertia: float  # kg m^2
    c: _core.Car

    @property
    def mass(self) -> float:
        return self.c.mass

    @property
    def equivalent_rotating_mass(self) -> float:
        """Sum over the axles of J / r^2 (C law)."""
        return self.axles * _core.rb_wheelset_equivalent_mass(ctypes.byref(self.c.wheelset))


def _vectorised(function, speed):
    v = np.asarray(speed, dtype=float)
    out = np.array([function(float(x)) for x in v.ravel()]).reshape(v.shape)
    return float(out) if out.ndim == 0 else out


@dataclass(frozen=True)
class Train:
    name: str
    title: str
    source: str
    assumptions: tuple
    max_speed: float  # m/s
    cars: tuple  # of Car
    c: _core.TrainC  # rb_train struct, checked

    @property
    def mass(self) -> float:
        """kg, tare plus load."""
        return _core.rb_train_mass(ctypes.byref(self.c))

    @property
    def rotating_mass(self) -> float:
        """kg, sum of J/r^2 over every wheelset."""
        return _core.rb_train_rotating_mass(ctypes.byref(self.c))

    @property
    def supply_pressure(self) -> float:
        """Pa absolute, the highest cylinder pressure the brake supply gives (lowest over cars)."""
        return min(car.c.supply_pressure for car in self.cars)

    @property
    def atmospheric_pressure(self) -> float:
        return self.cars[0].c.brake.caliper.atmospheric_pressure

    def car_types(self) -> set:
        return {"motor" if car.motor else "trailer" for car in self.cars}

    def running_resistance(self, speed):
        """N at speed (m/s): A + B v + C v^2 (C law)."""
        r = ctypes.byref(self.c.resistance)
        return _vectorised(lambda v: _core.rb_running_resistance(r, v), speed)

    def ed_brake_force(self, speed):
        """N at speed (m/s): the largest ED brake force of the whole train (C law)."""
        t = ctypes.byref(self.c)
        return _vectorised(lambda v: _core.rb_train_ed_force_max(t, v), speed)

    def to_c(self) -> _core.TrainC:
        """A copy of the rb_train struct (per car rb_car: wheelset, rb_axle_brake, rb_caliper, ED)."""
        copy = _core.TrainC()
        ctypes.pointer(copy)[0] = self.c
        return copy


def _ed_curve(ed: _EdBrake | None, motor_count: int) -> _core.EdCurve:
    curve = _core.EdCurve()
    if ed is None:
        return curve
    curve.terms = len(ed.branches_kN)
    for k, b in enumerate(ed.branches_kN):
        curve.c0[k], curve.c1[k], curve.c2[k] = kn_to_n(b.c0), kn_to_n(b.c1), kn_to_n(b.c2)
    if ed.table_kN is not None:
        curve.table = _core.speed_table(np.asarray(ed.table_kN.speed_kmh) * KMH,
                                        kn_to_n(np.asarray(ed.table_kN.value)))
    curve.scale = ed.scale / motor_count  # the whole-train curve, shared equally
    curve.fade_speed = ed.fade_kmh * KMH
    return curve


def _pad_friction(pad: _PadFriction) -> _core.PadFriction:
    out = _core.PadFriction()
    if pad.table is not None:
        out.table = _core.speed_table(np.asarray(pad.table.speed_kmh) * KMH, pad.table.value)
    else:
        _core.call(_core.rb_pad_friction_sintered, pad.sintered_low_speed, ctypes.byref(out))
    return out


def _car_struct(t: _CarType, ed: _core.EdCurve, p_atm: float, supply: float, loaded: bool) -> _core.Car:
    mass = tonne_to_kg(t.tare_t + (t.load_t if loaded else 0.0))
    c = _core.Car()
    c.motor, c.axles, c.mass = int(t.kind == "motor"), t.axles, mass
    c.wheelset = _core.Wheelset(t.wheel_radius_m, t.wheelset_inertia_kgm2, mass / t.axles)
    c.brake.discs = t.discs.per_axle
    c.brake.mounting = 1 if t.discs.mounting == "wheel" else 0
    c.brake.mean_radius = t.discs.mean_radius_m
    k = t.caliper
    c.brake.caliper = _core.Caliper(k.cylinder_area_m2, kn_to_n(k.return_spring_kN), k.lever_ratio,
                                    k.efficiency, p_atm)
    c.brake.pad = _pad_friction(t.pad_friction)
    if c.motor:
        c.ed = ed
    c.supply_pressure = supply
    return c


def _build(model: _TrainFile, loaded: bool) -> Train:
    p_atm = bar_to_pa(model.atmospheric_pressure_bar)
    supply = p_atm + bar_to_pa(model.supply_pressure_bar)
    types = [model.car_types[n] for n in model.formation]
    motors = sum(t.kind == "motor" for t in types)
    ed = _ed_curve(model.ed_brake, max(motors, 1))
    train_c = _core.TrainC()
    train_c.n_cars = len(types)
    cars = []
    for i, (name, t) in enumerate(zip(model.formation, types)):
        train_c.cars[i] = _car_struct(t, ed, p_atm, supply, loaded)
        cars.append(Car(i, name, t.kind == "motor", tonne_to_kg(t.tare_t), tonne_to_kg(t.load_t),
                        t.axles, t.wheel_radius_m, t.wheelset_inertia_kgm2, train_c.cars[i]))
    r = model.running_resistance
    train_c.resistance = _core.Resistance(kn_to_n(r.A_kN), kn_to_n(r.B_kN_per_kmh) / KMH,
                                          kn_to_n(r.C_kN_per_kmh2) / KMH**2)
    _core.call(_core.rb_train_check, ctypes.byref(train_c))
    return Train(model.name, model.title, " ".join(model.source.split()), tuple(model.assumptions),
                 model.max_speed_kmh * KMH, tuple(cars), train_c)


def _preset_dir():
    return resources.files("railbrake") / "data" / "trains"


def preset_names() -> list[str]:
    return sorted(p.name[:-5] for p in _preset_dir().iterdir() if p.name.endswith(".yaml"))


def parse_train(text: str, origin: str, loaded: bool = True) -> Train:
    data = config.load_mapping(text, origin)
    return parse_train_data(data, origin, config._line_index(yaml.compose(text)), loaded)


def parse_train_data(data: dict, origin: str, lines: dict, loaded: bool = True,
                     overrides: dict | None = None) -> Train:
    """A train from its file's mapping; lines and overrides say where each key came from."""
    model = config.validate_data(data, _TrainFile, config.locator(origin, lines, overrides))
    if model.schema_ != SCHEMA:
        raise InputError(f"{origin}: schema = {model.schema_!r}: expected {SCHEMA!r}")
    try:
        return _build(model, loaded)
    except InputError as exc:
        raise InputError(f"{origin}: {exc}") from None


def load_train(name_or_path: Union[str, Path, Train], loaded: bool = True) -> Train:
    """A preset name (see preset_names()) or a YAML file; loaded=False leaves out the payload."""
    if isinstance(name_or_path, Train):
        return name_or_path
    name = str(name_or_path)
    if name in preset_names():
        return parse_train((_preset_dir() / f"{name}.yaml").read_text(), f"train {name}", loaded)
    path = Path(name)
    if path.suffix in (".yaml", ".yml") and path.is_file():
        return parse_train(path.read_text(), str(path), loaded)
    raise InputError(f"train = {name!r}: not a preset ({', '.join(preset_names())}) nor a YAML file")


# ------------------------------------------------------------------ single laws, for users and tests

def pad_friction_sintered(speed, low_speed_value: float = SINTERED_LOW_SPEED):
    """lambda(v) of the default sintered pad [T] at speed (m/s)."""
    pad = _core.PadFriction()
    _core.call(_core.rb_pad_friction_sintered, low_speed_value, ctypes.byref(pad))
    return _vectorised(lambda v: _core.rb_pad_friction_at(ctypes.byref(pad), v), speed)


def equivalent_rotating_mass(wheelsets) -> float:
    """Sum of J / r^2 (kg) over (wheel_radius m, inertia kg m^2, axle_load kg) triples."""
    wheelsets = list(wheelsets)
    array = (_core.Wheelset * max(len(wheelsets), 1))(*[_core.Wheelset(*w) for w in wheelsets])
    out = ctypes.c_double()
    _core.call(_core.rb_equivalent_rotating_mass, array, len(wheelsets), ctypes.byref(out))
    return out.value


def caliper_pad_force(cylinder_pressure: float, cylinder_area: float, return_spring: float,
                      lever_ratio: float, efficiency: float, atmospheric_pressure: float = P_ATM) -> float:
    """Pad normal force (N) from the absolute cylinder pressure (Pa), EN 14531 form (checked)."""
    c = _core.Caliper(cylinder_area, return_spring, lever_ratio, efficiency, atmospheric_pressure)
    _core.call(_core.rb_caliper_check, ctypes.byref(c))
    return _core.rb_caliper_pad_force(ctypes.byref(c), cylinder_pressure)


def coupler_force(dx: float, dv: float, slack: float, stiffness: float, stiffness_cubic: float = 0.0,
                  damping: float = 0.0) -> float:
    """Coupler tension (N) at extension dx (m) and its rate dv (m/s) (checked)."""
    c = _core.Coupler(slack, stiffness, stiffness_cubic, damping)
    _core.call(_core.rb_coupler_check, ctypes.byref(c))
    return _core.rb_coupler_force(ctypes.byref(c), dx, dv)


def with_constant_pad_friction(train: Train, speed: float | None = None) -> Train:
    """The same train with each pad's lambda frozen at its value at `speed` (m/s; default: top
    speed); comparing the two shows what lambda(v) does to the target pressure."""
    v = train.max_speed if speed is None else float(speed)
    copy = train.to_c()
    for k in range(copy.n_cars):
        pad = copy.cars[k].brake.pad
        value = _core.rb_pad_friction_at(ctypes.byref(pad), v)
        pad.table = _core.speed_table([0.0], [value])
    _core.call(_core.rb_train_check, ctypes.byref(copy))
    cars = tuple(replace(car, c=copy.cars[car.index]) for car in train.cars)
    return replace(train, cars=cars, c=copy, title=f"{train.title}, lambda frozen at {v * 3.6:.0f} km/h")


def pad_friction_of(car: Car, speed):
    """lambda(v) of a car's pads at speed (m/s)."""
    pad = ctypes.byref(car.c.brake.pad)
    return _vectorised(lambda v: _core.rb_pad_friction_at(pad, v), speed)
