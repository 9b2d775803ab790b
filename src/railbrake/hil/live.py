"""The running loop's live view: the snapshot the C loop writes after each step (a seqlock,
rb_hil_runner_snapshot), read from any thread without ever holding up the loop."""

from __future__ import annotations

import ctypes

from railbrake import _core
from railbrake.results.channel_info import demand_text

READ_TRIES = 1000   # attempts to read between two of the loop's writes (each write takes about 1 us)


class LiveView:
    def __init__(self, state, atmosphere: float):
        self._state, self.atmosphere = state, atmosphere
        self._snapshot = _core.HilSnapshot()

    def read(self) -> dict | None:
        """The latest step as a JSON-ready dict (SI; pressures Pa absolute; the brake demand also as
        its text, channel_info.demand_text), None before the first."""
        s = self._snapshot
        if not _core.rb_hil_runner_snapshot(self._state, ctypes.byref(s), READ_TRIES) or s.n_cars == 0:
            return None
        n, na = s.n_cars, s.n_axles
        return {"step": s.step, "time": s.time, "speed": s.speed, "position": s.position,
                "main_reservoir": s.main_reservoir, "brake_demand": s.brake_demand,
                "brake_demand_text": demand_text(s.brake_demand), "safe": bool(s.safe),
                "counters": {k: getattr(s, k) for k in _core.HIL_SNAPSHOT_COUNTERS},
                "supply": list(s.supply[:n]), "pressure_demand": list(s.pressure_demand[:n]),
                "wheel_speed": list(s.wheel_speed[:na]), "slip": list(s.slip[:na]),
                "cylinder": list(s.cylinder[:na]), "hold": list(s.hold[:na]), "vent": list(s.vent[:na])}
