"""EP pressure-control valve: characteristic with hysteresis, step response, oscillation check."""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railbrake import _args, _core, config
from railbrake.errors import InputError
from railbrake.pneumatics import Network
from railbrake.units import BAR
from railbrake.valves.params import DATA, load

MM = 1e-3
T_AMBIENT = 293.15   # K, initial and wall temperature of the chambers

MAX_TIME_S = 3600.0      # longest simulated valve response (s): a software limit on the work asked
MAX_POINTS = 1_000_000   # output samples at most (memory grows with them)


def load_epv(override=None) -> dict:
    return load("epv", override)


def _params(params, argument: str = "params") -> dict:
    """A complete parameter set as given, else the defaults with `params` as overrides."""
    full = isinstance(params, dict) and {"solenoid_table", "armature", "piston", "current_max_a"} <= params.keys()
    return params if full else load("epv", params, argument)


def _force_table(force_table):
    """None, or (airgap m, current A, force N [airgap, current]) as read_force_table returns it."""
    if force_table is None:
        return None
    if not (isinstance(force_table, (tuple, list)) and len(force_table) == 3):
        raise TypeError(f"force_table = {_args.show(force_table)}: must be (airgap, current, force) as "
                        "read_force_table returns it")
    gap, current = _args.reals("force_table[0] (airgap)", force_table[0]), \
        _args.reals("force_table[1] (current)", force_table[1])
    force = _args.reals("force_table[2] (force)", force_table[2])
    if gap.ndim != 1 or current.ndim != 1 or force.shape != (gap.size, current.size):
        raise InputError(f"force_table: force must be an array [airgap, current] of {gap.size} x {current.size}")
    return gap, current, force


def _schedule(name: str, points) -> list:
    """[(time s, value)] pairs."""
    if not isinstance(points, (list, tuple)):
        raise TypeError(f"{name} = {_args.show(points)}: must be a list of (time s, value) pairs")
    for i, point in enumerate(points):
        if not (isinstance(point, (list, tuple)) and len(point) == 2):
            raise TypeError(f"{name}[{i}] = {_args.show(point)}: must be a (time s, value) pair")
        _args.real(f"{name}[{i}] time", point[0])
        _args.real(f"{name}[{i}] value", point[1])
    return list(points)


def read_force_table(path, rated_current: float | None = None):
    """Solenoid force table CSV: header 'airgap_mm,<currents A>...', rows 'airgap_mm,<forces N>...';
    '#' lines are comments. Returns (airgap m, current A, force N [airgap, current]). Refused: axes
    not strictly increasing, a force falling with current, a table not reaching rated_current (A)."""
    path = _args.path("path", path)
    if rated_current is not None:
        rated_current = _args.real("rated_current", rated_current, 0.0)
    if not path.is_file() and not (DATA / path).is_file():
        raise InputError(f"path = {_args.show(str(path))}: no such force table file")
    text = config.read_text(path) if path.is_file() else (DATA / path).read_text()
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
    gap, force = data[:, 0], data[:, 1:]
    bad = np.flatnonzero(np.diff(gap) <= 0)
    if bad.size:
        i = bad[0] + 1
        raise InputError(f"{path}: airgap_mm[{i}] = {gap[i]:g} after {gap[i - 1]:g}: the force table "
                         "must be sorted by airgap (strictly increasing)")
    bad = np.flatnonzero(np.diff(current) <= 0)
    if bad.size:
        j = bad[0] + 1
        raise InputError(f"{path}: current[{j}] = {current[j]:g} A after {current[j - 1]:g} A: the header's "
                         "currents must be strictly increasing")
    falls = np.argwhere(np.diff(force, axis=1) < 0)
    if falls.size:
        i, j = falls[0]
        raise InputError(f"{path}: airgap {gap[i]:g} mm: force {force[i, j + 1]:g} N at {current[j + 1]:g} A "
                         f"below {force[i, j]:g} N at {current[j]:g} A: the force must not fall with current "
                         "(monotone non-decreasing in current)")
    if rated_current is not None and not current[-1] >= rated_current:
        raise InputError(f"{path}: currents up to {current[-1]:g} A: the table must cover the rated current "
                         f"current_max_a = {rated_current:g} A (rated_current; range [0, >= {rated_current:g}] A)")
    return gap * MM, current, force


def _wall_conductance(volume: float, thermal_time: float | None) -> float:
    """h A (W/K) giving the air of `volume` at 5 bar the wall time constant thermal_time (s), as the
    detailed train model sets it (rb_detailed_params.thermal_time); None: adiabatic."""
    if thermal_time is None:
        return 0.0
    return _core.rb_wall_conductance(volume, T_AMBIENT, thermal_time, _core.WALL_REFERENCE_PRESSURE)


