"""Helpers shared by the CLI commands: list parsing, JSON output, error reporting."""

from __future__ import annotations

import functools
import json
import math
import sys
from pathlib import Path

import numpy as np
import typer

from railbrake.errors import InputError


SET_HELP = ("Override a key of the resolved configuration: KEY=VALUE, the value as in a file, e.g. "
            "--set initial_speed='300 km/h' (repeatable; `railbrake config show` lists the keys).")


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


def _jsonable(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")


def print_json(data) -> None:
    sys.stdout.write(json.dumps(data, default=_jsonable, indent=2) + "\n")


def reports_errors(command):
    """Turn InputError (and a missing file) into a one-line message and exit code 2."""

    @functools.wraps(command)
    def wrapper(*args, **kwargs):
        try:
            return command(*args, **kwargs)
        except (InputError, FileNotFoundError) as exc:
            typer.echo(f"error: {exc}", err=True)
            raise typer.Exit(code=2) from None

    return wrapper


def prepare_output(path: Path | None) -> Path | None:
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
    return path
