"""Whole-train brake simulation with wheel-slide protection (model in the loop).

Python sets the parameters up (ctypes structs) and calls the C core, which runs the BCU and the
plant at a fixed 1 ms step into a preallocated array (core/src/plant*.c, bcu*.c, run.c). The run
goes in chunks of simulated time so a caller can show progress. Model: docs/simulation.md.
"""

from __future__ import annotations

import ctypes
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from railbrake import _core
from railbrake.adhesion import load_condition, warn_outside_range
from railbrake.contact import wheel_rail_contact
from railbrake.errors import InputError
from railbrake.resolve import resolve
from railbrake.scenario import Scenario, load
from railbrake.vehicle import load_train
from railbrake.units import ms_to_kmh

DT = 1e-3
# Air and wheelsets advance in 4 sub-steps of 0.25 ms inside each 1 ms step: under WSP cycling the
# 1 ms step alone shifts the mean cylinder pressure by 0.15-0.2 bar against the detailed model
# (docs/detailed.md, step-size study); the sub-steps bring that to the comparison's noise floor.
SUBSTEPS = 4
ATMOSPHERE = 1.01325e5
EMERGENCY_DECEL = 1.2               # m/s^2, below the CRH380AL's 1.35 [P]
SERVICE_DECEL = 1.0                 # m/s^2 [T]
CHUNK = 2.0                         # s of simulated time per C call


@dataclass
class Result:
    scenario: str
    cars: int
    wsp: bool
    time: np.ndarray
    outputs: dict          # channel name -> array (SI)
    units: dict            # channel name -> SI unit
    kpis: dict

    def axle_channels(self, quantity: str) -> list[str]:
        return [n for n in self.outputs if n.startswith(quantity + "_c") and "a" in n.split("_c")[-1]]

    def car_channels(self, quantity: str) -> list[str]:
        return [n for n in self.outputs if n.startswith(quantity + "_c") and "a" not in n.split("_c")[-1]]


# ------------------------------------------------------------------ parameters

CAR_LENGTH = 25.0   # m over couplers [T]


def _car(train, index: int) -> _core.PlantCar:
    """Car `index` of the train (the formation repeats when more cars are asked for) with the
    plant's own data: geometry, contact and pneumatics (typical values [T], docs/simulation.md)."""
    vehicle = train.cars[index % len(train.cars)].c
    car = _core.PlantCar()
    ctypes.pointer(car.vehicle)[0] = vehicle
    car.length = CAR_LENGTH
    for k, x in enumerate((2.5, 5.0, CAR_LENGTH - 5.0, CAR_LENGTH - 2.5)):
        car.axle_position[k] = x
    w = vehicle.wheelset
    car.contact = wheel_rail_contact(wheel_radius=w.wheel_radius, axle_load=w.axle_load).creep_contact()
    car.ed_tau = 0.3   # s [T]
    car.supply_volume, car.pilot_volume, car.relay_volume = 0.1, 0.5e-3, 1.0e-3
    car.cylinder_volume, car.pipe_volume = 1.5e-3, math.pi / 4 * 0.025**2 * CAR_LENGTH
    car.charge_area, car.ep_area, car.ep_tau, car.ep_band = 7e-6, 3e-6, 0.1, 0.1e5
    car.relay_supply_area, car.relay_exhaust_area, car.relay_band = 20e-6, 20e-6, 0.1e5
    car.hold_area, car.vent_area, car.valve_delay, car.pipe_area = 15e-6, 40e-6, 0.015, 100e-6
    return car


def _resistance(train, n_cars: int) -> _core.Resistance:
    """The train's resistance for n_cars: A and B scale with the mass, C (air) with
    0.2 + 0.8 n/N (head and tail unchanged) [T]."""
    r, n = train.c.resistance, len(train.cars)
    if n_cars == n:
        return _core.Resistance(r.A, r.B, r.C)
    mass_ratio = sum(train.cars[i % n].c.mass for i in range(n_cars)) / train.mass
    return _core.Resistance(r.A * mass_ratio, r.B * mass_ratio, r.C * (0.2 + 0.8 * n_cars / n))


