"""Study files (versioned YAML schema ``railbrake.study/1``): a base scenario, fixed overrides,
factors, a design and noise seeds. Reference and examples: docs/campaigns.md.

Everything that can be wrong in a study is found here, before any run starts: an unknown factor
path (with the closest valid ones), a range with low >= high, a design with no runs. Each error
names the study file, the key and its line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal

import yaml
from pydantic import AfterValidator, BaseModel, ConfigDict, Field

from railbrake import _changes, _core, config
from railbrake._args import whole
from railbrake.campaign import budget, configuration
from railbrake.campaign.factors import COMPOSITES, Factor, make_factor
from railbrake.errors import InputError

SCHEMA = "railbrake.study/1"
DESIGNS = ("grid", "zip", "latin-hypercube", "sobol", "list")
ALL = "all"   # a factor's levels: every value its key may take (a key with a fixed set of values)


class _Strict(_changes.ReadOnlyModel, BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)   # frozen: changes go through Study.with_
    OWNER: ClassVar[str] = "study"


class Design(_Strict):
    kind: Literal["grid", "zip", "latin-hypercube", "sobol", "list"]
    samples: int | None = None          # latin-hypercube, sobol (base samples N: N (d + 2) runs)
    scramble: bool = True               # sobol
    points: list[dict[str, Any]] | None = None   # list


def _bounded(bound: str, unit: str, per: float = 1.0, positive: bool = False):
    """A number in the file's unit (SI = value * per) inside the C bound `bound` (core/src/bounds.c)."""
    def check(value: float) -> float:
        if not config.within(bound, value * per) or (positive and not value > 0.0):
            low, high, why = config.bound_in(bound, per)
            raise ValueError(f"must lie in {'(' if positive else '['}{low:g}, {high:g}] {unit} ({why})")
        return value

    return Annotated[float, AfterValidator(check)]


def _fraction(value: float) -> float:
    if not 0.0 <= value <= 1.0:
        raise ValueError("must lie in [0, 1] (a fraction)")
    return value


class Criteria(_Strict):
    """Pass/fail of an assessed case (EN 15595 style)."""
    max_lock_events: int = Field(default=0, ge=0)
    min_utilisation: Annotated[float, AfterValidator(_fraction)] = 0.85
    utilisation_cases: list[str] | None = None   # levels of the reference factor it applies to (None: all
    #                                            but the reference)
    max_safety_timer_trips: int = Field(default=0, ge=0)
    max_delta_s_pct: _bounded("study.delta_s", "%", 0.01) | None = None
    max_air_drawn_kg: _bounded("study.air_drawn", "kg", positive=True) | None = None


class Assessment(_Strict):
    kind: Literal["en15595"] = "en15595"
    reference: dict[str, Any] = Field(min_length=1)   # factor values of the reference case (dry rail)
    criteria: Criteria = Field(default_factory=Criteria)
    rank: str | None = None   # a factor whose levels (e.g. wsp.controller) the report ranks on the cases
    source: str = ""


class Tuning(_Strict):
    """Ranges of the WSP parameters `wsp tune` may choose from, and the air limit."""
    params: dict[str, dict[str, Any]] = Field(default_factory=dict)
    air_limit_kg: _bounded("study.air_drawn", "kg", positive=True) | None = None
    source: str = ""


class StudyFile(_Strict):
    schema_: str = Field(alias="schema")
    name: str
    title: str = ""
    base: str
    set: dict[str, Any] = Field(default_factory=dict)
    factors: dict[str, Any] = Field(default_factory=dict)
    design: Design
    seeds: int = 1
    seed: int = Field(default=0, ge=0)   # entropy of the study's numpy SeedSequence
    timeseries: bool = False
    assessment: Assessment | None = None
    tuning: Tuning | None = None
    source: str = ""


