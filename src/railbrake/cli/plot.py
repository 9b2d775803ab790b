"""`railbrake plot`: the run's figures again from a saved run (Parquet, MDF4 or CSV), without
re-running."""

from __future__ import annotations

import fnmatch
from pathlib import Path
from typing import Optional

import typer

from railbrake.cli._common import reports_errors
from railbrake.errors import InputError

PLOT_FORMATS = ("png", "svg", "pdf")


def parse_channels(text: Optional[str], record) -> list[str]:
    """'speed,cylinder_c3*' -> the recorded channels it names (shell patterns allowed)."""
    if not text:
        return []
    names = []
    for item in (s.strip() for s in text.split(",") if s.strip()):
        found = [n for n in record.outputs if n != "time" and fnmatch.fnmatchcase(n, item)]
        if not found:
            raise InputError(f"--channels = {text!r}: {item!r} names no recorded channel "
                             f"(e.g. speed, main_reservoir, cylinder_c1a1, supply_c1)")
        names += found
    return list(dict.fromkeys(names))


def register(app: typer.Typer) -> None:
    @app.command("plot")
    @reports_errors
    def plot(
        run: Path = typer.Argument(..., help="Run folder (from run/hil --out) or one .parquet, .mf4 or .csv file."),
        axles: Optional[str] = typer.Option(None, help="Axles for WSP cycle plots besides the worst and faulty "
                                            "ones, e.g. c3a2,c1a1."),
        window: Optional[str] = typer.Option(None, help="T0:T1 in s for the WSP cycle plots."),
        channels: Optional[str] = typer.Option(None, help="Also plot these channels over time, e.g. "
                                               "speed,cylinder_c3*."),
        fmt: str = typer.Option("png", "--format", help="Image format: png, svg or pdf."),
        out: Optional[Path] = typer.Option(None, help="Folder for the figures (default: the run's folder)."),
    ):
        """Redraw a saved run's figures (same data, same channels as the run drew them)."""
        from railbrake.plots.simulation import plot_all
        from railbrake.results import files
        from railbrake.results.record import parse_axles, parse_window
        if fmt not in PLOT_FORMATS:
            raise InputError(f"--format = {fmt!r}: must be one of {', '.join(PLOT_FORMATS)}")
        record = files.load(run)
        chosen, span = parse_axles(axles, record), parse_window(window, record)
        names = parse_channels(channels, record)
        folder = out or (run if run.is_dir() else run.parent)
        written = plot_all(record, folder, chosen, span, names, fmt)
        files.refresh_manifest(folder, written)   # a run folder's redrawn figures: still a complete folder
        for path in written:
            typer.echo(f"plot: {path}")
