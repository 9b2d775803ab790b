"""`railbrake valve ...`: EP valve characteristic and step response, relay valve step response."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from railbrake import atomic, valves
from railbrake.cli._common import prepare_output, prepare_plot, print_json, reports_errors
from railbrake.errors import InputError
from railbrake.units import BAR

app = typer.Typer(help="Valve design models: EP valve and its solenoid, relay valve (pressures in bar gauge).",
                  no_args_is_help=True)


def _step_summary(res, name: str, ambient: float, t_step: float = 0.05) -> dict:
    """Final pressure, 10-90 % rise time, overshoot, settling time of one node's pressure."""
    return {**valves.step_metrics(res.time, (res[name].p - ambient) / BAR, t_step),
            "oscillates": valves.oscillates(res.time, res[name].p)}


@app.command("epv")
@reports_errors
def epv(
    characteristic: bool = typer.Option(False, "--characteristic", help="Current ramp up and down."),
    step: bool = typer.Option(False, "--step", help="Response to a current step."),
    reduce: bool = typer.Option(False, "--reduce", help="Fit the real-time plant's valve parameters; print "
                                "them as a train-file fragment."),
    write: Optional[Path] = typer.Option(None, "--write", help="With --reduce: also write them (SI, with "
                                         "provenance) to this YAML file, e.g. data/valves/reduced.yaml."),
    current: float = typer.Option(0.5, help="Step current in A (at most the rated current_max_a)."),
    start_current: float = typer.Option(0.0, help="Current held before the step, A."),
    params: Optional[Path] = typer.Option(None, help="YAML file overriding the default EPV design."),
    ramp_time: float = typer.Option(100.0, help="Duration of the ramp up and down, s."),
    t_end: float = typer.Option(1.0, help="Step response duration, s."),
    plot: Optional[Path] = typer.Option(None, help="Write a PNG here."),
    json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
):
    """EP pressure-control valve: control pressure vs current (with hysteresis), step response, or
    the reduction to the real-time plant's parameters."""
    if characteristic + step + reduce != 1:
        raise InputError("give exactly one of --characteristic, --step or --reduce")
    p = valves.load_epv(params)
    if characteristic:
        _characteristic(p, ramp_time, plot, json)
    elif step:
        _step(p, current, start_current, t_end, plot, json)
    else:
        _reduce(p, plot, json, write)
    if plot and not json:
        typer.echo(f"plot: {plot}")


def _characteristic(p: dict, ramp_time: float, plot, json: bool) -> None:
    c = valves.epv_characteristic(p, ramp_time=ramp_time)
    if plot:
        from railbrake.plots.valves import plot_characteristic
        plot_characteristic(c, "EP valve characteristic", prepare_plot(plot))
    if json:
        print_json(c.as_dict())
        return
    hyst = f"hysteresis {c.hysteresis_bar:.3f} bar" if c.quasi_static else c.note
    typer.echo(f"control pressure at {c.current_up[-1]:.2f} A: {c.pressure_up[-1]:.3f} bar; {hyst}")


def _step(p: dict, current: float, start_current: float, t_end: float, plot, json: bool) -> None:
    res = valves.epv_step(p, current=current, start_current=start_current, t_end=t_end)
    summary = _step_summary(res, "control", p["ambient_pa"])
    if plot:
        from railbrake.plots.valves import plot_step
        plot_step(res, ["pilot", "control"], p["ambient_pa"], f"EP valve step {start_current:g} -> {current:g} A",
                  prepare_plot(plot))
    if json:
        print_json({"current_a": current, "start_current_a": start_current, **summary, "time": res.time,
                    "control_bar": (res["control"].p - p["ambient_pa"]) / BAR})
        return
    typer.echo(f"step {start_current:g} -> {current:g} A: control {summary['final_bar']:.3f} bar, rise (10-90 %) "
               f"{summary['rise_time_10_90_s'] * 1e3:.0f} ms, overshoot {summary['overshoot_bar']:.3f} bar "
               f"({summary['overshoot_pct']:.1f} %), settling (2 %) {summary['settling_time_s'] * 1e3:.0f} ms, "
               f"oscillates: {summary['oscillates']}")


def _reduce(p: dict, plot, json: bool, write) -> None:
    from railbrake.valves import reduce as R
    result = R.reduce(p)
    fit = result["fit"]
    if write:
        atomic.write_text(prepare_output(write), R.reduced_yaml(result))
    if plot:
        from railbrake.plots.valves import plot_reduction
        plot_reduction(fit, prepare_plot(plot))
    if json:
        print_json({"params_si": result["params"], "fit_rms_bar": fit["rms_bar"], "fit_max_bar": fit["max_bar"],
                    "relay_check": result["relay"], "air": result["air"],
                    "steps_bar": fit["steps_bar"], "static_si": fit["static"], "fragment": R.fragment(result)})
        return
    typer.echo(R.fragment(result), nl=False)


