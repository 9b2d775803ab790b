"""One valve from design to plant: the real-time plant with the reduced valve parameters derived
from the default designs (data/valves/reduced.yaml, carried by every preset train) against the
detailed model, which simulates those designs themselves (compare-rt). Issue 11 asks, on
emergency-250-dry and emergency-300-heavy-rain: stopping distance within 1 %, 1 s-mean cylinder
pressure RMS under 0.1 bar."""

import pytest
import yaml

from railbrake import scenario, simulation, valves
from railbrake.resolve import resolve
from railbrake.vehicle import load_train, preset_names

REDUCED = yaml.safe_load((valves.params.DATA / "reduced.yaml").read_text())["plant"]


@pytest.mark.parametrize("train", preset_names())
def test_every_preset_train_carries_the_reduced_valves(train):
    sc = scenario.load("emergency-250-dry").with_({"initial_speed": "100 km/h"})   # within every preset's speed
    plant = simulation.plant_params(sc, 2, train=load_train(train))
    for car in plant.car[:2]:
        for key, value in REDUCED.items():
            assert getattr(car, key) == pytest.approx(value, rel=1e-6), (train, key)   # the fragment is printed to 7 digits


# The agreement itself (compare-rt on emergency-250-dry and emergency-300-heavy-rain, 1 and 8 cars:
# distance within 1 %, 1 s-mean cylinder RMS under 0.1 bar) is checked once, in
# tests/unit/simulation/test_compare.py, on the same comparisons the plant tests use.


def _rain_distance(**keys):
    sets = [f"train.car_types.{kind}.{key}={value}" for kind in ("motor", "trailer") for key, value in keys.items()]
    return simulation.run(resolve("emergency-300-heavy-rain", 1, sets)).kpis["stopping_distance_m"]


@pytest.mark.slow
def test_heavy_rain_distance_depends_on_the_wsp_valves_not_on_the_reduced_ep_and_relay():
    # why the reduction of the EP and relay valves is not where the heavy-rain difference sits:
    # halving or doubling their reduced parameters moves the plant's distance far less than a
    # 20 % change of the WSP hold valve port does (measured: at most 0.25 % against 1.8 and 2.3 %)
    base = _rain_distance()
    car = yaml.safe_load((valves.params.DATA.parent / "trains" / "crh380al-16.yaml").read_text())["car_types"]["motor"]
    chain = [(f"{group}.{leaf}", car[group][leaf]) for group, leaf in (
        ("ep_valve", "response_s"), ("ep_valve", "band_bar"), ("ep_valve", "port_area_mm2"),
        ("relay_valve", "band_bar"), ("relay_valve", "supply_area_mm2"))]
    for key, value in chain:
        for factor in (0.5, 2.0):
            assert _rain_distance(**{key: value * factor}) == pytest.approx(base, rel=0.005), (key, factor)
    hold = car["wsp_valves"]["hold_area_mm2"]
    for factor in (0.8, 1.2):
        assert abs(_rain_distance(**{"wsp_valves.hold_area_mm2": hold * factor}) / base - 1.0) > 0.01, factor
