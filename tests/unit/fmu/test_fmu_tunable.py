"""Tunable parameters and fault inputs changed between doSteps of a running FMU: a WSP threshold
raised and a vent valve stuck open at 2 s in heavy rain (the WSP venting all the time,
docs/references.md). The FMU's outputs equal the baseline up to 2 s, differ from the next step on,
and equal the native run with the same change at the same time (simulation.Change, rb_run_retune);
every change is logged through the FMI logger."""

import numpy as np
import pytest
from fmpy import read_model_description

from railbrake import simulation
from railbrake.errors import InputError
from railbrake.fmu import export_fmu
from railbrake.simulation import Change

from fmi_session import Session

AT, END, STEP = 2.0, 4.0, 0.01
NEW_THRESHOLD = 3.0          # m/s, three times and more the scenario's WSP speed threshold
CHANNELS = ("speed", "cylinder_c1a1", "cylinder_c1a2", "wheel_speed_c1a1", "wheel_speed_c1a3")

SCENARIO = """schema: railbrake.scenario/1
name: heavy-rain-fault
title: Emergency brake from 300 km/h in heavy rain with a vent valve that sticks when switched on
train: {preset: crh380al-16}
initial_speed: 300 km/h
demand:
  - {time: 0 s, emergency: true}
adhesion: {condition: heavy-rain}
wsp: {enabled: true}
faults:
  - {type: vent_stuck_open, car: 1, axle: 2, start: 590 s}
stop: {speed: 0.05 m/s, max_time: 600 s}
outputs: {record_interval: 0.01 s}
source: test (emergency-300-heavy-rain with a fault for the FMU's fault input)
"""


@pytest.fixture(scope="module")
def scenario(tmp_path_factory):
    path = tmp_path_factory.mktemp("tunable") / "heavy-rain-fault.yaml"
    path.write_text(SCENARIO)
    return path


@pytest.fixture(scope="module")
def exported(scenario):
    """The scenario's FMU, exported once per FMI version: {version: path}."""
    return {version: export_fmu(str(scenario), scenario.with_name(f"plant{version}.fmu"), version, cars=1)
            for version in ("2", "3")}


@pytest.fixture(params=["2", "3"])
def run_with_change(request, exported, tmp_path):
    """The FMU stepped in 10 ms doSteps with the change made before the doStep at AT: (samples, log)."""
    version = request.param
    path = exported[version]
    log = []
    s = Session(version, path, tmp_path / "unzipped", log=log)
    s.fmu.setDebugLogging(True, [])
    s.init()
    vrs = [s.vr[name] for name in CHANNELS]
    samples = []
    for k in range(int(round(END / STEP)) + 1):
        t = k * STEP
        samples.append([t, *s.get_real_many(vrs)])
        if abs(t - AT) < 1e-9:
            s.set_real("wsp_speed_threshold", NEW_THRESHOLD)
            s.set_boolean("fault_1", True)
        if k < round(END / STEP):
            s.fmu.doStep(t, STEP)
    s.fmu.freeInstance()
    return np.array(samples), log


def _native(scenario, changes=()):
    result = simulation.run(str(scenario), cars=1, changes=changes)
    return result


def test_changes_between_do_steps_act_from_the_next_step_as_in_the_native_run(run_with_change, scenario):
    samples, log = run_with_change
    changed = _native(scenario, [Change(AT, wsp={"speed_threshold": NEW_THRESHOLD}, faults=(0,))])
    baseline = _native(scenario)
    fault_only = _native(scenario, [Change(AT, faults=(0,))])
    times = samples[:, 0]
    rows = np.searchsorted(changed.time, times - 1e-9)
    assert np.allclose(changed.time[rows], times, atol=1e-9)
    before, after = times <= AT + 1e-9, times > AT + 1e-9
    for i, name in enumerate(CHANNELS, start=1):
        fmu, native, base = samples[:, i], changed.outputs[name][rows], baseline.outputs[name][rows]
        assert np.all(np.abs(fmu - native) <= 1e-9 * np.abs(native)), name
        assert np.array_equal(native[before], base[before]), name
    # from the next step on: the stuck vent empties cylinder c1a2 at once
    first_after = np.argmax(after)
    assert samples[first_after, 2] != baseline.outputs["cylinder_c1a2"][rows][first_after]
    # ... and the WSP threshold counts on its own (the fault-only run differs from the tuned one)
    assert not np.array_equal(fault_only.outputs["wheel_speed_c1a1"], changed.outputs["wheel_speed_c1a1"])
    messages = [m for _, m in log]
    assert any("wsp_speed_threshold = 3 at t = 2.000000 s" in m for m in messages), messages
    assert any("fault_1 starts at t = 2.000000 s" in m for m in messages), messages


def test_fixed_parameters_stay_fixed_and_tuned_ones_are_checked(exported, tmp_path):
    path = exported["2"]
    md = read_model_description(str(path))
    variability = {v.name: v.variability for v in md.modelVariables}
    assert variability["wsp_speed_threshold"] == variability["adhesion_mu0"] == "tunable"
    assert variability["mass_c1"] == "fixed"
    s = Session("2", path, tmp_path / "unzipped")
    s.init()
    s.fmu.doStep(0.0, STEP)
    s.fails(s.set_real, "mass_c1", 50e3, words=("mass_c1", "step mode"))
    s.fmu.reset()
    s.init()
    s.fails(s.set_real, "wsp_safety_time", 0.1, words=("wsp_safety_time", "[0.5, 30]"))
    s.fmu.freeInstance()


def test_adhesion_change_acts_as_in_the_native_run(scenario, exported, tmp_path):
    path = exported["2"]
    s = Session("2", path, tmp_path / "unzipped")
    s.init()
    s.fmu.doStep(0.0, 1.0)
    s.set_real("adhesion_mu0", 0.3)
    s.fmu.doStep(1.0, 1.0)
    fmu = s.get_real_many([s.vr["wheel_speed_c1a1"], s.vr["speed"]])
    s.fmu.freeInstance()
    native = _native(scenario, [Change(1.0, adhesion_mu0=0.3)])
    row = np.searchsorted(native.time, 2.0 - 1e-9)
    for value, name in zip(fmu, ("wheel_speed_c1a1", "speed")):
        assert value == pytest.approx(native.outputs[name][row], rel=1e-9)
    assert native.outputs["speed"][row] < _native(scenario).outputs["speed"][row]   # more adhesion, more braking


def test_bad_changes_refused(scenario):
    for change, words in ((Change(-1.0), "time"), (Change(1.0, wsp={"speed": 1.0}), "not a WSP parameter"),
                          (Change(1.0, faults=(1,)), "not a fault"), (Change(1.0, adhesion_mu0=float("nan")), "mu0")):
        with pytest.raises(InputError, match=words):
            _native(scenario, [change])
