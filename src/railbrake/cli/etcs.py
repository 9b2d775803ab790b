"""`railbrake etcs braking-model TRAIN`: the ETCS braking model of a train; `railbrake etcs curves`: its
SUBSET-026 braking curves on a track (docs/etcs.md)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from railbrake import atomic
from railbrake.cli import _common
from railbrake.cli._common import prepare_folder, print_json, reports_errors

app = typer.Typer(help="ETCS braking model of a train: A_brake_emergency, T_brake, Kdry_rst, Kwet_rst.",
                  no_args_is_help=True)


@app.command("braking-model")
@reports_errors
def braking_model(
    train: str = typer.Argument(..., autocompletion=_common.complete_train, help="Train preset or train file."),
    reliability: str = typer.Option("hs-emu", help="Reliability file or preset (data/etcs/reliability-*.yaml)."),
    scatter: str = typer.Option("hs-emu", help="Scatter file or preset (data/etcs/scatter-*.yaml); 'none': no scatter."),
    cars: Optional[int] = typer.Option(None, min=1, max=16, help="Number of cars (default: the train's)."),
    speed: Optional[float] = typer.Option(None, min=1.0, max=600.0,
                                          help="Initial speed, km/h (default: the train's maximum)."),
    samples: Optional[int] = typer.Option(None, min=2, max=100_000,
                                          help="Scatter runs of each likely failure state (default: data/etcs/method.yaml)."),
    rare_samples: Optional[int] = typer.Option(None, min=2, max=100_000, help="Scatter runs of each rare state."),
    run_budget: Optional[int] = typer.Option(None, min=0, max=10_000_000,
                                             help="Runs in all (the first runs always run) up to which runs are added "
                                             "until every Kdry_rst bound is at most kdry_bound (default: "
                                             "data/etcs/method.yaml)."),
    seed: int = typer.Option(1, min=0, help="Seed of the Latin-hypercube blocks and the bootstrap."),
    out: Optional[Path] = typer.Option(None, help="Folder for the runs (a rerun resumes), the JSON, the "
                                       "OSRD export and the report (default: out/etcs/<train>)."),
    workers: int = typer.Option(2, min=1, max=64, help="Local worker processes (a local Dask cluster; 1: runs "
                                "in this process)."),
    scheduler: Optional[str] = typer.Option(None, help="Existing Dask scheduler, tcp://HOST:PORT (or "
                                            "DASK_SCHEDULER_ADDRESS), instead of local workers."),
    osrd_level: int = typer.Option(9, min=0, max=9, help="M_NVEBCL of the k_dry exported to OSRD (OSRD's national "
                                   "default: 9)."),
    osrd_layout: str = typer.Option("current", help="OSRD rolling-stock layout: current (signalling systems) or legacy."),
    force_conditions: bool = typer.Option(False, "--force-conditions",
                                          help="Run an adhesion condition outside its validity (recorded in the "
                                          "model's warnings) instead of refusing it."),
    json: bool = typer.Option(False, "--json", help="Print the braking model as JSON."),
):
    """Compute the braking model from whole-train runs over failure states and tolerances."""
    from railbrake import jsonio
    from railbrake.etcs import export, model, osrd, report, service
    settings = {k: v for k, v in (("samples", samples), ("rare_samples", rare_samples), ("run_budget", run_budget))
                if v is not None}
    spec = model.spec(train, reliability, None if scatter == "none" else scatter, cars, speed, seed,
                      force_conditions, **settings)
    folder = prepare_folder(out or Path("out") / "etcs" / Path(train).stem, "--out")
    bar = Progress(TextColumn(f"[bold]etcs {train}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                   console=Console(stderr=True), disable=json)
    task = bar.add_task("runs", total=None)
    with bar:
        m = model.braking_model(spec, folder, workers, scheduler=scheduler,
                                progress=lambda n, total: bar.update(task, completed=n, total=total))
    data = export.to_json(m)
    atomic.write_text(folder / "braking-model.json", jsonio.dumps(data, indent=1))
    train_data = service.service_data(data)
    atomic.write_text(folder / "service-brake.json", jsonio.dumps(train_data, indent=1))
    atomic.write_text(folder / "osrd-etcs-brake-params.json",
                      jsonio.dumps(osrd.document(data, train_data, osrd_level, osrd_layout), indent=1))
    atomic.write_text(folder / "etcs-train-data.json",
                      jsonio.dumps(osrd.train_data(data, train_data, osrd_level), indent=1))
    report.write(m, folder / "report.html")
    if json:
        print_json(data)
        return
    typer.echo(report.table_text(m))
    typer.echo(f"{m.runs} runs; {folder / 'braking-model.json'}, {folder / 'report.html'}")


@app.command("curves")
@reports_errors
def curves(
    train: str = typer.Argument(..., autocompletion=_common.complete_train, help="A braking model: the folder `etcs braking-model` wrote, or its "
                                "braking-model.json; or a train preset or file (its model computed first)."),
    track: str = typer.Option("flat-10km", help="Track file or preset (data/etcs/track-*.yaml)."),
    national: str = typer.Option("default", help="National values file or preset (data/etcs/national-*.yaml)."),
    cars: Optional[int] = typer.Option(None, min=1, max=16, help="A train's number of cars (model computed here)."),
    speed: Optional[float] = typer.Option(None, min=1.0, max=600.0, help="A train's initial speed, km/h (model "
                                          "computed here; default: its maximum)."),
    samples: Optional[int] = typer.Option(None, min=2, max=100_000, help="Scatter runs per likely state (model computed here)."),
    rare_samples: Optional[int] = typer.Option(None, min=2, max=100_000, help="Scatter runs per rare state (model "
                                               "computed here)."),
    run_budget: Optional[int] = typer.Option(None, min=0, max=10_000_000, help="Runs in all up to which runs are added "
                                             "for the Kdry_rst bounds (model computed here; default: "
                                             "data/etcs/method.yaml)."),
    force_conditions: bool = typer.Option(False, "--force-conditions", help="Run an adhesion condition outside its "
                                          "validity, recorded in the model's warnings (model computed here)."),
    workers: int = typer.Option(2, min=1, max=64, help="Local worker processes (model computed here)."),
    scheduler: Optional[str] = typer.Option(None, help="Existing Dask scheduler, tcp://HOST:PORT (model "
                                            "computed here)."),
    out: Optional[Path] = typer.Option(None, help="Folder for curves.json, curves.png and curves.html "
                                       "(default: out/etcs-curves/<train>)."),
    json: bool = typer.Option(False, "--json", help="Print the curves as JSON."),
):
    """The SUBSET-026 braking curves EBD, EBI, SBD, SBI1, SBI2, W, P, I of a train on a track."""
    import json as json_module

    from railbrake import jsonio
    from railbrake.errors import InputError
    from railbrake.etcs import curves as etcs_curves, curves_report, export, model, national as nv, service
    path = Path(train)
    if path.is_dir():
        path = path / "braking-model.json"
    if path.suffix == ".json":
        if not path.is_file():
            raise InputError(f"{path}: no such braking-model JSON")
        data = json_module.loads(path.read_text())
        svc_path = path.with_name("service-brake.json")
        train_data = json_module.loads(svc_path.read_text()) if svc_path.is_file() else service.service_data(data)
    else:
        settings = {k: v for k, v in (("samples", samples), ("rare_samples", rare_samples), ("run_budget", run_budget))
                    if v is not None}
        spec = model.spec(train, cars=cars, initial_speed_kmh=speed, force_conditions=force_conditions, **settings)
        data = json_module.loads(jsonio.dumps(export.to_json(model.braking_model(spec, workers=workers,
                                                                                      scheduler=scheduler))))
        train_data = service.service_data(data)
    result = etcs_curves.compute(data, train_data, nv.load_track(track), nv.load_national(national))
    folder = prepare_folder(out or Path("out") / "etcs-curves" / Path(str(data["train"])).stem, "--out")
    atomic.write_text(folder / "curves.json", jsonio.dumps(result, indent=1))
    curves_report.write(result, folder / "curves.html", folder / "curves.png")
    if json:
        print_json(result)
        return
    for name, points in result["curves"].items():
        typer.echo(f"{name:>5}: from {points[0][1]:.0f} km/h at {points[0][0]:.0f} m to 0 at {points[-1][0]:.0f} m")
    typer.echo(f"{folder / 'curves.json'}, {folder / 'curves.html'}")


def register(root: typer.Typer) -> None:
    root.add_typer(app, name="etcs")
