"""The figures a brake engineer reads after a whole-train run (MIL, HIL or a saved run): the WSP
cycle of single axles, the braking curve over distance, slip, reservoirs and cylinder pressure
against demand per car. Everything is drawn from a RunRecord, so `railbrake plot` redraws a saved
run exactly as the run drew it. Axes in bar gauge, km/h, m, s, %, m/s^2."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from railbrake.plots import new_figure, save
from railbrake.results import episodes
from railbrake.results.record import RunRecord, axle_key
from railbrake.units import BAR, ms_to_kmh

OUTSIDE = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "fontsize": 7, "borderaxespad": 0.0}
HIGHLIGHT = ["C0", "C3", "C2", "C4", "C1", "C5", "C6", "C8", "C9"]
SLIP_HEADROOM = 1.3        # y range of the slip plot: 1.3 x the 99.5th percentile outside locks
SLIP_QUANTILE = 99.5
SLIP_CHOSEN_HEADROOM = 1.05   # and the largest working slip of the axles in colour ...
SLIP_CHOSEN_CAP = 1.5         # ... up to 1.5 x the range above
AXLE_COLOURS = ["C0", "C1", "C2", "C4"]   # red (C3) marks a faulty axle
OVERVIEW_POINTS = 600      # per line in the small per-car panels
MEAN_SPAN = 1.0            # s, running mean of the cylinder pressures under WSP cycling


def _gauge(p, record: RunRecord):
    return (np.asarray(p) - record.atmosphere) / BAR


def _demand(record: RunRecord, car: str):
    """(samples, label) of a car's pressure demand: the BCU's demand (HIL) or the EP valve's pilot
    pressure, which follows it (MIL)."""
    if f"pressure_demand_{car}" in record.outputs:
        return record.outputs[f"pressure_demand_{car}"], "pressure demand"
    if f"pilot_{car}" in record.outputs:
        return record.outputs[f"pilot_{car}"], "EP pilot (demand)"
    return None, ""


def _why(record: RunRecord, axle: str) -> str:
    reasons = []
    if axle == episodes.worst_axle(record):
        reasons.append("worst axle")
    for f in record.meta.get("faults", []):
        if f["car"] == axle_key(axle)[0] and f.get("axle") in (None, axle_key(axle)[1]):
            reasons.append(f"fault {f['type']} from {f['start']:g} s")
    return ", ".join(reasons)


def _lock_spans(ax, record, axle, colour, label=True):
    for i, (s, e) in enumerate(episodes.lock_episodes(record, axle)):
        ax.axvspan(s, e + 1e-3, color=colour, alpha=0.15, lw=0,
                   label=f"lock {axle}" if label and i == 0 else None)


# ------------------------------------------------------------------ the WSP cycle of one axle

def plot_wsp_cycle(record: RunRecord, axle: str, path: Path, window=None) -> Path:
    """Wheel against train speed, cylinder pressure against demand, hold and vent valves, slip:
    one axle over a few seconds (window (t0, t1) s; default around its first WSP activity)."""
    t0, t1 = window or episodes.wsp_window(record, axle)
    t, o = record.time, record.outputs
    w = (t >= t0) & (t <= t1)
    tw = t[w]
    fig, (ax1, ax2, ax3, ax4) = new_figure(4, 1, sharex=True, figsize=(9, 8.5),
                                           gridspec_kw={"height_ratios": [3, 3, 1.3, 2]})
    ax1.plot(tw, ms_to_kmh(o["speed"][w]), "k", lw=1.0, label="train speed (reference)")
    ax1.plot(tw, ms_to_kmh(record.channel("wheel_speed", axle)[w]), "C0", lw=1.0, label=f"wheel {axle}")
    ax1.set_ylabel("speed (km/h)")
    ax1.legend(**OUTSIDE)
    ax2.plot(tw, _gauge(record.channel("cylinder", axle)[w], record), "C3", lw=1.0, label=f"cylinder {axle}")
    demand, label = _demand(record, "c" + str(axle_key(axle)[0]))
    if demand is not None:
        ax2.plot(tw, _gauge(demand[w], record), "k--", lw=0.8, label=label)
    ax2.set_ylabel("pressure (bar g)")
    ax2.set_ylim(bottom=min(0.0, ax2.get_ylim()[0]))
    ax2.legend(**OUTSIDE)
    hold, vent = record.channel("hold", axle)[w] > 0.5, record.channel("vent", axle)[w] > 0.5
    ax3.fill_between(tw, 1.2, 1.2 + 0.8 * hold, step="post", color="tab:orange", lw=0, label="hold (closed)")
    ax3.fill_between(tw, 0.0, 0.8 * vent, step="post", color="tab:red", lw=0, label="vent (open)")
    ax3.set_yticks([0.4, 1.6], ["vent", "hold"])
    ax3.set_ylim(-0.1, 2.1)
    ax3.legend(**OUTSIDE)
    ax4.plot(tw, 100 * record.channel("slip", axle)[w], "C0", lw=1.0, label=f"slip {axle}")
    ax4.axhline(0.0, color="0.5", lw=0.5)
    _lock_spans(ax4, record, axle, "C3")
    ax4.set_ylabel("slip (%)")
    ax4.set_xlabel("time (s)")
    ax4.set_xlim(t0, t1)
    ax4.legend(**OUTSIDE)
    openings = episodes.vent_openings(record, axle)
    n = int(((openings >= t0) & (openings < t1)).sum())
    why = _why(record, axle)
    ax1.set_title(f"{record.title()}\nWSP cycle of axle {axle}{f' ({why})' if why else ''}: "
                  f"{n} vent opening{'s' if n != 1 else ''} in {t1 - t0:.1f} s", fontsize=10)
    return save(fig, path)


# ------------------------------------------------------------------ the braking curve

def _demand_text(d: dict) -> str:
    if d.get("emergency"):
        return "emergency"
    return f"service {100 * d['service']:.0f} %" if d.get("service", 0) > 0 else "release"


def plot_braking_curve(record: RunRecord, path: Path) -> Path:
    """Speed over the position along the track, adhesion zones shaded, demand steps marked."""
    t, o = record.time, record.outputs
    x, v = o["position"], ms_to_kmh(o["speed"])
    fig, ax = new_figure(figsize=(9, 4.8))
    ax.plot(x, v, "k", lw=1.2, label="train speed")
    for i, z in enumerate(record.meta.get("zones", [])):
        ax.axvspan(z["start"], z["end"], color=HIGHLIGHT[i % len(HIGHLIGHT)], alpha=0.15, lw=0,
                   label=f"zone {z['start']:g}-{z['end']:g} m: {z['condition']}")
    for d in record.meta.get("demand", []):
        if t[0] <= d["time"] <= t[-1]:
            xd = float(np.interp(d["time"], t, x))
            ax.axvline(xd, color="C1", lw=0.8, ls="--")
            ax.annotate(f"{_demand_text(d)} at {d['time']:g} s", (xd, 0.02), xycoords=("data", "axes fraction"),
                        rotation=90, fontsize=7, color="C1", ha="right", va="bottom")
    k = record.kpis
    distance = k.get("stopping_distance_m")
    if k.get("stopped") and distance is not None:
        ax.plot([x[-1]], [v[-1]], "C3o", ms=4, label=f"stop: {distance:.0f} m, {k.get('stopping_time_s', 0):.1f} s")
    condition = record.meta.get("condition")
    ax.set_xlabel("position along the track (m)")
    ax.set_ylabel("speed (km/h)")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.set_title(f"{record.title()}\nbraking curve{f', adhesion {condition}' if condition else ''}", fontsize=10)
    ax.legend(**OUTSIDE)
    return save(fig, path)


def _zone_spans(ax, record: RunRecord, label: bool = True):
    """Shade the times the leading car spends in each adhesion zone."""
    x = record.outputs["position"]
    for i, z in enumerate(record.meta.get("zones", [])):
        if z["start"] > x[-1] or np.any(np.diff(x) < 0):
            continue
        t0, t1 = np.interp([z["start"], min(z["end"], x[-1])], x, record.time)
        ax.axvspan(t0, t1, color=HIGHLIGHT[i % len(HIGHLIGHT)], alpha=0.12, lw=0,
                   label=f"leading car in zone: {z['condition']}" if label else None)


def plot_speed_time(record: RunRecord, path: Path) -> Path:
    """Speed, and the achieved against the demanded deceleration, over time."""
    t, o = record.time, record.outputs
    fig, (ax1, ax2) = new_figure(2, 1, sharex=True, figsize=(9, 6))
    _zone_spans(ax1, record)
    _zone_spans(ax2, record, label=False)
    ax1.plot(t, ms_to_kmh(o["speed"]), "k", label="train speed")
    ax1.set_ylabel("speed (km/h)")
    ax1.set_ylim(bottom=0)
    ax1.legend(**OUTSIDE)
    ax1.set_title(f"{record.title()}\nspeed and deceleration", fontsize=10)
    if "deceleration" in o:
        ax2.plot(t, o["deceleration"], "C0", lw=0.6, label="achieved")
    if "demand_deceleration" in o:
        ax2.plot(t, o["demand_deceleration"], "k--", lw=1.0, label="demanded")
    ax2.set_ylabel("deceleration (m/s²)")
    ax2.set_xlabel("time (s)")
    ax2.legend(**OUTSIDE)
    return save(fig, path)


# ------------------------------------------------------------------ slip, reservoirs, cylinders

def _working_slip(record: RunRecord, axle: str) -> np.ndarray:
    """abs(slip) of an axle above 10 km/h outside its lock episodes."""
    keep = record.outputs["speed"] > episodes.LOCK_SPEED
    for s, e in episodes.lock_episodes(record, axle):
        keep &= ~((record.time >= s) & (record.time <= e))
    return np.abs(record.channel("slip", axle)[keep])


def slip_range(record: RunRecord, axles=()) -> tuple[float, float]:
    """% range that shows the working slips: SLIP_HEADROOM x the SLIP_QUANTILE percentile of abs(slip)
    of all axles above 10 km/h outside lock episodes, widened to the largest such slip of the
    chosen axles up to SLIP_CHOSEN_CAP times that (a lock's -100 %, or the large slips of the last
    seconds above 10 km/h, would squash the working slips to pixels)."""
    values = [_working_slip(record, a) for a in record.axle_names()]
    values = np.concatenate(values) if values else np.zeros(0)
    base = 100 * SLIP_HEADROOM * (np.percentile(values, SLIP_QUANTILE) if values.size else 0.01)
    top = base
    for a in axles:
        chosen = _working_slip(record, a)
        if chosen.size:
            top = max(top, min(100 * SLIP_CHOSEN_HEADROOM * chosen.max(), SLIP_CHOSEN_CAP * base))
    top = max(top, 1.0)
    return -top, 0.1 * top


def plot_slip(record: RunRecord, axles: list[str], path: Path) -> Path:
    """Slip above 10 km/h (below, slip is a ratio of small speeds): the chosen axles in colour with
    their lock episodes shaded, the range of all other axles in grey."""
    t = record.time
    running = record.outputs["speed"] > episodes.LOCK_SPEED

    def slip(a):
        return np.where(running, 100 * record.channel("slip", a), np.nan)

    fig, ax = new_figure(figsize=(9, 4.8))
    _zone_spans(ax, record)
    others = [a for a in record.axle_names() if a not in axles]
    if others:
        stack = np.vstack([slip(a) for a in others])
        ax.fill_between(t, np.min(stack, axis=0), np.max(stack, axis=0), color="0.8", lw=0,
                        label=f"range of the other {len(others)} axles")
    for i, a in enumerate(axles):
        colour = HIGHLIGHT[i % len(HIGHLIGHT)]
        ax.plot(t, slip(a), color=colour, lw=0.6, label=f"{a} ({_why(record, a) or 'chosen'})")
        _lock_spans(ax, record, a, colour)
    locks = sum(len(episodes.lock_episodes(record, a)) for a in record.axle_names())
    low, high = slip_range(record, axles)
    ax.set_ylim(low, high)
    ax.set_ylabel("slip (%)")
    ax.set_xlabel("time (s)")
    ax.set_title(f"{record.title()}\nslip above 10 km/h; {locks} lock episodes on all axles"
                 f"{' (shaded: those of the axles in colour)' if locks else ''}", fontsize=10)
    ax.legend(**OUTSIDE)
    return save(fig, path)


def plot_reservoirs(record: RunRecord, path: Path) -> Path:
    """Main reservoir, MR pipe at the last car, the supply reservoirs' range and the lowest one."""
    t, o = record.time, record.outputs
    fig, ax = new_figure(figsize=(9, 4.8))
    ax.plot(t, _gauge(o["main_reservoir"], record), "k", label="main reservoir")
    if "pipe_end" in o:
        ax.plot(t, _gauge(o["pipe_end"], record), "C7", lw=0.8, label="MR pipe, last car")
    supplies = {c: o[f"supply_{c}"] for c in record.car_names() if f"supply_{c}" in o}
    if supplies:
        stack = np.vstack([_gauge(s, record) for s in supplies.values()])
        ax.fill_between(t, stack.min(axis=0), stack.max(axis=0), color="C0", alpha=0.2, lw=0,
                        label=f"supply reservoirs, {len(supplies)} cars")
        lowest = min(supplies, key=lambda c: supplies[c].min())
        low = _gauge(supplies[lowest], record)
        ax.plot(t, low, "C3", lw=1.0, label=f"lowest supply: {lowest}, min {low.min():.2f} bar g")
        first = next(iter(supplies))
        if first != lowest:
            ax.plot(t, _gauge(supplies[first], record), "C0", lw=0.8, label=f"supply {first}")
    ax.set_ylabel("pressure (bar g)")
    ax.set_xlabel("time (s)")
    ax.grid(True, alpha=0.3)
    ax.set_title(f"{record.title()}\nair supply", fontsize=10)
    ax.legend(**OUTSIDE)
    return save(fig, path)


