"""One resolved configuration: a scenario, its train, and the overrides given on top of them.

files -> :func:`resolve` -> :class:`Resolved` (validated, SI inside) -> C structs -> results.

The resolved tree is the scenario's keys with ``train`` holding the train file's keys plus
``preset`` (the train preset or file) and ``cars``. Any key of that tree, or of the schemas
behind it, can be overridden with ``KEY=VALUE`` (``--set`` on the command line, ``set:`` in a
study): a dotted path, the value written as in a file, e.g. ``initial_speed=300 km/h`` or
``train.car_types.motor.wheelset_inertia_kgm2=140``. An error names the file and line the value
came from, or the override that set it; an unknown key names the closest valid keys.
Relative file names inside a scenario file resolve against the scenario file's folder.
"""

from __future__ import annotations

import copy
import dataclasses
import difflib
import hashlib
import json
import typing
from importlib import resources
from pathlib import Path

from pydantic import BaseModel

from railbrake import _core, config, vehicle
from railbrake._changes import SetsLike, _assign, _keys_of, _parse_sets, _unwrap, apply_changes  # noqa: F401
from railbrake._version import __version__
from railbrake._args import name_or_path, show, whole
from railbrake import scenario as scenarios
from railbrake.errors import InputError

# The key of a run folder's config.yaml that is no part of the configuration (results.config_file
# writes it, _resolve reads past it).
PROVENANCE_KEY = "provenance"
_TRAIN_KEYS = ("preset", "cars")   # the scenario's own keys under `train`; the rest is the train file


@dataclasses.dataclass(frozen=True)
class Resolved:
    """A scenario and its train after every override, validated; ``tree()`` shows it in file units."""

    scenario: scenarios.Scenario
    train: vehicle.Train
    cars: int
    _tree: dict
    _base: object = None          # what it was resolved from, and the overrides applied to it
    _overrides: tuple = ()

    @property
    def name(self) -> str:
        return self.scenario.name

    def tree(self) -> dict:
        return copy.deepcopy(self._tree)

    def canonical(self) -> str:
        """Canonical JSON of the configuration a run uses: the scenario in SI, the train as resolved."""
        body = {"scenario": self.scenario.spec.model_dump(mode="json", by_alias=True, exclude={"train"}),
                "train": {k: v for k, v in self._tree["train"].items() if k != "preset"},
                "cars": self.cars}
        return json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=False)

    def digest(self) -> str:
        """SHA-256 (hex) of the canonical configuration and the railbrake version."""
        return hashlib.sha256(f"{self.canonical()}\nrailbrake {__version__}".encode()).hexdigest()

    def keys(self) -> list[str]:
        return valid_keys(self._tree)

    def with_(self, changes=None, /, **kwargs) -> "Resolved":
        """This configuration with more overrides, e.g. ``with_(initial_speed="300 km/h")`` or
        ``with_({"train.car_types.motor.wheelset_inertia_kgm2": 140})``: as ``--set``."""
        from railbrake import _changes
        return resolve(self, sets=_changes.merge(changes, kwargs, "Resolved.with_"))

    def origin(self) -> str:
        """What it was resolved from: the preset name or file, or the name of a Scenario built in code."""
        base = self._base
        return base.name if isinstance(base, scenarios.Scenario) else str(base or self.name)

    def override_texts(self) -> list[str]:
        """The overrides applied, as KEY=VALUE (--cars as train.cars=N)."""
        return [f"{'.'.join(str(p) for p in path)}={value}" for path, value, _ in self._overrides]


# ------------------------------------------------------------------ reading the files

@dataclasses.dataclass
class _Source:
    data: dict
    origin: str
    lines: dict
    folder: Path | None   # where relative file names in it resolve; None for presets


def _read(text: str, origin: str, folder: Path | None) -> _Source:
    data = config.load_mapping(text, origin)
    return _Source(data, origin, config.line_index(text), folder)


def _from_spec(scenario: scenarios.Scenario, cars: int | None, sets: SetsLike) -> Resolved:
    """A Scenario built in code (no file behind it): taken as it is, its train from its preset."""
    if sets:
        raise InputError(f"scenario {scenario.name}: built in code, so it takes no overrides; "
                         "pass its preset name or file, or change the Scenario itself")
    n_cars = scenario.cars(cars)
    scenario.check_cars(n_cars)
    train = vehicle.load_train(scenario.spec.train.preset)
    tree = scenario.spec.model_dump(mode="json", by_alias=True)
    tree["train"] = {"preset": scenario.spec.train.preset, "cars": n_cars}
    return Resolved(scenario, train, n_cars, tree)


