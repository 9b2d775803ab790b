"""Every adhesion condition against every measured adhesion-speed data set of the validation cases.

A data set is the reference of a validation case run with the model peak_adhesion (its file and
source in the case's folder); each condition is evaluated as that case evaluates its own (the same
axle, car or train mean) at the data's speeds that lie inside the condition's validity. The cell is
the mean relative residual (peak / measured - 1); "outside" where no speed of the data set lies
inside the condition's validity. fit_table: per condition, the data sets its fit used and those it
is only checked on (each with that residual), its validity, and the findings of its fit.
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


def residuals(condition: adhesion.AdhesionCondition, case: Case) -> np.ndarray | str:
    """peak / measured - 1 at each of the case's speeds inside the condition's validity (OUTSIDE if none)."""
    speeds = np.asarray(case.data[case.x], dtype=float)
    measured = np.asarray(case.data[case.columns["value"]], dtype=float)
    valid = condition.validity
    inside = [i for i, v in enumerate(speeds) if valid is None or valid.contains(float(v))]
    if not inside:
        return OUTSIDE
    axles = _axles(case.inputs)
    return np.array([np.mean([adhesion.peak_adhesion(condition, units.kmh_to_ms(float(speeds[i])), a).coefficient
                              for a in axles]) / measured[i] - 1.0 for i in inside])


def residual(condition: adhesion.AdhesionCondition, case: Case) -> float | str:
    """Mean of peak / measured - 1 over the case's speeds inside the condition's validity."""
    r = residuals(condition, case)
    return r if isinstance(r, str) else float(np.mean(r))


def condition_table(root=None) -> dict:
    """{condition name: {data set (case id): mean relative residual or OUTSIDE}}."""
    cases = data_sets(root)
    return {c.name: {case.id: residual(c, case) for case in cases} for c in adhesion.conditions()}


def _with_residuals(condition: adhesion.AdhesionCondition, ids, cases: dict) -> str:
    parts = []
    for case_id in ids:
        r = residuals(condition, cases[case_id]) if case_id in cases else "missing"
        if isinstance(r, str):
            parts.append(f"{case_id} ({r})")
        else:
            worst = r[np.argmax(np.abs(r))]
            parts.append(f"{case_id} (mean {100 * np.mean(r):+.0f} %, worst {100 * worst:+.0f} %)")
    return "; ".join(parts) or "none"


def fit_table(root=None) -> dict:
    """{condition name: {"fitted on", "checked on", "speed km/h", "creep", "at a bound"}}: the data
    sets with the condition's mean and worst residual on each (a fit checked on its own data is not a
    validation: only "checked on" validates), where it holds, and the findings of its fit."""
    cases = {c.id: c for c in data_sets(root)}
    rows = {}
    for c in adhesion.conditions():
        fit, valid = c.fit, c.validity
        rows[c.name] = {
            "fitted on": _with_residuals(c, fit.fitted_on, cases) if fit and fit.fitted_on
            else f"no data set: {fit.no_data}" if fit else "no fit block",
            "checked on": _with_residuals(c, fit.checked_on, cases) if fit else "none",
            "speed km/h": f"{valid.speed_min_kmh:g}-{valid.speed_max_kmh:g}" if valid else "any",
            "creep": fit.creep if fit else "",
            "at a bound": "; ".join(f"{k}: {v}" for k, v in fit.at_bound.items()) if fit and fit.at_bound else "none",
        }
    return rows