@dataclass
class Study:
    spec: StudyFile
    origin: str
    text: str
    base: str                                  # preset name or absolute scenario path
    factors: list[Factor] = field(default_factory=list)
    fixed: dict[str, Any] = field(default_factory=dict)    # set: plain paths
    fixed_parts: dict[str, Any] = field(default_factory=dict)   # set: fault.* / zone.* parts
    keys: list[str] = field(default_factory=list)
    lines: dict = field(default_factory=dict)
    overrides: dict = field(default_factory=dict)   # key path -> label of a with_ change (for errors)
    max_runs: int = budget.MAX_RUNS                 # the limit it was checked against

    def __setattr__(self, name, value):
        if self.__dict__.get("_frozen"):   # set at the end of parse: a loaded study is immutable
            _changes.refuse_assignment("study", name)
        object.__setattr__(self, name, value)

    def _freeze(self) -> "Study":
        self.factors = tuple(self.factors)
        object.__setattr__(self, "_frozen", True)
        return self

    @property
    def name(self) -> str:
        return self.spec.name

    def where(self, *key) -> str:
        return f"{config.locator(self.origin, self.lines, self.overrides)(key)}: {'.'.join(str(k) for k in key)}"

    def with_(self, changes=None, /, **kwargs) -> "Study":
        """A copy with keys of the study file changed, e.g. ``with_(seeds=4)`` or
        ``with_({"design.samples": 64, "factors.initial_speed": ["250 km/h", "300 km/h"]})``:
        keys and values as in the file, and the whole study checked again as `campaign plan` does."""
        merged = _changes.merge(changes, kwargs, "Study.with_")
        data = config.load_mapping(self.text, self.origin)
        if "base" not in merged:
            data["base"] = self.base   # a file named relative to the study's folder, made absolute
        labels = _changes.apply_changes(data, merged, StudyFile,
                                        ("set", "factors", "design.points", "assessment.reference", "tuning.params"))
        text = yaml.safe_dump(data, sort_keys=False, allow_unicode=True)
        return parse(text, self.origin, lines=self.lines, overrides=labels,
                     max_runs=self.max_runs)

    def factor(self, name: str) -> Factor:
        return next(f for f in self.factors if f.name == name)


def _preset_dir():
    return resources.files("railbrake") / "data" / "studies"


def preset_names() -> list[str]:
    return sorted(p.name[:-5] for p in _preset_dir().iterdir() if p.name.endswith(".yaml"))


def _check_path(study: Study, key: str, where: tuple) -> None:
    """A factor or set path must be a resolved-configuration key or a fault/zone part."""
    head, _, part = key.partition(".")
    if head in COMPOSITES:
        if part not in COMPOSITES[head]:
            raise InputError(f"{study.where(*where)}: unknown {head} part {part!r} "
                             f"(parts: {', '.join(f'{head}.{p}' for p in COMPOSITES[head])})")
        return
    if key not in study.keys:
        close = configuration.closest_keys(key, study.keys + [f"{h}.{p}" for h, ps in COMPOSITES.items()
                                                               for p in ps])
        hint = f"; closest valid: {', '.join(close)}" if close else ""
        raise InputError(f"{study.where(*where)}: unknown path {key!r}{hint}")


def _check_design(study: Study) -> None:
    d = study.spec.design
    if study.spec.seeds < 1:
        raise InputError(f"{study.where('seeds')} = {study.spec.seeds}: a design with no runs (seeds >= 1)")
    if d.kind in ("latin-hypercube", "sobol"):
        if d.samples is None or d.samples < 1:
            raise InputError(f"{study.where('design', 'samples')} = {d.samples}: a design with no runs "
                             f"({d.kind} needs samples >= 1)")
        if not study.factors:
            raise InputError(f"{study.where('factors')}: a {d.kind} design needs at least one factor")
        if d.kind == "sobol" and d.samples & (d.samples - 1):
            raise InputError(f"{study.where('design', 'samples')} = {d.samples}: a Sobol design needs a "
                             "power of two")
    elif d.kind == "list":
        if not d.points:
            raise InputError(f"{study.where('design', 'points')}: a design with no runs (no points)")
        declared = {f.name for f in study.factors}
        for i, point in enumerate(d.points):
            for key in point:
                _check_path(study, key, ("design", "points", i, key))
        # every key a point sets is a factor (a column of the dataset)
        for key in dict.fromkeys(k for p in d.points for k in p):
            if key not in declared:
                levels = [p[key] for p in d.points if key in p]
                study.factors.append(make_factor(key, levels, study.where("design", "points")))
    else:
        for f in study.factors:
            if f.levels is None:
                raise InputError(f"{study.where('factors', f.name)}: a {d.kind} design needs levels "
                                 "(a list, or a range with 'levels: N')")
        if d.kind == "zip":
            lengths = {f.name: len(f.levels) for f in study.factors}
            if len(set(lengths.values())) > 1:
                raise InputError(f"{study.where('design', 'kind')} = 'zip': factors need as many levels each "
                                 f"({', '.join(f'{k}: {n}' for k, n in lengths.items())})")


