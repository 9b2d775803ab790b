"""A tolerance's correlation along the train (railbrake.etcs.inputs.Distribution.per: per train, per
car or per unit, with its quantity's default from data/etcs/factor-ranges.yaml):
- the default fills a scatter file's missing `per`; a correlation the quantity has no unit for is
  refused naming the file, line and key;
- the draws: per train every car's factor is one draw; per car the cars' factors are uncorrelated;
  per unit a car's factor is the mean of its 4 units', its spread half a unit's (scipy's truncated
  normal, independently of the code);
- on the whole train (no failure, pad friction only, 2 cars): the deceleration ratio's standard
  deviation goes as the tolerance's on the train's brake force, sd / sqrt(independent draws):
  sqrt(2) times larger per train than per car, twice as large per car as per unit (within the
  sampling's accuracy), and Kdry_rst lower the wider it is at every level above the median."""

import numpy as np
import pytest
from scipy.stats import truncnorm

from railbrake.errors import InputError
from railbrake.etcs import inputs, model, scatter

PAD = "pad_friction: {{distribution: truncated_normal, mean: 1.0, sd: 0.05, bounds: [0.85, 1.15], {per}source: test}}\n"
HEAD = "schema: railbrake.scatter/1\nname: t\nsource: test\n"
NO_FAILURES = "schema: railbrake.reliability/1\nname: none\nsource: test\nfailures: []\n"


def scatter_file(tmp_path, per: str | None, extra: str = ""):
    path = tmp_path / f"scatter-{per}.yaml"
    path.write_text(HEAD + PAD.format(per=f"per: {per}, " if per else "") + extra)
    return path


def test_the_default_fills_a_missing_per_and_a_unit_the_quantity_lacks_is_refused(tmp_path):
    defaults = {q: v["correlation"]["default"] for q, v in inputs.scatter_ranges().items()}
    assert set(defaults) == set(inputs.QUANTITIES)
    assert inputs.load_scatter(scatter_file(tmp_path, None)).pad_friction.per == defaults["pad_friction"]
    assert inputs.load_scatter(scatter_file(tmp_path, "unit")).pad_friction.per == "unit"
    bad = scatter_file(tmp_path, "car", "load: {distribution: uniform, bounds: [0.98, 1.02], per: unit, source: test}\n")
    with pytest.raises(InputError, match=r"line 5.*load.*per = 'unit'.*per car or per train"):
        inputs.load_scatter(bad)


def test_the_draws_follow_the_correlation(tmp_path):
    n, cars = 4096, 3
    unit_sd = float(truncnorm.std(-3.0, 3.0, loc=1.0, scale=0.05))
    for per in ("train", "car", "unit"):
        d = scatter.draws(inputs.load_scatter(scatter_file(tmp_path, per)), cars, n, 7)
        pads = d[:, inputs.QUANTITIES.index("pad_friction"), :]
        assert np.all(d[:, inputs.QUANTITIES.index("load"), :] == 1.0)
        if per == "train":
            assert np.all(pads == pads[:, :1])
            assert pads[:, 0].std() == pytest.approx(unit_sd, rel=0.02)
            continue
        assert abs(np.corrcoef(pads[:, 0], pads[:, 1])[0, 1]) < 0.06
        expected = unit_sd if per == "car" else unit_sd / 2.0   # the mean of 4 independent units
        assert pads.std(axis=0) == pytest.approx([expected] * cars, rel=0.03)
        assert pads.mean() == pytest.approx(1.0, abs=1e-3)


@pytest.mark.slow   # three analyses of 512 two-car runs
def test_kdry_spread_goes_with_the_independent_draws(tmp_path):
    rel = tmp_path / "none.yaml"
    rel.write_text(NO_FAILURES)
    spread, kdry = {}, {}
    for per in ("train", "car", "unit"):
        m = model.braking_model(model.spec("crh380a-8", reliability=rel, scatter=scatter_file(tmp_path, per), cars=2,
                                           initial_speed_kmh=80.0, samples=512, run_budget=0,
                                           force_conditions=True))
        (state,) = m.ratios   # no failure: one state, its sorted sample per speed step
        spread[per] = np.array([r.std(ddof=1) for r in state])
        kdry[per] = np.array(m.kdry)
    assert spread["train"] / spread["car"] == pytest.approx(np.full_like(spread["car"], np.sqrt(2.0)), rel=0.15)
    assert spread["car"] / spread["unit"] == pytest.approx(np.full_like(spread["car"], 2.0), rel=0.15)
    # the wider the spread, the lower Kdry_rst at every level above the median that the runs
    # themselves decide (up to 99.9 % from 512 runs); beyond, a tolerance drawn per train is read
    # through its own law, bounds included (railbrake.etcs.conditional: the ratio never falls below
    # what its lowest factor gives), the others through the normal tail of their runs, which runs
    # on past those bounds (the safe side), so their order there is the estimators', not the draws'
    decided = slice(1, 4)
    assert np.all(kdry["train"][:, decided] < kdry["car"][:, decided])
    assert np.all(kdry["car"][:, decided] < kdry["unit"][:, decided])
