"""Every WSP controller (core/src/bcu_wsp.c, core/src/wsp_controllers.c) against the must-holds of
the WSP library (issue 28):

- dry rail: no valve moves in an emergency stop;
- uniform low adhesion (hs-wet), all axles braked: adhesion utilisation <= 1, no wheel locked
  longer than the safety timer;
- an axle's speed sensor lost: no axle vents longer than the safety time;
- bit for bit the same run twice with a fixed seed (noisy sensors);
- the slip set-point controller uses >= 85 % of the available adhesion on hs-wet from 300 km/h
  with peak slip under 15 % on the 8- and 16-car presets (KPIs: docs/simulation.md).
"""

import numpy as np
import pytest

from railbrake import simulation
from railbrake.scenario import load

CONTROLLERS = simulation.WSP_CONTROLLERS
SAFETY_TIME = simulation.wsp_params().safety_time


def _run(controller, condition="hs-wet", cars=8, scenario="emergency-300-heavy-rain", **changes):
    return simulation.run(load(scenario).with_({"wsp.controller": controller, "adhesion.condition": condition,
                                                "train.cars": cars, **changes}))


def _longest_vent(result) -> float:
    """s, the longest continuous venting of any axle in the recorded commands."""
    dt = result.time[1] - result.time[0]
    longest = 0
    for name in result.axle_channels("vent"):
        run = 0
        for venting in result.outputs[name] > 0.5:
            run = run + 1 if venting else 0
            longest = max(longest, run)
    return longest * dt


@pytest.mark.parametrize("controller", CONTROLLERS)
@pytest.mark.parametrize("scenario", ["emergency-250-dry", "emergency-300-heavy-rain"])
def test_no_valve_moves_on_dry_rail(controller, scenario):
    r = _run(controller, "dry-medium", scenario=scenario)
    for name in r.axle_channels("vent") + r.axle_channels("hold"):
        assert not np.any(r.outputs[name]), name


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_uniform_low_adhesion_utilisation_and_locks(controller):
    k = _run(controller).kpis
    assert 0.0 < k["adhesion_utilisation"] <= 1.0
    assert k["max_lock_duration_s"] <= SAFETY_TIME


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_lost_sensor_never_vents_beyond_the_safety_time(controller):
    r = _run(controller, faults=[{"type": "sensor_lost", "car": 1, "axle": 1, "start": "0 s"}])
    assert r.kpis["stopped"]
    assert _longest_vent(r) <= SAFETY_TIME + 0.1   # + the BCU cycle and the record's sampling


@pytest.mark.slow   # two 8-car stops on hs-wet: 30 s under the sanitizers
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_reproducible_with_a_fixed_seed(controller):
    noisy = {"faults": [{"type": "sensor_noisy", "car": 2, "noise": "0.05 m/s", "start": "0 s"}], "seed": 7,
             "train.cars": 4}
    a, b = _run(controller, **noisy), _run(controller, **noisy)
    for name in a.outputs:
        assert np.array_equal(a.outputs[name], b.outputs[name]), name


@pytest.mark.slow   # an 8- and a 16-car stop on hs-wet
@pytest.mark.xfail(strict=True, reason="issue 28 must-hold not met since the emergency circuit's build-up "
                   "(issue 27): 84.4 % (8 cars), 83.2 % (16 cars) with the defaults; no set-point, band or lead "
                   "time of a 50-point scan reaches 85 % on 16 cars (best 84.7 %)")
@pytest.mark.parametrize("cars", [8, 16])
def test_slip_setpoint_uses_85_percent_of_hs_wet_adhesion(cars):
    k = _run("slip_setpoint", cars=cars).kpis
    assert k["adhesion_utilisation"] >= 0.85
    assert k["max_slip"] < 0.15
