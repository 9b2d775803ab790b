"""Plots of a whole-train simulation result (human units on the axes)."""

from __future__ import annotations

from pathlib import Path

from railbrake.plots import new_figure, save
from railbrake.units import BAR, cars_text, ms_to_kmh

ATMOSPHERE = 1.01325e5


def _axles(result, quantity, limit=8):
    names = result.axle_channels(quantity)
    step = max(1, len(names) // limit)
    return names[::step]


def plot_all(result, folder: Path) -> list[Path]:
    """Speed and distance; cylinder pressure per axle; slip per axle; valve states; reservoirs."""
    t, o = result.time, result.outputs
    title = f"{result.scenario}, {cars_text(result.cars)}, WSP {'on' if result.wsp else 'off'}"
    paths = []

    fig, (ax1, ax2) = new_figure(2, 1, sharex=True)
    ax1.plot(t, ms_to_kmh(o["speed"]), label="train")
    for name in _axles(result, "wheel_speed", 4):
        ax1.plot(t, ms_to_kmh(o[name]), lw=0.6, label=name.replace("wheel_speed_", "wheel "))
    ax1.set_ylabel("speed (km/h)")
    ax1.legend(fontsize=7)
    ax1.set_title(title)
    ax2.plot(t, o["position"] - o["position"][0])
    ax2.set_ylabel("distance (m)")
    ax2.set_xlabel("time (s)")
    paths.append(folder / "speed_distance.png")
    save(fig, paths[-1])

    fig, ax = new_figure()
    for name in _axles(result, "cylinder"):
        ax.plot(t, (o[name] - ATMOSPHERE) / BAR, lw=0.7, label=name.replace("cylinder_", ""))
    ax.set_ylabel("brake cylinder pressure (bar gauge)")
    ax.set_xlabel("time (s)")
    ax.set_title(f"{title}: WSP modulation")
    ax.legend(fontsize=7, ncol=2)
    paths.append(folder / "cylinder_pressure.png")
    save(fig, paths[-1])

    fig, ax = new_figure()
    for name in _axles(result, "slip"):
        ax.plot(t, 100 * o[name], lw=0.7, label=name.replace("slip_", ""))
    ax.set_ylabel("slip (%)")
    ax.set_xlabel("time (s)")
    ax.set_title(title)
    ax.legend(fontsize=7, ncol=2)
    paths.append(folder / "slip.png")
    save(fig, paths[-1])

    names = _axles(result, "vent")
    fig, ax = new_figure()
    for i, name in enumerate(names):
        hold = o[name.replace("vent_", "hold_")]
        ax.fill_between(t, 3 * i, 3 * i + hold, step="post", color="tab:orange", lw=0)
        ax.fill_between(t, 3 * i + 1, 3 * i + 1 + o[name], step="post", color="tab:red", lw=0)
    ax.set_yticks([3 * i + 1 for i in range(len(names))], [n.replace("vent_", "") for n in names])
    ax.set_xlabel("time (s)")
    ax.set_title(f"{title}: hold (orange) and vent (red) valves")
    paths.append(folder / "valves.png")
    save(fig, paths[-1])

    fig, ax = new_figure()
    ax.plot(t, (o["main_reservoir"] - ATMOSPHERE) / BAR, label="main reservoir")
    ax.plot(t, (o["pipe_end"] - ATMOSPHERE) / BAR, label="MR pipe, last car")
    for name in result.car_channels("supply")[:: max(1, result.cars // 4)]:
        ax.plot(t, (o[name] - ATMOSPHERE) / BAR, lw=0.7, label=name.replace("supply_", "supply "))
    ax.set_ylabel("pressure (bar gauge)")
    ax.set_xlabel("time (s)")
    ax.set_title(title)
    ax.legend(fontsize=7)
    paths.append(folder / "reservoirs.png")
    save(fig, paths[-1])
    return paths
