"""Relay valve with a membrane feeding the brake cylinders through the WSP hold and vent valves."""

from __future__ import annotations

import math

import numpy as np

from railbrake import _args
from railbrake.pneumatics import Network
from railbrake.units import BAR
from railbrake.valves.params import load

MM = 1e-3


def load_relay(override=None) -> dict:
    return load("relay", override)


def relay_network(p: dict, t_step: float = 0.05, hold=None, vent=None) -> Network:
    """Control chamber filled at t_step from a reservoir at control_step_bar; the membrane opens the
    inlet (x > 0) from the main reservoir or the exhaust (x < 0). hold / vent: WSP opening schedules
    [(t, 0..1)] (default: hold open, vent closed), applied after the valves' response delay."""
    pa, cd, m = p["ambient_pa"], p["discharge_coefficient"], p["membrane"]
    cyl, wsp = p["cylinder"], p["wsp"]
    area = lambda d_mm: math.pi * (d_mm * MM) ** 2 / 4  # noqa: E731
    net = Network(ambient_pressure=pa)
    net.add_reservoir("supply", pa + p["supply_bar"] * BAR)
    net.add_reservoir("atmosphere", pa)
    net.add_reservoir("control_source", pa + p["control_step_bar"] * BAR)
    net.add_volume("control", p["control_volume_l"] * 1e-3, pa)
    net.add_volume("output", p["output_volume_l"] * 1e-3, pa)
    n = cyl["count"]
    net.add_cylinder("cylinder", n * area(cyl["diameter_mm"]), cyl["stroke_mm"] * MM,
                     n * cyl["dead_volume_l"] * 1e-3, pa, spring_rate=n * cyl["spring_rate"],
                     spring_preload=n * cyl["spring_preload"], piston_mass=n * cyl["piston_mass"])
    table = (np.asarray(m["x_mm"]) * MM, np.asarray(m["volume_cm3"]) * 1e-6)
    travel = m["travel_mm"] * MM
    net.add_body("membrane", m["mass"], [("control", table, 1.0), ("output", table, -1.0)], m["spring_rate"],
                 m["spring_preload"], m["damping"], m["friction"], x_min=-travel, x_max=travel)
    net.add_valve("control_fill", "control_source", "control", area(p["control_orifice_diameter_mm"]), cd,
                  opening=[(t_step, 0.0), (t_step, 1.0)])
    net.add_driven_orifice("inlet", "supply", "output", "membrane", "seat", p["inlet_seat_diameter_mm"] * MM,
                           discharge_coefficient=cd)
    net.add_driven_orifice("exhaust", "output", "atmosphere", "membrane", "seat",
                           p["exhaust_seat_diameter_mm"] * MM, direction=-1.0, discharge_coefficient=cd)
    net.add_valve("wsp_hold", "output", "cylinder", area(wsp["hold_diameter_mm"]), cd,
                  opening=hold, delay=wsp["response_delay_s"])
    net.add_valve("wsp_vent", "cylinder", "atmosphere", area(wsp["vent_diameter_mm"]), cd,
                  opening=vent if vent is not None else [(0.0, 0.0)], delay=wsp["response_delay_s"])
    return net


def relay_step(params=None, t_end: float = 1.5, t_step: float = 0.05, hold=None, vent=None,
               n_points: int = 1001):
    from railbrake.valves.epv import MAX_POINTS, MAX_TIME_S, _schedule
    p = params if isinstance(params, dict) and "control_step_bar" in params else load("relay", params, "params")
    t_end = _args.real("t_end", t_end, 0.0, MAX_TIME_S, low_open=True)
    t_step = _args.real("t_step", t_step, 0.0, t_end)
    hold = None if hold is None else _schedule("hold", hold)
    vent = None if vent is None else _schedule("vent", vent)
    return relay_network(p, t_step, hold, vent).simulate(t_end, n_points=_args.whole("n_points", n_points, 2,
                                                                                        MAX_POINTS))
