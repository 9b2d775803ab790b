"""Argument fuzzer for the public Python API (railbrake.contact, railbrake.pneumatics, the single
laws of railbrake.vehicle, railbrake.sizing.make_profile): every call with one bad argument (NaN,
infinities, None, strings, Booleans, wrong shapes, 1e308, 0, -1, ...) either raises ValueError or
TypeError whose message names that argument as the caller wrote it, or returns a finite result
(non-negative where the quantity is: forces, conductances, radii, masses, friction). Then random
calls with several bad arguments at once: RAILBRAKE_FUZZ_API_CALLS (500 here, 50 000 in `make fuzz`)."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import random

import numpy as np
import pytest

from railbrake import contact, pneumatics, sizing, vehicle
from railbrake.contact import PolachParams

CALLS = int(os.environ.get("RAILBRAKE_FUZZ_API_CALLS", "500"))
DRY = PolachParams(0.55, 0.40, 0.60, 1.0, 0.4)
CONTACT = contact.default_contact()

# (function, keyword arguments that work, result is non-negative, arguments that take arrays,
#  arguments for which +inf is meaningful)
CASES = [
    (contact.hertz_contact, dict(normal_force=8e4, rx=0.46, ry=0.3), True, (), ()),
    (contact.wheel_rail_contact, dict(wheel_radius=0.46, axle_load=17e3, rail_head_radius=0.3,
                                      wheel_profile_radius=math.inf), True, (), ("wheel_profile_radius",
                                                                                 "rail_head_radius")),
    (contact.kalker_c11, dict(a_over_b=1.2, poisson=0.28), True, (), ()),
    (contact.kalker_c23, dict(a_over_b=0.8, poisson=0.28), True, (), ()),
    (contact.polach_coefficient, dict(creep=[-0.01, -0.1], speed=50.0, normal_force=8e4, contact=CONTACT,
                                      params=DRY), False, ("creep", "speed"), ()),
    (contact.polach_peak, dict(speed=50.0, normal_force=8e4, contact=CONTACT, params=DRY), True, (), ()),
    (PolachParams, dict(mu0=0.55, A=0.4, B=0.6, kA=1.0, kS=0.4), True, (), ()),
    (pneumatics.orifice_mass_flow, dict(p_up=6e5, T_up=293.0, p_down=1e5, area=1e-5, discharge_coefficient=0.8),
     False, ("p_up", "T_up", "p_down"), ()),
    (pneumatics.sonic_conductance, dict(area=1e-5, discharge_coefficient=0.8), True, (), ()),
    (vehicle.pad_friction_sintered, dict(speed=[0.0, 50.0], low_speed_value=0.42), True, ("speed",), ()),
    (vehicle.caliper_pad_force, dict(cylinder_pressure=4e5, cylinder_area=0.03, return_spring=1500.0,
                                     lever_ratio=3.0, efficiency=0.92), True, (), ()),
    (vehicle.coupler_force, dict(dx=0.02, dv=0.1, slack=0.01, stiffness=1e7, damping=2e5), False, (), ()),
    (vehicle.equivalent_rotating_mass, dict(wheelsets=[(0.46, 120.0, 17e3)] * 4), True, ("wheelsets",), ()),
    (sizing.make_profile, dict(speed_kmh=[0, 100, 300], deceleration_ms2=[1.2, 1.1, 0.9], delay=1.0, build_up=2.0),
     True, ("speed_kmh", "deceleration_ms2"), ()),
]

ALWAYS_BAD = [math.nan, -math.inf, None, "abc", True, object(), b"1"]
MAYBE_BAD = [math.inf, 1e308, -1e308, 0, -1, 1e-320, [1.0, 2.0], [[1.0, 2.0], [3.0]], [], 7]


def numbers_in(result):
    if isinstance(result, (int, float, np.floating, np.integer)) and not isinstance(result, bool):
        yield float(result)
    elif isinstance(result, np.ndarray):
        yield from (float(x) for x in result.ravel())
    elif isinstance(result, (tuple, list)):
        for x in result:
            yield from numbers_in(x)
    elif dataclasses.is_dataclass(result):
        for f in dataclasses.fields(result):
            yield from numbers_in(getattr(result, f.name))


def outcome(function, kwargs, bad: set, non_negative: bool):
    """None when the call behaved; else what went wrong."""
    try:
        result = function(**kwargs)
    except (ValueError, TypeError) as exc:
        if bad and not any(name in str(exc) for name in bad):
            return f"{type(exc).__name__} naming none of {sorted(bad)}: {exc}"
        return None
    except Exception as exc:   # noqa: BLE001 - counted
        return f"{type(exc).__name__}: {exc}"
    values = list(numbers_in(result))
    if any(not math.isfinite(x) for x in values):
        return f"returned a non-finite value: {result!r}"[:200]
    if non_negative and any(x < 0 for x in values):
        return f"returned a negative value: {result!r}"[:200]
    return "accepted"


def label(function, kwargs) -> str:
    return f"{function.__name__}({', '.join(f'{k}={v!r}' for k, v in kwargs.items())})"[:160]


def test_every_argument_alone():
    problems, calls = [], 0
    for function, base, non_negative, arrays, infinite_ok in CASES:
        assert outcome(function, dict(base), set(), non_negative) == "accepted", function.__name__
        for name in base:
            for value in ALWAYS_BAD + MAYBE_BAD:
                kwargs = dict(base, **{name: value})
                got = outcome(function, kwargs, {name}, non_negative)
                calls += 1
                must_raise = any(value is v for v in ALWAYS_BAD) and not (value is math.inf and name in infinite_ok)
                if got == "accepted" and must_raise:
                    got = "accepted an argument that is not a number"
                if got not in (None, "accepted"):
                    problems.append(f"{label(function, kwargs)}: {got}")
    # relative_radius takes its radii positionally
    for value in ALWAYS_BAD + MAYBE_BAD:
        got = outcome(lambda **k: contact.relative_radius(0.46, k["r"]), {"r": value}, {"radius 2"}, True)
        calls += 1
        if got == "accepted" and any(value is v for v in ALWAYS_BAD):
            got = "accepted an argument that is not a number"
        if got not in (None, "accepted"):
            problems.append(f"relative_radius(0.46, {value!r}): {got}")
    print(f"{calls} calls with one bad argument, {len(problems)} problems")
    assert calls > 500
    assert not problems, problems[:15]
    print("fuzz-result", json.dumps({"target": "api_single", "calls": calls, "problems": 0}))


def test_random_bad_arguments():
    rng = random.Random(int(os.environ.get("RAILBRAKE_FUZZ_SEED", "1")))
    palette = ALWAYS_BAD + MAYBE_BAD + [1e-3, 0.5, 2.0, 1e6, -0.5, np.float32(3.0), np.array([1.0, -1.0])]
    problems = []
    for _ in range(CALLS):
        function, base, non_negative, arrays, infinite_ok = CASES[rng.randrange(len(CASES))]
        names = rng.sample(list(base), k=min(len(base), rng.randint(1, 3)))
        kwargs = dict(base, **{n: rng.choice(palette) for n in names})
        got = outcome(function, kwargs, set(names), non_negative)
        if got not in (None, "accepted"):
            problems.append(f"{label(function, kwargs)}: {got}")
    assert not problems, problems[:15]
    print("fuzz-result", json.dumps({"target": "api_random", "calls": CALLS, "problems": 0,
                                     "seed": os.environ.get("RAILBRAKE_FUZZ_SEED", "1")}))


@pytest.mark.parametrize("call, expected", [
    (lambda: vehicle.caliper_pad_force(math.nan, 0.03, 1500.0, 3.0, 0.92), "cylinder_pressure"),
    (lambda: vehicle.coupler_force(math.nan, 0.0, 0.01, 1e7), "dx"),
    (lambda: pneumatics.sonic_conductance(-1e-5), "area"),
    (lambda: sizing.make_profile("fast", [1.0]), "speed_kmh"),
    (lambda: contact.relative_radius(0.46, None), "radius 2"),
])
def test_the_issue_reproducers(call, expected):
    """caliper_pad_force(cylinder_pressure=nan) gave 0 N, coupler_force(dx=nan) 0 N, a negative area a
    negative conductance, make_profile took anything."""
    with pytest.raises((ValueError, TypeError), match=expected):
        call()
