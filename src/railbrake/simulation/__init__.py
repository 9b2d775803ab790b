"""Whole-train brake simulation with wheel-slide protection (model in the loop).

Python sets the parameters up (ctypes structs) and calls the C core, which runs the BCU and the
plant at a fixed 1 ms step into a preallocated array (core/src/plant*.c, bcu*.c, run.c). The run
goes in chunks of simulated time so a caller can show progress. Model: docs/simulation.md.
"""

from __future__ import annotations

import ctypes
import math
import os
import time
import warnings
from dataclasses import dataclass, field
from functools import cache
from importlib import resources
from typing import Callable

import numpy as np
import yaml

from railbrake import _core, sizing
from railbrake.adhesion import load_condition, warn_outside_range
from railbrake.contact import wheel_rail_contact
from railbrake._args import choice, flag, function, instance, name_or_path, real, whole
from railbrake.errors import InputError
from railbrake.resolve import resolve
from railbrake.results import scripting
from railbrake.scenario import Scenario, load
from railbrake.simulation import changes as run_changes
from railbrake.simulation import response
from railbrake.simulation.changes import Change  # noqa: F401 (the run API's)
from railbrake.units import KMH, ms_to_kmh
from railbrake.vehicle import LOAD_CASES, Train, load_train, with_cars

DT = 1e-3
# One plant step per dt up to this; a longer dt is split into equal sub-steps no longer than it. With
# its timing rules (rb_plant.h) one 1 ms step is as accurate as 4 x 0.25 ms were (docs/detailed.md,
# step-size study); above 2 ms the WSP cycles need the sub-steps.
MAX_SUBSTEP = 2e-3
# The wheelset kernel (rb_plant.h): "auto" (the vector one where the CPU has it) or "portable".
KERNEL_ENV = "RAILBRAKE_KERNEL"
ZERO_CELSIUS = 273.15               # K
CHUNK = 2.0                         # s of simulated time per C call with a progress callback
QUIET_CHUNK = 60.0                  # without: fewer calls (each costs some us), Ctrl-C still heard soon


@dataclass
class Result:
    """A run's time series (SI), their units and KPIs (`run --json`'s units). For scripts:
    to_dataframe(), to_arrow(), plot(kind), save(folder) and railbrake.load_result(folder)."""

    scenario: str
    cars: int
    wsp: bool
    time: np.ndarray
    outputs: dict          # channel name -> array (SI)
    units: dict            # channel name -> SI unit
    kpis: dict
    atmosphere: float = math.nan   # Pa, the plant's (the train file's)
    meta: dict = field(default_factory=dict)   # what was run, as in run.json (a loaded result)
    resolved: object = field(default=None, repr=False, compare=False)   # the resolve.Resolved run

    def to_dataframe(self):
        """pandas DataFrame, a column per channel; units in .attrs["units"], KPIs in .attrs["kpis"]."""
        return scripting.to_dataframe(self)

    def to_arrow(self):
        """pyarrow Table, a column per channel, each field's unit in its metadata."""
        return scripting.to_arrow(self)

    def plot(self, kind: str = "braking_curve", path=None, **options):
        """A standard figure (railbrake.results.scripting.PLOT_KINDS): the Figure, or written to path."""
        return scripting.plot(self, kind, path, **options)

    def save(self, folder, overwrite: bool = False):
        """The run folder: timeseries.parquet, kpis.json, run.json (+ config.yaml); load_result reads it.
        An existing folder with files in it is refused unless overwrite=True."""
        return scripting.save(self, folder, overwrite)

    def axle_channels(self, quantity: str) -> list[str]:
        return [n for n in self.outputs if n.startswith(quantity + "_c") and "a" in n.split("_c")[-1]]

    def car_channels(self, quantity: str) -> list[str]:
        return [n for n in self.outputs if n.startswith(quantity + "_c") and "a" not in n.split("_c")[-1]]


# ------------------------------------------------------------------ parameters
# Every physical value comes from the train file (railbrake.vehicle, schema railbrake.train/2) or
# the scenario; the numbers here are unit conversions.

L, MM2, BAR = 1e-3, 1e-6, 1e5


