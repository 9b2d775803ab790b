"""The run's warnings mean something (issue 38): a brake cylinder below its demand is judged on
what a healthy brake of the same train does in its own build-up (simulation.response.
healthy_shortfall), so no shipped scenario without a fault and within its adhesion's validity
warns, and a real shortfall (a leaking cylinder, a supply run dry) does."""

import warnings

import pytest

from railbrake import scenario, simulation
from railbrake.adhesion.conditions import AdhesionRangeWarning
from railbrake.cli.simulation import warnings_for

LEAK = """schema: railbrake.scenario/1
name: leak
train: {preset: crh380a-8}
initial_speed: 200 km/h
demand: [{time: 0 s, emergency: true}]
adhesion: {condition: dry-medium}
faults: [{type: cylinder_leak, car: 2, axle: 1, start: 0 s, leak_area: 20 mm^2}]
stop: {max_time: 200 s}
"""


def test_no_warning_on_a_shipped_scenario_without_fault_and_with_valid_adhesion():
    checked = []
    for name in scenario.preset_names():
        sc = scenario.load(name)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = simulation.run(sc, record=False)
        if sc.spec.faults or any(issubclass(w.category, AdhesionRangeWarning) for w in caught):
            continue
        assert warnings_for(result) == [], name
        checked.append(name)
    assert len(checked) >= 3, checked   # the dry, descent and heavy-rain stops at least


def test_a_leaking_cylinder_is_warned_of():
    result = simulation.run(scenario.parse(LEAK, "leak"), record=False)
    healthy = result.meta.get("healthy_cylinder_shortfall_s")
    found = [w for w in warnings_for(result) if "below its demand" in w]
    assert found, (result.kpis["cylinder_shortfall_s"], healthy)
    assert result.kpis["cylinder_shortfall_s"] > 1.25 * result.meta["healthy_cylinder_shortfall_s"] > 0.0


def test_a_main_reservoir_below_its_minimum_working_pressure_is_warned_of():
    """The 16-car heavy-rain stop with its default WSP keeps the main reservoir above the train
    file's minimum working pressure and does not warn; with every compressor off the venting drains
    it below and the run says so."""
    sc = scenario.load("emergency-300-heavy-rain")
    for faults in ([], [{"type": "compressor_off", "start": "0 s"}]):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = simulation.run(sc.with_({"faults": faults}), record=False)
        working = result.resolved.train.spec.air_supply.min_working_bar
        below = result.kpis["min_main_reservoir_bar"] < working
        found = [w for w in warnings_for(result) if "minimum working pressure" in w]
        assert bool(found) == below, (faults, result.kpis["min_main_reservoir_bar"], working)
        assert below == bool(faults), (faults, result.kpis["min_main_reservoir_bar"])
