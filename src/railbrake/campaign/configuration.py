"""Where a campaign meets the resolved configuration: one run = base scenario + dotted overrides.

Everything goes through ``railbrake.resolve`` (the same resolution as ``--set`` on the command
line), so a campaign run is exactly the run ``railbrake run BASE --set ...`` would do. While that
module is not on this branch yet, ``_interim`` stands in with the same interface.
"""

from __future__ import annotations

import difflib
import importlib
import importlib.util
from typing import Any, Mapping

if importlib.util.find_spec("railbrake.resolve") is not None:
    _resolution = importlib.import_module("railbrake.resolve")
else:  # the coordinator's railbrake.resolve is not merged yet
    from railbrake.campaign import _interim as _resolution


def resolve(base: str, sets: Mapping[str, Any] | None = None, cars: int | None = None):
    """The resolved configuration of `base` with `sets` ({dotted.key: value in file units})."""
    return _resolution.resolve(base, cars=cars, sets=dict(sets or {}))


def valid_keys(resolved) -> list[str]:
    keys = getattr(resolved, "valid_keys", None) or getattr(_resolution, "valid_keys")
    return sorted(keys())


def closest_keys(key: str, keys: list[str], n: int = 3) -> list[str]:
    """The valid keys nearest to a misspelt one: by spelling, then those sharing its last part."""
    close = difflib.get_close_matches(key, keys, n=n, cutoff=0.5)
    tail = key.rsplit(".", 1)[-1]
    close += [k for k in keys if k.rsplit(".", 1)[-1] == tail and k not in close]
    return close[:n]


def tree(resolved) -> dict:
    return resolved.tree()


def run(resolved, record: bool):
    """Simulate one resolved configuration (in the C core) and return the Result."""
    from railbrake import simulation
    if getattr(_resolution, "INTERIM", False):
        return simulation.run(resolved.scenario, cars=resolved.cars, record=record)
    return simulation.run(resolved, record=record)
