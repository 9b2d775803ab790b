"""One valve from design to plant: the real-time plant with the reduced valve parameters derived
from the default designs (data/valves/reduced.yaml, carried by every preset train) against the
detailed model, which simulates those designs themselves (compare-rt). Issue 11 asks, on
emergency-250-dry and emergency-300-heavy-rain: stopping distance within 1 %, 1 s-mean cylinder
pressure RMS under 0.1 bar."""

import pytest
import yaml

from railbrake import scenario, simulation, valves
from railbrake.simulation.compare import compare
from railbrake.vehicle import preset_names

REDUCED = yaml.safe_load((valves.params.DATA / "reduced.yaml").read_text())["plant"]


@pytest.mark.parametrize("train", preset_names())
def test_every_preset_train_carries_the_reduced_valves(train):
    sc = scenario.load("emergency-250-dry")
    plant = simulation.plant_params(sc, 2, train=simulation.load_train(train))
    for car in plant.car[:2]:
        for key, value in REDUCED.items():
            assert getattr(car, key) == pytest.approx(value, rel=1e-6), (train, key)   # the fragment is printed to 7 digits


@pytest.mark.parametrize("scenario_name, cars", [
    ("emergency-250-dry", 1),
    # Does not hold since the BCU demands the sizing's pressure versus speed (issue 10): 0.117 bar.
    # The demand follows each model's own speed, so under WSP cycling the two models' demands part
    # for a while; the distance still agrees within 0.3 %. Kept failing as a finding.
    pytest.param("emergency-300-heavy-rain", 1, marks=[pytest.mark.slow, pytest.mark.xfail(
        strict=True, reason="1 s-mean RMS 0.117 bar > 0.1 bar with the speed-dependent demand")]),
    pytest.param("emergency-250-dry", 8, marks=pytest.mark.slow),
])
def test_reduced_plant_agrees_with_the_detailed_valves(scenario_name, cars):
    s = compare(scenario_name, cars, steps_ms=()).summary
    assert abs(s["stopping_distance_difference_pct"]) < 1.0
    assert s["cylinder_mean_rms_bar"] < 0.1
