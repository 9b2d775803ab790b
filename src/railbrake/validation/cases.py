"""Case folders: parsing ``case.yaml`` and ``reference.csv``; a bad folder becomes a BrokenCase.

Where the cases are: ``--cases DIR``, else ``$RAILBRAKE_VALIDATION_DIR``, else the repository's
``validation/`` folder (found from the source tree or the current directory), else the copy
installed with the package (``railbrake/validation/cases``, put there by CMake's install step).
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np
import yaml

from railbrake import _args, config
from railbrake.errors import InputError

KINDS = ("verification", "code-to-code", "validation")
AREAS = ("contact", "adhesion", "pneumatics", "valves", "vehicle", "real-time plant", "etcs")
COMPARISONS = ("value", "band")
ENV_VAR = "RAILBRAKE_VALIDATION_DIR"


@dataclass(frozen=True)
class Tolerance:
    value: float
    unit: str  # "%" relative to |reference|, else the quantity's own unit

    def text(self) -> str:
        return f"{self.value:g} %" if self.unit == "%" else f"{self.value:g} {self.unit}"


@dataclass
class Case:
    id: str
    title: str
    kind: str
    area: str
    folder: Path
    model: str                       # function name in railbrake.validation.models
    inputs: dict
    quantity: str
    unit: str
    x: str | None                    # column of reference.csv the model is evaluated at
    x_unit: str | None
    columns: dict                    # reference columns: value (and low, high for a band)
    data: dict                       # column name -> np.ndarray
    comparison: str
    tolerance: Tolerance
    tolerance_reason: str
    source: dict
    fast: bool = True
    expected_failure: str | None = None  # a known finding: why the model misses this reference
    notes: str = ""


@dataclass
class BrokenCase:
    id: str
    folder: Path
    reason: str
    kind: str = "unknown"
    area: str = "unknown"
    title: str = ""
    fast: bool = True
    source: dict = field(default_factory=dict)


def _repo_validation_dir() -> Path | None:
    here = Path(__file__).resolve()
    for parent in [Path.cwd(), *here.parents]:
        candidate = parent / "validation"
        if candidate.is_dir() and any(candidate.glob("*/*/case.yaml")):
            return candidate
    return None


def case_root(cases: Path | str | None = None, argument: str = "cases") -> Path:
    """The folder holding <kind>/<id>/case.yaml; a clear error when none can be found."""
    if cases is not None:
        root = _args.path(argument, cases)
        if not root.is_dir():
            raise InputError(f"{argument} (--cases) = {_args.show(str(root))}: not a folder")
        return root
    if os.environ.get(ENV_VAR):
        return case_root(os.environ[ENV_VAR])
    repo = _repo_validation_dir()
    if repo is not None:
        return repo
    installed = Path(str(resources.files("railbrake") / "validation" / "cases"))
    if installed.is_dir():
        return installed
    raise InputError(f"no validation cases found: give --cases DIR or set {ENV_VAR} to the "
                     "repository's validation/ folder")


def _fail(where: str, message: str):
    raise InputError(f"{where}: {message}")


def _tolerance(raw, where: str) -> Tolerance:
    if not isinstance(raw, dict):
        _fail(where, f"tolerance = {raw!r}: give a mapping {{value: ..., unit: ...}}")
    if "unit" not in raw or raw["unit"] in (None, ""):
        _fail(where, f"tolerance = {raw!r}: no unit (use '%' for relative, or the quantity's unit)")
    try:
        value = float(raw["value"])
    except (KeyError, TypeError, ValueError):
        _fail(where, f"tolerance.value = {raw.get('value')!r}: must be a number")
    if not value >= 0:
        _fail(where, f"tolerance.value = {value}: must be >= 0")
    return Tolerance(value, str(raw["unit"]))


def read_reference(path: Path, open_ends: dict | None = None) -> dict:
    """Columns of a CSV with a header row; '#' lines are comments. Every cell must be a number;
    open_ends {column: -inf or inf} lets those columns hold that infinity (a one-sided band)."""
    if not path.is_file():
        raise InputError(f"{path}: reference file missing")
    with io.StringIO(config.read_text(path), newline="") as f:   # a regular file under the size limit
        rows = [r for r in csv.reader(f) if r and not r[0].lstrip().startswith("#")]
    if len(rows) < 2:
        raise InputError(f"{path}: needs a header row and at least one row of numbers")
    header = [h.strip() for h in rows[0]]
    values = []
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise InputError(f"{path}, data row {line - 1}: {len(row)} cells for {len(header)} columns")
        try:
            values.append([float(c) for c in row])
        except ValueError:
            bad = next(c for c in row if not _is_number(c))
            raise InputError(f"{path}, data row {line - 1}: {bad.strip()!r} is not a number") from None
    array = np.array(values, dtype=float)
    allowed = np.array([[np.isfinite(x) or x == (open_ends or {}).get(name) for name, x in zip(header, row)]
                        for row in array])
    if not np.all(allowed):
        raise InputError(f"{path}: non-finite value" + (" (only -inf in a band's low column, inf in its high "
                                                         "column)" if open_ends else ""))
    return {name: array[:, i] for i, name in enumerate(header)}


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def _required(raw: dict, key: str, where: str):
    if key not in raw or raw[key] in (None, ""):
        _fail(where, f"missing key {key!r}")
    return raw[key]


def parse_case(folder: Path) -> Case:
    where = str(folder / "case.yaml")
    if not (folder / "case.yaml").is_file():
        _fail(str(folder), "case.yaml missing")
    try:
        raw = yaml.safe_load(config.read_text(folder / "case.yaml"))
    except yaml.YAMLError as exc:
        _fail(where, f"not valid YAML ({exc})")
    if not isinstance(raw, dict):
        _fail(where, "must be a mapping")
    kind = _required(raw, "kind", where)
    if kind not in KINDS:
        _fail(where, f"kind = {kind!r}: must be one of {', '.join(KINDS)}")
    area = _required(raw, "area", where)
    if area not in AREAS:
        _fail(where, f"area = {area!r}: must be one of {', '.join(AREAS)}")
    quantity = _required(raw, "quantity", where)
    if not isinstance(quantity, dict) or "unit" not in quantity or "name" not in quantity:
        _fail(where, f"quantity = {quantity!r}: give {{name: ..., unit: ...}} ('-' if dimensionless)")
    tolerance = _tolerance(_required(raw, "tolerance", where), where)
    if tolerance.unit not in ("%", quantity["unit"]):
        _fail(where, f"tolerance unit {tolerance.unit!r}: must be '%' or the quantity's unit "
                     f"{quantity['unit']!r}")
    source = _required(raw, "source", where)
    if not isinstance(source, dict) or not source.get("reference"):
        _fail(where, "source: give at least {reference: publication, table/figure, page}")
    ref = _required(raw, "reference", where)
    comparison = ref.get("comparison", "value")
    open_ends = {ref.get("low"): -np.inf, ref.get("high"): np.inf} if comparison == "band" else None
    data = read_reference(folder / ref.get("file", "reference.csv"), open_ends)
    if comparison not in COMPARISONS:
        _fail(where, f"reference.comparison = {comparison!r}: must be one of {', '.join(COMPARISONS)}")
    columns = {"value": ref.get("value")}
    if comparison == "band":
        columns.update(low=ref.get("low"), high=ref.get("high"))
    x = ref.get("x")
    for role, name in [*columns.items(), *([("x", x)] if x else [])]:
        if not name:
            _fail(where, f"reference.{role}: missing column name")
        if name not in data:
            _fail(where, f"reference.{role} = {name!r}: no such column in the CSV ({', '.join(data)})")
    model = _required(raw, "model", where)
    return Case(
        id=str(raw.get("id", folder.name)), title=_required(raw, "title", where), kind=kind, area=area,
        folder=folder, model=_required(model, "function", where), inputs=model.get("inputs", {}) or {},
        quantity=quantity["name"], unit=str(quantity["unit"]), x=x, x_unit=ref.get("x_unit"),
        columns=columns, data=data, comparison=comparison, tolerance=tolerance,
        tolerance_reason=_required(raw, "tolerance_reason", where), source=source,
        fast=bool(raw.get("fast", True)), expected_failure=raw.get("expected_failure"),
        notes=" ".join(str(raw.get("notes", "")).split()))


def load_cases(root: Path | str | None = None, case_id: str | None = None,
               kind: str | None = None) -> list:
    """Every case folder under root (Case or BrokenCase), filtered by id or kind."""
    if kind is not None:
        _args.choice("kind", kind, KINDS)
    if case_id is not None:
        _args.text("case_id", case_id)
    base = case_root(root, "root")
    folders = sorted(p.parent for p in base.glob("*/*/case.yaml"))
    folders += sorted(p for p in base.glob("*/*") if p.is_dir() and not (p / "case.yaml").exists()
                      and any(p.iterdir()))
    out = []
    for folder in folders:
        if case_id is not None and folder.name != case_id:
            continue
        try:
            case = parse_case(folder)
        except InputError as exc:
            case = BrokenCase(folder.name, folder, str(exc), kind=folder.parent.name)
        if kind is None or case.kind == kind:
            out.append(case)
    if case_id is not None and not out:
        raise InputError(f"case_id (--case) = {_args.show(case_id)}: no such case under {base}")
    return out
