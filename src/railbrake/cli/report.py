"""`railbrake report brake`: the brake calculation as engineers report it (UIC 544-1 braked weight
and brake percentage, EN 14531-1 mean decelerations, stopping distances against the TSI)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from railbrake import vehicle
from railbrake.cli import _common
from railbrake.cli._common import prepare_folder, print_json, reports_errors
from railbrake.errors import InputError

app = typer.Typer(help="Reports computed from a train file.", no_args_is_help=True)


@app.command("brake")
@reports_errors
def brake(
    trains: Optional[list[str]] = typer.Argument(None, autocompletion=_common.complete_train, help=f"Presets ({', '.join(vehicle.preset_names())}) or "
                                                 "train YAML files (default: every preset)."),
    load_case: Optional[str] = typer.Option(None, "--load-case", help="tare, normal or crush (default: each "
                                            "train file's)."),
    force_lambda: bool = typer.Option(False, "--force-lambda", help="Compute the UIC 544-1 brake percentage "
                                      "also for trains faster than its validity (200 km/h), flagged."),
    json: bool = typer.Option(False, "--json", help="Print the calculation as JSON."),
    out: Optional[Path] = typer.Option(None, help="Write brake-calculation.json and brake-calculation.html "
                                       "into this folder."),
):
    """Braked weight and brake percentage (UIC 544-1), EN 14531-1 mean decelerations and the
    emergency stopping distances against the TSI table, with pass/fail and margin."""
    from railbrake import brakecalc
    if load_case is not None and load_case not in vehicle.LOAD_CASES:
        raise InputError(f"--load-case = {load_case!r}: must be one of {', '.join(vehicle.LOAD_CASES)}")
    folder = prepare_folder(out)
    calcs = [brakecalc.calculate(t, load_case, force_lambda) for t in (trains or vehicle.preset_names())]
    if folder is not None:
        paths = brakecalc.write(calcs, folder)
    if json:
        print_json(brakecalc.as_json(calcs))
    else:
        from railbrake.brakecalc.report import SUMMARY_HEADERS, down, summary_rows, up
        table = Table(title="Brake calculation (level track, emergency brake step; distances rounded up, "
                      "lambda, weights, decelerations, margins down)")
        for column in SUMMARY_HEADERS:
            table.add_column(column, justify="right")
        for row in summary_rows(calcs):
            table.add_row(*row)
        Console(width=160).print(table)
        for c in calcs:
            for row in c.tsi:
                typer.echo(f"{c.train}: from {row['speed_kmh']:.0f} km/h {up(row['stopping_distance_m']):.0f} m, TSI "
                           f"{row['limit_m']:.0f} m, margin {down(row['margin_m']):.0f} m: "
                           f"{'pass' if row['passed'] else 'FAIL'}")
            if "note" in c.uic:
                typer.echo(f"{c.train}: UIC 544-1: {c.uic['note']}")
            for warning in c.warnings:
                typer.echo(f"warning: {c.train}: {warning}")
    if folder is not None:
        typer.echo(f"{paths[0]}, {paths[1]}", err=json)
