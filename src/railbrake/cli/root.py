"""The ``railbrake`` root command: its options (--version, --debug), each concern's commands
registered from its own module, and main() with warnings as one line."""

from __future__ import annotations

import warnings
from typing import Optional

import typer
import typer.core

import railbrake
from railbrake.cli import (_common, adhesion, campaign, compare, compare_runs, config, demo, etcs, fmu, hil, plot,
                           report, sequence, simulation, sizing, train, validate, valve, wsp)

app = typer.Typer(
    name="railbrake",
    help="Design and test electro-pneumatic train brakes with wheel-slide protection.",
    no_args_is_help=True,
    add_completion=True,      # --install-completion / --show-completion (bash, zsh, fish, PowerShell)
    pretty_exceptions_enable=False,
)


def _flags_without_type(option_class) -> None:
    """Help shows a plain flag (--json, --no-wsp, --help) without a '<bool>' type column."""
    shown = getattr(option_class, "display_type_rich", None)
    if shown is None or getattr(shown, "_railbrake", False):
        return

    def display_type_rich(self, ctx):
        return None if getattr(self, "is_flag", False) and not getattr(self, "secondary_opts", None) \
            else shown(self, ctx)
    display_type_rich._railbrake = True
    option_class.display_type_rich = display_type_rich


_flags_without_type(typer.core.TyperOption)


def _version(value: bool) -> None:
    if value:
        from railbrake import _core
        typer.echo(f"railbrake {railbrake.__version__} (core {_core.rb_version().decode()}, "
                   f"build {_core.rb_build_hash().decode()[:12]})")
        raise typer.Exit()


@app.callback()
def _root(version: Optional[bool] = typer.Option(None, "--version", callback=_version, is_eager=True,
                                                 help="Print the version and exit."),
          debug: bool = typer.Option(False, "--debug", help="Show the traceback of an error instead of "
                                     "its one-line message.")):
    """Design and test electro-pneumatic train brakes with wheel-slide protection."""
    _common.DEBUG = debug


app.add_typer(adhesion.app, name="adhesion")
app.add_typer(valve.app, name="valve")
app.add_typer(config.app, name="config")
app.add_typer(sequence.app, name="sequence")
app.add_typer(report.app, name="report")
campaign.register(app)
compare.register(app)
compare_runs.register(app)
demo.register(app)
etcs.register(app)
fmu.register(app)
hil.register(app)
plot.register(app)
simulation.register(app)
sizing.register(app)
train.register(app)
validate.register(app)
wsp.register(app)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings (e.g. an adhesion preset outside its range) as one line, without source lines."""
    typer.echo(f"warning: {message}", err=True)


def main() -> None:
    warnings.showwarning = _show_warning
    try:
        app()
    except BrokenPipeError:   # outside a command (help, version): as quiet as inside one
        try:
            _common.quiet_broken_pipe()
        except typer.Exit as stop:
            raise SystemExit(stop.exit_code) from None
