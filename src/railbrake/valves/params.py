"""Loading valve parameters: packaged YAML defaults, deep-merged with user overrides."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import yaml

from railbrake.errors import InputError

DATA = resources.files("railbrake") / "data" / "valves"


def _merge(base: dict, override: dict, where: str) -> dict:
    merged = dict(base)
    for key, value in override.items():
        if key not in base:
            raise InputError(f"{where}: unknown parameter {key!r}; known: {sorted(base)}")
        merged[key] = _merge(base[key], value, f"{where}.{key}") if isinstance(base[key], dict) else value
    return merged


def load(default_name: str, override=None) -> dict:
    """The default parameters `default_name`.yaml, updated by a dict or a YAML file path."""
    params = yaml.safe_load((DATA / f"{default_name}.yaml").read_text())
    if override is None:
        return params
    if isinstance(override, (str, Path)):
        path = Path(override)
        override = yaml.safe_load(path.read_text()) or {}
        if not isinstance(override, dict):
            raise InputError(f"{path}: must hold a mapping of parameters")
    return _merge(params, override, default_name)
