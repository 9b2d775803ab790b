"""The model side of each case: small adapters from a case's inputs to railbrake's public API.

Each function takes (inputs, x, case): the case's ``model.inputs`` mapping, the reference's x
column (or None) and the case itself (for files beside it), and returns a ModelOutput with one
model value per reference row, in the case's quantity unit. No law is written here: every value
comes from the C core through railbrake's modules; only unit conversions at the edges.
"""

from __future__ import annotations

import ctypes
import math
from dataclasses import dataclass, field

import numpy as np

from railbrake import adhesion, contact, sizing, units, vehicle
from railbrake.errors import InputError
from railbrake.pneumatics import Network
from railbrake.pneumatics.orifice import orifice_mass_flow

BAR = 1e5


@dataclass
class ModelOutput:
    values: object
    details: dict = field(default_factory=dict)
    curve: dict | None = None  # {"x": [...], "y": [...]} dense model curve for the plot


def _need(inputs: dict, key: str):
    if key not in inputs:
        raise InputError(f"model.inputs: missing {key!r}")
    return inputs[key]


def _x(x, what: str) -> np.ndarray:
    if x is None:
        raise InputError(f"reference.x: this model needs an x column ({what})")
    return np.asarray(x, dtype=float)


# ------------------------------------------------------------------ contact

def hertz(inputs, x, case):
    """Hertz a, b (m) or p0 (Pa) against the normal force x (N); radii rx, ry (m; 'inf' = flat)."""
    rx, ry = (float(inputs.get(k, math.inf)) for k in ("rx", "ry"))
    output = _need(inputs, "output")
    e, nu = float(inputs.get("youngs_modulus", contact.STEEL_YOUNGS_MODULUS)), float(inputs.get("poisson", 0.3))
    values = [getattr(contact.hertz_contact(q, rx, ry, e, nu), output) for q in _x(x, "normal force, N")]
    return ModelOutput(values)


def kalker(inputs, x, case):
    """Kalker's c11, c22 or c23 (inputs.coefficient) against a/b (x) for the given Poisson ratio."""
    nu = float(_need(inputs, "poisson"))
    function = {"c11": contact.kalker_c11, "c22": contact.kalker_c22, "c23": contact.kalker_c23}.get(
        _need(inputs, "coefficient"))
    if function is None:
        raise InputError(f"model.inputs.coefficient = {inputs['coefficient']!r}: c11, c22 or c23")
    ratios = _x(x, "a/b")
    dense = np.geomspace(0.1, 10.0, 60)
    return ModelOutput([function(r, nu) for r in ratios], curve={"x": dense.tolist(), "y": [function(r, nu) for r in dense]})


def _params(inputs) -> contact.PolachParams:
    return contact.PolachParams(**{k: float(v) for k, v in _need(inputs, "params").items()})


def polach_initial_slope_ratio(inputs, x, case):
    """(F/Q)/s at a tiny creep over Kalker's linear slope G a b c11 / Q (dimensionless)."""
    c = contact.default_contact()
    params = _params(inputs)
    ratios = []
    for s in _x(x, "creep"):
        fq = contact.polach_coefficient(s, float(inputs.get("speed", 0.0)), c.normal_force, c, params)
        kalker = c.shear_modulus * c.a * c.b * c.c11 / c.normal_force
        ratios.append(fq / s / kalker)
    return ModelOutput(ratios, {"a_m": c.a, "b_m": c.b, "c11": c.c11})


def polach_coefficient_at(inputs, x, case):
    """F/Q at creep x on the default wheelset."""
    c = contact.default_contact()
    values = contact.polach_coefficient(_x(x, "creep"), float(inputs.get("speed", 0.0)), c.normal_force, c,
                                        _params(inputs))
    return ModelOutput(values)


