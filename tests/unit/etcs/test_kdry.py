"""Kdry_rst from a mixture of failure states (railbrake.etcs): limiting cases, the coding, the
binomial states; the eight-unit case against its exact quantiles is validation case
kdry-equal-units (docs/validation-cases.md)."""

import math

import numpy as np
import pytest
from scipy.stats import binom, norm

from railbrake import etcs
from railbrake.errors import InputError


def test_no_scatter_no_failures_gives_one_at_every_level():
    states = [etcs.State.of(1.0, np.ones(50))]
    assert [etcs.k_dry(states, c) for c in etcs.EBCL] == [1.0] * 10
    assert [etcs.coded(etcs.k_dry(states, c)) for c in etcs.EBCL] == [1.0] * 10


def test_a_unit_certain_to_fail_takes_its_share():
    """Eight equal units, one always lost: the ratio is 7/8 at every level."""
    states = [etcs.State.of(1.0, np.full(10, 7 / 8))]
    assert all(etcs.k_dry(states, c) == pytest.approx(7 / 8, rel=1e-12) for c in etcs.EBCL)


def test_normal_state_gives_the_normal_quantile():
    """One state, a large normal sample: the quantiles inside the sample are the sample's, those
    beyond it (99.99 % and up) the normal tail's."""
    sample = norm.ppf((np.arange(100_000) + 0.5) / 100_000, loc=1.0, scale=0.02)
    states = [etcs.State.of(1.0, sample)]
    for c in etcs.EBCL:
        assert etcs.k_dry(states, c) == pytest.approx(norm.ppf(1 - c, loc=1.0, scale=0.02), abs=2e-4)


def test_kdry_does_not_rise_with_the_confidence_level():
    rng = np.random.default_rng(3)
    states = [etcs.State.of(float(binom.pmf(k, 8, 1e-3)), (8 - k) / 8 + rng.normal(0, 0.02, 4000))
              for k in range(4)]
    values = [etcs.k_dry(states, c) for c in etcs.EBCL]
    assert all(a >= b for a, b in zip(values, values[1:]))
    assert all(etcs.coded(a) >= etcs.coded(b) for a, b in zip(values, values[1:]))


def test_states_left_out_count_as_no_brake():
    """States whose probability is not listed count as ratio 0: a level below it gives 0."""
    states = [etcs.State.of(1.0 - 1e-6, np.ones(3))]
    assert etcs.quantile(states, 1e-7) == 0.0
    assert etcs.quantile(states, 1e-5) == 1.0


def test_the_coding_rounds_down_onto_the_grid():
    assert etcs.coded(0.95) == 0.95 and etcs.coded(0.9499) == 0.9 and etcs.coded(1.0) == 1.0
    assert etcs.coded(0.0) == 0.0 and etcs.coded(2.0) == etcs.K_MAX == 1.0
    for bad in (-0.1, math.nan, math.inf, "1"):
        with pytest.raises((InputError, TypeError), match="correction factor"):   # TypeError: not a number
            etcs.coded(bad)


def test_confidence_levels_are_written_exactly():
    from railbrake.etcs.confidence import ebcl_text
    assert [ebcl_text(i) for i in range(10)] == ["50 %", "90 %", "99 %", "99.9 %", "99.99 %", "99.999 %",
                                                "99.9999 %", "99.99999 %", "99.999999 %", "99.9999999 %"]
    assert all(float(ebcl_text(i)[:-2]) / 100 == pytest.approx(etcs.EBCL[i], abs=1e-15) for i in range(10))


def test_confidence_levels_are_subset_026s():
    assert etcs.ebcl(0) == 0.5 and etcs.ebcl(9) == 0.999999999
    assert all(1 - etcs.ebcl(i) == pytest.approx(10.0 ** -i) for i in range(1, 10))
    for bad in (-1, 10, 2.0, True):
        with pytest.raises((InputError, TypeError), match="M_NVEBCL"):   # TypeError: not a whole number
            etcs.ebcl(bad)


def test_binomial_states_down_to_the_floor():
    states = etcs.equal_units(8, 1e-4, floor=1e-12)
    assert [s.lost for s in states] == [0, 1, 2, 3]
    assert sum(s.probability for s in states) == pytest.approx(1.0, abs=1e-12)
    assert 1.0 - sum(s.probability for s in states) < 1e-12
    assert etcs.equal_units(4, 0.0)[0].probability == 1.0 and len(etcs.equal_units(4, 0.0)) == 1
    for n, p in ((0, 0.1), (3, 1.5), (3, -0.1), (3, math.nan), (2.0, 0.1)):
        with pytest.raises((InputError, TypeError)):   # TypeError: 2.0 is no whole number
            etcs.equal_units(n, p)


def test_bad_states_are_refused():
    with pytest.raises(InputError, match="probability"):
        etcs.State.of(1.5, [1.0])
    with pytest.raises(InputError, match="finite"):
        etcs.State.of(0.5, [1.0, math.nan])
    with pytest.raises(InputError, match="add up"):
        etcs.quantile([etcs.State.of(0.7, [1.0]), etcs.State.of(0.7, [0.5])], 0.1)
    with pytest.raises(InputError, match="level"):
        etcs.quantile([etcs.State.of(1.0, [1.0])], 1.0)
