"""`railbrake compare-rt`: the real-time plant checked against the detailed model."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from railbrake.cli import _common
from railbrake.cli._common import SET_HELP, prepare_folder, print_json, reports_errors
from railbrake.resolve import resolve
from railbrake.units import cars_text


def print_comparison(c) -> None:
    s = c.summary
    table = Table(title=f"{c.scenario}, {cars_text(c.cars)}: real-time plant (1 ms) vs detailed model")
    table.add_column("figure")
    table.add_column("value", justify="right")
    rows = [("stopping distance RT", f"{s['stopping_distance_rt_m']:.1f} m"),
            ("stopping distance detailed", f"{s['stopping_distance_detailed_m']:.1f} m"),
            ("difference", f"{s['stopping_distance_difference_pct']:+.2f} %"),
            ("cylinder pressure RMS (worst axle)", f"{s['cylinder_rms_bar']:.3f} bar"),
            ("cylinder pressure max |diff|", f"{s['cylinder_max_bar']:.3f} bar"),
            ("cylinder 1 s mean RMS (worst axle)", f"{s['cylinder_mean_rms_bar']:.3f} bar"),
            ("EP / relay output 1 s mean RMS (worst car)",
             f"{s['pilot_mean_rms_bar']:.3f} / {s['relay_mean_rms_bar']:.3f} bar"),
            ("stopping time difference", f"{s['stopping_time_difference_s']:+.2f} s"),
            ("air vented RT / detailed", f"{s['air_vented_rt_kg']:.3g} / {s['air_vented_detailed_kg']:.3g} kg"),
            ("vent open, all axles RT / detailed", f"{s['vent_open_rt_s']:.1f} / {s['vent_open_detailed_s']:.1f} s"),
            ("detailed model wall time", f"{s['detailed_wall_s']:.1f} s")]
    for name, value in rows:
        table.add_row(name, value)
    Console().print(table)
    if c.steps:
        study = Table(title="step-size study of the real-time plant (errors vs the detailed model)")
        for col in ("dt (ms)", "sub-steps", "distance (m)", "error (%)", "cyl RMS (bar)", "1 s mean RMS (bar)",
                    "stable"):
            study.add_column(col, justify="right")
        for r in c.steps:
            study.add_row(f"{r['dt_ms']:g}", str(r["substeps"]), f"{r['stopping_distance_m']:.1f}",
                          f"{r['distance_error_pct']:+.2f}",
                          f"{r['cylinder_rms_bar']:.3f}", f"{r['cylinder_mean_rms_bar']:.3f}",
                          "yes" if r["stable"] else f"no: {r['instability']}")
        Console().print(study)


def register(app: typer.Typer) -> None:
    @app.command("compare-rt")
    @reports_errors
    def compare_rt(
        scenario: str = typer.Argument(..., autocompletion=_common.complete_scenario, help="Preset name or scenario YAML file."),
        cars: Optional[int] = typer.Option(None, help="Number of cars (default: the scenario's train)."),
        plot: Optional[Path] = typer.Option(None, help="Folder for the comparison plots."),
        json: bool = typer.Option(False, "--json", help="Print the comparison as JSON."),
        no_steps: bool = typer.Option(False, "--no-steps", help="Skip the step-size study."),
        sets: list[str] = typer.Option([], "--set", help=SET_HELP),
    ):
        """Run the real-time plant and the detailed model; report their differences and the
        real-time plant's step-size study (0.25 to 5 ms)."""
        from railbrake.simulation.compare import compare

        bar = Progress(TextColumn("[bold]{task.description}"), BarColumn(), TimeElapsedColumn(),
                       console=Console(stderr=True), transient=True, disable=json)
        task = bar.add_task("detailed model", total=1.0)
        with bar:
            c = compare(resolve(scenario, cars, sets), steps_ms=() if no_steps else None,
                        progress=lambda stage, done: bar.update(task, description=stage, completed=done))
        if plot is not None:
            from railbrake.plots.compare import plot_all
            prepare_folder(plot, "--plot")
            plot_all(c, plot)
        if json:
            print_json(c.as_dict())
            return
        print_comparison(c)
        if plot is not None:
            typer.echo(f"plots: {plot}/")
