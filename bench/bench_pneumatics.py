"""Wall time of the EPV characteristic (20 s ramp up and down) and of a 10-volume network over 1 s.

Run: .venv/bin/python bench/bench_pneumatics.py (prints figures; not a test)."""

from __future__ import annotations

import time

from railbrake import valves
from railbrake.pneumatics import Network


def timed(label, function, repeat=5):
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    print(f"{label}: {best * 1e3:.1f} ms (best of {repeat})")
    return result


def ten_volume_chain():
    """Supply -> 10 volumes in a chain through orifices -> atmosphere, with a valve opening at 0.1 s."""
    net = Network()
    net.add_reservoir("supply", 9e5)
    net.add_reservoir("atmosphere", 1.01325e5)
    previous = "supply"
    for i in range(10):
        net.add_volume(f"v{i}", volume=1e-3 * (1 + i % 3), pressure=1.01325e5)
        net.add_orifice(f"o{i}", previous, f"v{i}", area=2e-5, discharge_coefficient=0.8)
        previous = f"v{i}"
    net.add_valve("vent", previous, "atmosphere", area=1e-5, opening=[(0.1, 0), (0.1, 1)], delay=0.02)
    return net.simulate(1.0, n_points=1001)


if __name__ == "__main__":
    c = timed("EPV characteristic, 20 s ramp up and down", lambda: valves.epv_characteristic(ramp_time=20.0))
    print(f"  hysteresis {c.hysteresis_bar:.3f} bar")
    r = timed("10-volume network over 1 s", ten_volume_chain)
    print(f"  {r.steps} steps, {r.rejected} rejected")
    timed("EPV step response over 1 s", lambda: valves.epv_step(current=0.8, t_end=1.0))
    timed("relay valve + cylinder step over 1.5 s", lambda: valves.relay_step())
