"""Parameters changed during a run (simulation.run(changes=...)): the native counterpart of the
FMU's tunable parameters and fault inputs set between doSteps. A change at time t acts from the
first plant step after t on, through rb_run_retune (WSP parameters, adhesion) and the faults'
start times, exactly where the FMU applies the same change made before its doStep at t."""

from __future__ import annotations

import ctypes
import math
from dataclasses import dataclass, field

from railbrake._args import show
from railbrake import _core
from railbrake.errors import InputError

WSP_FIELDS = tuple(name for name, _ in _core.WspParams._fields_)
# the integer fields (the controller, switches): a change gives them a whole number
WSP_INTEGERS = frozenset(name for name, kind in _core.WspParams._fields_ if kind is ctypes.c_int)


@dataclass(frozen=True)
class Change:
    """At `time` (s): WSP parameters (rb_wsp_params field -> SI value), the Polach mu0 of the
    adhesion outside the track zones, and scenario faults (0-based) started now unless their own
    start came first."""
    time: float
    wsp: dict = field(default_factory=dict)
    adhesion_mu0: float | None = None
    faults: tuple = ()


def check(changes, max_time: float, n_faults: int, per_bogie: bool = False) -> list[Change]:
    """The changes in time order; a time outside [0, max_time], an unknown WSP field or fault, or a
    non-finite value is refused, naming it; so are a fraction for an integer field and the
    conditioning mode with valves per bogie (per_bogie: the run's)."""
    if not isinstance(changes, (list, tuple)):
        raise TypeError(f"changes = {show(changes)}: must be a list of railbrake.simulation.Change")
    out = []
    for i, c in enumerate(changes):
        if not isinstance(c, Change):
            raise InputError(f"changes[{i}] = {c!r}: must be a railbrake.simulation.Change")
        if not (isinstance(c.time, (int, float)) and 0.0 <= c.time <= max_time):
            raise InputError(f"changes[{i}].time = {c.time!r}: must be a time in [0, {max_time:g}] s")
        for name, value in c.wsp.items():
            if name not in WSP_FIELDS:
                raise InputError(f"changes[{i}].wsp: {name!r} is not a WSP parameter ({', '.join(WSP_FIELDS)})")
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise InputError(f"changes[{i}].wsp[{name!r}] = {value!r}: must be a finite number")
            if name in WSP_INTEGERS and value != int(value):
                raise InputError(f"changes[{i}].wsp[{name!r}] = {value!r}: must be a whole number")
            if name == "conditioning_mode" and value and per_bogie:
                raise InputError(f"changes[{i}].wsp['conditioning_mode'] = {value!r}: the run has valves per "
                                 "bogie (wsp.per_bogie), the conditioning mode needs them per axle")
        if c.adhesion_mu0 is not None and not (isinstance(c.adhesion_mu0, (int, float))
                                               and math.isfinite(c.adhesion_mu0)):
            raise InputError(f"changes[{i}].adhesion_mu0 = {c.adhesion_mu0!r}: must be a finite number")
        for f in c.faults:
            if isinstance(f, bool) or not isinstance(f, int) or not 0 <= f < n_faults:
                raise InputError(f"changes[{i}].faults: {f!r} is not a fault of the scenario (0 to {n_faults - 1})")
        out.append(c)
    return sorted(out, key=lambda c: c.time)


def apply(change: Change, plant: _core.PlantParams, wsp: _core.WspParams, state) -> None:
    """Writes the change into the run's parameters and makes the core take it (rb_run_retune)."""
    for name, value in change.wsp.items():
        setattr(wsp, name, int(value) if name in WSP_INTEGERS else float(value))
    if change.adhesion_mu0 is not None:
        plant.condition[0].polach.mu0 = float(change.adhesion_mu0)
    for f in change.faults:
        plant.fault[f].start_time = min(plant.fault[f].start_time, float(change.time))
    _core.call(_core.rb_run_retune, ctypes.byref(plant), ctypes.byref(wsp), state)
