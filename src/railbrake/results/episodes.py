"""What the plots pick out of a run: lock episodes, each axle's WSP activity, the worst axle and
the window that shows its first WSP cycles. Data analysis of the recorded samples only; the KPIs
themselves come from the C core (the lock definition here is the KPI's, core/include/railbrake/rb_run.h)."""

from __future__ import annotations

import numpy as np

from railbrake.results.record import RunRecord
from railbrake.units import kmh_to_ms

LOCK_SPEED = kmh_to_ms(10.0)   # locks count above 10 km/h (rb_run.h)
LOCK_RATIO = 0.1               # wheel below 10 % of the train speed (rb_run.h)
CYCLES_SHOWN = 4               # complete vent-hold-reapply cycles the automatic window aims at
WINDOW_MIN, WINDOW_MAX = 3.0, 12.0   # s
LEAD = 0.5                     # s shown before the first activity


def _runs(mask: np.ndarray, t: np.ndarray) -> list[tuple[float, float]]:
    """(start, end) times of the runs of True in mask."""
    if not mask.any():
        return []
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return [(float(t[s]), float(t[e])) for s, e in zip(starts, ends)]


def lock_episodes(record: RunRecord, axle: str) -> list[tuple[float, float]]:
    v, w = record.outputs["speed"], record.channel("wheel_speed", axle)
    return _runs((v > LOCK_SPEED) & (w < LOCK_RATIO * v), record.time)


def vent_openings(record: RunRecord, axle: str) -> np.ndarray:
    """Times the vent valve opens (rising edges)."""
    vent = record.channel("vent", axle) > 0.5
    return record.time[1:][vent[1:] & ~vent[:-1]] if len(vent) > 1 else np.zeros(0)


def first_activity(record: RunRecord, axle: str) -> float | None:
    """s: the first sample with the hold or vent valve commanded."""
    active = (record.channel("hold", axle) > 0.5) | (record.channel("vent", axle) > 0.5)
    return float(record.time[np.argmax(active)]) if active.any() else None


def severity(record: RunRecord, axle: str) -> tuple[float, float]:
    """(longest lock in s, largest |slip| above 10 km/h): larger is worse, in this order."""
    locks = lock_episodes(record, axle)
    running = record.outputs["speed"] > LOCK_SPEED
    slip = np.abs(record.channel("slip", axle)[running])
    return (max((e - s for s, e in locks), default=0.0), float(slip.max()) if slip.size else 0.0)


def worst_axle(record: RunRecord) -> str:
    """The axle with the longest lock, or without locks the largest slip. Takes the run's
    worst_axle KPI when it names an axle."""
    named = record.kpis.get("worst_axle")
    if isinstance(named, str) and named in record.axle_names():
        return named
    return max(record.axle_names(), key=lambda a: severity(record, a))


def wsp_window(record: RunRecord, axle: str) -> tuple[float, float]:
    """From just before the axle's first WSP activity to the start of its (CYCLES_SHOWN + 1)-th vent
    opening (so CYCLES_SHOWN complete cycles), within WINDOW_MIN .. WINDOW_MAX s."""
    t = record.time
    start = first_activity(record, axle)
    if start is None:   # no WSP activity: the first seconds of braking
        start = record.braking_start()
    t0 = max(float(t[0]), start - LEAD)
    openings = vent_openings(record, axle)
    openings = openings[openings >= start]
    end = openings[CYCLES_SHOWN] if len(openings) > CYCLES_SHOWN else t0 + WINDOW_MAX
    t1 = min(max(end, t0 + WINDOW_MIN), t0 + WINDOW_MAX, float(t[-1]))
    return t0, t1


def plotted_axles(record: RunRecord, requested: list[str] | None = None) -> list[str]:
    """The worst axle, every faulty axle (of a fault on a whole car: its worst axle) and the requested
    ones, each once."""
    faulty = [max(group, key=lambda a: severity(record, a)) for group in record.faulty_axles()]
    return list(dict.fromkeys([worst_axle(record), *faulty, *(requested or [])]))
