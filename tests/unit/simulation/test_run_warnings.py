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
