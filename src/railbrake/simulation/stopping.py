"""The stopping distance of a train with its own brake's build-up: ta and tb measured on the plant
(simulation.response.simulated, an emergency stop from v0 on dry rail) and the EN 14531 calculation
of sizing.stopping_distance with them. `railbrake stopping-distance` and the API take this one
default; sizing.stopping_distance alone takes the profile's ta and tb."""

from __future__ import annotations

from dataclasses import replace

from railbrake import sizing
from railbrake._args import real
from railbrake.simulation.response import simulated
from railbrake.vehicle import load_train


def stopping_distance(v0: float, train=None, profile=None, deceleration=None, response_time=None,
                      delay=None, build_up=None, **options) -> sizing.StoppingResult:
    """sizing.stopping_distance (same arguments and result), where a train without a profile,
    deceleration or response of its own brakes with its build-up measured on the plant
    (result.simulated_response is then True)."""
    own = (train is not None and profile is None and deceleration is None and response_time is None
           and delay is None and build_up is None)
    if not own:
        return sizing.stopping_distance(v0, train=train, profile=profile, deceleration=deceleration,
                                        response_time=response_time, delay=delay, build_up=build_up, **options)
    trained = load_train(train)
    measured = simulated(trained, real("v0", v0, 0.0, low_open=True))
    result = sizing.stopping_distance(v0, train=trained, delay=measured.delay, build_up=measured.build_up,
                                      **options)
    return replace(result, simulated_response=True)
