"""Changes to a loaded configuration (``scenario.with_``, ``train.with_``, ``study.with_``): the
keys and values as ``--set`` takes them (dotted paths, values written as in a file), applied to a
copy of the file's data, which is then validated as a whole again. No law lives here."""

from __future__ import annotations

import difflib
import typing
from typing import ClassVar, Mapping, Sequence, Union

import yaml
from pydantic import BaseModel

from railbrake.errors import InputError, ReadOnlyError

SetsLike = Union[Sequence[str], Mapping[str, object]]


def merge(changes, kwargs: dict, call: str) -> dict:
    """One mapping of dotted key -> value from a positional mapping and keyword arguments."""
    if changes is None:
        changes = {}
    if not isinstance(changes, Mapping):
        raise TypeError(f"{call}: changes = {changes!r}: must be a mapping of dotted keys to values "
                        "(e.g. {'wsp.enabled': False}), or give keyword arguments")
    merged = {}
    for key, value in list(changes.items()) + list(kwargs.items()):
        if not isinstance(key, str) or not key.strip():
            raise TypeError(f"{call}: changes key {key!r}: must be a dotted key such as 'initial_speed'")
        merged[key] = value
    if not merged:
        example = _EXAMPLES.get(call.split(".")[0].lower(), _EXAMPLES["scenario"])
        raise InputError(f"{call}: changes = {{}}: no change given (e.g. {call}({example}))")
    return merged


_EXAMPLES = {"scenario": "initial_speed='300 km/h'", "train": "max_speed_kmh=300", "study": "seeds=4"}


def refuse_assignment(owner: str, name: str) -> None:
    """ReadOnlyError for an assignment to `name` of a loaded scenario, train or study (or a part)."""
    raise ReadOnlyError(f"{owner}: {name} cannot be assigned: a loaded {owner} is read-only (an assignment "
                        f"would skip validation, or be ignored); make a validated copy with {owner}.with_(KEY=VALUE), "
                        f"KEY a dotted key of its file, e.g. {owner}.with_({_EXAMPLES[owner]})")


class ReadOnlyModel:
    """Mixin for the pydantic models of a file schema: an assignment names the way to change them."""

    OWNER: ClassVar[str] = "scenario"

    def __setattr__(self, name, value):
        refuse_assignment(self.OWNER, name)

    def __delattr__(self, name):
        refuse_assignment(self.OWNER, name)


# ------------------------------------------------------------------ --set on a file's data
# (apply_changes: Train.with_, Study.with_; railbrake.resolve for a scenario and its train)

def _set_value(raw: str):
    """A value written as in a file (YAML: '300 km/h', 45, [a, b], {k: v}), as --set reads it."""
    try:
        return yaml.safe_load(raw) if raw.strip() else ""
    except yaml.YAMLError:
        return raw


def _parse_sets(sets: SetsLike, argument: str = "sets") -> list[tuple[tuple, object, str]]:
    """(key path, value, label) per override; a mapping's string values are read as --set reads
    its values (so sets={"k": "[1, 2]"} is the list, as --set k=[1,2]), its other values as they are.
    argument: the caller's name for them, in errors."""
    if isinstance(sets, (str, bytes)) or not isinstance(sets, (Mapping, Sequence, tuple, list)):
        raise TypeError(f"{argument} = {sets!r}: must be a list of 'KEY=VALUE' strings or a mapping of keys to values")
    if isinstance(sets, Mapping):
        for k in sets:
            if not isinstance(k, str) or not k.strip():
                raise TypeError(f"{argument}: key {k!r}: must be a dotted key such as 'initial_speed'")
        items = [(k, _set_value(v) if isinstance(v, str) else v, f"{argument}[{k!r}]")   # the caller's mapping, by its key
                 for k, v in sets.items()]
    else:
        items = []
        for i, text in enumerate(sets):
            if not isinstance(text, str):
                raise TypeError(f"{argument}[{i}] = {text!r}: must be a 'KEY=VALUE' string")
            key, sep, raw = text.partition("=")
            if not sep or not key.strip():
                raise InputError(f"--set {text!r}: expected KEY=VALUE, e.g. --set initial_speed='300 km/h'")
            items.append((key.strip(), _set_value(raw), f"--set {key.strip()}"))
    return [(tuple(int(p) if p.isdigit() else p for p in key.split(".")), value, label)
            for key, value, label in items]