def _condition(name: str, initial_speed: float) -> _core.PlantCondition:
    cond = load_condition(name)
    # A stop passes every speed below the initial one; only starting above the range is flagged.
    if cond.validity is not None and ms_to_kmh(initial_speed) > cond.validity.speed_max_kmh:
        warn_outside_range(cond, ms_to_kmh(initial_speed), "run from")
    c = _core.PlantCondition()
    c.polach = cond.params.to_c()
    c.leading_factor = cond.conditioning.leading_factor if cond.conditioning else 1.0
    c.recovery_axles = cond.conditioning.recovery_axles if cond.conditioning else 0.0
    return c


_FAULT_INDEX = {name: i for i, name in enumerate(_core.FAULT_KINDS)}


def plant_params(scenario: Scenario, n_cars: int, dt: float = DT, substeps: int = SUBSTEPS,
                 train=None) -> _core.PlantParams:
    """The plant's C parameters; train: the resolved train (default: the scenario's preset)."""
    spec = scenario.spec
    train = load_train(spec.train.preset) if train is None else train
    p = _core.PlantParams()
    p.n_cars, p.dt, p.substeps, p.temperature, p.atmosphere = n_cars, dt, substeps, 293.15, ATMOSPHERE
    p.discharge_coefficient, p.critical_ratio = 0.8, 0.528
    for i in range(n_cars):
        p.car[i] = _car(train, i)
    p.coupler = _core.Coupler(0.01, 1e7, 0.0, 2e5)   # slack m, N/m, N/m^3, N s/m [T]
    p.resistance = _resistance(train, n_cars)
    p.compressor_car = 0
    p.main_reservoir_volume, p.main_reservoir_area = 0.05 * n_cars, 100e-6
    p.compressor_flow, p.governor_on, p.governor_off = 0.03, 8.5e5, 10.0e5
    p.initial_pressure, p.initial_speed = 9.5e5, spec.initial_speed
    names = [spec.adhesion.condition] + [z.condition for z in spec.adhesion.zones]
    unique = list(dict.fromkeys(names))
    if len(unique) > _core.MAX_CONDITIONS:
        raise InputError(f"{scenario.where('adhesion', 'zones')}: at most {_core.MAX_CONDITIONS} conditions")
    p.n_conditions = len(unique)
    for i, name in enumerate(unique):
        p.condition[i] = _condition(name, spec.initial_speed)
    p.n_zones = len(spec.adhesion.zones)
    for i, z in enumerate(spec.adhesion.zones):
        p.zone[i] = _core.TrackZone(z.start, z.end, unique.index(z.condition))
    p.creep_speed_min = 1.0
    scenario.check_cars(n_cars)
    p.n_faults = len(spec.faults)
    for i, f in enumerate(spec.faults):
        value = f.noise if f.type == "sensor_noisy" else f.leak_area if f.type == "cylinder_leak" else None
        if value is None and f.type in ("sensor_noisy", "cylinder_leak"):
            key = "noise" if f.type == "sensor_noisy" else "leak_area"
            raise InputError(f"{scenario.where('faults', i, 'type')}: a {f.type} fault needs {key}")
        p.fault[i] = _core.Fault(_FAULT_INDEX[f.type], f.car - 1, -1 if f.axle is None else f.axle - 1,
                                 f.start, value or 0.0)
    p.noise_seed = spec.seed
    _core.call(_core.rb_plant_check, ctypes.byref(p))
    return p


def wsp_params(scenario: Scenario | None = None) -> _core.WspParams:
    w = _core.WspParams()
    _core.rb_wsp_default_params(ctypes.byref(w))
    if scenario is not None:
        for key in ("speed_threshold", "slip_threshold", "decel_threshold", "reaccel_threshold",
                    "ref_decel_max", "safety_time"):
            value = getattr(scenario.spec.wsp, key)
            if value is not None:
                setattr(w, key, value)
    return w


def bcu_params(plant: _core.PlantParams, scenario: Scenario, wsp: bool) -> _core.BcuParams:
    b = _core.BcuParams()
    b.n_cars, b.cycle, b.atmosphere = plant.n_cars, scenario.spec.wsp.cycle, ATMOSPHERE
    b.service_decel, b.emergency_decel, b.ed_in_emergency = SERVICE_DECEL, EMERGENCY_DECEL, 0
    supply = min(plant.car[i].vehicle.supply_pressure for i in range(plant.n_cars))
    _core.rb_bcu_pressure_map(ctypes.byref(plant), supply, ctypes.byref(b))
    b.wsp_enabled = int(wsp and scenario.spec.wsp.enabled)
    b.wsp_per_bogie = int(scenario.spec.wsp.per_bogie)
    return b


