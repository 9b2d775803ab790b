"""Drawing the scatter file's tolerances and applying a draw to a run's C structs.

The draws are Latin hypercubes over every factor (one per quantity and train, car or unit, as the
tolerance's correlation says, railbrake.etcs.inputs.Distribution.per):
each factor's range is covered in equal-probability strata, so a state's mean and spread converge
faster than with independent draws (McKay, Beckman & Conover 1979). Each failure state draws its
own, in blocks (block_draws: a block is one hypercube, seeded by the analysis' seed, the state and
the block's number), so that the states' samples are independent of one another (the bootstrap of
railbrake.etcs.bound needs it) and each is balanced whatever number of blocks it gets.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import norm, qmc, truncnorm

from railbrake import _core
from railbrake.errors import InputError
from railbrake.etcs.inputs import QUANTITIES, Distribution, ScatterFile

MAX_SAMPLES = 100_000
UNITS_PER_CAR = _core.AXLES_PER_CAR   # a tolerance drawn per unit: one draw per axle's brake


def _ppf(d: Distribution, u: np.ndarray) -> np.ndarray:
    if d.distribution == "uniform":
        low, high = d.bounds
        return low + (high - low) * u
    if d.distribution == "normal":
        return norm.ppf(u, loc=d.mean, scale=d.sd) if d.sd > 0.0 else np.full_like(u, d.mean)
    low, high = d.bounds
    if d.sd == 0.0:
        return np.full_like(u, d.mean)
    return truncnorm.ppf(u, (low - d.mean) / d.sd, (high - d.mean) / d.sd, loc=d.mean, scale=d.sd)


def draws(scatter: ScatterFile | None, n_cars: int, n: int, seed: int) -> np.ndarray:
    """n draws of every factor: array (n, len(QUANTITIES), n_cars), 1 where the file has no scatter."""
    if not 1 <= n <= MAX_SAMPLES:
        raise InputError(f"samples = {n}: must be in [1, {MAX_SAMPLES}]")
    out = np.ones((n, len(QUANTITIES), n_cars))
    given = scatter.quantities() if scatter is not None else {}
    if not given:
        return out
    dims = [(QUANTITIES.index(q), d, columns(d.per, n_cars)) for q, d in given.items()]
    u = qmc.LatinHypercube(d=sum(k for _, _, k in dims), seed=seed).random(n)
    column = 0
    for q, d, k in dims:
        out[:, q, :] = per_car(_ppf(d, u[:, column:column + k]), d.per, n_cars)
        column += k
    return out


def columns(per: str, n_cars: int) -> int:
    """The draws a tolerance takes per train: one, one per car, or one per unit (axle's brake)."""
    return {"train": 1, "car": n_cars, "unit": n_cars * UNITS_PER_CAR}[per]


def per_car(values: np.ndarray, per: str, n_cars: int) -> np.ndarray:
    """(draws, n_cars) car factors from (draws, columns(per, n_cars)) values: a car's factor is
    its units' mean (on dry rail a car's brake force is the sum of its units')."""
    if per == "unit":
        return values.reshape(values.shape[0], n_cars, UNITS_PER_CAR).mean(axis=2)
    return values if per == "car" else np.repeat(values[:, :1], n_cars, axis=1)


def train_tolerance(scatter: ScatterFile | None) -> tuple[str, Distribution] | None:
    """(quantity, distribution) of the one tolerance drawn per train, if the file has exactly one
    that scatters (railbrake.etcs.conditional reads the states given it); else None."""
    given = [(q, d) for q, d in (scatter.quantities().items() if scatter is not None else [])
             if d.per == "train" and (d.distribution == "uniform" or d.sd > 0.0)]
    return given[0] if len(given) == 1 else None


def block_draws(scatter: ScatterFile | None, n_cars: int, size: int, seed: int, state: int, block: int) -> np.ndarray:
    """Block `block` of failure state `state`'s draws: a Latin hypercube of `size` draws of its own
    (array (size, len(QUANTITIES), n_cars), as draws)."""
    sub = int(np.random.SeedSequence([seed, state, block]).generate_state(1, dtype=np.uint64)[0] >> 1)
    return draws(scatter, n_cars, size, sub)


def check_against(scatter: ScatterFile | None, plant, origin: str) -> None:
    """Refuse, before any run, a rigging-efficiency scatter that takes a car's efficiency above 1."""
    d = scatter.rigging_efficiency if scatter is not None else None
    if d is None:
        return
    high = d.bounds[1] if d.bounds else d.mean + 10.0 * d.sd
    worst = max(plant.car[c].vehicle.brake.caliper.efficiency for c in range(plant.n_cars)) * high
    if worst > 1.0:
        raise InputError(f"{origin}: rigging_efficiency: its upper end {high:g} takes the caliper efficiency "
                         f"to {worst:.4g}: the factor's upper bound must keep it at or below 1")


def _scale_table(table, factor: float) -> None:
    for i in range(table.n):
        table.value[i] *= factor


def apply(plant, bcu, factors: np.ndarray) -> tuple:
    """Copies of the plant and BCU structs with one draw (len(QUANTITIES) x n_cars factors): pad
    friction, caliper efficiency, wheel radius, mass, valve response, the emergency valve's choke
    and the load-weighing valve's limit (gauge) in the plant, which the BCU
    does not know (it brakes for the nominal train: load = the mass it weighs); the pressure its
    control gives per newton demanded in the BCU."""
    plant, bcu = type(plant).from_buffer_copy(plant), type(bcu).from_buffer_copy(bcu)
    f = dict(zip(QUANTITIES, factors))
    for c in range(plant.n_cars):
        car = plant.car[c]
        v = car.vehicle
        _scale_table(v.brake.pad.table, f["pad_friction"][c])
        v.brake.caliper.efficiency *= f["rigging_efficiency"][c]
        v.wheelset.wheel_radius *= f["wheel_diameter"][c]
        v.mass *= f["load"][c]
        v.wheelset.axle_load *= f["load"][c]
        car.ep_tau *= f["valve_response"][c]
        car.relay_tau *= f["valve_response"][c]
        car.emergency_area *= f["emergency_choke"][c]
        car.emergency_limit = plant.atmosphere + (car.emergency_limit - plant.atmosphere) * f["limiter_setting"][c]
        _scale_table(bcu.pressure_per_newton[c], f["pressure_control"][c])
    return plant, bcu

