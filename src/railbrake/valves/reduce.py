"""Reduction of the valve designs to the real-time plant's parameters (docs/pneumatics.md,
"From the design to the plant").

The plant (rb_plant.h) models the EP valve as a first-order lag of the pressure demand (ep_tau)
and inlet/exhaust ports of area ep_area opening in proportion to the error between the lagged
demand and the control pressure, fully at ep_band; the relay valve the same without the lag
(relay_band, relay_supply_area, relay_exhaust_area); the WSP valves as ports switching after a
delay; the EP output is held at most ep_supply_margin below the supply. The reduction:

1. static, from the design's geometry: port areas pi d^2 / 4 of the seats (the seat's curtain
   pi d x reaches the port at x = d / 4), bands = the spring force at that opening (plus the lap)
   over the pressure face (A_eff of the membrane at mid-stroke), WSP ports and delays as designed;
   the EP supply margin = the EP piston's preload over its area (the piston balances the nozzle
   chamber, fed from the supply, against the control pressure and the preload);
2. fitted, for the EP valve: tau, band and area by least squares to the detailed valve's
   (valves.epv_network, chambers with the detailed train model's wall heat exchange)
   control-pressure step responses over the operating range, into the train's control volume. The
   reduced model runs in the C core (rb_valve_reduced.h: the plant's law at a step well below the
   plant's); its difference to the detailed responses is reported;
3. checked, for the relay valve: the reduced relay against the detailed relay's output chamber for
   control-pressure steps (relay_check);
4. the valves' air: the EP pilot stage's bleed through its feed orifice (ep_bleed_area, the design's
   orifice), and the relay membrane's stroke: its lag (relay_tau = damping / spring rate), its stops
   (relay_travel = travel / full-opening stroke) and the volume it sweeps in the control chamber at
   the full-opening stroke (relay_sweep, from the membrane's V(x)), which the EP valve fills and
   exhausts as the membrane strokes; checked by the air one car lets out over WSP cycles against the
   detailed car network's (air_check).
"""

from __future__ import annotations

import copy
import ctypes
import math
from datetime import date
from importlib import resources

import numpy as np
import yaml
from scipy.optimize import least_squares

from railbrake import _core
from railbrake.pneumatics.orifice import CRITICAL_RATIO_NOZZLE
from railbrake.units import BAR
from railbrake.valves.epv import _params, epv_characteristic, epv_step
from railbrake.valves.relay import load_relay, relay_step

MM, T_AIR = 1e-3, 293.15
TARGETS_BAR = ((0.0, 1.0), (0.0, 2.0), (0.0, 3.0), (0.0, 3.8), (0.0, 4.3), (3.8, 2.0), (2.0, 0.0), (3.8, 0.0))
T_STEP, T_END, DT_REDUCED = 0.05, 1.5, 1e-4


def _seat_area(d_mm: float) -> float:
    return math.pi * (d_mm * MM) ** 2 / 4


def static_reduction(epv=None, relay=None) -> dict:
    """Reduced parameters from the designs' geometry and springs alone (SI)."""
    e, r = _params(epv), relay or load_relay()
    k, m = e["piston"], r["membrane"]
    piston = math.pi * (k["diameter_mm"] * MM) ** 2 / 4
    full = (e["inlet_seat_diameter_mm"] / 4 + e["seat_lap_mm"]) * MM
    membrane = _core.Membrane()
    x, v = _core.as_double_array(np.array(m["x_mm"]) * MM), _core.as_double_array(np.array(m["volume_cm3"]) * 1e-6)
    _core.call(_core.rb_membrane_init, ctypes.byref(membrane), _core.ptr(x), _core.ptr(v), len(x))
    vol, a_eff = ctypes.c_double(), ctypes.c_double()
    _core.rb_membrane_eval(ctypes.byref(membrane), 0.0, ctypes.byref(vol), ctypes.byref(a_eff))
    stroke = r["inlet_seat_diameter_mm"] / 4 * MM   # the membrane's stroke that opens the inlet fully
    swept = ctypes.c_double()
    _core.rb_membrane_eval(ctypes.byref(membrane), stroke, ctypes.byref(swept), ctypes.byref(ctypes.c_double()))
    return {"ep_area": _seat_area(e["inlet_seat_diameter_mm"]),
            "ep_band": k["spring_rate"] * full / piston,
            "ep_supply_margin": k["spring_preload"] / piston,
            "ep_bleed_area": _seat_area(e["pilot_orifice_diameter_mm"]),
            "relay_supply_area": _seat_area(r["inlet_seat_diameter_mm"]),
            "relay_exhaust_area": _seat_area(r["exhaust_seat_diameter_mm"]),
            "relay_band": m["spring_rate"] * stroke / a_eff.value,
            "relay_tau": m["damping"] / m["spring_rate"],
            "relay_sweep": swept.value - vol.value,
            "relay_travel": m["travel_mm"] * MM / stroke,
            "hold_area": _seat_area(r["wsp"]["hold_diameter_mm"]),
            "vent_area": _seat_area(r["wsp"]["vent_diameter_mm"]),
            "valve_delay": r["wsp"]["response_delay_s"]}


