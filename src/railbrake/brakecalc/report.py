"""The brake calculation as JSON and as one self-contained HTML page. Shown figures round toward
safety: distances up, brake percentage, braked weight, decelerations and margins down."""

from __future__ import annotations

import dataclasses
import html
import math
from pathlib import Path

from railbrake import _args
from railbrake.brakecalc.calc import BrakeCalculation, settings

STYLE = ("body{font-family:sans-serif;margin:1.5em;max-width:1100px}table{border-collapse:collapse;font-size:13px;"
         "margin-bottom:1em}td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}"
         "td:first-child,th:first-child{text-align:left}.fail{color:#b00;font-weight:bold}.pass{color:#070}"
         "p.source{font-size:11px;color:#555}")


def up(value: float, step: float = 1.0) -> float:
    return math.ceil(value / step - 1e-12) * step


def down(value: float, step: float = 1.0) -> float:
    return math.floor(value / step + 1e-12) * step


def _calcs(calcs) -> list[BrakeCalculation]:
    return _args.items("calcs", calcs, BrakeCalculation)


def as_json(calcs: list[BrakeCalculation]) -> dict:
    """Every figure unrounded, SI or the unit in its key, with the sources of the published ones."""
    calcs = _calcs(calcs)
    s = settings()
    return {"schema": "railbrake.brake-calculation-report/1",
            "sources": {k: s[k]["source"] for k in ("uic544", "en14531", "tsi")},
            "trains": [dict(dataclasses.asdict(c), passed=c.passed) for c in calcs]}


