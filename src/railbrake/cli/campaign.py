"""`railbrake campaign run|report|plan`: studies over many configurations (docs/campaigns.md)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn,
                           TimeRemainingColumn)

from railbrake.campaign.budget import MAX_RUNS
from railbrake.cli import _common
from railbrake.cli._common import print_json, reports_errors

MAX_RUNS_HELP = "Refuse a design of more runs than this (before drawing it), with an estimate of its cost."

app = typer.Typer(help="Campaigns: studies of many configurations on a laptop or a Dask cluster.",
                  no_args_is_help=True)


DASHBOARD = "127.0.0.1:8787"   # the local cluster's Dask dashboard (Dask moves it to a free port if taken)
NO_DASHBOARD = "off"


def _answers(link: str, timeout: float = 2.0) -> str | None:
    """None when the page at link answers an HTTP GET (200), else why not: a dashboard without its
    pages (no bokeh) answers 404."""
    import urllib.error
    import urllib.request
    try:
        with urllib.request.urlopen(link, timeout=timeout) as page:
            return None if page.status == 200 else f"HTTP {page.status}"
    except urllib.error.HTTPError as exc:
        return f"HTTP {exc.code}" + (" (its pages need bokeh)" if exc.code == 404 else "")
    except (OSError, ValueError) as exc:
        return f"no answer ({getattr(exc, 'reason', None) or exc})"


def _dashboard_reporter(asked: bool):
    """on_connect(client): the Dask dashboard's link once an HTTP GET of it succeeds; otherwise, if
    one was asked for (the default), why it is not shown; nothing when --dashboard off."""
    def show(client) -> None:
        link = client.dashboard_link if client.scheduler_info().get("services", {}).get("dashboard") else None
        why = _answers(link) if link else "the scheduler serves none (Dask serves it with bokeh installed)"
        if why is None:
            typer.echo(f"Dask dashboard: {link}", err=True)
        elif asked:
            typer.echo(f"Dask dashboard: not shown: {link + ' ' if link else ''}{why}", err=True)
    return show


def _dashboard_address(option: str) -> str | None:
    return None if option.strip().lower() == NO_DASHBOARD else option


def _default_out(study) -> Path:
    return Path("out") / "campaigns" / study.name


@app.command("run")
@reports_errors
def run(
    study: str = typer.Argument(..., autocompletion=_common.complete_study, help="Study YAML file or preset study (railbrake.study/1)."),
    out: Optional[Path] = typer.Option(None, help="Dataset folder (default: out/campaigns/<study name>)."),
    workers: Optional[int] = typer.Option(None, min=1, help="Local worker processes (default: one per core)."),
    scheduler: Optional[str] = typer.Option(None, help="Existing Dask scheduler, tcp://HOST:PORT "
                                            "(default: $DASK_SCHEDULER_ADDRESS, else a local cluster)."),
    batch_size: Optional[int] = typer.Option(None, min=1, help="Runs per Dask task (default: automatic)."),
    timeseries: bool = typer.Option(False, "--timeseries", help="Also write each run's time series."),
    dashboard: str = typer.Option(DASHBOARD, help="The local cluster's Dask dashboard at [HOST]:PORT (:0 "
                                  "for a free port; another one if taken), its link printed once it answers; "
                                  "'off': none. An external scheduler (--scheduler) serves its own."),
    json: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
    max_runs: int = typer.Option(MAX_RUNS, min=1, help=MAX_RUNS_HELP),
):
    """Run a study; a rerun into the same folder skips the runs already done (resume)."""
    from railbrake.campaign import execute, study as studies
    spec = studies.load(study, max_runs=max_runs)
    folder = out or _default_out(spec)
    bar = Progress(TextColumn(f"[bold]{spec.name}"), BarColumn(), MofNCompleteColumn(),
                   TextColumn("{task.fields[failed]} failed"), TimeElapsedColumn(), TextColumn("ETA"),
                   TimeRemainingColumn(), console=Console(stderr=True), disable=json)
    task = bar.add_task(spec.name, total=None, failed=0)

    def progress(done, total, failed):   # the bar appears once the runs start
        if not bar.live.is_started:
            bar.start()
        bar.update(task, completed=done, total=total, failed=failed)

    try:
        summary = execute.run_study(spec, folder, workers=workers, scheduler=scheduler,
                                    batch_size=batch_size, timeseries=timeseries, progress=progress,
                                    dashboard=_dashboard_address(dashboard),
                                    on_connect=_dashboard_reporter(_dashboard_address(dashboard) is not None))
    finally:
        bar.stop()
    if json:
        print_json(summary.json())
    else:
        typer.echo(f"{summary.runs} runs: {summary.done} done now ({summary.failed} failed), "
                   f"{summary.skipped} already in {summary.dataset}")
    if summary.interrupted:
        typer.echo("interrupted: the dataset holds the finished batches; run again to resume", err=True)
        raise typer.Exit(code=130)


@app.command("plan")
@reports_errors
def plan_command(
    study: str = typer.Argument(..., autocompletion=_common.complete_study, help="Study YAML file or preset study."),
    json: bool = typer.Option(False, "--json", help="Print the runs as JSON."),
    max_runs: int = typer.Option(MAX_RUNS, min=1, help=MAX_RUNS_HELP),
):
    """Check a study and list its runs without running them."""
    from railbrake.campaign import study as studies
    spec = studies.load(study, max_runs=max_runs)   # a design too large is refused here, before plan's imports
    from railbrake.campaign import plan
    runs = plan.plan(spec)
    if json:
        print_json([{"key": r.key, "point": r.point, "replicate": r.replicate, "seed": r.seed,
                     "sets": r.sets} for r in runs])
        return
    typer.echo(f"{spec.name}: {len(runs)} runs ({spec.spec.design.kind} design, {len(spec.factors)} factors, "
               f"{spec.spec.seeds} seed{'s' if spec.spec.seeds != 1 else ''})")


@app.command("report")
@reports_errors
def report(
    folder: Path = typer.Argument(..., help="Dataset folder written by 'campaign run'."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="HTML report (default: DIR/report.html)."),
    json: bool = typer.Option(False, "--json", help="Print the assessment as JSON."),
):
    """Self-contained HTML report and Markdown summary of a campaign."""
    from railbrake.campaign import report as reports
    html = output or folder / "report.html"
    result = reports.write(folder, html)
    if json:
        print_json(result)
        return
    typer.echo(f"report: {html}\nsummary: {html.with_suffix('.md')}")


def register(root: typer.Typer) -> None:
    root.add_typer(app, name="campaign")
