"""Rolling stock: train presets (data files), cars, wheelsets, foundation brake, resistance, ED brake.

The laws live in the C core (``core/src/vehicle_*.c``, ``rb_vehicle.h``); this module reads and
validates train files (schema ``railbrake.train/2``: the whole brake equipment, docs/vehicle.md),
converts their human units to SI and builds the C structs. Sources: TB/T 1407.2 (CRH380AL traction calculation), EN 14531-1 (brake
performance), published CRH380A / CRH3C / ICE 3 data; every preset marks its
assumptions [T].

Pressures: the YAML files give gauge pressures in bar; inside, pressures are absolute in Pa.
"""

from __future__ import annotations

import ctypes
import math
import numbers
from dataclasses import dataclass, field, replace
from importlib import resources
import types
from pathlib import Path
from typing import Annotated, ClassVar, Literal, Optional, Union, get_args, get_origin

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, ValidationInfo, field_validator, model_validator

from railbrake import _changes, _core, config
from railbrake._args import instance, name_or_path as _name_or_path, real, reals, whole
from railbrake.errors import InputError
from railbrake.units import KMH, TONNE, bar_to_pa, kn_to_n, tonne_to_kg

SCHEMA = "railbrake.train/2"
OLD_SCHEMAS = ("railbrake.train/1",)
LOAD_CASES = ("tare", "normal", "crush")
P_ATM = 101325.0  # Pa, standard atmosphere
SINTERED_LOW_SPEED = 0.42  # lambda at standstill of the default sintered pad [T]
ZERO_CELSIUS = 273.15  # K
MM, L, MM2, CM3, KN, BAR = 1e-3, 1e-3, 1e-6, 1e-6, 1e3, 1e5   # file units -> SI


# ------------------------------------------------------------------ file schema
# Numbers are strict (a bool or a string is never read as a number); every field carries its unit
# in its name and a plausibility range in that unit, so a tare given in kg where t is asked fails.

class _Strict(_changes.ReadOnlyModel, BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)   # frozen: changes go through Train.with_
    OWNER: ClassVar[str] = "train"


def _num(bound: str, per: float = 1.0, offset: float = 0.0, *, default=...):
    """A float in the C plausibility bound `bound` (core/src/bounds.c, SI: one table for the
    plant, the FMU and the files), in the unit its key names: SI = value * per + offset."""
    low, high, why = config.bound_in(bound, per, offset)
    return Field(default, ge=low, le=high, description=why)


class _Resistance(_Strict):
    A_kN: float = _num("train.resistance_a", KN)
    B_kN_per_kmh: float = _num("train.resistance_b", KN / KMH)
    C_kN_per_kmh2: float = _num("train.resistance_c", KN / KMH**2)
    source: str


class _Branch(_Strict):
    c0: float = _num("train.ed_c0", KN)               # kN
    c1: float = _num("train.ed_c1", KN, default=0.0)  # kN s/m
    c2: float = _num("train.ed_c2", KN, default=0.0)  # kN m/s


def _out_of_bound(key: str, values, bound: str, per: float, unit: str) -> None:
    """ValueError naming the first of `values` outside the C bound `bound` (file unit: SI / per)."""
    low, high, _ = config.bound_in(bound, per)
    for i, x in enumerate(values):
        if not low <= x <= high:
            raise ValueError(f"{key}[{i}] = {x:g}: {config.range_text(bound, unit, per)}")


class _Table(_Strict):
    """A table over speed; its values in the bound VALUE_BOUND ((name, per, unit) of core/src/bounds.c)."""
    VALUE_BOUND: ClassVar[tuple] = ()
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
        _out_of_bound("speed_kmh", self.speed_kmh, "train.table_speed", KMH, "km/h")
        if self.VALUE_BOUND:
            _out_of_bound("value", self.value, *self.VALUE_BOUND)
        return self


class _EdTable(_Table):
    VALUE_BOUND: ClassVar[tuple] = ("train.ed_force", KN, "kN")


class _PadTable(_Table):
    VALUE_BOUND: ClassVar[tuple] = ("train.pad_friction", 1.0, "")


class _CoolingTable(_Table):
    VALUE_BOUND: ClassVar[tuple] = ("train.disc_cooling", 1.0, "W/K")


class _EdBrake(_Strict):
    branches_kN: list[_Branch] = Field(default=[], max_length=_core.MAX_ED_TERMS)
    table_kN: Optional[_EdTable] = None
    scale: float = _num("train.ed_scale", default=1.0)
    fade_kmh: float = _num("train.ed_fade_speed", KMH, default=0.0)
    response_s: float = _num("train.ed_response")
    source: str


class _BrakeStep(_Strict):
    profile: str                  # a railbrake.sizing profile (preset name or file)
    ed_blending: bool             # ED brake first on the motor cars, pneumatic the rest
    source: str


class _EmergencyLoop(_Strict):
    """How the emergency command reaches each car: every car's loop relay drops out drop_out_s
    after the loop opens at the leading car; a command that travels (a brake pipe, a train line of
    relays in series) reaches car c's front after its distance / propagation_m_per_s (none: an
    electric loop, at once)."""
    drop_out_s: float = _num("train.emergency_drop_out")
    propagation_m_per_s: Optional[float] = _num("train.emergency_propagation", default=None)
    source: str


class _ServiceStep(_BrakeStep):
    """The service step; jerk_limit_m_s3: the BCU's limit on the rate of change of the service
    deceleration it demands (core/src/bcu.c; none when absent), with its own source."""
    jerk_limit_m_s3: Optional[float] = _num("bcu.service_jerk", default=None)
    jerk_limit_source: Optional[str] = None

    @model_validator(mode="after")
    def _sourced(self):
        if self.jerk_limit_m_s3 is not None and not (self.jerk_limit_source or "").strip():
            raise ValueError(f"jerk_limit_m_s3 = {self.jerk_limit_m_s3:g} needs jerk_limit_source (where the "
                             "value comes from)")
        return self


class _BrakeSteps(_Strict):
    emergency: _BrakeStep
    service: _ServiceStep


