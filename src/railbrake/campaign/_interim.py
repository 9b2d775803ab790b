"""Stand-in for ``railbrake.resolve`` until it is merged: same interface, scenario keys only.

resolve(scenario, cars=None, sets=()) -> Resolved with .scenario, .cars, .tree() (file units),
.canonical(), .digest() and valid_keys(). Delete this file once railbrake.resolve exists.
"""

from __future__ import annotations

import copy
import hashlib
import json
from pathlib import Path

import yaml
from pydantic import BaseModel

from railbrake import scenario as scenarios
from railbrake.errors import InputError

INTERIM = True


def _file_tree(name: str) -> tuple[dict, str]:
    if name in scenarios.preset_names():
        return yaml.safe_load((scenarios._preset_dir() / f"{name}.yaml").read_text()), f"preset {name}"
    path = Path(name)
    if path.is_file():
        return yaml.safe_load(path.read_text()), str(path)
    raise InputError(f"scenario = {name!r}: not a preset ({', '.join(scenarios.preset_names())}) nor a file")


def _model_keys(model: type[BaseModel], prefix: str = "") -> list[str]:
    keys = []
    for name, field in model.model_fields.items():
        name = field.alias or name
        annotation = field.annotation
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            keys += _model_keys(annotation, f"{prefix}{name}.")
        else:
            keys.append(prefix + name)
    return keys


def valid_keys() -> list[str]:
    return [k for k in _model_keys(scenarios.ScenarioFile) if k != "schema"]


def _value(value):
    return yaml.safe_load(value) if isinstance(value, str) else value


class Resolved:
    def __init__(self, base: str, cars, sets):
        tree, origin = _file_tree(str(base))
        tree = copy.deepcopy(tree)
        items = sets.items() if hasattr(sets, "items") else (s.split("=", 1) for s in sets)
        keys = set(valid_keys())
        for key, value in items:
            if key not in keys:
                close = ", ".join(k for k in keys if k.split(".")[-1] == key.split(".")[-1])
                raise InputError(f"--set {key}: unknown key{f' (closest: {close})' if close else ''}")
            node = tree
            parts = key.split(".")
            for part in parts[:-1]:
                node = node.setdefault(part, {})
            node[parts[-1]] = _value(value)
        if cars is not None:
            tree.setdefault("train", {})["cars"] = cars
        self._tree = tree
        self.scenario = scenarios.parse(yaml.safe_dump(tree, sort_keys=False), origin)
        self.cars = self.scenario.cars()
        self.train = self.scenario.spec.train

    def tree(self) -> dict:
        tree = copy.deepcopy(self._tree)
        tree.setdefault("train", {})["cars"] = self.cars
        return tree

    def canonical(self) -> str:
        return json.dumps(self.tree(), sort_keys=True, separators=(",", ":"))

    def digest(self) -> str:
        return hashlib.sha256(self.canonical().encode()).hexdigest()

    def valid_keys(self) -> list[str]:
        return valid_keys()


def resolve(scenario, cars=None, sets=()) -> Resolved:
    return Resolved(scenario, cars, sets)
