"""`railbrake adhesion ...`: creep-force curves, preset conditions, parameter fit."""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from railbrake import adhesion as adh
from railbrake.cli import _common
from railbrake.cli._common import parse_float_list, prepare_plot, print_json, reports_errors
from railbrake.contact import default_contact, polach_coefficient
from railbrake.errors import InputError
from railbrake.units import KMH, kmh_to_ms, ms_to_kmh

app = typer.Typer(help="Wheel-rail adhesion: creep-force curves, conditions, parameter fit.",
                  no_args_is_help=True)


@app.command("curves")
@reports_errors
def curves(
    condition: str = typer.Option("dry-high", autocompletion=_common.complete_condition, help="Preset name or YAML file (see 'adhesion conditions')."),
    speed_kmh: str = typer.Option("20,60,300", help="Comma-separated speeds in km/h."),
    axle: int = typer.Option(0, help="Axle counted from the front of the train (0 = leading)."),
    plot: Optional[Path] = typer.Option(None, help="Write a PNG of the curves here."),
    json: bool = typer.Option(False, "--json", help="Print the curves as JSON."),
):
    """Creep-force curves F/Q against creep on the default high-speed wheelset."""
    speeds = [kmh_to_ms(v) for v in parse_float_list(speed_kmh, "--speed-kmh")]
    if any(v < 0 for v in speeds):
        raise InputError(f"--speed-kmh = {speed_kmh!r}: speeds must be >= 0")
    cond = adh.load_condition(condition)
    result = adh.creep_curves(cond, speeds, axle=axle)
    if plot:
        from railbrake.plots.adhesion import plot_creep_curves
        plot_creep_curves(result, f"{cond.title} (axle {axle})", prepare_plot(plot))
    if json:
        print_json({"condition": cond.name, "axle": axle, "curves": [
            {"speed_kmh": ms_to_kmh(c.speed), "creep": c.creep, "coefficient": c.coefficient,
             "peak_creep": c.peak.creep, "peak_coefficient": c.peak.coefficient} for c in result]})
        return
    table = Table(title=f"{cond.title}, axle {axle}")
    for column in ("speed (km/h)", "peak F/Q", "at creep (%)"):
        table.add_column(column, justify="right")
    for c in result:
        table.add_row(f"{ms_to_kmh(c.speed):.0f}", f"{c.peak.coefficient:.4f}", f"{100 * c.peak.creep:.2f}")
    Console().print(table)
    if plot:
        typer.echo(f"plot: {plot}")


@app.command("conditions")
@reports_errors
def list_conditions(json: bool = typer.Option(False, "--json", help="Print as JSON.")):
    """The preset adhesion conditions with their Polach parameters and sources."""
    presets = adh.conditions()
    if json:
        print_json({"conditions": [
            {"name": c.name, "title": c.title, "params": c.params.as_dict(), "source": c.source,
             "conditioning": None if c.conditioning is None else vars(c.conditioning),
             "validity": None if c.validity is None else vars(c.validity),
             "fit": None if c.fit is None else vars(c.fit)}
            for c in presets]})
        return
    table = Table(title="Adhesion conditions (Polach parameters)")
    for column in ("name", "mu0", "A", "B (s/m)", "kA", "kS", "conditioning", "valid (km/h)", "source"):
        table.add_column(column)
    for c in presets:
        p = c.params
        cond = "-" if c.conditioning is None else \
            f"lead x{c.conditioning.leading_factor:g}, {c.conditioning.recovery_axles:g} axles"
        valid = "-" if c.validity is None else f"{c.validity.speed_min_kmh:g}-{c.validity.speed_max_kmh:g}"
        table.add_row(c.name, f"{p.mu0:g}", f"{p.A:g}", f"{p.B:g}", f"{p.kA:g}", f"{p.kS:g}", cond, valid, c.source)
    Console(width=200).print(table)


def _read_measurements(path: Path):
    from railbrake.config import read_text
    text = read_text(path)   # names a missing, unreadable or non-UTF-8 file
    with io.StringIO(text, newline="") as handle:
        reader = csv.DictReader(handle)
        needed = {"creep", "coefficient", "speed_kmh"}
        if not reader.fieldnames or not needed <= set(reader.fieldnames):
            raise InputError(f"{path}: columns {reader.fieldnames}: needs {sorted(needed)}")
        rows = []
        for line, row in enumerate(reader, start=2):
            try:
                rows.append([float(row["creep"]), float(row["coefficient"]), float(row["speed_kmh"])])
            except (TypeError, ValueError):
                raise InputError(f"{path}, line {line}: {row}: not numbers") from None
    if not rows:
        raise InputError(f"{path}: no data rows")
    data = np.array(rows)
    adh.check_points(data[:, 0], data[:, 1], data[:, 2],
                     lambda name, i: f"{path}, line {i + 2}: {'speed_kmh' if name == 'speed' else name}",
                     speed_unit=("km/h", KMH))
    return data[:, 0], data[:, 1], kmh_to_ms(data[:, 2])


@app.command("fit")
@reports_errors
def fit(
    measured: Path = typer.Argument(..., help="CSV with columns creep, coefficient, speed_kmh."),
    plot: Optional[Path] = typer.Option(None, help="Write a PNG of data and fit here."),
    json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
):
    """Fit Polach's five parameters to measured creep-force points (default wheelset)."""
    creep, coefficient, speed = _read_measurements(measured)
    result = adh.identify_polach(creep, coefficient, speed)
    if plot:
        from railbrake.plots.adhesion import plot_fit
        contact = default_contact()
        model = lambda s, v: polach_coefficient(s, v, contact.normal_force, contact, result.params)  # noqa: E731
        plot_fit(creep, coefficient, speed, model, f"Polach fit to {measured.name}", prepare_plot(plot))
    if json:
        print_json({"params": result.params.as_dict(), "std": result.std, "rms": result.rms,
                    "residuals": result.residuals})
        return
    table = Table(title=f"Polach fit to {measured.name} (rms residual {result.rms:.4f})")
    table.add_column("parameter")
    table.add_column("value", justify="right")
    table.add_column("std", justify="right")
    for name, value in result.params.as_dict().items():
        table.add_row(name, f"{value:.4g}", f"{result.std[name]:.2g}")
    Console().print(table)
