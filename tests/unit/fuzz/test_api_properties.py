"""Property-based test (Hypothesis) over the public Python API beyond the single laws that
test_api_fuzz.py covers (issue 32, part 7): scenarios, trains, sizing, stopping distances,
adhesion, simulation set-up and runs, benches, studies, units, and the with_() of loaded
configurations. Each call takes working arguments but one, drawn from NaN, infinities, huge and
negative integers, strings, bytes, Booleans, None, lists and mappings; the property: it returns, or
raises ValueError or TypeError (railbrake.errors.InputError among them) whose message names one of
the function's arguments. No other exception type (AttributeError, OverflowError,
ctypes.ArgumentError, ...) and no hang. RAILBRAKE_FUZZ_API_EXAMPLES sets the examples per function."""

from __future__ import annotations

import inspect
import math
import os
import time
import warnings

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from railbrake import adhesion, resolve, scenario, simulation, sizing, units, vehicle
from railbrake.campaign import study

EXAMPLES = int(os.environ.get("RAILBRAKE_FUZZ_API_EXAMPLES", "40"))
TRAIN = vehicle.load_train("crh380a-8")
SCENARIO = scenario.load("emergency-250-dry")
SHORT = resolve.resolve("emergency-250-dry", cars=1, sets={"initial_speed": "20 km/h", "stop.max_time": "5 s"})
STUDY = study.load("wsp-en15595")
CONDITION = adhesion.load_condition("dry-medium")

# (function, working keyword arguments, other names its messages may use for an argument)
CASES = [
    (sizing.make_profile, dict(speed_kmh=[0, 100], deceleration_ms2=[1.0, 1.0]), {}),
    (sizing.load_profile, dict(profile="emergency"), {}),
    (sizing.target_pressure, dict(train="crh380a-8", deceleration="emergency", speeds=[10.0, 20.0], gradient=0.0,
                                  adhesion_limit=0.15, ed=None), {}),
    (sizing.stopping_distance, dict(v0=50.0, train="crh380a-8"), {}),
    (sizing.stopping_distance_constant, dict(v0=50.0, deceleration=1.0, response_time=1.0), {}),
    (sizing.coast_down, dict(train="crh380a-8", v0=50.0, v_end=40.0), {}),
    (sizing.brake_step, dict(train="crh380a-8", kind="emergency"), {}),
    (sizing.car_demands, dict(train="crh380a-8", profile="emergency"), {}),
    (sizing.forward_deceleration, dict(train="crh380a-8", speed=[10.0], p_motor=[3e5], p_trailer=[3e5]), {}),
    (sizing.supply_warnings, dict(train="crh380a-8", steps={"emergency": 1.0}, v0=50.0), {}),
    (vehicle.load_train, dict(name_or_path="crh380a-8", loaded=True), {"name_or_path": ("train",)}),
    (vehicle.with_cars, dict(train=TRAIN, n_cars=4), {}),
    (vehicle.with_constant_pad_friction, dict(train=TRAIN, speed=10.0), {}),
    (vehicle.pad_friction_of, dict(car=TRAIN.cars[0], speed=10.0), {}),
    (scenario.load, dict(scenario="emergency-250-dry"), {}),
    (resolve.resolve, dict(scenario="emergency-250-dry", cars=2, sets=()), {}),
    (simulation.kernel_code, dict(kernel="auto"), {}),
    (simulation.substeps_for, dict(dt=0.001), {}),
    (simulation.wsp_params, dict(scenario=SCENARIO), {}),
    (simulation.channels, dict(n_cars=2), {}),
    (simulation.axle_name, dict(index=3), {}),
    (simulation.emergency_scenario, dict(train="crh380a-8", initial_speed=30.0), {}),
    (simulation.bench_plant, dict(cars=1, steps=10, runs=1, seconds=0.01), {}),
    (simulation.plant_params, dict(scenario=SCENARIO, n_cars=2), {}),
    (simulation.run, dict(scenario=SHORT, record=False), {}),
    (adhesion.load_condition, dict(condition="dry-medium"), {}),
    (adhesion.peak_adhesion, dict(condition="dry-medium", speed=10.0, axle=0), {}),
    (adhesion.creep_curves, dict(condition="dry-medium", speeds=[10.0], axle=0), {}),
    (adhesion.car_of_axle, dict(axle=3), {}),
    (adhesion.car_axles, dict(car=1), {}),
    (adhesion.warn_outside_range, dict(condition=CONDITION, speed_kmh=10.0), {}),
    (study.load, dict(study="wsp-en15595", max_runs=100), {}),
    (units.kmh_to_ms, dict(v_kmh=10.0), {}),
    (units.cars_text, dict(n=3), {}),
    (lambda changes: SCENARIO.with_(changes), dict(changes={"initial_speed": "200 km/h"}), {}),
    (lambda changes: TRAIN.with_(changes), dict(changes={"max_speed_kmh": 300}), {}),
    (lambda changes: STUDY.with_(changes), dict(changes={"seeds": 2}), {}),
]

ODD = [math.nan, math.inf, -math.inf, None, "", "abc", "x.yaml", True, False, b"1", 2**70, -2**70, 1e308, -1e308, 0, -1,
       1e-320, [], [1.0, 2.0], [[1.0], [2.0, 3.0]], {}, {"a": 1}, (1,), object(), float("nan")]
# small integers only (a valid bench of 2**40 steps would be a long test, not a finding)
values = st.one_of(st.sampled_from(ODD), st.floats(allow_nan=True, allow_infinity=True),
                   st.integers(-2**80, 20) | st.integers(2**31, 2**80), st.text(max_size=6),
                   st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=3),
                   st.dictionaries(st.text(max_size=4), st.integers(), max_size=2))


def _arguments(function, base: dict) -> list[str]:
    try:
        return list(inspect.signature(function).parameters)
    except (TypeError, ValueError):
        return list(base)


def _label(function) -> str:
    return getattr(function, "__qualname__", repr(function))


@pytest.mark.parametrize("function, base, aliases", CASES, ids=[_label(c[0]) for c in CASES])
def test_a_public_function_refuses_a_bad_argument_by_name(function, base, aliases):
    names = _arguments(function, base) + [a for v in aliases.values() for a in v]

    @settings(max_examples=EXAMPLES, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
    @given(name=st.sampled_from(sorted(base)), value=values)
    def one_bad_argument(name, value):
        kwargs = dict(base, **{name: value})
        start = time.monotonic()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                function(**kwargs)
        except (ValueError, TypeError) as exc:   # InputError is a ValueError
            message = str(exc)
            keys = [str(k) for k in value] if isinstance(value, dict) else []   # a change names its key
            assert any(n in message for n in names + keys), f"{_label(function)}({name}={value!r}): {message}"
        assert time.monotonic() - start < 60, f"{_label(function)}({name}={value!r}) took over a minute"

    one_bad_argument()


def test_bench_with_2_to_the_70_runs_is_refused_at_once():
    with pytest.raises(ValueError, match=r"runs = 1180591620717411303424: must be >= 1 and <= 10000"):
        simulation.bench_plant(cars=1, steps=10, runs=2**70)
    with pytest.raises(ValueError, match=r"runs = 1180591620717411303424: must be >= 1 and <= 10000"):
        simulation.bench("emergency-250-dry", cars=1, runs=2**70)
    with pytest.raises(ValueError, match=r"steps = 1000000000000: must be >= 1 and <= 1e\+07"):
        simulation.bench_plant(cars=1, steps=10**12, runs=1)
