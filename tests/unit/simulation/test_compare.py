"""The real-time plant (1 ms, reduced air model) against the detailed model (valve bodies, solenoid
table, energy balance, variable-step stiff solver) on the same train, scenario and BCU.

Issue 6 asks, on emergency-250-dry and emergency-300-heavy-rain with 1 and 8 cars, for stopping
distances within 1 % and cylinder pressure RMS differences under 0.1 bar. Measured (docs/detailed.md):
both hold on dry rail; in heavy rain the distances hold but the raw pressure RMS does not (0.32 and
0.57 bar for 1 and 8 cars): the WSP cycles of the two models drift out of phase, as do those of the
real-time plant at two steps (test below) and of the detailed model at two tolerances. The heavy-rain
tests check distance, WSP activity, the air vented and the valve chain, and the phase-insensitive
1 s mean pressure RMS (< 0.1 bar, issues 11 and 12).
"""

import numpy as np
import pytest

from railbrake.simulation import run
from railbrake.resolve import resolve
from railbrake.simulation.compare import pressure_difference, stable, step_study

DRY, RAIN = "emergency-250-dry", "emergency-300-heavy-rain"


def _check_dry(c):
    s = c.summary
    assert abs(s["stopping_distance_difference_pct"]) < 1.0
    assert s["cylinder_rms_bar"] < 0.1
    assert s["vent_open_rt_s"] == s["vent_open_detailed_s"] == 0.0   # no slide on dry rail


def test_dry_one_car(compared):
    _check_dry(compared(DRY, 1))


@pytest.mark.slow
def test_dry_eight_cars(compared):
    _check_dry(compared(DRY, 8))


def _check_rain(c):
    s = c.summary
    assert abs(s["stopping_distance_difference_pct"]) < 1.0
    # the WSP works alike: vent-open time over all axles within 10 %
    assert s["vent_open_detailed_s"] == pytest.approx(s["vent_open_rt_s"], rel=0.10)
    for axle in c.axles.values():
        assert axle["rt"]["vent_commands"] > 10 and axle["detailed"]["vent_commands"] > 10
    # the cylinders fill and vent as the detailed model's (energy balance): the WSP vents as often,
    # within 5 % over the train (isothermal cylinders: 20 % fewer)
    vents = {m: sum(a[m]["vent_commands"] for a in c.axles.values()) for m in ("rt", "detailed")}
    assert vents["rt"] == pytest.approx(vents["detailed"], rel=0.05)
    # the air let out, the valves' own included (EP pilot bleed, the control chamber the relay
    # membrane sweeps): within 4 % (-2 % on 1 and 8 cars; without the valves' air -7 % and -5 %)
    assert s["air_vented_rt_kg"] == pytest.approx(s["air_vented_detailed_kg"], rel=0.04)


def test_heavy_rain_one_car(compared):
    c = compared(RAIN, 1)
    _check_rain(c)
    # the demand, EP and relay valves (before the WSP valves) agree on one car: the reduced valve
    # chain tracks the speed-dependent demand (docs/detailed.md, 'Where the difference comes from')
    assert c.summary["relay_mean_rms_bar"] < 0.05


@pytest.mark.slow
def test_heavy_rain_eight_cars(compared):
    _check_rain(compared(RAIN, 8))


# Issue 11/12: the brake effort each axle received, averaged over 1 s, agrees within 0.1 bar (worst
# axle): 0.052 bar on 1 car, 0.097 on 8 (docs/detailed.md). On 8 cars the train runs short of air in
# the last 40 s, so the valves' own air counts (the EP pilot bleed and the control chamber the relay
# membrane sweeps: 0.108 bar without them). The margin is thin: from starts a few thousandths of a
# km/h apart the plant scores 0.100 +- 0.003 bar on 8 cars, the detailed model against itself
# 0.094 +- 0.003 bar.
def test_heavy_rain_mean_pressure_agrees_one_car(compared):
    assert compared(RAIN, 1).summary["cylinder_mean_rms_bar"] < 0.1


@pytest.mark.slow
def test_heavy_rain_mean_pressure_agrees_eight_cars(compared):
    assert compared(RAIN, 8).summary["cylinder_mean_rms_bar"] < 0.1


