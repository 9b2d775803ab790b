"""The detailed train model: the real-time plant's train with each car's air side made of the
detailed valve models (EP valve with armature, solenoid table and piston; relay valve with its
membrane; WSP solenoid valves; ideal-gas volumes with mass and energy balance) integrated by the
variable-step stiff solver between BCU cycles (core/src/detailed_*.c, docs/detailed.md).

The valves are the designs of ``railbrake/data/valves`` (epv.yaml, relay.yaml: the files that
``railbrake valve`` studies); ``railbrake/data/detailed/valves.yaml`` holds the solver settings.
"""

from __future__ import annotations

import ctypes
import math
import time as _time
from importlib import resources
from typing import Callable

import numpy as np
import yaml

from railbrake import _core
from railbrake.resolve import resolve
from railbrake.scenario import load
from railbrake.results.scripting import Result
from railbrake.simulation.runs import CHUNK
from railbrake.simulation.parameters import ZERO_CELSIUS, _scenario_struct, bcu_params, channels, plant_params, wsp_params
from railbrake.valves import load_epv, load_relay, read_force_table
from railbrake.valves.params import _merge

DATA = resources.files("railbrake") / "data" / "detailed"
MM, CM3 = 1e-3, 1e-6


def load_valves(override: dict | None = None) -> dict:
    """The valve designs {"epv": epv.yaml, "relay": relay.yaml} with the detailed model's settings
    (air, drive, solver), updated by a dict of overrides (unknown keys are refused)."""
    params = {"epv": load_epv(), "relay": load_relay(), **yaml.safe_load((DATA / "valves.yaml").read_text())}
    return params if override is None else _merge(params, override, lambda path: "detailed valves")


def _area(d_mm: float) -> float:
    return math.pi * (d_mm * MM) ** 2 / 4


def solenoid_table(valves: dict | None = None):
    """The EP valve's force table (airgap m, current A, force N), checked against its rated current."""
    epv = (valves or load_valves())["epv"]
    return read_force_table(epv["solenoid_table"], epv["current_max_a"])


def detailed_params(valves: dict | None = None) -> _core.DetailedParams:
    """C parameters from the valve set (a dict as load_valves gives; default: the packaged one)."""
    v = valves or load_valves()
    e, r, a, k, m = v["epv"], v["relay"], v["epv"]["armature"], v["epv"]["piston"], v["relay"]["membrane"]
    d = _core.DetailedParams()
    d.pilot_volume, d.pilot_orifice_area = e["pilot_volume_cm3"] * CM3, _area(e["pilot_orifice_diameter_mm"])
    d.nozzle_diameter = e["nozzle_diameter_mm"] * MM
    d.armature_mass, d.armature_spring_rate = a["mass"], a["spring_rate"]
    d.armature_preload, d.armature_damping = a["spring_preload"], a["damping"]
    d.airgap_open, d.flapper_travel = a["airgap_mm"] * MM, a["flapper_travel_mm"] * MM
    gap, current, force = solenoid_table(v)
    t = d.solenoid
    t.n_gap, t.n_current = len(gap), len(current)
    for i, g in enumerate(gap):
        t.gap[i] = g
        for j, c in enumerate(current):
            t.current[j] = c
            t.force[i * len(current) + j] = force[i, j]
    d.current_max = e["current_max_a"]
    d.piston_area, d.piston_mass = _area(k["diameter_mm"]), k["mass"]
    d.piston_spring_rate, d.piston_preload, d.piston_damping = k["spring_rate"], k["spring_preload"], k["damping"]
    d.piston_friction, d.piston_friction_velocity = k["friction"], k["friction_velocity"]
    d.piston_travel, d.seat_lap = k["travel_mm"] * MM, e["seat_lap_mm"] * MM
    d.epv_inlet_diameter, d.epv_exhaust_diameter = e["inlet_seat_diameter_mm"] * MM, e["exhaust_seat_diameter_mm"] * MM
    d.membrane_points = len(m["x_mm"])
    for i, (x, vol) in enumerate(zip(m["x_mm"], m["volume_cm3"])):
        d.membrane_x[i], d.membrane_volume[i] = x * MM, vol * CM3
    d.membrane_mass, d.membrane_spring_rate = m["mass"], m["spring_rate"]
    d.membrane_preload, d.membrane_damping, d.membrane_travel = m["spring_preload"], m["damping"], m["travel_mm"] * MM
    d.relay_inlet_diameter = r["inlet_seat_diameter_mm"] * MM
    d.relay_exhaust_diameter = r["exhaust_seat_diameter_mm"] * MM
    d.thermal_time, d.trim_time = v["air"]["thermal_time_s"], v["drive"]["trim_time_s"]
    d.rtol, d.atol, d.mechanics_dt = v["solver"]["rtol"], v["solver"]["atol"], v["solver"]["mechanics_dt_s"]
    _core.call(_core.rb_detailed_check, ctypes.byref(d))
    return d


