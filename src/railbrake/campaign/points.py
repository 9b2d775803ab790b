"""The --set overrides of one design point of a study: its fixed sets, its factors' values, and
the fault and the adhesion zone composed from their parts (campaign.factors.COMPOSITES). Below the
study (which measures one point to price a design too large) and the plan (every point)."""

from __future__ import annotations

from railbrake.campaign.factors import NO_FAULT, quantity
from railbrake.errors import InputError


def _fault(parts: dict) -> dict | None:
    if parts.get("type", NO_FAULT) == NO_FAULT:
        return None
    return {k: v for k, v in parts.items()}


def _zone(parts: dict, where: str) -> dict:
    missing = [p for p in ("start", "length", "condition") if p not in parts]
    if missing:
        raise InputError(f"{where}: an adhesion zone needs {', '.join('zone.' + m for m in missing)}")
    start, length = quantity(parts["start"]), quantity(parts["length"])
    if not start or not length or start[2] != "length" or length[2] != "length":
        raise InputError(f"{where}: zone.start = {parts['start']!r}, zone.length = {parts['length']!r}: both must "
                         "be lengths with units, e.g. '1500 m'")
    end = start[0] + length[0]
    scale = quantity(f"1 {start[1]}")[0]
    return {"start": parts["start"], "end": f"{end / scale:.12g} {start[1]}", "condition": parts["condition"]}


def point_sets(study, values: dict, base_tree: dict) -> dict:
    """The --set overrides of one design point of `study` (campaign.study.Study): fixed sets, factor
    values, one fault, one zone."""
    sets = dict(study.fixed)
    parts = {"fault": {}, "zone": {}}
    items = list(study.fixed_parts.items())
    for name, value in values.items():
        if isinstance(value, dict):   # a named case sets several keys
            items += [(k, v) for k, v in value.items() if k != "name"]
        else:
            items.append((name, value))
    for key, value in items:
        head, _, part = key.partition(".")
        if head in parts:
            parts[head][part] = value
        else:
            sets[key] = value
    if parts["fault"]:
        fault = _fault(parts["fault"])
        if fault is not None:
            sets["faults"] = list(base_tree.get("faults") or []) + [fault]
    if parts["zone"]:
        zones = list((base_tree.get("adhesion") or {}).get("zones") or [])
        sets["adhesion.zones"] = zones + [_zone(parts["zone"], study.where("factors"))]
    return sets
