"""WSP tuning over a study's cases (`railbrake wsp tune`).

Each evaluation runs every case of the study (on the same Dask cluster as a campaign) with a
set of WSP parameters and assesses them as the EN 15595-style assessment does. Objectives:
- worst-delta-s: minimise the worst dS % over the reduced-adhesion cases, subject to no wheel
  lock and the air limit (a penalty outside them), with Optuna's TPE sampler;
- pareto: the front of worst dS % against the air drawn (Optuna's NSGA-II), no lock as a
  constraint.
Trials live in an Optuna RDB storage (sqlite in the output folder): an interrupted tuning goes on
from the trials it stored. The first trial is the default WSP, so "tuned" is never worse.
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railbrake import atomic
from railbrake.campaign import execute
from railbrake.campaign.assess import assess, worst
from railbrake.campaign.factors import Factor
from railbrake.campaign.plan import plan
from railbrake.campaign.study import Study, tuning_range
from railbrake._args import whole
from railbrake.errors import InputError

OBJECTIVES = ("worst-delta-s", "pareto")
PENALTY = 1000.0    # % of dS per lock event and per unit of relative air excess: far above any dS
DB = "tuning.db"


@dataclass
class Parameter:
    key: str           # wsp.<name>
    factor: Factor     # its range (file units in, SI for the C core)


def parameters(study: Study, names: list[str]) -> list[Parameter]:
    ranges = study.spec.tuning.params if study.spec.tuning else {}
    out = []
    for name in names:
        key = name if name.startswith("wsp.") else f"wsp.{name}"
        if key not in ranges:
            raise InputError(f"--params {name}: {study.origin} has no tuning range for {key} "
                             f"(tuning.params: {', '.join(ranges) or 'none'})")
        out.append(Parameter(key, tuning_range(study, key)))
    return out


def default_values(params: list[Parameter]) -> dict:
    """The default WSP's parameters (the C core's rb_wsp_default_params), SI."""
    from railbrake import simulation
    w = simulation.wsp_params()
    return {p.key: float(getattr(w, p.key.split(".", 1)[1])) for p in params}


def start_values(fragment: Path, params: list[Parameter]) -> dict:
    """The parameters of a WSP fragment (`wsp:` block, file units; e.g. from a tuning on some of
    the cases) in SI, for a first trial. Each tuned parameter must be in it and in its range."""
    from railbrake import config
    data = config.load_mapping(config.read_text(fragment), str(fragment))
    wsp = data.get("wsp")
    if not isinstance(wsp, dict):
        raise InputError(f"--start {fragment}: needs a 'wsp:' block (wsp-fragment.yaml of a tuning)")
    values = {}
    for p in params:
        name = p.key.split(".", 1)[1]
        if name not in wsp:
            raise InputError(f"--start {fragment}: wsp.{name} missing (tuned: "
                             f"{', '.join(q.key for q in params)})")
        value = p.factor.si(wsp[name]) if p.factor.kind == "quantity" else float(wsp[name])
        if not p.factor.low <= value <= p.factor.high:
            raise InputError(f"--start {fragment}: wsp.{name} = {wsp[name]} outside "
                             f"its tuning range [{p.factor.file_value(p.factor.low)}, "
                             f"{p.factor.file_value(p.factor.high)}]")
        values[p.key] = value
    tuned = {p.key.split(".", 1)[1] for p in params}
    unknown = sorted(set(data) - {"wsp"}) + [f"wsp.{k}" for k in wsp if k not in tuned]
    if unknown:   # a value that would not be tried is refused, not dropped
        raise InputError(f"--start {fragment}: {', '.join(map(str, unknown))}: not tuned here (a fragment gives "
                         f"wsp.{', wsp.'.join(sorted(tuned))})")
    return values


def controller_only(study: Study, names: list[str], controller: str | None, only: list[str]) -> list[str]:
    """The runs of one WSP controller: the one asked for (--controller), the one an --only names,
    or else the first of the core's controllers that reads every tuned parameter (a controller that
    does not read one refuses it). Returns --only with that controller's runs kept, for a study whose
    `wsp.controller` is a factor."""
    from railbrake.scenario import CONTROLLER_KEYS
    specific = {k for read in CONTROLLER_KEYS.values() for k in read}   # the others: every controller reads them
    keys = [k for k in (n.split(".", 1)[1] if n.startswith("wsp.") else n for n in names) if k in specific]
    pinned = [item.partition("=")[2] for item in only if item.partition("=")[0] == "wsp.controller"]
    if controller is not None and controller not in CONTROLLER_KEYS:
        raise InputError(f"--controller {controller}: one of {', '.join(CONTROLLER_KEYS)}")
    if controller is not None and pinned and pinned != [controller]:
        raise InputError(f"--controller {controller} and --only wsp.controller={'/'.join(pinned)} disagree")
    chosen = controller or (pinned[0] if len(pinned) == 1 else None)
    if chosen is None and not pinned:
        chosen = next((c for c, read in CONTROLLER_KEYS.items() if set(keys) <= set(read)), None)
        if chosen is None:
            raise InputError(f"--params {','.join(names)}: no WSP controller reads them all ("
                             + "; ".join(f"{c}: {', '.join(read)}" for c, read in CONTROLLER_KEYS.items()) + ")")
    for name in [chosen] if chosen else pinned:
        unread = [k for k in keys if k not in CONTROLLER_KEYS.get(name, keys)]
        if unread:
            raise InputError(f"--params: the {name} controller does not read {', '.join(unread)} "
                             f"(it reads {', '.join(CONTROLLER_KEYS[name])})")
    if chosen and not pinned and "wsp.controller" in {f.name for f in study.factors}:
        return [*only, f"wsp.controller={chosen}"]
    return list(only)


def _with_sets(study: Study, sets: dict) -> Study:
    return dataclasses.replace(study, fixed=dict(study.fixed, **sets))._freeze()


def select(study: Study, only: list[str]) -> callable:
    """--only FACTOR=VALUE (repeatable; several values of one factor: any of them): keep those points."""
    wanted: dict = {}
    for item in only:
        name, _, value = item.partition("=")
        if name not in {f.name for f in study.factors}:
            raise InputError(f"--only {item}: {name!r} is not a factor ({', '.join(f.name for f in study.factors)})")
        factor = study.factor(name)
        si = value if factor.kind in ("category", "case") else factor.si(value if factor.kind == "quantity"
                                                                          else float(value))
        wanted.setdefault(name, []).append(si)

    def matches(got, value) -> bool:
        return got == value or (isinstance(value, float) and math.isclose(got, value, rel_tol=1e-9))

    def keep(factors: dict) -> bool:   # a run's factor values (SI)
        return all(any(matches(factors[n], v) for v in values) for n, values in wanted.items())
    return keep


class Evaluator:
    """Runs the study's (selected) cases for one set of WSP parameters on a Dask client."""

    def __init__(self, study: Study, out: Path, client, keep):
        if study.spec.assessment is None:
            raise InputError(f"{study.origin}: tuning needs an 'assessment' (reference case and criteria)")
        self.study, self.out, self.client, self.keep = study, out, client, keep
        self.evaluations = 0

    def __call__(self, values_si: dict, params: list[Parameter]) -> dict:
        sets = {p.key: p.factor.file_value(values_si[p.key]) for p in params}
        variant = _with_sets(self.study, sets)
        runs = plan(variant, self.keep)
        if not runs:
            raise InputError("--only: no case of the study is left")
        groups = execute.batches(runs, 1)   # one run a task: the workers share each evaluation
        options = execute._options(variant, self.out, False)
        futures = [self.client.submit(execute._batch_task, variant.base, [execute._payload(r) for r in g],
                                      options, pure=False, retries=execute.RETRIES) for g in groups]
        rows = []
        for result in self.client.gather(futures):
            for row in result["rows"]:
                rows.append({**row["factors"], **row["kpis"], **{k: row[k] for k in ("key", "status", "error",
                                                                                     "seed")}})
        self.evaluations += 1
        factors = [f.name for f in self.study.factors]

        def v0(row):
            return row.get("initial_speed") or _base_speed(self.study)
        cases = assess(rows, factors, self.study.spec.assessment, v0)
        figures = worst(cases)
        figures["cases"] = [{k: c.get(k) for k in factors + ["delta_s_pct", "wheel_lock_events", "passed"]}
                            for c in cases]
        return figures