class _Compressor(_Strict):
    car: int = Field(ge=1, le=_core.MAX_CARS)      # 1-based position in the formation
    delivery_kg_s: float = _num("train.compressor_delivery")


class _MainReservoirPipe(_Strict):
    diameter_mm: float = _num("train.pipe_diameter", MM)
    coupling_area_mm2: float = _num("train.air_flow_area", MM2)   # flow area of the hose couplings between cars


class _AirSupply(_Strict):
    compressors: list[_Compressor] = Field(min_length=1, max_length=_core.MAX_COMPRESSORS)
    governor_on_bar: float = _num("train.main_reservoir_gauge", BAR)       # gauge: a compressor starts below
    governor_off_bar: float = _num("train.main_reservoir_gauge", BAR)      # gauge: and stops above
    charged_bar: float = _num("train.main_reservoir_gauge", BAR)           # gauge: main reservoir and pipe at the start
    # gauge: the brake's working range ends below (a run whose main reservoir falls there warns)
    min_working_bar: float = _num("train.main_reservoir_min_working", BAR)
    main_reservoir_l: float = _num("main_reservoir_volume", L)   # lumped main reservoirs of the whole train
    main_reservoir_outlet_mm2: float = _num("train.air_flow_area", MM2)
    pipe: _MainReservoirPipe
    source: str

    @model_validator(mode="after")
    def _governor(self):
        if not self.governor_off_bar > self.governor_on_bar:
            raise ValueError(f"governor_off_bar = {self.governor_off_bar} must exceed governor_on_bar = "
                             f"{self.governor_on_bar} (bar gauge)")
        if not self.min_working_bar < self.governor_on_bar:
            raise ValueError(f"min_working_bar = {self.min_working_bar} must lie below governor_on_bar = "
                             f"{self.governor_on_bar} (bar gauge): the compressors keep the main reservoir above it")
        if not self.charged_bar <= self.governor_off_bar:
            raise ValueError(f"charged_bar = {self.charged_bar} must not exceed governor_off_bar = "
                             f"{self.governor_off_bar} (bar gauge): the compressors stop there")
        return self


class _Pneumatics(_Strict):
    air_temperature_c: float = _num("temperature", offset=ZERO_CELSIUS)
    discharge_coefficient: float = _num("train.discharge_coefficient")
    critical_ratio: float = _num("train.critical_ratio")
    source: str


class _Coupler(_Strict):
    slack_mm: float = _num("train.coupler_slack", MM)
    stiffness_kN_per_mm: float = _num("coupler.stiffness", KN / MM)
    damping_kN_s_per_m: float = _num("coupler.damping", KN)
    source: str


class _SurfaceLayer(_Strict):
    """The disc's friction surface as its own thermal node (rb_plant_car.disc_surface_*): its share of
    the disc's heat capacity and its conductance to the rest of the disc, per disc."""
    share: float = _num("train.disc_surface_share")
    conductance_W_per_K: float = _num("train.disc_surface_conductance")
    source: str


class _Discs(_Strict):
    per_axle: int = Field(ge=1, le=8)
    mounting: Literal["axle", "wheel"]
    mean_radius_m: float = _num("train.disc_radius")
    mass_kg: float = _num("train.disc_mass")                   # one disc (the part that stores heat)
    specific_heat_J_per_kgK: float = _num("train.disc_specific_heat")
    cooling_W_per_K: _CoolingTable                             # per disc, over speed
    surface_layer: Optional[_SurfaceLayer] = None              # none: one lumped disc


class _Cylinder(_Strict):
    area_m2: float = _num("car.cylinder_area")          # one cylinder per disc (caliper)
    stroke_mm: float = _num("train.cylinder_stroke", MM)
    dead_volume_l: float = _num("train.cylinder_dead_volume", L)
    return_spring_kN: float = _num("train.return_spring", KN)


class _Caliper(_Strict):
    lever_ratio: float = _num("train.lever_ratio")
    efficiency: float = _num("train.caliper_efficiency")


class _PadFade(_Strict):
    """Heat fading (rb_pad_friction): the friction divided by 1 + rate_per_K (T_s - onset_c) above
    the onset, T_s the disc's friction surface temperature."""
    onset_c: float = _num("train.pad_fade_onset", offset=ZERO_CELSIUS)
    rate_per_K: float = _num("train.pad_fade_rate")
    source: str


class _PadFriction(_Strict):
    sintered_low_speed: Optional[float] = _num("train.pad_sintered_low_speed", default=None)
    table: Optional[_PadTable] = None
    fade: Optional[_PadFade] = None    # none: the table alone, at any temperature

    @model_validator(mode="after")
    def _one_form(self):
        if (self.sintered_low_speed is None) == (self.table is None):
            raise ValueError("give exactly one of sintered_low_speed, table")
        return self


class _SupplyReservoir(_Strict):
    volume_l: float = _num("car.supply_volume", L)
    charge_area_mm2: float = _num("train.charge_area", MM2)   # check valve and choke from the MR pipe


class _EpValve(_Strict):
    design: str                                  # valve design file (railbrake valve)
    pilot_volume_l: float = _num("car.pilot_volume", L)
    port_area_mm2: float = _num("train.valve_port_area", MM2)
    response_s: float = _num("car.ep_tau")
    band_bar: float = _num("train.valve_band", BAR)
    supply_margin_bar: float = _num("car.ep_supply_margin", BAR)   # output at most supply - this
    bleed_area_mm2: float = _num("car.ep_bleed_area", MM2)   # pilot stage's feed orifice: the nozzle's bleed


class _RelayValve(_Strict):
    design: str
    output_volume_l: float = _num("car.relay_volume", L)
    supply_area_mm2: float = _num("train.valve_port_area", MM2)
    exhaust_area_mm2: float = _num("train.valve_port_area", MM2)
    band_bar: float = _num("train.valve_band", BAR)
    response_s: float = _num("car.relay_tau")   # membrane's response: lag of its stroke
    sweep_cm3: float = _num("car.relay_sweep", CM3)   # control chamber's growth at the full-opening stroke
    travel: float = _num("car.relay_travel")    # membrane's travel over that stroke (its stops)


