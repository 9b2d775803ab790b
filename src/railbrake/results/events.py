"""A run's events for its MDF4 recording: (time s, name, comment), what changed and when. The
faults the scenario schedules (fault_on at their start; a scheduled fault stays to the end) and
each WSP safety-timer trip (wsp_trip: an axle's recorded wsp_mode becoming inhibited or isolated,
at the first sample that shows it), from `run` and `hil` alike; `hil` adds its live fault changes
and safe-state changes (railbrake.hil.mdf.recording_events)."""

from __future__ import annotations

import re

import numpy as np

from railbrake.results.channel_info import STATES, WSP_TRIPPED
from railbrake.scenario import _UNITS, VALUE_RANGE


def fault_text(fault) -> str:
    """'vent_stuck_open on car 3, axle 2' (a FaultSpec, or a run's meta fault: a mapping), as the HIL
    loop words a fault; a value in the unit its range is given in ('relay_valve_failed on car 1,
    pressure 1.5 bar')."""
    field = fault.get if isinstance(fault, dict) else lambda key: getattr(fault, key, None)
    car, axle = field("car"), field("axle")
    where = "" if car is None else f" on car {car}" + ("" if axle is None else f", axle {axle}")
    value = next((f", {k} {field(k) / _UNITS[unit][1]:g} {unit}" for k, (_, unit) in VALUE_RANGE.items()
                  if field(k) is not None), "")
    return f"{field('type')}{where}{value}"


def scheduled_faults(scenario) -> list[tuple[float, str, str]]:
    """fault_on for each fault of the scenario (a Scenario), at its start."""
    spec = getattr(scenario, "spec", scenario)
    return [(float(f.start), "fault_on", f"{fault_text(f)} (scheduled by the scenario)")
            for f in (getattr(spec, "faults", None) or [])]


def wsp_trips(time, outputs: dict) -> list[tuple[float, str, str]]:
    """wsp_trip for each axle whose wsp_mode channel reaches a tripped state (a recording without
    those channels, as a HIL plant's, whose WSP is the external BCU's: none)."""
    events = []
    for name, values in outputs.items():
        where = re.fullmatch(r"wsp_mode_c(\d+)a(\d+)", name)
        tripped = np.flatnonzero(np.isin(np.asarray(values), WSP_TRIPPED)) if where else []
        if len(tripped):
            mode = int(values[tripped[0]])
            events.append((float(time[tripped[0]]), "wsp_trip",
                           f"car {where.group(1)}, axle {where.group(2)}: {STATES['wsp_mode'][mode]}"))
    return events


def run_events(scenario, record=None) -> list[tuple[float, str, str]]:
    """The events of a `run` (simulation) recording, in time order: the scenario's faults and,
    with its record (a RunRecord), the WSP trips."""
    trips = wsp_trips(record.time, record.outputs) if record is not None else []
    return sorted(scheduled_faults(scenario) + trips, key=lambda e: e[0])