def _read_scenario(name) -> _Source:
    if isinstance(name, scenarios.Scenario):   # relative file names in it: against its file's folder
        folder = Path(name.origin).resolve().parent if Path(name.origin).is_file() else None
        return _Source(name.data, name.origin, name._lines, folder)
    name = str(name)
    if name in scenarios.preset_names():
        text = (resources.files("railbrake") / "data" / "scenarios" / f"{name}.yaml").read_text()
        return _read(text, f"preset {name}", None)
    path = Path(name)
    if path.is_file():
        return _read(config.read_text(path), str(path), path.resolve().parent)
    raise InputError(f"scenario = {name!r}: not a preset ({', '.join(scenarios.preset_names())}) nor a file")


_in_folder = config.in_folder   # a file name relative to the scenario's folder made absolute

def _read_train(preset: str) -> _Source:
    if preset in vehicle.preset_names():
        text = (resources.files("railbrake") / "data" / "trains" / f"{preset}.yaml").read_text()
        return _read(text, f"train {preset}", None)
    path = Path(preset)
    if path.suffix in (".yaml", ".yml") and path.is_file():
        return _read(config.read_text(path), str(path), path.resolve().parent)
    raise InputError(f"train.preset = {show(preset)}: not a preset ({', '.join(vehicle.preset_names())}) nor a YAML file")


def choices(key: str) -> tuple | None:
    """The values a dotted key may take when its schema lists them (a Literal, e.g.
    wsp.controller), else None."""
    model, parts = (vehicle._TrainFile, key.split(".")[1:]) if key.startswith("train.") else \
        (scenarios.ScenarioFile, key.split("."))
    for i, part in enumerate(parts):
        field = next((f for n, f in model.model_fields.items() if (f.alias or n) == part), None)
        if field is None:
            return None
        kind = _unwrap(field.annotation)
        if i == len(parts) - 1:
            return typing.get_args(kind) if typing.get_origin(kind) is typing.Literal else None
        if not (isinstance(kind, type) and issubclass(kind, BaseModel)):
            return None
        model = kind
    return None


def valid_keys(tree: dict) -> list[str]:
    """Every dotted key a resolved tree may hold (those of the schemas and of the tree itself)."""
    known: set = set()
    _keys_of(scenarios.ScenarioFile, tree, "", known)
    _keys_of(vehicle._TrainFile, tree.get("train", {}), "train.", known)
    return sorted(known)


# ------------------------------------------------------------------ resolving

def resolve(scenario="emergency-300-heavy-rain", cars: int | None = None, sets: SetsLike = ()) -> Resolved:
    """The scenario (preset, file or Scenario), its train and the overrides, validated together.

    cars: the number of cars (as ``--set train.cars=N``); sets: ``KEY=VALUE`` strings or a mapping."""
    overrides = _parse_sets(sets)
    if cars is not None:
        overrides.append((("train", "cars"), whole("cars", cars, 1, _core.PLANT_MAX_CARS), "--cars"))
    if not isinstance(scenario, (Resolved, scenarios.Scenario)):
        name_or_path("scenario", scenario)
    if isinstance(scenario, Resolved):   # more overrides on top of those it has
        if not overrides:
            return scenario
        if scenario._base is None:
            raise InputError(f"scenario {scenario.name}: built in code, so it takes no overrides")
        return _resolve(scenario._base, list(scenario._overrides) + overrides)
    if isinstance(scenario, scenarios.Scenario) and not scenario.data:
        return _from_spec(scenario, cars, sets)
    return _resolve(scenario, overrides)


def _inline_train(source: _Source) -> _Source | None:
    """The train written out inside the scenario (a run folder's config.yaml: `train:` holds the
    train file's keys beside preset and cars), or None when `train:` only names one."""
    block = source.data.get("train")
    if not (isinstance(block, dict) and "schema" in block):
        return None
    data = {k: v for k, v in block.items() if k not in _TRAIN_KEYS}
    lines = {path[1:]: line for path, line in source.lines.items() if path[:1] == ("train",)}
    return _Source(data, source.origin, lines, source.folder)


