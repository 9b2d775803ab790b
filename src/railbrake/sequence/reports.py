"""Reports of a sequence run: JUnit XML (one testsuite per test, one testcase per step, as CI tools
read it) and a self-contained HTML page with a plot of each expectation's window."""

from __future__ import annotations

import base64
import html
import io
import socket
import xml.etree.ElementTree as ET
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from railbrake import atomic
from railbrake.units import BAR

from railbrake.sequence.schema import Sequence

PLOT_MARGIN = 1.0   # s shown before and after an expectation's window


def _case_name(step) -> str:
    return f"step {step.index + 1}: {step.action}" + (f" {step.name}" if step.name else "")


def junit_xml(sequence: Sequence, results: list, mode: str) -> str:
    root = ET.Element("testsuites", name=sequence.spec.name,
                      tests=str(sum(len(r.steps) for r in results)),
                      failures=str(sum(s.verdict == "fail" for r in results for s in r.steps)),
                      errors=str(sum(s.verdict == "error" for r in results for s in r.steps)),
                      time=f"{sum(r.seconds for r in results):.3f}")
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%S")
    for i, result in enumerate(results):
        suite = ET.SubElement(root, "testsuite", name=f"{sequence.spec.name}.{result.name}", id=str(i),
                              package=sequence.spec.name, hostname=socket.gethostname() or "localhost",
                              timestamp=stamp, tests=str(len(result.steps)),
                              failures=str(sum(s.verdict == "fail" for s in result.steps)),
                              errors=str(sum(s.verdict == "error" for s in result.steps)),
                              time=f"{result.seconds:.3f}")
        properties = ET.SubElement(suite, "properties")
        for name, value in [("mode", mode), ("scenario", sequence.spec.scenario), ("verdict", result.verdict)] + [
                (f"kpi.{k}", v) for k, v in result.kpis.items()]:
            ET.SubElement(properties, "property", name=name, value=str(value))
        for step in result.steps:
            case = ET.SubElement(suite, "testcase", name=_case_name(step),
                                 classname=f"{sequence.spec.name}.{result.name}", time=f"{step.seconds:.3f}")
            if step.verdict in ("fail", "error"):
                tag = "failure" if step.verdict == "fail" else "error"
                ET.SubElement(case, tag, message=step.message, type=step.action).text = step.message
            else:
                ET.SubElement(case, "system-out").text = step.message
        ET.SubElement(suite, "system-out").text = f"verdict {result.verdict}"
        ET.SubElement(suite, "system-err").text = ""
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _window_plot(result, step) -> str:
    """A PNG (base64) of the expectation's signal around its window, with the threshold."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    t0, t1, channels, threshold = step.window
    time = result.series["time"]
    shown = (time >= t0 - PLOT_MARGIN) & (time <= t1 + PLOT_MARGIN)
    pressure = result.units.get(channels[0]) == "Pa"
    scale = (lambda x: (x - result.atmosphere) / BAR) if pressure else (lambda x: x)
    fig = Figure(figsize=(6.4, 2.6), dpi=90)
    ax = fig.add_subplot()
    for name in channels[:16]:
        values = result.series[name][shown]
        ax.plot(time[shown], scale(np.abs(values) if len(channels) > 1 else values), lw=0.9, label=name)
    ax.axhline(scale(threshold.value), color="k", ls="--", lw=0.8, label=f"{threshold.comparison} {threshold.written}")
    ax.axvspan(t0, t1, color="tab:green" if step.verdict == "pass" else "tab:red", alpha=0.12)
    ax.set_xlabel("time (s)")
    unit = "bar g" if pressure else result.units.get(channels[0], "")
    ax.set_ylabel(unit if unit not in ("", "1") else "")
    ax.legend(fontsize=6, ncol=4, loc="best")
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return base64.b64encode(buffer.getvalue()).decode()


def html_report(sequence: Sequence, results: list, mode: str) -> str:
    e = html.escape
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{e(sequence.spec.name)}</title>",
             "<style>body{font-family:sans-serif;max-width:60em;margin:auto}td,th{padding:2px 6px;"
             "border-bottom:1px solid #ddd;text-align:left}.pass{color:#080}.fail,.error{color:#c00}"
             "</style></head><body>",
             f"<h1>{e(sequence.spec.name)}</h1><p>{e(sequence.spec.title)}</p>",
             f"<p>scenario {e(sequence.spec.scenario)}, {e(mode)}; file {e(sequence.origin)}</p>"]
    for result in results:
        parts.append(f"<h2>{e(result.name)}: <span class='{result.verdict}'>{result.verdict.upper()}</span></h2>")
        parts.append("<table><tr><th>step</th><th>t (s)</th><th>verdict</th><th>what happened</th></tr>")
        for step in result.steps:
            parts.append(f"<tr><td>{e(_case_name(step))}</td><td>{step.start_s:.3f}</td>"
                         f"<td class='{step.verdict}'>{step.verdict}</td><td>{e(step.message)}</td></tr>")
        parts.append("</table>")
        if result.kpis:
            parts.append("<p>KPIs: " + ", ".join(f"{e(k)} = {v:.6g}" for k, v in result.kpis.items()) + "</p>")
        for step in result.steps:
            if step.window is not None and step.window[2]:
                parts.append(f"<h3>{e(_case_name(step))} ({step.verdict})</h3><p>{e(step.message)}</p>"
                             f"<img alt='window of {e(_case_name(step))}' "
                             f"src='data:image/png;base64,{_window_plot(result, step)}'>")
    parts.append("</body></html>")
    return "\n".join(parts)


def write(sequence: Sequence, results: list, mode: str, junit: Path | None,
          html_path: Path | None) -> list[Path]:
    written = []
    if junit is not None:
        atomic.write_text(junit, junit_xml(sequence, results, mode))
        written.append(Path(junit))
    if html_path is not None:
        atomic.write_text(html_path, html_report(sequence, results, mode))
        written.append(Path(html_path))
    return written
