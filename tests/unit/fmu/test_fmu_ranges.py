"""What modelDescription.xml declares is what the FMU accepts: for every Real parameter and input
(generated from the FMU's own variable list) its declared min and max pass setReal and
exitInitializationMode, and the nearest doubles outside are refused; the declared ranges are the
core's bounds table (core/src/bounds.c). And doStep never passes the stopTime of the experiment
(FMI 2.0.4 section 4.2.1, FMI 3.0 section 4.2.1: an error)."""

import math

import pytest

from fmi_session import SCENARIO, Session
from railbrake import _core, scenario, simulation
from railbrake.fmu import export_fmu
from railbrake.fmu.variables import ORDERED, bound_name, table


def table_of(session):
    """The exporter's variable table of the 1-car plant (conftest.SCENARIO), with the C paths."""
    sc = scenario.load(SCENARIO)
    plant = simulation.plant_params(sc, 1)
    roots = {"plant": plant, "bcu": simulation.bcu_params(plant, sc, True), "wsp": simulation.wsp_params(sc)}
    return table(roots, 1, plant.atmosphere)


def ranged(md):
    return [v for v in md.modelVariables if v.type in ("Real", "Float64") and v.causality in ("parameter", "input")]


def _set_and_initialise(session, name, value, others=()):
    for other, other_value in others:
        session.set_real(other, other_value)
    session.set_real(name, value)
    if session.version == "2":
        session.fmu.setupExperiment(startTime=0.0)
    session.fmu.enterInitializationMode()
    session.fmu.exitInitializationMode()
    session.fmu.doStep(0.0, 1e-3)
    session.fmu.reset()


def check_declared_ends(session):
    """Each ranged variable's declared ends pass setReal, initialisation and a step; the nearest
    doubles outside are refused, naming the variable and its range. Returns how many were checked."""
    variables = ranged(session.md)
    for v in variables:
        low, high = float(v.min), float(v.max)
        assert math.isfinite(low) and math.isfinite(high) and low <= float(v.start) <= high, v.name
        for end in (low, high):
            _set_and_initialise(session, v.name, end)
        for outside in (math.nextafter(low, -math.inf), math.nextafter(high, math.inf)):
            session.fails(session.set_real, v.name, outside, words=(v.name, "must be a finite number in ["))
            session.fmu.reset()
    return len(variables)


def test_declared_ends_are_accepted_and_beyond_refused(session):
    assert check_declared_ends(session) > 20


def test_the_governor_pair_initialises_at_every_corner_of_its_declared_ranges(session):
    """governor_off >= governor_on: the declared ranges of the pair meet, so each combination of
    their ends initialises (with the other at its start value above, with each other here)."""
    by_name = {v.name: v for v in session.md.modelVariables}
    on, off = (by_name[name] for name in ORDERED)
    assert float(on.max) == float(off.min) and float(on.start) < float(on.max) < float(off.start)
    for on_end in (float(on.min), float(on.max)):
        for off_end in (float(off.min), float(off.max)):
            _set_and_initialise(session, "governor_off", off_end, others=(("governor_on", on_end),))


@pytest.fixture(scope="module")
def two_cars(tmp_path_factory):
    """The 2-car plant (FMI 2): the coupler's parameters exist only between two cars."""
    return export_fmu(SCENARIO, tmp_path_factory.mktemp("fmi2-two-cars") / "plant.fmu", "2", cars=2)


def test_declared_ends_of_the_coupler_parameters_too(two_cars, tmp_path):
    session = Session("2", two_cars, tmp_path / "unzipped")
    try:
        names = {v.name for v in ranged(session.md)}
        assert any("coupler" in name for name in names), sorted(names)
        assert check_declared_ends(session) == len(names)
    finally:
        session.fmu.freeInstance()


def test_declared_parameter_ranges_are_the_bounds_table(session):
    """Every Real parameter has an entry in the core's table and declares exactly its range."""
    paths = {v.name: v.where for v in table_of(session)}
    starts = {v.name: float(v.start) for v in session.md.modelVariables if v.name in ORDERED}
    pivot = 0.5 * (starts["governor_on"] + starts["governor_off"])
    for v in ranged(session.md):
        if v.causality == "parameter":
            low, high = _core.bound(bound_name(paths[v.name]))
            if v.name == "governor_on":     # the ordered pair: each on its side of the midpoint
                high = pivot
            elif v.name == "governor_off":
                low = pivot
            assert (float(v.min), float(v.max)) == (low, high), v.name


def _initialise(session, stop_time):
    if session.version == "2":
        session.fmu.setupExperiment(startTime=0.0, stopTime=stop_time)
        session.fmu.enterInitializationMode()
    else:
        session.fmu.enterInitializationMode(startTime=0.0, stopTime=stop_time)
    session.fmu.exitInitializationMode()


def test_no_step_past_the_stop_time(session):
    """Steps up to the stopTime pass (also one that ends on it); one step beyond fails, naming it."""
    _initialise(session, 0.05)
    for k in range(5):
        session.fmu.doStep(k * 0.01, 0.01)
    session.fails(session.fmu.doStep, 0.05, 1e-3, words=("passes the stopTime 0.05",))
    session.fmu.reset()
    _initialise(session, 0.0105)          # between two plant steps: 10 steps fit, not 11
    session.fmu.doStep(0.0, 0.01)
    session.fails(session.fmu.doStep, 0.01, 1e-3, words=("stopTime",))


def test_stop_time_before_start_refused(session):
    if session.version == "2":
        session.fails(session.fmu.setupExperiment, None, 0.0, -1.0, words=("stopTime = -1",))
    else:
        session.fails(session.fmu.enterInitializationMode, None, 0.0, -1.0, words=("stopTime = -1",))
