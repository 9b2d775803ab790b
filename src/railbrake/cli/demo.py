"""`railbrake demo`: the main job on the built-in default scenario."""

from __future__ import annotations

from pathlib import Path

import typer

from railbrake.cli import simulation as simulation_cli


def register(app: typer.Typer) -> None:
    @app.command("demo")
    def demo(out: Path = typer.Option(Path("out"), help="Folder for the outputs and plots.")):
        """16-car emergency brake from 300 km/h in heavy rain with WSP: KPIs, time series, plots."""
        result = simulation_cli.run_scenario(simulation_cli.DEFAULT_SCENARIO, None, True, out, quiet=False)
        simulation_cli.print_kpis(result)
        typer.echo(f"outputs: {out}/")
