"""The paced HIL loop with and without the dashboard streaming to two pages (issue 30): the loop's
work per step (wake-up to the end of the step's work) and its overruns (docs/hil.md, live dashboard).

Each "page" is a process of its own (as a browser's page is) polling /api/snapshot every 100 ms as
dashboard.js does; the HTTP server threads run in the plant's process, as with a browser. Runs of
SECONDS each (default 10), 8 cars, no BCU (the safe state: the same loop with nothing to wait for
but the clock), at the `hil` command's SCHED_FIFO priority (--priority 0: normal scheduling).
A shared virtual machine drifts by more than the 5 % asked for over a minute, so the two cases
alternate (ABBA, --pairs of each) and each is summed over its runs: the work per step is the mean
over all its steps, the overruns their total.

    python bench/bench_dashboard.py [SECONDS] [--pairs N] [--priority N] [--json PATH]

`--json docs/measured/bench_dashboard.json` also writes the figures, with the date and the command,
for docs/hil.md."""

import argparse
import json
import os
import shutil
import subprocess
import sys
from datetime import datetime, timezone
from pathlib import Path

from railbrake import hil
from railbrake.hil.dashboard import Dashboard

POLL_S = 0.1
PAGES = 2
CARS = 8

# a page: polls the snapshot as dashboard.js does and prints how many it got when told to stop
POLLER = """
import json, sys, time, urllib.request
url, poll, served = sys.argv[1], float(sys.argv[2]), 0
print("ready", flush=True)
try:
    while True:
        with urllib.request.urlopen(url, timeout=10) as r:
            served += json.loads(r.read())["snapshot"] is not None
        time.sleep(poll)
except KeyboardInterrupt:
    print(served, flush=True)
"""

# --browser: the pages themselves, in Debian's headless chromium, counting the snapshots they fetch
BROWSER = """
import sys
from playwright.sync_api import sync_playwright
url, pages, chromium = sys.argv[1], int(sys.argv[2]), sys.argv[3]
served = [0]
with sync_playwright() as p:
    browser = p.chromium.launch(executable_path=chromium, headless=True, args=["--no-sandbox"])
    for _ in range(pages):
        page = browser.new_page()
        page.on("response", lambda r: served.__setitem__(0, served[0] + ("/api/snapshot" in r.url)))
        page.goto(url)
    print("ready", flush=True)
    try:
        while True:               # the sync API hands events over only while it is called
            page.wait_for_timeout(100)
    except KeyboardInterrupt:
        print(served[0], flush=True)
    browser.close()
"""


def _open_pages(board: Dashboard, cpu: int | None, browser: str | None) -> list[subprocess.Popen]:
    """The pages' processes, started off the loop's CPU when it has one (their children inherit it)."""
    away = (lambda: os.sched_setaffinity(0, os.sched_getaffinity(0) - {cpu})) if cpu is not None else None
    if browser:
        commands = [[sys.executable, "-c", BROWSER, board.url, str(PAGES), browser]]
    else:
        url = f"http://{board.host}:{board.port}/api/snapshot?token={board.token}"
        commands = [[sys.executable, "-c", POLLER, url, str(POLL_S)]] * PAGES
    pages = [subprocess.Popen(c, stdout=subprocess.PIPE, text=True, preexec_fn=away) for c in commands]
    for p in pages:
        p.stdout.readline()
    return pages


def _close_pages(pages: list[subprocess.Popen]) -> int:
    served = 0
    for p in pages:
        p.send_signal(2)
        out, _ = p.communicate(timeout=30)
        served += int(out.split()[-1])
    return served


def run_once(seconds: float, priority: int, dashboard: bool, cpu: int | None, browser: str | None) -> dict:
    board = Dashboard(cars=CARS) if dashboard else None
    pages = []
    try:
        result = hil.run("emergency-300-heavy-rain", ("127.0.0.1", 9), cars=CARS, duration=seconds, priority=priority,
                         key=bytes(16), cpu=cpu, on_live=(lambda view: (board.attach(view=view), pages.extend(
                             _open_pages(board, cpu, browser)))) if board else None)
    finally:
        served = _close_pages(pages)
        if board:
            board.close()
    t, c = result.timing, result.counters
    return {"steps": c["steps"], "overruns": c["overruns"], "work_mean_us": t["work_mean_us"],
            "work_p99_us": t["work_p99_us"], "work_max_us": t["work_max_us"], "snapshots_served": served,
            "real_time": _granted(result.real_time)}