def _currents(p: dict, targets_bar) -> dict:
    """Current (A) holding each pressure, from the quasi-static characteristic (rising branch for
    a rise, falling branch for a fall)."""
    c = epv_characteristic(p)
    up = np.maximum.accumulate(c.pressure_up)
    down = np.maximum.accumulate(c.pressure_down[::-1])
    i_up = lambda bar: float(np.interp(bar, up + 1e-9 * np.arange(up.size), c.current_up))  # noqa: E731
    i_down = lambda bar: float(np.interp(bar, down + 1e-9 * np.arange(down.size), c.current_down[::-1]))  # noqa: E731
    return {(a, b): (i_up(a) if a > 0 else 0.0, (i_up(b) if b > a else i_down(b)) if b > 0 else 0.0)
            for a, b in targets_bar}


def detailed_thermal_time() -> float:
    """The wall heat-exchange time of the detailed train model's volumes (s)."""
    settings = yaml.safe_load((resources.files("railbrake") / "data" / "detailed" / "valves.yaml").read_text())
    return settings["air"]["thermal_time_s"]


def detailed_steps(epv=None, targets_bar=TARGETS_BAR) -> dict:
    """The detailed EP valve's control-pressure responses (Pa abs on a common time base) to the
    current steps that move it between each pair of pressures of targets_bar, its chambers
    exchanging heat with the wall as in the detailed train model."""
    p, thermal_time = _params(epv), detailed_thermal_time()
    time = np.arange(0.0, T_END + 1e-12, 0.005)
    out = {}
    for (a, b), (i0, i1) in _currents(p, targets_bar).items():
        res = epv_step(p, current=i1, start_current=i0, t_end=T_END, t_step=T_STEP, n_points=time.size,
                       thermal_time=thermal_time)
        out[(a, b)] = res["control"].p
    return {"time": time, "responses": out, "supply": p["ambient_pa"] + p["supply_bar"] * BAR,
            "volume": p["control_volume_l"] * 1e-3, "ambient": p["ambient_pa"], "cd": p["discharge_coefficient"]}


def reduced_steps(steps: dict, tau: float, band: float, area: float) -> np.ndarray:
    """The reduced EP model's responses [step, time] (C core, rb_valve_reduced.h) to the demand
    steps (each demand = where the detailed valve started and settled), same time base."""
    det = np.array(list(steps["responses"].values()))
    start, final = _core.as_double_array(det[:, 0]), _core.as_double_array(det[:, -1])
    v = _core.ReducedValve(steps["supply"], steps["ambient"], steps["volume"], T_AIR, steps["cd"],
                           CRITICAL_RATIO_NOZZLE, tau, band, area)
    t = _core.as_double_array(steps["time"])
    out = np.zeros(det.shape)
    _core.call(_core.rb_reduced_valve_steps, ctypes.byref(v), _core.ptr(start), _core.ptr(final), len(start),
               T_STEP, _core.ptr(t), t.size, DT_REDUCED, _core.ptr(out))
    return out


