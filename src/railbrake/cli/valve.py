"""`railbrake valve ...`: EP valve characteristic and step response, relay valve step response."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import numpy as np
import typer

from railbrake import valves
from railbrake.cli._common import prepare_plot, print_json, reports_errors
from railbrake.errors import InputError
from railbrake.units import BAR

app = typer.Typer(help="Valve design models: EP valve, relay valve (pressures in bar gauge).",
                  no_args_is_help=True)


def _step_summary(res, name: str, ambient: float) -> dict:
    """Final pressure, 10-90 % rise time and overshoot of one node's pressure."""
    p = (res[name].p - ambient) / BAR
    final, start = p[-1], p[0]
    rise = final - start
    t10 = res.time[np.argmax(p >= start + 0.1 * rise)] if rise > 0 else float("nan")
    t90 = res.time[np.argmax(p >= start + 0.9 * rise)] if rise > 0 else float("nan")
    return {"final_bar": final, "rise_time_10_90_s": t90 - t10,
            "overshoot_bar": max(0.0, float(p.max() - final)),
            "oscillates": valves.oscillates(res.time, res[name].p)}


@app.command("epv")
@reports_errors
def epv(
    characteristic: bool = typer.Option(False, "--characteristic", help="Current ramp up and down."),
    step: bool = typer.Option(False, "--step", help="Response to a current step."),
    current: float = typer.Option(0.5, help="Step current in A."),
    params: Optional[Path] = typer.Option(None, help="YAML file overriding the default EPV design."),
    ramp_time: float = typer.Option(20.0, help="Duration of the ramp up and down, s."),
    t_end: float = typer.Option(1.0, help="Step response duration, s."),
    plot: Optional[Path] = typer.Option(None, help="Write a PNG here."),
    json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
):
    """EP pressure-control valve: control pressure vs current (with hysteresis) or step response."""
    if characteristic == step:
        raise InputError("give exactly one of --characteristic or --step")
    p = valves.load_epv(params)
    if characteristic:
        c = valves.epv_characteristic(p, ramp_time=ramp_time)
        if plot:
            from railbrake.plots.valves import plot_characteristic
            plot_characteristic(c, "EP valve characteristic", prepare_plot(plot))
        if json:
            print_json(c.as_dict())
            return
        typer.echo(f"control pressure at {c.current_up[-1]:.2f} A: {c.pressure_up[-1]:.3f} bar; "
                   f"hysteresis {c.hysteresis_bar:.3f} bar")
    else:
        res = valves.epv_step(p, current=current, t_end=t_end)
        summary = _step_summary(res, "control", p["ambient_pa"])
        if plot:
            from railbrake.plots.valves import plot_step
            plot_step(res, ["pilot", "control"], p["ambient_pa"], f"EP valve step to {current:g} A",
                      prepare_plot(plot))
        if json:
            print_json({"current_a": current, **summary, "time": res.time,
                        "control_bar": (res["control"].p - p["ambient_pa"]) / BAR})
            return
        typer.echo(f"step to {current:g} A: control {summary['final_bar']:.3f} bar, rise (10-90 %) "
                   f"{summary['rise_time_10_90_s'] * 1e3:.0f} ms, "
                   f"overshoot {summary['overshoot_bar']:.3f} bar, oscillates: {summary['oscillates']}")
    if plot:
        typer.echo(f"plot: {plot}")


@app.command("relay")
@reports_errors
def relay(
    step: bool = typer.Option(True, "--step", help="Control-pressure step response (the default, only analysis)."),
    params: Optional[Path] = typer.Option(None, help="YAML file overriding the default relay valve."),
    t_end: float = typer.Option(1.5, help="Duration, s."),
    plot: Optional[Path] = typer.Option(None, help="Write a PNG here."),
    json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
):
    """Relay valve with membrane filling the brake cylinders after a control-pressure step."""
    p = valves.load_relay(params)
    res = valves.relay_step(p, t_end=t_end)
    summary = _step_summary(res, "cylinder", p["ambient_pa"])
    if plot:
        from railbrake.plots.valves import plot_step
        plot_step(res, ["control", "output", "cylinder"], p["ambient_pa"], "Relay valve step",
                  prepare_plot(plot))
    if json:
        print_json({**summary, "time": res.time, "cylinder_bar": (res["cylinder"].p - p["ambient_pa"]) / BAR})
        return
    typer.echo(f"cylinder {summary['final_bar']:.3f} bar, rise (10-90 %) "
               f"{summary['rise_time_10_90_s'] * 1e3:.0f} ms, overshoot {summary['overshoot_bar']:.3f} bar")
    if plot:
        typer.echo(f"plot: {plot}")