def polach_on_contact(inputs, x, case):
    """F/(mu0 Q) at creep x on a given contact ellipse (a, b in m), as other codes tabulate it."""
    a, b, q, g, nu = (float(_need(inputs, k)) for k in ("a_m", "b_m", "normal_force", "shear_modulus", "poisson"))
    ellipse = contact.HertzContact(a, b, 0.0, q, 2.0 * g * (1.0 + nu), nu, g)
    params = _params(inputs)
    creep = _x(x, "creep")
    dense = np.geomspace(max(float(creep.min()), 1e-5), float(creep.max()), 80)
    f = lambda s: contact.polach_coefficient(s, float(inputs.get("speed", 0.0)), q, ellipse, params) / params.mu0  # noqa: E731
    return ModelOutput(f(creep), {"c11": ellipse.c11}, {"x": dense.tolist(), "y": f(dense).tolist()})


# ------------------------------------------------------------------ adhesion

def peak_adhesion(inputs, x, case):
    """Peak F/Q of a condition against speed x (km/h): on one axle, or the mean over a car or a train."""
    cond = adhesion.load_condition(_need(inputs, "condition"))
    speeds = _x(x, "speed, km/h")
    if "car" in inputs:
        axles = list(adhesion.car_axles(int(inputs["car"])))
    elif "cars" in inputs:
        axles = list(range(adhesion.AXLES_PER_CAR * int(inputs["cars"])))
    else:
        axles = [int(inputs.get("axle", 0))]

    def mean_peak(v_kmh):
        return float(np.mean([adhesion.peak_adhesion(cond, units.kmh_to_ms(v_kmh), a).coefficient for a in axles]))

    dense = np.linspace(max(min(speeds) - 20.0, 0.0), max(speeds) + 20.0, 41)
    return ModelOutput([mean_peak(v) for v in speeds], {"condition": cond.name, "axles": len(axles)},
                       {"x": dense.tolist(), "y": [mean_peak(v) for v in dense]})


# ------------------------------------------------------------------ pneumatics

def orifice_flow(inputs, x, case):
    """Mass flow (kg/s) through an ISO 6358 orifice against the pressure ratio x = p2/p1."""
    p1, t1 = float(_need(inputs, "p_up_pa")), float(inputs.get("T_up_k", 293.15))
    values = orifice_mass_flow(p1, t1, p1 * _x(x, "p2/p1"), sonic_conductance=float(_need(inputs, "C")),
                               critical_ratio=float(_need(inputs, "b")))
    return ModelOutput(np.atleast_1d(values))


def _tank_network(inputs, filling: bool):
    net = Network()
    p_supply, p0 = float(_need(inputs, "p_supply_pa")), float(_need(inputs, "p0_pa"))
    t = float(inputs.get("T_k", 293.15))
    net.add_reservoir("supply", p_supply, t)
    net.add_volume("tank", float(_need(inputs, "volume_m3")), p0, t)
    a, b = ("supply", "tank") if filling else ("tank", "supply")
    net.add_orifice("orifice", a, b, sonic_conductance=float(_need(inputs, "C")),
                    critical_ratio=float(_need(inputs, "b")))
    return net


def tank_pressure(inputs, x, case):
    """Adiabatic tank pressure (Pa) at times x (s), filled from or emptied into a reservoir."""
    filling = _need(inputs, "mode") == "fill"
    times = _x(x, "time, s")
    result = _tank_network(inputs, filling).simulate(float(times.max()), times=times, rtol=1e-9, atol=1e-11)
    return ModelOutput(result["tank"].p)


# ------------------------------------------------------------------ valves

