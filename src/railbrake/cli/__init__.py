"""The ``railbrake`` command line. Each concern registers its commands in its own module."""

from __future__ import annotations

import warnings

import typer

from railbrake.cli import adhesion, campaign, compare, demo, fmu, hil, simulation, sizing, validate, valve, wsp

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
validate.register(app)
wsp.register(app)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings (e.g. an adhesion preset outside its range) as one line, without source lines."""
    typer.echo(f"warning: {message}", err=True)


def main() -> None:
    warnings.showwarning = _show_warning
    app()
