"""Adhesion conditions, peak adhesion and the fit of Polach's parameters to measurements."""

from railbrake.adhesion.conditions import (
    AXLES_PER_CAR,
    AdhesionCondition,
    AdhesionRangeWarning,
    CreepCurve,
    EnergyConditioning,
    Peak,
    RailConditioning,
    car_axles,
    car_of_axle,
    conditions,
    creep_curves,
    load_condition,
    peak_adhesion,
    preset_names,
    warn_outside_range,
)
from railbrake.adhesion.fit import PolachFit, check_points, identify_polach

__all__ = [
    "AXLES_PER_CAR", "AdhesionCondition", "AdhesionRangeWarning", "CreepCurve", "EnergyConditioning",
    "Peak", "PolachFit", "RailConditioning",
    "car_axles", "car_of_axle", "check_points", "conditions", "creep_curves", "identify_polach", "load_condition",
    "peak_adhesion", "preset_names", "warn_outside_range",
]
