"""`railbrake size` and `railbrake stopping-distance`: target pressure and stopping distance."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from railbrake import sizing, vehicle
from railbrake.cli._common import prepare_plot, print_json, reports_errors
from railbrake.errors import InputError
from railbrake.units import kmh_to_ms, ms_to_kmh


def _size(train: str, profile: str, profile_csv: Optional[Path], adhesion_limit: float,
          plot: Optional[Path], json: bool) -> None:
    t = vehicle.load_train(train)
    prof = sizing.read_profile_csv(profile_csv) if profile_csv else sizing.load_profile(profile)
    result = sizing.target_pressure(t, prof, adhesion_limit=adhesion_limit)
    if plot:
        from railbrake.plots.sizing import plot_target_pressure
        frozen = sizing.target_pressure(vehicle.with_constant_pad_friction(t), prof,
                                        speeds=result.speed, adhesion_limit=adhesion_limit)
        friction = {}
        for car in t.cars:
            kind = "motor" if car.motor else "trailer"
            friction.setdefault(kind, vehicle.pad_friction_of(car, result.speed))
        plot_target_pressure(result, frozen, friction, f"{t.title}: {prof.title}", prepare_plot(plot))
    bar = {k: result.gauge_bar(getattr(result, f"p_{k}")) for k in ("motor", "trailer")}
    if json:
        print_json({"speed_kmh": ms_to_kmh(result.speed), "target_pressure_bar": bar,
                    "adhesion_demand": result.adhesion_demand, "warnings": result.warnings})
        return
    table = Table(title=f"{t.title}: {prof.title} (cylinder pressure, bar gauge)")
    for column in ("speed (km/h)", "decel (m/s2)", "motor (bar)", "trailer (bar)", "ED (kN)", "adhesion"):
        table.add_column(column, justify="right")
    fmt = lambda a, i: "-" if a is None else f"{a[i]:.2f}"  # noqa: E731
    for i in range(0, result.speed.size, max(1, result.speed.size // 15)):
        table.add_row(f"{ms_to_kmh(result.speed[i]):.0f}", f"{result.deceleration[i]:.2f}",
                      fmt(bar["motor"], i), fmt(bar["trailer"], i), f"{result.ed_force[i] / 1e3:.0f}",
                      f"{result.adhesion_demand[i]:.3f}")
    Console(width=120).print(table)
    for warning in result.warnings:
        typer.echo(f"warning: {warning}")
    if plot:
        typer.echo(f"plot: {plot}")


def register(app: typer.Typer) -> None:
    @app.command("size")
    @reports_errors
    def size(
        train: str = typer.Option("crh380a-8", help=f"Preset ({', '.join(vehicle.preset_names())}) or YAML."),
        profile: str = typer.Option("emergency", help=f"Preset ({', '.join(sizing.profile_names())}) or file."),
        profile_csv: Optional[Path] = typer.Option(None, help="CSV with speed_kmh, deceleration_ms2."),
        adhesion_limit: float = typer.Option(sizing.ADHESION_LIMIT, help="Design limit of the adhesion demand."),
        plot: Optional[Path] = typer.Option(None, help="Write a PNG of pressure and lambda(v) here."),
        json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
    ):
        """Target brake-cylinder pressure per car type for a deceleration profile (inverse)."""
        _size(train, profile, profile_csv, adhesion_limit, plot, json)

    @app.command("stopping-distance")
    @reports_errors
    def stopping_distance(
        train: str = typer.Option("crh380a-8", help="Train preset or YAML file."),
        v0_kmh: float = typer.Option(..., "--v0-kmh", help="Initial speed, km/h."),
        profile: str = typer.Option("emergency", help="Deceleration profile (preset or file)."),
        deceleration_ms2: Optional[float] = typer.Option(None, help="Hand check: constant deceleration."),
        response_time_s: Optional[float] = typer.Option(None, help="Equivalent response time te, s."),
        gradient: float = typer.Option(0.0, help="Rise over run, uphill positive (train mode)."),
        plot: Optional[Path] = typer.Option(None, help="Write a PNG of the speed-distance curve here."),
        json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
    ):
        """Stopping distance (EN 14531 manner); with --deceleration-ms2, the hand check."""
        if not v0_kmh > 0:
            raise InputError(f"--v0-kmh = {v0_kmh}: must be > 0")
        if deceleration_ms2 is not None:
            result = sizing.stopping_distance(kmh_to_ms(v0_kmh), deceleration=deceleration_ms2,
                                              response_time=response_time_s or 0.0)
            title = f"{deceleration_ms2} m/s2 after {response_time_s or 0.0} s"
        else:
            result = sizing.stopping_distance(kmh_to_ms(v0_kmh), train=train, profile=profile,
                                              response_time=response_time_s, gradient=gradient)
            title = f"{train}, {profile}"
        if plot:
            from railbrake.plots.sizing import plot_stopping
            plot_stopping(result, f"{title} from {v0_kmh:g} km/h", prepare_plot(plot))
        if json:
            print_json({"stopping_distance_m": result.distance, "stopping_time_s": result.time,
                        "warnings": result.warnings})
            return
        typer.echo(f"{title} from {v0_kmh:g} km/h: {result.distance:.0f} m in {result.time:.1f} s")
        for warning in result.warnings:
            typer.echo(f"warning: {warning}")