def fit_epv(epv=None, steps: dict | None = None) -> dict:
    """EP valve's tau, band, area fitted to the detailed step responses; starts from the static
    reduction. Returns the values (SI) and the RMS / largest difference (bar) after the fit."""
    steps = steps or detailed_steps(epv)
    det = np.array(list(steps["responses"].values()))
    first = static_reduction(epv)
    x0 = np.log([0.05, first["ep_band"], first["ep_area"]])

    def residual(x):
        return ((reduced_steps(steps, *np.exp(x)) - det) / BAR).ravel()

    fit = least_squares(residual, x0, x_scale=1.0, diff_step=1e-3, max_nfev=60,
                        bounds=(np.log([1e-3, 1e2, 1e-8]), np.log([1.0, 1e6, 1e-4])))
    tau, band, area = np.exp(fit.x)
    r = residual(fit.x)
    return {"ep_tau": float(tau), "ep_band": float(band), "ep_area": float(area),
            "rms_bar": float(np.sqrt(np.mean(r ** 2))), "max_bar": float(np.max(np.abs(r))),
            "steps_bar": [list(k) for k in steps["responses"]], "static": first, "steps": steps,
            "reduced": reduced_steps(steps, tau, band, area)}


RELAY_TARGETS_BAR = (1.0, 2.0, 3.8)
RELAY_STEP_ORIFICE_MM = 10.0   # control fill of the relay check: a near step of the control pressure


def relay_check(relay=None, params: dict | None = None) -> dict:
    """The relay valve's reduced model (no lag, relay_band, relay ports) against the detailed relay
    (valves.relay_network, WSP hold valve shut: the output chamber alone) for control-pressure
    steps to RELAY_TARGETS_BAR: RMS and largest difference of the output pressure (bar)."""
    r = copy.deepcopy(relay or load_relay())
    params = params or static_reduction(relay=r)
    pa = r["ambient_pa"]
    time = np.arange(0.0, T_END + 1e-12, 0.005)
    det = []
    for bar in RELAY_TARGETS_BAR:
        r["control_step_bar"], r["control_orifice_diameter_mm"] = bar, RELAY_STEP_ORIFICE_MM
        res = relay_step(r, t_end=T_END, t_step=T_STEP, hold=[(0.0, 0.0)], n_points=time.size)
        det.append(res["output"].p)
    det = np.array(det)
    steps = {"time": time, "responses": dict(zip(RELAY_TARGETS_BAR, det)), "supply": pa + r["supply_bar"] * BAR,
             "volume": r["output_volume_l"] * 1e-3, "ambient": pa, "cd": r["discharge_coefficient"]}
    reduced = reduced_steps(steps, 0.0, params["relay_band"], params["relay_supply_area"])
    diff = (reduced - det) / BAR
    return {"rms_bar": float(np.sqrt(np.mean(diff ** 2))), "max_bar": float(np.max(np.abs(diff))),
            "final_bar": float(np.max(np.abs(diff[:, -1]))), "steps_bar": list(RELAY_TARGETS_BAR)}


# The WSP cycles of the air check: vent 80 ms (the mean vent pulse of the detailed model's
# emergency-300-heavy-rain stop, 82 ms), hold 70 ms, reapply 150 ms, and two others about it; every
# axle of the car at once, at the emergency cylinder pressure of the presets.
AIR_CYCLES_S = ((0.08, 0.07, 0.15), (0.05, 0.05, 0.10), (0.15, 0.10, 0.30))
AIR_TARGET_BAR, AIR_SETTLE_S, AIR_CYCLES = 3.6, 3.0, 20
AIR_SCENARIO = "emergency-250-dry"   # its train's first car


def _air_plant(params: dict):
    """The scenario's one-car plant with the reduced parameters `params` (SI, plant names)."""
    from railbrake.simulation.detailed import load, plant_params
    plant = plant_params(load(AIR_SCENARIO), 1)
    for name, value in params.items():
        if name in FRAGMENT_KEYS:
            setattr(plant.car[0], name, value)
    return plant


