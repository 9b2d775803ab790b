"""report.html: one self-contained file per run (images embedded as base64) with the scenario,
the resolved configuration, the KPIs with their definitions and warnings, the plots and the
provenance. Each KPI row carries its exact value as JSON in data-value (tests read it back)."""

from __future__ import annotations

import base64
import json
from html import escape
from pathlib import Path

from railbrake import atomic
from railbrake.results import kpis as kpi_info
from railbrake.results.events import fault_text
from railbrake.results.files import dumps
from railbrake.results.record import RunRecord

_MIME = {".png": "image/png", ".svg": "image/svg+xml", ".pdf": "application/pdf"}
_STYLE = """
body { font-family: sans-serif; max-width: 1100px; margin: 1em auto; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0; }
td, th { border: 1px solid #ccc; padding: 2px 8px; text-align: left; vertical-align: top; }
td.value { text-align: right; font-family: monospace; }
.warning { color: #a00; }
img { max-width: 100%; border: 1px solid #eee; margin: 0.5em 0; }
pre { background: #f6f6f6; padding: 0.5em; overflow-x: auto; font-size: 85%; }
"""


def _rows(pairs) -> str:
    return "\n".join(f"<tr><th>{escape(str(k))}</th><td>{escape(str(v))}</td></tr>" for k, v in pairs)


def _kpi_table(kpis: dict) -> str:
    rows = []
    for key, value in kpis.items():
        rows.append(f'<tr data-kpi="{escape(key)}" data-value="{escape(json.dumps(json.loads(dumps(value))))}">'
                    f"<th>{escape(key)}</th><td class=\"value\">{escape(kpi_info.text(value))}</td>"
                    f"<td>{escape(kpi_info.unit(key))}</td><td>{escape(kpi_info.definition(key))}</td></tr>")
    return ('<table id="kpis"><tr><th>KPI</th><th>value</th><th>unit</th><th>definition</th></tr>\n'
            + "\n".join(rows) + "</table>")


def _image(path: Path) -> str:
    data = base64.b64encode(path.read_bytes()).decode()
    mime = _MIME.get(path.suffix, "application/octet-stream")
    if mime == "application/pdf":
        return f'<p><a download="{escape(path.name)}" href="data:{mime};base64,{data}">{escape(path.name)}</a></p>'
    return f'<figure><img alt="{escape(path.stem)}" src="data:{mime};base64,{data}"><figcaption>' \
           f"{escape(path.name)}</figcaption></figure>"


def write_report(record: RunRecord, plots: list[Path], path: Path) -> Path:
    m = record.meta
    prov = m.get("provenance", {})
    warnings = kpi_info.warnings(record.kpis, m.get("healthy_cylinder_shortfall_s"))
    faults = ", ".join(f"{fault_text(f)} from {f['start']:g} s" for f in m.get("faults", [])) or "none"
    zones = ", ".join(f"{z['start']:g}-{z['end']:g} m {z['condition']}" for z in m.get("zones", [])) or "none"
    scenario = [("scenario", m.get("scenario", "")), ("title", m.get("title", "")), ("kind", record.kind),
                ("train", m.get("train", "")), ("cars", record.cars), ("WSP", "on" if record.wsp else "off"),
                ("adhesion", m.get("condition", "")), ("adhesion zones", zones), ("faults", faults)]
    if "hil" in m:
        scenario += [(f"HIL {k.replace('_', ' ')}", v) for k, v in (m["hil"].get("counters") or {}).items()]
    html = [
        "<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
        f"<title>railbrake report: {escape(record.title())}</title><style>{_STYLE}</style></head><body>",
        f"<h1>{escape(record.title())}</h1>",
        f"<p>{escape(m.get('title', ''))}</p>",
        '<h2>Scenario</h2><table id="scenario">', _rows(scenario), "</table>",
        "<h2>KPIs</h2>",
        ('<ul id="warnings">' + "".join(f'<li class="warning">{escape(w)}</li>' for w in warnings) + "</ul>")
        if warnings else '<p id="warnings">No warnings.</p>',
        _kpi_table(record.kpis),
        "<h2>Plots</h2>", *(_image(p) for p in plots),
        '<h2>Provenance</h2><table id="provenance">', _rows(prov.items()), "</table>",
        "<h2>Resolved configuration</h2>",
        f'<pre id="configuration">{escape(dumps(m.get("configuration", {})))}</pre>',
        "</body></html>"]
    return atomic.write_text(path, "\n".join(html) + "\n")
