"""The brake calculation as engineers report it (``railbrake report brake``): braked weight and
brake percentage (UIC 544-1), EN 14531-1 mean decelerations and the emergency stopping distances
against the TSI table, from the C stopping-distance calculation with the train's simulated build-up.
Published figures: data/brakecalc/brake_calculation.yaml, with their sources."""

from railbrake.brakecalc.calc import (BrakeCalculation, brake_percentage, braked_weight, braking_curve, calculate,
                                      equivalent_deceleration, interval_decelerations, settings,
                                      uic_stopping_distance)
from railbrake.brakecalc.report import as_json, to_html, write

__all__ = ["BrakeCalculation", "as_json", "brake_percentage", "braked_weight", "braking_curve", "calculate",
           "equivalent_deceleration", "interval_decelerations", "settings", "to_html",
           "uic_stopping_distance", "write"]
