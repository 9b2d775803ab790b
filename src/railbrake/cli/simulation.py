"""`railbrake run` and `railbrake bench`: the whole-train simulation and the plant's timing."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional, Sequence

import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from railbrake import simulation
from railbrake.cli._common import SET_HELP, print_json, reports_errors
from railbrake.resolve import resolve
from railbrake.units import cars_text

DEFAULT_SCENARIO = "emergency-300-heavy-rain"

_UNITS = {"stopping_distance_m": "m", "stopping_time_s": "s", "mean_deceleration": "m/s^2",
          "max_lock_duration_s": "s", "air_consumed_kg": "kg"}


def run_scenario(scenario: str, cars: Optional[int], wsp: bool, out: Optional[Path], quiet: bool,
                 sets: Sequence[str] = ()):
    """Runs with a progress bar that appears once the run has lasted 2 s; writes the outputs."""
    resolved = resolve(scenario, cars, sets)
    sc = resolved.scenario
    bar = Progress(TextColumn("[bold]{task.description}"), BarColumn(), TextColumn("{task.fields[speed]}"),
                   TimeElapsedColumn(), console=Console(stderr=True), transient=True, disable=quiet)
    task = bar.add_task(sc.name, total=sc.spec.stop.max_time, speed="")
    start = time.monotonic()

    def progress(t, v):
        if not bar.live.is_started and time.monotonic() - start > 2.0:
            bar.start()
        bar.update(task, completed=t, speed=f"{3.6 * v:5.0f} km/h")

    try:
        result = simulation.run(resolved, wsp=wsp, progress=progress)
    finally:
        bar.stop()
    if out is not None:
        from railbrake.plots.simulation import plot_all
        from railbrake.simulation.io import write_kpis, write_parquet
        out.mkdir(parents=True, exist_ok=True)
        write_parquet(result, out / "timeseries.parquet")
        write_kpis(result, out / "kpis.json")
        plot_all(result, out)
    return result


def print_kpis(result) -> None:
    table = Table(title=f"{result.scenario}: {cars_text(result.cars)}, WSP {'on' if result.wsp else 'off'}")
    table.add_column("KPI")
    table.add_column("value", justify="right")
    for key, value in result.kpis.items():
        text = f"{value:.4g}" if isinstance(value, float) else str(value)
        table.add_row(key, f"{text} {_UNITS.get(key, '')}".strip())
    Console().print(table)


def register(app: typer.Typer) -> None:
    @app.command("run")
    @reports_errors
    def run(
        scenario: str = typer.Argument(DEFAULT_SCENARIO, help="Preset name or scenario YAML file."),
        cars: Optional[int] = typer.Option(None, help="Number of cars (default: the scenario's train)."),
        no_wsp: bool = typer.Option(False, "--no-wsp", help="Run without wheel-slide protection."),
        out: Optional[Path] = typer.Option(None, help="Folder for timeseries.parquet, kpis.json and plots."),
        json: bool = typer.Option(False, "--json", help="Print the KPIs as JSON."),
        sets: list[str] = typer.Option([], "--set", help=SET_HELP),
    ):
        """Whole-train brake simulation with WSP (default: 16 cars, emergency from 300 km/h in heavy rain)."""
        result = run_scenario(scenario, cars, not no_wsp, out, quiet=json, sets=sets)
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
        json: bool = typer.Option(False, "--json", help="Print as JSON."),
    ):
        """The plant alone at 1 ms (timing loop in C): real-time factor and step times."""
        figures = simulation.bench(cars, steps)
        if json:
            print_json(figures)
            return
        typer.echo(f"{figures['cars']} cars: {figures['realtime_factor']:.0f}x real time, "
                   f"step {figures['step_us_mean']:.2f} us mean, {figures['step_us_p99']:.2f} us p99")
