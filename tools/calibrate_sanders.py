"""Calibrate the sand's conditioning strength (sand_reference_kg_m) of a sander validation case.

Run: python tools/calibrate_sanders.py [case folder]
(default validation/validation/sanders-t1107-class387). It finds, by bisection on a logarithmic
bracket, the sand_reference_kg_m with which the case's model (railbrake.validation.models.
sander_stopping_distance) stops its calibration configuration (the case's reference row whose low
equals its high and whose configuration is named in calibration.yaml's calibrated_on) at the
published distance, and prints it; the value is written into the case's calibration.yaml by hand.
Only that one parameter, on that one configuration: every other row of the case is a prediction.
With --sensitivity it does so for sand_retention (the [T] share of the loose sand an axle leaves for
the next) from 0 to 0.8 and prints every configuration's predicted distance with each.
"""

import sys
import tempfile
from pathlib import Path

import yaml
from scipy.optimize import brentq

from railbrake.validation import load_cases
from railbrake.validation.models import sander_stopping_distance

CALIBRATION_CONFIGURATION = 2     # the single fixed-rate sander on axle 3 (the case's reference.csv)


def distance(case, configuration: int, sand_reference: float, retention: float | None = None) -> float:
    inputs = dict(case.inputs)
    calibration = yaml.safe_load((case.folder / inputs["calibration"]).read_text())
    calibration["sand_reference_kg_m"] = sand_reference
    if retention is not None:
        calibration["sand_retention"] = retention
    path = Path(tempfile.mkdtemp()) / "calibration.yaml"
    path.write_text(yaml.safe_dump(calibration))
    inputs["calibration"] = str(path)   # absolute, so case.folder / it is itself
    return float(sander_stopping_distance(inputs, [configuration], case).values[0])


def calibrate(case, target: float, retention: float | None = None) -> float:
    return brentq(lambda r: distance(case, CALIBRATION_CONFIGURATION, r, retention) - target, 1e-4, 1e-1,
                  xtol=1e-7, rtol=1e-6)


def sensitivity(case, target: float) -> None:
    variable = next(c for c in load_cases(case.folder.parent.parent, "sanders-t1107-variable-rate"))
    for retention in (0.0, 0.2, 0.4, 0.6, 0.8):
        found = calibrate(case, target, retention)
        rows = [(c, distance(case, c, found, retention)) for c in (1, 3)]
        rows += [(c, distance(variable, c, found, retention)) for c in (4, 5)]
        print(f"sand_retention {retention:.1f}: sand_reference_kg_m {found:.4g}; "
              + ", ".join(f"configuration {c}: {d:.0f} m" for c, d in rows))


def main(folder: str = "validation/validation/sanders-t1107-class387", *options: str) -> None:
    folder = Path(folder)
    case = next(c for c in load_cases(folder.parent.parent, folder.name))
    row = list(case.data[case.x]).index(CALIBRATION_CONFIGURATION)
    target = float(case.data[case.columns["value"]][row])
    if "--sensitivity" in options:
        sensitivity(case, target)
        return
    found = calibrate(case, target)
    value = float(f"{found:.4g}")   # as written into calibration.yaml; the stop is not smooth in it
    print(f"configuration {CALIBRATION_CONFIGURATION}: {target:.0f} m published; sand_reference_kg_m = {value:.4g} "
          f"gives {distance(case, CALIBRATION_CONFIGURATION, value):.1f} m")


if __name__ == "__main__":
    args = sys.argv[1:]
    main(*([a for a in args if not a.startswith("--")] or ["validation/validation/sanders-t1107-class387"]),
         *[a for a in args if a.startswith("--")])
