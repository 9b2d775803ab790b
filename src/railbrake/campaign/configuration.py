"""Where a campaign meets the resolved configuration: one run = base scenario + dotted overrides.

Everything goes through ``railbrake.resolve`` (the same resolution as ``--set`` on the command
line), so a campaign run is exactly the run ``railbrake run BASE --set ...`` would do.
"""

from __future__ import annotations

import difflib
from typing import Any, Mapping

from railbrake import resolve as resolution


def resolve(base: str, sets: Mapping[str, Any] | None = None, cars: int | None = None) -> resolution.Resolved:
    """The resolved configuration of `base` with `sets` ({dotted.key: value in file units})."""
    return resolution.resolve(base, cars=cars, sets=dict(sets or {}))


def valid_keys(resolved: resolution.Resolved) -> list[str]:
    return sorted(resolved.keys())


def closest_keys(key: str, keys: list[str], n: int = 3) -> list[str]:
    """The valid keys nearest to a misspelt one: by spelling, then those sharing its last part."""
    close = difflib.get_close_matches(key, keys, n=n, cutoff=0.5)
    tail = key.rsplit(".", 1)[-1]
    close += [k for k in keys if k.rsplit(".", 1)[-1] == tail and k not in close]
    return close[:n]


def tree(resolved: resolution.Resolved) -> dict:
    return resolved.tree()


def run(resolved: resolution.Resolved, record: bool):
    """Simulate one resolved configuration (in the C core) and return the Result."""
    from railbrake import simulation
    return simulation.run(resolved, record=record)
