"""Paced-loop latency (issue 6: a 60 s paced run has no overrun): the plant at 1 kHz on the wall
clock against the reference BCU in its own process over UDP loopback, 8 cars. Prints wake-up
latency, step execution time and overruns, what the OS granted (SCHED_FIFO, mlockall) and the load
average, since other jobs on the machine show up in the latencies; then, as a baseline, the same loop
for a third of the time with 1 car and no BCU (nothing to wait for but the clock), so overruns that
both runs show can be put down to the machine. First, the cost of the frames' SipHash-2-4 tag (ICD v4)
per frame: rb_frame_authentic on the largest plant frame (16 cars), an 8-car plant frame and an
8-car BCU frame, less the cost of a ctypes call that does nothing (rb_crc32 of 0 bytes).
Usage: bench_hil.py [SECONDS]."""

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from railbrake import _core, hil
from railbrake.hil.keys import write_key

SCENARIO = "emergency-300-heavy-rain"


def _per_call_us(call, runs: int = 200_000) -> float:
    """The fastest of 5 rounds of `runs` calls, per call in us."""
    best = float("inf")
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(runs):
            call()
        best = min(best, time.perf_counter() - start)
    return best / runs * 1e6


def mac_cost() -> None:
    """SipHash-2-4's cost per byte from 1 MiB hashed in one call (the ctypes call's own cost spread
    over a million bytes), times each frame's body (header and payload): the tag's cost per frame.
    Hashing is linear in the length but for a fixed initialisation and 4 finalisation rounds
    (a few ns); a whole call from Python, ctypes included, is shown as an upper bound."""
    key = bytes(range(16))
    big = bytes(1 << 20)
    per_byte = _per_call_us(lambda: _core.rb_siphash24(key, big, len(big)), runs=20) / len(big)
    print(f"  SipHash-2-4: {1e-3 / per_byte:.2f} GB/s ({per_byte * 1e3:.2f} ns per byte)")
    for name, size in (("plant frame, 16 cars", _core.rb_plant_frame_size(16, 64)),
                       ("plant frame, 8 cars", _core.rb_plant_frame_size(8, 32)),
                       ("BCU frame, 8 cars", _core.rb_bcu_frame_size(8, 32))):
        body = bytes(size - 12)
        call = _per_call_us(lambda: _core.rb_siphash24(key, body, len(body)))
        print(f"  tag of a {name} ({size} bytes): {per_byte * len(body):.2f} us "
              f"(a whole call from Python, ctypes included: {call:.2f} us)")


def main(duration: float = 60.0) -> None:
    print("frame authentication cost:")
    mac_cost()
    railbrake = str(Path(sys.executable).parent / "railbrake")
    key = Path(tempfile.mkdtemp(prefix="bench-hil-")) / "hil.key"
    write_key(key)
    bcu = subprocess.Popen([railbrake, "bcu", SCENARIO, "--cars", "8", "--listen", "udp://127.0.0.1:0",
                            "--idle-timeout", "1", "--key", str(key)], stdout=subprocess.PIPE, text=True)
    port = int(bcu.stdout.readline().rsplit(":", 1)[1])
    load_before = os.getloadavg()[0]
    r = hil.run(SCENARIO, ("127.0.0.1", port), cars=8, duration=duration, key=key)
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
          f"late {c['late']}, lost {c['lost']}, malformed {c['malformed']}, forged {c['forged']}, "
          f"safe-state steps {c['safe_state_steps']}")
    base = hil.run(SCENARIO, ("127.0.0.1", 9), cars=1, duration=duration / 3, key=key)   # port 9: discard
    t = base.timing
    print(f"baseline {duration / 3:.0f} s, 1 car, no BCU: wake-up p50 {t['wakeup_p50_us']:.0f} us, "
          f"p99 {t['wakeup_p99_us']:.0f} us, max {t['wakeup_max_us']:.0f} us; "
          f"overruns {t['overruns']} of {base.counters['steps']} steps")


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 60.0)