@pytest.mark.slow   # 0.1 ms runs of the heavy-rain stop: a minute under the sanitizers
def test_one_ms_step_brakes_as_its_converged_self_under_wsp():
    # the wheelset update probes its secant stiffness at the slip the step ends near, so the 1 ms rail
    # force follows WSP's slip along the adhesion curve. One stop's gap to its 0.1 ms self depends on
    # where the WSP cycles fall (-0.02 % to -0.14 % from 280-300 km/h on one code), so the mean of
    # three initial speeds is held to 0.15 %
    gaps = []
    for speed in ("280 km/h", "290 km/h", "300 km/h"):
        scenario = resolve(RAIN, 1, {"initial_speed": speed})
        coarse, fine = (run(scenario, dt=dt).kpis["stopping_distance_m"] for dt in (1e-3, 0.1e-3))
        gaps.append(coarse / fine - 1.0)
    assert abs(np.mean(gaps)) < 0.0015, gaps


def test_wsp_cycle_phase_dominates_the_raw_pressure_rms(compared):
    # the real-time plant against itself at 0.25 ms differs in raw cylinder RMS about as much as
    # it does from the detailed model: the raw RMS measures the phase of the WSP cycles
    c = compared(RAIN, 1)
    fine = run(RAIN, cars=1, dt=0.25e-3)
    self_rms = max(pressure_difference(c.rt, fine, n)["rms_bar"] for n in fine.axle_channels("cylinder"))
    assert self_rms > 0.2
    assert c.summary["cylinder_rms_bar"] < 2.0 * self_rms


def test_step_size_study_converges_and_is_stable(compared):
    c = compared(DRY, 1)                                     # the study against the same detailed run
    steps = step_study(resolve(DRY, 1), c.detailed)
    assert [(r["dt_ms"], r["substeps"]) for r in steps] == [(0.25, 1), (0.5, 1), (1.0, 1), (2.0, 1), (5.0, 3),
                                                            (5.0, 1)]
    assert all(r["stable"] for r in steps)
    rms = [r["cylinder_rms_bar"] for r in steps if r["substeps"] == 1]   # 0.25, 0.5, 1, 2, 5 ms
    assert rms[2:] == sorted(rms[2:]) and rms[4] > 1.2 * rms[2]   # the error grows with the bare step
    # up to 1 ms converged: the emergency circuit's choke fills both models alike, so what is left
    # is the step's own error, below 0.001 bar RMS (before it the models' difference, flat in the step)
    assert max(rms[:3]) < 1e-3
    assert steps[2]["stopping_distance_m"] == pytest.approx(c.summary["stopping_distance_rt_m"])


def test_stability_check_flags_non_finite_and_ripple(compared):
    r = compared(DRY, 1).rt
    ok, _ = stable(r)
    assert ok
    bad = type(r)(r.scenario, r.cars, r.wsp, r.time, dict(r.outputs), r.units, r.kpis)
    pilot = bad.car_channels("pilot")[0]
    bad.outputs[pilot] = r.outputs[pilot] + 0.2e5 * np.where(np.arange(r.time.size) % 2, 1.0, -1.0)
    ok, why = stable(bad)
    assert not ok and "peak-to-peak" in why
    bad.outputs["speed"] = np.full_like(r.time, np.nan)
    assert stable(bad) == (False, "speed not finite")


def test_stability_check_allows_the_references_own_ripple(compared):
    # under WSP the EP output swings for a physical reason (each relay stroke sweeps the control
    # chamber), in the detailed model as in the plant; an oscillation on top of it still counts
    c = compared(RAIN, 1)
    assert stable(c.rt, c.detailed) == (True, "")
    bad = type(c.rt)(c.rt.scenario, c.rt.cars, c.rt.wsp, c.rt.time, dict(c.rt.outputs), c.rt.units, c.rt.kpis)
    pilot = bad.car_channels("pilot")[0]
    bad.outputs[pilot] = c.rt.outputs[pilot] + 0.2e5 * np.where(np.arange(c.rt.time.size) % 2, 1.0, -1.0)
    ok, why = stable(bad, c.detailed)
    assert not ok and "allowed" in why


def test_detailed_model_heats_the_discs_as_the_plant(compared):
    # the same two-node discs and fading pads (rb_plant_discs) after the detailed model's fine
    # mechanics: the friction energy and the hottest friction surface agree with the 1 ms plant's
    c = compared(DRY, 1)
    assert c.detailed.kpis["brake_energy_mj"] == pytest.approx(c.rt.kpis["brake_energy_mj"], rel=0.01)
    rise_rt = c.rt.kpis["max_disc_surface_temperature_c"] - c.rt.kpis["max_disc_temperature_c"]
    assert rise_rt > 0.0   # the surface runs ahead of the disc's mean
    assert c.detailed.kpis["max_disc_surface_temperature_c"] == pytest.approx(
        c.rt.kpis["max_disc_surface_temperature_c"], abs=2.0)
