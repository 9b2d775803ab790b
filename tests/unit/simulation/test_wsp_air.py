"""Air as a constraint (issue 38): the slip set-point WSP on hs-wet from 300 km/h uses the adhesion
(utilisation >= 0.85, peak slip < 15 %) without emptying the air supply: the main reservoir stays
above the train file's minimum working pressure (air_supply.min_working_bar) and no car's supply
reservoir falls below its cylinder demand (max_air_shortfall_bar, the shortfall for want of air,
within 0.2 bar). (The train file's minimum working pressure itself: tests/unit/vehicle/test_train_schema.py.)"""

import warnings

import pytest

from railbrake import simulation, vehicle
from railbrake.scenario import load

SHORTFALL_BAR = 0.2   # the must-hold's "no cylinder more than 0.2 bar below its demand"


def _run(preset: str):
    sc = load("emergency-300-heavy-rain").with_({"train.preset": preset, "adhesion.condition": "hs-wet",
                                                 "wsp.controller": "slip_setpoint"})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulation.run(sc).kpis


def _check(preset: str):
    k = _run(preset)
    working = vehicle.load_train(preset).spec.air_supply.min_working_bar
    assert k["adhesion_utilisation"] >= 0.85, k["adhesion_utilisation"]
    assert k["max_slip"] < 0.15, k["max_slip"]
    assert k["min_main_reservoir_bar"] >= working, (k["min_main_reservoir_bar"], working)
    assert k["max_air_shortfall_bar"] <= SHORTFALL_BAR, k["max_air_shortfall_bar"]
    assert k["max_air_shortfall_bar"] == max(0.0, -k["min_supply_margin_bar"])


def test_slip_setpoint_keeps_the_air_of_8_cars_on_hs_wet():
    _check("velaro-8")


@pytest.mark.slow   # a 16-car stop from 300 km/h: about 25 s under the sanitizers
def test_slip_setpoint_keeps_the_air_of_16_cars_on_hs_wet():
    _check("crh380al-16")