class _LoadLimit(_Strict):
    """The load-weighing valve's limit of the emergency control pressure (bar gauge) at the tare
    and the crush mass of the car; linear in the car's mass between them (its air-spring pressure)."""
    tare: float = _num("train.emergency_limit", BAR)
    crush: float = _num("train.emergency_limit", BAR)


class _EmergencyValve(_Strict):
    """The car's emergency circuit beside the EP valve (rb_plant_car.emergency_*): its solenoid
    valve, the choke into the relay valve's control chamber that sets the filling rate, and the
    load-weighing valve that limits the pressure."""
    response_s: float = _num("train.emergency_valve_response")
    choke_diameter_mm: float = _num("train.emergency_choke", MM)
    limit_bar: _LoadLimit
    source: str


class _WspValves(_Strict):
    hold_area_mm2: float = _num("car.hold_area", MM2)
    vent_area_mm2: float = _num("car.vent_area", MM2)
    response_s: float = _num("car.valve_delay")


class _Payload(_Strict):
    """Payload per car (t) of the load cases; "tare" carries none."""
    normal: float = _num("train.car_payload", TONNE)
    crush: float = _num("train.car_payload", TONNE)

    @field_validator("crush")
    @classmethod
    def _heaviest(cls, crush: float, info: ValidationInfo) -> float:
        normal = info.data.get("normal")
        high = config.bound_in("train.car_payload", TONNE)[1]
        if normal is not None and crush < normal:
            raise ValueError(f"must lie in [{normal:g}, {high:g}] t: at least normal = {normal:g} t, "
                             "crush being the heaviest load case")
        return crush


class _CarType(_Strict):
    kind: Literal["motor", "trailer"]
    tare_t: float = _num("train.car_tare", TONNE)
    payload_t: _Payload
    axles: int
    length_m: float = _num("train.car_length")
    axle_positions_m: list[float] = Field(min_length=1, max_length=8)
    wheel_radius_m: float = _num("train.wheel_radius")
    wheelset_inertia_kgm2: float = _num("train.wheelset_inertia")
    discs: _Discs
    cylinder: _Cylinder
    caliper: _Caliper
    pad_friction: _PadFriction
    supply_reservoir: _SupplyReservoir
    ep_valve: _EpValve
    relay_valve: _RelayValve
    wsp_valves: _WspValves
    emergency_valve: Optional[_EmergencyValve] = None   # none: the EP valve brakes in emergency too

    @field_validator("axles")
    @classmethod
    def _four_axles(cls, axles: int) -> int:
        if axles != _core.AXLES_PER_CAR:   # rb_plant: one axle brake, sensor and WSP valve pair per slot
            raise ValueError(f"must be {_core.AXLES_PER_CAR}: the whole-train plant models "
                             f"{_core.AXLES_PER_CAR} axles per car (allowed: {_core.AXLES_PER_CAR})")
        return axles

    @model_validator(mode="after")
    def _geometry(self):
        if len(self.axle_positions_m) != self.axles:
            raise ValueError(f"axle_positions_m has {len(self.axle_positions_m)} entries: one per axle "
                             f"({self.axles}) needed")
        for i, x in enumerate(self.axle_positions_m):
            if not 0.0 <= x <= self.length_m:
                raise ValueError(f"axle_positions_m[{i}] = {x}: must lie in [0, length_m = {self.length_m}] m")
            if i and not x > self.axle_positions_m[i - 1]:   # axles count from the front (rail conditioning)
                raise ValueError(f"axle_positions_m[{i}] = {x}: must exceed axle_positions_m[{i - 1}] = "
                                 f"{self.axle_positions_m[i - 1]} m (axles from the front end)")
        return self


class _SandRateTable(_Table):
    """A variable-rate sander's sand rate (kg/min, both rails) over its car's speed."""
    VALUE_BOUND: ClassVar[tuple] = ("train.sand_rate", 1.0 / 60.0, "kg/min")

    @model_validator(mode="after")
    def _sands(self):
        if not max(self.value) > 0.0:
            raise ValueError("every rate is 0 kg/min: the sander never sands")
        return self


class _Sander(_Strict):
    car: int = Field(ge=1, le=_core.MAX_CARS)            # 1-based position in the train
    axle: int = Field(ge=1, le=4)                       # 1-based within the car: sand falls in front of it
    # sand rate (both rails): a number for a fixed-rate sander, {speed_kmh, value} for a
    # variable-rate one (linear between the points, constant beyond)
    rate_kg_min: Union[Annotated[float, Field(gt=0.0, le=60.0)], _SandRateTable]
    trigger: Literal["driver", "wsp"] = "wsp"           # driver: from start_s on; wsp: while a WSP valve acts
    start_s: float = Field(default=0.0, ge=0.0, le=3600.0)


class _Sanders(_Strict):
    """Sanders, a conditioning source of the rail cells (core/src/rail_conditioning.c): they act in
    runs whose adhesion condition cleans the rail cell by cell (scenario rail_conditioning: cells)."""
    units: list[_Sander] = Field(min_length=1, max_length=_core.MAX_SANDERS)
    sand_reference_kg_m: float = Field(gt=0.0, le=10.0)  # sand per metre of track that removes 63 % of the contamination
    # of a cell's loose sand, the part each passing axle crushes into its contact and the part it
    # leaves loose for the axles behind (the rest is carried away; core/src/rail_conditioning.c)
    sand_entrained: float = Field(gt=0.0, le=1.0)
    sand_retention: float = Field(ge=0.0, le=1.0)
    source: str

    @model_validator(mode="after")
    def _shares(self):
        if self.sand_entrained + self.sand_retention > 1.0:
            raise ValueError(f"sand_entrained + sand_retention = {self.sand_entrained + self.sand_retention:g}: "
                             "must be <= 1 (shares of the same sand)")
        return self


class _Etcs(_Strict):
    """The train's ETCS train data not computed from its brake (railbrake.etcs.service)."""
    traction_cut_off_s: float = Field(gt=0.0, le=60.0)   # SUBSET-026 T_traction_cut_off
    traction_cut_off_implemented: bool = True             # the on-board commands the cut-off (3.13.9.3.2.3)
    source: str


