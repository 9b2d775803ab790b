"""`railbrake export-fmu`: the real-time plant as a co-simulation FMU for HIL targets."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from railbrake.cli import _common
from railbrake.cli._common import KERNEL_HELP, SET_HELP, prepare_output, reports_errors
from railbrake.fmu.binaries import DEFAULT_PLATFORMS, PLATFORMS, parse_platforms
from railbrake.fmu.export import BASE_SCENARIO, export_fmu


def register(app: typer.Typer) -> None:
    @app.command("export-fmu")
    @reports_errors
    def export(
        scenario: str = typer.Argument(BASE_SCENARIO, autocompletion=_common.complete_scenario_or_train, help="Scenario (preset or YAML file) or train preset "
                                       f"(then {BASE_SCENARIO} with that train)."),
        fmi: str = typer.Option("2", "--fmi", help="FMI version: 2 or 3."),
        cars: Optional[int] = typer.Option(None, help="Number of cars (default: the scenario's train)."),
        output: Path = typer.Option(Path("plant.fmu"), "-o", "--output", help="The FMU file to write."),
        sets: list[str] = typer.Option([], "--set", help=SET_HELP),
        kernel: Optional[str] = typer.Option(None, help=KERNEL_HELP),
        platforms: str = typer.Option(",".join(DEFAULT_PLATFORMS), "--platforms",
                                      help=f"Binaries to build, comma-separated: {', '.join(PLATFORMS)}."),
        identifier: Optional[str] = typer.Option(None, "--model-identifier",
                                                 help="modelIdentifier (a C identifier); default: "
                                                 "railbrake_<scenario>_<configuration digest>."),
    ):
        """Co-simulation FMU of the plant and BCU (1 ms fixed step) with its C sources and checked
        binaries for the platforms asked for (docs/fmu.md)."""
        path = export_fmu(scenario, prepare_output(output, "--output", (".fmu",)), fmi, cars, sets=sets,
                          kernel=kernel, platforms=parse_platforms(platforms), identifier=identifier)
        typer.echo(f"{path}: FMI {fmi}.0 co-simulation, {platforms}, {path.stat().st_size / 1024:.0f} kB")
        from railbrake.fmu.binaries import host_toolchain_note
        note = host_toolchain_note(path)
        if note:
            typer.echo(f"note: {note}", err=True)