@app.command("solenoid")
@reports_errors
def solenoid(
    params: Optional[Path] = typer.Option(None, help="YAML file overriding the default solenoid design."),
    table: Optional[Path] = typer.Option(None, help="Write the F(airgap, current) table (CSV) here."),
    thermal: bool = typer.Option(False, "--thermal", help="Coil temperature for a duty cycle and ambient."),
    duty: float = typer.Option(1.0, help="Fraction of the time the coil carries the current, [0, 1]."),
    ambient_c: float = typer.Option(20.0, help="Ambient temperature, C."),
    current: Optional[float] = typer.Option(None, help="Coil current in A (default: the rated current)."),
    step: bool = typer.Option(False, "--step", help="Current response of the PWM drive with the EPV armature."),
    plot: Optional[Path] = typer.Option(None, help="Write a PNG here."),
    json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
):
    """Proportional solenoid of the EP valve: magnetic circuit -> force table, inductance, current
    response and coil temperature."""
    from railbrake.valves import solenoid as S
    p = S.load_solenoid(params)
    if not 0.0 <= duty <= 1.0:
        raise InputError(f"--duty {duty:g}: must lie in [0, 1]")
    if thermal:
        _thermal(S, p, duty, ambient_c, current, plot, json)
    elif step:
        _current_step(S, p, current, plot, json)
    else:
        _table(S, p, table, plot, json)
    if plot and not json:
        typer.echo(f"plot: {plot}")


def _table(S, p: dict, table, plot, json: bool) -> None:
    gap, current, force = S.force_table(p)
    if table:
        S.write_table(p, prepare_output(table))
    if plot:
        from railbrake.plots.valves import plot_force_table
        plot_force_table(gap, current, force, prepare_plot(plot))
    rated, g_mid = p["rated_current_a"], gap[len(gap) // 2]
    st = S.state(p, g_mid, rated)
    figures = {"rated_current_a": rated, "airgap_mm": g_mid * 1e3, "force_n": st["force"],
               "inductance_mh": st["inductance"] * 1e3, "incremental_inductance_mh": st["incremental_inductance"] * 1e3,
               "iron_flux_density_t": st["iron_flux_density"], "resistance_20c_ohm": p["coil"]["resistance_20c_ohm"]}
    if json:
        print_json({**figures, "airgap_mm_axis": gap * 1e3, "current_a_axis": current, "force_n_table": force,
                    "table": str(table) if table else None})
        return
    typer.echo(f"at {rated:g} A, airgap {g_mid * 1e3:.2f} mm: force {st['force']:.3f} N, "
               f"L {st['inductance'] * 1e3:.1f} mH "
               f"(incremental {st['incremental_inductance'] * 1e3:.1f} mH), iron {st['iron_flux_density']:.2f} T")
    if table:
        typer.echo(f"force table: {table}")


def _thermal(S, p: dict, duty: float, ambient_c: float, current, plot, json: bool) -> None:
    r = S.thermal(p, duty=duty, ambient_c=ambient_c, current=current)
    if plot:
        from railbrake.plots.valves import plot_thermal
        plot_thermal(r, prepare_plot(plot))
    if json:
        print_json(r)
        return
    verdict = "within" if r["within_class"] else "ABOVE"
    typer.echo(f"{r['current_a']:g} A at duty {duty:g}, ambient {ambient_c:g} C: steady coil {r['steady_c']:.1f} C "
               f"(R {r['resistance_hot_ohm']:.2f} ohm, {r['power_hot_w']:.2f} W), time constant "
               f"{r['time_constant_s'] / 60:.1f} min; after {r['time_s'][-1] / 60:.0f} min "
               f"{r['temperature_c'][-1]:.1f} C; "
               f"{verdict} class {r['insulation_class']} ({r['limit_c']:.0f} C with the hot-spot allowance)")


def _current_step(S, p: dict, current, plot, json: bool) -> None:
    r = S.current_step(p, valves.load_epv()["armature"], current)
    if plot:
        from railbrake.plots.valves import plot_current_step
        plot_current_step(r, prepare_plot(plot))
    e = {k: float(r[k][-1]) for k in ("e_electric", "e_copper", "e_magnetic", "e_mechanical", "e_damping", "e_impact")}
    balance = e["e_electric"] - sum(v for k, v in e.items() if k != "e_electric")
    if json:
        print_json({**r, "energy_balance_j": balance})
        return
    typer.echo(f"PWM duty {r['duty']:.3f}: mean current {r['current_mean_a']:.3f} A, "
               f"90 % after {r['current_rise_90_s'] * 1e3:.1f} ms; "
               f"airgap {r['gap'][-1] * 1e3:.3f} mm; energy in {e['e_electric']:.4f} J, unbooked {balance:.2e} J")


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
