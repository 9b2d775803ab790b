"""The plant's step of the mixture's runs (data/etcs/method.yaml step_ms): the deceleration ratios
at the method's step against the nominal 1 ms, for every single failure and common-cause group of
the shipped reliability file and the shipped tolerances at their ends (railbrake.etcs.effects'
cases) on the first 4 cars of the CRH380A from 160 km/h (a top speed step of 10 km/h, the most
sensitive to the step): the analysis' step allowance is the largest change per speed step, below
half the method's Kdry_rst bound, and the coded Kdry_rst takes it off."""

import numpy as np
import pytest

from railbrake import simulation
from railbrake.etcs import confidence, effects, model, runs, scatter
from railbrake.etcs.inputs import QUANTITIES


def setup(step_ms: float) -> tuple:
    ctx = runs.context(model.spec("crh380a-8", cars=4, initial_speed_kmh=160.0, step_ms=step_ms))
    t_be = model.nominal_build_up(ctx)
    return ctx, t_be, model.nominal_decelerations(ctx, t_be, ctx.structs[3].stop_speed)


def ratios(step_ms: float) -> np.ndarray:
    ctx, t_be, nominal = setup(step_ms)
    stop_speed = ctx.structs[3].stop_speed

    def ratio_of(kpis):
        return model.step_decelerations(ctx.v0, ctx.marks, stop_speed, runs._row(kpis), t_be) / nominal

    found, _ = effects.screen(ctx, ratio_of, model.method().no_effect_ratio)
    plant, bcu, wsp, scen = ctx.structs
    ends = []
    for q, d in ctx.scatter.quantities().items():   # each tolerance at its ends on every car
        for end in effects._ends(d):
            factors = np.ones((len(QUANTITIES), len(ctx.train.cars)))
            factors[QUANTITIES.index(q), :] = end
            ends.append((*scatter.apply(plant, bcu, factors), wsp, scen))
    return np.array([e["ratio"] for e in found] + [list(ratio_of(k)) for k in simulation.run_structs(ends)])


@pytest.mark.slow   # every failure and tolerance end run at 1 and 2 ms: 100 s under the sanitizers
def test_the_step_allowance_is_the_largest_ratio_change_against_1_ms():
    method = model.method()
    assert method.step_ms > 1.0   # else there is nothing to check
    coarse, fine = ratios(method.step_ms), ratios(1.0)
    assert coarse.shape == fine.shape and coarse.shape[0] > 10
    assert np.ptp(fine) > 0.1   # the cases move the ratio: a failure of a car is among them
    change = np.max(np.abs(coarse - fine), axis=0)
    print(f"largest ratio change per speed step at {method.step_ms:g} ms against 1 ms: {np.round(change, 5)}")
    allowance = model.step_allowance(*setup(method.step_ms))
    assert np.allclose(allowance, change, rtol=0.0, atol=1e-12)
    assert max(allowance) < method.kdry_bound / 2
    assert model.step_allowance(*setup(1.0)) == [0.0] * len(allowance)


def test_the_coded_kdry_takes_the_step_allowance_off():
    levels = len(confidence.EBCL)
    m = model.BrakingModel("t", None, [0.0], [1.0], 1.0, [[0.951] * levels], 1.0, [], [], [[""] * levels],
                           kdry_bounds=[[(0.0005, 0.0005)] * levels])
    assert m.kdry_coded() == [[0.95] * levels]
    m.step_allowance = [0.001]
    assert m.kdry_coded() == [[0.9] * levels]
