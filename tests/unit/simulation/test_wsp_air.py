"""Air as a constraint (issue 38): the slip set-point WSP on hs-wet from 300 km/h uses the adhesion
(utilisation >= 0.85, peak slip < 15 %) without emptying the air supply: the main reservoir stays
above the train file's minimum working pressure (air_supply.min_working_bar) and no car's supply
reservoir falls below its cylinder demand (max_air_shortfall_bar, the shortfall for want of air,
within 0.2 bar). The train file's minimum working pressure is checked with file, line and range."""

import copy
import warnings

import pytest

from railbrake import simulation, vehicle
from railbrake.errors import InputError
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


def test_every_preset_names_its_minimum_working_pressure_below_the_governor():
    for name in ("velaro-8", "crh380al-16", "crh380a-8", "class387-4"):
        spec = vehicle.load_train(name).spec
        assert spec.supply_pressure_bar < spec.air_supply.min_working_bar < spec.air_supply.governor_on_bar


def _with(path, value, name="crh380a-8"):
    text, origin = vehicle.train_file_text(name)
    data, lines = vehicle.read_train_data(text, origin)
    data = copy.deepcopy(data)
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return data, origin, lines


@pytest.mark.parametrize("value, message", [
    (20.0, r"line \d+: air_supply\.min_working_bar = 20\.0: must lie in \[1, 10\] bar"),
    (8.0, r"min_working_bar = 8\.0 must lie below governor_on_bar = 7\.5 \(bar gauge\)"),
    (4.0, r"supply_pressure_bar = 4\.5: must stay below air_supply\.min_working_bar = 4 \(bar gauge; train crh380a-8, line \d+\)"),
])
def test_a_bad_minimum_working_pressure_is_named_with_file_line_and_range(value, message):
    data, origin, lines = _with(("air_supply", "min_working_bar"), value)
    with pytest.raises(InputError, match=message) as err:
        vehicle.parse_train_data(data, origin, lines)
    assert str(err.value).startswith("train crh380a-8")


def test_a_train_file_without_it_is_refused():
    data, origin, lines = _with(("air_supply", "min_working_bar"), None)
    del data["air_supply"]["min_working_bar"]
    with pytest.raises(InputError, match=r"air_supply\.min_working_bar"):
        vehicle.parse_train_data(data, origin, lines)
