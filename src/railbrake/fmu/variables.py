"""The FMU's variables, in one table: value reference (position), name, causality, type, unit,
start, range and where the value lives in the C instance (core/fmi/fmu_model.h, fmu_instance).

modelDescription.xml (FMI 2 and 3) and the C variable table of fmu_scenario.c are both written
from this list. Parameter start values are read from the scenario's ctypes structs at the same
C path, so the XML, the generated C and the native run agree by construction.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace

from railbrake import _core
from railbrake.units import BAR, KMH, KN, TONNE
from railbrake.vehicle import L, MM2, ZERO_CELSIUS

INF = math.inf


@dataclass(frozen=True)
class Variable:
    name: str
    causality: str          # independent | parameter | input | output
    type: str               # Real | Boolean
    where: str              # C member designator inside fmu_instance
    unit: str | None = None
    start: float | bool | None = None
    min: float = -INF
    max: float = INF
    description: str = ""
    tunable: bool = False           # a parameter that may change between doSteps


@dataclass(frozen=True)
class Unit:
    base: dict                      # SI base-unit exponents (FMI BaseUnit)
    quantity: str
    displays: tuple = ()            # (name, factor, offset): display value = factor * value + offset
    default_display: str | None = None


def units(atmosphere: float) -> dict[str, Unit]:
    """Every unit the FMU uses, with its quantity and the display units integrators read: pressures
    (absolute inside) in bar gauge over the train's own atmosphere, speeds in km/h, temperatures in
    degC, forces in kN, masses in t, volumes in l, areas in mm2."""
    pa = {"kg": 1, "m": -1, "s": -2}
    return {
        "m": Unit({"m": 1}, "Length"), "m/s": Unit({"m": 1, "s": -1}, "Velocity", (("km/h", 1 / KMH, 0.0),), "km/h"),
        "m/s2": Unit({"m": 1, "s": -2}, "Acceleration"), "s": Unit({"s": 1}, "Time", (("ms", 1e3, 0.0),)),
        "kg": Unit({"kg": 1}, "Mass", (("t", 1 / TONNE, 0.0),), "t"),
        "kg/s": Unit({"kg": 1, "s": -1}, "MassFlowRate"),
        "K": Unit({"K": 1}, "ThermodynamicTemperature", (("degC", 1.0, -ZERO_CELSIUS),), "degC"),
        "m2": Unit({"m": 2}, "Area", (("mm2", 1 / MM2, 0.0),), "mm2"),
        "m3": Unit({"m": 3}, "Volume", (("l", 1 / L, 0.0),), "l"),
        "Pa": Unit(pa, "Pressure", (("bar_g", 1 / BAR, -atmosphere / BAR), ("bar", 1 / BAR, 0.0)), "bar_g"),
        "N": Unit({"kg": 1, "m": 1, "s": -2}, "Force", (("kN", 1 / KN, 0.0),), "kN"),
        "N/m": Unit({"kg": 1, "s": -2}, "TranslationalSpringConstant", (("kN/mm", 1e-6, 0.0),), "kN/mm"),
        "N.s/m": Unit({"kg": 1, "s": -1}, "TranslationalDampingConstant"),
        "1": Unit({}, "Dimensionless"),
    }


# Parameters that may change between doSteps (variability tunable): the WSP's and the adhesion,
# applied at the next doStep as rb_run_retune applies them in a native run (simulation.Change).
TUNABLE = frozenset({"adhesion_mu0", "wsp_speed_threshold", "wsp_slip_threshold", "wsp_decel_threshold",
                     "wsp_reaccel_threshold", "wsp_safety_time"})

# Global parameters: name, C path, unit, description.
_PARAMETERS = [
    ("initial_speed", "plant.initial_speed", "m/s", "train speed at t = 0"),
    ("initial_pressure", "plant.initial_pressure", "Pa",
     "main reservoir, pipe and supply reservoirs at t = 0 (absolute)"),
    ("main_reservoir_volume", "plant.main_reservoir_volume", "m3", "main reservoir volume"),
    ("compressor_flow", "plant.compressor_flow", "kg/s", "compressor delivery when running"),
    ("governor_on", "plant.governor_on", "Pa", "compressor starts below this main-reservoir pressure"),
    ("governor_off", "plant.governor_off", "Pa", "compressor stops above this main-reservoir pressure"),
    ("air_temperature", "plant.temperature", "K", "air temperature (volumes) and the cylinders' wall temperature"),
    ("cylinder_wall_time", "plant.wall_time", "s",
     "brake cylinders' wall heat-exchange time for their air at 5 bar abs (0: isothermal cylinders)"),
    ("coupler_stiffness", "plant.coupler.stiffness", "N/m", "coupler stiffness beyond the slack"),
    ("coupler_damping", "plant.coupler.damping", "N.s/m", "coupler damping"),
    ("adhesion_mu0", "plant.condition[0].polach.mu0", "1",
     "Polach maximum friction coefficient outside the track zones"),
    ("bcu_cycle", "bcu.cycle", "s", "BCU cycle time"),
    ("service_deceleration", "bcu.service_decel", "m/s2", "demanded deceleration at full service brake"),
    ("emergency_deceleration", "bcu.emergency_decel", "m/s2", "demanded deceleration in emergency"),
    ("wsp_speed_threshold", "wsp.speed_threshold", "m/s", "WSP: speed difference that starts venting"),
    ("wsp_slip_threshold", "wsp.slip_threshold", "1", "WSP: plus this fraction of the reference speed"),
    ("wsp_decel_threshold", "wsp.decel_threshold", "m/s2", "WSP: wheel deceleration that starts venting"),
    ("wsp_reaccel_threshold", "wsp.reaccel_threshold", "m/s2", "WSP: wheel acceleration that ends venting"),
    ("wsp_safety_time", "wsp.safety_time", "s", "WSP: longest continuous venting"),
]

# Per car parameters: name (suffixed _c<car>), C path with {i} the 0-based car, unit, description.
_CAR_PARAMETERS = [
    ("mass", "plant.car[{i}].vehicle.mass", "kg",
     "car mass (dynamics and BCU load-weighing; wheel loads and contact stay as exported)"),
    ("supply_pressure", "plant.car[{i}].vehicle.supply_pressure", "Pa",
     "brake supply pressure (absolute), the BCU's maximum demand"),
    ("cylinder_area", "plant.car[{i}].vehicle.brake.caliper.cylinder_area", "m2", "brake cylinder piston area"),
    ("supply_volume", "plant.car[{i}].supply_volume", "m3", "supply reservoir volume"),
    ("cylinder_volume", "plant.car[{i}].cylinder_volume", "m3", "brake cylinder volume (per axle)"),
    ("hold_area", "plant.car[{i}].hold_area", "m2", "WSP hold valve flow area"),
    ("vent_area", "plant.car[{i}].vent_area", "m2", "WSP vent valve flow area"),
    ("valve_delay", "plant.car[{i}].valve_delay", "s", "WSP valve response delay"),
    ("ep_tau", "plant.car[{i}].ep_tau", "s", "EP valve response time constant"),
]


def car(c: int) -> str:
    return f"_c{c + 1}"


def axle(a: int) -> str:
    return f"_c{a // _core.AXLES_PER_CAR + 1}a{a % _core.AXLES_PER_CAR + 1}"


def resolve(roots: dict, path: str):
    """The value at C path `path` (e.g. plant.car[0].vehicle.mass) in the ctypes structs `roots`."""
    tokens = re.findall(r"\w+|\[\d+\]", path)
    value = roots[tokens[0]]
    for token in tokens[1:]:
        value = value[int(token[1:-1])] if token.startswith("[") else getattr(value, token)
    return value


def bound_name(path: str) -> str:
    """The C bounds-table name of a parameter's C path: plant.car[0].vehicle.mass -> car.mass,
    plant.condition[0].polach.mu0 -> condition.mu0."""
    name = re.sub(r"^plant\.", "", path)
    name = re.sub(r"^condition\[[^]]*\]\.polach\.", "condition.", name)
    return re.sub(r"^car\[[^]]*\]\.(vehicle\.(brake\.caliper\.)?)?", "car.", name)


def parameter_range(path: str) -> tuple[float, float]:
    """(min, max) of a parameter: the C core's plausibility bound (core/src/bounds.c), the same table
    rb_plant_bounds_check and rb_wsp_check use at exitInitializationMode, so that what the
    modelDescription declares is what the FMU accepts."""
    name = bound_name(path)
    if name not in _core.BOUNDS:
        raise KeyError(f"FMU parameter {path}: no entry {name!r} in the bounds table (core/src/bounds.c)")
    return _core.bound(name)


# governor_off >= governor_on (rb_plant_check), which independent min/max cannot state: the declared
# ranges meet halfway between the two start values, so every pair inside them initialises
ORDERED = ("governor_on", "governor_off")


def split_ordered(variables: list[Variable]) -> None:
    """Narrows the ranges of the ORDERED pair (in place) to the two sides of their start values'
    midpoint: what the FMU declares is then exactly what exitInitializationMode accepts."""
    at = {v.name: i for i, v in enumerate(variables)}
    low, high = (variables[at[name]] for name in ORDERED)
    pivot = 0.5 * (low.start + high.start)
    variables[at[low.name]] = replace(low, max=min(low.max, pivot))
    variables[at[high.name]] = replace(high, min=max(high.min, pivot))


def table(roots: dict, n_cars: int, atmosphere: float) -> list[Variable]:
    """Every variable of the FMU; roots: the ctypes structs plant, bcu, wsp (start values)."""
    plant = roots["plant"]
    n_axles = n_cars * _core.AXLES_PER_CAR
    v = [Variable("time", "independent", "Real", "out.time", "s", description="simulation time")]

    def parameter(name, path, unit, description):
        low, high = parameter_range(path)
        v.append(Variable(name, "parameter", "Real", path, unit, float(resolve(roots, path)), low, high, description,
                          tunable=name in TUNABLE))

    for name, path, unit, description in _PARAMETERS:
        parameter(name, path, unit, description)
    split_ordered(v)
    for c in range(n_cars):
        for name, path, unit, description in _CAR_PARAMETERS:
            parameter(name + car(c), path.format(i=c), unit, f"car {c + 1}: {description}")
    v += [
        Variable("wsp_enabled", "parameter", "Boolean", "bcu.wsp_enabled", start=bool(roots["bcu"].wsp_enabled),
                 description="the internal BCU runs wheel-slide protection"),
        Variable("scenario_demand", "parameter", "Boolean", "scenario_demand", start=True,
                 description="brake demand from the scenario's schedule (true) or the demand inputs (false)"),
        Variable("external_bcu", "parameter", "Boolean", "external_bcu", start=False,
                 description="pressure demand and WSP valves from the inputs; the internal BCU is not run"),
    ]
    # inputs
    v += [Variable("service_demand", "input", "Real", "service_demand", "1", 0.0, 0.0, 1.0,
                   "service brake demand, 0..1 of full service (when scenario_demand is false)"),
          Variable("emergency_demand", "input", "Boolean", "emergency_demand", start=False,
                   description="emergency brake demand (when scenario_demand is false)")]
    for c in range(n_cars):
        v.append(Variable("pressure_demand" + car(c), "input", "Real", f"external.pressure_demand[{c}]", "Pa",
                          atmosphere, 0.0, 2e6, f"car {c + 1}: EP valve pressure demand, absolute (external BCU)"))
    for kind, meaning in (("hold", "hold valve closed"), ("vent", "vent valve open")):
        for a in range(n_axles):
            v.append(Variable(kind + axle(a), "input", "Boolean", f"external.{kind}[{a}]", start=False,
                              description=f"WSP command: {meaning} (external BCU)"))
    for i in range(plant.n_faults):
        f = plant.fault[i]
        where = "every axle" if f.axle < 0 else f"axle {f.axle + 1}"
        v.append(Variable(f"fault_{i + 1}", "input", "Boolean", f"fault_switch[{i}]", start=False,
                          description=f"starts scenario fault {i + 1} ({_core.FAULT_KINDS[f.kind]}, car {f.car + 1}, "
                                      f"{where}) now unless its scenario start {f.start_time:g} s came first"))
    # outputs
    v += [Variable("speed", "output", "Real", "out.speed", "m/s", description="train speed (leading car)"),
          Variable("position", "output", "Real", "out.position", "m", description="leading car front along the track"),
          Variable("deceleration", "output", "Real", "out.deceleration", "m/s2",
                   description="leading car deceleration"),
          Variable("main_reservoir", "output", "Real", "out.main_reservoir", "Pa",
                   description="main reservoir pressure (absolute)")]
    for c in range(n_cars):
        v.append(Variable("supply" + car(c), "output", "Real", f"out.supply[{c}]", "Pa",
                          description=f"car {c + 1}: supply reservoir pressure (absolute)"))
    for c in range(n_cars):
        v.append(Variable("ed_force" + car(c), "output", "Real", f"out.ed_force[{c}]", "N",
                          description=f"car {c + 1}: electrodynamic brake force achieved"))
    for name, field, unit, description in (
            ("wheel_speed", "wheel_speed", "m/s", "wheel peripheral speed (true)"),
            ("wheel_speed_measured", "wheel_speed_measured", "m/s", "wheel speed sensor (< 0: sensor lost)"),
            ("cylinder", "cylinder", "Pa", "brake cylinder pressure (absolute)"),
            ("disc_surface_temperature", "disc_surface_temperature", "K",
             "friction surface temperature of the axle's brake discs"),
            ("pad_friction", "pad_friction", "1", "the pads' friction coefficient, faded by the discs' heat")):
        for a in range(n_axles):
            v.append(Variable(name + axle(a), "output", "Real", f"out.{field}[{a}]", unit, description=description))
    return v
