"""FMUs exported once per test session (1 car keeps them quick to build and run)."""

import pytest

from fmi_session import SCENARIO, Session
from railbrake.fmu import export_fmu


@pytest.fixture(scope="session", params=["2", "3"])
def fmu(request, tmp_path_factory):
    """(FMI version, path) of the 1-car emergency-250-dry plant, FMI 2.0 and 3.0."""
    path = tmp_path_factory.mktemp(f"fmi{request.param}") / "plant.fmu"
    return request.param, export_fmu(SCENARIO, path, request.param, cars=1)


@pytest.fixture(scope="session")
def fmu2(tmp_path_factory):
    return export_fmu(SCENARIO, tmp_path_factory.mktemp("fmi2only") / "plant.fmu", "2", cars=1)


@pytest.fixture
def session(fmu, tmp_path):
    """A Session of the `fmu` fixture's FMU, freed after the test."""
    version, path = fmu
    s = Session(version, path, tmp_path / "unzipped")
    yield s
    s.fmu.freeInstance()