def _car(train, index: int) -> _core.PlantCar:
    """Car `index` of the train (already lengthened to the plant's cars, vehicle.with_cars) with
    the plant's data from its car type: geometry, contact and pneumatics."""
    entry = train.cars[index]
    vehicle, t = entry.c, entry.equipment
    car = _core.PlantCar()
    ctypes.pointer(car.vehicle)[0] = vehicle
    car.length = t.length_m
    for k, x in enumerate(t.axle_positions_m):
        car.axle_position[k] = x
    w = vehicle.wheelset
    car.contact = wheel_rail_contact(wheel_radius=w.wheel_radius, axle_load=w.axle_load).creep_contact()
    ed = train.spec.ed_brake
    car.ed_tau = ed.response_s if ed is not None else 1.0   # no ED brake: the lag is never used
    cyl, discs = t.cylinder, t.discs
    pipe = train.spec.air_supply.pipe
    car.supply_volume = t.supply_reservoir.volume_l * L
    car.pilot_volume, car.relay_volume = t.ep_valve.pilot_volume_l * L, t.relay_valve.output_volume_l * L
    # one cylinder per disc: swept volume at full stroke plus the dead volume
    car.cylinder_volume = discs.per_axle * (cyl.area_m2 * cyl.stroke_mm * 1e-3 + cyl.dead_volume_l * L)
    car.pipe_volume = math.pi / 4 * (pipe.diameter_mm * 1e-3) ** 2 * t.length_m
    car.charge_area = t.supply_reservoir.charge_area_mm2 * MM2
    car.ep_area, car.ep_tau, car.ep_band = t.ep_valve.port_area_mm2 * MM2, t.ep_valve.response_s, t.ep_valve.band_bar * BAR
    car.ep_supply_margin, car.ep_bleed_area = t.ep_valve.supply_margin_bar * BAR, t.ep_valve.bleed_area_mm2 * MM2
    r = t.relay_valve
    car.relay_supply_area, car.relay_exhaust_area, car.relay_band = (r.supply_area_mm2 * MM2, r.exhaust_area_mm2 * MM2,
                                                                     r.band_bar * BAR)
    car.relay_tau, car.relay_sweep, car.relay_travel = r.response_s, r.sweep_cm3 * 1e-6, r.travel
    v = t.wsp_valves
    car.hold_area, car.vent_area, car.valve_delay = v.hold_area_mm2 * MM2, v.vent_area_mm2 * MM2, v.response_s
    car.pipe_area = min(pipe.coupling_area_mm2 * MM2, math.pi / 4 * (pipe.diameter_mm * 1e-3) ** 2)
    car.disc_heat_capacity = discs.per_axle * discs.mass_kg * discs.specific_heat_J_per_kgK
    cooling = discs.cooling_W_per_K
    car.disc_cooling = _core.speed_table(np.asarray(cooling.speed_kmh) * KMH,
                                         discs.per_axle * np.asarray(cooling.value))
    _emergency_circuit(train, index, car)
    return car


def _emergency_circuit(train, index: int, car: _core.PlantCar) -> None:
    """Car `index`'s emergency circuit (rb_plant_car.emergency_*) from the train file: the delay
    from the loop's opening at the leading car (propagation to the car's front, relay drop-out,
    valve response), the choke and the load-weighing valve's limit at the car's mass."""
    entry = train.cars[index]
    valve, loop = entry.equipment.emergency_valve, train.spec.emergency_loop
    if valve is None:
        car.emergency_area = 0.0   # the EP valve brakes in emergency too
        return
    front = sum(c.equipment.length_m for c in train.cars[:index])
    travel = front / loop.propagation_m_per_s if loop.propagation_m_per_s else 0.0
    car.emergency_delay = travel + loop.drop_out_s + valve.response_s
    car.emergency_area = math.pi / 4 * (valve.choke_diameter_mm * 1e-3) ** 2
    tare = entry.tare
    crush = tare + entry.equipment.payload_t.crush * 1e3
    share = min(max((entry.mass - tare) / (crush - tare), 0.0), 1.0) if crush > tare else 1.0
    limit = valve.limit_bar.tare + share * (valve.limit_bar.crush - valve.limit_bar.tare)
    car.emergency_limit = train.atmospheric_pressure + limit * BAR


