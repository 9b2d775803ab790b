"""Target pressure over speed, and stopping curves."""

from __future__ import annotations

import numpy as np

from railbrake.plots import new_figure, save
from railbrake.units import ms_to_kmh


COLOURS = {"motor": "C0", "trailer": "C1"}
OUTSIDE = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "fontsize": 8, "borderaxespad": 0.0}
LOW_SPEED = 100.0   # km/h: shaded, where the pad friction coefficient rises as the speed falls


def plot_target_pressure(result, frozen, friction, title: str, path) -> None:
    """result / frozen: SizingResult with lambda(v) and with lambda frozen at top speed;
    friction: {car type: lambda over result.speed}."""
    fig, (ax, ax2) = new_figure(2, 1, sharex=True, figsize=(9.5, 8))
    v = ms_to_kmh(result.speed)
    for kind, colour in COLOURS.items():
        p, q = getattr(result, f"p_{kind}"), getattr(frozen, f"p_{kind}")
        if p is None:
            continue
        ax.plot(v, result.gauge_bar(p), color=colour, label=f"{kind}, pad lambda(v)")
        ax.plot(v, frozen.gauge_bar(q), "--", color=colour, label=f"{kind}, pad lambda at top speed")
    ax.axhline(result.gauge_bar(result.supply_pressure), color="k", lw=1.0, ls=":", label="supply pressure")
    for a in (ax, ax2):
        a.axvspan(0, LOW_SPEED, color="0.92", zorder=0, label=f"below {LOW_SPEED:g} km/h" if a is ax else None)
        a.grid(True, alpha=0.3)
    ax.set_ylabel("target cylinder pressure (bar g)")
    ax.set_title(title)
    ax.legend(**OUTSIDE)
    for kind, values in friction.items():
        ax2.plot(v, values, color=COLOURS.get(kind), label=f"pad friction lambda, {kind}")
    ax2.plot(v, result.adhesion_demand, "k", label="adhesion demand (largest axle)")
    ax2.axhline(result.adhesion_limit, color="r", lw=1.0, ls=":", label="adhesion design limit")
    ax2.set_xlabel("speed (km/h)")
    ax2.set_ylabel("friction / adhesion coefficient")
    ax2.legend(**OUTSIDE)
    save(fig, path)


def plot_stopping(result, title: str, path) -> None:
    fig, ax = new_figure()
    ax.plot(result.curve_distance, ms_to_kmh(np.asarray(result.curve_speed)))
    ax.set_xlabel("distance (m)")
    ax.set_ylabel("speed (km/h)")
    ax.set_title(f"{title}: {result.distance:.0f} m, {result.time:.1f} s")
    ax.grid(True, alpha=0.3)
    save(fig, path)