def detailed_valve_air(cycle, target_bar: float = AIR_TARGET_BAR) -> dict:
    """The detailed car network's air (kg) over AIR_CYCLES WSP cycles `cycle` (vent, hold, reapply s)
    at the EP current of target_bar: through the EP feed orifice (its bleed), the EP and relay
    exhausts, the relay inlet and the cylinder vents; `valves`: what the EP and relay valves let out."""
    from railbrake.simulation.detailed import detailed_params, epv_current, load, plant_params
    plant = plant_params(load(AIR_SCENARIO), 1)
    current = epv_current(plant.atmosphere + target_bar * BAR, scenario=AIR_SCENARIO)
    air, phase = (ctypes.c_double * 5)(), (ctypes.c_double * 3)(*cycle)
    _core.call(_core.rb_detailed_valve_air, ctypes.byref(plant), ctypes.byref(detailed_params()), current,
               AIR_SETTLE_S, phase, AIR_CYCLES, air)
    out = dict(zip(("bleed", "ep_exhaust", "relay_exhaust", "relay_inlet", "cylinder_vents"), air))
    out["valves"] = out["bleed"] + out["ep_exhaust"] + out["relay_exhaust"]
    return out


def plant_valve_air(params: dict, cycle, target_bar: float = AIR_TARGET_BAR) -> dict:
    """The air (kg) one car of the plant with `params` lets out over the same cycles: `valves` (EP and
    relay: bleed and exhausts) and `cylinder_vents`."""
    plant = _air_plant(params)
    air, phase = (ctypes.c_double * 2)(), (ctypes.c_double * 3)(*cycle)
    _core.call(_core.rb_plant_valve_air, ctypes.byref(plant), plant.atmosphere + target_bar * BAR, AIR_SETTLE_S,
               phase, AIR_CYCLES, air)
    return {"valves": air[0], "cylinder_vents": air[1]}


def air_check(params: dict, cycles=AIR_CYCLES_S) -> list[dict]:
    """The valves' air of the plant with `params` against the detailed car network's (the detailed
    train model's, with its packaged designs), per WSP cycle (g over AIR_CYCLES cycles): what the EP
    and relay valves let out, and the cylinders' vents."""
    rows = []
    for cycle in cycles:
        det, rt = detailed_valve_air(cycle), plant_valve_air(params, cycle)
        rows.append({"cycle_s": list(cycle), "detailed_g": {k: 1e3 * v for k, v in det.items()},
                     "plant_g": {k: 1e3 * v for k, v in rt.items()}})
    return rows


def reduce(epv=None, relay=None) -> dict:
    """All the plant's valve parameters: EP fitted, relay and WSP static (SI), with the fit's figures,
    the relay check and the air check."""
    fit = fit_epv(epv)
    params = {**fit["static"], "ep_tau": fit["ep_tau"], "ep_band": fit["ep_band"], "ep_area": fit["ep_area"]}
    static = static_reduction(epv, relay)
    params = {**params, "ep_supply_margin": static["ep_supply_margin"], "ep_bleed_area": static["ep_bleed_area"],
              **{k: v for k, v in static.items() if not k.startswith("ep_")}}
    return {"params": params, "fit": fit, "relay": relay_check(relay, params), "air": air_check(params)}


# train-file fragment (the car type's keys of railbrake.train/2): plant parameter -> (key, factor from SI)
FRAGMENT_KEYS = {"ep_tau": ("ep_valve.response_s", 1.0), "ep_band": ("ep_valve.band_bar", 1 / BAR),
                 "ep_area": ("ep_valve.port_area_mm2", 1e6),
                 "ep_supply_margin": ("ep_valve.supply_margin_bar", 1 / BAR),
                 "ep_bleed_area": ("ep_valve.bleed_area_mm2", 1e6),
                 "relay_band": ("relay_valve.band_bar", 1 / BAR),
                 "relay_tau": ("relay_valve.response_s", 1.0),
                 "relay_sweep": ("relay_valve.sweep_cm3", 1e6), "relay_travel": ("relay_valve.travel", 1.0),
                 "relay_supply_area": ("relay_valve.supply_area_mm2", 1e6),
                 "relay_exhaust_area": ("relay_valve.exhaust_area_mm2", 1e6),
                 "hold_area": ("wsp_valves.hold_area_mm2", 1e6), "vent_area": ("wsp_valves.vent_area_mm2", 1e6),
                 "valve_delay": ("wsp_valves.response_s", 1.0)}