def solenoid_c_core(inputs, x, case):
    """Force (N) of the solenoid design model (C core, rb_solenoid_eval) on a C-core with linear iron
    at airgaps x (mm): turns, current_a, iron_length_mm, iron_area_mm2, mu_r, pole_diameter_mm,
    working_gaps from the case; no fringing, leakage or parasitic gap (the closed form's assumptions)."""
    from railbrake import _core
    mm, mm2 = 1e-3, 1e-6
    s = _core.Solenoid()
    s.turns, s.resistance_20c = float(_need(inputs, "turns")), 1.0
    s.iron_length, s.iron_area = float(_need(inputs, "iron_length_mm")) * mm, float(_need(inputs, "iron_area_mm2")) * mm2
    mu0 = 4e-7 * math.pi
    s.bh_points, s.bh_h[1], s.bh_b[1] = 2, 1e6, float(_need(inputs, "mu_r")) * mu0 * 1e6   # linear iron
    s.pole_diameter, s.working_gaps = float(_need(inputs, "pole_diameter_mm")) * mm, int(_need(inputs, "working_gaps"))
    amps = float(_need(inputs, "current_a"))
    out = []
    for g in _x(x, "airgap, mm"):
        state = _core.SolenoidState()
        _core.call(_core.rb_solenoid_eval, ctypes.byref(s), g * mm, amps, ctypes.byref(state))
        out.append(state.force)
    return ModelOutput(out)


# ------------------------------------------------------------------ vehicle and braking

def stop_constant(inputs, x, case):
    """Stopping distance (m) from v0 = x (km/h) at a constant deceleration after a response time."""
    a, te = float(_need(inputs, "deceleration")), float(_need(inputs, "response_time"))
    values = [sizing.stopping_distance(units.kmh_to_ms(v), deceleration=a, response_time=te,
                                       dt=float(inputs.get("dt", 0.01))).distance for v in _x(x, "v0, km/h")]
    return ModelOutput(values)


def caliper_force(inputs, x, case):
    """Pad normal force (N) against the gauge cylinder pressure x (bar)."""
    p_atm = float(inputs.get("atmospheric_pressure", 101325.0))
    values = [vehicle.caliper_pad_force(p * BAR + p_atm, float(_need(inputs, "cylinder_area")),
                                        float(_need(inputs, "return_spring")), float(_need(inputs, "lever_ratio")),
                                        float(_need(inputs, "efficiency")), p_atm) for p in _x(x, "bar")]
    return ModelOutput(values)


BUILD_UP_QUANTITIES = ("delay", "build_up", "response", "filling", "jerk")
RESPONSES = ("profile", "simulated")


def _build_up(inputs, train, v: float):
    from railbrake.simulation import response
    return response.simulated(train, units.kmh_to_ms(v), preset=str(_need(inputs, "train")))


def train_stopping_distance(inputs, x, case):
    """Emergency stopping distance (m) of a train preset from v0 = x (km/h), EN 14531 manner;
    inputs.response: "profile" (the profile's ta, tb; default) or "simulated" (the train's own
    build-up measured on the plant, as `railbrake stopping-distance` does by default)."""
    train = vehicle.load_train(_need(inputs, "train"))
    profile = inputs.get("profile", "emergency")
    mode = inputs.get("response", "profile")
    if mode not in RESPONSES:
        raise InputError(f"model.inputs.response = {mode!r}: must be one of {', '.join(RESPONSES)}")
    out, warns = [], []
    for v in _x(x, "v0, km/h"):
        b = _build_up(inputs, train, v) if mode == "simulated" else None
        r = sizing.stopping_distance(units.kmh_to_ms(v), train=train, profile=profile,
                                     delay=b.delay if b else None, build_up=b.build_up if b else None)
        out.append(r.distance)
        warns += r.warnings
    return ModelOutput(out, {"train": train.name, "profile": str(profile), "sizing_warnings": sorted(set(warns))})


def train_build_up(inputs, x, case):
    """EN 14531 build-up of a train preset's emergency brake, measured on the 1 ms plant from
    v0 = x (km/h) (railbrake.simulation.response): inputs.quantity one of delay (ta, s), build_up
    (tb, s), response (te, s), filling (s), jerk (m/s^3); inputs.load: the load case."""
    train = vehicle.load_train(_need(inputs, "train"), inputs.get("load") or True)
    quantity = _need(inputs, "quantity")
    if quantity not in BUILD_UP_QUANTITIES:
        raise InputError(f"model.inputs.quantity = {quantity!r}: must be one of {', '.join(BUILD_UP_QUANTITIES)}")
    values = [getattr(_build_up(inputs, train, v), quantity) for v in _x(x, "v0, km/h")]
    return ModelOutput(values, {"train": train.name, "load": train.load_case})