def running_mean(t: np.ndarray, x: np.ndarray, span: float = MEAN_SPAN) -> np.ndarray:
    """Centred mean over span s (the WSP's fast cycling averaged out; edges use what is there)."""
    dt = float(np.median(np.diff(t))) if len(t) > 1 else span
    n = max(1, int(round(span / dt)))
    kernel = np.ones(n)
    return np.convolve(x, kernel, "same") / np.convolve(np.ones_like(x), kernel, "same")


def _envelope(t, rows: np.ndarray, points: int = OVERVIEW_POINTS):
    """(t, low, high) of rows' range in at most `points` bins: the same picture as every sample
    in a small panel, drawn far faster."""
    k = max(1, math.ceil(len(t) / points))
    n = len(t) // k * k
    if k == 1 or n == 0:
        return t, rows.min(axis=0), rows.max(axis=0)
    low = rows[:, :n].reshape(rows.shape[0], -1, k).min(axis=(0, 2))
    high = rows[:, :n].reshape(rows.shape[0], -1, k).max(axis=(0, 2))
    return t[:n:k], low, high


def plot_cylinders(record: RunRecord, path: Path, faulty=()) -> Path:
    """Brake cylinder pressure against the car's demand, one small panel per car: the range of its
    four axles shaded, each axle's 1 s mean as a line (the faulty ones thick, red)."""
    t = record.time
    cars = record.car_names()
    ncols = min(4, len(cars))
    nrows = math.ceil(len(cars) / ncols)
    # a fixed layout: the constrained one costs seconds for 16 panels
    fig, axes = new_figure(nrows, ncols, sharex=True, sharey=True, squeeze=False, constrained_layout=False,
                           figsize=(2.6 * ncols + 1.8, 1.7 * nrows + 1.0))
    width, height = fig.get_size_inches()
    fig.subplots_adjust(left=0.6 / width, right=1 - 1.9 / width, bottom=0.55 / height, top=1 - 0.75 / height,
                        wspace=0.08, hspace=0.35)
    for ax, car in zip(axes.flat, cars):
        axles = [a for a in record.axle_names() if a.startswith(car + "a")]
        p = np.vstack([_gauge(record.channel("cylinder", a), record) for a in axles])
        ax.fill_between(*_envelope(t, p), color="0.85", lw=0, label="range of the axles")
        step = max(1, len(t) // OVERVIEW_POINTS)
        demand, label = _demand(record, car)
        if demand is not None:
            ax.plot(t, _gauge(demand, record), "k--", lw=0.8, label=label)
        for k, (axle, pa) in enumerate(zip(axles, p)):
            bad = axle in faulty
            ax.plot(t[::step], running_mean(t, pa)[::step], color="C3" if bad else AXLE_COLOURS[k % 4],
                    lw=1.4 if bad else 0.7,
                    label=f"axle {axle[-1]}, {MEAN_SPAN:g} s mean")
            if bad:
                ax.annotate(f"faulty: axle {axle[-1]}", (0.98, 0.05), xycoords="axes fraction", ha="right",
                            fontsize=7, color="C3")
        ax.set_title(car.replace("c", "car "), fontsize=8, pad=2)
        ax.tick_params(labelsize=7)
    for ax in axes.flat[len(cars):]:
        ax.set_visible(False)
    for ax in axes[:, 0]:
        ax.set_ylabel("bar g", fontsize=8)
    for ax in axes[-1, :]:
        ax.set_xlabel("time (s)", fontsize=8)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper right", fontsize=7)
    fig.suptitle(f"{record.title()}\nbrake cylinder pressure against demand per car", fontsize=10)
    return save(fig, path)


def plot_channels(record: RunRecord, names: list[str], path: Path, window=None) -> Path:
    """Any recorded channels over time, one panel per unit (SI, pressures in bar g, speeds in km/h)."""
    t = record.time
    w = np.ones_like(t, dtype=bool) if window is None else (t >= window[0]) & (t <= window[1])
    groups: dict[str, list[str]] = {}
    for n in names:
        groups.setdefault(record.units.get(n, ""), []).append(n)
    fig, axes = new_figure(len(groups), 1, sharex=True, squeeze=False, figsize=(9, 2.6 * len(groups) + 0.8))
    for ax, (unit, group) in zip(axes[:, 0], groups.items()):
        scales = {"Pa": (lambda x: _gauge(x, record), "bar g"), "m/s": (ms_to_kmh, "km/h")}
        scale, shown = scales.get(unit, (lambda x: x, unit or "-"))
        for n in group:
            ax.plot(t[w], scale(record.outputs[n][w]), lw=0.8, label=n)
        ax.set_ylabel(shown)
        ax.legend(**OUTSIDE)
    axes[-1, 0].set_xlabel("time (s)")
    axes[0, 0].set_title(f"{record.title()}\nchannels", fontsize=10)
    return save(fig, path)


# ------------------------------------------------------------------ every figure of a run

def plot_all(record: RunRecord, folder: Path, axles=None, window=None, channels=None, fmt: str = "png") -> list[Path]:
    """The run's figures into folder: wsp_cycle_<axle> for the worst, the faulty and the requested
    axles, braking_curve, speed_time, slip, reservoirs, cylinders, and channels when asked for."""
    if not isinstance(record, RunRecord):   # a simulation Result without its scenario
        record = RunRecord(record.time, record.outputs, record.units, record.kpis,
                           {"scenario": record.scenario, "cars": record.cars, "wsp": record.wsp})
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    chosen = episodes.plotted_axles(record, axles)
    faulty = {a for group in record.faulty_axles() for a in group}
    paths = [plot_wsp_cycle(record, a, folder / f"wsp_cycle_{a}.{fmt}", window) for a in chosen]
    paths.append(plot_braking_curve(record, folder / f"braking_curve.{fmt}"))
    paths.append(plot_speed_time(record, folder / f"speed_time.{fmt}"))
    paths.append(plot_slip(record, chosen, folder / f"slip.{fmt}"))
    paths.append(plot_reservoirs(record, folder / f"reservoirs.{fmt}"))
    paths.append(plot_cylinders(record, folder / f"cylinders.{fmt}", faulty))
    if channels:
        paths.append(plot_channels(record, channels, folder / f"channels.{fmt}", window))
    return paths
