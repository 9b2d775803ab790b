"""Comparisons of the real-time plant with the detailed model, shared by the tests of this folder
(each run once per session)."""

import pytest

from railbrake.simulation.compare import compare

_cache = {}


def comparison(scenario: str, cars: int):
    key = (scenario, cars)
    if key not in _cache:
        _cache[key] = compare(scenario, cars, steps_ms=())
    return _cache[key]


@pytest.fixture(scope="session")
def compared():
    return comparison