def _cycle_ms(air: dict) -> str:
    vent, hold, reapply = (1e3 * t for t in air["cycle_s"])
    return f"vent {vent:.0f} / hold {hold:.0f} / reapply {reapply:.0f} ms"


def fragment(result: dict) -> str:
    """The reduced parameters as a YAML fragment for a car type of a train file."""
    p, f = result["params"], result["fit"]
    groups: dict[str, list[str]] = {}
    for name, (key, factor) in FRAGMENT_KEYS.items():
        group, leaf = key.split(".")
        groups.setdefault(group, []).append(f"    {leaf}: {p[name] * factor:.6g}")
    lines = [f"# Reduced valve parameters of the real-time plant, derived {date.today().isoformat()} by",
             "# 'railbrake valve epv --reduce' from data/valves/epv.yaml and relay.yaml (docs/pneumatics.md):",
             f"# EP valve fitted to {len(f['steps_bar'])} detailed step responses (RMS {f['rms_bar']:.3f} bar, "
             f"largest {f['max_bar']:.3f} bar); relay and WSP from the design's geometry"
             + (f" (relay check: RMS {result['relay']['rms_bar']:.3f} bar, largest {result['relay']['max_bar']:.3f} "
                "bar, output chamber alone)" if "relay" in result else "")
             + (f"; valves' air over WSP cycles of {_cycle_ms(result['air'][0])}: plant "
                f"{result['air'][0]['plant_g']['valves']:.2f} g, detailed {result['air'][0]['detailed_g']['valves']:.2f} g."
                if "air" in result else ".")]
    for group, rows in groups.items():
        lines += [f"  {group}:", *rows]
    return "\n".join(lines) + "\n"


_COMMENTS = {"ep_tau": "s, EP valve demand lag (fitted)", "ep_band": "Pa, error at full opening (fitted)",
             "ep_area": "m^2, EP ports (fitted)", "ep_supply_margin": "Pa, EP piston preload / area",
             "ep_bleed_area": "m^2, EP pilot feed orifice pi d^2/4",
             "relay_band": "Pa, membrane spring x d/4 / A_eff(0)",
             "relay_tau": "s, relay membrane damping / spring rate",
             "relay_sweep": "m^3, membrane V(d/4) - V(0)", "relay_travel": "membrane travel / (d/4)",
             "relay_supply_area": "m^2, seat pi d^2/4", "relay_exhaust_area": "m^2, seat pi d^2/4",
             "hold_area": "m^2, WSP hold port", "vent_area": "m^2, WSP vent port",
             "valve_delay": "s, WSP valve response delay"}


def reduced_yaml(result: dict) -> str:
    """data/valves/reduced.yaml: the reduced parameters (SI, plant names) with their provenance."""
    p, f = result["params"], result["fit"]
    lines = ["# Reduced valve parameters of the real-time plant (rb_plant_car), derived from the valve designs",
             "# data/valves/epv.yaml (+ solenoid.yaml) and relay.yaml by",
             "# 'railbrake valve epv --reduce --write src/railbrake/data/valves/reduced.yaml'",
             "# (src/railbrake/valves/reduce.py, docs/pneumatics.md 'From the design to the plant'). Do not",
             "# edit by hand: rerun the reduction after changing a design and copy the values into the train",
             "# files' car types (the fragment the command prints). SI units.",
             f'source: "Derived from the railbrake valve designs [T]: EP valve fitted to {len(f["steps_bar"])} step '
             f'responses of the detailed valve (RMS {f["rms_bar"]:.3f} bar, largest {f["max_bar"]:.3f} bar); relay '
             'and WSP valves from the design\'s geometry"',
             "steps_bar: " + str(f["steps_bar"]),
             f"static_ep: {{ep_band: {f['static']['ep_band']:.4g}, ep_area: {f['static']['ep_area']:.4g}}}"
             "   # geometric start of the fit",
             "plant:"]
    lines += [f"  {k}: {p[k]:.10g}".ljust(36) + f" # {c}" for k, c in _COMMENTS.items()]
    return "\n".join(lines) + "\n"
