"""The brake's build-up measured on a simulated emergency stop, by EN 14531-1's definitions
(data/response/en14531.yaml, with its sources): delay time ta, build-up time tb, equivalent response
time te = ta + tb/2, the cylinders' filling time and the largest jerk.

The force is the train's total brake force at the rails (every axle's friction brake by the C law
at its cylinder pressure and wheel speed, plus the ED brake achieved), as TSI LOC&PAS evaluates the
emergency brake's response on the total braking force.
"""

from __future__ import annotations

import contextlib
import ctypes
import warnings
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np
import yaml

from railbrake import _core
from railbrake._args import choice, flag, instance, name_or_path, real
from railbrake.errors import InputError
from railbrake.results.record import HEALTHY_SHORTFALL   # Result.meta key of healthy_shortfall
from railbrake.results.scripting import Result
from railbrake.scenario import Scenario
from railbrake.units import ms_to_kmh
from railbrake.vehicle import LOAD_CASES, load_train


@cache
def settings() -> dict:
    """The measurement's thresholds and window (data/response/en14531.yaml)."""
    return yaml.safe_load((resources.files("railbrake") / "data" / "response" / "en14531.yaml").read_text())


@dataclass(frozen=True)
class BuildUp:
    delay: float      # s, ta
    build_up: float   # s, tb
    filling: float    # s, mean cylinder pressure to the filling fraction of its final value
    jerk: float       # m/s^3, the largest mean rise of the brake's deceleration over jerk_interval_s
    force: float      # N, the force the first step demands (the 100 % of ta and tb)

    @property
    def response(self) -> float:
        """EN 14531 equivalent response time te = ta + tb/2 (s)."""
        return self.delay + 0.5 * self.build_up


def brake_force(result, train) -> np.ndarray:
    """N at each sample of `result` (a run of `train`): every axle's friction brake at the rails
    (rb_axle_brake_torque at its cylinder pressure and wheel speed, over the wheel radius) plus
    each car's ED brake force."""
    total = np.zeros(result.time.size)
    for c, car in enumerate(train.cars[:result.cars]):
        brake, radius = ctypes.byref(car.c.brake), car.c.wheelset.wheel_radius
        for a in range(_core.AXLES_PER_CAR):
            name = f"c{c + 1}a{a + 1}"
            pressure, speed = result.outputs[f"cylinder_{name}"], result.outputs[f"wheel_speed_{name}"]
            total += [_core.rb_axle_brake_torque(brake, float(p), float(v)) / radius
                      for p, v in zip(pressure, speed)]
        total += np.abs(result.outputs[f"ed_force_c{c + 1}"])
    return total


def _crossing(t: np.ndarray, y: np.ndarray, level: float, what: str = "the brake force") -> float:
    """First time y reaches level, interpolated linearly between samples."""
    i = int(np.argmax(y >= level))
    if y[i] < level:
        raise InputError(f"{what} never reaches {level:.4g} within the window")
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (level - y[i - 1]) * (t[i] - t[i - 1]) / (y[i] - y[i - 1]))


def demanded_force(train, speed: float, step: str = "emergency", fraction: float = 1.0,
                   cars: int | None = None) -> float:
    """N: the total brake force (of a train of `cars` cars, default: as it is) (ED plus friction, at the rails) that the train's brake step
    demands at `speed` (m/s), as its BCU is given it (railbrake.sizing.car_demands, load-weighed);
    the level a healthy brake builds up to. step: "emergency" or "service" (times fraction)."""
    from railbrake import sizing
    from railbrake.vehicle import with_cars
    if cars is not None:
        train = with_cars(train, cars)   # as the run's BCU is given it: its resistance is the run's train's
    profile, _ = sizing.brake_step(train, step)
    return float(fraction * sum(np.interp(speed, d.speed, d.force) for d in sizing.car_demands(train, profile)))


def _first_step(result, demand_time: float) -> tuple[str, float]:
    """("emergency" | "service", fraction) of the run's demand at demand_time (its scenario's
    demand list; a run without one is taken as an emergency stop)."""
    resolved = getattr(result, "resolved", None)
    if resolved is None:
        return "emergency", 1.0
    step = None
    for d in resolved.scenario.spec.demand:
        if d.time <= demand_time + 1e-9:
            step = d
    if step is None or step.emergency or not step.service > 0.0:
        return "emergency", 1.0
    return "service", float(step.service)