def tuning_range(study: Study, key: str) -> Factor:
    """The range `wsp tune` may choose wsp.<name> from: a tuning.params range {low, high} of a WSP
    key of the resolved configuration, inside the C bound of that parameter."""
    where = study.where("tuning", "params", key)
    if not key.startswith("wsp.") or key not in study.keys:
        wsp = [k for k in study.keys if k.startswith("wsp.") and k not in ("wsp.enabled", "wsp.per_bogie")]
        raise InputError(f"{where}: not a WSP parameter (tunable: {', '.join(wsp)})")
    factor = make_factor(key, study.spec.tuning.params[key], where, max_levels=study.max_runs)
    if factor.low is None or factor.levels is not None:
        raise InputError(f"{where}: a tuning range is {{low: .., high: ..}} (no levels)")
    if key in _core.BOUNDS:
        low, high, _, why = _core.BOUNDS[key]
        if not (low <= factor.low and factor.high <= high):
            unit = factor.file_unit or ""
            per = factor.si(f"1 {unit}") if unit else 1.0
            raise InputError(f"{where}: low {factor.file_value(factor.low)!r} to high "
                             f"{factor.file_value(factor.high)!r}: must lie in [{low / per:g}, {high / per:g}]"
                             f"{' ' + unit if unit else ''} ({why})")
    return factor


def _check_assessment(study: Study) -> None:
    """The reference names factors and their levels; utilisation_cases name levels of those factors."""
    assessment = study.spec.assessment
    if assessment is None:
        return
    factors = {f.name: f for f in study.factors}
    reference_levels = []
    for key, value in assessment.reference.items():
        where = study.where("assessment", "reference", key)
        if key not in factors:
            raise InputError(f"{where}: not a factor of the study ({', '.join(factors) or 'none'})")
        factor = factors[key]
        levels = [factor.si(level) for level in factor.levels or []]
        wanted = value["name"] if isinstance(value, dict) and "name" in value else value
        try:
            found = factor.si(wanted) in levels if factor.kind != "case" else wanted in levels
        except (TypeError, ValueError, KeyError):
            found = False
        if not found:
            shown = [level["name"] if isinstance(level, dict) else level for level in factor.levels or []]
            raise InputError(f"{where} = {value!r}: not a level of factor {key} "
                             f"({', '.join(map(str, shown)) or 'a range without levels'})")
        reference_levels += levels
    if assessment.rank is not None and (assessment.rank not in factors or assessment.rank in assessment.reference):
        raise InputError(f"{study.where('assessment', 'rank')} = {assessment.rank!r}: must be a factor of the study "
                         f"other than the reference's ({', '.join(f for f in factors if f not in assessment.reference)})")
    for i, case in enumerate(assessment.criteria.utilisation_cases or []):
        if case not in reference_levels:
            raise InputError(f"{study.where('assessment', 'criteria', 'utilisation_cases', i)} = {case!r}: not a "
                             f"level of the reference's factors ({', '.join(map(str, reference_levels))})")


def _check_tuning(study: Study) -> None:
    if study.spec.tuning is not None:
        for key in study.spec.tuning.params:
            tuning_range(study, key)


def _check_size(study: Study, max_runs: int) -> None:
    """The design's run count, from the design alone, within max_runs (budget.MAX_RUNS by default)."""
    d = study.spec.design
    levels = [len(f.levels) for f in study.factors if f.levels is not None]
    points = budget.design_runs(d.kind, d.samples, levels, len(d.points or []))
    runs = points * study.spec.seeds
    if runs > max_runs:
        key = ("seeds",) if points <= max_runs else \
            ("design", "samples") if d.kind in ("latin-hypercube", "sobol") else ("design",)
        first = {f.name: f.at(0.0) for f in study.factors}

        def measure():
            from railbrake.campaign.points import point_sets
            base_tree = configuration.tree(configuration.resolve(study.base))
            return budget.measure_one(study.base, point_sets(study, first, base_tree))

        budget.refuse(study.where(*key), runs, budget.describe(d.kind, d.samples, levels, study.spec.seeds),
                      max_runs, measure)


