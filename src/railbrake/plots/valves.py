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


def plot_force_table(gap, current, force, path) -> None:
    fig, ax = new_figure()
    for i in range(0, len(gap), max(1, len(gap) // 5)):
        ax.plot(current, force[i], label=f"airgap {gap[i] * 1e3:.2f} mm")
    ax.set_xlabel("current [A]")
    ax.set_ylabel("solenoid force [N]")
    ax.set_title("Solenoid force from the magnetic circuit (co-energy)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    save(fig, path)


def plot_thermal(r: dict, path) -> None:
    fig, ax = new_figure()
    ax.plot(r["time_s"] / 60, r["temperature_c"], label="coil (mean)")
    ax.axhline(r["steady_c"], color="k", lw=0.8, ls=":", label=f"steady {r['steady_c']:.1f} C")
    ax.axhline(r["limit_c"], color="r", lw=0.8, ls="--", label=f"class {r['insulation_class']} less hot spot")
    ax.set_xlabel("time [min]")
    ax.set_ylabel("temperature [C]")
    ax.set_title(f"Coil at {r['current_a']:g} A, duty {r['duty']:g}, ambient {r['ambient_c']:g} C")
    ax.grid(True, alpha=0.3)
    ax.legend()
    save(fig, path)


def plot_current_step(r: dict, path) -> None:
    fig, ax = new_figure()
    ax.plot(r["t"] * 1e3, r["current"], label="current [A]")
    ax.plot(r["t"] * 1e3, r["gap"] * 1e3, label="airgap [mm]")
    ax.set_xlabel("time [ms]")
    ax.set_title(f"Solenoid switched on (PWM duty {r['duty']:.3f})")
    ax.grid(True, alpha=0.3)
    ax.legend()
    save(fig, path)


def plot_reduction(fit: dict, path) -> None:
    fig, ax = new_figure()
    steps = fit["steps"]
    for k, (key, det) in enumerate(steps["responses"].items()):
        line, = ax.plot(steps["time"], (det - steps["ambient"]) / BAR, lw=1.5)
        ax.plot(steps["time"], (fit["reduced"][k] - steps["ambient"]) / BAR, "--", color=line.get_color(), lw=1)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("control pressure [bar gauge]")
    ax.set_title(f"EP valve: detailed (solid) vs reduced (dashed), tau {fit['ep_tau'] * 1e3:.0f} ms, "
                 f"RMS {fit['rms_bar']:.3f} bar")
    ax.grid(True, alpha=0.3)
    save(fig, path)
