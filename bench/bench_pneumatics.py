"""Wall time of the EPV characteristic (100 s ramp and its quasi-static check), the solenoid force
table, the reduction to the plant, the `valve epv --characteristic --json` command, and of a
10-volume network over 1 s.

Run: .venv/bin/python bench/bench_pneumatics.py (prints figures; not a test)."""

from __future__ import annotations

import subprocess
import sys
import time

from railbrake import valves
from railbrake.valves import reduce, solenoid
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
    c = timed("EPV characteristic, 100 s ramp + 200 s check", valves.epv_characteristic)
    print(f"  hysteresis {c.hysteresis_bar:.3f} bar, quasi-static {c.quasi_static}")
    timed("solenoid force table (11 x 13)", lambda: solenoid.force_table(solenoid.load_solenoid()))
    f = timed("EPV reduction (8 detailed steps + fit)", reduce.fit_epv, repeat=2)
    print(f"  tau {f['ep_tau'] * 1e3:.1f} ms, RMS {f['rms_bar']:.3f} bar")
    cli = [sys.executable, "-c", "from railbrake.cli import main; main()", "valve", "epv", "--characteristic", "--json"]
    timed("railbrake valve epv --characteristic --json (process)",
          lambda: subprocess.run(cli, check=True, capture_output=True), repeat=3)
    r = timed("10-volume network over 1 s", ten_volume_chain)
    print(f"  {r.steps} steps, {r.rejected} rejected")
    timed("EPV step response over 1 s", lambda: valves.epv_step(current=0.8, t_end=1.0))
    timed("relay valve + cylinder step over 1.5 s", lambda: valves.relay_step())