def _scenario_struct(scenario: Scenario) -> _core.Scenario:
    spec = scenario.spec
    s = _core.Scenario()
    s.n_demand = len(spec.demand)
    for i, d in enumerate(spec.demand):
        s.demand_time[i], s.demand_service[i], s.demand_emergency[i] = d.time, d.service, float(d.emergency)
    s.max_time, s.stop_speed = spec.stop.max_time, spec.stop.speed
    s.record_interval, s.adhesion_interval = spec.outputs.record_interval, 0.1
    return s


def channels(n_cars: int) -> list[tuple[str, str]]:
    return _core.channel_list(_core.rb_run_channel_count, _core.rb_run_channel_info, n_cars)


# ------------------------------------------------------------------ running

WspCallback = Callable[[_core.WspInputs, _core.WspCommands], None]


def run(scenario="emergency-300-heavy-rain", cars: int | None = None, wsp: bool = True,
        wsp_function: WspCallback | None = None, progress: Callable[[float, float], None] | None = None,
        record: bool = True, dt: float = DT, substeps: int = SUBSTEPS) -> Result:
    """Run a scenario (preset name, file, Scenario or railbrake.resolve.Resolved) in the C core.

    cars: override the train's number of cars; wsp=False: no WSP (valves never commanded);
    wsp_function(inputs, commands): a Python WSP replacing the default (prototyping; slower);
    progress(t, v): called after each chunk of simulated time with the time and speed (SI);
    dt: the plant's fixed step (s); substeps: sub-steps of air and wheelsets per step.
    """
    resolved = resolve(scenario, cars)
    sc, n_cars = resolved.scenario, resolved.cars
    plant = plant_params(sc, n_cars, dt, substeps, resolved.train)
    bcu = bcu_params(plant, sc, wsp)
    callback = None
    if wsp_function is not None:
        def _adapter(_context, inputs, commands):
            wsp_function(inputs.contents, commands.contents)
        callback = _core.WSP_FUNCTION(_adapter)
        bcu.wsp = callback
    wspp = wsp_params(sc)
    spec = _scenario_struct(sc)
    state = ctypes.create_string_buffer(_core.rb_run_state_size())
    _core.call(_core.rb_run_init, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(wspp),
               ctypes.byref(spec), state)
    names = channels(n_cars)
    rows = int(math.ceil(sc.spec.stop.max_time / sc.spec.outputs.record_interval)) + 3 if record else 0
    series = np.zeros((rows, len(names)))
    finished = ctypes.c_int(0)
    t = 0.0
    while not finished.value:
        t += CHUNK
        _core.call(_core.rb_run_advance, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(spec), state,
                   t, _core.ptr(series) if record else None, rows, ctypes.byref(finished))
        if progress is not None:
            row = min(int(t / sc.spec.outputs.record_interval), rows - 1)
            progress(min(t, sc.spec.stop.max_time), float(series[row, 1]) if record else math.nan)
    kpis = _core.Kpis()
    _core.rb_run_kpis(ctypes.byref(plant), state, ctypes.byref(kpis))
    n_rows = int(np.count_nonzero(series[:, 0])) + 1 if record else 0
    series = series[:n_rows]
    outputs = {name: series[:, i].copy() for i, (name, _) in enumerate(names)}
    result = {k: getattr(kpis, k) for k in _core.KPI_NAMES}
    for k in ("wheel_lock_events", "safety_timer_trips"):
        result[k] = int(result[k])
    result["stopped"] = bool(result["stopped"])
    return Result(sc.name, n_cars, bool(bcu.wsp_enabled), outputs.get("time", np.zeros(0)), outputs,
                  dict(names), result)


def bench(cars: int = 16, steps: int = 20000) -> dict:
    """The plant alone at 1 ms with the brakes applied on dry rail: timing measured in C."""
    sc = load("emergency-250-dry")
    plant = plant_params(sc, cars)
    mean, p99 = ctypes.c_double(), ctypes.c_double()
    supply = plant.car[0].vehicle.supply_pressure
    _core.call(_core.rb_plant_bench, ctypes.byref(plant), supply, steps, ctypes.byref(mean),
               ctypes.byref(p99))
    return {"cars": cars, "realtime_factor": DT * 1e6 / mean.value,
            "step_us_mean": mean.value, "step_us_p99": p99.value}