def run_detailed(scenario="emergency-300-heavy-rain", cars: int | None = None, valves: dict | None = None,
                 progress: Callable[[float, float], None] | None = None) -> Result:
    """Run a scenario with the detailed model; the same Result shape as simulation.run. The kpis
    add the solver's work (ode_steps, ode_rejected, rhs_calls) and the wall time (wall_s)."""
    resolved = resolve(scenario, cars)
    sc, n_cars = resolved.scenario, resolved.cars
    plant = plant_params(sc, n_cars, train=resolved.train)
    bcu = bcu_params(plant, sc, True, resolved.train)
    wsp, spec, det = wsp_params(sc), _scenario_struct(sc), detailed_params(valves)
    state = ctypes.create_string_buffer(_core.rb_detailed_state_size())
    _core.call(_core.rb_detailed_init, ctypes.byref(plant), ctypes.byref(det), ctypes.byref(bcu),
               ctypes.byref(wsp), ctypes.byref(spec), state)
    names = channels(n_cars)
    rows = int(math.ceil(sc.spec.stop.max_time / sc.spec.outputs.record_interval)) + 3
    series = np.zeros((rows, len(names)))
    finished, t, start = ctypes.c_int(0), 0.0, _time.perf_counter()
    while not finished.value:
        t += CHUNK
        _core.call(_core.rb_detailed_advance, ctypes.byref(plant), ctypes.byref(det), ctypes.byref(bcu),
                   ctypes.byref(spec), state, t, _core.ptr(series), rows, ctypes.byref(finished))
        if progress is not None:
            row = min(int(t / sc.spec.outputs.record_interval), rows - 1)
            progress(min(t, sc.spec.stop.max_time), float(series[row, 1]))
    wall = _time.perf_counter() - start
    kpis, stats = _core.Kpis(), _core.OdeStats()
    _core.rb_detailed_kpis(ctypes.byref(plant), state, ctypes.byref(kpis))
    _core.rb_detailed_stats(state, ctypes.byref(stats))
    n_rows = int(np.count_nonzero(series[:, 0])) + 1
    series = series[:n_rows]
    outputs = {name: series[:, i].copy() for i, (name, _) in enumerate(names)}
    result = {k: getattr(kpis, k) for k in ("stopping_distance_m", "stopping_time_s", "mean_deceleration",
                                            "max_slip", "air_consumed_kg", "air_balance_error")}
    result.update(brake_energy_mj=kpis.brake_energy / 1e6,
                  max_disc_surface_temperature_c=kpis.max_disc_surface_temperature - ZERO_CELSIUS)
    result.update(stopped=bool(kpis.stopped), safety_timer_trips=int(kpis.safety_timer_trips),
                  ode_steps=stats.steps, ode_rejected=stats.rejected, rhs_calls=stats.rhs_calls, wall_s=wall)
    return Result(sc.name, n_cars, bool(bcu.wsp_enabled), outputs["time"], outputs, dict(names), result,
                  plant.atmosphere)


def epv_current(pressure: float, supply: float | None = None, valves: dict | None = None,
                scenario="emergency-250-dry") -> float:
    """The EP drive's static inverse: current (A) for a control pressure (Pa abs)."""
    plant = plant_params(load(scenario), 1)
    out = ctypes.c_double()
    _core.call(_core.rb_detailed_epv_current, ctypes.byref(plant), ctypes.byref(detailed_params(valves)),
               plant.initial_pressure if supply is None else supply, pressure, ctypes.byref(out))
    return out.value


def valve_run(current: float, t_end: float = 3.0, valves: dict | None = None,
              scenario="emergency-250-dry") -> dict:
    """One car's valves alone at a constant EP current (WSP valves open to the cylinders) for t_end
    seconds: final pressures (Pa) and body positions (m)."""
    plant = plant_params(load(scenario), 1)
    p, x = (ctypes.c_double * 4)(), (ctypes.c_double * 3)()
    _core.call(_core.rb_detailed_valve_run, ctypes.byref(plant), ctypes.byref(detailed_params(valves)),
               current, t_end, p, x)
    return {"pilot": p[0], "control": p[1], "relay": p[2], "cylinder": p[3],
            "armature": x[0], "piston": x[1], "membrane": x[2]}