def _gradients(scenario: Scenario, p: _core.PlantParams) -> None:
    track = scenario.spec.track
    p.n_gradients = len(track.gradients)
    for i, g in enumerate(track.gradients):
        p.gradient_start[i], p.gradient[i] = g.start, g.gradient


def _condition(name: str, initial_speed: float, cells: bool) -> _core.PlantCondition:
    cond = load_condition(name)
    # A stop passes every speed below the initial one; only starting above the range is flagged.
    if cond.validity is not None and ms_to_kmh(initial_speed) > cond.validity.speed_max_kmh:
        warn_outside_range(cond, ms_to_kmh(initial_speed), "run from")
    c = _core.PlantCondition()
    c.polach = cond.params.to_c()
    k = cond.conditioning
    c.leading_factor = k.leading_factor if k else 1.0
    if k and cells and k.reference_energy > 0.0:   # the rail cleaned cell by cell (rail_conditioning.c)
        c.reference_energy = k.reference_energy
    else:
        c.recovery_axles = k.recovery_axles if k else 0.0
    return c


def _sanders(train, n_cars: int, p: _core.PlantParams) -> None:
    """The train file's sanders; they condition the rail cells, so without them they act on nothing
    (said, not dropped silently)."""
    sanders = train.spec.sanders
    if sanders is None:
        return
    if p.rail_cell_length <= 0.0:
        warnings.warn(f"train {train.name}: its sanders act on the rail cells, which this run does not use "
                      "(adhesion.rail_conditioning: cells with a condition that has conditioning.cells)", stacklevel=3)
        return
    for i, s in enumerate(sanders.units):
        if s.car > n_cars:
            raise InputError(f"train {train.name}: sanders.units[{i}].car = {s.car}: the run has cars 1..{n_cars}")
        p.sander_axle[i] = (s.car - 1) * _core.AXLES_PER_CAR + s.axle - 1
        p.sander_trigger[i] = ("driver", "wsp").index(s.trigger)
        rate = s.rate_kg_min
        p.sander_rate[i] = _core.speed_table(np.asarray(rate.speed_kmh) * KMH, np.asarray(rate.value) / 60.0) \
            if hasattr(rate, "speed_kmh") else _core.speed_table([0.0], [rate / 60.0])   # variable or fixed
        p.sander_start[i] = s.start_s
    p.n_sanders = len(sanders.units)
    p.sand_reference = sanders.sand_reference_kg_m


def _rail_cells(names: list, p: _core.PlantParams) -> None:
    """The finest cell length of the conditions conditioned cell by cell (their files')."""
    lengths = [k.cell_length for k in (load_condition(n).conditioning for n in names) if k and k.reference_energy > 0.0]
    p.rail_cell_length = min(lengths) if lengths else 0.0


_FAULT_INDEX = {name: i for i, name in enumerate(_core.FAULT_KINDS)}


def substeps_for(dt: float) -> int:
    """Sub-steps of the plant at step dt (s): 1 up to MAX_SUBSTEP, then as many as keep each within it."""
    dt = real("dt", dt, 0.0, 1.0, low_open=True)   # its range: rb_plant_check
    return max(1, math.ceil(dt / MAX_SUBSTEP - 1e-9))


def kernel_code(kernel: str | None = None) -> int:
    """rb_plant_params.kernel for a kernel name; None: the RAILBRAKE_KERNEL environment variable,
    else "auto"."""
    where = "--kernel"
    if kernel is None:
        kernel, where = os.environ.get(KERNEL_ENV, "auto"), f"environment variable {KERNEL_ENV}"
    if not isinstance(kernel, str) or kernel not in _core.KERNELS:
        raise InputError(f"{where} = {kernel!r}: must be one of {', '.join(_core.KERNELS)}")
    return _core.KERNELS[kernel]


