"""A run's events for its MDF4 recording: (time s, name, comment), what changed and when. The
faults the scenario schedules (fault_on at their start; a scheduled fault stays to the end), from
`run` and `hil` alike; `hil` adds its live fault changes and safe-state changes
(railbrake.hil.mdf.recording_events)."""

from __future__ import annotations


def fault_text(fault) -> str:
    """'vent_stuck_open on car 3, axle 2' (a FaultSpec), as the HIL loop words a fault."""
    where = "" if fault.car is None else f" on car {fault.car}" + ("" if fault.axle is None else f", axle {fault.axle}")
    value = next((f", {k} {getattr(fault, k):g}" for k in ("noise", "leak_area") if getattr(fault, k) is not None), "")
    return f"{fault.type}{where}{value}"


def scheduled_faults(scenario) -> list[tuple[float, str, str]]:
    """fault_on for each fault of the scenario (a Scenario), at its start."""
    spec = getattr(scenario, "spec", scenario)
    return [(float(f.start), "fault_on", f"{fault_text(f)} (scheduled by the scenario)")
            for f in (getattr(spec, "faults", None) or [])]


def run_events(scenario) -> list[tuple[float, str, str]]:
    """The events of a `run` (simulation) recording, in time order."""
    return sorted(scheduled_faults(scenario), key=lambda e: e[0])