class _TrainFile(_Strict):
    schema_: str = Field(alias="schema")
    name: str
    title: str
    source: str
    assumptions: list[str] = []
    max_speed_kmh: float = _num("train.max_speed", KMH)
    supply_pressure_bar: float = Field(gt=0.0)              # gauge, highest cylinder pressure (bound: _supply)
    atmospheric_pressure_bar: float = _num("train.atmosphere", BAR)  # absolute
    running_resistance: _Resistance
    ed_brake: Optional[_EdBrake] = None
    brake_steps: _BrakeSteps
    emergency_loop: Optional[_EmergencyLoop] = None
    air_supply: _AirSupply
    pneumatics: _Pneumatics
    coupler: _Coupler
    load_case: Literal["tare", "normal", "crush"] = "normal"
    car_types: dict[str, _CarType]
    formation: list[str] = Field(min_length=1, max_length=_core.MAX_CARS)
    sanders: Optional[_Sanders] = None
    etcs: Optional[_Etcs] = None

    @model_validator(mode="after")
    def _known_types(self):
        for i, name in enumerate(self.formation):
            if name not in self.car_types:
                raise ValueError(f"formation[{i}] = {name!r}: not one of car_types "
                                 f"({', '.join(self.car_types)})")
        fitted = [name for name, t in self.car_types.items() if t.emergency_valve is not None]
        if fitted and self.emergency_loop is None:
            raise ValueError(f"car_types {', '.join(fitted)} have an emergency_valve: the train needs an "
                             "emergency_loop (how the command reaches the cars)")
        for i, c in enumerate(self.air_supply.compressors):
            if c.car > len(self.formation):
                raise ValueError(f"air_supply.compressors[{i}].car = {c.car}: the formation has cars "
                                 f"1..{len(self.formation)}")
        return self


# ------------------------------------------------------------------ the train

@dataclass(frozen=True)
class Car:
    """One car (SI). ``c`` is its rb_car struct."""

    index: int
    type_name: str
    motor: bool
    tare: float  # kg
    load: float  # kg, payload of the train's load case
    axles: int
    wheel_radius: float  # m
    wheelset_inertia: float  # kg m^2
    c: _core.Car
    equipment: _CarType  # the car type as validated from the file (file units)

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
    spec: _TrainFile  # the whole file as validated (file units): brake equipment, air supply
    load_case: str = "normal"
    origin: str = ""   # the file (or preset) it was read from, and the lines of its keys (for errors)
    lines: dict = field(default_factory=dict, repr=False, compare=False)

    def with_(self, changes=None, /, **kwargs) -> "Train":
        """A copy with keys of the train file changed, e.g. ``with_(max_speed_kmh=300)`` or
        ``with_({'car_types.motor.tare_t': 50, 'load_case': 'crush'})``: keys and values in file
        units, as ``--set train.KEY=VALUE`` takes them, validated as a whole as a train file is."""
        merged = _changes.merge(changes, kwargs, "Train.with_")
        data = self.spec.model_dump(mode="json", by_alias=True)
        labels = _changes.apply_changes(data, merged, _TrainFile)
        loaded = data.get("load_case") if "load_case" in merged else self.load_case
        train = parse_train_data(data, self.origin, self.lines, loaded, overrides=labels)
        return train if len(self.cars) == len(self.spec.formation) else with_cars(train, len(self.cars))

    def brake_step(self, kind: str) -> _BrakeStep:
        """The train's "emergency" or "service" brake step: profile name and ED blending."""
        return getattr(self.spec.brake_steps, kind)

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


def _refuse_assignment(self, name, value=None):
    _changes.refuse_assignment("train", name)


# immutable, with a message naming the way to change them (dataclass's own says only "cannot assign")
Train.__setattr__ = Train.__delattr__ = _refuse_assignment
Car.__setattr__ = Car.__delattr__ = _refuse_assignment


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
    if pad.fade is not None:
        out.fade_onset, out.fade_rate = pad.fade.onset_c + ZERO_CELSIUS, pad.fade.rate_per_K
    return out


def _payload_t(t: _CarType, load_case: str) -> float:
    return 0.0 if load_case == "tare" else getattr(t.payload_t, load_case)


def _car_struct(t: _CarType, ed: _core.EdCurve, p_atm: float, supply: float, load_case: str) -> _core.Car:
    mass = tonne_to_kg(t.tare_t + _payload_t(t, load_case))
    c = _core.Car()
    c.motor, c.axles, c.mass = int(t.kind == "motor"), t.axles, mass
    c.wheelset = _core.Wheelset(t.wheel_radius_m, t.wheelset_inertia_kgm2, mass / t.axles)
    c.brake.discs = t.discs.per_axle
    c.brake.mounting = 1 if t.discs.mounting == "wheel" else 0
    c.brake.mean_radius = t.discs.mean_radius_m
    k, cyl = t.caliper, t.cylinder
    c.brake.caliper = _core.Caliper(cyl.area_m2, kn_to_n(cyl.return_spring_kN), k.lever_ratio,
                                    k.efficiency, p_atm)
    c.brake.pad = _pad_friction(t.pad_friction)
    if c.motor:
        c.ed = ed
    c.supply_pressure = supply
    return c


def _build(model: _TrainFile, load_case: str) -> Train:
    p_atm = bar_to_pa(model.atmospheric_pressure_bar)
    supply = p_atm + bar_to_pa(model.supply_pressure_bar)
    types = [model.car_types[n] for n in model.formation]
    motors = sum(t.kind == "motor" for t in types)
    ed = _ed_curve(model.ed_brake, max(motors, 1))
    train_c = _core.TrainC()
    train_c.n_cars = len(types)
    cars = []
    for i, (name, t) in enumerate(zip(model.formation, types)):
        train_c.cars[i] = _car_struct(t, ed, p_atm, supply, load_case)
        cars.append(Car(i, name, t.kind == "motor", tonne_to_kg(t.tare_t), tonne_to_kg(_payload_t(t, load_case)),
                        t.axles, t.wheel_radius_m, t.wheelset_inertia_kgm2, train_c.cars[i], t))
    r = model.running_resistance
    train_c.resistance = _core.Resistance(kn_to_n(r.A_kN), kn_to_n(r.B_kN_per_kmh) / KMH,
                                          kn_to_n(r.C_kN_per_kmh2) / KMH**2)
    _core.call(_core.rb_train_check, ctypes.byref(train_c))
    return Train(model.name, model.title, " ".join(model.source.split()), tuple(model.assumptions),
                 model.max_speed_kmh * KMH, tuple(cars), train_c, model, load_case)