def scenario_train(scenario: Scenario, n_cars: int | None = None):
    """The scenario's train with its load case, lengthened to n_cars (default: the scenario's)."""
    spec = scenario.spec
    train = load_train(spec.train.preset, spec.train.load_case or True)
    return with_cars(train, scenario.cars(n_cars) if n_cars is None else n_cars)


@cache
def wall_time() -> float:
    """The brake cylinders' wall heat-exchange time (s): the detailed model's, for every volume of it
    (data/detailed/valves.yaml, air.thermal_time_s, with its source), so that both models'
    cylinders exchange heat alike (rb_plant_params.wall_time)."""
    settings = yaml.safe_load((resources.files("railbrake") / "data" / "detailed" / "valves.yaml").read_text())
    return float(settings["air"]["thermal_time_s"])


def plant_params(scenario: Scenario, n_cars: int, dt: float = DT, substeps: int | None = None,
                 kernel: str | None = None, train=None) -> _core.PlantParams:
    """The plant's parameters; substeps None: substeps_for(dt); kernel: see kernel_code; train: the
    resolved train (default: the scenario's preset)."""
    instance("scenario", scenario, Scenario)
    n_cars = whole("n_cars", n_cars, 1, _core.PLANT_MAX_CARS)
    substeps = None if substeps is None else whole("substeps", substeps, 1)   # its range: rb_plant_check
    dt = real("dt", dt, 0.0, 1.0, low_open=True)
    spec = scenario.spec
    train = scenario_train(scenario, n_cars) if train is None else with_cars(train, n_cars)
    scenario.check_speed(train)
    eq = train.spec
    p = _core.PlantParams()
    p.n_cars, p.dt = n_cars, dt
    p.substeps = substeps_for(dt) if substeps is None else substeps
    p.kernel = kernel_code(kernel)
    p.temperature = eq.pneumatics.air_temperature_c + ZERO_CELSIUS
    p.ambient_temperature = p.temperature
    p.atmosphere = train.atmospheric_pressure
    p.discharge_coefficient, p.critical_ratio = eq.pneumatics.discharge_coefficient, eq.pneumatics.critical_ratio
    p.wall_time = wall_time()
    for i in range(n_cars):
        p.car[i] = _car(train, i)
    k = eq.coupler
    p.coupler = _core.Coupler(k.slack_mm * 1e-3, k.stiffness_kN_per_mm * 1e6, 0.0, k.damping_kN_s_per_m * 1e3)
    p.resistance = _core.Resistance(train.c.resistance.A, train.c.resistance.B, train.c.resistance.C)
    _air_supply(train, n_cars, p)
    p.initial_speed = spec.initial_speed
    _gradients(scenario, p)
    names = [spec.adhesion.condition] + [z.condition for z in spec.adhesion.zones]
    unique = list(dict.fromkeys(names))
    if len(unique) > _core.MAX_CONDITIONS:
        raise InputError(f"{scenario.where('adhesion', 'zones')}: at most {_core.MAX_CONDITIONS} conditions")
    p.n_conditions = len(unique)
    cells = spec.adhesion.rail_conditioning == "cells"
    for i, name in enumerate(unique):
        p.condition[i] = _condition(name, spec.initial_speed, cells)
    if cells:
        _rail_cells(unique, p)
    _sanders(train, n_cars, p)
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
        p.fault[i] = _core.Fault(_FAULT_INDEX[f.type], 0 if f.car is None else f.car - 1, -1 if f.axle is None else f.axle - 1,
                                 f.start, value or 0.0)
    p.noise_seed = spec.seed
    _core.call(_core.rb_plant_check, ctypes.byref(p))
    return p


