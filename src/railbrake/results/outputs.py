"""Everything `run --out` and `hil --out` write into a run folder: time series (Parquet, CSV,
MDF4), kpis.json, run.json, the plots, report.html, config.yaml, and last manifest.json (sample
count and each file's digest: railbrake.results.files.check_complete). Each file is whole or
absent (railbrake.atomic); a folder without its manifest is an interrupted one."""

from __future__ import annotations

from pathlib import Path

from railbrake.results.files import write_run
from railbrake.results.record import RunRecord, parse_axles, parse_window
from railbrake.results.report import write_report


def write_outputs(record: RunRecord, out: Path, formats=("parquet",), axles: str | None = None,
                  window: str | None = None, mdf_extra: dict | None = None, mdf_events=(),
                  resolved=None) -> list[Path]:
    """resolved: the run's configuration, written as config.yaml (railbrake.results.config_file)."""
    from railbrake.plots.simulation import plot_all
    from railbrake.results import files
    chosen, span = parse_axles(axles, record), parse_window(window, record)
    files.begin_folder(out)
    paths = []
    for fmt in formats:
        if fmt == "mf4":
            paths.append(files.write_mdf(record, out / files.FORMATS["mf4"], mdf_extra, mdf_events))
    paths += write_run(record, out, [f for f in formats if f != "mf4"], complete=False)
    plots = plot_all(record, out, chosen, span)
    paths += plots
    paths.append(write_report(record, plots, out / "report.html"))
    if resolved is not None:
        from railbrake.results.config_file import write_config
        paths += write_config(resolved, out / "config.yaml")   # and the files it names, copied beside it
    paths.append(files.write_manifest(out, record, paths))
    return paths
