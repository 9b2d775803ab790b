"""Target pressure over speed, and stopping curves."""

from __future__ import annotations

import numpy as np

from railbrake.plots import new_figure, save
from railbrake.units import ms_to_kmh


def plot_target_pressure(result, frozen, friction, title: str, path) -> None:
    """result / frozen: SizingResult with lambda(v) and with lambda frozen at top speed;
    friction: {car type: lambda over result.speed}."""
    fig, (ax, ax2) = new_figure(2, 1, sharex=True)
    v = ms_to_kmh(result.speed)
    for kind, colour in (("motor", "C0"), ("trailer", "C1")):
        p, q = getattr(result, f"p_{kind}"), getattr(frozen, f"p_{kind}")
        if p is None:
            continue
        ax.plot(v, result.gauge_bar(p), color=colour, label=f"{kind}, lambda(v)")
        ax.plot(v, frozen.gauge_bar(q), "--", color=colour, label=f"{kind}, lambda constant")
    ax.axhline(result.gauge_bar(result.supply_pressure), color="k", lw=0.8, ls=":", label="supply")
    ax.axvspan(0, 100, color="0.9", zorder=0)
    ax.set_ylabel("target cylinder pressure [bar g]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    for kind, values in friction.items():
        ax2.plot(v, values, label=f"pad lambda, {kind}")
    ax2.plot(v, result.adhesion_demand, "k", label="adhesion demand (largest axle)")
    ax2.axhline(result.adhesion_limit, color="r", lw=0.8, ls=":", label="adhesion design limit")
    ax2.axvspan(0, 100, color="0.9", zorder=0)
    ax2.set_xlabel("speed [km/h]")
    ax2.set_ylabel("[-]")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    save(fig, path)


def plot_stopping(result, title: str, path) -> None:
    fig, ax = new_figure()
    ax.plot(result.curve_distance, ms_to_kmh(np.asarray(result.curve_speed)))
    ax.set_xlabel("distance [m]")
    ax.set_ylabel("speed [km/h]")
    ax.set_title(f"{title}: {result.distance:.0f} m, {result.time:.1f} s")
    ax.grid(True, alpha=0.3)
    save(fig, path)
