"""`railbrake compare`: saved runs side by side (KPIs and their differences from the first run,
the largest channel differences, overlaid plots). Runs: MIL (Parquet), HIL (MDF4), FMU (CSV)."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer
from rich.console import Console
from rich.table import Table

from railbrake.cli._common import print_json, reports_errors
from railbrake.errors import InputError


def _cell(value) -> str:
    from railbrake.results import kpis
    return kpis.text(value)


def _difference(d) -> str:
    if d is None:
        return "same"
    if isinstance(d, str):
        return d
    return "0" if d == 0 else f"{d:+.4g}"


def _human(d: dict) -> str:
    """'cylinder_c3a2 3.41 bar' from a difference in SI."""
    from railbrake.units import BAR, ms_to_kmh
    scale, unit = {"Pa": (1 / BAR, "bar"), "m/s": (ms_to_kmh(1.0), "km/h")}.get(d["unit"], (1.0, d["unit"]))
    return f"{d['channel']} {d['difference'] * scale:.3g} {unit}"


def _print_channels(report: dict) -> None:
    """Every common channel: its largest difference from the first run, absolute (SI) and relative."""
    labels = [r["label"] for r in report["runs"]]
    table = Table()
    table.add_column("channel", no_wrap=True)
    for lab in labels[1:]:
        table.add_column(f"{lab}-{labels[0]} (SI)", justify="right")
        table.add_column(f"{lab}-{labels[0]} relative", justify="right")
    names = list(dict.fromkeys(n for diffs in report["channels"] for n in diffs))
    for name in names:
        cells = []
        for diffs, relative in zip(report["channels"], report["channels_relative"]):
            cells += [_difference(diffs.get(name)) if name in diffs else "-",
                      f"{relative[name]:.3g}" if relative.get(name) is not None else "-"]
        table.add_row(name, *cells)
    Console().print(table)


def _print(report: dict) -> None:
    from railbrake.results import kpis as info
    console = Console()
    for run in report["runs"]:
        console.print(f"{run['label']}: {run['path']}  [dim]{run['title']}[/]", highlight=False)
    table = Table()
    table.add_column("KPI", no_wrap=True)
    labels = [r["label"] for r in report["runs"]]
    for lab in labels:
        table.add_column(lab, justify="right")
    for lab in labels[1:]:
        table.add_column(f"{lab}-{labels[0]}", justify="right")
    for key, row in report["kpis"].items():
        unit = info.unit(key)
        shown = unit and unit != "1" and not key.endswith(("_m", "_s", "_kg", "_bar", "_mj", "_c"))
        table.add_row(f"{key}{f' ({unit})' if shown else ''}",
                      *map(_cell, row["values"]), *map(_difference, row["differences"]))
    console.print(table)
    for lab, largest in zip(labels[1:], report["largest_channel_differences"]):
        text = "; ".join(_human(d) for d in largest) or "no common channels"
        console.print(f"{lab}-{labels[0]} largest sample differences: {text}", highlight=False)
    console.print("identical" if report["identical"] else "the runs differ", highlight=False)


def register(app: typer.Typer) -> None:
    @app.command("compare")
    @reports_errors
    def compare(
        runs: List[Path] = typer.Argument(..., help="Two or more run folders or files (.parquet, .mf4, .csv)."),
        plot: Optional[Path] = typer.Option(None, help="Folder for overlaid braking curves and axle pressures."),
        axles: Optional[str] = typer.Option(None, help="Axles to overlay besides the worst and faulty ones."),
        window: Optional[str] = typer.Option(None, help="T0:T1 in s for the axle pressures."),
        json: bool = typer.Option(False, "--json", help="Print the comparison as JSON."),
        channels: bool = typer.Option(False, "--channels", help="Also list every common channel's largest "
                                      "difference, absolute and relative (e.g. an FMU's CSV against a run)."),
    ):
        """Saved runs side by side: KPIs with differences from the first run; MIL, HIL and FMU alike."""
        from railbrake.results import files
        from railbrake.results.compare import compare_runs
        from railbrake.results.record import parse_axles, parse_window
        if len(runs) < 2:
            raise InputError(f"compare: {len(runs)} run given: needs at least two")
        records = [files.load(r) for r in runs]
        report = compare_runs(records, [str(r) for r in runs])
        if json:
            print_json(report)
        else:
            _print(report)
            if channels:
                _print_channels(report)
        if plot is not None:
            from railbrake.plots.compare_runs import plot_comparison
            labels = [r["label"] for r in report["runs"]]
            for path in plot_comparison(records, labels, plot, parse_axles(axles, records[0]),
                                        parse_window(window, records[0])):
                typer.echo(f"plot: {path}", err=json)