def _base_speed(study: Study) -> float:
    from railbrake.campaign import configuration
    return configuration.resolve(study.base).scenario.spec.initial_speed


def _objective_value(figures: dict, air_limit: float | None) -> float:
    value = figures["worst_delta_s_pct"]
    if not math.isfinite(value):
        return PENALTY * 10
    value += PENALTY * figures["locks"]
    air = figures["max_case_air_drawn_kg"]   # the limit holds per case, whichever cases are tuned on
    if air_limit is not None and air > air_limit:
        value += PENALTY * (air - air_limit) / air_limit
    return value


def _recover(trials, storage, defaults: dict) -> None:
    """After an interruption: the trials it left running are failed (one tuning per folder at a
    time), and the default WSP is queued first unless it was evaluated (or is queued) already."""
    from optuna.trial import TrialState
    study_id = storage.get_study_id_from_name(trials.study_name)
    for t in trials.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):
        storage.set_trial_state_values(storage.get_trial_id_from_study_id_trial_number(study_id, t.number),
                                       TrialState.FAIL)
    if not any(t.user_attrs.get("default") for t in trials.get_trials(
            deepcopy=False, states=(TrialState.COMPLETE, TrialState.WAITING))):
        trials.enqueue_trial(defaults, user_attrs={"default": True})