def _car_of_type(train, kind: str):
    car = next((c for c in train.cars if c.type_name == kind), None)
    if car is None:
        raise InputError(f"model.inputs.car_type = {kind!r}: {train.name} has {sorted({c.type_name for c in train.cars})}")
    return car


def _dyno(inputs):
    """The pad data file's dynamometer (inputs.data, default sintered-cu): its car and conditions."""
    from railbrake import pad_fade
    data = pad_fade.load_data(inputs.get("data", "sintered-cu"))
    return pad_fade, data, *pad_fade.dynamometer(data)


def dynamometer_stop_mean(inputs, x, case):
    """Stop-averaged friction (UIC 541-3's mean) of a preset's pads in dynamometer stops of its disc
    from x (km/h), as the pad data file's dynamometer runs them (the fade by the disc's surface
    temperature included)."""
    _, _, car, conditions = _dyno(inputs)
    stops = [vehicle.dynamometer_stop(car, units.kmh_to_ms(v), **conditions) for v in _x(x, "speed, km/h")]
    return ModelOutput([s.mean_friction for s in stops], {"car": car.type_name, "surface_peak_c": [
        round(s.max_surface_temperature - vehicle.ZERO_CELSIUS, 1) for s in stops]})


def dynamometer_recession(inputs, x, case):
    """Fall of the stop-averaged friction between dynamometer stops from inputs.speeds_kmh = [from, to]."""
    _, _, car, conditions = _dyno(inputs)
    low, high = (vehicle.dynamometer_stop(car, units.kmh_to_ms(float(v)), **conditions).mean_friction
                 for v in _need(inputs, "speeds_kmh"))
    return ModelOutput([low - high], {"mean_from": low, "mean_to": high})


def dynamometer_cross_fit(inputs, x, case):
    """Stop-averaged friction from x (km/h) of the preset's pads with their fade fitted on other data
    than the case's reference: the onset at the surface peak of a stop from inputs.onset_kmh, the
    rate from the ratio inputs.ratio of the stop averages between inputs.ratio_kmh = [from, to]
    (another pad), the level from inputs.level = {speed_kmh, mean}."""
    pad_fade, _, car, conditions = _dyno(inputs)
    level, (low, high) = _need(inputs, "level"), _need(inputs, "ratio_kmh")
    fit = pad_fade.fit(car, conditions, onset_speed=units.kmh_to_ms(float(_need(inputs, "onset_kmh"))),
                       level_speed=units.kmh_to_ms(float(level["speed_kmh"])), level_mean=float(level["mean"]),
                       ratio_speeds=(units.kmh_to_ms(float(low)), units.kmh_to_ms(float(high))),
                       rate_ratio=float(_need(inputs, "ratio")))
    pad = pad_fade.pad_with(car, fit.shift, fit.onset, fit.rate)
    speeds = _x(x, "speed, km/h")
    means = [vehicle.dynamometer_stop(car, units.kmh_to_ms(v), pad=pad, **conditions).mean_friction for v in speeds]
    details = {"fade_onset_c": round(fit.onset - vehicle.ZERO_CELSIUS, 1), "fade_rate_per_K": fit.rate,
               "table_shift": fit.shift}
    return ModelOutput(means, details | _needed_fade(pad_fade, car, conditions, fit, inputs, speeds[-1], case))


