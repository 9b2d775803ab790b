"""The sander validation cases' one calibration and its sensitivity to the sand left loose.

sand_reference_kg_m is calibrated on one configuration of case sanders-t1107-class387 (the single
fixed-rate sander's published distance); sand_retention (the share of the loose sand an axle leaves
for the next, core/src/rail_conditioning.c) has no published value [T], so `sensitivity`
recalibrates for several values and predicts every other configuration with each.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import yaml
from scipy.optimize import brentq

from railbrake.validation.cases import load_cases
from railbrake.validation.models import sander_stopping_distance

FIXED, VARIABLE = "sanders-t1107-class387", "sanders-t1107-variable-rate"
CALIBRATION_CONFIGURATION = 2     # the single fixed-rate sander on axle 3 (the case's reference.csv)


def distance(case, configuration: int, sand_reference: float, retention: float | None = None) -> float:
    """Stopping distance (m) of a configuration of the case with these sand parameters."""
    inputs = dict(case.inputs)
    calibration = yaml.safe_load((case.folder / inputs["calibration"]).read_text())
    calibration["sand_reference_kg_m"] = sand_reference
    if retention is not None:
        calibration["sand_retention"] = retention
    with tempfile.TemporaryDirectory() as folder:   # one a call: the calibration's root finding makes many
        path = Path(folder) / "calibration.yaml"
        path.write_text(yaml.safe_dump(calibration))
        inputs["calibration"] = str(path)   # absolute, so case.folder / it is itself
        return float(sander_stopping_distance(inputs, [configuration], case).values[0])


def published(case, configuration: int) -> float:
    row = list(case.data[case.x]).index(configuration)
    return float(case.data[case.columns["value"]][row])


def calibrate(case, retention: float | None = None) -> float:
    """sand_reference_kg_m that stops the calibration configuration at its published distance."""
    target = published(case, CALIBRATION_CONFIGURATION)
    return brentq(lambda r: distance(case, CALIBRATION_CONFIGURATION, r, retention) - target, 1e-4, 1e-1,
                  xtol=1e-7, rtol=1e-6)


def sensitivity(root=None, retentions=(0.0, 0.4, 0.8)) -> list[dict]:
    """Per sand_retention: the calibrated sand_reference_kg_m and every other configuration's
    predicted and published distance (m)."""
    fixed, variable = (next(iter(load_cases(root, name))) for name in (FIXED, VARIABLE))
    rows = []
    for retention in retentions:
        found = calibrate(fixed, retention)
        row = {"sand_retention": retention, "sand_reference_kg_m": found}
        for case, configurations in ((fixed, (1, 3)), (variable, (4, 5))):
            for c in configurations:
                row[f"configuration {c} (m)"] = distance(case, c, found, retention)
        rows.append(row)
    return rows
