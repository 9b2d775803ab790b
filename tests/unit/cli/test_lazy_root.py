"""`railbrake --help` imports no command module (issue 40: the root's help in under 0.5 s, measured by
bench/bench_cli_start.py): the root lists its commands from railbrake.cli.root.COMMANDS and imports a
command's module only when the command is resolved. The table must say what the commands say."""

import inspect
import json
import pkgutil
import subprocess
import sys

import pytest
from typer.testing import CliRunner

import railbrake.cli
from railbrake.cli import app
from railbrake.cli.root import COMMANDS, load_commands

HEAVY = ("numpy", "scipy", "pandas", "matplotlib", "pyarrow", "pydantic", "yaml", "railbrake._core")


# the command line as `python -m railbrake ARGS` runs it, then the names of the modules it imported
PROBE = """import json, sys
sys.argv = ["railbrake"] + json.loads(sys.argv[1])
from railbrake.cli import main
try:
    main()
except SystemExit as stop:
    sys.stderr.write(f"status {stop.code}\\n")
print(json.dumps(sorted(sys.modules)))
"""


def imported(*args: str, status: int = 0) -> set[str]:
    """The modules the command line imports to answer ARGS (its status must be `status`)."""
    done = subprocess.run([sys.executable, "-c", PROBE, json.dumps(args)], capture_output=True, text=True,
                          timeout=120)
    assert f"status {status}" in done.stderr, done.stderr[-2000:]
    return set(json.loads(done.stdout.splitlines()[-1]))


@pytest.mark.parametrize("args, status", [(["--help"], 0), ([], 2)])   # no command: the help, status 2
def test_the_root_help_imports_no_command_and_no_heavy_library(args, status):
    modules = imported(*args, status=status)
    assert "railbrake.cli.root" in modules     # the report is read right
    assert not {m for m in modules for heavy in HEAVY if m == heavy or m.startswith(heavy + ".")}
    commands = {f"railbrake.cli.{module}" for module, _ in COMMANDS.values()} | {"railbrake.cli._common"}
    assert not modules & commands


def test_a_command_is_imported_when_it_runs_or_shows_its_help():
    assert "railbrake.cli.sizing" in imported("stopping-distance", "--help")
    done = CliRunner().invoke(app, ["stopping-distance", "--v0-kmh", "100", "--deceleration-ms2", "1.0"])
    assert done.exit_code == 0 and " m in " in done.output


def _help_line(command) -> str:
    return " ".join(inspect.cleandoc(command.short_help or command.help or "").split("\n\n")[0].split())


def test_the_table_lists_every_command_with_its_own_help_line():
    registering = {m.name for m in pkgutil.iter_modules(railbrake.cli.__path__) if not m.name.startswith("_")
                   and m.name != "root"}
    assert {module for module, _ in COMMANDS.values()} == registering   # a new command module is listed
    found = {}
    for module in registering:
        found.update(load_commands(module))
    assert set(found) == set(COMMANDS)
    for name, (_, line) in COMMANDS.items():
        assert _help_line(found[name]) == line, name


def test_the_root_help_shows_the_table_and_a_typo_gets_a_suggestion():
    done = CliRunner().invoke(app, ["--help"], terminal_width=200)
    assert done.exit_code == 0
    for name, (_, line) in COMMANDS.items():
        assert f" {name} " in done.output and line[:40] in done.output
    typo = CliRunner().invoke(app, ["stoping-distance"])
    assert typo.exit_code == 2 and "stopping-distance" in typo.output
