"""Every adhesion condition against every measured adhesion-speed data set of the validation cases.

A data set is the reference of a validation case run with the model peak_adhesion (its file and
source in the case's folder); each condition is evaluated as that case evaluates its own (the same
axle, car or train mean) at the data's speeds that lie inside the condition's validity. The cell is
the mean relative residual (peak / measured - 1); "outside" where no speed of the data set lies
inside the condition's validity.
"""

from __future__ import annotations

import numpy as np

from railbrake import adhesion, units
from railbrake.validation.cases import Case, load_cases

OUTSIDE = "outside"


def data_sets(root=None) -> list[Case]:
    """The validation cases whose model is peak_adhesion (a measured or published adhesion curve)."""
    return [c for c in load_cases(root, kind="validation")
            if isinstance(c, Case) and c.model == "peak_adhesion"]


def _axles(inputs: dict) -> list[int]:
    if "car" in inputs:
        return list(adhesion.car_axles(int(inputs["car"])))
    if "cars" in inputs:
        return list(range(adhesion.AXLES_PER_CAR * int(inputs["cars"])))
    return [int(inputs.get("axle", 0))]


def residual(condition: adhesion.AdhesionCondition, case: Case) -> float | str:
    """Mean of peak / measured - 1 over the case's speeds inside the condition's validity."""
    speeds = np.asarray(case.data[case.x], dtype=float)
    measured = np.asarray(case.data[case.columns["value"]], dtype=float)
    valid = condition.validity
    inside = [i for i, v in enumerate(speeds) if valid is None or valid.contains(float(v))]
    if not inside:
        return OUTSIDE
    axles = _axles(case.inputs)
    ratios = [np.mean([adhesion.peak_adhesion(condition, units.kmh_to_ms(float(speeds[i])), a).coefficient
                       for a in axles]) / measured[i] - 1.0 for i in inside]
    return float(np.mean(ratios))


def condition_table(root=None) -> dict:
    """{condition name: {data set (case id): mean relative residual or OUTSIDE}}."""
    cases = data_sets(root)
    return {c.name: {case.id: residual(c, case) for case in cases} for c in adhesion.conditions()}
