"""The reliability and scatter files: the shipped ones load; bad ones are refused with file, line,
key and value before anything runs."""

import math
import re

import pytest

from railbrake.errors import InputError
from railbrake.etcs import inputs

RELIABILITY = """schema: railbrake.reliability/1
name: t
source: test
failures:
  - kind: ep_valve_failed
    unit: car
    per_demand: 1.0e-5
    source: x
  - kind: hold_stuck_closed
    unit: axle
    latent_rate_per_h: 1.0e-6
    test_interval_h: 24.0
    source: x
"""

COMMON_CAUSE = """common_cause:
  - name: front unit
    kind: ep_valve_failed
    cars: [1, 2]
    per_demand: 1.0e-8
    source: x
"""

SCATTER = """schema: railbrake.scatter/1
name: t
source: test
pad_friction:
  distribution: truncated_normal
  mean: 1.0
  sd: 0.05
  bounds: [0.85, 1.15]
  per: car
  source: x
"""


def _write(tmp_path, text, name="f.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_shipped_files_load():
    assert inputs.preset_names("reliability") == ["hs-emu"] and inputs.preset_names("scatter") == ["hs-emu"]
    rel = inputs.load_reliability("hs-emu")
    assert all(0.0 < f.probability() < 1e-3 for f in rel.failures)
    # every tolerance but those that cannot move the emergency stop (railbrake.etcs.effects)
    assert set(inputs.load_scatter("hs-emu").quantities()) == set(inputs.QUANTITIES) - {"valve_response",
                                                                                        "limiter_setting"}


def test_latent_failures_count_their_mean_unavailability(tmp_path):
    """A latent failure at rate l found by a test every T is present at a demand with probability
    1 - (1 - exp(-l T)) / (l T), about l T / 2 when l T is small."""
    rel = inputs.load_reliability(_write(tmp_path, RELIABILITY))
    latent = rel.failures[1]
    assert latent.probability() == pytest.approx(1e-6 * 24 / 2, rel=1e-5)
    assert rel.failures[0].probability() == pytest.approx(1e-5, rel=1e-12)


@pytest.mark.parametrize("old, new, line, key", [
    ("per_demand: 1.0e-5", "per_demand: 1.5", 7, "per_demand = 1.5"),
    ("per_demand: 1.0e-5", "per_demand: -0.1", 7, "per_demand = -0.1"),
    ("latent_rate_per_h: 1.0e-6", "latent_rate_per_h: -1.0e-6", 11, "latent_rate_per_h = -1e-06"),
    ("kind: ep_valve_failed", "kind: brake_gone", 5, "kind = 'brake_gone'"),
    ("unit: car", "unit: wagon", 5, "unit = 'wagon'"),
    ("unit: axle", "unit: car", 9, "unit = 'car'"),
    ("    test_interval_h: 24.0\n", "", 9, "test_interval_h"),
])
def test_bad_reliability_files_are_refused_with_file_line_and_key(tmp_path, old, new, line, key):
    path = _write(tmp_path, RELIABILITY.replace(old, new))
    with pytest.raises(InputError) as exc:
        inputs.load_reliability(path)
    message = str(exc.value)
    assert str(path) in message and key in message
    assert re.search(rf"line {line}\b", message), message


@pytest.mark.parametrize("second", [
    "  - name: front unit\n    kind: car_isolated\n    cars: [3]\n    per_demand: 1.0e-8\n    source: x\n",
    "  - name: other words\n    kind: ep_valve_failed\n    cars: [2, 1]\n    per_demand: 1.0e-8\n    source: x\n",
])
def test_a_common_cause_group_given_twice_is_refused(tmp_path, second):
    """Given twice, a group would fail its units twice as often: refused, naming the key and line."""
    path = _write(tmp_path, RELIABILITY + COMMON_CAUSE + second)
    with pytest.raises(InputError) as exc:
        inputs.load_reliability(path)
    message = str(exc.value)
    assert str(path) in message and "common_cause[1]" in message and "given twice" in message
    assert re.search(r"line 14\b", message), message   # the common_cause key
    inputs.load_reliability(_write(tmp_path, RELIABILITY + COMMON_CAUSE, "once.yaml"))   # once: fine


@pytest.mark.parametrize("quantity, text", [
    ("wheel_diameter", "  distribution: uniform\n  bounds: [0.0014, 1.0]\n  per: car\n  source: x\n"),
    ("pressure_control", "  distribution: truncated_normal\n  mean: 1.0\n  sd: 0.05\n  bounds: [0.01, 1.15]\n"
                     "  per: car\n  source: x\n"),
    ("load", "  distribution: normal\n  mean: 9.0\n  sd: 0.01\n  per: car\n  source: x\n"),
])
def test_a_scatter_factor_outside_its_quantitys_range_is_refused(tmp_path, quantity, text):
    """A wheel at 0.14 % of its nominal diameter is a typing slip, not a tolerance: each factor has a
    sourced range (data/etcs/factor-ranges.yaml)."""
    path = _write(tmp_path, SCATTER + f"{quantity}:\n" + text)
    with pytest.raises(InputError) as exc:
        inputs.load_scatter(path)
    message = str(exc.value)
    assert str(path) in message and f"{quantity}:" in message and "must lie in" in message
    assert re.search(r"line 11\b", message), message


@pytest.mark.parametrize("old, new, key", [
    ("  bounds: [0.85, 1.15]\n", "", "needs bounds"),
    ("distribution: truncated_normal", "distribution: gamma", "distribution"),
    ("  sd: 0.05\n", "  sd: -0.05\n", "sd"),
    ("bounds: [0.85, 1.15]", "bounds: [1.15, 0.85]", "bounds"),
    ("per: car", "per: axle", "per"),
    ("pad_friction:", "pad_wear:", "pad_wear"),
])
def test_bad_scatter_files_are_refused_with_file_line_and_key(tmp_path, old, new, key):
    path = _write(tmp_path, SCATTER.replace(old, new))
    with pytest.raises(InputError) as exc:
        inputs.load_scatter(path)
    message = str(exc.value)
    assert str(path) in message and key in message and re.search(r"line \d+", message), message


def test_a_normal_without_bounds_must_stay_positive(tmp_path):
    text = SCATTER.replace("truncated_normal", "normal").replace("  bounds: [0.85, 1.15]\n", "")
    assert inputs.load_scatter(_write(tmp_path, text)).pad_friction.distribution == "normal"
    with pytest.raises(InputError, match="mean > 10 sd"):
        inputs.load_scatter(_write(tmp_path, text.replace("sd: 0.05", "sd: 0.2"), "g.yaml"))


def test_value_faults_need_their_value(tmp_path):
    text = RELIABILITY.replace("kind: hold_stuck_closed", "kind: cylinder_leak")
    with pytest.raises(InputError, match="leak_area_mm2: needed"):
        inputs.load_reliability(_write(tmp_path, text))
    leak = inputs.load_reliability(_write(tmp_path, text.replace("test_interval_h: 24.0", "test_interval_h: 24.0\n    leak_area_mm2: 2.0"), "g.yaml"))
    assert math.isclose(leak.failures[1].value_si(), 2e-6)
