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


# decel_slip_speed: the whole train's wheels creep together past the hs-wet peak (the fastest
# wheel, their speed reference, creeps with them) until the adhesion falls off its cliff at
# 40-44 km/h; the slide that follows is 0.138 deep with the ED brake against 0.122 without, and the
# order flips with the speed estimate's margin (0.126/0.102 at 0.01 m/s^2, 0.127/0.129 at 0.02):
# not yet met
@pytest.mark.parametrize("controller", ["threshold", "slip_setpoint", pytest.param(
    "decel_slip_speed", marks=pytest.mark.xfail(strict=True, reason="issue 38: the whole train creeps past the "
                                                "hs-wet peak; with the ED brake its slide is deeper (0.138 vs 0.122)"))])
def test_no_axle_slides_deeper_with_the_ed_brake_than_without(controller):
    # max_slip: the largest |slip| of any axle above 10 km/h, every 1 ms step
    with_ed, without = _run(controller, True), _run(controller, False)
    assert max(with_ed.outputs[n].max() for n in with_ed.car_channels("ed_force")) > 10e3   # it does brake
    assert max(without.outputs[n].max() for n in without.car_channels("ed_force")) == 0.0
    deepest, deepest_off = with_ed.kpis["max_slip"], without.kpis["max_slip"]
    assert deepest <= deepest_off, (controller, deepest, deepest_off)
    if controller == "slip_setpoint":
        assert with_ed.kpis["max_slip"] < 0.15 and with_ed.kpis["adhesion_utilisation"] >= 0.80
