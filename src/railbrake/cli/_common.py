"""Helpers shared by the CLI commands: list parsing, JSON output, output paths, and the one error
path: every error exits with status 2 and one line on stderr (`error: ...`), never a traceback,
whatever the input (library errors such as OSError or ValueError included); `railbrake --debug`
shows the traceback instead. A closed stdout (`railbrake ... | head`) ends quietly."""

from __future__ import annotations

import functools
import math
import os
import signal
import sys
from pathlib import Path

import click
import typer

from railbrake import jsonio
from railbrake.errors import InputError

# The plant's wheelset kernel option (railbrake.simulation.kernel_code), shared by run, bench, hil, export-fmu.
KERNEL_HELP = ("Wheelset kernel: auto (the vector one where the CPU has it) or portable "
               "(default: $RAILBRAKE_KERNEL, else auto).")


SET_HELP = ("Override a key of the resolved configuration: KEY=VALUE, the value as in a file, e.g. "
            "--set initial_speed='300 km/h' (repeatable; `railbrake config show` lists the keys).")


def _presets_then_files(presets: list[str], incomplete: str) -> list[str]:
    """Shell completion of an argument taking a preset name or a YAML file: the presets, then the
    YAML files of the current folder, that start with what is typed."""
    found = [n for n in presets if n.startswith(incomplete)]
    return found + sorted(str(p) for p in Path(".").glob(f"{incomplete}*") if p.suffix in (".yaml", ".yml"))


def complete_scenario(incomplete: str) -> list[str]:
    """A scenario argument: the scenario presets, then YAML files."""
    from railbrake import scenario
    return _presets_then_files(scenario.preset_names(), incomplete)


def complete_train(incomplete: str) -> list[str]:
    """A train argument: the train presets, then YAML files."""
    from railbrake import vehicle
    return _presets_then_files(vehicle.preset_names(), incomplete)


def complete_study(incomplete: str) -> list[str]:
    """A study argument: the study presets, then YAML files."""
    from railbrake.campaign import study
    return _presets_then_files(study.preset_names(), incomplete)


def complete_profile(incomplete: str) -> list[str]:
    """A deceleration profile: the profile presets, then YAML files."""
    from railbrake import profiles
    return _presets_then_files(profiles.profile_names(), incomplete)


def complete_condition(incomplete: str) -> list[str]:
    """An adhesion condition: the condition presets, then YAML files."""
    from railbrake import adhesion
    return _presets_then_files(adhesion.preset_names(), incomplete)


def complete_sequence(incomplete: str) -> list[str]:
    """A test sequence: the shipped sequences, then YAML files."""
    from railbrake.sequence import schema
    return _presets_then_files(schema.presets(), incomplete)


def complete_scenario_or_train(incomplete: str) -> list[str]:
    """As complete_scenario, with the train presets (export-fmu takes a train too)."""
    return sorted(set(complete_scenario(incomplete) + complete_train(incomplete)))


def parse_float_list(text: str, option: str) -> list[float]:
    """'20,60,300' -> [20.0, 60.0, 300.0]; an error names the option and the bad item."""
    values = []
    for item in text.split(","):
        try:
            value = float(item)
        except ValueError:
            raise InputError(f"{option} = {text!r}: {item!r} is not a number") from None
        if not math.isfinite(value):
            raise InputError(f"{option} = {text!r}: {item!r} is not finite")
        values.append(value)
    return values


def print_json(data) -> None:
    """JSON on stdout; NaN and infinities as null (NaN is not JSON)."""
    sys.stdout.write(jsonio.dumps(data, indent=2) + "\n")


DEBUG = False   # set by `railbrake --debug`: errors show their traceback


def _one_line(exc: BaseException) -> str:
    if isinstance(exc, InputError):
        return str(exc)
    if isinstance(exc, OSError) and exc.filename is not None:
        return f"{exc.filename}: {exc.strerror or exc}"
    text = str(exc) or "an unexpected error"
    return f"{text} (unexpected: railbrake --debug shows where)"


BROKEN_PIPE_STATUS = 141   # as a shell reports a command ended by SIGPIPE (128 + 13)


def quiet_broken_pipe() -> None:
    """The reader of stdout went away (`railbrake ... | head`): end quietly, as a Unix tool does.
    stdout is pointed at /dev/null so that the interpreter's last flush cannot fail again."""
    import os
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    raise SystemExit(BROKEN_PIPE_STATUS)


def reports_errors(command):
    """Every error becomes one message on stderr and exit status 2 (Ctrl-C: 130; a closed pipe on
    stdout ends quietly with 141); --debug re-raises."""

    @functools.wraps(command)
    def wrapper(*args, **kwargs):
        try:
            return command(*args, **kwargs)
        except (typer.Exit, typer.Abort, click.exceptions.ClickException):
            raise
        except BrokenPipeError:
            quiet_broken_pipe()
        except KeyboardInterrupt:
            if DEBUG:
                raise
            typer.echo("interrupted", err=True)
            raise typer.Exit(code=130) from None
        except Exception as exc:   # noqa: BLE001 - the one error path: no input may end in a traceback
            if DEBUG:
                raise
            typer.echo(f"error: {_one_line(exc)}", err=True)
            raise typer.Exit(code=2) from None

    return wrapper


def quiet_broken_pipe():
    """The reader of stdout went away (`railbrake ... | head`): stop quietly, as a tool killed by
    SIGPIPE does (status 141), without 'Broken pipe' when Python flushes stdout at exit."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    raise typer.Exit(code=128 + signal.SIGPIPE)


def _check_parent(path: Path, option: str) -> None:
    for parent in [path.parent, *path.parent.parents]:
        if parent.exists() and not parent.is_dir():
            raise InputError(f"{option} {path}: {parent} is a file, not a folder")


def prepare_output(path: Path | None, option: str = "output", suffixes: tuple[str, ...] = ()) -> Path | None:
    """The file `path` can be written: its folder exists (created), it is not a folder itself, and
    its suffix is one of `suffixes` (when given), so the file written is the one named."""
    if path is None:
        return None
    if suffixes and path.suffix.lower() not in suffixes:
        raise InputError(f"{option} {path}: the file name must end in {' or '.join(suffixes)}")
    if path.is_dir():
        raise InputError(f"{option} {path}: is a folder; give a file name")
    _check_parent(path, option)
    path.parent.mkdir(parents=True, exist_ok=True)
    return path


def plot_formats() -> tuple[str, ...]:
    """Suffixes matplotlib can write (.png, .pdf, .svg, ...)."""
    from matplotlib.figure import Figure
    return tuple(f".{ext}" for ext in sorted(Figure().canvas.get_supported_filetypes()))


def prepare_plot(path: Path | None) -> Path | None:
    """--plot FILE: a format matplotlib writes, named by the suffix (no silent .png added)."""
    return prepare_output(path, "--plot", plot_formats()) if path is not None else None


def prepare_folder(path: Path | None, option: str = "--out") -> Path | None:
    """A folder for outputs: created; an existing file of that name is an error, not a traceback."""
    if path is None:
        return None
    if path.exists() and not path.is_dir():
        raise InputError(f"{option} {path}: is a file; give a folder")
    _check_parent(path / "x", option)
    path.mkdir(parents=True, exist_ok=True)
    return path
