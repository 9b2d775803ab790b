"""Everything `run --out` and `hil --out` write into a run folder: time series (Parquet, CSV,
MDF4), kpis.json, run.json, the plots and report.html."""

from __future__ import annotations

from pathlib import Path

from railbrake.results.files import write_run
from railbrake.results.record import RunRecord, parse_axles, parse_window
from railbrake.results.report import write_report


def write_outputs(record: RunRecord, out: Path, formats=("parquet",), axles: str | None = None,
                  window: str | None = None, mdf_extra: dict | None = None, mdf_events=()) -> list[Path]:
    from railbrake.plots.simulation import plot_all
    from railbrake.results import files
    chosen, span = parse_axles(axles, record), parse_window(window, record)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for fmt in formats:
        if fmt == "mf4":
            paths.append(files.write_mdf(record, out / files.FORMATS["mf4"], mdf_extra, mdf_events))
    paths += write_run(record, out, [f for f in formats if f != "mf4"])
    plots = plot_all(record, out, chosen, span)
    paths += plots
    paths.append(write_report(record, plots, out / "report.html"))
    return paths
