"""`railbrake wsp tune`: WSP parameters optimised over a study's cases (docs/campaigns.md)."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

from railbrake.cli import _common
from railbrake.cli._common import print_json, reports_errors
from railbrake.cli.campaign import MAX_RUNS, MAX_RUNS_HELP

app = typer.Typer(help="Wheel-slide protection: tuning over a study's cases.", no_args_is_help=True)


@app.command("tune")
@reports_errors
def tune(
    study: str = typer.Argument(..., autocompletion=_common.complete_study, help="Study YAML file or preset study with 'assessment' and 'tuning'."),
    params: str = typer.Option(..., help="WSP parameters to tune, e.g. speed_threshold,decel_threshold."),
    objective: str = typer.Option("worst-delta-s", help="worst-delta-s (TPE) or pareto (NSGA-II: dS vs air)."),
    budget: int = typer.Option(24, min=1, help="Evaluations in all (a rerun continues up to this many)."),
    only: List[str] = typer.Option([], "--only", help="Keep the cases at FACTOR=VALUE (repeatable)."),
    controller: Optional[str] = typer.Option(None, help="The WSP controller tuned: its runs of a study that "
                                             "runs several (default: the first of threshold, slip_setpoint, "
                                             "decel_slip_speed that reads every --params)."),
    out: Optional[Path] = typer.Option(None, help="Folder for trials, fragment and plots "
                                       "(default: out/campaigns/<study>/tuning)."),
    workers: Optional[int] = typer.Option(None, min=1, help="Local worker processes (default: one per core)."),
    scheduler: Optional[str] = typer.Option(None, help="Existing Dask scheduler, tcp://HOST:PORT."),
    start: List[Path] = typer.Option([], help="A WSP fragment (wsp-fragment.yaml, e.g. from a tuning on some "
                                     "of the cases) to try right after the default WSP (repeatable)."),
    front: bool = typer.Option(False, "--front", help="Print the Pareto front too (objective pareto)."),
    json: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
    max_runs: int = typer.Option(MAX_RUNS, min=1, help=MAX_RUNS_HELP),
):
    """Optimise WSP parameters: the worst dS % with no lock and the air limit, or a Pareto front."""
    from railbrake.campaign import study as studies
    from railbrake.campaign import tune as tuning
    spec = studies.load(study, max_runs=max_runs)
    folder = out or Path("out") / "campaigns" / spec.name / "tuning"
    air = spec.spec.tuning.air_limit_kg if spec.spec.tuning else None
    bar = Progress(TextColumn(f"[bold]tuning {spec.name}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                   TextColumn("ETA"), TimeRemainingColumn(), console=Console(stderr=True), disable=json)
    task = bar.add_task("tune", total=budget)
    with bar:
        summary = tuning.tune(spec, [p.strip() for p in params.split(",") if p.strip()], objective, budget,
                              folder, workers=workers, scheduler=scheduler, only=only, air_limit=air, start=start,
                              progress=lambda n, total: bar.update(task, completed=n, total=total),
                              controller=controller)
    if json:
        data = {k: summary[k] for k in ("default", "tuned", "evaluations")}
        if front and "front" in summary:
            data["front"] = summary["front"]
        print_json(data)
        return
    d, t = summary["default"], summary["tuned"]
    typer.echo(f"default WSP: worst dS {d['worst_delta_s_pct']:.2f} %, {d['locks']} locks")
    typer.echo(f"tuned WSP:   worst dS {t['worst_delta_s_pct']:.2f} %, {t['locks']} locks; "
               + ", ".join(f"{k} = {v:.4g}" for k, v in t["params"].items()))
    typer.echo(f"{summary['evaluations']} evaluations; fragment {folder / 'wsp-fragment.yaml'}, "
               f"plot {folder / 'convergence.png'}")
    if front and "front" in summary:
        for point in summary["front"]:
            typer.echo(f"  front: dS {point['worst_delta_s_pct']:.2f} %, air {point['air_drawn_kg']:.2f} kg")


def register(root: typer.Typer) -> None:
    root.add_typer(app, name="wsp")