def _air_supply(train, n_cars: int, p: _core.PlantParams) -> None:
    """Compressors of the train's formation (repeated with it), lumped main reservoirs on the
    first compressor's car, governor pressures gauge -> absolute."""
    air = train.spec.air_supply
    n_formation = len(train.spec.formation)
    units = [(start + c.car - 1, c.delivery_kg_s) for start in range(0, n_cars, n_formation)
             for c in air.compressors if start + c.car - 1 < n_cars]
    if not units:   # a train cut shorter than its first compressor's car still needs air
        units = [(n_cars - 1, air.compressors[0].delivery_kg_s)]
    if len(units) > _core.MAX_COMPRESSORS:
        raise InputError(f"train {train.name}, {n_cars} cars: {len(units)} compressors (the formation's "
                         f"repeated); the plant takes at most {_core.MAX_COMPRESSORS}")
    positions, deliveries = [c for c, _ in units], [q for _, q in units]
    p.n_compressors = len(positions)
    for i, (c, q) in enumerate(zip(positions, deliveries)):
        p.compressor_position[i], p.compressor_delivery[i] = c, q
    p.compressor_car = positions[0]
    p.compressor_flow = sum(deliveries)
    p.main_reservoir_volume = air.main_reservoir_l * L * n_cars / n_formation
    p.main_reservoir_area = air.main_reservoir_outlet_mm2 * MM2
    p.governor_on = p.atmosphere + air.governor_on_bar * BAR
    p.governor_off = p.atmosphere + air.governor_off_bar * BAR
    p.initial_pressure = p.atmosphere + air.charged_bar * BAR


WSP_CONTROLLERS = ("threshold", "slip_setpoint", "decel_slip_speed")   # rb_wsp_controller's order (rb_bcu.h)
# the scenario's wsp keys that are rb_wsp_params fields of the same name (SI)
_WSP_OVERRIDES = ("speed_threshold", "slip_threshold", "decel_threshold", "reaccel_threshold", "ref_decel_max",
                  "safety_time", "setpoint_speed", "setpoint_slip", "setpoint_band", "lead_time", "ref_decel_margin",
                  "setpoint_release", "ds_speed_threshold", "ds_slip_threshold", "ds_decel_threshold",
                  "ds_reaccel_threshold", "conditioning_ratio")


def wsp_params(scenario: Scenario | None = None) -> _core.WspParams:
    w = _core.WspParams()
    _core.rb_wsp_default_params(ctypes.byref(w))
    if scenario is not None:
        instance("scenario", scenario, Scenario)
        settings = scenario.spec.wsp
        for key in _WSP_OVERRIDES:
            value = getattr(settings, key)
            if value is not None:
                setattr(w, key, int(value) if isinstance(value, bool) else value)
        w.controller = WSP_CONTROLLERS.index(settings.controller)
        w.conditioning_mode = int(settings.conditioning_mode)
    return w


def _tables(demands: list, table_name: str, n_cars: int) -> list:
    return [_core.speed_table(d.speed, getattr(d, table_name)) for d in demands[:n_cars]]


def bcu_params(plant: _core.PlantParams, scenario: Scenario, wsp: bool, train=None) -> _core.BcuParams:
    """The BCU: per car the brake force of the train's emergency and service steps over speed and
    the pneumatic law solved for the pressure, from railbrake.sizing (load-weighed, pad lambda(v),
    ED blending as the train file's brake steps say). docs/simulation.md, 'From demand to cylinder'."""
    train = scenario_train(scenario, plant.n_cars) if train is None else with_cars(train, plant.n_cars)
    b = _core.BcuParams()
    b.n_cars, b.cycle, b.atmosphere = plant.n_cars, scenario.spec.wsp.cycle, plant.atmosphere
    emergency, ed_emergency = sizing.brake_step(train, "emergency")
    service, ed_service = sizing.brake_step(train, "service")
    b.ed_in_emergency, b.ed_in_service = int(ed_emergency), int(ed_service)
    # the constant decelerations only document the steps (the tables are used): their top values
    b.emergency_decel, b.service_decel = float(emergency.deceleration.max()), float(service.deceleration.max())
    _core.rb_bcu_pressure_map(ctypes.byref(plant), train.supply_pressure, ctypes.byref(b))
    b.demand_tables = 1
    e_demand, s_demand = sizing.car_demands(train, emergency), sizing.car_demands(train, service)
    for c in range(plant.n_cars):
        b.emergency_force[c] = _core.speed_table(e_demand[c].speed, e_demand[c].force)
        b.service_force[c] = _core.speed_table(s_demand[c].speed, s_demand[c].force)
        b.pressure_per_newton[c] = _core.speed_table(e_demand[c].speed, e_demand[c].pressure_per_newton)
        b.pressure_offset[c] = e_demand[c].threshold
    b.emergency_profile, b.service_profile = emergency.table(), service.table()
    b.service_jerk = train.brake_step("service").jerk_limit_m_s3 or 0.0   # 0: no limit
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
    """(name, SI unit) of each recorded channel of a run of n_cars cars."""
    return list(_channels(whole("n_cars", n_cars, 1, _core.PLANT_MAX_CARS)))


