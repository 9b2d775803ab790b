"""Changes to a loaded configuration (``scenario.with_``, ``train.with_``, ``study.with_``): the
keys and values as ``--set`` takes them (dotted paths, values written as in a file), applied to a
copy of the file's data, which is then validated as a whole again. No law lives here."""

from __future__ import annotations

from typing import ClassVar, Mapping

from railbrake.errors import InputError, ReadOnlyError


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
