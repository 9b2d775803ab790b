"""What a better brake buys on the line: the EBI-to-EoA distance and the time lost in braking
from the top speed, per WSP controller, on dry rail and on the EN 15595 test adhesion
(docs/etcs.md).

The curves depend on the brake through the braking model's train data. Kwet_rst is the one that
the WSP controller changes: it comes from the EN 15595 test pairs (railbrake.etcs.model.kwet, the
same runs, each controller's). The other data (A_brake_emergency, Kdry_rst on dry rail, T_be and
the service data) are the braking model's. "Dry" is the trackside's M_NVAVADH = 1 (no wet-rail
reduction: Kwet_rst has no effect), "EN 15595 test adhesion" M_NVAVADH = 0 (the full reduction).
"""

from __future__ import annotations

import copy
import typing
import warnings

import numpy as np

from railbrake import scenario, simulation, sizing
from railbrake.etcs import confidence, curves, model, runs
from railbrake.etcs.national import National, Track
from railbrake.resolve import resolve
from railbrake.units import KMH

CONTROLLERS = typing.get_args(scenario.WspSettings.model_fields["controller"].annotation)
ADHESION = {"dry (M_NVAVADH 1)": 1.0, "EN 15595 test adhesion (M_NVAVADH 0)": 0.0}


class _Stops:
    """The EN 15595 test stops of a braking model's train with scenario changes (model.kwet's)."""

    def __init__(self, spec: runs.Spec, changes: dict):
        self.spec, self.changes = spec, dict(changes)
        base = simulation.emergency_scenario(spec.train, 1.0, spec.dry_condition)
        self.train = simulation.scenario_train(base, spec.cars)
        self.v0 = spec.initial_speed_kmh * KMH if spec.initial_speed_kmh else self.train.max_speed
        self.marks = tuple(v * KMH for v in sorted(spec.speed_steps_kmh, reverse=True) if 0 < v * KMH < self.v0)

    def stop(self, v0: float, condition: str) -> tuple:
        # the EN 15595 test level at the test speeds, forced as in runs.Context.stop
        sc = simulation.emergency_scenario(self.spec.train, v0, condition,
                                           allow_outside_validity=condition == self.spec.reduced_condition
                                           ).with_(self.changes)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sizing.SupplyWarning)
            return simulation.structs(resolve(sc, len(self.train.cars)))


def spec_of(data: dict) -> runs.Spec:
    a = dict(data["analysis"])
    a["speed_steps_kmh"] = tuple(a["speed_steps_kmh"])
    return runs.Spec(**a)


def time_following(points: list) -> float:
    """Time (s) to run a curve's [distance m, speed km/h] points down to its end, each piece at
    constant deceleration (V^2 linear in distance): 2 dx / (v1 + v2)."""
    x = np.asarray([p[0] for p in points])
    v = np.asarray([p[1] for p in points]) * KMH
    return float(np.sum(2.0 * np.diff(x) / (v[:-1] + v[1:])))


def study(data: dict, service: dict, track: Track, national: National, controllers=CONTROLLERS) -> list[dict]:
    """Per controller and adhesion: Kwet_rst, the EBI's distance to the EoA at the top speed and
    the time lost following the permitted speed from the top speed to the EoA (against running
    the same distance at the top speed)."""
    spec = spec_of(data)
    rows = []
    for controller in controllers:
        kwet, _, _ = model.kwet(_Stops(spec, {"wsp.controller": controller}), data["T_brake_emergency_s"])
        variant = copy.deepcopy(data)
        variant["Kwet_rst"]["coded"] = confidence.coded(kwet)
        for label, avadh in ADHESION.items():
            r = curves.compute(variant, service, track, national.model_copy(update={"M_NVAVADH": avadh}))
            p = r["curves"]["P"]
            top = p[0][1] * KMH
            rows.append({"controller": controller, "adhesion": label, "Kwet_rst": confidence.coded(kwet),
                         "Kwet_before_rounding": kwet,
                         "EBI_to_EoA_m": r["eoa_m"] - r["curves"]["EBI"][0][0],
                         "time_lost_s": time_following(p) - (p[-1][0] - p[0][0]) / top,
                         "top_speed_kmh": p[0][1]})
    return rows
