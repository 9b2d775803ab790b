"""The ETCS braking model of a train from whole-train runs (docs/etcs.md).

- A_brake_emergency(V): the nominal train's emergency stop from its maximum speed on dry rail,
  as a step function on the speed steps: the stop is taken as the ETCS model has it, the speed
  kept for the equivalent build-up time T_brake_emergency, then each step braked at its constant
  deceleration. Between two speed marks V_j > V_j+1 passed at distances d_j, d_j+1 the step's
  deceleration is (V_j^2 - V_j+1^2) / (2 (d_j+1 - d_j)); the top step's distance starts after
  V0 T_brake_emergency.
- T_brake_emergency: EN 14531-1's equivalent response time te = ta + tb/2 of that stop's total
  brake force (railbrake.simulation.response).
- Kdry_rst(V, EBCL): per speed step the deceleration ratio of each run (failure state and scatter
  draw, the same stop) to the nominal one, mixed over the failure states
  (railbrake.etcs.mixture), read at 1 - EBCL.
- Kwet_rst: the EN 15595 test pairs, dry and reduced adhesion (the test's soap-solution condition,
  data/adhesion/en15595-low.yaml) at 120 km/h and at the maximum speed, 100 / (100 + increase of
  the deceleration distance in %), the worse pair deciding; per speed step, the worse of the pairs
  whose stop runs through the whole step. A condition used outside its validity is refused unless
  forced, and a forced use recorded in the warnings.
"""

from __future__ import annotations

import copy
import logging
import math
from dataclasses import dataclass, field
from importlib import resources
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from railbrake import _core, config, simulation
from railbrake.adhesion import load_condition
from railbrake.simulation import response
from railbrake.errors import InputError
from railbrake.etcs import bound, conditional, confidence, effects, importance, mixture, runs, scatter
from railbrake.units import KMH


class Method(BaseModel):
    """data/etcs/method.yaml: the method's settings, each with its source."""
    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)
    schema_: Literal["railbrake.etcs-method/1"] = Field(alias="schema")
    speed_steps_kmh: list[float] = Field(min_length=1, max_length=_core.MAX_SPEED_MARKS)
    speed_steps_source: str
    dry_condition: str
    kwet_test_speed_kmh: float = Field(gt=0.0, le=600.0)
    reduced_condition: str
    samples: int = Field(ge=2, le=100_000)
    rare_samples: int = Field(ge=2, le=100_000)
    likely_state: float = Field(ge=0.0, le=1.0)
    state_floor: float = Field(gt=0.0, lt=1e-9)
    no_effect_ratio: float = Field(gt=0.0, lt=0.05)
    kdry_bound: float = Field(gt=0.0, le=0.05)
    run_budget: int = Field(ge=0, le=10_000_000)
    bootstrap_replicates: int = Field(ge=20, le=10_000)
    step_ms: float = Field(gt=0.0, le=2.0)   # one plant step, no sub-steps (simulation.MAX_SUBSTEP)


LOG = logging.getLogger(__name__)
# the window the bootstrap reads a quantile in (+- this about the estimate): replicates beyond it
# are taken at its edge, which the bound then shows as this large
BOUND_WINDOW = 0.1
# a round of added runs goes to the states holding this share of a level's variance (_more_runs):
# doubling them takes the variance down by at least ALLOCATED / 2 a round
ALLOCATED = 0.8


def method() -> Method:
    return config.load_yaml(str(resources.files("railbrake") / "data" / "etcs" / "method.yaml"), Method)


def spec(train: str, reliability: str = "hs-emu", scatter: str | None = "hs-emu", cars: int | None = None,
         initial_speed_kmh: float | None = None, seed: int = 1, force_conditions: bool = False,
         **settings) -> runs.Spec:
    """An analysis of `train` with the method file's settings, any of them replaced by `settings`."""
    m = method().model_dump()
    m.update(settings)
    return runs.Spec(train=str(train), reliability=str(reliability), scatter=None if scatter is None else str(scatter),
                     cars=cars, speed_steps_kmh=tuple(m["speed_steps_kmh"]), dry_condition=m["dry_condition"],
                     reduced_condition=m["reduced_condition"], kwet_test_speed_kmh=m["kwet_test_speed_kmh"],
                     initial_speed_kmh=initial_speed_kmh, samples=m["samples"], rare_samples=m["rare_samples"],
                     likely_state=m["likely_state"], state_floor=m["state_floor"], seed=seed,
                     kdry_bound=m["kdry_bound"], run_budget=m["run_budget"], replicates=m["bootstrap_replicates"],
                     force_conditions=bool(force_conditions), step_ms=m["step_ms"])