def _granted(rt: hil.RealTime) -> str:
    if not rt.requested:
        return "normal scheduling"
    return (f"SCHED_FIFO {rt.priority} {'granted' if rt.fifo_priority else 'refused'}, memory "
            f"{'locked' if rt.memory_locked else 'not locked'}")


def summarise(runs: list[dict]) -> dict:
    steps = sum(r["steps"] for r in runs)
    return {"runs": len(runs), "steps": steps, "overruns": sum(r["overruns"] for r in runs),
            "work_mean_us": sum(r["work_mean_us"] * r["steps"] for r in runs) / steps,
            "work_p99_us_worst": max(r["work_p99_us"] for r in runs),
            "work_max_us": max(r["work_max_us"] for r in runs),
            "snapshots_served": sum(r["snapshots_served"] for r in runs)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("seconds", nargs="?", type=float, default=10.0)
    parser.add_argument("--pairs", type=int, default=3, help="runs of each case, alternating ABBA")
    parser.add_argument("--priority", type=int, default=hil.DEFAULT_PRIORITY)
    parser.add_argument("--cpu", type=int, help="the CPU the loop has to itself (hil --cpu; the pages kept off "
                        "it too, as on a bench with an isolated core); default: wherever the OS puts it")
    parser.add_argument("--browser", action="store_true", help="two pages in Debian's headless chromium (driven "
                        "by playwright) instead of two processes polling as they do")
    parser.add_argument("--json", type=Path, help="also write the figures to this file")
    args = parser.parse_args()
    browser = shutil.which("chromium") if args.browser else None
    if args.browser and not browser:
        parser.error("--browser: Debian's chromium is not installed (`make browser`)")
    load = os.getloadavg()[0]
    print(f"paced {args.seconds:g} s per run, {CARS} cars, no BCU, priority {args.priority}, loop's CPU "
          f"{'any' if args.cpu is None else args.cpu}, {PAGES} pages in {'chromium' if browser else 'polling processes'}, "
          f"{args.pairs} runs of each case; load average {load:.2f} on {os.cpu_count()} cores")
    runs = {False: [], True: []}
    for i in range(2 * args.pairs):
        dashboard = (i % 4) in (1, 2)    # A B B A ...
        runs[dashboard].append(run_once(args.seconds, args.priority, dashboard, args.cpu, browser))
        r = runs[dashboard][-1]
        print(f"  {'dashboard' if dashboard else 'plain    '}: work per step mean {r['work_mean_us']:.2f} us, "
              f"p99 {r['work_p99_us']:.0f} us, max {r['work_max_us']:.0f} us; overruns {r['overruns']} of "
              f"{r['steps']}" + (f"; snapshots served {r['snapshots_served']}" if dashboard else ""), flush=True)
    without, with_ = summarise(runs[False]), summarise(runs[True])
    change = with_["work_mean_us"] / without["work_mean_us"] - 1.0
    print(f"work per step: {without['work_mean_us']:.2f} us without, {with_['work_mean_us']:.2f} us with the "
          f"dashboard ({change:+.1%}); overruns {without['overruns']} and {with_['overruns']} of "
          f"{without['steps']} steps each; {runs[False][0]['real_time']}")
    if args.json:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                                cwd=Path(__file__).parent).stdout.strip()
        args.json.write_text(json.dumps({
            "made": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"), "railbrake_commit": commit,
            "command": "python bench/bench_dashboard.py " + " ".join(sys.argv[1:]),
            "cars": CARS, "seconds_per_run": args.seconds, "priority": args.priority, "cpu": args.cpu, "pages": PAGES, "pages_in": "chromium" if browser else "polling processes",
            "poll_s": POLL_S, "load_average_1min": load, "real_time": runs[False][0]["real_time"],
            "without": without, "with_dashboard": with_, "work_change": change}, indent=1) + "\n")


if __name__ == "__main__":
    main()
