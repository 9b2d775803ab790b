"""T_brake_service (T_bs) with the BCU's service jerk limit (core/src/bcu.c; the C ramp itself:
core/tests/test_bcu.c). A demand ramped at J up to the full service deceleration A has EN 14531's
te = 0.1 A/J + 0.8 A/J / 2 = A / (2 J) by itself; the plant's brake force cannot lead its demand,
and lags it by no more than it lags a step, so A / (2 J) <= T_bs(J) <= A / (2 J) + T_bs(no limit).
One car from 80 km/h on the braking model's dry rail."""

import warnings

import numpy as np
import pytest

from railbrake import simulation, sizing
from railbrake.errors import InputError
from railbrake.etcs import model, service
from railbrake.units import KMH

TRAIN, V0 = "crh380a-8", 80.0 * KMH


def _limited(train, jerk):
    return train.with_({"brake_steps.service.jerk_limit_m_s3": jerk, "brake_steps.service.jerk_limit_source": "test"})


@pytest.fixture(scope="module")
def train():
    dry = model.method().dry_condition
    return simulation.scenario_train(simulation.emergency_scenario(TRAIN, 1.0, dry), 1)


def _t_bs(train):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sizing.SupplyWarning)
        return service.build_up(train, TRAIN, V0, model.method().dry_condition)


@pytest.mark.parametrize("jerk", [0.5, 1.0, 2.0])
def test_t_bs_holds_the_ramp_and_no_more_than_the_step_lag(train, jerk):
    step, _ = sizing.brake_step(train, "service")
    a_full = float(np.interp(V0, step.speed, step.deceleration))
    free = _t_bs(train)
    limited = _t_bs(_limited(train, jerk))
    ramp = a_full / (2.0 * jerk)
    assert ramp <= limited <= ramp + free
    assert limited > free


def test_a_jerk_limit_needs_its_source(train):
    with pytest.raises(InputError, match="jerk_limit_source"):
        train.with_({"brake_steps.service.jerk_limit_m_s3": 1.0})


def test_the_service_stop_scenario_demands_service_and_checks_its_demand():
    from railbrake.simulation import response
    sc = response.service_scenario(TRAIN, V0, "dry-medium", 0.5)
    assert sc.data["demand"] == [{"time": "0 s", "service": 0.5}] and sc.name == "service-80-dry-medium"
    for demand in (0, 1.5):
        with pytest.raises(InputError, match=f"demand = {demand}: must be > 0 and <= 1"):
            response.service_scenario(TRAIN, V0, "dry-medium", demand)
