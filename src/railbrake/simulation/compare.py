"""The real-time plant checked against the detailed model (docs/detailed.md).

compare() runs a scenario with both and reports: stopping distance, cylinder pressure per axle
(RMS and largest difference over the common time base, raw and as 1 s means), WSP valve activity
per axle, and a step-size study of the real-time plant. To tell where a cylinder difference comes
from it also reports the valve chain alone (1 s-mean RMS of each car's EP output and relay
output: demand, EP and relay valves, before the WSP valves), the stopping time difference (a
train that arrives later at the WSP's low-speed release fills its cylinders later: a 1 s-mean
step of about 2 bar) and the air both vented.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from railbrake.resolve import resolve
from railbrake.results.scripting import Result
from railbrake.simulation.runs import run
from railbrake.simulation.parameters import substeps_for
from railbrake.simulation.detailed import run_detailed
from railbrake.units import BAR

STEPS_MS = (0.25, 0.5, 1.0, 2.0, 5.0)
MEAN_WINDOW = 1.0        # s, window of the brake-effort (mean pressure) comparison
RIPPLE_WINDOW = 1.0      # s, window of the stability ripple measure
RIPPLE_LIMIT = 0.1 * BAR  # Pa, peak-to-peak EP output ripple that counts as an oscillation
SETTLE = 2.0             # s after the first brake demand before the ripple is judged


@dataclass
class Comparison:
    scenario: str
    cars: int
    rt: Result
    detailed: Result
    summary: dict
    axles: dict                     # axle channel suffix -> per-axle figures
    steps: list = field(default_factory=list)
    cars_figures: dict = field(default_factory=dict)   # car suffix -> valve chain figures

    def as_dict(self) -> dict:
        return {"scenario": self.scenario, "cars": self.cars, "summary": self.summary, "axles": self.axles,
                "car_valves": self.cars_figures, "step_study": self.steps}


def common_time(a: Result, b: Result) -> np.ndarray:
    """b's record times within the span both runs cover."""
    end = min(a.time[-1], b.time[-1])
    return b.time[b.time <= end]


def _on(result: Result, channel: str, t: np.ndarray) -> np.ndarray:
    return np.interp(t, result.time, result.outputs[channel])


def _moving_mean(t: np.ndarray, x: np.ndarray, window: float) -> np.ndarray:
    """Mean of x over [t - window, t] (trapezoidal running integral)."""
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (x[1:] + x[:-1]) * np.diff(t))])
    start = np.clip(t - window, t[0], None)
    span = np.maximum(t - start, 1e-12)
    return np.where(t - t[0] > 0, (integral - np.interp(start, t, integral)) / span, x)


def pressure_difference(a: Result, b: Result, channel: str) -> dict:
    """RMS and largest |a - b| (bar) of a pressure channel on the common time base, raw and as
    MEAN_WINDOW means (the brake effort each axle received, insensitive to the phase of WSP cycles)."""
    t = common_time(a, b)
    d = _on(a, channel, t) - _on(b, channel, t)
    m = _moving_mean(t, _on(a, channel, t), MEAN_WINDOW) - _moving_mean(t, _on(b, channel, t), MEAN_WINDOW)
    return {"rms_bar": float(np.sqrt(np.mean(d**2)) / BAR), "max_bar": float(np.max(np.abs(d)) / BAR),
            "mean_rms_bar": float(np.sqrt(np.mean(m**2)) / BAR)}


def valve_activity(result: Result, axle: str) -> dict:
    """Hold and vent valve actuations (off -> on switchings of the valve, each following a BCU command
    by the response delay) and the time the vent was open."""
    t = result.time
    out = {}
    for valve in ("hold", "vent"):
        state = result.outputs[f"{valve}_{axle}"] > 0.5
        out[f"{valve}_commands"] = int(np.count_nonzero(state[1:] & ~state[:-1]))
        if valve == "vent":
            out["vent_open_s"] = float(np.sum(np.diff(t) * state[:-1]))
    return out


def _ripple(t: np.ndarray, x: np.ndarray, start: float) -> float:
    """Peak-to-peak (Pa) of x about its linear trend over [start, start + RIPPLE_WINDOW) (the demand
    follows the brake profile over speed, slowly against 1 s); 0 for too few samples."""
    w = (t >= start) & (t < start + RIPPLE_WINDOW)
    if np.count_nonzero(w) <= 2:
        return 0.0
    return float(np.ptp(x[w] - np.polyval(np.polyfit(t[w], x[w], 1), t[w])))


def stable(result: Result, reference: Result | None = None) -> tuple[bool, str]:
    """Stable: every output finite, the train stopped, and no sustained oscillation of the EP valve
    output: after SETTLE s its peak-to-peak about the linear trend stays within RIPPLE_LIMIT of the
    reference's in the same window (without one: of none), in at least one of any two successive
    RIPPLE_WINDOWs: an oscillation lasts, while a single WSP cycle the reference made a few seconds
    earlier or later (their cycles drift apart over a long stop) exceeds one window. Under WSP the output
    swings for a physical reason, which the reference shows too: each relay stroke sweeps the control
    chamber the EP valve feeds (the detailed model's swings by 0.11 bar in heavy rain); an
    integrator's oscillation comes on top of that."""
    for name, values in result.outputs.items():
        if not np.all(np.isfinite(values)):
            return False, f"{name} not finite"
    if not result.kpis["stopped"]:
        return False, "did not stop"
    t = result.time
    for name in result.car_channels("pilot"):
        x = result.outputs[name]
        above = None   # the previous window's excess, if it had one
        for start in np.arange(SETTLE, t[-1] - RIPPLE_WINDOW, RIPPLE_WINDOW):
            allowed = RIPPLE_LIMIT
            if reference is not None and start + RIPPLE_WINDOW <= reference.time[-1]:
                allowed += _ripple(reference.time, reference.outputs[name], start)
            ripple = _ripple(t, x, start)
            if ripple > allowed and above is not None:
                return False, (f"{name}: {ripple / BAR:.3f} bar peak-to-peak at {start:.1f} s and "
                               f"{above[0] / BAR:.3f} bar in the window before (allowed {allowed / BAR:.3f}, "
                               f"{above[1] / BAR:.3f})")
            above = (ripple, allowed) if ripple > allowed else None
    return True, ""


