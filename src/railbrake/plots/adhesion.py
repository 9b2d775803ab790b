"""Creep-force curves and fits."""

from __future__ import annotations

import numpy as np

from railbrake.plots import new_figure, save
from railbrake.units import ms_to_kmh


def plot_creep_curves(curves, title: str, path) -> None:
    fig, ax = new_figure()
    for curve in curves:
        line, = ax.plot(100 * curve.creep, curve.coefficient, label=f"{ms_to_kmh(curve.speed):.0f} km/h")
        ax.plot(100 * curve.peak.creep, curve.peak.coefficient, "o", color=line.get_color())
    ax.set_xlabel("creep [%]")
    ax.set_ylabel("adhesion F/Q [-]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(title="speed (o: peak)")
    save(fig, path)


def plot_fit(creep, coefficient, speed, model, title: str, path) -> None:
    """Measured points and the fitted model at each measured speed; model(creep, speed) -> F/Q."""
    fig, ax = new_figure()
    for v in np.unique(speed):
        at_v = speed == v
        points = ax.plot(100 * creep[at_v], coefficient[at_v], ".", label=f"measured {ms_to_kmh(v):.0f} km/h")
        grid = np.linspace(0.0, creep[at_v].max(), 300) if creep[at_v].max() > 0 else \
            np.linspace(creep[at_v].min(), 0.0, 300)
        ax.plot(100 * grid, model(grid, v), "-", color=points[0].get_color())
    ax.set_xlabel("creep [%]")
    ax.set_ylabel("adhesion F/Q [-]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    save(fig, path)
