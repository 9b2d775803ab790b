"""Calibrate the sand's conditioning strength (sand_reference_kg_m) of the sander validation case.

Run: python tools/calibrate_sanders.py [--sensitivity]
It finds, by root-finding on a logarithmic bracket, the sand_reference_kg_m with which the model of
case sanders-t1107-class387 (railbrake.validation.models.sander_stopping_distance) stops its
calibration configuration (the single fixed-rate sander, named in calibration.yaml's calibrated_on)
at the published distance, and prints it; the value is written into the case's calibration.yaml by
hand. Only that one parameter, on that one configuration: every other row of the cases is a
prediction. With --sensitivity it does so for sand_retention (the [T] share of the loose sand an
axle leaves for the next) from 0 to 0.8 and prints every configuration's predicted distance with
each (railbrake.validation.sanders).
"""

import sys

from railbrake.validation import load_cases
from railbrake.validation.sanders import CALIBRATION_CONFIGURATION, FIXED, calibrate, distance, published, sensitivity


def main(*options: str) -> None:
    if "--sensitivity" in options:
        for row in sensitivity(retentions=(0.0, 0.2, 0.4, 0.6, 0.8)):
            print(", ".join(f"{k} {v:.4g}" for k, v in row.items()))
        return
    case = next(iter(load_cases(None, FIXED)))
    value = float(f"{calibrate(case):.4g}")   # as written into calibration.yaml; the stop is not smooth in it
    print(f"configuration {CALIBRATION_CONFIGURATION}: {published(case, CALIBRATION_CONFIGURATION):.0f} m published; "
          f"sand_reference_kg_m = {value:.4g} gives {distance(case, CALIBRATION_CONFIGURATION, value):.1f} m")


if __name__ == "__main__":
    main(*sys.argv[1:])
