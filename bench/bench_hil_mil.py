"""The paced HIL stop against the MIL run (the figure tests/unit/hil/test_loopback.py leaves to a
bench, since it depends on the machine's load): the 8-car heavy-rain stop from 300 km/h paced at
1 kHz against the reference BCU in its own process over UDP loopback (hold time 1 s, as the test),
and the same scenario run in the simulation. Prints both stopping distances, their difference in
per cent, the loop's overruns and late BCU frames and the load average (about 170 s of wall clock).
Usage: bench_hil_mil.py"""

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from railbrake import simulation
from railbrake.hil.keys import write_key

SCENARIO = "emergency-300-heavy-rain"


def main() -> None:
    railbrake = str(Path(sys.executable).parent / "railbrake")
    key = Path(tempfile.mkdtemp(prefix="bench-hil-mil-")) / "hil.key"
    write_key(key)
    mil = simulation.run(SCENARIO, cars=8).kpis["stopping_distance_m"]
    bcu = subprocess.Popen([railbrake, "bcu", SCENARIO, "--cars", "8", "--listen", "udp://127.0.0.1:0",
                            "--idle-timeout", "0.5", "--key", str(key)], stdout=subprocess.PIPE, text=True)
    try:
        address = bcu.stdout.readline().split()[-1]
        load = os.getloadavg()
        out = subprocess.run([railbrake, "hil", SCENARIO, "--cars", "8", "--bcu", address, "--key", str(key),
                              "--hold-time", "1.0", "--json"], capture_output=True, text=True, check=True)
    finally:
        bcu.wait(timeout=60)
    report = json.loads(out.stdout)
    hil, c = report["kpis"]["stopping_distance_m"], report["counters"]
    print(f"paced HIL stop {hil:.1f} m, MIL {mil:.1f} m: {100 * (hil - mil) / mil:+.3f} %")
    print(f"  overruns {c['overruns']} of {c['steps']} steps, late BCU frames {c['late']}, "
          f"safe-state steps {c['safe_state_steps']}; load average before {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")


if __name__ == "__main__":
    main()