def epv_network(p: dict, current_schedule, force_table=None, thermal_time: float | None = None) -> Network:
    """The EPV as a network: supply -> pilot orifice -> pilot chamber -> flapper-nozzle -> atmosphere;
    relay piston between pilot and control chambers opening the inlet (x > 0) or exhaust (x < 0).
    thermal_time (s): wall heat exchange of the chambers (default: adiabatic)."""
    p = _params(p, "p")
    current_schedule = _schedule("current_schedule", current_schedule)
    if not 1 <= len(current_schedule) <= 16:
        raise InputError(f"current_schedule: {len(current_schedule)} points: needs 1 to 16")
    force_table = _force_table(force_table)
    if thermal_time is not None:
        _args.real("thermal_time", thermal_time, 0.0, low_open=True)
    a, k = p["armature"], p["piston"]
    pa, cd = p["ambient_pa"], p["discharge_coefficient"]
    gap, current, force = (force_table if force_table is not None
                           else read_force_table(p["solenoid_table"], p["current_max_a"]))
    net = Network(ambient_pressure=pa)
    net.add_reservoir("supply", pa + p["supply_bar"] * BAR)
    net.add_reservoir("atmosphere", pa)
    for name, volume in (("pilot", p["pilot_volume_cm3"] * 1e-6), ("control", p["control_volume_l"] * 1e-3)):
        net.add_volume(name, volume, pa, T_AMBIENT, heat_transfer=_wall_conductance(volume, thermal_time))
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
    hysteresis_bar: float | None   # None when the ramp is too fast to be quasi-static
    ramp_time_s: float
    lag_bar: float             # hysteresis at this ramp minus at a ramp twice as slow
    quasi_static: bool
    max_drop_up_bar: float     # largest fall of pressure_up from one point to the next (0: monotone)
    note: str = ""

    def as_dict(self) -> dict:
        return {"current_up": self.current_up, "pressure_up": self.pressure_up,
                "current_down": self.current_down, "pressure_down": self.pressure_down,
                "hysteresis_bar": self.hysteresis_bar, "ramp_time_s": self.ramp_time_s, "lag_bar": self.lag_bar,
                "quasi_static": self.quasi_static, "max_drop_up_bar": self.max_drop_up_bar,
                "pressure_max_bar": float(np.max(self.pressure_up)),
                "pressure_down_at_0_a_bar": float(self.pressure_down[-1]), "note": self.note}


QUASI_STATIC_BAR = 0.01        # hysteresis may change by this much (or 10 %) when the ramp is halved in rate
SETTLE_S = 2.0                 # held at the first current before the ramp: the ramp starts at equilibrium


def _ramp(p: dict, ramp_time: float, n_points: int, force_table):
    """Up and down branches (current A, control bar gauge) and the largest up/down difference at
    equal current."""
    i_max, half = p["current_max_a"], ramp_time / 2
    net = epv_network(p, [(0.0, 0.0), (SETTLE_S, 0.0), (SETTLE_S + half, i_max), (SETTLE_S + ramp_time, 0.0)],
                      force_table)
    times = SETTLE_S + np.linspace(0.0, ramp_time, 2 * n_points - 1)
    res = net.simulate(times[-1], times=np.concatenate([[0.0], times]), max_step=ramp_time / 400)
    current = np.interp(times, SETTLE_S + np.array([0, half, ramp_time]), [0, i_max, 0])
    gauge = (res["control"].p[1:] - p["ambient_pa"]) / BAR
    up, down = slice(0, n_points), slice(n_points - 1, None)
    down_on_up = np.interp(current[up], current[down][::-1], gauge[down][::-1])
    return current[up], gauge[up], current[down], gauge[down], float(np.max(np.abs(down_on_up - gauge[up])))


def epv_characteristic(params=None, ramp_time: float = 100.0, n_points: int = 201,
                       force_table=None) -> EpvCharacteristic:
    """Control pressure against current from a linear ramp 0 -> current_max_a -> 0 taking ramp_time
    (s) in all, started from the equilibrium at 0 A. Hysteresis: the largest up/down pressure
    difference at equal current, reported only when quasi-static: the same ramp twice as slow
    changes it by less than QUASI_STATIC_BAR or 10 % (else it is the valve's lag, lag_bar)."""
    p = _params(params)
    ramp_time = _args.real("ramp_time", ramp_time, 0.0, MAX_TIME_S, low_open=True)
    n_points = _args.whole("n_points", n_points, 2, MAX_POINTS)
    force_table = _force_table(force_table)
    c_up, p_up, c_down, p_down, hyst = _ramp(p, ramp_time, n_points, force_table)
    slow = _ramp(p, 2.0 * ramp_time, n_points, force_table)[4]
    lag = hyst - slow
    quasi = abs(lag) <= max(QUASI_STATIC_BAR, 0.1 * slow)
    note = "" if quasi else (f"ramp {ramp_time:g} s too fast to be quasi-static: the up/down difference "
                             f"{hyst:.3f} bar is {lag:.3f} bar more than at {2 * ramp_time:g} s (valve lag, not "
                             "hysteresis); use a longer --ramp-time")
    return EpvCharacteristic(c_up, p_up, c_down, p_down, hyst if quasi else None, ramp_time, lag, quasi,
                             float(max(0.0, -np.min(np.diff(p_up)))), note)


