"""Validated, versioned YAML configuration: one loader for every kind of file.

Files are validated with pydantic models (unknown keys forbidden). An error names the file, the
key path, the line in the file, the value found and what is allowed, so the user can go straight
to it. Line numbers come from PyYAML's node marks.
"""

from __future__ import annotations

from pathlib import Path
from typing import TypeVar

import yaml
from pydantic import BaseModel, ValidationError

from railbrake.errors import InputError

Model = TypeVar("Model", bound=BaseModel)


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


def _describe(error: dict) -> str:
    key = ".".join(str(p) for p in error["loc"]) or "(top level)"
    if error["type"] == "extra_forbidden":
        return f"{key}: unknown key"
    if error["type"] == "missing":
        return f"{key}: missing"
    value = error.get("input")
    if isinstance(value, (dict, list)):  # a whole block: the key says enough
        return f"{key}: {error['msg']}"
    return f"{key} = {value!r}: {error['msg']}"


def load_mapping(text: str, origin: str) -> dict:
    """The YAML text as a mapping; InputError names the line of a syntax error."""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f", line {mark.line + 1}" if mark else ""
        raise InputError(f"{origin}{where}: not valid YAML ({getattr(exc, 'problem', exc)})") from None
    if not isinstance(data, dict):
        raise InputError(f"{origin}: expected a mapping of keys at the top level")
    return data


def parse_yaml(text: str, model: type[Model], origin: str) -> Model:
    """Validate YAML text against a pydantic model; InputError names key, value and line."""
    data = load_mapping(text, origin)
    node = yaml.compose(text)
    return validate_data(data, model, locator(origin, _line_index(node)))


def locator(origin: str, lines: dict, overrides: dict | None = None):
    """locate(key path) -> 'file, line N', or the command-line override that set the key."""
    overrides = overrides or {}

    def locate(loc) -> str:
        loc = tuple(loc)
        for end in range(len(loc), 0, -1):
            if loc[:end] in overrides:
                return overrides[loc[:end]]
        line = _line_of(lines, loc) if lines else None
        return f"{origin}{f', line {line}' if line else ''}"

    return locate


def validate_data(data: dict, model: type[Model], locate) -> Model:
    """Validate already-loaded data; ``locate(loc)`` names where a key path came from
    (file and line, or a command-line override) for the error message."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        messages = [f"{locate(tuple(error['loc']))}: {_describe(error)}" for error in exc.errors()]
        raise InputError("\n".join(messages)) from None


def load_yaml(path: str | Path, model: type[Model]) -> Model:
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    return parse_yaml(path.read_text(), model, str(path))