def _all_levels(study: Study, key: str) -> list:
    """`KEY: all`: every value the schema allows for KEY (e.g. every WSP controller the core has)."""
    _check_path(study, key, ("factors", key))
    from railbrake import resolve
    levels = resolve.choices(key)
    if not levels:
        raise InputError(f"{study.where('factors', key)} = {ALL!r}: {key} has no fixed set of values to take "
                         "them all from; give its levels as a list")
    return list(levels)


def parse(text: str, origin: str, folder: Path | None = None, lines: dict | None = None,
          overrides: dict | None = None, max_runs: int = budget.MAX_RUNS) -> Study:
    """The study of a file's text; lines and overrides (of Study.with_) say where keys came from;
    a design of more than max_runs runs is refused before it is drawn."""
    max_runs = whole("max_runs", max_runs, 1)
    lines = config.line_index(text) if lines is None else lines
    spec = config.validate_data(config.load_mapping(text, origin), StudyFile,
                                config.locator(origin, lines, overrides))
    study = Study(spec, origin, text, spec.base, lines=lines, overrides=dict(overrides or {}))
    if spec.schema_ != SCHEMA:
        raise InputError(f"{study.where('schema')} = {spec.schema_!r}: expected {SCHEMA!r}")
    base_path = (folder or Path.cwd()) / spec.base
    if not Path(spec.base).is_absolute() and base_path.is_file():
        study.base = str(base_path.resolve())
    try:
        resolved = configuration.resolve(study.base)
    except InputError as exc:
        raise InputError(f"{study.where('base')} = {spec.base!r}: {exc}") from None
    study.keys = configuration.valid_keys(resolved)
    for key, value in spec.set.items():
        _check_path(study, key, ("set", key))
        hint = config.named_unit_hint(key, value)   # '60 t' for train.car_types.motor.tare_t: a bare number
        if hint:
            raise InputError(f"{study.where('set', key)} = {value!r}: {hint}")
        target = study.fixed_parts if key.partition(".")[0] in COMPOSITES else study.fixed
        target[key] = value
    for name, value in spec.factors.items():
        if value == ALL:
            value = _all_levels(study, name)
        factor = make_factor(name, value, study.where("factors", name), max_levels=max_runs)
        if factor.bundle:   # a named case: its name is free, the keys it sets are paths
            for i, level in enumerate(factor.levels):
                for key in level:
                    if key != "name":
                        _check_path(study, key, ("factors", name, i, key))
        else:
            _check_path(study, name, ("factors", name))
        study.factors.append(factor)
    _check_design(study)
    study.max_runs = max_runs   # kept for with_ and tuning ranges
    _check_size(study, max_runs)
    _check_assessment(study)
    _check_tuning(study)
    return study._freeze()


def load(study: str | Path, max_runs: int = budget.MAX_RUNS) -> Study:
    """A preset study name (railbrake/data/studies) or a study YAML file (read as every
    configuration file is: a regular file under config.MAX_BYTES); a design of more than max_runs
    runs is refused before it is drawn."""
    if not isinstance(study, (str, Path)):
        raise TypeError(f"study = {study!r}: must be a preset study name or a file path")
    name = str(study)
    if name in preset_names():
        return parse((_preset_dir() / f"{name}.yaml").read_text(), f"study {name}", max_runs=max_runs)
    path = Path(name)
    if not name.strip() or not path.exists():
        raise InputError(f"study = {name!r}: not a preset study ({', '.join(preset_names())}) nor a file")
    if not path.is_file():   # a directory, a FIFO, a device: never read
        raise InputError(f"study = {name!r}: not a regular file")
    return parse(config.read_text(path), str(path), path.resolve().parent, max_runs=max_runs)
