"""EP pressure-control valve: characteristic with hysteresis, step response, oscillation check."""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railbrake.errors import InputError
from railbrake.pneumatics import Network
from railbrake.units import BAR
from railbrake.valves.params import DATA, load

MM = 1e-3


def load_epv(override=None) -> dict:
    return load("epv", override)


def _params(params) -> dict:
    """A complete parameter set as given, else the defaults with `params` as overrides."""
    return params if isinstance(params, dict) and "solenoid_table" in params else load_epv(params)


def read_force_table(path):
    """Solenoid force table CSV: header 'airgap_mm,<currents A>...', rows 'airgap_mm,<forces N>...';
    '#' lines are comments. Returns (airgap m, current A, force N [airgap, current])."""
    path = Path(path)
    text = path.read_text() if path.is_file() else (DATA / str(path)).read_text()
    lines = [line for line in text.splitlines() if line.strip() and not line.startswith("#")]
    rows = list(csv.reader(lines))
    try:
        current = np.array([float(v) for v in rows[0][1:]])
        data = np.array([[float(v) for v in r] for r in rows[1:]])
    except (ValueError, IndexError):
        raise InputError(f"{path}: force table must be numbers under a header "
                         "'airgap_mm,<currents>'") from None
    if data.ndim != 2 or data.shape[1] != current.size + 1:
        raise InputError(f"{path}: every row needs an airgap and {current.size} forces")
    gap = data[:, 0]
    bad = np.flatnonzero(np.diff(gap) <= 0)
    if bad.size:
        i = bad[0] + 1
        raise InputError(f"{path}: airgap_mm[{i}] = {gap[i]:g} after {gap[i - 1]:g}: the force table "
                         "must be sorted by airgap (strictly increasing)")
    return gap * MM, current, data[:, 1:]


def epv_network(p: dict, current_schedule, force_table=None) -> Network:
    """The EPV as a network: supply -> pilot orifice -> pilot chamber -> flapper-nozzle -> atmosphere;
    relay piston between pilot and control chambers opening the inlet (x > 0) or exhaust (x < 0)."""
    a, k = p["armature"], p["piston"]
    pa, cd = p["ambient_pa"], p["discharge_coefficient"]
    gap, current, force = force_table if force_table is not None else read_force_table(p["solenoid_table"])
    net = Network(ambient_pressure=pa)
    net.add_reservoir("supply", pa + p["supply_bar"] * BAR)
    net.add_reservoir("atmosphere", pa)
    net.add_volume("pilot", p["pilot_volume_cm3"] * 1e-6, pa)
    net.add_volume("control", p["control_volume_l"] * 1e-3, pa)
    nozzle_area = math.pi * (p["nozzle_diameter_mm"] * MM) ** 2 / 4
    travel = a["flapper_travel_mm"] * MM
    net.add_body("armature", a["mass"], [("pilot", nozzle_area, -1.0)], a["spring_rate"], a["spring_preload"],
                 a["damping"], a["friction"], x_min=0.0, x_max=travel,
                 solenoid=(gap, current, force, a["airgap_mm"] * MM, current_schedule))
    piston_area = math.pi * (k["diameter_mm"] * MM) ** 2 / 4
    stroke = k["travel_mm"] * MM
    net.add_body("piston", k["mass"], [("pilot", piston_area, 1.0), ("control", piston_area, -1.0)],
                 k["spring_rate"], k["spring_preload"], k["damping"], k["friction"], k["friction_velocity"],
                 x_min=-stroke, x_max=stroke)
    pilot_orifice = math.pi * (p["pilot_orifice_diameter_mm"] * MM) ** 2 / 4
    net.add_orifice("pilot_orifice", "supply", "pilot", area=pilot_orifice, discharge_coefficient=cd)
    net.add_driven_orifice("nozzle", "pilot", "atmosphere", "armature", "flapper",
                           p["nozzle_diameter_mm"] * MM, offset=travel, direction=-1.0, discharge_coefficient=cd)
    lap = p["seat_lap_mm"] * MM  # both seats shut for |x| <= lap: the piston can rest without hunting
    net.add_driven_orifice("inlet", "supply", "control", "piston", "seat", p["inlet_seat_diameter_mm"] * MM,
                           offset=lap, discharge_coefficient=cd)
    net.add_driven_orifice("exhaust", "control", "atmosphere", "piston", "seat",
                           p["exhaust_seat_diameter_mm"] * MM, offset=-lap, direction=-1.0,
                           discharge_coefficient=cd)
    return net


@dataclass
class EpvCharacteristic:
    current_up: np.ndarray     # A
    pressure_up: np.ndarray    # bar gauge
    current_down: np.ndarray
    pressure_down: np.ndarray
    hysteresis_bar: float

    def as_dict(self) -> dict:
        return {"current_up": self.current_up, "pressure_up": self.pressure_up,
                "current_down": self.current_down, "pressure_down": self.pressure_down,
                "hysteresis_bar": self.hysteresis_bar}


def epv_characteristic(params=None, ramp_time: float = 20.0, n_points: int = 201,
                       force_table=None) -> EpvCharacteristic:
    """Control pressure against current from a linear ramp 0 -> current_max_a -> 0 taking ramp_time
    (s) in all. Hysteresis: the largest up/down pressure difference at equal current."""
    p = _params(params)
    if not ramp_time > 0:
        raise InputError(f"ramp_time = {ramp_time}: must be > 0 (s)")
    i_max, half = p["current_max_a"], ramp_time / 2
    net = epv_network(p, [(0.0, 0.0), (half, i_max), (ramp_time, 0.0)], force_table)
    res = net.simulate(ramp_time, n_points=2 * n_points - 1, max_step=ramp_time / 400)
    current = np.interp(res.time, [0, half, ramp_time], [0, i_max, 0])
    gauge = (res["control"].p - p["ambient_pa"]) / BAR
    up, down = slice(0, n_points), slice(n_points - 1, None)
    down_on_up = np.interp(current[up], current[down][::-1], gauge[down][::-1])
    # The first 5 % of the up ramp still carries the start from rest: left out of the measure.
    judged = current[up] >= 0.05 * i_max
    return EpvCharacteristic(current[up], gauge[up], current[down], gauge[down],
                             float(np.max(np.abs(down_on_up - gauge[up])[judged])))


def epv_step(params=None, current: float = 0.5, t_end: float = 1.0, t_step: float = 0.05,
             n_points: int = 1001, force_table=None):
    """Response to a current step 0 -> current at t_step; returns the network result."""
    p = _params(params)
    if not 0 <= current <= p["current_max_a"] * 1.2:
        raise InputError(f"current = {current} A: must lie in [0, {1.2 * p['current_max_a']:g}] A")
    net = epv_network(p, [(t_step, 0.0), (t_step, current)], force_table)
    return net.simulate(t_end, n_points=n_points)


def oscillates(time, pressure, settle_fraction: float = 0.5, amplitude: float = 0.01 * BAR) -> bool:
    """True when, over the last (1 - settle_fraction) of the record, the pressure keeps swinging
    around its mean by more than `amplitude` (Pa) with at least 3 mean crossings each way."""
    tail = np.asarray(pressure)[int(len(time) * settle_fraction):]
    swing = tail - tail.mean()
    crossings = np.count_nonzero(np.diff(np.sign(swing)) != 0)
    return bool(np.ptp(tail) > 2 * amplitude and crossings >= 6)
