"""What each failure and each tolerance of an analysis does to the configured emergency brake, run
on its own before the mixture (railbrake.etcs.model): a failure or scatter factor that cannot
change this brake (the EP valve when the emergency valve bypasses it, a response time that does
not move the stop) is reported as "no effect on this brake" in the model's warnings, never kept
silently.

A failure runs alone on the first unit of each car type it can hit (no scatter); a common-cause
group runs alone; its effect per speed step is the ratio's drop, and beside it the unit's share
of the train's emergency brake force (the BCU's per-car demand, railbrake.sizing; a bogie half
its car's, an axle a quarter). A scatter factor runs at its two ends (bounds, else mean +- 3 sd)
on every car.
"""

from __future__ import annotations

import numpy as np

from railbrake import simulation, sizing
from railbrake.etcs import failures, scatter
from railbrake.etcs.failures import Unit
from railbrake.etcs.inputs import QUANTITIES
from railbrake.units import KMH

SPAN = {"car": 1.0, "bogie": 0.5, "axle": 0.25, "train": None}
END_SIGMAS = 3.0   # a normal factor without bounds is screened at mean +- 3 sd


def _shares(ctx, edges: list) -> np.ndarray:
    """(cars, steps): each car's share of the train's emergency brake force, averaged over each
    speed step (lowest first)."""
    demands = sizing.car_demands(ctx.train, sizing.brake_step(ctx.train, "emergency")[0])
    out = np.empty((len(demands), len(edges) - 1))
    for j in range(len(edges) - 1):
        v = np.linspace(edges[j], edges[j + 1], 50)
        forces = np.array([np.interp(v, d.speed, d.force) for d in demands])
        out[:, j] = np.mean(forces / forces.sum(axis=0), axis=1)
    return out


def _cases(ctx) -> list[tuple[dict, list]]:
    """(description, faults) of every single failure on the first unit of each car type, and of
    every common-cause group."""
    rel, out = ctx.reliability, []
    for i, f in enumerate(rel.failures):
        if f.probability() == 0.0:
            continue
        if f.unit == "train":
            out.append(({"failure": i, "kind": f.kind, "unit": "train", "car_type": None, "car": None},
                        [(f.kind, Unit(0, -1), f.value_si())]))
            continue
        for type_name in dict.fromkeys(c.type_name for c in ctx.train.cars):
            car = next(c.index for c in ctx.train.cars if c.type_name == type_name)
            axles = [-1] if f.unit == "car" else ([0, 1] if f.unit == "bogie" else [0])
            out.append(({"failure": i, "kind": f.kind, "unit": f.unit, "car_type": type_name, "car": car},
                        [(f.kind, Unit(car, a), f.value_si()) for a in axles]))
    for (kind, units), g in zip(ctx.common, rel.common_cause):
        out.append(({"common_cause": g.name, "kind": kind, "unit": "group", "car_type": None, "car": None},
                    [(kind, u, 0.0) for u in units]))
    return out


def alone(ctx, ratio_of) -> tuple[list, list, list]:
    """(cases, ratios of the cases, ratios of the scatter ends): every single failure and common-
    cause group (_cases) and every scatter factor at each of its ends on every car (_scatter_end_structs),
    each run on its own, all in one batch of the C core; ratio_of turns a run's KPIs into its
    ratio per step."""
    cases = _cases(ctx)
    plant, bcu, wsp, scen = ctx.structs
    prepared = []
    for _, faults in cases:
        p = type(plant).from_buffer_copy(plant)
        failures.set_faults(p, failures.plant_faults(faults))
        prepared.append((p, bcu, wsp, scen))
    names, ends = _scatter_end_structs(ctx)
    ratios = [ratio_of(row) for row in simulation.run_structs(prepared + ends)]
    return cases, ratios[:len(cases)], list(zip(names, ratios[len(cases):]))


def screen(ctx, ratio_of, no_effect: float, found: tuple | None = None) -> tuple[list[dict], list[str]]:
    """(effects, warnings): each single failure's and common-cause group's ratio per step (lowest
    first), the drop against its unit's share, and a warning for each failure or scatter factor
    that moves no step's ratio by `no_effect` or more. found: alone's result, if already run."""
    edges = [0.0, *sorted(ctx.marks), ctx.v0]
    shares = _shares(ctx, edges)
    cases, case_ratios, end_ratios = found if found is not None else alone(ctx, ratio_of)
    effects, warnings = [], []
    for (desc, _), ratio in zip(cases, case_ratios):
        drop = 1.0 - ratio
        row = {**desc, "ratio": [float(r) for r in ratio]}
        span = SPAN.get(desc["unit"])
        if desc["car"] is not None and span is not None:
            share = shares[desc["car"]] * span
            row["unit_share"] = [float(s) for s in share]
            row["drop_of_share"] = float(np.min(drop / share))   # the least over the steps
        row["no_effect"] = bool(np.max(np.abs(drop)) < no_effect)
        if row["no_effect"]:
            where = f" on a {desc['car_type']} car" if desc["car_type"] else ""
            what = desc.get("common_cause") or desc["kind"]
            warnings.append(f"failure {what} ({desc['unit']}{where}): no effect on this brake (the ratio moves "
                            f"by less than {no_effect:g} at every speed step from {ctx.v0 / KMH:.0f} km/h)")
        effects.append(row)
    warnings += _scatter_warnings(ctx, end_ratios, no_effect)
    return effects, warnings


def _ends(d) -> tuple[float, float]:
    if d.bounds is not None:
        return tuple(d.bounds)
    return d.mean - END_SIGMAS * d.sd, d.mean + END_SIGMAS * d.sd


def _scatter_end_structs(ctx) -> tuple[list[str], list]:
    """(quantity, C structs) of each scatter factor at each of its ends on every car."""
    if ctx.scatter is None:
        return [], []
    n_cars = len(ctx.train.cars)
    prepared, names = [], []
    plant, bcu, wsp, scen = ctx.structs
    for q, d in ctx.scatter.quantities().items():
        for end in _ends(d):
            factors = np.ones((len(QUANTITIES), n_cars))
            factors[QUANTITIES.index(q), :] = end
            p, b = scatter.apply(plant, bcu, factors)
            prepared.append((p, b, wsp, scen))
            names.append(q)
    return names, prepared


def _scatter_warnings(ctx, end_ratios: list, no_effect: float) -> list[str]:
    given = ctx.scatter.quantities() if ctx.scatter is not None else {}
    out = []
    for q in given:
        moved = max(float(np.max(np.abs(1.0 - r))) for n, r in end_ratios if n == q)
        if moved < no_effect:
            out.append(f"scatter {q}: no effect on this brake (at its ends {_ends(given[q])[0]:g} and "
                       f"{_ends(given[q])[1]:g} on every car the ratio moves by {moved:.2g} at most)")
    return out
