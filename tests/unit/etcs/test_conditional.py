"""Kdry_rst given the train's tolerance (railbrake.etcs.conditional): the mixture's quantiles
against closed forms, the delta-method bound's coverage against repeated samples whose true
quantile is known, and the regression's form on a plant's runs."""

import numpy as np
import pytest
from scipy.stats import norm, qmc, truncnorm

from railbrake.etcs import conditional, inputs, model, runs, scatter
from railbrake.etcs.conditional import Fits, Law

NORMAL = Law("normal", 1.0, 0.05, -np.inf, np.inf)
TRUNCATED = Law("truncated_normal", 1.0, 0.05, 0.85, 1.15)


def _fixed(law, a, b, sigma, probability=(1.0,)):
    k = len(probability)
    return Fits(law, np.array(probability), np.full(k, a), np.full(k, b), np.full(k, sigma), np.full(k, 1000),
                np.zeros((k, 2, 2)), np.zeros(k))


@pytest.mark.parametrize("level", [0.5, 1e-2, 1e-5, 1e-9, 1e-12])
def test_a_normal_tolerance_and_normal_residual_give_the_normal_sum_s_quantile(level):
    # a + b P + sigma Z with P ~ N(1, 0.05): normal, sd sqrt(b^2 0.05^2 + sigma^2)
    a, b, sigma = 0.1, 0.9, 0.005
    exact = a + b + np.hypot(b * 0.05, sigma) * norm.ppf(level)
    assert _fixed(NORMAL, a, b, sigma).quantile(level) == pytest.approx(exact, abs=1e-9)


@pytest.mark.parametrize("level", [0.5, 1e-2, 1e-5, 1e-9])
def test_without_residual_the_quantile_is_the_tolerance_s_own_bounds_included(level):
    exact = 0.1 + 0.9 * truncnorm(-3.0, 3.0, loc=1.0, scale=0.05).ppf(level)
    assert _fixed(TRUNCATED, 0.1, 0.9, 0.0).quantile(level) == pytest.approx(exact, abs=1e-9)
    assert _fixed(TRUNCATED, 0.1, 0.9, 0.0).quantile(1e-9) >= 0.1 + 0.9 * 0.85   # never below the lowest factor's


def test_a_mixture_s_quantile_solves_its_cdf_and_states_left_out_count_as_no_brake():
    f = _fixed(NORMAL, 0.1, 0.9, 0.005, probability=(0.99, 0.01 - 1e-6))
    f.a[1] = -0.2   # a state that loses a third of the brake
    x = f.quantile(1e-3, missing=1e-6)
    assert f.mixture_cdf(x, 1e-6) == pytest.approx(1e-3, rel=1e-6)
    assert f.quantile(1e-7, missing=1e-6) == 0.0


def _lhs_truncated(n, rng):
    u = qmc.LatinHypercube(d=1, seed=rng).random(n)[:, 0]
    return truncnorm(-3.0, 3.0, loc=1.0, scale=0.05).ppf(u)


def test_the_bound_covers_the_true_quantile_in_95_percent_of_repeated_analyses():
    # three states (a healthy one of many runs, two rare ones of 8 runs), ratios a + b P + N(0, s);
    # the true mixture's quantile is computed from the true parameters
    true = [(0.999, 0.10, 0.90, 0.006, 256), (9e-4, 0.05, 0.85, 0.006, 8), (1e-4 - 1e-12, 0.0, 0.80, 0.008, 8)]
    probabilities = [p for p, *_ in true]
    exact = Fits(TRUNCATED, np.array(probabilities), *(np.array(x, float) for x in list(zip(*true))[1:4]),
                 np.array([n for *_, n in true]), np.zeros((3, 2, 2)), np.zeros(3))
    rng = np.random.default_rng(36)
    for level in (1e-2, 1e-5):
        truth, covered, widths = exact.quantile(level), 0, []
        trials = 200
        for _ in range(trials):
            factors = [_lhs_truncated(n, rng) for *_, n in true]
            ratios = [a + b * p + rng.normal(0.0, s, p.size) for (_, a, b, s, _), p in zip(true, factors)]
            fits = Fits.of(TRUNCATED, probabilities, ratios, factors)
            x = fits.quantile(level)
            half, shares = fits.bound(level, x)
            covered += abs(x - truth) <= half
            widths.append(half)
            assert shares.sum() == pytest.approx(1.0)
        # 95 % nominal, the rare states' share inflated for their few runs: at least 90 % of 200
        assert covered >= 0.90 * trials, (level, covered, np.median(widths))


def test_a_state_without_slope_or_spread_is_a_step_or_the_normal_of_its_runs():
    f = Fits.of(TRUNCATED, [0.5, 0.5], [np.full(4, 0.7), np.array([0.9, 1.0, 1.1])],
                [np.linspace(0.9, 1.1, 4), np.ones(3)])
    assert f.b.tolist() == [0.0, 0.0]
    assert f.cdfs(0.6999)[0] == 0.0 and f.cdfs(0.7)[0] == 1.0
    assert f.cdfs(1.0)[1] == pytest.approx(0.5)


def test_a_plant_s_ratio_is_linear_in_the_train_s_pad_friction(tmp_path):
    # the no-failure state of 2 CRH380A cars from 80 km/h with the shipped scatter file: a
    # quadratic term in the pad friction's draw leaves the residual's spread as it is
    none = tmp_path / "none.yaml"
    none.write_text("schema: railbrake.reliability/1\nname: none\nsource: test\nfailures: []\n")
    spec = model.spec("crh380a-8", reliability=none, cars=2, initial_speed_kmh=80.0, samples=64,
                      force_conditions=True)
    ctx = runs.context(spec)
    quantity, _ = scatter.train_tolerance(ctx.scatter)
    rows = runs.run_batch(spec, [(0, i) for i in range(64)])
    stop = np.array([r["stopping_distance_m"] for r in rows])
    p = ctx.train_draws(0, list(range(64)), quantity)
    y = 1.0 / stop   # the mean deceleration goes as 1 / distance
    lin = np.polynomial.polynomial.polyfit(p, y, 1, full=True)[1][0][0]
    quad = np.polynomial.polynomial.polyfit(p, y, 2, full=True)[1][0][0]
    assert quad >= 0.9 * lin   # the quadratic term takes under 10 % of the residual's sum of squares
    assert np.corrcoef(p, y)[0, 1] > 0.9   # and the pad friction carries the spread


def test_only_a_single_scattering_train_tolerance_is_read_given():
    shipped = inputs.load_scatter("hs-emu")
    assert scatter.train_tolerance(shipped)[0] == "pad_friction"
    two = shipped.model_copy(update={"load": shipped.load.model_copy(update={"per": "train"})})
    assert scatter.train_tolerance(two) is None   # two of them: the runs' bootstrap
    assert scatter.train_tolerance(None) is None
    assert conditional.Law.of(shipped.pad_friction).low == 0.85