def valve_chain(a: Result, b: Result) -> dict:
    """Per car, the 1 s-mean RMS difference (bar) of the EP valve's output (pilot) and of the relay
    valve's output: the demand and valve chain before the WSP valves."""
    out = {}
    for channel in b.car_channels("pilot"):
        car = channel.split("_", 1)[1]
        out[car] = {f"{name}_mean_rms_bar": pressure_difference(a, b, f"{name}_{car}")["mean_rms_bar"]
                    for name in ("pilot", "relay")}
    return out


def _distance_pct(a: Result, b: Result) -> float:
    return 100.0 * (a.kpis["stopping_distance_m"] / b.kpis["stopping_distance_m"] - 1.0)


def step_study(scenario, detailed: Result, steps_ms=STEPS_MS, progress=None) -> list[dict]:
    """The real-time plant at each step (ms) against the detailed model (scenario: a resolved one): with its default sub-steps
    (none up to MAX_SUBSTEP) and, above that, also without them (where the bare step fails)."""
    cases = [(dt, None) for dt in steps_ms] + [(dt, 1) for dt in steps_ms if substeps_for(dt * 1e-3) > 1]
    rows = []
    for i, (dt, substeps) in enumerate(cases):
        if progress is not None:
            progress(f"real-time plant at {dt:g} ms", i / len(cases))
        r = run(scenario, dt=dt * 1e-3, substeps=substeps)
        ok, why = stable(r, detailed)
        rms = [pressure_difference(r, detailed, c) for c in detailed.axle_channels("cylinder")]
        rows.append({"dt_ms": dt, "substeps": substeps or substeps_for(dt * 1e-3),
                     "stopping_distance_m": r.kpis["stopping_distance_m"],
                     "distance_error_pct": _distance_pct(r, detailed),
                     "cylinder_rms_bar": max(x["rms_bar"] for x in rms),
                     "cylinder_mean_rms_bar": max(x["mean_rms_bar"] for x in rms),
                     "stable": ok, "instability": why})
    return rows


def figures(rt: Result, det: Result) -> tuple[dict, dict, dict]:
    """The comparison's figures of a real-time run against a detailed one: (summary, per-axle
    figures, per-car valve chain)."""
    chain = valve_chain(rt, det)
    axles = {}
    for channel in det.axle_channels("cylinder"):
        axle = channel.split("_", 1)[1]
        axles[axle] = {**pressure_difference(rt, det, channel),
                       "rt": valve_activity(rt, axle), "detailed": valve_activity(det, axle)}
    summary = {
        "stopping_distance_rt_m": rt.kpis["stopping_distance_m"],
        "stopping_distance_detailed_m": det.kpis["stopping_distance_m"],
        "stopping_distance_difference_pct": _distance_pct(rt, det),
        "cylinder_rms_bar": max(a["rms_bar"] for a in axles.values()),
        "cylinder_max_bar": max(a["max_bar"] for a in axles.values()),
        "cylinder_mean_rms_bar": max(a["mean_rms_bar"] for a in axles.values()),
        "stopping_time_difference_s": rt.kpis["stopping_time_s"] - det.kpis["stopping_time_s"],
        "pilot_mean_rms_bar": max(c["pilot_mean_rms_bar"] for c in chain.values()),
        "relay_mean_rms_bar": max(c["relay_mean_rms_bar"] for c in chain.values()),
        "air_vented_rt_kg": float(rt.outputs["air_vented"][-1]),
        "air_vented_detailed_kg": float(det.outputs["air_vented"][-1]),
        "vent_open_rt_s": sum(a["rt"]["vent_open_s"] for a in axles.values()),
        "vent_open_detailed_s": sum(a["detailed"]["vent_open_s"] for a in axles.values()),
        "detailed_wall_s": det.kpis["wall_s"], "detailed_ode_steps": det.kpis["ode_steps"],
        "detailed_air_balance_error": det.kpis["air_balance_error"],
    }
    return summary, axles, chain


def compare(scenario="emergency-250-dry", cars: int | None = None, steps_ms=None,
            progress: Callable[[str, float], None] | None = None) -> Comparison:
    """Both models on one scenario; steps_ms: the study's steps (default STEPS_MS; () skips it);
    progress(stage, fraction of that stage done) while it works."""
    steps_ms = STEPS_MS if steps_ms is None else steps_ms
    resolved = resolve(scenario, cars)
    sc, n = resolved.scenario, resolved.cars
    v0 = sc.spec.initial_speed
    on_speed = None if progress is None else (lambda _t, v: progress("detailed model", 1.0 - v / v0))
    det = run_detailed(resolved, progress=on_speed)
    rt = run(resolved)
    summary, axles, chain = figures(rt, det)
    steps = step_study(resolved, det, steps_ms, progress) if steps_ms else []
    return Comparison(sc.name, n, rt, det, summary, axles, steps, chain)
