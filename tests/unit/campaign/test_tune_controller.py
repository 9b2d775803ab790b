"""`wsp tune` tunes one WSP controller on that controller's runs: a study running every controller
(wsp-en15595) keeps the runs of the one asked for, or of the first that reads every tuned
parameter, so `railbrake wsp tune wsp-en15595 --params speed_threshold,decel_threshold` (the
example of its --help) plans no run whose controller would refuse a tuned key."""

import pytest

from railbrake.campaign import plan, study, tune
from railbrake.errors import InputError
from railbrake.scenario import CONTROLLER_KEYS


@pytest.fixture(scope="module")
def en15595():
    return study.load("wsp-en15595")


def controllers(s, only):
    return {r.factors["wsp.controller"] for r in plan.plan(s, tune.select(s, only))}


def test_the_help_example_keeps_the_runs_of_the_controller_that_reads_its_parameters(en15595):
    only = tune.controller_only(en15595, ["speed_threshold", "decel_threshold"], None, [])
    assert only == ["wsp.controller=threshold"]
    assert controllers(en15595, only) == {"threshold"}
    assert controllers(en15595, []) == set(CONTROLLER_KEYS)   # without it: every controller's runs


@pytest.mark.parametrize("params, controller", [(["wsp.setpoint_speed"], "slip_setpoint"),
                                                (["ds_speed_threshold", "ds_decel_threshold"], "decel_slip_speed")])
def test_each_controller_s_own_parameters_choose_it(en15595, params, controller):
    assert tune.controller_only(en15595, params, None, []) == [f"wsp.controller={controller}"]


def test_an_explicit_controller_or_only_is_kept_and_checked(en15595):
    assert tune.controller_only(en15595, ["speed_threshold"], "slip_setpoint", []) == \
        ["wsp.controller=slip_setpoint"]
    assert tune.controller_only(en15595, ["speed_threshold"], None, ["wsp.controller=threshold"]) == \
        ["wsp.controller=threshold"]
    with pytest.raises(InputError, match="the decel_slip_speed controller does not read speed_threshold"):
        tune.controller_only(en15595, ["speed_threshold"], "decel_slip_speed", [])
    with pytest.raises(InputError, match="disagree"):
        tune.controller_only(en15595, ["speed_threshold"], "threshold", ["wsp.controller=slip_setpoint"])
    with pytest.raises(InputError, match="no WSP controller reads them all"):
        tune.controller_only(en15595, ["reaccel_threshold", "setpoint_speed"], None, [])
    with pytest.raises(InputError, match="--controller pid: one of threshold"):
        tune.controller_only(en15595, ["speed_threshold"], "pid", [])
