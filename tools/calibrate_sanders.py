"""Calibrate the sand's conditioning strength (sand_reference_kg_m) of a sander validation case.

Run: python tools/calibrate_sanders.py [case folder]
(default validation/validation/sanders-t1107-class387). It finds, by bisection on a logarithmic
bracket, the sand_reference_kg_m with which the case's model (railbrake.validation.models.
sander_stopping_distance) stops its calibration configuration (the case's reference row whose low
equals its high and whose configuration is named in calibration.yaml's calibrated_on) at the
published distance, and prints it; the value is written into the case's calibration.yaml by hand.
Only that one parameter, on that one configuration: every other row of the case is a prediction.
"""

import sys
import tempfile
from pathlib import Path

import yaml
from scipy.optimize import brentq

from railbrake.validation import load_cases
from railbrake.validation.models import sander_stopping_distance

CALIBRATION_CONFIGURATION = 2     # the single fixed-rate sander on axle 3 (the case's reference.csv)


def distance(case, configuration: int, sand_reference: float) -> float:
    inputs = dict(case.inputs)
    calibration = yaml.safe_load((case.folder / inputs["calibration"]).read_text())
    calibration["sand_reference_kg_m"] = sand_reference
    path = Path(tempfile.mkdtemp()) / "calibration.yaml"
    path.write_text(yaml.safe_dump(calibration))
    inputs["calibration"] = str(path)   # absolute, so case.folder / it is itself
    return float(sander_stopping_distance(inputs, [configuration], case).values[0])


def main(folder: str = "validation/validation/sanders-t1107-class387") -> None:
    folder = Path(folder)
    case = next(c for c in load_cases(folder.parent.parent, folder.name))
    row = list(case.data[case.x]).index(CALIBRATION_CONFIGURATION)
    target = float(case.data[case.columns["value"]][row])
    found = brentq(lambda r: distance(case, CALIBRATION_CONFIGURATION, r) - target, 1e-4, 1e-1, xtol=1e-7, rtol=1e-6)
    value = float(f"{found:.4g}")   # as written into calibration.yaml; the stop is not smooth in it
    print(f"configuration {CALIBRATION_CONFIGURATION}: {target:.0f} m published; sand_reference_kg_m = {value:.4g} "
          f"gives {distance(case, CALIBRATION_CONFIGURATION, value):.1f} m")


if __name__ == "__main__":
    main(*sys.argv[1:])
