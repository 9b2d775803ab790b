"""`railbrake size` and `railbrake stopping-distance`: target pressure and stopping distance."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from railbrake import sizing, vehicle
from railbrake.cli import _common
from railbrake.cli._common import prepare_plot, print_json, reports_errors
from railbrake.errors import InputError
from railbrake.units import kmh_to_ms, ms_to_kmh


def _size(train: str, profile: Optional[str], profile_csv: Optional[Path], adhesion_limit: float,
          plot: Optional[Path], json: bool, ed: Optional[bool] = None) -> None:
    t = vehicle.load_train(train)
    prof = sizing.read_profile_csv(profile_csv) if profile_csv else \
        sizing.brake_step(t, "emergency")[0] if profile is None else sizing.load_profile(profile)
    result = sizing.target_pressure(t, prof, adhesion_limit=adhesion_limit, ed=ed)
    brakes = sizing.blending_text(result)
    if plot:
        from railbrake.plots.sizing import plot_target_pressure
        frozen = sizing.target_pressure(vehicle.with_constant_pad_friction(t), prof, speeds=result.speed,
                                        adhesion_limit=adhesion_limit, ed=result.ed_blending)
        friction = {}
        for car in t.cars:
            kind = "motor" if car.motor else "trailer"
            friction.setdefault(kind, vehicle.pad_friction_of(car, result.speed))
        plot_target_pressure(result, frozen, friction, f"{t.title}: {prof.title}", prepare_plot(plot))
    bar = {k: result.gauge_bar(getattr(result, f"p_{k}")) for k in ("motor", "trailer")}
    if json:
        print_json({"speed_kmh": ms_to_kmh(result.speed), "target_pressure_bar": bar,
                    "adhesion_demand": result.adhesion_demand, "ed_blending": result.ed_blending,
                    "brakes": brakes, "warnings": result.warnings})
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
    typer.echo(f"brakes: {brakes}")
    for warning in result.warnings:
        typer.echo(f"warning: {warning}")
    if plot:
        typer.echo(f"plot: {plot}")


def _gradient_pieces(text: Optional[str]) -> list:
    """'0:0,2000:-12' -> [(0.0, 0.0), (2000.0, -0.012)] (m, rise/run)."""
    if not text:
        return []
    pieces = []
    for item in text.split(","):
        start, sep, permille = item.partition(":")
        try:
            pieces.append((float(start), float(permille) * 1e-3))
        except ValueError:
            raise InputError(f"--gradients = {text!r}: {item!r} is not START_M:PERMILLE") from None
        if not sep or not -100.0 <= pieces[-1][1] * 1e3 <= 100.0:
            raise InputError(f"--gradients = {text!r}: {item!r}: START_M:PERMILLE with the gradient in [-100, 100]")
    return pieces


def register(app: typer.Typer) -> None:
    @app.command("size")
    @reports_errors
    def size(
        train: str = typer.Option("crh380a-8", autocompletion=_common.complete_train, help=f"Preset ({', '.join(vehicle.preset_names())}) or YAML."),
        profile: Optional[str] = typer.Option(None, autocompletion=_common.complete_profile, help=f"Preset ({', '.join(sizing.profile_names())}) or file "
                                              "(default: the train's emergency brake step)."),
        profile_csv: Optional[Path] = typer.Option(None, help="CSV with speed_kmh, deceleration_ms2."),
        adhesion_limit: float = typer.Option(sizing.ADHESION_LIMIT, help="Design limit of the adhesion demand."),
        plot: Optional[Path] = typer.Option(None, help="Write a PNG of pressure and lambda(v) here."),
        json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
        ed: Optional[bool] = typer.Option(None, "--ed/--no-ed", help="Blend the ED brake first on the motor "
                                          "cars, or not (default: as the train's brake step with this profile "
                                          "says, else not: pneumatic only)."),
    ):
        """Target brake-cylinder pressure per car type for a deceleration profile (inverse); the
        output says which brakes it counts."""
        _size(train, profile, profile_csv, adhesion_limit, plot, json, ed)

    @app.command("stopping-distance")
    @reports_errors
    def stopping_distance(
        train: str = typer.Option("crh380a-8", autocompletion=_common.complete_train, help="Train preset or YAML file."),
        v0_kmh: float = typer.Option(..., "--v0-kmh", help="Initial speed, km/h."),
        profile: Optional[str] = typer.Option(None, autocompletion=_common.complete_profile, help="Deceleration profile (preset or file; default: the "
                                                          "train's emergency brake step)."),
        deceleration_ms2: Optional[float] = typer.Option(None, help="Hand check: constant deceleration."),
        response_time_s: Optional[float] = typer.Option(None, help="Equivalent response time te, s."),
        profile_response: bool = typer.Option(False, "--profile-response",
                                              help="Take ta and tb from the profile instead of the train's own "
                                              "simulated build-up (EN 14531 on a 6 s run of the plant)."),
        gradient_permille: float = typer.Option(0.0, "--gradient-permille",
                                                help="Gradient, per mille, uphill positive (train mode)."),
        load: Optional[str] = typer.Option(None, help="Load case: tare, normal, crush (default: the train file's)."),
        gradients: Optional[str] = typer.Option(None, help="Piecewise gradient along the track from the brake's "
                                                "start, START_M:PERMILLE pairs, e.g. '0:0,2000:-12' (train mode)."),
        plot: Optional[Path] = typer.Option(None, help="Write a PNG of the speed-distance curve here."),
        json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
    ):
        """Stopping distance (EN 14531 manner); with --deceleration-ms2, the hand check."""
        if not v0_kmh > 0:
            raise InputError(f"--v0-kmh = {v0_kmh}: must be > 0")
        if not -100.0 <= gradient_permille <= 100.0:
            raise InputError(f"--gradient-permille = {gradient_permille}: must lie in [-100, 100] per mille")
        if deceleration_ms2 is not None:
            result = sizing.stopping_distance(kmh_to_ms(v0_kmh), deceleration=deceleration_ms2,
                                              response_time=response_time_s or 0.0)
            title = f"{deceleration_ms2} m/s2 after {response_time_s or 0.0} s"
        else:
            t = vehicle.load_train(train, load or True)
            if kmh_to_ms(v0_kmh) > t.max_speed * (1 + 1e-9):
                raise InputError(f"--v0-kmh = {v0_kmh:g}: above the maximum speed of train {t.name}, "
                                 f"{ms_to_kmh(t.max_speed):g} km/h")
            if profile_response and profile is None:   # the emergency step's profile with its ta, tb
                profile_asked = t.brake_step("emergency").profile
            else:
                profile_asked = profile
            from railbrake.simulation import stopping_distance as measured_stop   # the plant: at call time
            result = measured_stop(kmh_to_ms(v0_kmh), train=t, profile=profile_asked,
                                   response_time=response_time_s, gradient=gradient_permille * 1e-3,
                                   gradients=_gradient_pieces(gradients))
            name = profile or t.brake_step("emergency").profile
            title = f"{train} ({t.load_case} load), {name}"
            if result.simulated_response:
                title += (f", simulated build-up ta {result.delay:.2f} s, tb {result.build_up:.2f} s, "
                          f"te {result.delay + 0.5 * result.build_up:.2f} s")
        if plot:
            from railbrake.plots.sizing import plot_stopping
            plot_stopping(result, f"{title} from {v0_kmh:g} km/h", prepare_plot(plot))
        if json:
            print_json({"stopping_distance_m": result.distance, "stopping_time_s": result.time,
                        "warnings": result.warnings})
        else:
            typer.echo(f"{title} from {v0_kmh:g} km/h: {result.distance:.0f} m in {result.time:.1f} s")
            for warning in result.warnings:
                typer.echo(f"warning: {warning}")
        if plot:
            typer.echo(f"plot: {plot}", err=json)
