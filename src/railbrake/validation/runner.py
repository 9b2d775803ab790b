"""Evaluate cases: the model at the reference's points, the difference, the tolerance, the verdict.

A model function or an input that raises becomes a *broken* case with the reason, so one bad
folder never stops the run and never counts as a pass.
"""

from __future__ import annotations

import time
import traceback
import warnings
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from railbrake import _args
from railbrake.errors import InputError
from railbrake.validation import models
from railbrake.validation.cases import BrokenCase, Case


@dataclass
class CaseResult:
    id: str
    kind: str
    area: str
    title: str
    status: str                      # "pass", "fail" or "broken"
    reason: str = ""
    quantity: str = ""
    unit: str = ""
    x_name: str | None = None
    x: np.ndarray | None = None
    reference: np.ndarray | None = None
    low: np.ndarray | None = None
    high: np.ndarray | None = None
    model: np.ndarray | None = None
    difference: float | None = None  # worst difference, in the tolerance's unit
    tolerance: str = ""
    tolerance_reason: str = ""
    source: dict = field(default_factory=dict)
    details: dict = field(default_factory=dict)
    curve: dict | None = None        # a dense model curve for the plot: {"x": ..., "y": ...}
    seconds: float = 0.0
    fast: bool = True

    @property
    def passed(self) -> bool:
        return self.status == "pass"


def _broken(case, reason: str) -> CaseResult:
    return CaseResult(case.id, case.kind, case.area, case.title, "broken", reason,
                      source=case.source, fast=case.fast)


def _worst(case: Case, model: np.ndarray) -> float:
    ref = case.data[case.columns["value"]]
    if case.comparison == "band":
        low, high = case.data[case.columns["low"]], case.data[case.columns["high"]]
        gap = np.maximum(low - model, 0.0) + np.maximum(model - high, 0.0)
    else:
        gap = np.abs(model - ref)
    if case.tolerance.unit == "%":
        if np.any(ref == 0):
            raise InputError(f"{case.folder / 'reference.csv'}: a relative tolerance needs a non-zero reference")
        gap = 100.0 * gap / np.abs(ref)
    return float(np.max(gap))


def evaluate(case: Case) -> CaseResult:
    function: Callable | None = models.REGISTRY.get(case.model)
    if function is None:
        return _broken(case, f"model.function = {case.model!r}: unknown (known: {', '.join(sorted(models.REGISTRY))})")
    x = case.data[case.x] if case.x else None
    start = time.perf_counter()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            out = function(dict(case.inputs), x, case)
    except (InputError, ValueError, TypeError, KeyError, FileNotFoundError) as exc:
        return _broken(case, f"model {case.model} failed: {type(exc).__name__}: {exc}")
    except Exception as exc:  # a bug in an adapter must still not stop the run
        last = traceback.extract_tb(exc.__traceback__)[-1]
        return _broken(case, f"model {case.model} raised {type(exc).__name__}: {exc} ({last.filename}:{last.lineno})")
    seconds = time.perf_counter() - start
    result = out if isinstance(out, models.ModelOutput) else models.ModelOutput(out)
    value = np.atleast_1d(np.asarray(result.values, dtype=float))
    ref = case.data[case.columns["value"]]
    if value.shape != ref.shape:
        return _broken(case, f"model gave {value.size} values for {ref.size} reference rows")
    if not np.all(np.isfinite(value)):
        return _broken(case, f"model {case.model} gave a non-finite value")
    try:
        worst = _worst(case, value)
    except InputError as exc:
        return _broken(case, str(exc))
    passed = worst <= case.tolerance.value
    unit = "%" if case.tolerance.unit == "%" else case.unit
    reason = "" if passed else (
        f"difference {worst:.4g} {unit} exceeds the tolerance {case.tolerance.text()}"
        + (f": {case.expected_failure}" if case.expected_failure else ""))
    details = dict(result.details)
    if caught:
        details["warnings"] = sorted({str(w.message) for w in caught})
    band = case.comparison == "band"
    return CaseResult(
        case.id, case.kind, case.area, case.title, "pass" if passed else "fail", " ".join(reason.split()),
        quantity=case.quantity, unit=case.unit, x_name=case.x, x=x, reference=ref,
        low=case.data[case.columns["low"]] if band else None,
        high=case.data[case.columns["high"]] if band else None, model=value, difference=worst,
        tolerance=case.tolerance.text(), tolerance_reason=" ".join(case.tolerance_reason.split()),
        source=case.source, details=details, curve=result.curve, seconds=seconds, fast=case.fast)


def run_cases(cases, fast_only: bool = False, progress: Callable[[str, int, int], None] | None = None) -> list:
    cases = _args.items("cases", cases, (Case, BrokenCase), low=0)
    fast_only, progress = _args.flag("fast_only", fast_only), _args.function("progress", progress)
    selected = [c for c in cases if c.fast or not fast_only]
    results = []
    for i, case in enumerate(selected):
        if progress is not None:
            progress(case.id, i, len(selected))
        if isinstance(case, BrokenCase):
            results.append(_broken(case, case.reason))
        else:
            results.append(evaluate(case))
    return results


def summary(results) -> dict:
    return {"passed": sum(r.status == "pass" for r in results),
            "failed": sum(r.status == "fail" for r in results),
            "broken": sum(r.status == "broken" for r in results)}
