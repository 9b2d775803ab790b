"""Rail conditioning cell by cell (core/src/rail_conditioning.c) in runs of the presets.

- heavy-rain's car-by-car targets (front car 0.02, car 4 0.05 at 300 km/h, Shinkansen heavy rain)
  hold with the rail cleaned cell by cell, measured as the preset file says.
- rail_conditioning "axles": the file's cells block is inert, the run is that of the condition
  without it, bit for bit (the plant as it was before the cells).
- With the cells, the maximum adhesion of successive cars rises, the air balance closes.
"""

import re
from importlib import resources

import numpy as np
import pytest

from railbrake import simulation
from railbrake.adhesion import car_max_adhesion, load_condition
from railbrake.scenario import load

HEAVY_RAIN = load_condition("heavy-rain")


def _run(**changes):
    return simulation.run(load("emergency-300-heavy-rain").with_(changes))


@pytest.fixture(scope="module")
def cells16():
    return _run(**{"adhesion.rail_conditioning": "cells"})


def test_heavy_rain_targets_hold_with_rail_cells(cells16):
    k = HEAVY_RAIN.conditioning
    assert k.reference_energy > 0 and k.calibration_scenario == "emergency-300-heavy-rain"
    cars = car_max_adhesion(cells16, k.calibration_above_kmh)
    for target in (t for t in HEAVY_RAIN.targets if t.get("car")):
        assert cars[target["car"]] == pytest.approx(target["peak"], rel=target["rel_tolerance"])


def test_cars_behind_see_more_adhesion(cells16):
    cars = car_max_adhesion(cells16, HEAVY_RAIN.conditioning.calibration_above_kmh)
    values = np.array([cars[c] for c in sorted(cars)])
    assert np.all(np.diff(values[:8]) > 0)   # cleaned rail: rising over the first cars
    assert values[-1] > 2 * values[0]


def test_air_balance_closes_with_rail_cells(cells16):
    """(The energy balance with sliding wheels on cleaned rail: core/tests/test_rail_conditioning.c.)"""
    k = cells16.kpis
    assert k["air_balance_error"] < 1e-9
    assert k["stopped"]


def test_axles_mode_ignores_the_cells_block(tmp_path):
    text = tmp_path / "heavy-rain.yaml"
    original = (resources.files("railbrake") / "data" / "adhesion" / "heavy-rain.yaml").read_text()
    without = re.sub(r"\n  # the plant's rail cells.*?calibration_above_kmh: [0-9.]+\n", "\n", original, flags=re.S)
    assert "cells:" not in without and "recovery_axles: 8.7" in without
    text.write_text(without)
    a = _run(**{"adhesion.rail_conditioning": "axles", "train.cars": 4})
    b = _run(**{"adhesion.condition": str(text), "train.cars": 4})
    assert a.outputs.keys() == b.outputs.keys()
    for name in a.outputs:
        assert np.array_equal(a.outputs[name], b.outputs[name]), name
