"""Comparing saved runs (MIL, HIL, FMU, two designs, WSP on/off): the KPIs side by side with their
differences from the first run, and the largest differences of the common channels sampled at the
first run's times (within the time both cover)."""

from __future__ import annotations

import numbers

import numpy as np

from railbrake.results.record import RunRecord

LABELS = "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
# Channels whose sample differences are reported (when both runs have them).
COMPARED = ("speed", "position", "main_reservoir")
COMPARED_PREFIXES = ("cylinder_", "wheel_speed_", "supply_")


def _number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and value is not None


def kpi_difference(a, b):
    """b - a for numbers; for anything else None if equal, else 'differs'."""
    if _number(a) and _number(b):
        return float(b) - float(a)
    return None if a == b else "differs"


def _channels(a: RunRecord, b: RunRecord) -> list[str]:
    names = [n for n in a.outputs if n in b.outputs and (n in COMPARED or n.startswith(COMPARED_PREFIXES))]
    return names


def channel_differences(a: RunRecord, b: RunRecord) -> dict:
    """{channel: largest |b - a|} (SI) over a's samples inside the time both runs cover; b is
    linearly interpolated unless both share the same times exactly."""
    ta, tb = np.asarray(a.time), np.asarray(b.time)
    same = ta.shape == tb.shape and np.array_equal(ta, tb)
    inside = np.ones_like(ta, dtype=bool) if same else (ta >= tb[0]) & (ta <= tb[-1])
    out = {}
    for name in _channels(a, b):
        xa = np.asarray(a.outputs[name])[inside]
        xb = np.asarray(b.outputs[name]) if same else np.interp(ta[inside], tb, b.outputs[name])
        out[name] = float(np.max(np.abs(xb[inside] - xa) if same else np.abs(xb - xa))) if xa.size else None
    return out


def relative_differences(a: RunRecord, diffs: dict) -> dict:
    """{channel: largest |b - a| / largest |a|} of channel_differences: how far an FMU's or another
    tool's samples are from the run, channel by channel, in one scale."""
    out = {}
    for name, value in diffs.items():
        scale = float(np.max(np.abs(a.outputs[name]))) if len(a.outputs[name]) else 0.0
        out[name] = None if value is None else (value / scale if scale > 0.0 else (0.0 if value == 0.0 else None))
    return out


def _largest_per_unit(diffs: dict, units: dict) -> list[dict]:
    """The largest difference among the channels of each unit (m/s, m, Pa): a pressure in Pa and a
    speed in m/s are not to be ranked against each other."""
    best: dict[str, tuple[str, float]] = {}
    for name, value in diffs.items():
        unit = units.get(name, "")
        if value is not None and (unit not in best or value > best[unit][1]):
            best[unit] = (name, value)
    return [{"unit": u, "channel": n, "difference": v} for u, (n, v) in best.items()]


def compare_runs(records: list[RunRecord], paths: list[str]) -> dict:
    """Each run against the first: KPIs (union of keys, in the first run's order) and channels."""
    labels = [LABELS[i % len(LABELS)] for i in range(len(records))]
    keys = list(dict.fromkeys(k for r in records for k in r.kpis))
    first = records[0]
    kpis = {}
    for key in keys:
        values = [r.kpis.get(key) for r in records]
        kpis[key] = {"values": values, "differences": [kpi_difference(values[0], v) for v in values[1:]]}
    channels = [channel_differences(first, r) for r in records[1:]]
    relative = [relative_differences(first, diffs) for diffs in channels]
    largest = [_largest_per_unit(diffs, first.units) for diffs in channels]
    numeric = [abs(d) for k in kpis.values() for d in k["differences"] if isinstance(d, float)]
    flagged = [d for k in kpis.values() for d in k["differences"] if d == "differs"]
    samples = [v for diffs in channels for v in diffs.values() if v is not None]
    return {"runs": [{"label": lab, "path": p, "title": r.title(), "kind": r.kind}
                     for lab, p, r in zip(labels, paths, records)],
            "kpis": kpis, "channels": channels, "channels_relative": relative, "largest_channel_differences": largest,
            "identical": not flagged and all(d == 0.0 for d in numeric) and all(v == 0.0 for v in samples)}
