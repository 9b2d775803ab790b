"""The ED brake under WSP (issue 38): the traction control's slide control cuts the ED force of a
motor car whose axle slides and restores it along a ramp, and the BCU withdraws the ED demand of a
car whose WSP acts, bringing it back along a ramp once the WSP is at rest, handing what is missing
to the friction brake (core/src/plant_step.c ed_slide_control, core/src/bcu.c; parameters
data/traction/ed_slide_control.yaml). velaro-8 brakes with its ED brake in emergency: from
300 km/h on hs-wet no axle slides deeper than on the same train with its ED brake off."""

import warnings

import pytest

from railbrake import scenario, simulation, vehicle

TEXT = """schema: railbrake.scenario/1
name: ed-hs-wet
train: {preset: velaro-8}
initial_speed: 300 km/h
demand: [{time: 0 s, emergency: true}]
adhesion: {condition: hs-wet}
wsp: {controller: %s}
stop: {max_time: 400 s}
"""


def _run(controller: str, ed: bool):
    train = vehicle.load_train("velaro-8").with_({"brake_steps.emergency.ed_blending": ed})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulation.run(scenario.parse(TEXT % controller, "ed-hs-wet"), train=train)


# Not yet met for two controllers (issue 38), kept as findings:
# - decel_slip_speed: the whole train's wheels creep together past the hs-wet peak (the fastest
#   wheel, their speed reference, creeps with them) until the adhesion falls off its cliff at
#   40-44 km/h; the slide that follows is 0.127 deep with the ED brake against 0.109 without;
# - slip_setpoint: its deepest slide is a trailer's (no ED brake) at the hs-wet cliff, 0.033 with the
#   ED brake against 0.014 without; which run slides deeper is chance: over setpoint_memory
#   0.86-0.88 and setpoint_ramp 0.18-0.22 bar/s, 4 of 9 pairs slide deeper with the ED brake, the
#   deepest of all at 0.012-0.12 either way (the ED force of a car whose WSP acts is withdrawn).
@pytest.mark.parametrize("controller", ["threshold", pytest.param(
    "slip_setpoint", marks=pytest.mark.xfail(strict=True, reason="issue 38: a trailer's slide at the hs-wet cliff, "
                                             "0.033 with the ED brake vs 0.014 without (chance: 4 of 9 nearby "
                                             "settings)")), pytest.param(
    "decel_slip_speed", marks=pytest.mark.xfail(strict=True, reason="issue 38: the whole train creeps past the "
                                                "hs-wet peak; with the ED brake its slide is deeper (0.127 vs 0.109)"))])
def test_no_axle_slides_deeper_with_the_ed_brake_than_without(controller):
    # max_slip: the largest |slip| of any axle above 10 km/h, every 1 ms step
    with_ed, without = _run(controller, True), _run(controller, False)
    assert max(with_ed.outputs[n].max() for n in with_ed.car_channels("ed_force")) > 10e3   # it does brake
    assert max(without.outputs[n].max() for n in without.car_channels("ed_force")) == 0.0
    deepest, deepest_off = with_ed.kpis["max_slip"], without.kpis["max_slip"]
    assert deepest <= deepest_off, (controller, deepest, deepest_off)


def test_the_slip_setpoint_controller_keeps_the_ed_train_s_slip_and_uses_its_adhesion():
    k = _run("slip_setpoint", True).kpis
    assert k["max_slip"] < 0.15 and k["adhesion_utilisation"] >= 0.80, (k["max_slip"], k["adhesion_utilisation"])