def _storage(out: Path):
    import optuna
    out.mkdir(parents=True, exist_ok=True)
    return optuna.storages.RDBStorage(f"sqlite:///{(out / DB).resolve()}")


def tune(study: Study, names: list[str], objective: str, budget: int, out: Path, workers=None,
         scheduler=None, only=(), air_limit: float | None = None, progress=None, start=(),
         controller=None) -> dict:
    """start: WSP fragments tried right after the default WSP (each once, also on a resume);
    controller: the WSP controller tuned (default: the one that reads the parameters), see
    controller_only."""
    import optuna
    if objective not in OBJECTIVES:
        raise InputError(f"--objective {objective}: one of {', '.join(OBJECTIVES)}")
    whole("budget", budget, 1)
    execute._check_counts(workers=workers)
    params = parameters(study, names)
    only = controller_only(study, [p.key for p in params], controller, list(only))
    if controller and "wsp.controller" not in {f.name for f in study.factors}:
        study = _with_sets(study, {"wsp.controller": controller})
    keep = select(study, list(only))
    defaults = default_values(params)
    seed = int(np.random.SeedSequence(study.spec.seed).generate_state(1)[0])
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    # "no lock" as a constraint: Trial.set_constraint from Optuna 5, constraints_func before it
    set_constraint = hasattr(optuna.trial.Trial, "set_constraint")
    if objective == "pareto":
        old_style = {} if set_constraint else {"constraints_func": lambda t: [t.user_attrs["locks"] - 0.5]}
        sampler = optuna.samplers.NSGAIISampler(seed=seed, **old_style)
        directions = ["minimize", "minimize"]
    else:
        sampler = optuna.samplers.TPESampler(seed=seed, n_startup_trials=min(8, max(1, budget // 3)))
        directions = ["minimize"]
    name = f"{study.name}:{objective}:{','.join(p.key for p in params)}:{' '.join(sorted(only))}"
    storage = _storage(out)
    trials = optuna.create_study(study_name=name, storage=storage, sampler=sampler,
                                 directions=directions, load_if_exists=True)
    _recover(trials, storage, {p.key: defaults[p.key] for p in params})
    for fragment in [start] if isinstance(start, (str, Path)) else start:
        first = start_values(fragment, params)
        if not any(first in (t.params, t.system_attrs.get("fixed_params")) for t in trials.trials):
            trials.enqueue_trial(first, user_attrs={"start": str(fragment)})
    client, cluster = execute.connect(execute.scheduler_address(scheduler), workers)
    try:
        evaluate = Evaluator(study, out, client, keep)

        def run_trial(trial):
            values = {p.key: trial.suggest_float(p.key, p.factor.low, p.factor.high) for p in params}
            figures = evaluate(values, params)
            for k in ("worst_delta_s_pct", "locks", "air_drawn_kg", "max_case_air_drawn_kg", "safety_timer_trips",
                      "failed_runs"):
                trial.set_user_attr(k, figures[k])
            trial.set_user_attr("cases", figures["cases"])
            if progress:
                progress(len(trials.trials), budget)
            if objective == "pareto":
                if set_constraint:
                    trial.set_constraint("locks", figures["locks"] - 0.5)
                ds = figures["worst_delta_s_pct"]
                return (ds if math.isfinite(ds) else PENALTY * 10), figures["air_drawn_kg"]
            return _objective_value(figures, air_limit)

        done = sum(t.state.name == "COMPLETE" for t in trials.trials)   # failed: interrupted, run again
        remaining = max(0, budget - done)
        if remaining:
            trials.optimize(run_trial, n_trials=remaining, catch=())
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return summarise(trials, params, objective, air_limit, out, list(only))


def _figures(trial) -> dict:
    return {"worst_delta_s_pct": trial.user_attrs["worst_delta_s_pct"], "locks": trial.user_attrs["locks"],
            "air_drawn_kg": trial.user_attrs["air_drawn_kg"]}


def summarise(trials, params: list[Parameter], objective: str, air_limit, out: Path, only=()) -> dict:
    complete = [t for t in trials.trials if t.state.name == "COMPLETE"]
    default = next(t for t in complete if t.user_attrs.get("default"))
    if objective == "pareto":
        front = [t for t in trials.best_trials if t.user_attrs["locks"] == 0]
        best = min(front or complete, key=lambda t: t.values[0])
    else:
        best = min(complete, key=lambda t: t.value)
    summary = {"default": _figures(default),
               "tuned": {**_figures(best), "params": {p.key.split(".", 1)[1]: best.params[p.key] for p in params}},
               "evaluations": len(complete), "objective": objective, "air_limit_kg": air_limit,
               "cases": list(only) or "all",
               "units": {p.key.split(".", 1)[1]: p.factor.unit for p in params}}
    if objective == "pareto":
        summary["front"] = [{**_figures(t), "params": {k.split(".", 1)[1]: v for k, v in t.params.items()}}
                            for t in sorted(front, key=lambda t: t.values[0])]
    write_outputs(summary, complete, params, objective, air_limit, out)
    return summary


def write_outputs(summary: dict, complete, params, objective, air_limit, out: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import yaml
    fragment = {"wsp": {p.key.split(".", 1)[1]: p.factor.file_value(summary["tuned"]["params"][p.key.split(".", 1)[1]])
                        for p in params}}
    atomic.write_text(out / "wsp-fragment.yaml",
        "# WSP parameters from 'railbrake wsp tune' (paste into a scenario)\n" + yaml.safe_dump(fragment, sort_keys=False))
    atomic.write_text(out / "summary.json", json.dumps(summary, indent=2))
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ds = [t.user_attrs["worst_delta_s_pct"] for t in complete]
    ok = [t.user_attrs["locks"] == 0 for t in complete]
    best = np.minimum.accumulate([d if k else np.inf for d, k in zip(ds, ok)])
    numbers = np.arange(len(ds))
    ok_mask = np.array(ok, dtype=bool)
    ax.plot(numbers[ok_mask], np.array(ds)[ok_mask], "o", alpha=0.6, label="trial without lock")
    ax.plot(numbers[~ok_mask], np.array(ds)[~ok_mask], "x", color="tab:red", alpha=0.6, label="trial with locks")
    ax.plot(range(len(ds)), best, "-", label="best without lock")
    ax.axhline(summary["default"]["worst_delta_s_pct"], color="grey", ls="--", label="default WSP")
    ax.set_xlabel("evaluation")
    ax.set_ylabel("worst dS (%)")
    ax.legend()
    ax.grid(alpha=0.3)
    atomic.save_figure(fig, out / "convergence.png", dpi=100, bbox_inches="tight")
    plt.close(fig)
    if objective == "pareto":
        fig, ax = plt.subplots(figsize=(5, 3.5))
        ax.plot([t.user_attrs["air_drawn_kg"] for t in complete], ds, "o", alpha=0.4, label="trials")
        front = summary["front"]
        ax.plot([f["air_drawn_kg"] for f in front], [f["worst_delta_s_pct"] for f in front], "s-", label="front")
        ax.set_xlabel("air drawn (kg)")
        ax.set_ylabel("worst dS (%)")
        ax.legend()
        atomic.save_figure(fig, out / "front.png", dpi=100, bbox_inches="tight")
        plt.close(fig)