def measure(result, train, demand_time: float = 0.0, step: tuple[str, float] | None = None) -> BuildUp:
    """The build-up of the brake in `result` (a run of `train` whose demand steps at demand_time
    s) toward the demand of that first step: ta and tb are the times the total brake force takes
    to reach the fractions of data/response/en14531.yaml of the force that step demands at the
    speed at demand_time (demanded_force), not of the force at some later time (a speed-stepped
    demand changes within seconds). step: ("emergency" | "service", fraction), default: the
    run's scenario's demand at demand_time."""
    demand_time = real("demand_time", demand_time, 0.0)
    s = settings()
    t = result.time - demand_time
    inside = (t >= 0.0) & (t <= s["window_s"] + 1e-9)
    if not inside.any():
        raise InputError(f"scenario {result.scenario}: no sample within {s['window_s']:g} s of the demand "
                         "to measure the build-up (data/response/en14531.yaml, window_s)")
    kind, fraction = _first_step(result, demand_time) if step is None else step
    speed = float(result.outputs["speed"][inside][0])
    target = demanded_force(train, speed, kind, fraction, result.cars)
    if not target > 0.0:
        raise InputError(f"scenario {result.scenario}: the {kind} step demands no brake force at "
                         f"{speed * 3.6:.0f} km/h")
    t, force = t[inside], brake_force(result, train)[inside]
    what = f"scenario {result.scenario}: the brake force (of the {kind} step's {target:.4g} N)"
    ta = _crossing(t, force, s["delay_fraction"] * target, what)
    tb = _crossing(t, force, s["build_up_fraction"] * target, what) - ta
    cylinders = [n for n in result.outputs if n.startswith("cylinder_c")]
    gauge = np.mean([result.outputs[n] for n in cylinders], axis=0)[inside] - result.atmosphere
    full = _crossing(t, force, target, what) if force.max() >= target else t[-1]   # the step's level reached
    filling = _crossing(t, gauge, s["filling_fraction"] * float(np.interp(full, t, gauge)), "the cylinder pressure")
    mass = sum(car.mass + car.equivalent_rotating_mass for car in train.cars[:result.cars])
    lag = max(1, int(round(s["jerk_interval_s"] / float(np.median(np.diff(t)))))) if t.size > 1 else 1
    jerk = float(np.max(force[lag:] - force[:-lag]) / (mass * s["jerk_interval_s"])) if force.size > lag else 0.0
    return BuildUp(ta, tb, filling, jerk, target)


def simulated(train, initial_speed: float, condition: str = "dry-medium", preset: str | None = None) -> BuildUp:
    """The build-up of `train`'s emergency brake (a vehicle.Train, its load case as it is) in an
    emergency stop from initial_speed (m/s) on `condition`, measured over the window; preset: the
    preset name or file the train was read from (default: its preset's name, else the file it was
    read from), for the run's scenario."""
    from railbrake.simulation.runs import run
    from railbrake.vehicle import Train, preset_names
    instance("train", train, Train)
    if preset is None:
        preset = train.spec.name if train.spec.name in preset_names() else train.origin
    initial_speed = real("initial_speed", initial_speed, 0.0, low_open=True)
    scenario = emergency_scenario(preset, initial_speed, condition, settings()["window_s"] + 0.1,
                                  train.load_case)
    told = (f"the simulated build-up of {train.origin} (its emergency brake from {ms_to_kmh(initial_speed):.0f} km/h "
            f"on {condition})")
    with told_as(scenario.name, told):
        return measure(run(scenario, cars=len(train.cars), train=train), train)


@contextlib.contextmanager
def told_as(name: str, told: str):
    """The warnings and errors of a run of a scenario made in code (emergency_scenario: its name,
    e.g. emergency-160-dry-medium, is no preset or file the user gave) told as `told` instead of
    'scenario NAME', each warning still one warning of its own."""
    prefix = f"scenario {name}: "

    def reworded(text: str) -> str:
        return f"{told}: {text[len(prefix):]}" if text.startswith(prefix) else text

    caught = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            yield
    except InputError as exc:
        raise InputError(reworded(str(exc))) from None
    finally:
        for w in caught:
            warnings.warn_explicit(reworded(str(w.message)), w.category, w.filename, w.lineno)


# ------------------------------------------------------------------ the simulated chain's response (the API's)

RESPONSE_WINDOW = settings()["window_s"]   # s of emergency braking the build-up is measured over