def step_decelerations(v0: float, marks: tuple, stop_speed: float, row: dict, t_be: float) -> np.ndarray:
    """Each speed step's deceleration (m/s^2, lowest step first) from a run's mark distances."""
    if row.get("error"):
        return np.zeros(len(marks) + 1)   # a run the core refused: no brake (the safe side)
    speeds = [v0, *marks, stop_speed]
    ends = [v0 * t_be, *row["marks_m"], row["stopping_distance_m"]]
    out = []
    for j in range(len(speeds) - 1):
        if ends[j + 1] is None:   # a step the run did not get through in its time: no brake there
            out.append(0.0)
            continue
        run = ends[j + 1] - ends[j]
        if run <= 0.0:
            raise InputError(f"speed step {speeds[j + 1] / KMH:.0f}-{speeds[j] / KMH:.0f} km/h is passed within "
                             f"the equivalent build-up time ({t_be:.2f} s): choose speed steps wider at the top")
        out.append((speeds[j] ** 2 - speeds[j + 1] ** 2) / (2.0 * run))
    return np.asarray(out[::-1])


@dataclass
class BrakingModel:
    train: str
    spec: runs.Spec
    speed_steps_kmh: list        # lower speed of each step
    a_brake_emergency: list      # m/s^2 per step
    t_brake_emergency: float     # s
    kdry: list                   # [step][M_NVEBCL], before rounding
    kwet: float                  # before rounding, the worse pair's
    kwet_pairs: list             # per test speed: dry and reduced deceleration distances
    states: list                 # per failure state: label, probability, mean ratio per step, runs
    deciding: list               # [step][M_NVEBCL]: the state most likely at the quantile
    runs: int = 0
    ratios: list = field(default_factory=list, repr=False)   # per state, per step: the sorted sample
    effects: list = field(default_factory=list)   # each failure alone: railbrake.etcs.effects.screen
    warnings: list = field(default_factory=list)
    unenumerated_probability: float = 0.0         # states below the floor, counted as no brake
    kdry_bounds: list = field(default_factory=list)   # [step][M_NVEBCL]: (lower, upper) distance, 95 %
    kwet_steps: list = field(default_factory=list)    # Kwet_rst per speed step, before rounding
    initial_speed_kmh: float = 0.0
    importance: list = field(default_factory=list)   # [M_NVEBCL]: railbrake.etcs.importance.ranking
    step_allowance: list = field(default_factory=list)   # per step: the runs' step's ratio error (step_allowance)
    bound_method: str = ""                        # how the sampling bounds were found (_bound_method)

    def kdry_coded(self) -> list:
        """Each Kdry_rst on the coding grid from the conservative side of its bound, less the
        step allowance of its speed step."""
        allowance = self.step_allowance or [0.0] * len(self.kdry)
        if not self.kdry_bounds:
            return [[confidence.coded(max(0.0, k - a)) for k in step] for step, a in zip(self.kdry, allowance)]
        return [[confidence.coded(max(0.0, k - low - a)) for k, (low, _) in zip(step, b)]
                for step, b, a in zip(self.kdry, self.kdry_bounds, allowance)]

    def kwet_coded(self) -> float:
        return confidence.coded(self.kwet)

    def kwet_steps_coded(self) -> list:
        """Kwet_rst per speed step on the coding grid (rounded down); the worst pair's where the
        analysis has none per step."""
        return [confidence.coded(k) for k in (self.kwet_steps or [self.kwet] * len(self.kdry))]


