"""`railbrake train new --from PRESET [--cars N] [--formation A,B,...] [--max-speed KMH]`: a train
file to start from, commented.

The template is the preset's own file (its values, sources and comments) with a new name, and
above each line that sets a number or a choice, a comment with what the schema allows there (the
plausibility bounds of core/src/bounds.c in the key's unit, or the choices), so a user editing it
sees the range before `railbrake run` refuses a value. --cars / --formation give it another
formation of the preset's car types (its compressors placed as in the preset's, its title saying
so), --max-speed another top speed; the result is checked as every train file.
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


def _formation(data: dict, cars: int | None, formation: str | None) -> list[str] | None:
    """--formation (car type names, comma-separated) and/or --cars: the new formation (the preset's
    repeated and cut to --cars when only that is given); None when neither is."""
    if cars is None and formation is None:
        return None
    types = list(data["car_types"])
    if formation is not None:
        chosen = [n.strip() for n in formation.split(",") if n.strip()]
        unknown = [n for n in chosen if n not in types]
        if unknown or not chosen:
            raise InputError(f"--formation {formation!r}: car types of the train file, comma-separated "
                             f"({', '.join(types)})" + (f"; unknown: {', '.join(unknown)}" if unknown else ""))
        if cars is not None and cars != len(chosen):
            raise InputError(f"--cars {cars} and --formation of {len(chosen)} cars disagree")
        return chosen
    if not 1 <= cars <= 64:
        raise InputError(f"--cars {cars}: must lie in [1, 64] (a run takes at most 16 of them)")
    base = list(data["formation"])
    return [base[i % len(base)] for i in range(cars)]


def _compressors(data: dict, n: int) -> list[dict]:
    """The preset's compressors at their places in each repetition of its formation, on the cars
    the new one has; none left: the first one on the last car (as a run cuts a train)."""
    base, items = len(data["formation"]), data["air_supply"]["compressors"]
    placed = [dict(c, car=c["car"] + k * base) for k in range(n // base + 1) for c in items if c["car"] + k * base <= n]
    return placed or [dict(items[0], car=n)]


def _replace_block(lines: list, first: int, last: int, new: list[str]) -> None:
    """Lines first..last (1-based) replaced by new, padded with None so the lines before keep their
    numbers (the compressors, replaced last, may grow)."""
    lines[first - 1:last] = new + [None] * max(0, last - first + 1 - len(new))


def _reshape(text: str, name: str, preset: str, formation: list[str] | None, max_speed: float | None) -> str:
    """The train file's text with another formation (its compressors and title to match) and top speed;
    every other line, comments included, as it was."""
    data = config.load_mapping(text, preset)
    index = config.line_index(text)
    lines: list = text.splitlines()
    if max_speed is not None:
        line = index[("max_speed_kmh",)]
        lines[line - 1] = re.sub(r"^max_speed_kmh:\s*[^#\s]+", f"max_speed_kmh: {max_speed:g}", lines[line - 1])
    if formation is not None:
        motors = sum(data["car_types"][t].get("kind") == "motor" for t in formation)
        title = f"{len(formation)} cars ({motors}M{len(formation) - motors}T) of {preset}'s car types"
        lines[index[("title",)] - 1] = f"title: {name}, {title}"
        rows = [k for k in index if k[:1] == ("formation",)]
        _replace_block(lines, min(index[k] for k in rows), max(index[k] for k in rows),
                       [f"formation: [{', '.join(formation)}]"])
        rows = [k for k in index if k[:2] == ("air_supply", "compressors") and len(k) > 2]
        items = [f"    - {{car: {c['car']}, delivery_kg_s: {c['delivery_kg_s']}}}"
                 for c in _compressors(data, len(formation))]
        first = min(index[k] for k in rows if len(k) > 2 and isinstance(k[2], int))
        last = max(index[k] for k in rows if len(k) > 2 and isinstance(k[2], int))
        _replace_block(lines, first, last, items)
    return "\n".join(line for line in lines if line is not None) + "\n"


def template(preset: str, name: str | None = None, cars: int | None = None, formation: str | None = None,
             max_speed_kmh: float | None = None) -> str:
    """The commented train file of `preset` (a preset name or a train file), renamed to `name`;
    cars, formation (car type names, comma-separated), max_speed_kmh: the new train's, its title
    and compressors made to match (checked as every train file)."""
    text, origin = vehicle.train_file_text(text_arg("preset", preset))
    vehicle.parse_train(text, origin)   # a broken file is no template
    new_formation = _formation(config.load_mapping(text, origin), cars, formation)
    if new_formation is not None or max_speed_kmh is not None:
        text = _reshape(text, name or f"my-{vehicle.load_train(preset).name}", vehicle.load_train(preset).name,
                        new_formation, max_speed_kmh)
        vehicle.parse_train(text, f"the train of --cars/--formation/--max-speed from {preset}")
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
