"""The brake's build-up measured on a simulated emergency stop, by EN 14531-1's definitions
(data/response/en14531.yaml, with its sources): delay time ta, build-up time tb, equivalent response
time te = ta + tb/2, the cylinders' filling time and the largest jerk.

The force is the train's total brake force at the rails (every axle's friction brake by the C law
at its cylinder pressure and wheel speed, plus the ED brake achieved), as TSI LOC&PAS evaluates the
emergency brake's response on the total braking force.
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np
import yaml

from railbrake import _core
from railbrake._args import choice, flag, instance, name_or_path, real
from railbrake.errors import InputError
from railbrake.results.scripting import Result
from railbrake.scenario import Scenario
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
    force: float      # N, the brake force at the end of the window (the 100 % of ta and tb)

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


def _crossing(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """First time y reaches level, interpolated linearly between samples."""
    i = int(np.argmax(y >= level))
    if y[i] < level:
        raise InputError(f"the brake force never reaches {level:.4g} N within the window")
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (level - y[i - 1]) * (t[i] - t[i - 1]) / (y[i] - y[i - 1]))


def measure(result, train, demand_time: float = 0.0) -> BuildUp:
    """The build-up of the brake in `result` (a run of `train` whose demand steps at demand_time
    s) over the window of data/response/en14531.yaml."""
    demand_time = real("demand_time", demand_time, 0.0)
    s = settings()
    t = result.time - demand_time
    inside = (t >= 0.0) & (t <= s["window_s"] + 1e-9)
    if not inside.any() or t[inside][-1] < s["window_s"] - 0.05:
        raise InputError(f"scenario {result.scenario}: the run must record {s['window_s']:g} s after the demand "
                         "to measure the build-up (data/response/en14531.yaml, window_s)")
    t, force = t[inside], brake_force(result, train)[inside]
    final = float(force[-1])
    if not final > 0.0:
        raise InputError(f"scenario {result.scenario}: no brake force within {s['window_s']:g} s of the demand")
    ta = _crossing(t, force, s["delay_fraction"] * final)
    tb = _crossing(t, force, s["build_up_fraction"] * final) - ta
    cylinders = [n for n in result.outputs if n.startswith("cylinder_c")]
    gauge = np.mean([result.outputs[n] for n in cylinders], axis=0)[inside] - result.atmosphere
    filling = _crossing(t, gauge, s["filling_fraction"] * float(gauge[-1]))
    mass = sum(car.mass + car.equivalent_rotating_mass for car in train.cars[:result.cars])
    lag = max(1, int(round(s["jerk_interval_s"] / float(np.median(np.diff(t))))))
    jerk = float(np.max(force[lag:] - force[:-lag]) / (mass * s["jerk_interval_s"])) if force.size > lag else 0.0
    return BuildUp(ta, tb, filling, jerk, final)


def simulated(train, initial_speed: float, condition: str = "dry-medium", preset: str | None = None) -> BuildUp:
    """The build-up of `train`'s emergency brake (a vehicle.Train, its load case as it is) in an
    emergency stop from initial_speed (m/s) on `condition`, measured over the window; preset: the
    preset name or file the train was read from (default: its name), for the run's scenario."""
    from railbrake.simulation.runs import run
    from railbrake.vehicle import Train
    instance("train", train, Train)
    initial_speed = real("initial_speed", initial_speed, 0.0, low_open=True)
    scenario = emergency_scenario(preset or train.spec.name, initial_speed, condition, settings()["window_s"] + 0.1,
                                  train.load_case)
    return measure(run(scenario, cars=len(train.cars), train=train), train)


# ------------------------------------------------------------------ the simulated chain's response (the API's)

RESPONSE_WINDOW = settings()["window_s"]   # s of emergency braking the build-up is measured over


def emergency_scenario(train: str, initial_speed: float, condition: str = "dry-medium",
                       max_time: float = 3600.0, load: str | None = None,
                       allow_outside_validity: bool = False) -> Scenario:
    """An emergency stop of `train` (preset or file) from initial_speed (m/s) on `condition`;
    allow_outside_validity: run the condition outside its validity (flagged) instead of refusing."""
    from railbrake.scenario import SCHEMA, from_data
    train, condition = name_or_path("train", train), name_or_path("condition", condition)
    initial_speed, max_time = real("initial_speed", initial_speed, 0.0), real("max_time", max_time, 0.0)
    if load is not None:
        choice("load", load, LOAD_CASES)
    data = {"schema": SCHEMA, "name": f"emergency-{initial_speed * 3.6:.0f}-{condition}",
            "title": f"Emergency brake from {initial_speed * 3.6:.0f} km/h, {train}",
            "train": {"preset": str(train)}, "initial_speed": f"{initial_speed!r} m/s",
            "demand": [{"time": "0 s", "emergency": True}],
            "adhesion": {"condition": condition, "allow_outside_validity": flag("allow_outside_validity",
                                                                                allow_outside_validity)},
            "stop": {"speed": "0.05 m/s", "max_time": f"{max_time} s"}}
    if load is not None:
        data["train"]["load_case"] = load
    return from_data(data, f"emergency stop of {train}", {})


def response_times(result: Result, train=None) -> tuple[float, float]:
    """EN 14531-1 delay ta and build-up tb of a run's brake, measured on its total brake force
    (measure); train: the run's (default: its resolved configuration's)."""
    instance("result", result, Result)
    if train is None:
        if result.resolved is None:
            raise InputError("response_times: give the train of a run made with a train of its own")
        train = result.resolved.train
    b = measure(result, train)
    return b.delay, b.build_up


def simulated_response(train: str, initial_speed: float, load: str | None = None) -> tuple[float, float]:
    """(ta, tb) of `train`'s simulated emergency brake from initial_speed (m/s) on dry rail: the
    first RESPONSE_WINDOW s of a run (simulated)."""
    train = name_or_path("train", train)
    b = simulated(load_train(train, load or True), initial_speed, preset=str(train))
    return b.delay, b.build_up