def nominal_build_up(ctx: runs.Context) -> float:
    """T_brake_emergency: EN 14531-1's te = ta + tb/2 of the nominal train's emergency brake from
    its initial speed on dry rail, on its total brake force (railbrake.simulation.response, as
    `railbrake run` and `stopping-distance` measure it). The deceleration would not do: a
    speed-stepped demand and the pad friction make it rise over the whole stop."""
    return response.simulated(ctx.train, ctx.v0, ctx.spec.dry_condition, preset=ctx.spec.train).response


def check_condition(spec: runs.Spec, condition: str, speed_kmh: float, use: str, warnings_: list) -> None:
    """Refuse an adhesion condition used outside its validity (its data file's), unless the
    analysis forces it: then the use is recorded in the model's warnings."""
    valid = load_condition(condition).validity
    if valid is None or valid.contains(speed_kmh):
        return
    what = (f"adhesion condition {condition!r} for {use} from {speed_kmh:.0f} km/h: outside "
            f"{valid.speed_min_kmh:.0f}-{valid.speed_max_kmh:.0f} km/h where it holds ({valid.conditions})")
    if not spec.force_conditions:
        raise InputError(what + "; choose a condition valid there, or force it (force_conditions, "
                         "--force-conditions) to have the use recorded in the model's warnings")
    warnings_.append("forced: " + what)


def check_conditions(ctx: runs.Context) -> list[str]:
    """Every adhesion condition of the analysis at every speed it runs from (check_condition),
    before any run: the warnings of those forced."""
    out: list[str] = []
    check_condition(ctx.spec, ctx.spec.dry_condition, ctx.v0 / KMH, "Kdry_rst and A_brake_emergency", out)
    for v in _kwet_speeds(ctx):
        for condition in (ctx.spec.dry_condition, ctx.spec.reduced_condition):
            check_condition(ctx.spec, condition, v / KMH, "the Kwet_rst test pair", out)
    return out


def _kwet_speeds(ctx: runs.Context) -> list[float]:
    return sorted({ctx.spec.kwet_test_speed_kmh * KMH, ctx.v0})


def kwet(ctx: runs.Context, t_be: float) -> tuple[float, list, list]:
    """Kwet_rst from the EN 15595 test pairs (the worse deciding), the pairs' figures, and Kwet per
    speed step (lowest first): the worst of the pairs whose stop runs through the whole step."""
    speeds = _kwet_speeds(ctx)
    prepared = [ctx.stop(v, c) for v in speeds for c in (ctx.spec.dry_condition, ctx.spec.reduced_condition)]
    rows = simulation.run_structs(prepared)
    pairs = []
    for i, v in enumerate(speeds):
        dry, wet = rows[2 * i], rows[2 * i + 1]
        for r, c in ((dry, ctx.spec.dry_condition), (wet, ctx.spec.reduced_condition)):
            if isinstance(r, Exception) or r["stopping_distance_m"] is None:
                raise InputError(f"Kwet test from {v / KMH:.0f} km/h on {c}: the train did not stop ({r})")
        d_dry = dry["stopping_distance_m"] - v * t_be
        d_wet = wet["stopping_distance_m"] - v * t_be
        increase = 100.0 * (d_wet - d_dry) / d_dry
        # a reduced adhesion cannot shorten the stop: a negative increase (within the model's
        # accuracy) counts as none; the pair's own figures are reported as they are
        pairs.append({"speed_kmh": v / KMH, "dry_deceleration_distance_m": d_dry,
                      "reduced_deceleration_distance_m": d_wet, "increase_percent": increase,
                      "kwet": 100.0 / (100.0 + max(increase, 0.0))})
    tops = [*sorted(ctx.marks), ctx.v0]
    per_step = [min(p["kwet"] for p in pairs if p["speed_kmh"] * KMH >= top - 1e-9) for top in tops]
    return min(p["kwet"] for p in pairs), pairs, per_step


def _deciding(states: list, x: float) -> int:
    """The state with the largest share of the mixture's probability below x."""
    return int(np.argmax([s.probability * s.cdf(x) for s in states]))