@cache
def _channels(n_cars: int) -> tuple:
    """The C layout's names, asked once per train length (a call per channel: 6 ms for 16 cars)."""
    return tuple(_core.channel_list(_core.rb_run_channel_count, _core.rb_run_channel_info, n_cars))


# ------------------------------------------------------------------ running

WspCallback = Callable[[_core.WspInputs, _core.WspCommands], None]


def structs(resolved, wsp: bool = True, dt: float = DT, substeps: int | None = None, kernel: str | None = None,
            train=None) -> tuple:
    """The C structs of a resolved configuration: (plant, BCU, WSP, scenario)."""
    sc, n_cars = resolved.scenario, resolved.cars
    train = with_cars(resolved.train if train is None else train, n_cars)
    plant = plant_params(sc, n_cars, dt, substeps, kernel, train)
    for text in sizing.supply_warnings(train, demanded_steps(sc), sc.spec.initial_speed):
        warnings.warn(f"scenario {sc.name}: {text}", sizing.SupplyWarning, stacklevel=3)
    return plant, bcu_params(plant, sc, wsp, train), wsp_params(sc), _scenario_struct(sc)


def run_batch(configurations: list, kernel: str | None = None) -> list:
    """The KPIs of many runs, made in one call of the C core without recording (a study's batch):
    configurations are resolved (railbrake.resolve.Resolved) or anything `run` takes; per run its
    KPI dict as `run` gives it, or the InputError that stopped it in the core."""
    return run_structs([structs(resolve(c), kernel=kernel) for c in configurations])


def run_structs(prepared: list) -> list:
    """run_batch on configurations already turned into C structs (`structs`)."""
    n = len(prepared)
    if n > _core.MAX_BATCH:
        raise InputError(f"configurations: {n} runs; a batch takes at most {_core.MAX_BATCH}")
    arrays = [(kind * n)() for kind in (_core.PlantParams, _core.BcuParams, _core.WspParams, _core.Scenario)]
    for i, four in enumerate(prepared):
        for array, struct in zip(arrays, four):
            array[i] = struct
    kpis, status, errors = (_core.Kpis * n)(), (ctypes.c_int * n)(), (_core.RbError * n)()
    state = ctypes.create_string_buffer(_core.rb_run_state_size())
    _core.call(_core.rb_run_batch, n, *arrays, state, kpis, status, errors)
    return [kpi_dict(kpis[i], arrays[0][i].atmosphere, arrays[3][i].n_speed_marks) if status[i] == 0
            else InputError(errors[i].message.decode("utf-8", "replace")) for i in range(n)]


