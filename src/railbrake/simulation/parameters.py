"""The C structs of a run (ctypes): the plant, the BCU, the WSP and the scenario, from a resolved
configuration (railbrake.resolve), and the C KPIs back as a dict. Every physical value comes from
the train file or the scenario; the numbers here are unit conversions. The runs themselves:
railbrake.simulation.runs. Model: docs/simulation.md.
"""

from __future__ import annotations

import ctypes
import math
import os
import warnings
from functools import cache
from importlib import resources

import numpy as np
import yaml

from railbrake import _core, sizing
from railbrake.adhesion import AdhesionRangeWarning, load_condition
from railbrake.contact import wheel_rail_contact
from railbrake._args import instance, real, whole
from railbrake.errors import InputError
from railbrake.scenario import Scenario, fault_problem, fault_value
from railbrake.simulation import traction
from railbrake.units import KMH
from railbrake.vehicle import axle_discs, load_train, with_cars

DT = 1e-3
# One plant step per dt up to this; a longer dt is split into equal sub-steps no longer than it. With
# its timing rules (rb_plant.h) one 1 ms step is as accurate as 4 x 0.25 ms were (docs/detailed.md,
# step-size study); above 2 ms the WSP cycles need the sub-steps.
MAX_SUBSTEP = 2e-3
# The wheelset kernel (rb_plant.h): "auto" (the vector one where the CPU has it) or "portable".
KERNEL_ENV = "RAILBRAKE_KERNEL"
ZERO_CELSIUS = 273.15               # K


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
    traction.set_car(car, entry.motor and ed is not None)
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
    heat = axle_discs(entry)
    car.disc_heat_capacity, car.disc_surface_capacity = heat.heat_capacity, heat.surface_capacity
    car.disc_surface_conductance = heat.surface_conductance
    car.disc_cooling = _core.speed_table(heat.cooling_speed, heat.cooling)
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
    cond = load_condition(name)   # its validity: checked with the scenario (Scenario.check_validity)
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
    p.sand_entrained, p.sand_retention = sanders.sand_entrained, sanders.sand_retention


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
    spec = instance("scenario", scenario, Scenario).spec
    if n_cars is not None:
        whole("n_cars", n_cars, 1, _core.PLANT_MAX_CARS)
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
        problem = fault_problem(f)   # a spec built in Python (with_) is checked as a file's
        if problem is not None:
            raise InputError(f"{scenario.where('faults', i, problem[0])}{problem[1]}")
        p.fault[i] = _core.Fault(_FAULT_INDEX[f.type], 0 if f.car is None else f.car - 1, -1 if f.axle is None else f.axle - 1,
                                 f.start, fault_value(f))
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
                  "setpoint_release", "setpoint_memory", "setpoint_ramp", "ds_speed_threshold", "ds_slip_threshold", "ds_decel_threshold",
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


def structs(resolved, wsp: bool = True, dt: float = DT, substeps: int | None = None, kernel: str | None = None,
            train=None) -> tuple:
    """The C structs of a resolved configuration: (plant, BCU, WSP, scenario)."""
    sc, n_cars = resolved.scenario, resolved.cars
    train = with_cars(resolved.train if train is None else train, n_cars)
    plant = plant_params(sc, n_cars, dt, substeps, kernel, train)
    for text in sc.outside_validity():   # forced (adhesion.allow_outside_validity), else refused
        warnings.warn(f"scenario {sc.name}: forced outside validity: {text}", AdhesionRangeWarning, stacklevel=3)
    for text in sizing.supply_warnings(train, demanded_steps(sc), sc.spec.initial_speed):
        warnings.warn(f"scenario {sc.name}: {text}", sizing.SupplyWarning, stacklevel=3)
    return plant, bcu_params(plant, sc, wsp, train), wsp_params(sc), _scenario_struct(sc)


def demanded_steps(scenario: Scenario) -> dict:
    """The brake steps a scenario demands: {"emergency": 1.0, "service": largest fraction}."""
    steps = {}
    for step in instance("scenario", scenario, Scenario).spec.demand:
        if step.emergency:
            steps["emergency"] = 1.0
        elif step.service > 0.0:
            steps["service"] = max(steps.get("service", 0.0), step.service)
    return steps


def axle_name(index: int) -> str:
    """'c3a2' (car 3, axle 2, 1-based) for the 0-based global axle index, as in channel names."""
    index = whole("index", index, 0)
    return f"c{index // _core.AXLES_PER_CAR + 1}a{index % _core.AXLES_PER_CAR + 1}"


def outside_validity_kpi(scenario: Scenario, max_slip: float | None = None) -> dict:
    """{"adhesion_outside_validity": what} for a run forced outside a condition's validity, else {}.
    With the run's max_slip, a condition whose file gives a creep range the run left refuses the
    run's result unless forced (the creep is known only once run)."""
    outside = instance("scenario", scenario, Scenario).outside_validity()
    if max_slip is not None:
        max_slip = real("max_slip", max_slip, 0.0)
        creep = scenario.creep_outside_validity(max_slip)
        if creep and not scenario.spec.adhesion.allow_outside_validity:
            raise InputError(f"scenario {scenario.name}: {creep[0]}: the run's largest creep (KPI max_slip) left the "
                             "range the condition was measured in; force it with adhesion.allow_outside_validity: true")
        outside += creep
    return {"adhesion_outside_validity": "; ".join(outside)} if outside else {}


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
        "max_air_shortfall_bar": max(0.0, -k["min_supply_margin"] / BAR),
        "air_drawn_kg": k["air_drawn_kg"],
        "air_vented_kg": k["air_vented_kg"],
        "cylinder_shortfall_s": k["cylinder_shortfall_s"],
        "brake_energy_mj": k["brake_energy"] / 1e6,
        "max_disc_temperature_c": k["max_disc_temperature"] - ZERO_CELSIUS,
        "air_balance_error": k["air_balance_error"],
        "valve_switchings": int(k["valve_switchings"]),
        "max_sliding_energy_kj": k["max_sliding_energy"] / 1e3,
        "sliding_energy_kj": k["sliding_energy"] / 1e3,
        "mean_pad_friction": k["mean_pad_friction"] if k["mean_pad_friction"] > 0.0 else None,
        "max_disc_surface_temperature_c": k["max_disc_surface_temperature"] - ZERO_CELSIUS,
        "stopped": stopped,
    }