def _estimate(ctx: runs.Context, ratios: list, missing: float, seed: int,
              factors: list | None = None) -> tuple[list, list, list, list]:
    """(kdry, bounds, deciding, carrying) per step and level from the states' samples: given the
    runs' draws of the train's tolerance (`factors`, per state), by the regression on it
    (railbrake.etcs.conditional), else by the bootstrap of the runs (railbrake.etcs.bound)."""
    if factors is not None:
        return _estimate_given(ctx, ratios, missing, factors)
    rng = np.random.default_rng([seed, 36])
    kdry, bounds, deciding, carrying = [], [], [], []
    for j in range(len(ctx.marks) + 1):
        states = [mixture.State.of(st.probability, r[:, j], st.label) for st, r in zip(ctx.states, ratios)]
        values = [mixture.k_dry(states, c) for c in confidence.EBCL]
        step_bounds, step_carrying = [], []
        for c, v in zip(confidence.EBCL, values):
            low, high, carry = bound.bound(states, 1.0 - c, v, missing, rng, ctx.spec.replicates, BOUND_WINDOW)
            step_bounds.append((low, high))
            step_carrying.append({s: _variance_share(states[s], v) for s in carry})
        kdry.append([min(v, confidence.K_MAX) if v > 0 else 0.0 for v in values])
        bounds.append(step_bounds)
        deciding.append([ctx.states[_deciding(states, v)].label if v > 0 else "states left out (no brake)"
                         for v in values])
        carrying.append(step_carrying)
    return kdry, bounds, deciding, carrying


def _estimate_given(ctx: runs.Context, ratios: list, missing: float, factors: list) -> tuple[list, list, list, list]:
    """_estimate by the regression on the train's tolerance (railbrake.etcs.conditional)."""
    law = conditional.Law.of(scatter.train_tolerance(ctx.scatter)[1])
    probabilities = [st.probability for st in ctx.states]
    kdry, bounds, deciding, carrying = [], [], [], []
    for j in range(len(ctx.marks) + 1):
        fits = conditional.Fits.of(law, probabilities, [r[:, j] for r in ratios], factors)
        values = [fits.quantile(1.0 - c, missing) for c in confidence.EBCL]
        step_bounds, step_carrying, step_deciding = [], [], []
        for c, v in zip(confidence.EBCL, values):
            half, shares = fits.bound(1.0 - c, v) if v > 0 else (0.0, np.zeros(len(probabilities)))
            step_bounds.append((half, half))
            step_carrying.append({int(s): float(shares[s]) for s in np.flatnonzero(shares >= conditional.CARRY)})
            step_deciding.append(ctx.states[int(np.argmax(fits.probability * fits.cdfs(v)))].label if v > 0
                                 else "states left out (no brake)")
        kdry.append([min(v, confidence.K_MAX) if v > 0 else 0.0 for v in values])
        bounds.append(step_bounds)
        deciding.append(step_deciding)
        carrying.append(step_carrying)
    return kdry, bounds, deciding, carrying


def _variance_share(state: mixture.State, x: float) -> float:
    """A state's share of the variance of the mixture's CDF at x (to first order, that of the
    quantile there): p^2 F (1 - F) / n, its estimate of F(x) from n runs weighed by its probability."""
    f = state.cdf(x)
    return state.probability ** 2 * f * (1.0 - f) / state.ratios.size


def _more_runs(ctx: runs.Context, counts: list, bounds: list, carrying: list, budget: int) -> list:
    """The next runs: for every (step, level) whose bound is above the target, the samples doubled
    (a block at least) of the states that carry it, those with the largest shares of its variance
    first until they hold ALLOCATED of it (the others would buy little: Neyman's allocation, to
    first order), the states whose runs are fewest relative to their share first, within the
    budget; [] if none is needed or the budget is spent."""
    target, block = ctx.spec.kdry_bound, ctx.spec.rare_samples
    wanted: dict[int, int] = {}
    for step_bounds, step_carrying in zip(bounds, carrying):
        for (low, high), carry in zip(step_bounds, step_carrying):
            if max(low, high) <= target:
                continue
            total, held = sum(carry.values()), 0.0
            for s in sorted(carry, key=lambda s: -carry[s]):
                if total > 0.0 and held >= ALLOCATED * total:
                    break
                held += carry[s]
                wanted[s] = max(wanted.get(s, 0), max(block, counts[s]))
    jobs = []
    for s in sorted(wanted, key=lambda s: -ctx.states[s].probability / counts[s]):
        extra = min(wanted[s], budget - len(jobs))
        if extra <= 0:
            break
        jobs += [(s, counts[s] + i) for i in range(extra)]
    return jobs