def run(scenario="emergency-300-heavy-rain", cars: int | None = None, wsp: bool = True,
        wsp_function: WspCallback | None = None, progress: Callable[[float, float], None] | None = None,
        record: bool = True, dt: float = DT, substeps: int | None = None, kernel: str | None = None,
        train=None, changes=()) -> Result:
    """Run a scenario (preset name, file, Scenario or railbrake.resolve.Resolved) in the C core.

    cars: override the train's number of cars; wsp=False: no WSP (valves never commanded);
    wsp_function(inputs, commands): a Python WSP replacing the default (prototyping; slower);
    progress(t, v): called after each chunk of simulated time with the time and speed (SI);
    dt: the plant's fixed step (s); substeps: sub-steps of air and wheelsets per step (None:
    substeps_for(dt)); kernel: the wheelset kernel, "auto" or "portable" (None: RAILBRAKE_KERNEL);
    train: a vehicle.Train to use instead of the scenario's (e.g. with overrides), lengthened to
    the cars asked for; changes: simulation.Change's (WSP parameters, adhesion, faults changed at a
    time during the run, as the FMU's tunable parameters between doSteps).
    """
    wsp, record = flag("wsp", wsp), flag("record", record)
    function("wsp_function", wsp_function)
    function("progress", progress)
    if train is not None:
        instance("train", train, Train)
    resolved = resolve(scenario, cars)
    sc, n_cars = resolved.scenario, resolved.cars
    configured = resolved if train is None else None   # a train given here is not in the configuration
    plant, bcu, wspp, spec = structs(resolved, wsp, dt, substeps, kernel, train)
    callback = None
    if wsp_function is not None:
        def _adapter(_context, inputs, commands):
            wsp_function(inputs.contents, commands.contents)
        callback = _core.WSP_FUNCTION(_adapter)
        bcu.wsp = callback
    state = ctypes.create_string_buffer(_core.rb_run_state_size())
    _core.call(_core.rb_run_init, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(wspp),
               ctypes.byref(spec), state)
    names = channels(n_cars)
    speed_column = [name for name, _ in names].index("speed")
    rows = int(math.ceil(sc.spec.stop.max_time / sc.spec.outputs.record_interval)) + 3 if record else 0
    series = np.zeros((rows, len(names)))
    finished = ctypes.c_int(0)
    pending = run_changes.check(changes, sc.spec.stop.max_time, plant.n_faults, bool(bcu.wsp_per_bogie))
    t, chunk = 0.0, CHUNK if progress is not None else QUIET_CHUNK
    while not finished.value:
        t = min(t + chunk, pending[0].time) if pending else t + chunk
        _core.call(_core.rb_run_advance, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(spec), state,
                   t, _core.ptr(series) if record else None, rows, ctypes.byref(finished))
        while pending and pending[0].time <= t and not finished.value:
            run_changes.apply(pending.pop(0), plant, wspp, state)
        if progress is not None:   # the speed of the last row surely written (the one at t may not be)
            row = max(0, min(int(t / sc.spec.outputs.record_interval) - 1, rows - 1))
            progress(min(t, sc.spec.stop.max_time), float(series[row, speed_column]) if record else math.nan)
    kpis = _core.Kpis()
    _core.rb_run_kpis(ctypes.byref(plant), state, ctypes.byref(kpis))
    n_rows = int(np.count_nonzero(series[:, 0])) + 1 if record else 0
    series = series[:n_rows]
    outputs = {name: series[:, i].copy() for i, (name, _) in enumerate(names)}
    return Result(sc.name, n_cars, bool(bcu.wsp_enabled), outputs.get("time", np.zeros(0)), outputs,
                  dict(names), kpi_dict(kpis, plant.atmosphere), plant.atmosphere,
                  resolved=configured)


def demanded_steps(scenario: Scenario) -> dict:
    """The brake steps a scenario demands: {"emergency": 1.0, "service": largest fraction}."""
    steps = {}
    for step in scenario.spec.demand:
        if step.emergency:
            steps["emergency"] = 1.0
        elif step.service > 0.0:
            steps["service"] = max(steps.get("service", 0.0), step.service)
    return steps


def axle_name(index: int) -> str:
    """'c3a2' (car 3, axle 2, 1-based) for the 0-based global axle index, as in channel names."""
    index = whole("index", index, 0)
    return f"c{index // _core.AXLES_PER_CAR + 1}a{index % _core.AXLES_PER_CAR + 1}"


