"""Plots of a real-time vs detailed comparison (human units on the axes)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railbrake.plots import new_figure, save
from railbrake.units import BAR, cars_text, ms_to_kmh

ZOOM = 5.0   # s


def plot_all(c, folder: Path) -> list[Path]:
    """Cylinder pressures RT vs detailed (first axles, whole stop and a 5 s zoom), speed, and the
    step-size study."""
    rt, det = c.rt, c.detailed
    title = f"{c.scenario}, {cars_text(c.cars)}"
    paths = []

    names = det.axle_channels("cylinder")[:2]
    fig, axes = new_figure(len(names), 1, sharex=True, squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        ax.plot(rt.time, (rt.outputs[name] - rt.atmosphere) / BAR, lw=0.7, label="real-time (1 ms)")
        ax.plot(det.time, (det.outputs[name] - det.atmosphere) / BAR, lw=0.7, ls="--", label="detailed")
        ax.set_ylabel(f"{name.split('_', 1)[1]} (bar g)")
        ax.legend(fontsize=7)
    axes[0, 0].set_title(f"{title}: brake-cylinder pressure")
    axes[-1, 0].set_xlabel("time (s)")
    paths.append(folder / "cylinder_rt_vs_detailed.png")
    save(fig, paths[-1])

    # a 5 s window in the middle of the stop: the WSP cycles of both models, with the vent valve
    mid = 0.5 * min(rt.time[-1], det.time[-1])
    name, vent = names[0], names[0].replace("cylinder", "vent")
    fig, ax = new_figure()
    for r, ls, label in ((rt, "-", "real-time (1 ms)"), (det, "--", "detailed")):
        w = (r.time >= mid) & (r.time <= mid + ZOOM)
        line, = ax.plot(r.time[w], (r.outputs[name][w] - r.atmosphere) / BAR, ls=ls, label=f"{label}: cylinder")
        ax.plot(r.time[w], 0.3 * r.outputs[vent][w], ls=ls, lw=0.6, color=line.get_color(), label=f"{label}: vent open")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"{name.split('_', 1)[1]} (bar g); vent")
    ax.set_title(f"{title}: {ZOOM:g} s in the middle of the stop")
    ax.legend(fontsize=7)
    paths.append(folder / "cylinder_zoom.png")
    save(fig, paths[-1])

    fig, ax = new_figure()
    ax.plot(rt.time, ms_to_kmh(rt.outputs["speed"]), label="real-time (1 ms)")
    ax.plot(det.time, ms_to_kmh(det.outputs["speed"]), ls="--", label="detailed")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("speed (km/h)")
    ax.set_title(f"{title}: train speed")
    ax.legend()
    paths.append(folder / "speed_rt_vs_detailed.png")
    save(fig, paths[-1])

    if c.steps:
        dt = np.array([r["dt_ms"] for r in c.steps])
        fig, (ax1, ax2) = new_figure(2, 1, sharex=True)
        ax1.plot(dt, [abs(r["distance_error_pct"]) for r in c.steps], "o-")
        ax1.set_ylabel("|stopping distance error| (%)")
        ax1.set_title(f"{title}: real-time plant step-size study vs the detailed model")
        ax2.plot(dt, [r["cylinder_rms_bar"] for r in c.steps], "o-", label="cylinder RMS")
        ax2.plot(dt, [r["cylinder_mean_rms_bar"] for r in c.steps], "s-", label="1 s mean RMS")
        for r in c.steps:
            if not r["stable"]:
                ax2.annotate("unstable", (r["dt_ms"], r["cylinder_rms_bar"]), fontsize=7)
        ax2.set_xscale("log")
        ax2.set_xlabel("plant step (ms)")
        ax2.set_ylabel("difference (bar)")
        ax2.legend(fontsize=7)
        paths.append(folder / "step_study.png")
        save(fig, paths[-1])
    return paths
