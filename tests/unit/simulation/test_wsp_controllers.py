"""Every WSP controller (core/src/bcu_wsp.c, core/src/wsp_controllers.c, core/src/wsp_decel_slip.c),
with and without the conditioning mode, against the must-holds of the WSP library (issue 28):

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
from railbrake.errors import InputError
from railbrake.scenario import load

CONTROLLERS = simulation.WSP_CONTROLLERS
SAFETY_TIME = simulation.wsp_params().safety_time
# every controller, alone and in the conditioning mode (the latter in the plain pass only: the
# sanitized pass runs the same code with the mode's factor of 1)
MODES = [pytest.param(c, False, id=c) for c in CONTROLLERS] + [
    pytest.param(c, True, id=f"{c}-conditioning", marks=pytest.mark.slow) for c in CONTROLLERS]


def _run(controller, condition="hs-wet", cars=8, scenario="emergency-300-heavy-rain", conditioning=False, **changes):
    return simulation.run(load(scenario).with_({"wsp.controller": controller, "adhesion.condition": condition,
                                                "train.cars": cars, "wsp.conditioning_mode": conditioning,
                                                **changes}))


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


@pytest.mark.parametrize("controller, conditioning", MODES)
@pytest.mark.parametrize("scenario", ["emergency-250-dry", "emergency-300-heavy-rain"])
def test_no_valve_moves_on_dry_rail(controller, conditioning, scenario):
    r = _run(controller, "dry-medium", scenario=scenario, conditioning=conditioning)
    for name in r.axle_channels("vent") + r.axle_channels("hold"):
        assert not np.any(r.outputs[name]), name


@pytest.mark.parametrize("controller, conditioning", MODES)
def test_uniform_low_adhesion_utilisation_and_locks(controller, conditioning):
    r = _run(controller, conditioning=conditioning)
    k = r.kpis
    assert 0.0 < k["adhesion_utilisation"] <= 1.0
    assert k["max_lock_duration_s"] <= SAFETY_TIME
    assert any(np.any(r.outputs[name]) for name in r.axle_channels("vent"))   # the controller acted


@pytest.mark.parametrize("controller, conditioning", MODES)
def test_lost_sensor_never_vents_beyond_the_safety_time(controller, conditioning):
    r = _run(controller, conditioning=conditioning, faults=[{"type": "sensor_lost", "car": 1, "axle": 1,
                                                             "start": "0 s"}])
    assert r.kpis["stopped"]
    assert _longest_vent(r) <= SAFETY_TIME + 0.1   # + the BCU cycle and the record's sampling
    assert not np.any(r.outputs["vent_c1a1"])      # the axle without its sensor is braked as demanded


@pytest.mark.slow   # two 4-car stops on hs-wet: 30 s under the sanitizers
@pytest.mark.parametrize("controller, conditioning", MODES)
def test_reproducible_with_a_fixed_seed(controller, conditioning):
    noisy = {"faults": [{"type": "sensor_noisy", "car": 2, "noise": "0.05 m/s", "start": "0 s"}], "seed": 7,
             "train.cars": 4}
    a, b = _run(controller, conditioning=conditioning, **noisy), _run(controller, conditioning=conditioning, **noisy)
    for name in a.outputs:
        assert np.array_equal(a.outputs[name], b.outputs[name]), name


@pytest.mark.slow   # an 8- and a 16-car stop on hs-wet
@pytest.mark.parametrize("cars", [8, 16])
def test_slip_setpoint_uses_85_percent_of_hs_wet_adhesion(cars):
    k = _run("slip_setpoint", cars=cars).kpis
    assert k["adhesion_utilisation"] >= 0.85
    assert k["max_slip"] < 0.15


def _mean_slip(result, axle_in_car: int) -> float:
    """Time-mean |slip| of the car's axle_in_car (1-based) over every car, above 10 km/h."""
    moving = result.outputs["speed"] > 10 / 3.6
    names = [n for n in result.axle_channels("slip") if n.endswith(f"a{axle_in_car}")]
    return float(np.mean([np.abs(result.outputs[n][moving]).mean() for n in names]))


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_conditioning_mode_lets_the_trailing_axle_of_each_bogie_slide_more(controller):
    """Without the mode the two axles of a bogie slide alike on uniform adhesion; with it the
    trailing one (axles 2 and 4 of a car) slides more than the leading one (1 and 3)."""
    plain, conditioned = _run(controller, cars=2), _run(controller, cars=2, conditioning=True)
    for r in (plain, conditioned):
        assert r.kpis["max_lock_duration_s"] <= SAFETY_TIME
    lead = [_mean_slip(conditioned, a) for a in (1, 3)]
    trail = [_mean_slip(conditioned, a) for a in (2, 4)]
    assert min(trail) > 1.1 * max(lead), (lead, trail)
    alike = [_mean_slip(plain, a) for a in (1, 2, 3, 4)]
    assert max(alike) < 1.05 * min(alike), alike


