"""Validated, versioned YAML configuration: one loader for every kind of file.

Files are validated with pydantic models (unknown keys forbidden). An error names the file, the
key path, the line in the file, the value found and what is allowed, so the user can go straight
to it. Line numbers come from PyYAML's node marks.

Before validation the text is checked as a whole, without recursion, so no input can hang the
loader or end in a traceback: it must be UTF-8 (read_text), nest at most MAX_DEPTH levels, use no
anchors or aliases (`&a`, `*a`: an alias bomb of 13 levels expands to 67 million items) and give
no key twice in a mapping (both lines are named), and no .nan or .inf anywhere. Values are validated strictly: a string or a
Boolean is not read as a number (`load_t: "1_000"`, `wheelset_inertia_kgm2: true`). A key whose name
gives its unit (`tare_t`) takes a bare number: `'60 t'` is refused with the number to write
(named_unit_hint; scenario keys take their unit in the value instead).
"""

from __future__ import annotations

import copy
import functools
import math
import os
import re
import stat
from pathlib import Path
from typing import TypeVar

import yaml
from pydantic import BaseModel, ValidationError

from railbrake._args import name_or_path, show
from railbrake.errors import InputError
from railbrake.units import unit_in_name

Model = TypeVar("Model", bound=BaseModel)

MAX_DEPTH = 32          # nesting levels of mappings and sequences (the schemas use at most 5)
MAX_BYTES = 1 << 20     # 1 MiB: no configuration file comes near it
# libyaml's parser where PyYAML has it (about 10 times faster; the same resolver and marks)
_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


_NOT_REGULAR = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def read_bytes(path: str | Path, limit: int = MAX_BYTES) -> bytes:
    """The bytes of a regular file of at most `limit` bytes; InputError (naming the file) for any
    other: a missing or unreadable file, a directory, a FIFO or a device (also behind a symlink,
    e.g. to /dev/zero) is refused at once, without reading (opened non-blocking, so a FIFO with no
    writer cannot hang), and a file is never read beyond the limit."""
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: a directory, not a file") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        kind = next((text for test, text in _NOT_REGULAR if test(mode)), "not a regular file")
        raise InputError(f"{path}: {kind}: a configuration is read from a regular file only")
    with os.fdopen(fd, "rb") as handle:
        try:
            data = handle.read(limit + 1)
        except OSError as exc:
            raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if len(data) > limit:
        raise InputError(f"{path}: over {limit} bytes: a configuration file must be under {limit} bytes")
    return data


def in_folder(name: str, folder: Path | None, presets, where: str = "") -> str:
    """A file name relative to the folder of the file that names it, made absolute: a file names
    other files from where it lies, whatever the current folder (presets, absolute paths, names
    that are no file there, and names in a preset (folder None) stay as they are). where (the
    file, line and key that gave it) names a name no file system takes (too long)."""
    try:
        name_or_path("name", name)
    except InputError as exc:
        raise InputError(f"{where or 'name'}: {str(exc).split(': ', 1)[-1]} (given: {show(name)})") from None
    if folder is None or name in presets or Path(name).is_absolute():
        return name
    candidate = Path(folder) / name
    return str(candidate) if candidate.exists() else name


def read_text(path: str | Path) -> str:
    """A configuration file's text (read_bytes: a regular file under MAX_BYTES); InputError (naming
    the file) if it cannot be read or is not UTF-8."""
    data = read_bytes(path)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise InputError(f"{path}, line {line}: byte 0x{data[exc.start]:02x} is not UTF-8 text "
                         "(save the file as UTF-8)") from None


@functools.lru_cache(maxsize=16)
def compose(text: str):
    """The YAML node tree of `text` (safe tags), cached: a file is composed once for its data
    and once more for its line index. Nodes are never changed by the callers."""
    return yaml.compose(text, Loader=_LOADER)


def line_index(text: str) -> dict:
    """Key path -> line of every value of the YAML text (see _line_index)."""
    node = compose(text)
    return _line_index(node) if node is not None else {}