def epv_step(params=None, current: float = 0.5, t_end: float = 1.0, t_step: float = 0.05,
             n_points: int = 1001, force_table=None, start_current: float = 0.0,
             thermal_time: float | None = None):
    """Response to a current step start_current -> current at t_step (the valve at rest at
    start_current before it; chambers adiabatic unless thermal_time, s); returns the network result."""
    p = _params(params)
    t_end = _args.real("t_end", t_end, 0.0, MAX_TIME_S, low_open=True)
    t_step = _args.real("t_step", t_step, 0.0, t_end)
    n_points = _args.whole("n_points", n_points, 2, MAX_POINTS)
    force_table = _force_table(force_table)
    for name, value in (("current", current), ("start_current", start_current)):
        if not 0 <= _args.real(name, value) <= p["current_max_a"]:
            raise InputError(f"{name} = {value:g} A: must lie in [0, {p['current_max_a']:g}] A "
                             "(current_max_a, the rated current)")
    settle = SETTLE_S if start_current > 0 else 0.0
    net = epv_network(p, [(0.0, start_current), (settle + t_step, start_current), (settle + t_step, current)],
                      force_table, thermal_time)
    if not settle:
        return net.simulate(t_end, times=np.linspace(0.0, t_end, n_points))
    res = net.simulate(settle + t_end, times=np.concatenate([[0.0], settle + np.linspace(0.0, t_end, n_points)]))
    res.time = res.time[1:] - settle
    for e in res.elements.values():   # drop the settling sample
        for name in ("p", "T", "m", "mdot", "x", "v"):
            if getattr(e, name, None) is not None:
                setattr(e, name, getattr(e, name)[1:])
    return res


def step_metrics(time, gauge_bar, t_step: float = 0.05, band: float = 0.02) -> dict:
    """Final value, 10-90 % rise time, overshoot (bar and % of the change) and settling time (from the
    step to entering for good the band +-`band` x change, at least +-0.01 bar, around the final)."""
    time, p = _args.reals("time", time), _args.reals("gauge_bar", gauge_bar)
    if time.ndim != 1 or time.size < 2 or p.shape != time.shape:
        raise InputError(f"time, gauge_bar: two arrays of the same length >= 2 (here {time.shape}, {p.shape})")
    t_step, band = _args.real("t_step", t_step), _args.real("band", band, 0.0)
    final, start = float(p[-1]), float(np.interp(t_step, time, p))
    change = final - start
    sign = 1.0 if change >= 0 else -1.0
    crossed = lambda f: time[np.argmax(sign * (p - start) >= f * abs(change))]  # noqa: E731
    rise = float(crossed(0.9) - crossed(0.1)) if abs(change) > 0 else math.nan
    over = max(0.0, float(sign * (p - final).max() if sign > 0 else -(p - final).min()))
    outside = np.flatnonzero(np.abs(p - final) > max(band * abs(change), 0.01))
    settle = float(time[outside[-1] + 1] - t_step) if outside.size and outside[-1] + 1 < len(time) else 0.0
    return {"final_bar": final, "rise_time_10_90_s": rise, "overshoot_bar": over,
            "overshoot_pct": 100.0 * over / abs(change) if abs(change) > 0 else 0.0, "settling_time_s": settle}


def oscillates(time, pressure, settle_fraction: float = 0.5, amplitude: float = 0.01 * BAR) -> bool:
    """True when, over the last (1 - settle_fraction) of the record, the pressure keeps swinging
    around its mean by more than `amplitude` (Pa) with at least 3 mean crossings each way."""
    time, pressure = _args.reals("time", time), _args.reals("pressure", pressure)
    if time.ndim != 1 or time.size < 2 or pressure.shape != time.shape:
        raise InputError(f"time, pressure: two arrays of the same length >= 2 (here {time.shape}, {pressure.shape})")
    settle_fraction = _args.real("settle_fraction", settle_fraction, 0.0, 1.0, high_open=True)
    amplitude = _args.real("amplitude", amplitude, 0.0)
    tail = pressure[int(len(time) * settle_fraction):]
    swing = tail - tail.mean()
    crossings = np.count_nonzero(np.diff(np.sign(swing)) != 0)
    return bool(np.ptp(tail) > 2 * amplitude and crossings >= 6)