def test_wsp_keys_a_controller_does_not_read_are_refused():
    with pytest.raises(InputError, match=r"wsp.setpoint_speed = '0.05 m/s': the threshold controller "
                                         r"\(wsp.controller\) does not read it, only slip_setpoint"):
        load("emergency-300-heavy-rain").with_({"wsp.setpoint_speed": "0.05 m/s"})
    with pytest.raises(InputError, match=r"wsp.ds_speed_threshold.*only decel_slip_speed"):
        load("emergency-300-heavy-rain").with_({"wsp.controller": "slip_setpoint", "wsp.ds_speed_threshold": "1 m/s"})
    with pytest.raises(InputError, match=r"wsp.conditioning_ratio = 2: acts only with wsp.conditioning_mode: true"):
        load("emergency-300-heavy-rain").with_({"wsp.conditioning_ratio": 2})
    with pytest.raises(InputError, match=r"wsp.conditioning_mode: true with wsp.per_bogie: true.*valves per axle"):
        load("emergency-300-heavy-rain").with_({"wsp.conditioning_mode": True, "wsp.per_bogie": True})
    with pytest.raises(InputError, match=r"wsp.ds_decel_threshold.*0.1.*100"):
        load("emergency-300-heavy-rain").with_({"wsp.controller": "decel_slip_speed",
                                                "wsp.ds_decel_threshold": "200 m/s^2"})
    with pytest.raises(InputError, match=r"wsp.controller.*threshold.*slip_setpoint.*decel_slip_speed"):
        load("emergency-300-heavy-rain").with_({"wsp.controller": "pid"})


def test_each_controller_s_keys_reach_the_c_parameters():
    sc = load("emergency-300-heavy-rain").with_({"wsp.controller": "decel_slip_speed",
                                                 "wsp.ds_speed_threshold": "2 km/h", "wsp.ds_slip_threshold": 0.01,
                                                 "wsp.ds_decel_threshold": "3 m/s^2",
                                                 "wsp.ds_reaccel_threshold": "1 m/s^2",
                                                 "wsp.ref_decel_margin": "0.2 m/s^2",
                                                 "wsp.conditioning_mode": True, "wsp.conditioning_ratio": 2.5})
    w = simulation.wsp_params(sc)
    assert w.controller == CONTROLLERS.index("decel_slip_speed") == 2
    assert (w.ds_speed_threshold, w.ds_slip_threshold, w.ds_decel_threshold, w.ds_reaccel_threshold,
            w.ref_decel_margin) == (pytest.approx(2 / 3.6), 0.01, 3.0, 1.0, pytest.approx(0.2))
    assert (w.conditioning_mode, w.conditioning_ratio) == (1, 2.5)
    sc = load("emergency-300-heavy-rain").with_({"wsp.controller": "slip_setpoint", "wsp.setpoint_release": "2 s"})
    assert simulation.wsp_params(sc).setpoint_release == 2.0


def test_a_change_during_the_run_switches_the_controller_and_the_conditioning_mode():
    """simulation.Change (the native counterpart of the FMU's tunables) sets integer fields as
    whole numbers and refuses a fraction; the switched run differs from the plain one."""
    sc = load("emergency-300-heavy-rain").with_({"adhesion.condition": "hs-wet", "train.cars": 2,
                                                 "stop.max_time": "20 s"})
    switched = simulation.run(sc, changes=[simulation.Change(5.0, wsp={"controller": 2, "conditioning_mode": 1})])
    plain = simulation.run(sc)
    assert not np.array_equal(switched.outputs["vent_c1a2"], plain.outputs["vent_c1a2"])
    with pytest.raises(InputError, match=r"changes\[0\].wsp\['controller'\] = 1.5: must be a whole number"):
        simulation.run(sc, changes=[simulation.Change(5.0, wsp={"controller": 1.5})])
    with pytest.raises(InputError, match="valves per bogie"):
        simulation.run(load("emergency-300-heavy-rain").with_({"wsp.per_bogie": True, "train.cars": 1,
                                                               "stop.max_time": "5 s"}),
                       changes=[simulation.Change(1.0, wsp={"conditioning_mode": 1})])
