"""The ``railbrake`` command line. Each concern registers its commands in its own module."""

from __future__ import annotations

import typer

from railbrake.cli import adhesion, campaign, compare, demo, fmu, hil, simulation, sizing, valve, wsp

app = typer.Typer(
    name="railbrake",
    help="Design and test electro-pneumatic train brakes with wheel-slide protection.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
app.add_typer(adhesion.app, name="adhesion")
app.add_typer(valve.app, name="valve")
campaign.register(app)
compare.register(app)
demo.register(app)
fmu.register(app)
hil.register(app)
simulation.register(app)
sizing.register(app)
wsp.register(app)


def main() -> None:
    app()