def emergency_scenario(train: str, initial_speed: float, condition: str = "dry-medium",
                       max_time: float = 3600.0, load: str | None = None,
                       allow_outside_validity: bool = False) -> Scenario:
    """An emergency stop of `train` (preset or file) from initial_speed (m/s) on `condition`;
    allow_outside_validity: run the condition outside its validity (flagged) instead of refusing."""
    return _stop_scenario(train, initial_speed, condition, {"emergency": True}, "emergency", "Emergency brake",
                          max_time, load, allow_outside_validity)


def service_scenario(train: str, initial_speed: float, condition: str, demand: float,
                     max_time: float = 3600.0) -> Scenario:
    """A service stop of `train` (preset or file) from initial_speed (m/s) on `condition` at
    `demand` (0-1 of full service)."""
    demand = real("demand", demand, 0.0, 1.0, low_open=True)
    return _stop_scenario(train, initial_speed, condition, {"service": demand}, "service",
                          f"Service brake {demand:g}", max_time, None, False)


def _stop_scenario(train, initial_speed, condition, demand: dict, kind: str, title: str, max_time,
                   load, allow_outside_validity) -> Scenario:
    from railbrake.scenario import SCHEMA, from_data
    train, condition = name_or_path("train", train), name_or_path("condition", condition)
    initial_speed, max_time = real("initial_speed", initial_speed, 0.0), real("max_time", max_time, 0.0)
    if load is not None:
        choice("load", load, LOAD_CASES)
    data = {"schema": SCHEMA, "name": f"{kind}-{ms_to_kmh(initial_speed):.0f}-{condition}",
            "title": f"{title} from {ms_to_kmh(initial_speed):.0f} km/h, {train}",
            "train": {"preset": str(train)}, "initial_speed": f"{initial_speed!r} m/s",
            "demand": [{"time": "0 s", **demand}],
            "adhesion": {"condition": condition, "allow_outside_validity": flag("allow_outside_validity",
                                                                                allow_outside_validity)},
            "stop": {"speed": "0.05 m/s", "max_time": f"{max_time} s"}}
    if load is not None:
        data["train"]["load_case"] = load
    return from_data(data, f"{kind} stop of {train}", {})


def response_times(result: Result, train=None) -> tuple[float, float]:
    """EN 14531-1 delay ta and build-up tb of a run's brake, measured on its total brake force
    (measure); train: the run's (default: its resolved configuration's)."""
    instance("result", result, Result)
    if train is None:
        if result.resolved is None:
            raise InputError("response_times: give the train of a run made with a train of its own")
        train = result.resolved.train
    from railbrake.vehicle import Train
    instance("train", train, Train)
    b = measure(result, train)
    return b.delay, b.build_up


def simulated_response(train: str, initial_speed: float, load: str | None = None) -> tuple[float, float]:
    """(ta, tb) of `train`'s simulated emergency brake from initial_speed (m/s) on dry rail: the
    first RESPONSE_WINDOW s of a run (simulated)."""
    train = name_or_path("train", train)
    b = simulated(load_train(train, load or True), initial_speed, preset=str(train))
    return b.delay, b.build_up




def healthy_shortfall(result) -> float | None:
    """s: how long a cylinder of a healthy brake of the run's train stays more than 0.2 bar below
    its demand in its own emergency build-up (the KPI cylinder_shortfall_s of an emergency stop of
    the same train, cars and load from the run's initial speed, on dry rail, without faults): what
    the run's cylinder_shortfall_s is compared with (railbrake.results.kpis.warnings). None for a
    run without its configuration (a loaded result) or from standstill. Kept in result.meta."""
    import warnings
    from railbrake.simulation.runs import run
    from railbrake.vehicle import with_cars
    if HEALTHY_SHORTFALL in result.meta:
        return result.meta[HEALTHY_SHORTFALL]
    resolved = getattr(result, "resolved", None)
    if resolved is None or not resolved.scenario.spec.initial_speed > 0.0:
        return None
    train = with_cars(resolved.train, result.cars)
    with warnings.catch_warnings():   # the run's own warnings were given; this is its reference
        warnings.simplefilter("ignore")
        scenario = emergency_scenario(resolved.scenario.spec.train.preset, resolved.scenario.spec.initial_speed,
                                      max_time=2.0 * settings()["window_s"], load=train.load_case)
        value = run(scenario, cars=result.cars, train=train, record=False).kpis["cylinder_shortfall_s"]
    result.meta[HEALTHY_SHORTFALL] = value
    return value