def _needed_fade(pad_fade, car, conditions, fit, inputs, speed_kmh, case) -> dict:
    """What the fit would have had to find for the reference at speed_kmh within the case's tolerance
    (the same onset and level): the fading rates and the ratio they give between inputs.ratio_kmh, to
    set against the other pad's inputs.ratio. A diagnosis of a miss, not a fit on the reference."""
    reference = float(case.data[case.columns["value"]][-1])
    tol = case.tolerance.value * (abs(reference) / 100.0 if case.tolerance.unit == "%" else 1.0)
    level = inputs["level"]
    low, high = (units.kmh_to_ms(float(v)) for v in inputs["ratio_kmh"])
    try:
        rates = [pad_fade.rate_for(car, conditions, onset=fit.onset, level_speed=units.kmh_to_ms(float(level["speed_kmh"])),
                                   level_mean=float(level["mean"]), speed=units.kmh_to_ms(float(speed_kmh)), mean=m)
                 for m in (reference + tol, reference - tol)]
    except ValueError:   # no fading rate within the bounds reaches the reference: nothing to diagnose
        return {"rate_needed_per_K": None}
    return {"rate_needed_per_K": rates,
            "ratio_needed": [pad_fade.stop_ratio(car, conditions, fit.onset, r, low, high) for r in rates]}


def disc_temperature(inputs, x, case):
    """Peak disc temperature (°C) in an emergency stop of a train preset on dry rail from x (km/h):
    inputs.which = surface (the friction surface) or mean (the disc's mean), over every disc."""
    from railbrake import simulation
    which = _need(inputs, "which")
    key = {"surface": "max_disc_surface_temperature_c", "mean": "max_disc_temperature_c"}.get(which)
    if key is None:
        raise InputError(f"model.inputs.which = {which!r}: must be surface or mean")
    train = _need(inputs, "train")
    values, details = [], {}
    for v in _x(x, "v0, km/h"):
        scenario = simulation.emergency_scenario(train, units.kmh_to_ms(v), inputs.get("condition", "dry-medium"))
        kpis = simulation.run(scenario, record=False).kpis
        values.append(kpis[key])
        details[f"{v:g} km/h"] = {"surface_c": round(kpis["max_disc_surface_temperature_c"], 1),
                                  "mean_c": round(kpis["max_disc_temperature_c"], 1),
                                  "mean_pad_friction": round(kpis["mean_pad_friction"], 4)}
    return ModelOutput(values, {"train": train} | details)


def ed_brake_force(inputs, x, case):
    """Whole-train ED brake force (kN) of a train preset at speed x (km/h)."""
    train = vehicle.load_train(_need(inputs, "train"))
    return ModelOutput(np.atleast_1d(train.ed_brake_force(units.kmh_to_ms(_x(x, "km/h")))) / 1e3)


def running_resistance(inputs, x, case):
    """Whole-train running resistance (kN) of a train preset at speed x (km/h)."""
    train = vehicle.load_train(_need(inputs, "train"))
    return ModelOutput(np.atleast_1d(train.running_resistance(units.kmh_to_ms(_x(x, "km/h")))) / 1e3)


# ------------------------------------------------------------------ real-time plant and detailed model

def _observed_order(values: list[float], ratio: float) -> float:
    """Order p from three solutions at steps h, h/r, h/r^2: p = log(|e1| / |e2|) / log(r)."""
    e1, e2 = values[0] - values[1], values[1] - values[2]
    if e2 == 0.0 or e1 == 0.0:
        raise InputError(f"solutions {values}: differences vanish, the order cannot be observed")
    return math.log(abs(e1 / e2)) / math.log(ratio)


def plant_order(inputs, x, case):
    """Observed order of convergence of the real-time plant in its step (one value)."""
    from railbrake.simulation import run
    scenario = case.folder / _need(inputs, "scenario")
    steps = [float(s) * 1e-3 for s in _need(inputs, "steps_ms")]
    quantity = inputs.get("quantity", "stopping_distance_m")
    values = [run(scenario, cars=int(inputs.get("cars", 1)), wsp=bool(inputs.get("wsp", False)), dt=dt,
                  substeps=int(inputs.get("substeps", 1)), record=False).kpis[quantity] for dt in steps]
    ratio = steps[0] / steps[1]
    order = _observed_order(values, ratio)
    # Richardson: the error left at the middle step, from the observed order.
    error = (values[1] - values[2]) * ratio ** order / (ratio ** order - 1.0)
    return ModelOutput([order], {"steps_ms": [s * 1e3 for s in steps], quantity: values,
                                 f"error_at_{steps[1] * 1e3:g}_ms": error})


