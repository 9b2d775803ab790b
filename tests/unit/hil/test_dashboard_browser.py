"""The dashboard in a real headless browser (Debian's chromium, `make browser`, driven by
Playwright) during a paced run without BCU: the page loads with every request off this machine
blocked, shows the live speed within 1 % of the recording at the plant time it shows, and a fault
injected from the page is in the recording from the time the loop applied it."""

import shutil

import numpy as np
import pytest

from conftest import run_with_dashboard
from railbrake.hil.dashboard import Dashboard
from railbrake.units import ms_to_kmh

CHROMIUM = shutil.which("chromium")
playwright = pytest.importorskip("playwright.sync_api", reason="playwright not installed (pip install '.[test]')")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed: `make browser` "
                                "installs it (apt-get, as root)")


def drive(board, seen, errors):
    origin = f"http://{board.host}:{board.port}"
    try:
        with playwright.sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=["--no-sandbox"])
            page = browser.new_page()
            blocked = []

            def only_local(route):
                if route.request.url.startswith(origin + "/"):
                    route.continue_()
                else:   # the network beyond this machine is blocked
                    blocked.append(route.request.url)
                    route.abort()

            page.route("**/*", only_local)
            page.goto(board.url)
            page.wait_for_function("Number(document.getElementById('time').textContent) > 1.0", timeout=60000)
            seen["speed"] = page.eval_on_selector("#speed", "e => [Number(e.dataset.time), Number(e.dataset.value)]")
            page.select_option("#fault-type", "vent_stuck_open")
            page.fill("#fault-car", "1")
            page.fill("#fault-axle", "3")
            page.click("#inject")
            page.wait_for_function("document.getElementById('fault-answer').dataset.ok === 'true'", timeout=30000)
            seen["fault_time"] = float(page.eval_on_selector("#fault-answer", "e => e.dataset.time"))
            # a kind that reads a value: the page's value field, named after the key, with its unit
            page.select_option("#fault-type", "relay_valve_failed")
            seen["value_key"] = page.eval_on_selector("#fault-value-key", "e => e.textContent")
            page.fill("#fault-axle", "")
            page.fill("#fault-value", "1.5 bar")
            page.click("#inject")
            page.wait_for_function("document.getElementById('fault-answer').dataset.time > "
                                   f"{seen['fault_time']}", timeout=30000)
            seen["relay_answer"] = page.eval_on_selector("#fault-answer", "e => [e.dataset.ok, e.textContent]")
            page.wait_for_function(f"Number(document.getElementById('time').textContent) > {seen['fault_time'] + 0.5}",
                                   timeout=60000)
            page.click("#stop")
            seen["blocked"] = blocked
            browser.close()
    except Exception as exc:   # noqa: BLE001 - reported by the test
        errors.append(repr(exc))
        board.request_stop()


@pytest.mark.slow   # chromium does not start with the sanitizers preloaded
def test_dashboard_in_headless_chromium():
    board = Dashboard(cars=1)
    seen, errors = {}, []
    result = run_with_dashboard(board, lambda: drive(board, seen, errors), 120.0)
    assert not errors, errors
    assert seen["blocked"] == []                         # the page needs nothing from the network
    assert result.interrupted                            # the page's stop button ended the run
    t, shown_kmh = seen["speed"]
    recorded_kmh = ms_to_kmh(np.interp(t, result.time, result.outputs["speed"]))
    assert shown_kmh == pytest.approx(recorded_kmh, rel=0.01)
    change = result.fault_changes[0]
    assert change.origin == "dashboard" and change.time_s == pytest.approx(seen["fault_time"])
    vent = result.outputs["vent_c1a3"]
    assert not vent[result.time <= change.time_s].any() and vent[result.time > change.time_s + 0.01].all()
    assert seen["value_key"] == "pressure" and seen["relay_answer"][0] == "true", seen["relay_answer"]
    relay = result.fault_changes[1]
    assert relay.fault["type"] == "relay_valve_failed" and relay.fault["pressure"] == pytest.approx(1.5e5)


def read_layout(board, seen, errors):
    """The page once it has drawn 0.5 s of the run: the demand shown, each plot's text boxes; the
    snapshot as the API gives it to a client sending its token as `Authorization: Bearer`."""
    import json
    import urllib.request
    try:
        with playwright.sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=["--no-sandbox"])
            page = browser.new_page()
            page.goto(board.url)
            page.wait_for_function("Number(document.getElementById('time').textContent) > 0.5 && "
                                   "document.getElementById('slips').dataset.labels", timeout=60000)
            seen["demand"] = page.inner_text("#demand")
            seen["labels"] = {c: json.loads(page.eval_on_selector(f"#{c}", "e => e.dataset.labels"))
                              for c in ("speeds", "cylinders", "slips")}
            seen["sizes"] = {c: page.eval_on_selector(f"#{c}", "e => [e.width, e.height]") for c in seen["labels"]}
            request = urllib.request.Request(f"http://{board.host}:{board.port}/api/snapshot",
                                             headers={"Authorization": f"Bearer {board.token}"})
            with urllib.request.urlopen(request, timeout=30) as reply:
                seen["snapshot"] = json.loads(reply.read())["snapshot"]
            page.click("#stop")
            browser.close()
    except Exception as exc:   # noqa: BLE001 - reported by the test
        errors.append(repr(exc))
        board.request_stop()


def _overlap(a, b):
    return a["x0"] < b["x1"] and b["x0"] < a["x1"] and a["y0"] < b["y1"] and b["y0"] < a["y1"]


@pytest.mark.slow   # chromium does not start with the sanitizers preloaded
def test_dashboard_reads_at_a_glance():
    """Without BCU the loop holds the safe state, whose demand is emergency: the page and the API
    say so in words. Each plot's texts lie inside it and apart (the legend clear of the value
    labels), its time axis reads -30 .. 0 s relative to now with its name, its value axis its name
    and unit."""
    board = Dashboard(cars=1)
    seen, errors = {}, []
    run_with_dashboard(board, lambda: read_layout(board, seen, errors), 60.0)
    assert not errors, errors
    assert seen["demand"] == "emergency" and seen["snapshot"]["brake_demand_text"] == "emergency"
    names = {"speeds": "speed [km/h]", "cylinders": "pressure [bar g]", "slips": "slip [1]"}
    for canvas, boxes in seen["labels"].items():
        width, height = seen["sizes"][canvas]
        texts = [b["text"] for b in boxes]
        assert all(0 <= b["x0"] < b["x1"] <= width and 0 <= b["y0"] < b["y1"] <= height for b in boxes), boxes
        assert not [(a["text"], b["text"]) for i, a in enumerate(boxes) for b in boxes[i + 1:] if _overlap(a, b)]
        ticks = [b for b in boxes if b["text"] in ("\u221230", "\u221220", "\u221210", "0")]
        assert [b["text"] for b in ticks] == ["\u221230", "\u221220", "\u221210", "0"]
        assert "t \u2212 now [s]" in texts and all(b["y0"] > max(t["y1"] for t in ticks) for b in boxes
                                                   if b["text"] == "t \u2212 now [s]")
        assert names[canvas] in texts   # the value axis's name and unit
