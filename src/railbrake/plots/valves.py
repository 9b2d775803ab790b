"""Valve characteristics and step responses (pressures in bar gauge, time in s)."""

from __future__ import annotations

from railbrake.plots import new_figure, save
from railbrake.units import BAR


def plot_characteristic(c, title: str, path) -> None:
    fig, ax = new_figure()
    ax.plot(c.current_up, c.pressure_up, label="current rising")
    ax.plot(c.current_down, c.pressure_down, label="current falling")
    ax.set_xlabel("current [A]")
    ax.set_ylabel("control pressure [bar gauge]")
    ax.set_title(f"{title} (hysteresis {c.hysteresis_bar:.3f} bar)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    save(fig, path)


def plot_step(res, names, ambient_pa: float, title: str, path) -> None:
    fig, ax = new_figure()
    for name in names:
        ax.plot(res.time, (res[name].p - ambient_pa) / BAR, label=name)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("pressure [bar gauge]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    save(fig, path)
