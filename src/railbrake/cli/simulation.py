"""`railbrake run` and `railbrake bench`: the whole-train simulation and the plant's timing."""

from __future__ import annotations

import time
from pathlib import Path
from typing import List, Optional, Sequence

import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from railbrake import simulation
from railbrake.cli._common import KERNEL_HELP, SET_HELP, prepare_folder, print_json, reports_errors
from railbrake.resolve import resolve
from railbrake.units import cars_text

DEFAULT_SCENARIO = "emergency-300-heavy-rain"

_UNITS = {"stopping_distance_m": "m", "stopping_time_s": "s", "mean_deceleration": "m/s^2",
          "max_lock_duration_s": "s", "min_main_reservoir_bar": "bar", "min_supply_bar": "bar",
          "min_supply_margin_bar": "bar", "air_drawn_kg": "kg", "air_vented_kg": "kg",
          "cylinder_shortfall_s": "s", "brake_energy_mj": "MJ", "max_disc_temperature_c": "degC"}
SHORTFALL_WARNING_S = 2.0   # s: a cylinder short of its demand for longer did not get the air [T]


def warnings_for(result) -> list[str]:
    """What a brake engineer must not miss in a run: cylinders short of demand, supply too low."""
    k, found = result.kpis, []
    if k["cylinder_shortfall_s"] > SHORTFALL_WARNING_S:
        found.append(f"a brake cylinder stayed more than 0.2 bar below its demand for {k['cylinder_shortfall_s']:.1f} s "
                     f"(WSP valves at rest): the air did not reach it in time")
    if k["min_supply_margin_bar"] < 0.0:
        found.append(f"a supply reservoir fell {-k['min_supply_margin_bar']:.2f} bar below its car's cylinder demand "
                     f"(lowest supply {k['min_supply_bar']:.2f} bar gauge): the brake could not get its pressure")
    if not k["stopped"]:
        found.append("the train did not stop before max_time: stopping_distance_m is null")
    return found


def run_scenario(scenario: str, cars: Optional[int], wsp: bool, out: Optional[Path], quiet: bool,
                 sets: Sequence[str] = (), axles: Optional[str] = None, window: Optional[str] = None,
                 formats: Optional[list] = None, kernel: Optional[str] = None):
    """Runs with a progress bar that appears once the run has lasted 2 s; writes the outputs
    (time series in `formats`, kpis.json, run.json, plots, report.html: railbrake.results)."""
    from railbrake.results import files, record
    resolved = resolve(scenario, cars, sets)
    sc = resolved.scenario
    formats = files.parse_formats(",".join(formats or []) or None)   # checked before the run
    record.parse_axles(axles, resolved.cars)
    record.parse_window(window)
    bar = Progress(TextColumn("[bold]{task.description}"), BarColumn(), TextColumn("{task.fields[speed]}"),
                   TimeElapsedColumn(), console=Console(stderr=True), transient=True, disable=quiet)
    task = bar.add_task(sc.name, total=sc.spec.stop.max_time, speed="")
    start = time.monotonic()

    def progress(t, v):
        if not bar.live.is_started and time.monotonic() - start > 2.0:
            bar.start()
        bar.update(task, completed=t, speed=f"{3.6 * v:5.0f} km/h")

    try:
        result = simulation.run(resolved, wsp=wsp, progress=progress, kernel=kernel)
    finally:
        bar.stop()
    if out is not None:
        from railbrake.results.outputs import write_outputs
        prepare_folder(out)
        write_outputs(record.from_simulation(result, sc), out, formats, axles, window)
    return result


def print_kpis(result) -> None:
    table = Table(title=f"{result.scenario}: {cars_text(result.cars)}, WSP {'on' if result.wsp else 'off'}")
    table.add_column("KPI")
    table.add_column("value", justify="right")
    for key, value in result.kpis.items():
        text = f"{value:.4g}" if isinstance(value, float) else "-" if value is None else str(value)
        table.add_row(key, f"{text} {_UNITS.get(key, '') if value is not None else ''}".strip())
    Console().print(table)


def print_warnings(result) -> None:
    for warning in warnings_for(result):
        typer.echo(f"warning: {warning}", err=True)


def register(app: typer.Typer) -> None:
    @app.command("run")
    @reports_errors
    def run(
        scenario: str = typer.Argument(DEFAULT_SCENARIO, help="Preset name or scenario YAML file."),
        cars: Optional[int] = typer.Option(None, help="Number of cars (default: the scenario's train)."),
        no_wsp: bool = typer.Option(False, "--no-wsp", help="Run without wheel-slide protection."),
        out: Optional[Path] = typer.Option(None, help="Folder for the time series, kpis.json, plots and "
                                           "report.html."),
        json: bool = typer.Option(False, "--json", help="Print the KPIs as JSON."),
        axles: Optional[str] = typer.Option(None, help="Axles for WSP cycle plots besides the worst and "
                                            "faulty ones, e.g. c3a2,c1a1."),
        window: Optional[str] = typer.Option(None, help="T0:T1 in s for the WSP cycle plots (default: "
                                             "around each axle's first WSP activity)."),
        formats: Optional[List[str]] = typer.Option(None, "--format", help="Time series format(s): parquet, "
                                                    "csv, mf4 (repeat or comma-separate; default parquet)."),
        sets: list[str] = typer.Option([], "--set", help=SET_HELP),
        kernel: Optional[str] = typer.Option(None, help=KERNEL_HELP),
    ):
        """Whole-train brake simulation with WSP (default: 16 cars, emergency from 300 km/h in heavy rain)."""
        result = run_scenario(scenario, cars, not no_wsp, out, quiet=json, axles=axles, window=window,
                              formats=formats, sets=sets, kernel=kernel)
        print_warnings(result)
        if json:
            print_json(result.kpis)
            return
        print_kpis(result)
        if out is not None:
            typer.echo(f"outputs: {out}/")

    @app.command("bench")
    @reports_errors
    def bench(
        cars: int = typer.Option(16, help="Number of cars."),
        steps: int = typer.Option(20000, help="Plant steps to time (1 ms each)."),
        kernel: Optional[str] = typer.Option(None, help=KERNEL_HELP),
        json: bool = typer.Option(False, "--json", help="Print as JSON."),
    ):
        """The plant alone at 1 ms (timing loop in C): real-time factor (CPU time per step) and step times."""
        figures = simulation.bench(cars, steps, kernel=kernel)
        if json:
            print_json(figures)
            return
        typer.echo(f"{cars_text(figures['cars'])}, {figures['kernel']} kernel, {figures['substeps']} sub-step(s): "
                   f"{figures['realtime_factor']:.0f}x real time, step {figures['step_us_mean']:.2f} us mean CPU "
                   f"({figures['step_us_wall_mean']:.2f} us wall), {figures['step_us_p99']:.2f} us p99, "
                   f"{figures['step_us_max']:.2f} us max")