def with_cars(train: Train, n_cars: int) -> Train:
    """The train lengthened or shortened to n_cars by repeating its formation. Running
    resistance: A and B scale with the mass, C (air) with 0.2 + 0.8 n/N (head and tail
    unchanged) [T]."""
    instance("train", train, Train)
    n = len(train.cars)
    n_cars = whole("n_cars", n_cars)
    if n_cars == n:
        return train
    if not 1 <= n_cars <= _core.MAX_CARS:
        raise InputError(f"n_cars = {n_cars}: must be in [1, {_core.MAX_CARS}]")
    c = _core.TrainC()
    c.n_cars = n_cars
    for i in range(n_cars):
        c.cars[i] = train.c.cars[i % n]
    r = train.c.resistance
    mass_ratio = sum(train.cars[i % n].c.mass for i in range(n_cars)) / train.mass
    c.resistance = _core.Resistance(r.A * mass_ratio, r.B * mass_ratio, r.C * (0.2 + 0.8 * n_cars / n))
    _core.call(_core.rb_train_check, ctypes.byref(c))
    cars = tuple(replace(train.cars[i % n], index=i, c=c.cars[i]) for i in range(n_cars))
    return replace(train, cars=cars, c=c, title=f"{train.title}, {n_cars} cars")


def _preset_dir():
    return resources.files("railbrake") / "data" / "trains"


def preset_names() -> list[str]:
    return sorted(p.name[:-5] for p in _preset_dir().iterdir() if p.name.endswith(".yaml"))


def _load_case(loaded: Union[bool, str, None], model: _TrainFile, origin: str) -> str:
    """loaded: a load case name, True (the file's own load_case) or False (tare)."""
    if loaded is True or loaded is None:
        return model.load_case
    if loaded is False:
        return "tare"
    if not isinstance(loaded, str) or loaded not in LOAD_CASES:
        raise InputError(f"loaded = {loaded!r}: must be a load case ({', '.join(LOAD_CASES)}), True (the train "
                         "file's) or False (tare)")
    return loaded


def _refuse_old_schema(data: dict, origin: str, lines: dict) -> None:
    schema = data.get("schema") if isinstance(data, dict) else None
    if schema in OLD_SCHEMAS:
        line = lines.get(("schema",)) if lines else None
        raise InputError(f"{origin}{f', line {line}' if line else ''}: schema = {schema!r}: no longer read; "
                         f"train files are {SCHEMA!r} now, carrying the whole brake equipment "
                         "(see docs/vehicle.md, or copy a preset: railbrake config show)")


def parse_train_data(data: dict, origin: str, lines: dict, loaded: Union[bool, str] = True,
                     overrides: dict | None = None) -> Train:
    """A Train from the data of a train file (a dict in file units, e.g. with overrides applied);
    lines and overrides say where each key came from; loaded: load case name, True (the file's
    load_case) or False (tare)."""
    _refuse_old_schema(data, origin, lines)
    model = validate_data(data, _TrainFile, config.locator(origin, lines, overrides))
    if model.schema_ != SCHEMA:
        raise InputError(f"{origin}: schema = {model.schema_!r}: expected {SCHEMA!r}")
    locate = config.locator(origin, lines, overrides)
    _check_supply(model, locate)
    _check_references(model, locate)
    _check_ed_use(model, locate)
    load_case = _load_case(loaded, model, origin)
    try:
        train = _build(model, load_case)
    except InputError as exc:
        raise InputError(f"{origin}: {exc}") from None
    train = replace(train, origin=origin, lines=lines)
    _check_ed_force(train, locate)
    return train


def _check_references(model: _TrainFile, locate) -> None:
    """The brake steps' profiles load and the valve designs name a design file: a name that names
    nothing is refused here, with its key, not when a run first needs it."""
    from railbrake.profiles import load_profile
    for step in ("emergency", "service"):
        name = getattr(model.brake_steps, step).profile
        try:
            load_profile(name)
        except InputError as exc:
            raise InputError(f"{locate(('brake_steps', step, 'profile'))}: brake_steps.{step}.profile = {name!r}: "
                             f"{str(exc).removeprefix(f'profile = {name!r}: ')}") from None
    designs = valve_design_names()
    for type_name, t in model.car_types.items():
        for valve in ("ep_valve", "relay_valve"):
            design = getattr(t, valve).design
            if design not in designs and not Path(design).is_file():
                raise InputError(f"{locate(('car_types', type_name, valve, 'design'))}: car_types.{type_name}.{valve}"
                                 f".design = {design!r}: not a valve design ({', '.join(designs)}) nor a file")


def _check_ed_use(model: _TrainFile, locate) -> None:
    """An ED brake the train cannot use (no motor car), or ED blending without an ED brake, would
    change nothing: refused."""
    if model.ed_brake is not None and all(model.car_types[n].kind != "motor" for n in model.formation):
        raise InputError(f"{locate(('ed_brake',))}: ed_brake: the formation has no motor car, so no ED brake "
                         "acts: remove ed_brake or put a motor car (kind: motor) in the formation")
    for step in ("emergency", "service"):
        if model.ed_brake is None and getattr(model.brake_steps, step).ed_blending:
            raise InputError(f"{locate(('brake_steps', step, 'ed_blending'))}: brake_steps.{step}.ed_blending = "
                             "true: the train has no ed_brake to blend (allowed: false, or add ed_brake)")


