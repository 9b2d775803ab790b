"""`railbrake demo`: the main job on the built-in default scenario."""

from __future__ import annotations

from pathlib import Path

import typer

from railbrake.cli import adhesion as adhesion_cli


def register(app: typer.Typer) -> None:
    @app.command("demo")
    def demo(out: Path = typer.Option(Path("out"), help="Folder for the plots.")):
        """Heavy-rain creep-force curves on the leading and the fourth car, with plots."""
        out.mkdir(parents=True, exist_ok=True)
        adhesion_cli.list_conditions(json=False)
        for axle in (0, 12):
            adhesion_cli.curves(condition="heavy-rain", speed_kmh="20,60,160,300", axle=axle,
                                plot=out / f"adhesion-heavy-rain-axle{axle}.png", json=False)