def braking_model(spec: runs.Spec, out=None, workers: int = 1, progress=None, scheduler: str | None = None,
                  connect_timeout: float | None = None) -> BrakingModel:
    """The braking model of spec's train; its runs in `out` (None: kept in memory) on the campaign
    engine (railbrake.etcs.runs.Runner: `workers` local processes, or an existing Dask scheduler)."""
    with runs.Runner(spec, out, workers, scheduler, progress, connect_timeout) as runner:
        return _braking_model(spec, runner)


def _braking_model(spec: runs.Spec, runner: runs.Runner) -> BrakingModel:
    ctx = runs.context(spec)
    warnings_ = check_conditions(ctx)   # before any run
    t_be = nominal_build_up(ctx)
    stop_speed = ctx.structs[3].stop_speed
    nominal = nominal_decelerations(ctx, t_be, stop_speed)   # at the runs' step: the ratios' denominator
    a_brake = nominal_decelerations(ctx, t_be, stop_speed, ctx.stop(ctx.v0, spec.dry_condition))   # at 1 ms
    found = effects.alone(ctx, _ratio_of(ctx, t_be, nominal))   # each failure and tolerance end alone
    effects_, screened = screen(ctx, t_be, nominal, found)
    warnings_ += screened
    allowance = step_allowance(ctx, t_be, nominal, found)
    missing = max(0.0, 1.0 - sum(st.probability for st in ctx.states))
    rows = runner.run(ctx.jobs())
    given = scatter.train_tolerance(ctx.scatter)
    while True:
        per_state, samples = [[] for _ in ctx.states], [[] for _ in ctx.states]
        for (s, i), row in sorted(rows.items()):
            per_state[s].append(step_decelerations(ctx.v0, ctx.marks, stop_speed, row, t_be) / nominal)
            samples[s].append(i)
        ratios = [np.asarray(r) for r in per_state]
        factors = None if given is None else [ctx.train_draws(s, ii, given[0]) for s, ii in enumerate(samples)]
        kdry, bounds, deciding, carrying = _estimate(ctx, ratios, missing, spec.seed, factors)
        more = _more_runs(ctx, [len(r) for r in ratios], bounds, carrying, spec.run_budget - len(rows))
        LOG.info("%d runs: worst bound %.4f, %d levels above %g; %d runs more", len(rows),
                 max(max(lh) for step in bounds for lh in step),
                 sum(max(lh) > spec.kdry_bound for step in bounds for lh in step), spec.kdry_bound, len(more))
        if not more:
            break
        rows.update(runner.run(more))
    worst = max(max(lh) for step in bounds for lh in step)
    if worst > spec.kdry_bound:
        warnings_.append(f"Kdry_rst: the sampling bound reaches {worst:.4f} (above {spec.kdry_bound:g}) after the "
                         f"run budget of {spec.run_budget} runs; the coded values take the conservative side")
    k_wet, pairs, kwet_steps = kwet(ctx, t_be)
    steps = [0.0, *sorted(v / KMH for v in ctx.marks)]
    summary = [{"label": st.label, "probability": st.probability, "runs": len(r),
                "mean_ratio": [float(x) for x in r.mean(axis=0)]} for st, r in zip(ctx.states, ratios)]
    n_steps = len(ctx.marks) + 1
    return BrakingModel(spec.train, spec, steps, [float(a) for a in a_brake], t_be, kdry, k_wet, pairs,
                        summary, deciding, len(rows), [[np.sort(r[:, j]) for j in range(n_steps)] for r in ratios],
                        effects_, warnings_, missing, bounds, kwet_steps, ctx.v0 / KMH,
                        importance.ranking(ctx, ratios, samples, missing), allowance, _bound_method(given))


