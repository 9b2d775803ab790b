"""Paced-loop latency (issue 6: a 60 s paced run has no overrun): the plant at 1 kHz on the wall
clock against the reference BCU in its own process over UDP loopback, 8 cars. Prints wake-up
latency, step execution time and overruns, what the OS granted (SCHED_FIFO, mlockall) and the load
average, since other jobs on the machine show up in the latencies; then, as a baseline, the same loop
for a third of the time with 1 car and no BCU (nothing to wait for but the clock), so overruns that
both runs show can be put down to the machine. Usage: bench_hil.py [SECONDS]."""

import os
import subprocess
import sys
from pathlib import Path

from railbrake import hil

SCENARIO = "emergency-300-heavy-rain"


def main(duration: float = 60.0) -> None:
    railbrake = str(Path(sys.executable).parent / "railbrake")
    bcu = subprocess.Popen([railbrake, "bcu", SCENARIO, "--cars", "8", "--listen", "udp://127.0.0.1:0",
                            "--idle-timeout", "1"], stdout=subprocess.PIPE, text=True)
    port = int(bcu.stdout.readline().rsplit(":", 1)[1])
    load_before = os.getloadavg()[0]
    r = hil.run(SCENARIO, ("127.0.0.1", port), cars=8, duration=duration)
    bcu.wait(timeout=30)
    t, c = r.timing, r.counters
    rt = r.real_time
    granted = {True: "granted", False: "refused"}
    print(f"hil paced {duration:.0f} s, 8 cars over UDP loopback (SCHED_FIFO {granted[rt.fifo_priority]}, "
          f"mlockall {granted[rt.memory_locked]}; load average {load_before:.2f} -> "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores)")
    print(f"  wake-up latency: p50 {t['wakeup_p50_us']:.0f} us, p99 {t['wakeup_p99_us']:.0f} us, "
          f"max {t['wakeup_max_us']:.0f} us")
    print(f"  step execution: mean {t['work_mean_us']:.1f} us, p99 {t['work_p99_us']:.0f} us, "
          f"max {t['work_max_us']:.0f} us")
    print(f"  overruns: {c['overruns']} of {c['steps']} steps; BCU frames received {c['received']}, "
          f"late {c['late']}, lost {c['lost']}, malformed {c['malformed']}, "
          f"safe-state steps {c['safe_state_steps']}")
    base = hil.run(SCENARIO, ("127.0.0.1", 9), cars=1, duration=duration / 3)   # port 9: discard
    t = base.timing
    print(f"baseline {duration / 3:.0f} s, 1 car, no BCU: wake-up p50 {t['wakeup_p50_us']:.0f} us, "
          f"p99 {t['wakeup_p99_us']:.0f} us, max {t['wakeup_max_us']:.0f} us; "
          f"overruns {t['overruns']} of {base.counters['steps']} steps")


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 60.0)
