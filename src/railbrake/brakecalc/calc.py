"""The figures of the brake calculation for one train and load case.

Every stop is the C stopping-distance calculation (sizing.stopping_distance, EN 14531 manner) of
the train's emergency brake step, with the delay and build-up measured on a simulated emergency
stop from the same speed (simulation.response, EN 14531-1 definitions)."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import yaml

from railbrake import sizing, vehicle
from railbrake._args import flag, real, reals, show
from railbrake.errors import InputError
from railbrake.units import kmh_to_ms, ms_to_kmh

if TYPE_CHECKING:   # the simulation package is imported only when a stop is run (emergency_stop)
    from railbrake.simulation.response import BuildUp

CURVE_STEP_S = 0.05   # s between the stop's output samples the interval decelerations interpolate
# an interval from v1 counts when the braking curve starts at most this fraction below v1 (the
# run-down by resistance during te), and is then evaluated from the curve's first speed
INTERVAL_START_TOLERANCE = 0.01


@cache
def settings() -> dict:
    """The published figures and their sources (data/brakecalc/brake_calculation.yaml)."""
    path = resources.files("railbrake") / "data" / "brakecalc" / "brake_calculation.yaml"
    return yaml.safe_load(path.read_text())


# ------------------------------------------------------------------ formulae

def equivalent_deceleration(v0: float, distance: float, response_time: float) -> float:
    """EN 14531-1 equivalent deceleration a_e (m/s2) of a stop of `distance` m from v0 m/s with the
    equivalent response time te s: s = v0 te + v0^2 / (2 a_e)."""
    v0, distance = real("v0", v0, 0.0, low_open=True), real("distance", distance, 0.0, low_open=True)
    response_time = real("response_time", response_time, 0.0)
    braking = distance - v0 * response_time
    if not braking > 0.0:
        raise InputError(f"distance = {distance:g} m (v0, response_time): must exceed the response distance v0 te = "
                         f"{v0 * response_time:g} m")
    return v0 * v0 / (2.0 * braking)


def braking_curve(time, speed, distance, response_time: float) -> tuple[np.ndarray, np.ndarray]:
    """(speed m/s, distance m) of a stop from the end of its equivalent response time te on: the
    brake acts from there (EN 14531-1), so a mean deceleration over the first speed interval does
    not count the free run during te. The sample at te is interpolated."""
    time, speed, distance = reals("time", time), reals("speed", speed), reals("distance", distance)
    if time.ndim != 1 or time.size < 2 or speed.shape != time.shape or distance.shape != time.shape:
        raise InputError(f"time, speed, distance: three arrays of one length >= 2 (here {time.shape}, "
                         f"{speed.shape}, {distance.shape})")
    te = real("response_time", response_time, 0.0)
    after = time > te
    if not after.any():
        raise InputError(f"response_time = {te:g} s: the stop ends at {time[-1]:g} s, before the brake acts")
    return (np.concatenate([[np.interp(te, time, speed)], speed[after]]),
            np.concatenate([[np.interp(te, time, distance)], distance[after]]))


def interval_decelerations(speed, distance, intervals_kmh) -> list[dict]:
    """Mean deceleration (v1^2 - v2^2) / (2 s_12) over each speed interval [v1, v2] km/h (v1 > v2)
    of a braking curve (speed m/s falling with distance m, from braking_curve), the distance between
    the two speeds interpolated linearly in speed. An interval above the curve's first speed is left
    out, one that holds it starts there: its from_kmh is that speed (a stop from 350 km/h has run
    down a little by the end of te)."""
    speed, distance = reals("speed", speed).ravel(), reals("distance", distance).ravel()
    if not isinstance(intervals_kmh, (list, tuple)) or not all(
            isinstance(i, (list, tuple)) and len(i) == 2 for i in intervals_kmh):
        raise TypeError(f"intervals_kmh = {show(intervals_kmh)}: must be a list of [from, to] km/h pairs")
    for i, pair in enumerate(intervals_kmh):
        reals(f"intervals_kmh[{i}]", pair, 0.0)
    if speed.size < 2 or speed.size != distance.size:
        raise InputError(f"the stop's curve: {speed.size} speeds and {distance.size} distances, "
                         "at least two of each and as many")
    falling = speed[::-1], distance[::-1]     # np.interp needs rising speeds
    first = float(speed[0])
    rows = []
    for v1_kmh, v2_kmh in intervals_kmh:
        v1, v2 = kmh_to_ms(float(v1_kmh)), kmh_to_ms(float(v2_kmh))
        if not v1 > v2 >= 0.0:
            raise InputError(f"intervals_kmh: speed interval [{v1_kmh}, {v2_kmh}] km/h: the first speed must exceed the "
                             "second, both >= 0")
        if v2 >= first or v1 > first * (1 + INTERVAL_START_TOLERANCE):
            continue
        v1 = min(v1, first)
        s12 = float(np.interp(v2, *falling) - np.interp(v1, *falling))
        rows.append({"from_kmh": ms_to_kmh(v1), "to_kmh": float(v2_kmh), "distance_m": s12,
                     "deceleration_ms2": (v1 * v1 - v2 * v2) / (2.0 * s12)})
    return rows


def brake_percentage(distance: float) -> float:
    """Brake percentage lambda (%) of a stop of `distance` m from the UIC 544-1 reference speed:
    lambda_ref S_ref / S (data file: anchor and its source)."""
    anchor = settings()["uic544"]["anchor"]
    distance = real("distance", distance, 0.0, low_open=True)
    return anchor["lambda_percent"] * anchor["stopping_distance_m"] / distance


def uic_stopping_distance(lambda_percent: float) -> float:
    """The inverse of brake_percentage: the stopping distance (m) from the reference speed."""
    anchor = settings()["uic544"]["anchor"]
    lambda_percent = real("lambda_percent", lambda_percent, 0.0, low_open=True)
    return anchor["lambda_percent"] * anchor["stopping_distance_m"] / lambda_percent


def braked_weight(lambda_percent: float, mass_t: float) -> float:
    """Braked weight B (t) = lambda m / 100 (UIC 544-1)."""
    return real("lambda_percent", lambda_percent, 0.0) * real("mass_t", mass_t, 0.0, low_open=True) / 100.0


# ------------------------------------------------------------------ the train's stops

@dataclass(frozen=True)
class Stop:
    v0: float                 # m/s
    distance: float           # m
    time: float               # s
    measured: BuildUp         # ta, tb and te of the simulated emergency stop
    curve_time: np.ndarray    # s along the stop
    speed: np.ndarray         # m/s
    along: np.ndarray         # m
    warnings: list = field(default_factory=list)

    @property
    def delay(self) -> float:
        return self.measured.delay

    @property
    def build_up(self) -> float:
        return self.measured.build_up

    @property
    def response(self) -> float:
        return self.measured.response


def emergency_stop(train: vehicle.Train, v0: float, preset: str | None) -> Stop:
    """The emergency stop of `train` from v0 m/s on level track with its simulated build-up."""
    from railbrake.simulation import response
    measured = response.simulated(train, v0, preset=preset)
    r = sizing.stopping_distance(v0, train=train, delay=measured.delay, build_up=measured.build_up,
                                 dt_out=CURVE_STEP_S)
    return Stop(v0, r.distance, r.time, measured, r.curve_time, r.curve_speed,
                r.curve_distance, list(r.warnings))


@dataclass(frozen=True)
class BrakeCalculation:
    train: str
    title: str
    load_case: str
    mass_t: float
    max_speed_kmh: float
    brakes: str                    # which brakes the emergency step counts
    uic: dict                      # reference stop, lambda, braked weight, validity
    en14531: dict                  # stop from the maximum speed: te, a_e, interval decelerations
    tsi: list                      # per TSI speed: limit, distance, margin, passed
    warnings: list

    @property
    def passed(self) -> bool | None:
        """Every TSI row within its limit (None: no TSI value applies to the train)."""
        return all(row["passed"] for row in self.tsi) if self.tsi else None


def _uic(train: vehicle.Train, preset: str | None, force: bool) -> dict:
    s = settings()["uic544"]
    limit = s["valid_up_to_kmh"]
    valid = ms_to_kmh(train.max_speed) <= limit * (1 + 1e-9)
    out = {"brake_position": s["brake_position"], "reference_speed_kmh": float(s["reference_speed_kmh"]),
           "valid_up_to_kmh": float(limit), "within_validity": bool(valid), "stopping_distance_m": None,
           "response_time_s": None, "brake_percentage": None, "braked_weight_t": None}
    if not valid and not force:
        out["note"] = (f"maximum speed {ms_to_kmh(train.max_speed):g} km/h above {limit:g} km/h: UIC 544-1 "
                       "assesses such trains on their stopping distances (clause 1.2), not on lambda; "
                       "--force-lambda computes it anyway")
        return out
    stop = emergency_stop(train, kmh_to_ms(s["reference_speed_kmh"]), preset)
    lam = brake_percentage(stop.distance)
    out.update(stopping_distance_m=stop.distance, response_time_s=stop.response, brake_percentage=lam,
               braked_weight_t=braked_weight(lam, train.mass / 1e3))
    if not valid:
        out["note"] = f"outside UIC 544-1's validity (maximum speed above {limit:g} km/h), computed as forced"
    return out


def _en14531(train: vehicle.Train, preset: str | None) -> tuple[dict, list]:
    stop = emergency_stop(train, train.max_speed, preset)
    out = {"initial_speed_kmh": ms_to_kmh(stop.v0), "stopping_distance_m": stop.distance,
           "stopping_time_s": stop.time, "delay_s": stop.delay, "build_up_s": stop.build_up,
           "response_time_s": stop.response,
           "equivalent_deceleration_ms2": equivalent_deceleration(stop.v0, stop.distance, stop.response),
           "intervals": interval_decelerations(*braking_curve(stop.curve_time, stop.speed, stop.along, stop.response),
                                               settings()["en14531"]["speed_intervals_kmh"])}
    return out, stop.warnings


def _tsi(train: vehicle.Train, preset: str | None) -> list[dict]:
    s = settings()["tsi"]
    if ms_to_kmh(train.max_speed) < s["applies_from_max_speed_kmh"]:
        return []
    rows = []
    for v_kmh, limit in zip(s["speed_kmh"], s["max_distance_m"]):
        if kmh_to_ms(v_kmh) > train.max_speed * (1 + 1e-9):
            continue
        stop = emergency_stop(train, kmh_to_ms(v_kmh), preset)
        rows.append({"speed_kmh": float(v_kmh), "limit_m": float(limit), "stopping_distance_m": stop.distance,
                     "response_time_s": stop.response,
                     "equivalent_deceleration_ms2": equivalent_deceleration(stop.v0, stop.distance, stop.response),
                     "margin_m": limit - stop.distance,
                     "margin_percent": 100.0 * (limit - stop.distance) / limit,
                     "passed": bool(stop.distance <= limit)})
    return rows


def calculate(train, load_case: str | None = None, force_lambda: bool = False) -> BrakeCalculation:
    """The brake calculation of `train` (preset name, train file or vehicle.Train) in `load_case` (tare, normal,
    crush; default: the train file's)."""
    if load_case is not None and load_case not in vehicle.LOAD_CASES:
        raise InputError(f"load_case = {show(load_case)}: must be one of {', '.join(vehicle.LOAD_CASES)} or None "
                         "(the train file's)")
    force_lambda = flag("force_lambda", force_lambda)
    t = vehicle.load_train(train, load_case or True)
    preset = str(train) if isinstance(train, (str, Path)) else None   # the simulated stop's train
    _, ed = sizing.brake_step(t, "emergency")
    brakes = "friction and ED brake (the emergency step blends the ED brake)" if ed else "friction brake only"
    en14531, warnings = _en14531(t, preset)
    return BrakeCalculation(t.name, t.title, t.load_case, t.mass / 1e3, ms_to_kmh(t.max_speed), brakes,
                            _uic(t, preset, force_lambda), en14531, _tsi(t, preset), sorted(set(warnings)))