def _check_events(text: str, origin: str) -> None:
    """Nesting depth, anchors and aliases, from PyYAML's event stream (no recursion)."""
    depth = 0
    for event in yaml.parse(text, Loader=_LOADER):
        line = event.start_mark.line + 1
        if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None):
            raise InputError(f"{origin}, line {line}: YAML anchors and aliases (&name, *name) are not "
                             "supported: write the value out")
        if isinstance(event, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
            depth += 1
            if depth > MAX_DEPTH:
                raise InputError(f"{origin}, line {line}: nested deeper than {MAX_DEPTH} levels")
        elif isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
            depth -= 1


def _check_finite(data, origin: str, index: dict, path=()) -> None:
    """YAML's .nan and .inf are never a meaningful configuration value: refused wherever they appear."""
    if isinstance(data, dict):
        for key, value in data.items():
            _check_finite(value, origin, index, path + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            _check_finite(value, origin, index, path + (i,))
    elif isinstance(data, float) and not math.isfinite(data):
        line = _line_of(index, path)
        key = ".".join(str(p) for p in path)
        raise InputError(f"{origin}{f', line {line}' if line else ''}: {key} = {data}: must be a finite number")


def _key_text(node) -> str:
    return node.value if isinstance(node, yaml.ScalarNode) else f"<{node.tag}>"


def _check_duplicates(node, origin: str, path=()) -> None:
    """A key given twice in one mapping: both lines (YAML says keys are unique; PyYAML keeps the last)."""
    if isinstance(node, yaml.MappingNode):
        seen = {}
        for key_node, value_node in node.value:
            key = _key_text(key_node)
            if key in seen:
                where = ".".join(str(p) for p in path + (key,))
                raise InputError(f"{origin}, line {key_node.start_mark.line + 1}: {where}: key given twice "
                                 f"(first on line {seen[key]})")
            seen[key] = key_node.start_mark.line + 1
            _check_duplicates(value_node, origin, path + (key,))
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            _check_duplicates(item, origin, path + (i,))


def _line_index(node, path=(), index=None) -> dict:
    """Map each key path (tuple of str/int) to the 1-based line of its value node."""
    index = {} if index is None else index
    index[path] = node.start_mark.line + 1
    if isinstance(node, yaml.MappingNode):
        for key_node, value_node in node.value:
            key_path = path + (key_node.value,)
            _line_index(value_node, key_path, index)
            index[key_path + ("<key>",)] = key_node.start_mark.line + 1
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            _line_index(item, path + (i,), index)
    return index


def _line_of(index: dict, location: tuple) -> int | None:
    """Line of the deepest known part of a pydantic error location."""
    location = tuple(location)
    for end in range(len(location), -1, -1):
        prefix = location[:end]
        if prefix + ("<key>",) in index and end == len(location):
            return index[prefix + ("<key>",)]
        if prefix in index:
            return index[prefix]
    return None


def _message(error: dict) -> str:
    """pydantic's message without its "Value error, " / "Assertion failed, " prefix."""
    msg = error["msg"]
    for prefix in ("Value error, ", "Assertion failed, "):
        if msg.startswith(prefix):
            return msg[len(prefix):]
    return msg


def _describe(error: dict) -> str:
    key = ".".join(str(p) for p in error["loc"]) or "(top level)"
    if error["type"] == "extra_forbidden":
        return f"{key}: unknown key"
    if error["type"] == "missing":
        return f"{key}: missing"
    value = error.get("input")
    if isinstance(value, (dict, list)):  # a whole block: the key says enough
        return f"{key}: {_message(error)}"
    if error["type"] in ("float_type", "int_type") and isinstance(value, str) and _yaml_text_number(value):
        number = float(value.replace("_", ""))
        written = f"{number:.1e}" if "e" in value.lower() else f"{number:g}"
        return (f"{key} = {value!r}: text, not a number (YAML 1.1 reads quoted values and exponents "
                f"without a dot, such as 1e29, as strings): write {written}")
    if error["type"] in ("float_type", "int_type") and isinstance(value, str) and _QUANTITY.match(value):
        return f"{key} = {value!r}: {_number_alone(tuple(error['loc']), value)}"
    return f"{key} = {value!r}: {_message(error)}"


# a number followed by a unit, as scenario keys take them ('300 km/h', '60 t', '-2.5e3 kg')
_QUANTITY = re.compile(r"^\s*([-+]?(?:\d[\d_]*\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([^\d\s.+-].*?)\s*$")


def named_unit_hint(key, value) -> str | None:
    """How to write a value given with a unit ('60 t') to a key whose name gives its unit: tare_t,
    a dotted key ending in it, or a key inside one (limit_bar.tare): a bare number in that unit
    (train files name units in their keys; scenario keys take them in their values). None for any
    other key or value."""
    parts = tuple(str(key).split(".")) if isinstance(key, str) else tuple(key)
    if (not isinstance(value, str) or _yaml_text_number(value) or not _QUANTITY.match(value)
            or _named_unit(parts) is None):
        return None
    return _number_alone(parts, value)


def _named_unit(parts: tuple) -> tuple[str, str] | None:
    """(key, unit) of the innermost key of a key path whose name gives a unit."""
    return next(((str(p), unit_in_name(str(p))) for p in reversed(parts) if unit_in_name(str(p))), None)


def _number_alone(parts: tuple, value: str) -> str:
    number, unit = _QUANTITY.match(value).groups()
    named = _named_unit(parts)
    if named is None:
        return f"write the number alone, e.g. {number}"
    name, named_unit = named
    if unit.replace(" ", "") == named_unit.replace(" ", ""):
        return f"the key's name gives the unit ({name}: {named_unit}): write the number alone, {number}"
    return (f"the key's name gives the unit ({name}: {named_unit}): write the number alone, in {named_unit} "
            f"(not {unit})")


def _yaml_text_number(text: str) -> bool:
    """A string that Python would read as a number ('1e29', '1_000'): YAML 1.1 keeps it text."""
    try:
        float(text.replace("_", ""))
    except ValueError:
        return False
    return True


def load_mapping(text: str, origin: str) -> dict:
    """The YAML text as a mapping, checked as above; InputError names the line of a problem."""
    return copy.deepcopy(_checked_mapping(text, origin)[0])


@functools.lru_cache(maxsize=128)
def _checked_mapping(text: str, origin: str) -> tuple[dict, dict]:
    """(mapping, line index) of the YAML text, kept for the next read of the same text: a study
    or a script reads the same train and scenario files run after run. Callers copy the mapping
    before they change it."""
    try:
        _check_events(text, origin)
        node = compose(text)
        _check_duplicates(node, origin)
        data = yaml.SafeLoader("").construct_document(node) if node is not None else None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f", line {mark.line + 1}" if mark else ""
        raise InputError(f"{origin}{where}: not valid YAML ({getattr(exc, 'problem', exc)})") from None
    except RecursionError:   # bounded by MAX_DEPTH above; kept as a last guard
        raise InputError(f"{origin}: nested too deeply") from None
    if not isinstance(data, dict):
        raise InputError(f"{origin}: expected a mapping of keys at the top level")
    lines = _line_index(node)
    _check_finite(data, origin, lines)
    return data, lines


def parse_yaml(text: str, model: type[Model], origin: str) -> Model:
    """Validate YAML text against a pydantic model; InputError names key, value and line."""
    data, lines = _checked_mapping(text, origin)
    return validate_data(data, model, locator(origin, lines))   # validation reads, never writes


def locator(origin: str, lines: dict, overrides: dict | None = None):
    """locate(key path) -> 'file, line N', or the command-line override that set the key."""
    overrides = overrides or {}

    def locate(loc) -> str:
        loc = tuple(loc)
        for end in range(len(loc), 0, -1):
            if loc[:end] in overrides:
                return overrides[loc[:end]]
        line = _line_of(lines, loc) if lines else None
        where = f"{origin}{f', line {line}' if line else ''}"
        inside = [label for key, label in overrides.items() if loc and key[:len(loc)] == loc]
        # an error of a whole block (e.g. axle positions against axles) after an override inside it
        return f"{', '.join(inside)} ({where})" if inside else where

    return locate


def validate_data(data: dict, model: type[Model], locate) -> Model:
    """Validate already-loaded data strictly; ``locate(loc)`` names where a key path came from
    (file and line, or a command-line override) for the error message."""
    try:
        return model.model_validate(data, strict=True)
    except ValidationError as exc:
        messages = [f"{locate(tuple(error['loc']))}: {_describe(error)}" for error in exc.errors()]
        raise InputError("\n".join(messages)) from None


def load_yaml(path: str | Path, model: type[Model]) -> Model:
    return parse_yaml(read_text(path), model, str(path))


# ------------------------------------------------------------------ plausibility bounds

def bound_in(name: str, per: float = 1.0, offset: float = 0.0) -> tuple[float, float, str]:
    """(min, max, why) of the C bound `name` (core/src/bounds.c, SI) in a file's unit, where
    SI = value * per + offset (e.g. per=1e3 for t -> kg, offset=273.15 for degC -> K)."""
    from railbrake import _core
    low, high, _, why = _core.BOUNDS[name]
    return (low - offset) / per, (high - offset) / per, why


def range_text(name: str, unit: str, per: float = 1.0, offset: float = 0.0) -> str:
    """'must lie in [0, 540] km/h (up to 540 km/h)': the bound `name` in the user's unit."""
    low, high, why = bound_in(name, per, offset)
    return f"must lie in [{low:.6g}, {high:.6g}]{f' {unit}' if unit else ''} ({why})"


def within(name: str, value_si: float) -> bool:
    from railbrake import _core
    low, high, _, _ = _core.BOUNDS[name]
    return math.isfinite(value_si) and low <= value_si <= high