def _check_ed_force(train: Train, locate) -> None:
    """The ED curve (any branches and table) inside the bound train.ed_force and above zero from 1 km/h
    to the top speed: the C law takes a negative force as none, which would remove the ED brake unseen."""
    if train.spec.ed_brake is None or not any(car.motor for car in train.cars):
        return
    speeds = np.linspace(1.0, train.max_speed / KMH, 400) * KMH
    force = np.atleast_1d(train.ed_brake_force(speeds))
    low, high, why = config.bound_in("train.ed_force", KN)
    low = max(low, 0.0)
    bad = np.flatnonzero(~((force > low * KN) & (force <= high * KN)))
    if bad.size and force[bad[0]] <= 0.0:
        v = speeds[bad[0]] / KMH
        raise InputError(f"{locate(('ed_brake',))}: ed_brake (branches_kN c0, c1, c2, table_kN, scale): the whole-train "
                         f"ED force at {v:.0f} km/h is zero or negative (taken as no ED brake at all): it must lie in "
                         f"(0, {high:g}] kN from 1 km/h to max_speed_kmh ({why}); a train without an ED brake "
                         "omits ed_brake")
    if bad.size:
        i = bad[0]
        raise InputError(f"{locate(('ed_brake',))}: ed_brake (branches_kN c0, c1, c2, table_kN, scale): the whole-train "
                         f"ED force at {speeds[i] / KMH:.0f} km/h is {force[i] / KN:.4g} kN: must lie in [{low:g}, "
                         f"{high:g}] kN ({why})")


def _check_supply(model: _TrainFile, locate) -> None:
    """The brake supply: absolute inside the plant's bound, and below the main reservoir that charges it."""
    gauge, atm = model.supply_pressure_bar, model.atmospheric_pressure_bar
    where = f"{locate(('supply_pressure_bar',))}: supply_pressure_bar = {gauge:g}"
    if not config.within("car.supply_pressure", bar_to_pa(atm + gauge)):
        low, high, why = config.bound_in("car.supply_pressure", BAR, bar_to_pa(atm))
        raise InputError(f"{where}: must lie in [{low:.3g}, {high:.3g}] bar gauge at atmospheric_pressure_bar = "
                         f"{atm:g} ({why})")
    working = model.air_supply.min_working_bar
    if not gauge < working:
        raise InputError(f"{where}: must stay below air_supply.min_working_bar = {working:g} (bar gauge; "
                         f"{locate(('air_supply', 'min_working_bar'))}): a main reservoir at its minimum working "
                         "pressure still charges the brake supply")
    governor_on = model.air_supply.governor_on_bar
    if not gauge < governor_on:
        raise InputError(f"{where}: must stay below air_supply.governor_on_bar = {governor_on:g} (bar gauge; "
                         f"{locate(('air_supply', 'governor_on_bar'))}): the main reservoir pipe charges the "
                         "brake supply")


def read_train_data(text: str, origin: str) -> tuple[dict, dict]:
    """The data of a train file's text and its line index (key path -> line)."""
    data = config.load_mapping(text, origin)
    return data, config.line_index(text)


_UNIT_OF_SUFFIX = {"_t": "t", "_kgm2": "kg m^2", "_l": "l", "_mm2": "mm^2", "_m2": "m^2", "_mm": "mm",
                   "_m": "m", "_bar": "bar", "_kN": "kN", "_s": "s", "_kg_s": "kg/s", "_kmh": "km/h",
                   "_kg": "kg", "_c": "degC", "_kN_per_mm": "kN/mm", "_kN_s_per_m": "kN s/m",
                   "_J_per_kgK": "J/(kg K)", "_kN_per_kmh": "kN/(km/h)", "_kN_per_kmh2": "kN/(km/h)^2"}


_UNIT_OF_KEY = {"c0": "kN", "c1": "kN s/m", "c2": "kN m/s"}   # keys without a unit suffix (ed_brake.branches_kN)


def _unwrap(annotation):
    """X from Optional[X]."""
    if get_origin(annotation) in (Union, types.UnionType):
        args = [a for a in get_args(annotation) if a is not type(None)]
        return args[0] if len(args) == 1 else annotation
    return annotation


def _field_info(model, loc):
    """The pydantic FieldInfo at an error location (None if the location is not a model field)."""
    annotation, info = model, None
    for part in loc:
        annotation = _unwrap(annotation)
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            info = annotation.model_fields.get("schema_" if part == "schema" else part)
            if info is None:
                return None
            annotation = info.annotation
        elif get_origin(annotation) in (dict, list):
            annotation, info = get_args(annotation)[-1], None
        else:
            return None
    return info


def _range_text(model, error) -> str | None:
    """'must lie in [5, 100] t' for a number out of its plausible range."""
    if error["type"] not in ("greater_than_equal", "less_than_equal", "greater_than", "less_than"):
        return None
    info = _field_info(model, error["loc"])
    if info is None:
        return None
    lo = hi = None
    low_open = False
    for m in info.metadata:
        lo = getattr(m, "ge", lo)
        if getattr(m, "gt", None) is not None:
            lo, low_open = m.gt, True
        hi = getattr(m, "le", hi)
    key = str(error["loc"][-1])
    unit = _UNIT_OF_KEY.get(key) or next((u for suffix, u in sorted(_UNIT_OF_SUFFIX.items(), key=lambda x: -len(x[0]))
                                          if key.endswith(suffix)), "")
    if lo is None or hi is None:
        return None
    why = f" ({info.description})" if info.description else ""
    return f"must lie in {'(' if low_open else '['}{lo:.6g}, {hi:.6g}] {unit}".rstrip() + why


