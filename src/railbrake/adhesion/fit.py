"""Fit of Polach's five parameters to measured creep-force curves (bounded least squares).

The model is the C core's Polach law; scipy.optimize.least_squares does the fitting, and the
parameter uncertainty comes from the Jacobian at the optimum (Gauss-Newton covariance).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from railbrake import _args
from railbrake.contact import HertzContact, PolachParams, default_contact, polach_coefficient
from railbrake.errors import InputError

PARAMETER_NAMES = ("mu0", "A", "B", "kA", "kS")
LOWER = np.array([1e-3, 0.0, 0.0, 1e-3, 1e-3])
UPPER = np.array([1.5, 1.0, 20.0, 1.0, 1.0])
# Starting points: Polach's dry and wet sets (2005, Table 2) and a low-adhesion set.
STARTS = ((0.55, 0.4, 0.6, 1.0, 0.4), (0.30, 0.4, 0.2, 0.3, 0.1), (0.08, 0.4, 0.2, 0.3, 0.1))
MIN_POINTS = 10
MAX_CONDITION_NUMBER = 1e10


@dataclass(frozen=True)
class PolachFit:
    params: PolachParams
    std: dict  # one standard deviation of each parameter
    residuals: np.ndarray  # model - measured F/Q at each point
    rms: float
    covariance: np.ndarray


def _check_data(creep, coefficient, speed):
    try:   # the lengths first: a shorter column is named as such, whatever it holds
        sizes = np.size(creep), np.size(coefficient)
    except (ValueError, TypeError):
        sizes = None
    if sizes and sizes[0] != sizes[1]:
        raise InputError(f"coefficient: {sizes[1]} values for {sizes[0]} creep values")
    creep = _args.reals("creep", creep).ravel()
    coefficient = _args.reals("coefficient", coefficient).ravel()
    speed = _args.reals("speed", speed)
    if speed.ndim and speed.ravel().shape != creep.shape:
        raise InputError(f"speed: {speed.size} values for {creep.size} creep values (or give one speed)")
    speed = np.broadcast_to(speed.ravel() if speed.ndim else speed, creep.shape).astype(float)
    if coefficient.shape != creep.shape:
        raise InputError(f"coefficient: {coefficient.size} values for {creep.size} creep values")
    for name, values in (("creep", creep), ("coefficient", coefficient), ("speed", speed)):
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise InputError(f"{name}[{bad[0]}] = {values[bad[0]]}: must be a finite number")
    check_points(creep, coefficient, speed, lambda name, i: f"{name}[{i}]")
    if creep.size < MIN_POINTS:
        raise InputError(f"{creep.size} points: at least {MIN_POINTS} are needed to determine "
                         "5 parameters and their uncertainty")
    return creep, coefficient, speed


def check_points(creep, coefficient, speed, where, speed_unit: tuple = ("m/s", 1.0)) -> None:
    """Each point inside the C plausibility bounds (core/src/bounds.c); where(name, i) names a value
    (e.g. 'creep[3]' or 'data.csv, line 5: creep'); speed_unit: (unit, factor to m/s) of `speed`.
    Creep given in percent is refused with a hint."""
    from railbrake import config
    creep, coefficient = _args.reals("creep", creep).ravel(), _args.reals("coefficient", coefficient).ravel()
    speed = _args.reals("speed", speed)
    if speed.ndim and speed.ravel().shape != creep.shape:
        raise InputError(f"speed: {speed.size} values for {creep.size} creep values (or give one speed)")
    speed = np.broadcast_to(speed.ravel() if speed.ndim else speed, creep.shape)
    if coefficient.shape != creep.shape:
        raise InputError(f"coefficient: {coefficient.size} values for {creep.size} creep values")
    if not callable(where):
        raise TypeError(f"where = {_args.show(where)}: must be a function (name, index) -> the value's label")
    if not (isinstance(speed_unit, tuple) and len(speed_unit) == 2 and isinstance(speed_unit[0], str)):
        raise TypeError(f"speed_unit = {_args.show(speed_unit)}: must be (unit, factor to m/s), e.g. ('km/h', 1 / 3.6)")
    _args.real("speed_unit[1]", speed_unit[1], 0.0, low_open=True)
    for name, values, bound, per, unit in (("creep", creep, "adhesion.creep", 1.0, ""),
                                           ("coefficient", coefficient, "adhesion.coefficient", 1.0, ""),
                                           ("speed", speed, "train.table_speed", speed_unit[1], speed_unit[0])):
        bad = [i for i, x in enumerate(values) if not config.within(bound, x * per)]
        if not bad:
            continue
        i = bad[0]
        hint = ""
        if name == "creep" and np.all(np.abs(creep) <= 100.0):
            hint = "; creep is a fraction (0.05 = 5 %): the values look like percent, divide them by 100"
        raise InputError(f"{where(name, i)} = {values[i]:g}: {config.range_text(bound, unit, per)}{hint}")


def _has_peak(creep, coefficient, speed) -> bool:
    """True if at some speed |F/Q| reaches a maximum and at least two points lie beyond it."""
    for v in np.unique(speed):
        at_v = speed == v
        order = np.argsort(np.abs(creep[at_v]))
        values = np.abs(coefficient[at_v])[order]
        if values.size >= 4 and np.argmax(values) <= values.size - 3:
            return True
    return False


def identify_polach(creep, coefficient, speed, contact: HertzContact | None = None,
                    normal_force: float | None = None) -> PolachFit:
    """Fit (mu0, A, B, kA, kS) to measured F/Q against creep at one or several speeds (m/s).

    Refuses data that cannot determine the parameters: fewer than 10 points, curves that do
    not pass their peak, or a Jacobian so ill-conditioned that some combination is free.
    """
    creep, coefficient, speed = _check_data(creep, coefficient, speed)
    if not _has_peak(creep, coefficient, speed):
        raise InputError("no peak: at every speed the measured |F/Q| still rises at the largest "
                         "creep, so mu0, A, B and kS cannot be determined; measure beyond the peak")
    contact = default_contact() if contact is None else _args.instance("contact", contact, HertzContact)
    q = contact.normal_force if normal_force is None else _args.real("normal_force", normal_force, 0.0, low_open=True)

    def residual(x):
        return polach_coefficient(creep, speed, q, contact, PolachParams(*x)) - coefficient

    best = min((least_squares(residual, start, bounds=(LOWER, UPPER), x_scale="jac")
                for start in STARTS), key=lambda r: r.cost)
    jac = best.jac
    jtj = jac.T @ jac
    if np.linalg.cond(jtj) > MAX_CONDITION_NUMBER:
        _, vectors = np.linalg.eigh(jtj)
        weakest = vectors[:, 0]
        combo = " + ".join(f"{w:.2f}*{n}" for w, n in zip(weakest, PARAMETER_NAMES) if abs(w) > 0.1)
        raise InputError(f"creep, coefficient, speed (normal_force {q:g} N): the data do not determine the "
                         f"parameters: the combination {combo} "
                         "is free; add speeds or points beyond the peak")
    dof = max(creep.size - len(PARAMETER_NAMES), 1)
    covariance = np.linalg.inv(jtj) * (2.0 * best.cost / dof)
    std = dict(zip(PARAMETER_NAMES, np.sqrt(np.diag(covariance))))
    residuals = best.fun
    return PolachFit(PolachParams(*best.x), std, residuals,
                     float(np.sqrt(np.mean(residuals ** 2))), covariance)
