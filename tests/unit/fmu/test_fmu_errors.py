"""Calls in the wrong state, bad values and a bad instantiation token: the FMU returns an FMI
error and logs a message naming what was wrong, never crashes (FMI 2.0 / 3.0 state machines).
Driven through FMPy's low-level classes with a logger callback."""

import ctypes
import math

import pytest
from fmpy import read_model_description
from fmpy.fmi2 import fmi2Real

from fmi_session import ERROR, Session


def test_step_before_initialisation(session):
    session.fails(session.fmu.doStep, 0.0, 1e-3, words=("DoStep", "instantiated"))


def test_an_error_leaves_only_reset_and_free(session):
    """After fmi2Error/fmi3Error the standard allows only Reset and FreeInstance (FMI 2: and
    reading values): a step is refused until the instance is reset."""
    session.init()
    session.fails(session.set_real, "initial_speed", 10.0, words=("initial_speed", "parameter", "step mode"))
    session.fails(session.fmu.doStep, 0.0, 1e-3, words=("DoStep", "error state"))
    session.fmu.reset()
    session.init()
    session.fmu.doStep(0.0, 1e-3)
    session.fmu.reset()
    session.init()
    session.fails(session.set_real, "speed", 10.0, words=("speed", "output"))


def test_calls_the_state_machine_forbids(session):
    """Values cannot be read before initialisation; Terminate is not allowed in initialisation mode."""
    session.fails(session.get_real, session.vr["speed"], words=("instantiated",))
    session.fmu.reset()
    if session.version == "2":
        session.fmu.setupExperiment(startTime=0.0)
    session.fmu.enterInitializationMode()
    session.fails(session.fmu.terminate, words=("Terminate", "initialization mode"))


def test_real_status_needs_step_mode(fmu2, tmp_path):
    s = Session("2", fmu2, tmp_path / "unzipped")
    value = fmi2Real()
    last_successful_time = 2   # fmi2LastSuccessfulTime
    s.fails(s.fmu.fmi2GetRealStatus, s.fmu.component, last_successful_time, ctypes.byref(value),
            words=("GetRealStatus", "instantiated"))
    s.fmu.reset()
    s.init()
    s.fmu.doStep(0.0, 2e-3)
    s.fmu.fmi2GetRealStatus(s.fmu.component, last_successful_time, ctypes.byref(value))
    assert value.value == pytest.approx(2e-3)
    s.fmu.freeInstance()


def test_nan_and_out_of_range_inputs(session):
    session.fails(session.set_real, "initial_speed", math.nan, words=("initial_speed", "nan", "finite"))
    session.fmu.reset()
    session.init()
    session.fails(session.set_real, "service_demand", math.nan, words=("service_demand", "[0, 1]"))
    session.fmu.reset()
    session.init()
    session.fails(session.set_real, "pressure_demand_c1", -1.0, words=("pressure_demand_c1", "-1"))


def test_a_rejected_call_changes_nothing(fmu2, tmp_path):
    """Not even the valid values before the bad one (FMI 2 can read values in the error state)."""
    s = Session("2", fmu2, tmp_path / "unzipped")
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    before = s.get_real(s.vr["initial_speed"])[0]
    s.fails(s.fmu.setReal, [s.vr["initial_speed"], s.vr["service_demand"]], [10.0, 2.0],
            words=("service_demand = 2",))
    assert s.get_real(s.vr["initial_speed"])[0] == before != 10.0
    s.fmu.freeInstance()


@pytest.mark.parametrize("name, value", [("coupler_damping", 2e9), ("coupler_stiffness", 1e13),
                                         ("mass_c1", 1e-308), ("supply_volume_c1", 5e-324),
                                         ("cylinder_volume_c1", 1e-310), ("wsp_safety_time", 0.0),
                                         ("wsp_speed_threshold", -1.0)])
def test_parameters_beyond_what_the_numerics_bear(session, name, value):
    """Values the old [0, inf) ranges let through and that turned the outputs into NaN (or isolated
    every axle): the C bounds table refuses them, naming the parameter and its range."""
    session.fails(session.set_real, name, value, words=(name, "must be a finite number in ["))


def test_step_sizes_and_communication_points(session):
    session.init()
    session.fails(session.fmu.doStep, 0.0, 1.5e-3, words=("communicationStepSize = 0.0015", "whole number"))
    for bad_call in ((0.0, 0.0), (0.5, 1e-3), (0.0, 9.2e15), (0.0, math.inf), (0.0, -1e-3)):
        session.fmu.reset()
        session.init()
        session.fails(session.fmu.doStep, *bad_call, words=("doStep",))
    session.fmu.reset()
    session.init()
    session.fails(session.fmu.doStep, 0.0, 9.2e15, words=("at most 600 s",))
    session.fmu.reset()
    session.init()
    session.fmu.doStep(0.0, 2e-3)
    session.fmu.doStep(2e-3, 1e-3)
    assert session.get_real(session.vr["time"])[0] == pytest.approx(3e-3, abs=1e-15)


def test_unknown_value_reference_and_wrong_type(session):
    session.init()
    session.fails(session.get_real, 123456, words=("unknown value reference 123456",))
    session.fmu.reset()
    session.init()
    boolean = session.vr["external_bcu"]
    session.fails(session.get_real, boolean, words=(f"value reference {boolean}", "external_bcu"))


def test_governor_off_below_governor_on_refused_when_set(session):
    """governor_off below governor_on (8.5 bar absolute) is outside its declared range (which
    starts where governor_on's ends): refused at once, naming the variable and its range."""
    session.fails(session.set_real, "governor_off", 5e5, words=("governor_off", "must be a finite number in ["))


def test_bad_instantiation_token(fmu, tmp_path):
    version, path = fmu
    log = []
    with pytest.raises(Exception, match="instantiate"):
        Session(version, path, tmp_path / "unzipped", token="{wrong}", log=log)
    expected = read_model_description(str(tmp_path / "unzipped")).guid
    assert log[-1][0] == ERROR and "{wrong}" in log[-1][1] and expected in log[-1][1]
