"""Failure states counted exactly (railbrake.etcs.failures), against references computed here
without the enumeration's symmetry: every failure of every site drawn on its own.

Effect model of these cases (no plant: the counting is what is checked): an axle brakes with its
share of the train's force unless a hold valve is stuck closed or a vent valve stuck open on it, or
its car's brake is isolated; two faults on one axle lose it once."""

import numpy as np
import pytest
from scipy.stats import binom

from railbrake.errors import InputError
from railbrake.etcs import confidence, failures, inputs, mixture

AXLES = 4
LOSING = ("hold_stuck_closed", "vent_stuck_open")

# two axle-level kinds and a car-level kind on one car type, and a common-cause group on car 1
RELIABILITY = """schema: railbrake.reliability/1
name: verification
source: test
failures:
  - {kind: hold_stuck_closed, unit: axle, per_demand: 0.01, source: test}
  - {kind: vent_stuck_open, unit: axle, per_demand: 0.005, source: test}
  - {kind: car_isolated, unit: car, per_demand: 0.001, source: test}
common_cause:
  - {name: vent supply, kind: vent_stuck_open, cars: [1], per_demand: 1.0e-4, source: test}
"""


class _Car:
    def __init__(self, index, type_name):
        self.index, self.type_name = index, type_name


class _Train:
    def __init__(self, types):
        self.cars = [_Car(i, t) for i, t in enumerate(types)]


def _load(tmp_path, text):
    path = tmp_path / "rel.yaml"
    path.write_text(text)
    return inputs.load_reliability(path)


def _ratio(faults, n_cars: int) -> float:
    lost = set()
    for kind, unit, _ in faults:
        axles = range(AXLES) if unit.axle < 0 else [unit.axle]
        if kind in LOSING or kind == "car_isolated":
            lost |= {(unit.car, a) for a in axles}
    return 1.0 - len(lost) / (AXLES * n_cars)


def _exact_quantile(values: np.ndarray, probs: np.ndarray, level: float) -> float:
    """The smallest x with P(ratio <= x) >= level of a discrete law."""
    order = np.argsort(values)
    cdf = np.cumsum(probs[order])
    return float(values[order][np.searchsorted(cdf, level * (1 - 1e-12))])


def test_states_against_every_site_drawn_on_its_own(tmp_path):
    """2 cars of one type, 2 axle kinds + a car kind + a common-cause group: 19 independent
    Bernoulli sites, all 2^19 outcomes enumerated; the ratio's law and Kdry at every level equal
    the enumeration's (within 0.005, the must-hold; in fact to the floor)."""
    rel = _load(tmp_path, RELIABILITY)
    train = _Train(["A", "A"])
    _, _, states = failures.enumerate_states(rel, train, floor=1e-13)
    # reference: the bits are (car, hold axle 0-3, vent axle 0-3, isolated) x 2 cars, then the group
    p_site = [0.01] * 4 + [0.005] * 4 + [0.001]
    p = np.array(p_site * 2 + [1e-4])
    bits = (np.arange(2 ** p.size)[:, None] >> np.arange(p.size) & 1).astype(bool)
    prob = np.prod(np.where(bits, p, 1.0 - p), axis=1)
    lost = np.zeros((bits.shape[0], 2, AXLES), dtype=bool)
    for car in range(2):
        b = bits[:, 9 * car:9 * car + 9]
        lost[:, car, :] = b[:, 0:4] | b[:, 4:8] | b[:, 8:9] | (bits[:, -1:] & (car == 0))
    ref_values = 1.0 - lost.reshape(len(prob), -1).sum(axis=1) / 8.0
    assert prob.sum() == pytest.approx(1.0, abs=1e-12)
    method_values = np.array([_ratio(s.faults, 2) for s in states])
    method_probs = np.array([s.probability for s in states])
    missing = 1.0 - method_probs.sum()
    assert missing < 1e-10   # below the floor, counted as no brake: far below the highest level's 1e-9
    for x in np.unique(ref_values):   # the law, value by value
        assert method_probs[method_values == x].sum() == pytest.approx(prob[ref_values == x].sum(), abs=missing + 1e-15)
    mix = [mixture.State.of(s.probability, [v]) for s, v in zip(states, method_values)]
    for level, c in enumerate(confidence.EBCL):
        ref = _exact_quantile(ref_values, prob, 1.0 - c)
        got = mixture.k_dry(mix, c)
        print(f"EBCL {level}: method {got:.4f}, exact {ref:.4f}")
        assert abs(got - ref) <= 0.005


def test_eight_cars_two_axle_kinds_against_the_binomial(tmp_path):
    """8 cars of two types, two axle kinds: an axle is lost with q = 1 - (1 - p1)(1 - p2)
    independently of every other, so the lost axles are binomial(32, q): P(>= k lost) from the
    states equals binom.sf(k - 1, 32, q) for every k the floor reaches (the issue's case: two kinds
    landing on one axle only as often as the draws put them there)."""
    rel = _load(tmp_path, """schema: railbrake.reliability/1
name: t
source: test
failures:
  - {kind: hold_stuck_closed, unit: axle, per_demand: 1.0e-3, source: test}
  - {kind: vent_stuck_open, unit: axle, per_demand: 5.0e-4, source: test}
""")
    train = _Train(["motor", "trailer"] * 4)
    _, _, states = failures.enumerate_states(rel, train, floor=1e-13)
    q = 1.0 - (1.0 - 1e-3) * (1.0 - 5e-4)
    lost = np.array([round((1.0 - _ratio(s.faults, 8)) * 32) for s in states])
    probs = np.array([s.probability for s in states])
    missing = 1.0 - probs.sum()   # left out below the floor: may hold any number lost
    assert 0.0 <= missing < 1e-10
    for k in range(1, 5):
        exact = binom.sf(k - 1, 32, q)
        print(f"P(>= {k} axles lost): states {probs[lost >= k].sum():.6g}, binomial {exact:.6g}")
        assert exact - missing * (1 + 1e-6) - 1e-14 <= probs[lost >= k].sum() <= exact * (1 + 1e-12), k
    # and every state's failed units are distinct axles (two kinds on one axle only as a pair)
    for s in states:
        units = [(u.car, u.axle) for _, u, _ in s.faults]
        assert len(units) - len(set(units)) == sum(1 for u in set(units) if units.count(u) == 2)


def test_a_common_cause_group_given_twice_is_refused(tmp_path):
    twice = RELIABILITY + "  - {name: again, kind: vent_stuck_open, cars: [1], per_demand: 0.002, source: test}\n"
    with pytest.raises(InputError, match="given twice"):
        _load(tmp_path, twice)
    same_name = RELIABILITY + "  - {name: vent supply, kind: car_isolated, cars: [1], per_demand: 0.002, source: test}\n"
    with pytest.raises(InputError, match="given twice"):
        _load(tmp_path, same_name)


def test_the_brute_force_draw_places_faults_unit_by_unit(tmp_path):
    """failures.draw (the brute force's) against the site probabilities: each axle's hold fault
    with its 0.01 (+ nothing from the group, a vent kind), counted over many draws."""
    rel = _load(tmp_path, RELIABILITY)
    train = _Train(["A", "A"])
    common = failures.common_units(rel, train)
    rng = np.random.default_rng(5)
    n = 20_000
    hits = np.zeros((2, AXLES))
    for _ in range(n):
        for kind, u, _ in failures.draw(rel, train, common, rng):
            if kind == "hold_stuck_closed":
                hits[u.car, u.axle] += 1
    assert np.all(np.abs(hits / n - 0.01) < 5 * np.sqrt(0.01 * 0.99 / n))