def _table(headers, rows) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
    body = "".join("<tr>" + "".join(f"<td>{cell}</td>" for cell in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def verdict(passed: bool | None) -> str:
    return "n/a" if passed is None else "pass" if passed else "FAIL"


def _verdict_html(passed: bool | None) -> str:
    css = "" if passed is None else "pass" if passed else "fail"
    return f"<span class='{css}'>{verdict(passed)}</span>"


def summary_rows(calcs: list[BrakeCalculation]) -> list[list[str]]:
    """One row per train: load, mass, lambda, braked weight, a_e, worst TSI margin, verdict (text)."""
    rows = []
    for c in calcs:
        lam, bw = c.uic["brake_percentage"], c.uic["braked_weight_t"]
        worst = min(c.tsi, key=lambda r: r["margin_m"]) if c.tsi else None
        rows.append([c.train, c.load_case, f"{c.mass_t:.1f}", f"{c.max_speed_kmh:.0f}",
                     "-" if lam is None else f"{down(lam):.0f}", "-" if bw is None else f"{down(bw):.0f}",
                     f"{down(c.en14531['equivalent_deceleration_ms2'], 0.01):.2f}",
                     f"{c.en14531['response_time_s']:.2f}",
                     "-" if worst is None else f"{down(worst['margin_m']):.0f} m from {worst['speed_kmh']:.0f} km/h",
                     verdict(c.passed)])
    return rows


SUMMARY_HEADERS = ["train", "load", "mass (t)", "v max (km/h)", "lambda (%)", "braked weight (t)",
                   "a_e from v max (m/s2)", "te (s)", "smallest TSI margin", "TSI"]


def _train_html(c: BrakeCalculation) -> str:
    e, u = c.en14531, c.uic
    parts = [f"<h2>{html.escape(c.train)}: {html.escape(c.title)}</h2>",
             f"<p>Load case {html.escape(c.load_case)}, {c.mass_t:.1f} t, maximum speed {c.max_speed_kmh:.0f} km/h; "
             f"emergency brake step: {html.escape(c.brakes)}.</p>", "<h3>UIC 544-1 braked weight</h3>"]
    if u["brake_percentage"] is None:
        parts.append(f"<p>{html.escape(u.get('note', ''))}</p>")
    else:
        parts.append(_table(["position", "stop from (km/h)", "te (s)", "distance (m)", "lambda (%)",
                             "braked weight (t)"],
                            [[u["brake_position"], f"{u['reference_speed_kmh']:.0f}", f"{u['response_time_s']:.2f}",
                              f"{up(u['stopping_distance_m']):.0f}", f"{down(u['brake_percentage']):.0f}",
                              f"{down(u['braked_weight_t']):.0f}"]]))
        if "note" in u:
            parts.append(f"<p class='fail'>{html.escape(u['note'])}</p>")
    parts.append(f"<h3>EN 14531-1 mean decelerations, emergency stop from {e['initial_speed_kmh']:.0f} km/h</h3>"
                 f"<p>ta {e['delay_s']:.2f} s, tb {e['build_up_s']:.2f} s, te {e['response_time_s']:.2f} s; "
                 f"stopping distance {up(e['stopping_distance_m']):.0f} m in {e['stopping_time_s']:.1f} s; "
                 f"equivalent deceleration a_e {down(e['equivalent_deceleration_ms2'], 0.01):.2f} m/s²</p>")
    parts.append(_table(["speed interval (km/h)", "distance (m)", "mean deceleration (m/s²)"],
                        [[f"{r['from_kmh']:.0f} - {r['to_kmh']:.0f}", f"{up(r['distance_m']):.0f}",
                          f"{down(r['deceleration_ms2'], 0.01):.2f}"] for r in e["intervals"]]))
    parts.append("<h3>Emergency stopping distance against the TSI</h3>")
    if not c.tsi:
        parts.append(f"<p>No TSI value applies: maximum speed below "
                     f"{settings()['tsi']['applies_from_max_speed_kmh']:g} km/h.</p>")
    else:
        rows = [[f"{r['speed_kmh']:.0f}", f"{r['response_time_s']:.2f}",
                 f"{down(r['equivalent_deceleration_ms2'], 0.01):.2f}", f"{up(r['stopping_distance_m']):.0f}",
                 f"{r['limit_m']:.0f}", f"{down(r['margin_m']):.0f}", f"{down(r['margin_percent'], 0.1):.1f}",
                 _verdict_html(r["passed"])] for r in c.tsi]
        parts.append(_table(["from (km/h)", "te (s)", "a_e (m/s²)", "distance (m)", "TSI limit (m)", "margin (m)",
                             "margin (%)", "verdict"], rows))
    parts += [f"<p class='fail'>warning: {html.escape(w)}</p>" for w in c.warnings]
    return "".join(parts)


def to_html(calcs: list[BrakeCalculation], title: str = "railbrake brake calculation") -> str:
    calcs, title = _calcs(calcs), _args.text("title", title)
    s = settings()
    summary = _table(SUMMARY_HEADERS, [[html.escape(cell) for cell in row] for row in summary_rows(calcs)])
    sources = "".join(f"<p class='source'><b>{name}</b>: {html.escape(' '.join(s[key]['source'].split()))}</p>"
                      for name, key in (("UIC 544-1", "uic544"), ("EN 14531-1", "en14531"), ("TSI", "tsi")))
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
            f"<style>{STYLE}</style></head><body><h1>{html.escape(title)}</h1>"
            "<p>Level track, dry rail, the emergency brake step of each train file; every stop is the C "
            "stopping-distance calculation with the build-up (ta, tb) measured on a simulated emergency stop "
            "from the same speed. Distances rounded up, lambda, braked weight, decelerations and margins down."
            f"</p>{summary}{''.join(_train_html(c) for c in calcs)}<h2>Sources</h2>{sources}</body></html>")


def write(calcs: list[BrakeCalculation], folder: Path) -> tuple[Path, Path]:
    """brake-calculation.json and brake-calculation.html in folder (made if missing)."""
    from railbrake import atomic, jsonio
    calcs, folder = _calcs(calcs), _args.path("folder", folder)
    folder.mkdir(parents=True, exist_ok=True)
    json_path, html_path = folder / "brake-calculation.json", folder / "brake-calculation.html"
    atomic.write_text(json_path, jsonio.dumps(as_json(calcs), indent=2) + "\n")
    atomic.write_text(html_path, to_html(calcs))
    return json_path, html_path