def validate_data(data: dict, model, locate):
    """data validated against a pydantic model; InputError names key, value, where it came from
    (locate(key path): file and line, or the override) and the plausible range."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        messages = []
        for error in exc.errors():
            text = config._describe(error)
            allowed = _range_text(model, error)
            if allowed:
                key = ".".join(str(p) for p in error["loc"])
                text = f"{key} = {error.get('input')!r}: {allowed}"
            messages.append(f"{locate(tuple(error['loc']))}: {text}")
        raise InputError("\n".join(messages)) from None


def parse_train(text: str, origin: str, loaded: Union[bool, str] = True) -> Train:
    data, lines = read_train_data(text, origin)
    return parse_train_data(data, origin, lines, loaded)


def train_file_text(name_or_path: Union[str, Path]) -> tuple[str, str]:
    """(text, origin) of a preset name or a train YAML file."""
    name = _name_or_path("train", name_or_path)
    if name in preset_names():
        return (_preset_dir() / f"{name}.yaml").read_text(), f"train {name}"
    path = Path(name)
    if path.suffix in (".yaml", ".yml") and path.is_file():
        return config.read_text(path), str(path)
    raise InputError(f"train = {name!r}: not a preset ({', '.join(preset_names())}) nor a YAML file")


def valve_design_names() -> list[str]:
    return sorted(p.name[:-5] for p in (resources.files("railbrake") / "data" / "valves").iterdir()
                  if p.name.endswith(".yaml"))


def anchor_files(data: dict, folder: Path | None) -> dict:
    """The files a train file names (its brake steps' profiles, its valves' design files), relative
    to the train file's folder, made absolute in data (in place), so the train loads from any
    current folder; presets' names stay."""
    from railbrake.profiles import profile_names
    if folder is None or not isinstance(data, dict):
        return data
    for step in (data.get("brake_steps") or {}).values():
        if isinstance(step, dict) and isinstance(step.get("profile"), str):
            step["profile"] = config.in_folder(step["profile"], folder, profile_names())
    for car_type in (data.get("car_types") or {}).values():
        for valve in ("ep_valve", "relay_valve"):
            block = car_type.get(valve) if isinstance(car_type, dict) else None
            if isinstance(block, dict) and isinstance(block.get("design"), str):
                block["design"] = config.in_folder(block["design"], folder, valve_design_names())
    return data


def load_train(name_or_path: Union[str, Path, Train], loaded: Union[bool, str] = True) -> Train:
    """A preset name (see preset_names()) or a YAML file (the files it names: relative to its folder);
    loaded: load case ("tare", "normal", "crush"), True for the file's own, False for tare."""
    if isinstance(name_or_path, Train):
        return name_or_path
    text, origin = train_file_text(name_or_path)
    data, lines = read_train_data(text, origin)
    folder = Path(origin).resolve().parent if Path(origin).is_file() else None
    return parse_train_data(anchor_files(data, folder), origin, lines, loaded)


# ------------------------------------------------------------------ single laws, for users and tests

def pad_friction_sintered(speed, low_speed_value: float = SINTERED_LOW_SPEED):
    """lambda(v) of the default sintered pad [T] at speed (m/s)."""
    pad = _core.PadFriction()
    _core.call(_core.rb_pad_friction_sintered, real("low_speed_value", low_speed_value), ctypes.byref(pad))
    return _vectorised(lambda v: _core.rb_pad_friction_at(ctypes.byref(pad), v), _speeds(speed))


def equivalent_rotating_mass(wheelsets) -> float:
    """Sum of J / r^2 (kg) over (wheel_radius m, inertia kg m^2, axle_load kg) triples."""
    if isinstance(wheelsets, (str, bytes)) or not hasattr(wheelsets, "__iter__"):
        raise TypeError(f"wheelsets = {wheelsets!r}: must be an iterable of (wheel_radius, inertia, axle_load)")
    wheelsets = list(wheelsets)
    rows = []
    for i, w in enumerate(wheelsets):
        if isinstance(w, (str, bytes)) or not hasattr(w, "__len__") or len(w) != 3:
            raise TypeError(f"wheelsets[{i}] = {w!r}: must be (wheel_radius m, inertia kg m^2, axle_load kg)")
        rows.append(_core.Wheelset(real(f"wheelsets[{i}] wheel_radius", w[0], 0.0, low_open=True),
                                   real(f"wheelsets[{i}] inertia", w[1], 0.0),
                                   real(f"wheelsets[{i}] axle_load", w[2], 0.0)))
    array = (_core.Wheelset * max(len(rows), 1))(*rows)
    out = ctypes.c_double()
    _core.call(_core.rb_equivalent_rotating_mass, array, len(wheelsets), ctypes.byref(out))
    return out.value


def caliper_pad_force(cylinder_pressure: float, cylinder_area: float, return_spring: float,
                      lever_ratio: float, efficiency: float, atmospheric_pressure: float = P_ATM) -> float:
    """Pad normal force (N) from the absolute cylinder pressure (Pa), EN 14531 form (checked)."""
    # ranges of the API: beyond them the force overflows (areas to 10 m^2, ratios to 1000, 1 GPa)
    c = _core.Caliper(real("cylinder_area", cylinder_area, 0.0, 10.0, low_open=True),
                      real("return_spring", return_spring, 0.0, 1e9),
                      real("lever_ratio", lever_ratio, 0.0, 1e3, low_open=True),
                      real("efficiency", efficiency, 0.0, 1.0, low_open=True),
                      real("atmospheric_pressure", atmospheric_pressure, 0.0, 1e9, low_open=True))
    _core.call(_core.rb_caliper_check, ctypes.byref(c))
    return _core.rb_caliper_pad_force(ctypes.byref(c), real("cylinder_pressure", cylinder_pressure, 0.0, 1e9))


def coupler_force(dx: float, dv: float, slack: float, stiffness: float, stiffness_cubic: float = 0.0,
                  damping: float = 0.0) -> float:
    """Coupler tension (N) at extension dx (m) and its rate dv (m/s) (checked)."""
    c = _core.Coupler(real("slack", slack, 0.0), real("stiffness", stiffness, 0.0, low_open=True),
                      real("stiffness_cubic", stiffness_cubic, 0.0), real("damping", damping, 0.0))
    _core.call(_core.rb_coupler_check, ctypes.byref(c))
    force = _core.rb_coupler_force(ctypes.byref(c), real("dx", dx), real("dv", dv))
    if not math.isfinite(force):   # e.g. a cubic term of 1e308: not a force
        raise InputError(f"coupler_force: dx = {dx:g} m, dv = {dv:g} m/s give a force beyond any float")
    return force