def kpi_dict(kpis: _core.Kpis, atmosphere: float, speed_marks: int = 0) -> dict:
    """The C KPIs in the units of `run --json`: pressures bar gauge, energy MJ, temperature degC;
    with speed_marks (rb_scenario.n_speed_marks) > 0 also "speed_marks": the time (s) and distance
    (m) from the brake demand to each mark, None for a mark never reached."""
    k = {name: getattr(kpis, name) for name in _core.KPI_NAMES + _core.KPI_TAIL_NAMES}
    stopped = bool(k["stopped"])
    gauge = lambda pa: (pa - atmosphere) / BAR  # noqa: E731
    marks = {} if not speed_marks else {"speed_marks": {
        "time_s": [t if t >= 0.0 else None for t in kpis.mark_time_s[:speed_marks]],
        "distance_m": [d if d >= 0.0 else None for d in kpis.mark_distance_m[:speed_marks]]}}
    return marks | {
        "stopping_distance_m": k["stopping_distance_m"] if stopped else None,
        "stopping_time_s": k["stopping_time_s"] if stopped else None,
        "mean_deceleration": k["mean_deceleration"],
        "max_slip": k["max_slip"],
        "wheel_lock_events": int(k["wheel_lock_events"]),
        "max_lock_duration_s": k["max_lock_duration_s"],
        "worst_axle": None if k["worst_axle"] < 0 else axle_name(int(k["worst_axle"])),
        "adhesion_utilisation": k["adhesion_utilisation"],
        "safety_timer_trips": int(k["safety_timer_trips"]),
        "min_main_reservoir_bar": gauge(k["min_main_reservoir"]),
        "min_supply_bar": gauge(k["min_supply"]),
        "min_supply_margin_bar": k["min_supply_margin"] / BAR,
        "air_drawn_kg": k["air_drawn_kg"],
        "air_vented_kg": k["air_vented_kg"],
        "cylinder_shortfall_s": k["cylinder_shortfall_s"],
        "brake_energy_mj": k["brake_energy"] / 1e6,
        "max_disc_temperature_c": k["max_disc_temperature"] - ZERO_CELSIUS,
        "air_balance_error": k["air_balance_error"],
        "valve_switchings": int(k["valve_switchings"]),
        "max_sliding_energy_kj": k["max_sliding_energy"] / 1e3,
        "sliding_energy_kj": k["sliding_energy"] / 1e3,
        "stopped": stopped,
    }


from railbrake.simulation.timing import bench, bench_plant  # noqa: E402  (they use run, above)


# ------------------------------------------------------------------ response of the simulated chain

RESPONSE_WINDOW = response.settings()["window_s"]   # s of emergency braking the build-up is measured over


def emergency_scenario(train: str, initial_speed: float, condition: str = "dry-medium",
                       max_time: float = 3600.0, load: str | None = None) -> Scenario:
    """An emergency stop of `train` (preset or file) from initial_speed (m/s) on `condition`."""
    from railbrake.scenario import SCHEMA, from_data
    train, condition = name_or_path("train", train), name_or_path("condition", condition)
    initial_speed, max_time = real("initial_speed", initial_speed, 0.0), real("max_time", max_time, 0.0)
    if load is not None:
        choice("load", load, LOAD_CASES)
    data = {"schema": SCHEMA, "name": f"emergency-{initial_speed * 3.6:.0f}-{condition}",
            "title": f"Emergency brake from {initial_speed * 3.6:.0f} km/h, {train}",
            "train": {"preset": str(train)}, "initial_speed": f"{initial_speed!r} m/s",
            "demand": [{"time": "0 s", "emergency": True}], "adhesion": {"condition": condition},
            "stop": {"speed": "0.05 m/s", "max_time": f"{max_time} s"}}
    if load is not None:
        data["train"]["load_case"] = load
    return from_data(data, f"emergency stop of {train}", {})


def response_times(result: Result, train=None) -> tuple[float, float]:
    """EN 14531-1 delay ta and build-up tb of a run's brake, measured on its total brake force
    (railbrake.simulation.response); train: the run's (default: its resolved configuration's)."""
    instance("result", result, Result)
    if train is None:
        if result.resolved is None:
            raise InputError("response_times: give the train of a run made with a train of its own")
        train = result.resolved.train
    b = response.measure(result, train)
    return b.delay, b.build_up


def simulated_response(train: str, initial_speed: float, load: str | None = None) -> tuple[float, float]:
    """(ta, tb) of `train`'s simulated emergency brake from initial_speed (m/s) on dry rail: the
    first RESPONSE_WINDOW s of a run (railbrake.simulation.response.simulated)."""
    train = name_or_path("train", train)
    b = response.simulated(load_train(train, load or True), initial_speed, preset=str(train))
    return b.delay, b.build_up
