"""The paced HIL loop with and without the dashboard streaming to two pages: the loop's work per
step (wake-up to the end of the step's work) and its overruns (docs/hil.md, live dashboard).

Each "page" is a thread polling /api/snapshot every 100 ms as dashboard.js does (the HTTP server
threads run in the plant's process, as with a browser). Runs of SECONDS each (default 20), 8 cars,
no BCU (the safe state: the same loop with nothing to wait for but the clock), normal scheduling
priority unless --priority is given.

    python bench/bench_dashboard.py [SECONDS] [--priority N]
"""

import json
import os
import sys
import threading
import urllib.request

from railbrake import hil
from railbrake.hil.dashboard import Dashboard

POLL_S = 0.1
PAGES = 2


def run(seconds: float, priority: int, board: Dashboard | None):
    stop = threading.Event()
    polls = []

    def page():
        url = f"http://{board.host}:{board.port}/api/snapshot?token={board.token}"
        while not stop.wait(POLL_S):
            with urllib.request.urlopen(url, timeout=10) as r:
                polls.append(json.loads(r.read())["snapshot"] is not None)

    pages = [threading.Thread(target=page) for _ in range(PAGES if board else 0)]
    for p in pages:
        p.start()
    try:
        result = hil.run("emergency-300-heavy-rain", ("127.0.0.1", 9), cars=8, duration=seconds, priority=priority,
                         key=bytes(16), on_live=(lambda view: board.attach(view=view)) if board else None)
    finally:
        stop.set()
        for p in pages:
            p.join()
    return result, polls


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    seconds = float(args[0]) if args else 20.0
    priority = int(sys.argv[sys.argv.index("--priority") + 1]) if "--priority" in sys.argv else 0
    print(f"paced {seconds:g} s, 8 cars, no BCU, priority {priority}; load average {os.getloadavg()[0]:.2f} on "
          f"{os.cpu_count()} cores")
    for label in ("without dashboard", f"dashboard, {PAGES} pages polling every {POLL_S:g} s"):
        board = Dashboard(cars=8) if "pages" in label else None
        result, polls = run(seconds, priority, board)
        if board:
            board.close()
        t, c = result.timing, result.counters
        print(f"  {label}: work per step mean {t['work_mean_us']:.1f} us, p99 {t['work_p99_us']:.0f} us, "
              f"max {t['work_max_us']:.0f} us; overruns {c['overruns']} of {c['steps']} steps; wake-up p99 "
              f"{t['wakeup_p99_us']:.0f} us" + (f"; snapshots served {sum(polls)}" if board else ""))


if __name__ == "__main__":
    main()