def detailed_order(inputs, x, case):
    """Observed order of the detailed model in its mechanics step (air solver held tight)."""
    from railbrake.simulation.detailed import load_valves, run_detailed
    scenario = case.folder / _need(inputs, "scenario")
    steps = [float(s) * 1e-3 for s in _need(inputs, "steps_ms")]
    solver = {"rtol": float(inputs.get("rtol", 1e-6)), "atol": float(inputs.get("atol", 1e-8))}
    values = [run_detailed(scenario, cars=int(inputs.get("cars", 1)),
                           valves=load_valves({"solver": {**solver, "mechanics_dt_s": dt}})).kpis["stopping_distance_m"]
              for dt in steps]
    return ModelOutput([_observed_order(values, steps[0] / steps[1])],
                       {"steps_ms": [s * 1e3 for s in steps], "stopping_distance_m": values})


def stop_ramp(inputs, x, case):
    """Stopping distance (m) from v0 = x (km/h): delay ta, then a linear build-up over tb to a
    constant deceleration (EN 14531's ramp, not its equivalent step)."""
    a, ta, tb = (float(_need(inputs, k)) for k in ("deceleration", "delay", "build_up"))
    values = [sizing.stopping_distance(units.kmh_to_ms(v), deceleration=a, delay=ta, build_up=tb,
                                       equivalent_response=False, dt=float(inputs.get("dt", 0.001))).distance
              for v in _x(x, "v0, km/h")]
    return ModelOutput(values)


def _sanders(units: list, calibration: dict) -> dict | None:
    """The train file's sanders block for a configuration's units (None: no sanders)."""
    if not units:
        return None
    return {"units": units, "sand_reference_kg_m": float(_need(calibration, "sand_reference_kg_m")),
            "sand_entrained": float(_need(calibration, "sand_entrained")),
            "sand_retention": float(_need(calibration, "sand_retention")),
            "source": str(calibration.get("source", ""))}


def sander_stopping_distance(inputs, x, case):
    """Stopping distance (m) of a scenario (inputs.scenario, relative to the case folder) with the
    sanders of configuration x (inputs.configurations: {x: list of train-file sander units}; an
    empty list: no sanders), the sand's conditioning strength from inputs.calibration (a YAML file
    with sand_reference_kg_m, relative to the case folder)."""
    import yaml
    from railbrake.resolve import resolve
    from railbrake.simulation import run
    from railbrake import config
    scenario = case.folder / _need(inputs, "scenario")
    calibration = yaml.safe_load(config.read_text(case.folder / _need(inputs, "calibration")))
    configurations = {int(k): v for k, v in _need(inputs, "configurations").items()}
    values, details = [], {}
    for c in _x(x, "configuration number").astype(int):
        if c not in configurations:
            raise InputError(f"model.inputs.configurations: no configuration {c} (given: "
                             f"{', '.join(map(str, sorted(configurations)))})")
        k = run(resolve(str(scenario), sets={"train.sanders": _sanders(configurations[c], calibration)}),
                record=False).kpis
        if not k["stopped"]:
            raise InputError(f"configuration {c}: the train did not stop within the scenario's max_time")
        values.append(k["stopping_distance_m"])
        details[f"configuration {c}"] = {key: k[key] for key in ("stopping_distance_m", "adhesion_utilisation",
                                                                   "max_slip", "wheel_lock_events")}
    return ModelOutput(values, {"sand_reference_kg_m": calibration["sand_reference_kg_m"], **details})


