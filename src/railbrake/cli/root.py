"""The ``railbrake`` root command: its options (--version, --debug), each concern's commands
loaded from its own module when first used, and main() with each warning on a line of its own.

The commands are listed in COMMANDS (name -> module of railbrake.cli, the help line the root's
--help shows) so that `railbrake --help`, `railbrake` and completing a command's name import no
command module (numpy, pydantic, the C core: about 2 s): a command's module is imported when the
command runs or its own help is asked for. tests/unit/cli/test_lazy_root.py checks the table
against the commands' own help.
"""

from __future__ import annotations

import importlib
import warnings
from typing import Optional

import typer
import typer.core
import typer.main

import railbrake

# name -> (module of railbrake.cli that registers it, the first paragraph of its help), in the order
# `railbrake --help` lists them: commands, then groups of commands
COMMANDS = {
    "compare-rt": ("compare", "Run the real-time plant and the detailed model; report their differences and the "
                   "real-time plant's step-size study (0.25 to 5 ms)."),
    "compare": ("compare_runs", "Saved runs side by side: KPIs with differences from the first run; MIL, HIL and "
                "FMU alike."),
    "demo": ("demo", "16-car emergency brake from 300 km/h in heavy rain with WSP: KPIs, time series, plots."),
    "export-fmu": ("fmu", "Co-simulation FMU of the plant and BCU (1 ms fixed step) with its C sources and checked "
                   "binaries for the platforms asked for (docs/fmu.md)."),
    "hil": ("hil", "The plant paced at 1 kHz on the wall clock, exchanging frames with a BCU over UDP "
            "(docs/hil.md)."),
    "hil-key": ("hil", "A new random key file for `hil --key` and `bcu --key` (give both the same file)."),
    "bcu": ("hil", "The reference BCU: the simulation's BCU and WSP logic answering plant frames over UDP."),
    "plot": ("plot", "Redraw a saved run's figures (same data, same channels as the run drew them)."),
    "run": ("simulation", "Whole-train brake simulation with WSP (default: 16 cars, emergency from 300 km/h in "
            "heavy rain)."),
    "bench": ("simulation", "What a run costs: a whole run of SCENARIO (BCU, WSP, KPIs, no recording) in CPU us "
              "per simulated ms against its plant alone on the same inputs, and its real-time factor (wall "
              "clock). --plant: the plant's step times alone."),
    "size": ("sizing", "Target brake-cylinder pressure per car type for a deceleration profile (inverse); the "
             "output says which brakes it counts."),
    "stopping-distance": ("sizing", "Stopping distance (EN 14531 manner); with --deceleration-ms2, the hand "
                          "check."),
    "validate": ("validate", "Run the cases: the models against analytic solutions, other codes and "
                 "measurements."),
    "adhesion": ("adhesion", "Wheel-rail adhesion: creep-force curves, conditions, parameter fit."),
    "valve": ("valve", "Valve design models: EP valve and its solenoid, relay valve (pressures in bar gauge)."),
    "config": ("config", "The resolved configuration: every key a run uses, with its units."),
    "sequence": ("sequence", "Test sequences (railbrake.sequence/1): steps, expectations, verdicts "
                 "(docs/sequences.md)."),
    "report": ("report", "Reports computed from a train file."),
    "campaign": ("campaign", "Campaigns: studies of many configurations on a laptop or a Dask cluster."),
    "etcs": ("etcs", "ETCS braking model of a train: A_brake_emergency, T_brake, Kdry_rst, Kwet_rst."),
    "train": ("train", "Train files: a commented template to start from."),
    "wsp": ("wsp", "Wheel-slide protection: tuning over a study's cases."),
}


def load_commands(module_name: str) -> dict:
    """name -> click command of each command a module of railbrake.cli registers: its register(app)
    when it has one, else its Typer app `app` as the group of the name COMMANDS gives it."""
    module = importlib.import_module(f"railbrake.cli.{module_name}")
    holder = typer.Typer()
    if hasattr(module, "register"):
        module.register(holder)
    else:
        holder.add_typer(module.app, name=next(n for n, (m, _) in COMMANDS.items() if m == module_name))
    return dict(typer.main.get_group(holder).commands)


class LazyGroup(typer.core.TyperGroup):
    """The root group: commands listed from COMMANDS, each module imported when one of its
    commands is resolved (to run, to show its help, to complete its arguments). Listing them (the
    root's help, completing a command name) shows COMMANDS' help lines and imports nothing."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.commands = dict.fromkeys(COMMANDS)   # the names, for typer's "did you mean" on a typo
        self._loaded: dict = {}
        self._listing = False

    def list_commands(self, ctx) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx, cmd_name: str):
        if cmd_name not in COMMANDS:
            return None
        module_name, help_line = COMMANDS[cmd_name]
        if self._listing:
            return typer.core.TyperCommand(name=cmd_name, help=help_line)
        if module_name not in self._loaded:
            self._loaded[module_name] = load_commands(module_name)
        return self._loaded[module_name][cmd_name]

    def _listed(self, method, *args):
        self._listing = True
        try:
            return method(*args)
        finally:
            self._listing = False

    def format_help(self, ctx, formatter):
        return self._listed(super().format_help, ctx, formatter)

    def shell_complete(self, ctx, incomplete):
        return self._listed(super().shell_complete, ctx, incomplete)


app = typer.Typer(
    name="railbrake",
    cls=LazyGroup,
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
    from railbrake.cli import _common
    _common.DEBUG = debug


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings (e.g. an adhesion preset outside its range) as one line, without source lines."""
    typer.echo(f"warning: {message}", err=True)


def main() -> None:
    warnings.showwarning = _show_warning
    try:
        app()
    except BrokenPipeError:   # outside a command (help, version): as quiet as inside one
        from railbrake.cli import _common
        try:
            _common.quiet_broken_pipe()
        except typer.Exit as stop:
            raise SystemExit(stop.exit_code) from None
