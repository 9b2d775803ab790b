"""`railbrake train new --from PRESET`: a train file to start from, commented.

The template is the preset's own file (its values, sources and comments) with a new name, and
above each line that sets a number or a choice, a comment with what the schema allows there (the
plausibility bounds of core/src/bounds.c in the key's unit, or the choices), so a user editing it
sees the range before `railbrake run` refuses a value.
"""

from __future__ import annotations

import re
from typing import Literal, get_args, get_origin

from railbrake import config, vehicle
from railbrake._args import text as text_arg
from railbrake.errors import InputError

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$")


def _allowed(path: tuple) -> str | None:
    """'[5, 100] t (why)' or 'one of a, b' for the key at `path` of a train file, None if free."""
    ranged = vehicle._range_text(vehicle._TrainFile, {"type": "greater_than_equal", "loc": path})
    if ranged:
        return ranged.removeprefix("must lie in ")
    if path[-1] == "axles":
        return f"{vehicle._core.AXLES_PER_CAR} (the whole-train plant models {vehicle._core.AXLES_PER_CAR} axles per car)"
    info = vehicle._field_info(vehicle._TrainFile, path)
    annotation = vehicle._unwrap(info.annotation) if info is not None else None
    if get_origin(annotation) is Literal:
        return "one of " + ", ".join(str(a) for a in get_args(annotation))
    return None


def _notes(text: str) -> dict[int, list[str]]:
    """Line -> '# key: allowed' comments for the keys set on that line."""
    notes: dict[int, list[str]] = {}
    seen = set()   # a key of list items (ED branches) is explained at its first item only
    for path, line in config.line_index(text).items():
        if not path or path[-1] == "<key>" or not isinstance(path[-1], str):
            continue
        key = tuple(p for p in path if isinstance(p, str))
        allowed = _allowed(path)
        if allowed and key not in seen:
            seen.add(key)
            notes.setdefault(line, []).append(f"# {path[-1]}: {allowed}")
    return notes


def template(preset: str, name: str | None = None) -> str:
    """The commented train file of `preset` (a preset name or a train file), renamed to `name`."""
    text, origin = vehicle.train_file_text(text_arg("preset", preset))
    vehicle.parse_train(text, origin)   # a broken file is no template
    name = f"my-{vehicle.load_train(preset).name}" if name is None else text_arg("name", name)
    if not _NAME.match(name):
        raise InputError(f"--name {name!r}: letters, digits, '.', '_' and '-', up to 64 characters")
    notes = _notes(text)
    name_line = config.line_index(text).get(("name",))
    out = [f"# Train file made by `railbrake train new --from {preset}` (schema {vehicle.SCHEMA}, docs/vehicle.md).",
           "# Comments give what each value may be; a scenario names this file under train: preset.",
           "# Change source: and the assumptions when you change values.", ""]
    for number, line in enumerate(text.splitlines(), start=1):
        indent = line[:len(line) - len(line.lstrip(" -"))].replace("-", " ")
        out += [indent + note for note in notes.get(number, [])]
        if number == name_line:
            line = f"name: {name}"
        out.append(line)
    return "\n".join(out) + "\n"
