"""One FMU instance driven through FMPy's low-level classes with a logger callback, for the tests
that check calls, states and log messages (FMI 2.0 / 3.0)."""

import zipfile

import pytest
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.fmi3 import FMU3Slave

ERROR = 3   # fmi2Error == fmi3Error
SCENARIO = "emergency-250-dry"   # the session FMUs' (conftest.py): 1 car keeps them quick to build and run


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

    def get_real_many(self, vrs):
        return list((self.fmu.getReal if self.version == "2" else self.fmu.getFloat64)(vrs))

    def set_boolean(self, name, value):
        self.fmu.setBoolean([self.vr[name]], [value])

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
