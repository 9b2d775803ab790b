"""Verification and validation: the models against analytic solutions, other codes and measurements.

A *case* is a folder ``validation/<kind>/<id>/`` with ``case.yaml`` (inputs, the model function,
the quantity, the tolerance with its unit and reason, the source) and ``reference.csv``. The
runner evaluates each case's model (railbrake.validation.models), compares it with the reference
and reports pass, fail or broken (a case folder that cannot be evaluated, with the reason).
Report: railbrake.validation.report (HTML with embedded plots, Markdown, JSON). Model: docs/validation.md.
"""

from railbrake.validation.cases import Case, BrokenCase, case_root, load_cases
from railbrake.validation.runner import CaseResult, run_cases

__all__ = ["BrokenCase", "Case", "CaseResult", "case_root", "load_cases", "run_cases"]
