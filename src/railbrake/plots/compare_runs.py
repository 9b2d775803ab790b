"""Plots of saved runs side by side: braking curves overlaid, and the cylinder pressure of chosen
axles (the first run's worst and faulty axles, and any asked for) overlaid per axle."""

from __future__ import annotations

from pathlib import Path

from railbrake.plots import new_figure, save
from railbrake.plots.simulation import OUTSIDE, _gauge
from railbrake.results import episodes
from railbrake.results.record import axle_key
from railbrake.units import ms_to_kmh


def plot_braking_curves(records, labels, path: Path) -> Path:
    fig, ax = new_figure(figsize=(9, 4.8))
    for i, (r, lab) in enumerate(zip(records, labels)):
        d = r.kpis.get("stopping_distance_m")
        extra = f", {d:.0f} m" if isinstance(d, (int, float)) and d is not None else ""
        ax.plot(r.outputs["position"], ms_to_kmh(r.outputs["speed"]), lw=1.0, ls=("-", "--", ":", "-.")[i % 4],
                label=f"{lab}: {r.title()}{extra}")
    ax.set_xlabel("position along the track (m)")
    ax.set_ylabel("speed (km/h)")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.set_title("braking curves", fontsize=10)
    ax.legend(**(OUTSIDE | {"loc": "upper left", "bbox_to_anchor": (0.0, -0.15)}))
    save(fig, path)
    return path


def plot_axle_pressures(records, labels, axles, path: Path, window=None) -> Path:
    fig, axes = new_figure(len(axles), 1, sharex=True, squeeze=False, figsize=(9, 2.4 * len(axles) + 1.2))
    first = records[0]
    t0, t1 = window or (episodes.wsp_window(first, axles[0]) if first.axle_names() else (first.time[0], first.time[-1]))
    for ax, axle in zip(axes[:, 0], axles):
        for i, (r, lab) in enumerate(zip(records, labels)):
            p = r.channel("cylinder", axle)
            if p is None:
                continue
            w = (r.time >= t0) & (r.time <= t1)
            ax.plot(r.time[w], _gauge(p[w], r), lw=0.9, ls=("-", "--", ":", "-.")[i % 4], label=f"{lab}")
        ax.set_ylabel(f"{axle} (bar g)")
        ax.legend(**OUTSIDE)
    axes[-1, 0].set_xlabel("time (s)")
    axes[0, 0].set_title(f"brake cylinder pressure per axle, {t0:.1f}-{t1:.1f} s\n"
                         + "\n".join(f"{lab}: {r.title()}" for r, lab in zip(records, labels)), fontsize=9)
    save(fig, path)
    return path


def plot_comparison(records, labels, folder: Path, axles=None, window=None, fmt: str = "png") -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    common = set.intersection(*({n[len("cylinder_"):] for n in r.outputs if n.startswith("cylinder_c")}
                                for r in records))
    first = episodes.plotted_axles(records[0], axles) if records[0].axle_names() else list(axles or [])
    chosen = [a for a in first if a in common] or sorted(common, key=axle_key)[:1]
    paths = [plot_braking_curves(records, labels, folder / f"compare_braking_curves.{fmt}")]
    if chosen:   # an FMU result may hold no cylinder pressure
        paths.append(plot_axle_pressures(records, labels, chosen, folder / f"compare_cylinders.{fmt}", window))
    return paths
