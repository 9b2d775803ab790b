"""Adhesion conditions, peak adhesion and the fit of Polach's parameters to measurements."""

from railbrake.adhesion.conditions import (
    AXLES_PER_CAR,
    AdhesionCondition,
    AdhesionRangeWarning,
    CreepCurve,
    EnergyConditioning,
    Fit,
    Peak,
    RailConditioning,
    car_axles,
    car_max_adhesion,
    car_of_axle,
    conditions,
    creep_curves,
    creep_outside_validity,
    load_condition,
    peak_adhesion,
    preset_names,
    run_outside_validity,
    warn_outside_range,
)

_FIT = ("PolachFit", "check_points", "identify_polach")


def __getattr__(name):
    """The fit (and scipy.optimize, most of a second to import) loads when first used, not with
    every scenario that names an adhesion condition."""
    if name in _FIT:
        from railbrake.adhesion import fit
        return getattr(fit, name)
    raise AttributeError(f"module 'railbrake.adhesion' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_FIT))   # the lazy names too (help(), the API reference)

__all__ = [
    "AXLES_PER_CAR", "AdhesionCondition", "AdhesionRangeWarning", "CreepCurve", "EnergyConditioning",
    "Fit", "Peak", "PolachFit", "RailConditioning",
    "car_axles", "car_of_axle", "check_points", "conditions", "creep_curves", "creep_outside_validity",
    "identify_polach", "load_condition",
    "peak_adhesion", "preset_names", "run_outside_validity", "warn_outside_range",
]
