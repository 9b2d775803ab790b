"""Calls in the wrong state, bad values and a bad instantiation token: the FMU returns an FMI
error and logs a message naming what was wrong, never crashes (FMI 2.0 / 3.0 state machines).
Driven through FMPy's low-level classes with a logger callback."""

import math
import zipfile

import pytest
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.fmi3 import FMU3Slave

ERROR = 3   # fmi2Error == fmi3Error


class Session:
    """One FMU instance with its log; `fails(call, *words)` checks an error and its message."""

    def __init__(self, version, path, folder, token=None, log=None):
        with zipfile.ZipFile(path) as zf:
            zf.extractall(folder)
        self.md = read_model_description(str(folder))
        self.version = version
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.log = [] if log is None else log
        args = dict(guid=token or self.md.guid, unzipDirectory=str(folder),
                    modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="test")
        if version == "2":
            self.callbacks = fmi2CallbackFunctions()
            self.callbacks.logger = fmi2CallbackLoggerTYPE(
                lambda env, name, status, category, message: self.log.append((status, message.decode())))
            self.fmu = FMU2Slave(**args)
            self.fmu.instantiate(callbacks=self.callbacks)
        else:
            self.fmu = FMU3Slave(**args)
            self.fmu.instantiate(logMessage=lambda env, status, category, message:
                                 self.log.append((status, message.decode())))

    def init(self):
        if self.version == "2":
            self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def set_real(self, name, value):
        setter = self.fmu.setReal if self.version == "2" else self.fmu.setFloat64
        setter([self.vr[name]], [value])

    def get_real(self, vr):
        return (self.fmu.getReal if self.version == "2" else self.fmu.getFloat64)([vr])

    def fails(self, call, *args, words=()):
        self.log.clear()
        with pytest.raises(FMICallException) as info:
            call(*args)
        assert info.value.status == ERROR
        assert self.log and self.log[-1][0] == ERROR
        message = self.log[-1][1]
        for word in words:
            assert word in message, message
        return message


@pytest.fixture
def session(fmu, tmp_path):
    version, path = fmu
    s = Session(version, path, tmp_path / "unzipped")
    yield s
    s.fmu.freeInstance()


def test_step_before_initialisation(session):
    session.fails(session.fmu.doStep, 0.0, 1e-3, words=("doStep", "instantiated"))


def test_parameter_after_initialisation(session):
    session.init()
    session.fails(session.set_real, "initial_speed", 10.0, words=("initial_speed", "parameter", "step mode"))
    session.fails(session.set_real, "speed", 10.0, words=("speed", "output"))
    session.fmu.doStep(0.0, 1e-3)            # the instance is still usable after rejected calls


def test_nan_and_out_of_range_inputs(session):
    session.fails(session.set_real, "initial_speed", math.nan, words=("initial_speed", "nan", "finite"))
    # a rejected call changes nothing, not even the valid values before the bad one
    before = session.get_real(session.vr["initial_speed"])[0]
    setter = session.fmu.setReal if session.version == "2" else session.fmu.setFloat64
    session.fails(setter, [session.vr["initial_speed"], session.vr["service_demand"]], [10.0, 2.0],
                  words=("service_demand = 2",))
    assert session.get_real(session.vr["initial_speed"])[0] == before != 10.0
    session.init()
    session.fails(session.set_real, "service_demand", math.nan, words=("service_demand", "[0, 1]"))
    session.fails(session.set_real, "pressure_demand_c1", -1.0, words=("pressure_demand_c1", "-1"))


def test_unknown_value_reference_and_wrong_type(session):
    session.init()
    session.fails(session.get_real, 123456, words=("unknown value reference 123456",))
    boolean = session.vr["external_bcu"]
    session.fails(session.get_real, boolean, words=(f"value reference {boolean}", "external_bcu"))


def test_step_sizes_and_communication_points(session):
    session.init()
    session.fails(session.fmu.doStep, 0.0, 1.5e-3, words=("communicationStepSize = 0.0015", "whole number"))
    session.fails(session.fmu.doStep, 0.0, 0.0, words=("communicationStepSize = 0",))
    session.fails(session.fmu.doStep, 0.5, 1e-3, words=("currentCommunicationPoint = 0.5",))
    session.fmu.doStep(0.0, 2e-3)
    session.fmu.doStep(2e-3, 1e-3)
    assert session.get_real(session.vr["time"])[0] == pytest.approx(3e-3, abs=1e-15)


def test_invalid_parameter_rejected_at_initialisation(session):
    """A value inside the table's range but outside the plant's: rb_plant_check names it."""
    session.set_real("supply_volume_c1", 0.0)
    if session.version == "2":
        session.fmu.setupExperiment(startTime=0.0)
    session.fmu.enterInitializationMode()
    session.fails(session.fmu.exitInitializationMode, words=("supply_volume",))


def test_bad_instantiation_token(fmu, tmp_path):
    version, path = fmu
    log = []
    with pytest.raises(Exception, match="instantiate"):
        Session(version, path, tmp_path / "unzipped", token="{wrong}", log=log)
    expected = read_model_description(str(tmp_path / "unzipped")).guid
    assert log[-1][0] == ERROR and "{wrong}" in log[-1][1] and expected in log[-1][1]