# ------------------------------------------------------------------ ETCS braking model

def kdry_equal_units(inputs, x, case):
    """Kdry_rst before rounding at the confidence levels M_NVEBCL = x of equal brake units, each
    lost with a probability per demand, with a friction factor drawn per unit: the failure states
    by symmetry (railbrake.etcs.equal_units), within each a Latin-hypercube sample of the units'
    factors, the ratio the mean over the units of factor x (unit not lost)."""
    from scipy.stats import norm, qmc
    from railbrake import etcs
    n, p = int(_need(inputs, "units")), float(_need(inputs, "loss_probability"))
    mean, sd = float(_need(inputs, "friction_mean")), float(_need(inputs, "friction_sd"))
    samples = int(inputs.get("samples", 20000))
    rng = np.random.default_rng(int(inputs.get("seed", 0)))
    states = []
    for s in etcs.equal_units(n, p, floor=1e-3 * (1.0 - etcs.EBCL[-1])):
        friction = mean + sd * norm.ppf(qmc.LatinHypercube(n - s.lost, seed=rng).random(samples)) if s.lost < n \
            else np.zeros((samples, 0))
        states.append(etcs.State.of(s.probability, friction.sum(axis=1) / n, f"{s.lost} lost"))
    levels = _x(x, "M_NVEBCL").astype(int)
    return ModelOutput([etcs.k_dry(states, etcs.ebcl(int(i))) for i in levels],
                       {"states": len(states), "samples per state": samples})


def etcs_curve_distance(inputs, x, case):
    """Distance (m) to the SvL of an ETCS braking curve (inputs.curve: EBD, EBI, ...) from speed x
    (km/h), for an OSRD rolling stock's EtcsBrakeParams (inputs.rolling_stock, a JSON file beside
    the case) on a track (inputs.track: a preset or a file beside the case), national values
    inputs.national (a preset or a file beside the case; default: the shipped defaults). The curve is exact in V^2 between its points."""
    import json
    from railbrake.etcs import curves, national, osrd
    path = case.folder / _need(inputs, "rolling_stock")
    doc = json.loads(path.read_text())
    params = osrd.params_of(doc, str(path))
    if isinstance(doc.get("max_speed"), bool) or not isinstance(doc.get("max_speed"), (int, float)):
        raise InputError(f"{path}: max_speed = {doc.get('max_speed')!r}: the rolling stock's maximum speed, m/s "
                         "(a number, as OSRD's rolling stock has it)")
    model, service = osrd.from_osrd(params, float(doc["max_speed"]), doc.get("name", str(path)))
    track = str(_need(inputs, "track"))
    track = national.load_track(case.folder / track if track.endswith(".yaml") else track)
    values = str(inputs.get("national", "default"))
    values = national.load_national(case.folder / values if values.endswith(".yaml") else values)
    result = curves.compute(model, service, track, values)
    points = np.asarray(result["curves"][_need(inputs, "curve")])[::-1]   # lowest speed first
    v = _x(x, "speed, km/h")
    distance = result["svl_m"] - np.interp(v ** 2, points[:, 1] ** 2, points[:, 0])
    return ModelOutput(distance, {"T_be s": result["times_s"]["T_be"], "T_traction s": result["times_s"]["T_traction"]},
                       {"x": list(points[:, 1]), "y": list(result["svl_m"] - points[:, 0])})


REGISTRY = {f.__name__: f for f in (detailed_order, stop_ramp, kdry_equal_units, etcs_curve_distance,
    hertz, kalker, polach_on_contact, polach_initial_slope_ratio, polach_coefficient_at, peak_adhesion, orifice_flow,
    tank_pressure, stop_constant, caliper_force, train_stopping_distance, train_build_up, solenoid_c_core, ed_brake_force,
    running_resistance, plant_order, sander_stopping_distance, dynamometer_stop_mean, dynamometer_recession,
    dynamometer_cross_fit, disc_temperature)}
