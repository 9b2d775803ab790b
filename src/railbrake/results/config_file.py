"""config.yaml of a run folder: the fully resolved configuration a run used (the scenario, the
whole train file's contents inline, after every --cars and --set), with what it was resolved from
and by which version under `provenance:`. `railbrake run OUT/config.yaml` runs it again from
the folder it is copied to, bit for bit: nothing in it points back to the machine it was written on
(adhesion condition files, a train that is no preset and the profiles and valve designs it names
are copied beside it)."""

from __future__ import annotations

import shutil
from pathlib import Path

import yaml

from railbrake.errors import InputError
from railbrake.resolve import PROVENANCE_KEY


def display_name(name: str) -> str:
    """A preset's name as it is; a file's stem, without the folders it lies in on this machine."""
    text = str(name)
    return Path(text).stem if ("/" in text or "\\" in text or text.endswith((".yaml", ".yml"))) else text


def _copy_file(name: str, folder: Path, presets, what: str) -> str:
    """A file the configuration names copied into folder (its name there); a preset name as it is."""
    path = Path(name)
    if name in presets or not path.is_file():
        return name
    target = folder / path.name
    if target.resolve() != path.resolve():
        if target.exists() and target.read_bytes() != path.read_bytes():
            raise InputError(f"{target}: exists with other contents than {what} {path}")
        shutil.copyfile(path, target)
    return path.name


def _copy_condition(name: str, folder: Path) -> str:
    """An adhesion condition file copied into folder (its name there); a preset name as it is."""
    from railbrake.adhesion import preset_names
    return _copy_file(name, folder, preset_names(), "adhesion condition")


def _copy_train_files(train: dict, folder: Path) -> None:
    """The files the train names (brake step profiles, valve designs) copied into folder."""
    from railbrake.profiles import profile_names
    from railbrake.vehicle import valve_design_names
    for step in (train.get("brake_steps") or {}).values():
        step["profile"] = _copy_file(step["profile"], folder, profile_names(), "deceleration profile")
    for car_type in (train.get("car_types") or {}).values():
        for valve in ("ep_valve", "relay_valve"):
            car_type[valve]["design"] = _copy_file(car_type[valve]["design"], folder, valve_design_names(),
                                                   "valve design")


def _train_file(train: dict, folder: Path) -> str:
    """A train that is no preset written as a train file into folder (its file name there): the
    scenario's checks read the train it names, and the run takes config.yaml's inline copy."""
    from railbrake.vehicle import preset_names
    if train["preset"] in preset_names():
        return train["preset"]
    name = f"{display_name(train.get('name') or train['preset'])}.yaml"
    contents = {k: v for k, v in train.items() if k not in ("preset", "cars")}
    (folder / name).write_text(yaml.safe_dump(contents, sort_keys=False, allow_unicode=True, width=100))
    return name


def config_tree(resolved, folder: Path) -> dict:
    """The resolved tree made portable: the train's contents inline (a train that is no preset also
    as a file beside it), adhesion condition files copied into folder."""
    tree = resolved.tree()
    _copy_train_files(tree["train"], folder)
    tree["train"]["preset"] = _train_file(tree["train"], folder)
    adhesion = tree.get("adhesion") or {}
    if adhesion.get("condition"):
        adhesion["condition"] = _copy_condition(adhesion["condition"], folder)
    for zone in adhesion.get("zones") or []:
        zone["condition"] = _copy_condition(zone["condition"], folder)
    return tree


def write_config(resolved, path: Path) -> Path:
    """config.yaml at path: the portable tree, then `provenance:` (digest, overrides, versions)."""
    from railbrake.results.provenance import provenance
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tree = config_tree(resolved, path.parent)
    tree[PROVENANCE_KEY] = {"digest": resolved.digest(), "resolved_from": display_name(str(resolved.origin())),
                            "overrides": resolved.override_texts(), **provenance()}
    header = (f"# {resolved.name}: the configuration this run used, resolved (railbrake run {path.name} "
              "runs it again)\n")
    path.write_text(header + yaml.safe_dump(tree, sort_keys=False, allow_unicode=True, width=100))
    return path
