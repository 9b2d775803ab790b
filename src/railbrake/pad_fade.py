"""The pads' heat fading fitted to published dynamometer stops.

A pad's friction is its cold table over speed divided by 1 + rate (T_s - onset) above the onset,
T_s the disc's friction surface temperature (rb_pad_friction, core/src/vehicle_brake.c). Published
dynamometer figures are stop averages (UIC 541-3: (1/s) int mu ds), so the law is fitted by running
stops of the car's own disc in the core (vehicle.dynamometer_stop) until their averages match:

- the onset is the friction surface's peak in a stop from `onset_speed`, the speed below which a
  pad's stop-averaged friction is published as stable;
- the fading rate makes either one stop's average (`rate_mean` from `rate_speed`) or the ratio of
  two stops' averages (`rate_ratio` between `ratio_speeds`) the published one;
- the cold level (the table shifted as a whole) makes the stop from `level_speed` average
  `level_mean`.

Which figures go into the fit and which are left to check it is the caller's (the validation
cases and the train files name them).
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass

from importlib import resources

import yaml
from scipy.optimize import brentq

from railbrake import _core, vehicle
from railbrake.units import KMH

MAX_RATE = 0.01   # 1/K: the bound of train.pad_fade_rate (core/src/bounds.c)


@dataclass(frozen=True)
class FadeFit:
    shift: float   # added to every value of the car's cold table
    onset: float   # K
    rate: float    # 1/K


def pad_with(car: vehicle.Car, shift: float = 0.0, onset: float = 0.0, rate: float = 0.0) -> _core.PadFriction:
    """The car's pads with their cold table shifted by `shift` and the given fading."""
    pad = _core.PadFriction()
    ctypes.pointer(pad)[0] = car.c.brake.pad
    for i in range(pad.table.n):
        pad.table.value[i] += shift
    pad.fade_onset, pad.fade_rate = onset, rate
    return pad


def stop_mean(car, speed: float, pad, conditions: dict) -> float:
    return vehicle.dynamometer_stop(car, speed, pad=pad, **conditions).mean_friction


def fit(car: vehicle.Car, conditions: dict, *, onset_speed: float, level_speed: float, level_mean: float,
        rate_speed: float | None = None, rate_mean: float | None = None,
        ratio_speeds: tuple[float, float] | None = None, rate_ratio: float | None = None) -> FadeFit:
    """Fit the fading and the level (speeds in m/s; conditions: vehicle.dynamometer_stop's
    deceleration, ambient_temperature, dt)."""
    onset = vehicle.dynamometer_stop(car, onset_speed, pad=pad_with(car), **conditions).max_surface_temperature
    if rate_ratio is not None:
        low, high = ratio_speeds
        def miss(rate):
            return stop_ratio(car, conditions, onset, rate, low, high) - rate_ratio
        rate = brentq(miss, 0.0, MAX_RATE, xtol=1e-9)
    else:
        rate = rate_for(car, conditions, onset=onset, level_speed=level_speed, level_mean=level_mean,
                        speed=rate_speed, mean=rate_mean)
    return FadeFit(level_shift(car, conditions, onset, rate, level_speed, level_mean), onset, rate)


def level_shift(car, conditions: dict, onset: float, rate: float, level_speed: float, level_mean: float) -> float:
    """The shift of the cold table that makes the stop from level_speed average level_mean."""
    return brentq(lambda s: stop_mean(car, level_speed, pad_with(car, s, onset, rate), conditions) - level_mean,
                  -0.2, 0.2, xtol=1e-7)


def rate_for(car, conditions: dict, *, onset: float, level_speed: float, level_mean: float, speed: float,
             mean: float) -> float:
    """The fading rate, the level refitted with it, that makes the stop from `speed` average `mean`."""
    def miss(rate):
        shift = level_shift(car, conditions, onset, rate, level_speed, level_mean)
        return stop_mean(car, speed, pad_with(car, shift, onset, rate), conditions) - mean
    return brentq(miss, 0.0, MAX_RATE, xtol=1e-9)


def stop_ratio(car, conditions: dict, onset: float, rate: float, low: float, high: float) -> float:
    """Stop average from `high` over the one from `low` (speeds in m/s) with the car's cold table."""
    pad = pad_with(car, 0.0, onset, rate)
    return stop_mean(car, high, pad, conditions) / stop_mean(car, low, pad, conditions)


def load_data(name: str = "sintered-cu") -> dict:
    """A pad data file (src/railbrake/data/pads/NAME.yaml): published figures and the dynamometer."""
    return yaml.safe_load((resources.files("railbrake") / "data" / "pads" / f"{name}.yaml").read_text(encoding="utf-8"))


def dynamometer(data: dict) -> tuple[vehicle.Car, dict]:
    """The data file's dynamometer: its car (a preset's car type) and vehicle.dynamometer_stop's conditions."""
    d = data["dynamometer"]
    train = vehicle.load_train(d["train"])
    car = next(c for c in train.cars if c.type_name == d["car_type"])
    return car, {"deceleration": float(d["deceleration_ms2"]),
                 "ambient_temperature": float(d["ambient_c"]) + vehicle.ZERO_CELSIUS, "dt": float(d["dt_s"])}


def preset_fit(data: dict) -> FadeFit:
    """The fit the train files carry: the data file's `fit` entry on its dynamometer."""
    car, conditions = dynamometer(data)
    f = data["fit"]
    return fit(car, conditions, onset_speed=f["onset"]["speed_kmh"] * KMH, level_speed=f["level"]["speed_kmh"] * KMH,
               level_mean=f["level"]["mean"], rate_speed=f["rate"]["speed_kmh"] * KMH, rate_mean=f["rate"]["mean"])
