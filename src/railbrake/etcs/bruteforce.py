"""A brute-force Monte Carlo of whole-train stops, to check the method (railbrake.etcs.model)
against: every stop draws its failures (each unit of each fault independently, each common-cause
event) and its tolerances (independent draws, no Latin hypercube) together, and the deceleration
ratios' empirical quantiles carry the order statistics' confidence interval.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import binom

from railbrake import simulation
from railbrake.errors import InputError
from railbrake.etcs import failures, model, runs, scatter
from railbrake.etcs.inputs import QUANTITIES

CHUNK = 64          # runs per C call
MAX_STOPS = 1_000_000


def _draw_factors(ctx: runs.Context, rng: np.random.Generator) -> np.ndarray:
    n_cars = len(ctx.train.cars)
    factors = np.ones((len(QUANTITIES), n_cars))
    for q, d in (ctx.scatter.quantities() if ctx.scatter else {}).items():
        u = rng.random((1, scatter.columns(d.per, n_cars)))
        factors[QUANTITIES.index(q), :] = scatter.per_car(scatter._ppf(d, u), d.per, n_cars)[0]
    return factors


def ratios(spec: runs.Spec, n: int, seed: int) -> np.ndarray:
    """The deceleration ratio per speed step (lowest first) of n brute-force stops: (n, steps)."""
    if not 1 <= n <= MAX_STOPS:
        raise InputError(f"stops = {n}: must be in [1, {MAX_STOPS}]")
    ctx = runs.context(spec)
    t_be = model.nominal_build_up(ctx)
    stop_speed = ctx.structs[3].stop_speed
    nominal = model.nominal_decelerations(ctx, t_be, stop_speed)
    rng = np.random.default_rng(seed)
    out = []
    for start in range(0, n, CHUNK):
        prepared = []
        for _ in range(min(CHUNK, n - start)):
            plant, bcu = scatter.apply(ctx.structs[0], ctx.structs[1], _draw_factors(ctx, rng))
            faults = failures.draw(ctx.reliability, ctx.train, ctx.common, rng)
            failures.set_faults(plant, failures.plant_faults(faults))
            prepared.append((plant, bcu, ctx.structs[2], ctx.structs[3]))
        for row in simulation.run_structs(prepared):
            out.append(model.step_decelerations(ctx.v0, ctx.marks, stop_speed, runs._row(row), t_be) / nominal)
    return np.asarray(out)


def quantile_interval(sample: np.ndarray, level: float, coverage: float = 0.95) -> tuple[float, float, float]:
    """(estimate, low, high): the sample's quantile at `level` and its distribution-free interval
    from the order statistics (the count below the true quantile is binomial(n, level))."""
    x = np.sort(np.asarray(sample, dtype=float))
    n = x.size
    lo = int(binom.ppf((1 - coverage) / 2, n, level))
    hi = int(binom.ppf(1 - (1 - coverage) / 2, n, level)) + 1
    if lo < 1 or hi > n:
        raise InputError(f"{n} stops are too few for a {coverage:.0%} interval of the {level:g} quantile")
    return float(np.quantile(x, level)), float(x[lo - 1]), float(x[hi - 1])
