"""The KPIs the C core accumulates step by step equal their definitions (docs/simulation.md, rb_run.h)
applied to the run's own time series recorded at every 1 ms step, bit for bit. A 1-car train, so the
recorded speed is the car's; with and without WSP (locks only happen without)."""

import numpy as np
import pytest

from railbrake import simulation
from railbrake.resolve import resolve
from railbrake.simulation import ZERO_CELSIUS
from railbrake.units import BAR

LOCK_SPEED = 10.0 / 3.6   # m/s: locks and slips count above 10 km/h (rb_run.h)


@pytest.fixture(scope="module", params=[True, False], ids=["wsp", "no-wsp"])
def every_step(request):
    resolved = resolve("emergency-300-heavy-rain", cars=1,
                       sets=["initial_speed=120 km/h", "outputs.record_interval=1 ms"])
    return simulation.run(resolved, wsp=request.param)


def axles(result, quantity):
    return np.array([result.outputs[n] for n in result.axle_channels(quantity)])


def lock_episodes(result):
    """(events, longest lock): an axle below 10 % of the speed above 10 km/h; one episode per entry;
    its duration the sum of the steps' dt, in the order the steps add them."""
    dt = result.time[1] - result.time[0]
    speed, wheels = result.outputs["speed"], axles(result, "wheel_speed")
    events, longest = 0, 0.0
    for wheel in wheels:
        lock_time = 0.0
        for k in range(1, speed.size):   # row k: the state after step k
            if not speed[k] > LOCK_SPEED:
                continue
            if wheel[k] < 0.1 * speed[k]:
                events += lock_time == 0.0
                lock_time += dt
                longest = max(longest, lock_time)
            else:
                lock_time = 0.0
    return events, longest


def test_the_steps_are_recorded_one_by_one(every_step):
    assert np.allclose(np.diff(every_step.time), 1e-3, rtol=0, atol=1e-12)


def test_extremes_equal_their_definitions_on_the_series(every_step):
    r, k = every_step, every_step.kpis
    after = slice(1, None)   # the KPIs accumulate after each step (row 0: the initial state)
    counted = r.outputs["speed"][after] > LOCK_SPEED
    slips = np.abs(axles(r, "slip")[:, after][:, counted])
    assert k["max_slip"] == slips.max()
    pressures = {"main_reservoir": r.outputs["main_reservoir"], "supply": r.outputs["supply_c1"]}
    assert k["min_main_reservoir_bar"] == (pressures["main_reservoir"].min() - r.atmosphere) / BAR
    assert k["min_supply_bar"] == (pressures["supply"].min() - r.atmosphere) / BAR
    assert k["max_disc_temperature_c"] == axles(r, "disc_temperature").max() - ZERO_CELSIUS
    assert k["brake_energy_mj"] == axles(r, "brake_energy")[:, -1].sum() / 1e6
    assert k["stopping_distance_m"] == r.outputs["position"][-1] - r.outputs["position"][0]


def test_lock_events_and_durations_equal_their_definitions(every_step):
    events, longest = lock_episodes(every_step)
    assert every_step.kpis["wheel_lock_events"] == events
    assert every_step.kpis["max_lock_duration_s"] == longest


def test_valve_switchings_equal_their_definition(every_step):
    """Every change of state of a hold or vent valve from one step to the next (the recorded valve
    states), over the whole stop; on heavy rain the WSP does switch, without it nothing does."""
    r = every_step
    changes = sum(int(np.count_nonzero(np.diff(axles(r, q), axis=1))) for q in ("hold", "vent"))
    assert r.kpis["valve_switchings"] == changes
    assert (changes > 0) == r.wsp


def test_without_wsp_the_wheels_lock():
    """The lock test above is not vacuous: without WSP on heavy rain the axles lock."""
    resolved = resolve("emergency-300-heavy-rain", cars=1,
                       sets=["initial_speed=120 km/h", "outputs.record_interval=1 ms"])
    assert lock_episodes(simulation.run(resolved, wsp=False))[0] > 0