def with_constant_pad_friction(train: Train, speed: float | None = None) -> Train:
    """The same train with each pad's lambda frozen at its value at `speed` (m/s; default: top
    speed); comparing the two shows what lambda(v) does to the target pressure."""
    instance("train", train, Train)
    v = train.max_speed if speed is None else real("speed", speed, 0.0)
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
    pad = ctypes.byref(instance("car", car, Car).c.brake.pad)
    return _vectorised(lambda v: _core.rb_pad_friction_at(pad, v), _speeds(speed))


def pad_friction_at_temperature(car: Car, speed, surface_temperature: float):
    """The instantaneous friction of a car's pads at speed (m/s) on a friction surface at
    surface_temperature (K): the table faded by the heat (rb_pad_friction_eval)."""
    pad = ctypes.byref(instance("car", car, Car).c.brake.pad)
    t = real("surface_temperature", surface_temperature, 0.0, 5000.0)
    return _vectorised(lambda v: _core.rb_pad_friction_eval(pad, v, t), _speeds(speed))


@dataclass(frozen=True)
class AxleDiscs:
    """The discs of one of a car's axles as the plant and the stopping distance heat them (SI)."""
    heat_capacity: float        # J/K
    surface_capacity: float     # J/K, the friction surface layer's (0: one lumped node)
    surface_conductance: float  # W/K, surface to bulk
    cooling_speed: np.ndarray   # m/s
    cooling: np.ndarray         # W/K over cooling_speed


def axle_discs(car: Car) -> AxleDiscs:
    """A car's discs per axle from its train file: discs x one disc's heat capacity, its surface
    layer's share and conductance, its cooling."""
    discs = instance("car", car, Car).equipment.discs
    capacity = discs.per_axle * discs.mass_kg * discs.specific_heat_J_per_kgK
    layer = discs.surface_layer
    return AxleDiscs(capacity, 0.0 if layer is None else layer.share * capacity,
                     0.0 if layer is None else discs.per_axle * layer.conductance_W_per_K,
                     np.asarray(discs.cooling_W_per_K.speed_kmh, dtype=float) * KMH,
                     discs.per_axle * np.asarray(discs.cooling_W_per_K.value, dtype=float))


def train_discs(train: Train) -> _core.TrainDiscs:
    """Every car's axle discs (axle_discs) for the stopping distance, at the train's air temperature."""
    out = _core.TrainDiscs()
    for k, car in enumerate(instance("train", train, Train).cars):
        d = axle_discs(car)
        out.heat_capacity[k], out.surface_capacity[k], out.surface_conductance[k] = (
            d.heat_capacity, d.surface_capacity, d.surface_conductance)
        out.cooling[k] = _core.speed_table(d.cooling_speed, d.cooling)
    out.ambient_temperature = train.spec.pneumatics.air_temperature_c + ZERO_CELSIUS
    return out


@dataclass(frozen=True)
class DynoStop:
    """A dynamometer stop of one of a car's discs (rb_dyno_stop_run; SI, temperatures in K)."""
    mean_friction: float            # UIC 541-3's mean: (1/s) int mu ds
    max_surface_temperature: float
    max_mean_temperature: float
    heat: float                     # J into the disc
    stored: float                   # J in the disc at the stop
    cooled: float                   # J to the air
    distance: float                 # m
    time: float                     # s
    pad_force: float                # N per pad


def dynamometer_stop(car: Car, initial_speed: float, deceleration: float, ambient_temperature: float,
                     dt: float = 1e-3, pad: _core.PadFriction | None = None) -> DynoStop:
    """One of a car's discs on a dynamometer: the mass it brakes (the car's over its discs) from
    initial_speed (m/s) to a stop at a constant pad force, the force that gives `deceleration`
    (m/s^2) with the cold pad's friction at the initial speed; the pads fade with the disc's surface
    temperature as in the plant (the car's discs and pads as in its train file, cooling included).
    ambient_temperature (K): the disc's at the start and its cooling's reference; pad: other pads
    than the car's (a fit's trial, railbrake.pad_fade)."""
    instance("car", car, Car)
    if pad is not None:
        instance("pad", pad, _core.PadFriction)
    v0 = real("initial_speed", initial_speed, 0.0, 200.0, low_open=True)
    a = real("deceleration", deceleration, 0.0, 10.0, low_open=True)
    discs, brake = car.equipment.discs, car.c.brake
    pad = brake.pad if pad is None else pad
    n_discs = car.axles * discs.per_axle
    mass = car.c.mass / n_discs
    mu0 = _core.rb_pad_friction_at(ctypes.byref(pad), v0)
    d = _core.DynoStop()
    d.initial_speed, d.mass = v0, mass
    d.pad_force = mass * a * car.wheel_radius / (2.0 * mu0 * brake.mean_radius)
    d.friction_radius, d.wheel_radius = brake.mean_radius, car.wheel_radius
    d.heat_capacity = discs.mass_kg * discs.specific_heat_J_per_kgK
    if discs.surface_layer is not None:
        d.surface_capacity = discs.surface_layer.share * d.heat_capacity
        d.surface_conductance = discs.surface_layer.conductance_W_per_K
    d.cooling = _core.speed_table(np.asarray(discs.cooling_W_per_K.speed_kmh) * KMH, discs.cooling_W_per_K.value)
    d.ambient_temperature = real("ambient_temperature", ambient_temperature, 200.0, 350.0)
    d.dt = real("dt", dt, 0.0, 0.1, low_open=True)
    r = _core.DynoResult()
    _core.call(_core.rb_dyno_stop_run, ctypes.byref(pad), ctypes.byref(d), ctypes.byref(r))
    return DynoStop(r.mean_friction, r.max_surface_temperature, r.max_mean_temperature, r.heat, r.stored, r.cooled,
                    r.distance, r.time, d.pad_force)


def _speeds(speed):
    """speed (m/s): a number or an array of numbers, finite and >= 0, as the caller gave it."""
    if isinstance(speed, numbers.Real) and not isinstance(speed, bool):
        return real("speed", speed, 0.0)
    return reals("speed", speed, 0.0)