def _bound_method(given: tuple | None) -> str:
    if given is None:
        return "bootstrap of each state's runs (railbrake.etcs.bound)"
    return (f"regression of each state's runs on the train's tolerance {given[0]}, read through its own "
            f"distribution; delta-method bound (railbrake.etcs.conditional)")


def _ratio_of(ctx: runs.Context, t_be: float, denominator: np.ndarray):
    stop_speed = ctx.structs[3].stop_speed
    return lambda kpis: step_decelerations(ctx.v0, ctx.marks, stop_speed, runs._row(kpis), t_be) / denominator


def screen(ctx: runs.Context, t_be: float, nominal: np.ndarray, found: tuple | None = None) -> tuple[list, list]:
    """Each failure and scatter factor run on its own (railbrake.etcs.effects.screen; found: their
    runs at the analysis' step, effects.alone, if already made)."""
    return effects.screen(ctx, _ratio_of(ctx, t_be, nominal), method().no_effect_ratio, found)


def step_allowance(ctx: runs.Context, t_be: float, nominal: np.ndarray, found: tuple | None = None) -> list[float]:
    """Per speed step (lowest first), the largest change of the ratio between the runs' step and
    the plant's nominal 1 ms over the failures run alone and the tolerances at their ends
    (railbrake.etcs.effects.alone; found: those at the runs' step, if already made): the coded
    Kdry_rst takes it off too (the safe side). 0 at 1 ms."""
    n_steps = len(ctx.marks) + 1
    if ctx.spec.step_ms * 1e-3 == simulation.DT:
        return [0.0] * n_steps
    fine = copy.copy(ctx)
    fine.structs = ctx.stop(ctx.v0, ctx.spec.dry_condition)
    fine.structs[3].max_time = ctx.structs[3].max_time
    coarse = found if found is not None else effects.alone(ctx, _ratio_of(ctx, t_be, nominal))
    fine_nominal = nominal_decelerations(fine, t_be, ctx.structs[3].stop_speed)
    at_1ms = effects.alone(fine, _ratio_of(fine, t_be, fine_nominal))
    def table(found_):
        return np.array(list(found_[1]) + [r for _, r in found_[2]])
    change = np.abs(table(coarse) - table(at_1ms))
    return [float(x) for x in np.max(change, axis=0, initial=0.0)] if len(change) else [0.0] * n_steps


def nominal_decelerations(ctx: runs.Context, t_be: float, stop_speed: float, structs: tuple | None = None) -> np.ndarray:
    """Per step, the nominal train's deceleration (no failure, no scatter) in the stop `structs`
    (default: the analysis' runs', at its step): at 1 ms, A_brake_emergency."""
    row = runs._row(simulation.run_structs([structs or ctx.structs])[0])
    a = step_decelerations(ctx.v0, ctx.marks, stop_speed, row, t_be)
    if not np.all(a > 0.0):
        raise InputError(f"train {ctx.spec.train}: the nominal emergency stop from {ctx.v0 / KMH:.0f} km/h did not stop")
    return a


def braking_distance(model: BrakingModel, level: int, avadh: float) -> float:
    """The ETCS emergency braking distance from the analysis' initial speed at M_NVEBCL = level with
    M_NVAVADH = avadh: the speed kept for T_brake_emergency, then A_safe = A x Kdry x (Kwet +
    avadh (1 - Kwet)) per speed step (coded values)."""
    v0 = model.spec.initial_speed_kmh * KMH if model.spec.initial_speed_kmh else runs.context(model.spec).v0
    edges = [v * KMH for v in model.speed_steps_kmh] + [v0]
    kwets = model.kwet_steps_coded()
    distance = v0 * model.t_brake_emergency
    for j, a in enumerate(model.a_brake_emergency):
        kw = kwets[j]
        safe = a * model.kdry_coded()[j][level] * (kw + avadh * (1.0 - kw))
        if safe <= 0.0:
            return math.inf
        distance += (edges[j + 1] ** 2 - edges[j] ** 2) / (2.0 * safe)
    return distance