def _assign(tree: dict, path: tuple, value, label: str, known: set,
            listed: str = " (`railbrake config show` lists them)") -> None:
    dotted = ".".join(str(p) for p in path)
    if dotted not in known:
        close = difflib.get_close_matches(dotted, sorted(known), n=3, cutoff=0.5)
        hint = f"; closest valid keys: {', '.join(close)}" if close else ""
        raise InputError(f"{label}: no such key{hint}{listed}")
    node = tree
    for part in path[:-1]:
        if isinstance(node, list) and isinstance(part, int) and part < len(node):
            node = node[part]
        elif isinstance(node, dict):
            node = node.setdefault(part, {})
        else:
            raise InputError(f"{label}: {part!r} is not a key of {dotted}")
    if isinstance(node, list):
        if not (isinstance(path[-1], int) and path[-1] < len(node)):
            raise InputError(f"{label}: index {path[-1]!r} is outside the list")
    current = node[path[-1]] if isinstance(node, list) else node.get(path[-1])
    if isinstance(current, dict) and not isinstance(value, dict):   # a section, not a value
        keys = ", ".join(str(k) for k in list(current)[:4]) + (", ..." if len(current) > 4 else "")
        raise InputError(f"{label} = {value!r}: {dotted} is a section ({keys}); set one of its keys, "
                         f"e.g. --set {dotted}.{next(iter(current), 'KEY')}=VALUE")
    node[path[-1]] = value


def apply_changes(tree: dict, changes: Mapping, model: type[BaseModel], open_sections: tuple = (),
                  argument: str = "changes") -> dict:
    """Each dotted key of `changes` set in `tree` (file data of `model`), as --set does: a key the
    schema does not know is refused, except under `open_sections` (free mappings, e.g. a study's
    factors), where the schema's own validation judges. Returns key path -> label for errors."""
    labels = {}
    for path, value, label in _parse_sets(changes, argument):
        known: set = set()
        _keys_of(model, tree, "", known)
        dotted = ".".join(str(p) for p in path)
        if any(dotted.startswith(f"{section}.") for section in open_sections):
            known.add(dotted)
        _assign(tree, path, value, label, known, listed="")
        labels[path] = label
    return labels


def _unwrap(annotation):
    """The model, dict or list type inside Optional[...] / Annotated[...]."""
    while True:
        origin = typing.get_origin(annotation)
        if origin is typing.Annotated:
            annotation = typing.get_args(annotation)[0]
        elif origin is Union or str(origin) == "types.UnionType":
            args = [a for a in typing.get_args(annotation) if a is not type(None)]
            if len(args) != 1:
                return annotation
            annotation = args[0]
        else:
            return annotation


def _keys_of(model: type[BaseModel], data, prefix: str, out: set) -> None:
    data = data if isinstance(data, dict) else {}
    for name, field in model.model_fields.items():
        key = field.alias or name
        path = f"{prefix}{key}"
        out.add(path)
        kind = _unwrap(field.annotation)
        origin, args = typing.get_origin(kind), typing.get_args(kind)
        sub = data.get(key)
        if isinstance(kind, type) and issubclass(kind, BaseModel):
            _keys_of(kind, sub, f"{path}.", out)
        elif origin is dict and args and isinstance(_unwrap(args[1]), type) \
                and issubclass(_unwrap(args[1]), BaseModel) and isinstance(sub, dict):
            for item_key, item in sub.items():
                out.add(f"{path}.{item_key}")
                _keys_of(_unwrap(args[1]), item, f"{path}.{item_key}.", out)
        elif origin is list and args and isinstance(_unwrap(args[0]), type) \
                and issubclass(_unwrap(args[0]), BaseModel) and isinstance(sub, list):
            for i, item in enumerate(sub):
                out.add(f"{path}.{i}")
                _keys_of(_unwrap(args[0]), item, f"{path}.{i}.", out)