def _resolve(scenario, overrides: list) -> Resolved:
    source = _read_scenario(scenario)
    source.data.pop(PROVENANCE_KEY, None)   # a run folder's config.yaml: what it was resolved from
    tree = copy.deepcopy(source.data)
    train_block = tree.setdefault("train", {})
    locate = config.locator(source.origin, source.lines)
    if not isinstance(train_block, dict):
        raise InputError(f"{locate(('train',))}: train = {show(train_block)}: must be a mapping (preset, cars, "
                         "load_case), e.g. train: {preset: crh380a-8}")
    inline = _inline_train(source)   # a run folder's config.yaml: the train file written out in it
    if inline is None:
        _check_train_keys(train_block, source)
    adhesion = tree.get("adhesion")
    if isinstance(adhesion, dict):   # relative adhesion files: against the scenario's folder
        from railbrake.adhesion import preset_names as adhesion_presets
        names = adhesion_presets()
        if isinstance(adhesion.get("condition"), str):
            adhesion["condition"] = _in_folder(adhesion["condition"], source.folder, names,
                                               f"{locate(('adhesion', 'condition'))}: adhesion.condition")
        for i, zone in enumerate(adhesion.get("zones") or []):
            if isinstance(zone, dict) and isinstance(zone.get("condition"), str):
                zone["condition"] = _in_folder(zone["condition"], source.folder, names,
                                               f"{locate(('adhesion', 'zones', i, 'condition'))}: "
                                               f"adhesion.zones.{i}.condition")
    preset = train_block.get("preset", scenarios.Train.model_fields["preset"].default)
    preset = _in_folder(str(preset), source.folder, vehicle.preset_names(),
                        f"{locate(('train', 'preset'))}: train.preset")
    labels = {}
    for path, value, label in overrides:   # the train preset first: it says which file the train is
        if path == ("train", "preset"):
            preset, labels[path] = str(value), label
    train_source = inline if inline is not None and ("train", "preset") not in labels else _read_train(preset)
    vehicle.anchor_files(train_source.data, train_source.folder)   # its profiles, valve designs: beside it
    train_block.clear()
    train_block.update({"preset": preset, "cars": source.data["train"].get("cars")
                        if isinstance(source.data.get("train"), dict) else None})
    train_block.update(copy.deepcopy(train_source.data))
    chosen = source.data.get("train") if isinstance(source.data.get("train"), dict) else {}
    if chosen.get("load_case") is not None:   # the scenario chooses the train's load case
        train_block["load_case"] = chosen["load_case"]
    known = None   # the tree's valid keys, found again only after a value that brings keys of its own
    for path, value, label in overrides:
        if path == ("train", "preset"):
            continue
        known = set(valid_keys(tree)) if known is None else known
        _assign(tree, path, value, label, known)
        known = None if isinstance(value, (dict, list)) else known
        labels[path] = label
    if train_block["cars"] is None:
        train_block["cars"] = len(train_block.get("formation") or []) or None
        _check_formation(train_block["cars"], train_source, labels)
    resolved = _validate(tree, source, train_source, labels)
    return dataclasses.replace(resolved, _base=scenario, _overrides=tuple(overrides))


def _check_train_keys(block: dict, source: _Source) -> None:
    """A scenario's train: takes preset, cars and load_case; any other key would be dropped (the
    train file gives the rest): refused with its line."""
    allowed = tuple(scenarios.Train.model_fields)
    for key in block:
        if key not in allowed:
            line = source.lines.get(("train", key, "<key>")) or source.lines.get(("train", key))
            close = difflib.get_close_matches(str(key), allowed, n=1, cutoff=0.6)
            hint = f"did you mean {close[0]}? " if close else ""
            raise InputError(f"{source.origin}{f', line {line}' if line else ''}: train.{key}: unknown key: {hint}"
                             f"a scenario's train: takes {', '.join(allowed)}; a key of the train file itself "
                             f"goes in the train file, or --set train.{key}=VALUE")


def _check_formation(n_cars, train_source: _Source, labels: dict) -> None:
    """A formation longer than the plant runs, taken whole: the train file's line, not the scenario's."""
    from railbrake import _core
    if isinstance(n_cars, int) and n_cars > _core.PLANT_MAX_CARS:
        where = labels.get(("train", "formation")) or \
            config.locator(train_source.origin, train_source.lines)(("formation",))
        raise InputError(f"{where}: formation has {n_cars} cars: a run simulates 1 to {_core.PLANT_MAX_CARS} "
                         "cars; set train.cars in the scenario (or --cars) to run part of it")


def _validate(tree: dict, source: _Source, train_source: _Source, labels: dict) -> Resolved:
    scenario_data = {k: v for k, v in tree.items() if k != "train"}
    scenario_data["train"] = {k: tree["train"][k] for k in _TRAIN_KEYS + ("load_case",)
                              if tree["train"].get(k) is not None}   # load_case: the one in effect
    spec = scenarios.from_data(scenario_data, source.origin, source.lines, labels)
    train_data = {k: v for k, v in tree["train"].items() if k not in _TRAIN_KEYS}
    train_labels = {k[1:]: v for k, v in labels.items() if k[:1] == ("train",)}
    train = vehicle.parse_train_data(train_data, train_source.origin, train_source.lines, overrides=train_labels)
    spec.check_speed(train)   # the train as overridden, not only its file
    spec.check_faults_on(train)
    return Resolved(spec, train, spec.cars(), tree)
