"""config.yaml of a run folder: the fully resolved configuration a run used (the scenario, the
whole train file's contents inline, after every --cars and --set), with what it was resolved from
and by which version under `provenance:`. `railbrake run OUT/config.yaml` runs it again from
the folder it is copied to, bit for bit: nothing in it points back to the machine it was written on
(adhesion condition files, a train that is no preset and the profiles and valve designs it names
are copied beside it)."""

from __future__ import annotations

from pathlib import Path

import yaml

from railbrake import atomic
from railbrake.errors import InputError
from railbrake.resolve import PROVENANCE_KEY


def display_name(name: str) -> str:
    """A preset's name as it is; a file's stem, without the folders it lies in on this machine."""
    text = str(name)
    return Path(text).stem if ("/" in text or "\\" in text or text.endswith((".yaml", ".yml"))) else text


def _copy_file(name: str, folder: Path, presets, what: str, written: list) -> str:
    """A file the configuration names copied into folder (its name there, its path added to
    written, for the manifest); a preset name as it is."""
    path = Path(name)
    if name in presets or not path.is_file():
        return name
    target = folder / path.name
    if target.resolve() != path.resolve():
        if target.exists() and target.read_bytes() != path.read_bytes():
            raise InputError(f"{target}: exists with other contents than {what} {path}")
        atomic.write_bytes(target, path.read_bytes())
    written.append(target)
    return path.name


def _copy_condition(name: str, folder: Path, written: list) -> str:
    """An adhesion condition file copied into folder (its name there); a preset name as it is."""
    from railbrake.adhesion import preset_names
    return _copy_file(name, folder, preset_names(), "adhesion condition", written)


def _copy_train_files(train: dict, folder: Path, written: list) -> None:
    """The files the train names (brake step profiles, valve designs) copied into folder."""
    from railbrake.profiles import profile_names
    from railbrake.vehicle import valve_design_names
    for step in (train.get("brake_steps") or {}).values():
        step["profile"] = _copy_file(step["profile"], folder, profile_names(), "deceleration profile",
                                     written)
    for car_type in (train.get("car_types") or {}).values():
        for valve in ("ep_valve", "relay_valve"):
            car_type[valve]["design"] = _copy_file(car_type[valve]["design"], folder, valve_design_names(),
                                                   "valve design", written)


def _train_file(train: dict, folder: Path, written: list) -> str:
    """A train that is no preset written as a train file into folder (its file name there): the
    scenario's checks read the train it names, and the run takes config.yaml's inline copy."""
    from railbrake.vehicle import preset_names
    if train["preset"] in preset_names():
        return train["preset"]
    name = f"{display_name(train.get('name') or train['preset'])}.yaml"
    contents = {k: v for k, v in train.items() if k not in ("preset", "cars")}
    written.append(atomic.write_text(folder / name, yaml.safe_dump(contents, sort_keys=False, allow_unicode=True,
                                                                   width=100)))
    return name


def config_tree(resolved, folder: Path, written: list) -> dict:
    """The resolved tree made portable: the train's contents inline (a train that is no preset also
    as a file beside it), the files it names (profiles, valve designs, adhesion conditions) copied
    into folder; each file written there added to written."""
    tree = resolved.tree()
    _copy_train_files(tree["train"], folder, written)
    tree["train"]["preset"] = _train_file(tree["train"], folder, written)
    adhesion = tree.get("adhesion") or {}
    if adhesion.get("condition"):
        adhesion["condition"] = _copy_condition(adhesion["condition"], folder, written)
    for zone in adhesion.get("zones") or []:
        zone["condition"] = _copy_condition(zone["condition"], folder, written)
    return tree


def write_config(resolved, path: Path) -> list[Path]:
    """config.yaml at path: the portable tree, then `provenance:` (digest, overrides, versions).
    Returns every file written beside it (the copies it names, then config.yaml), for the
    folder's manifest: a rerun from the folder needs each of them."""
    from railbrake.results.provenance import provenance
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    tree = config_tree(resolved, path.parent, written)
    tree[PROVENANCE_KEY] = {"digest": resolved.digest(), "resolved_from": display_name(str(resolved.origin())),
                            "overrides": resolved.override_texts(), **provenance()}
    header = (f"# {resolved.name}: the configuration this run used, resolved (railbrake run {path.name} "
              "runs it again)\n")
    config = atomic.write_text(path, header + yaml.safe_dump(tree, sort_keys=False, allow_unicode=True, width=100))
    return list(dict.fromkeys(written)) + [config]   # a file named twice is listed once
