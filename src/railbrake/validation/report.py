"""Reports of a validation run: a self-contained HTML file (plots embedded as base64 PNG), a
Markdown summary for docs/validation.md, and the JSON of ``railbrake validate --json``."""

from __future__ import annotations

import base64
import html
import io
from collections import defaultdict
from datetime import datetime, timezone

import numpy as np

from railbrake._version import __version__ as RAILBRAKE_VERSION
from railbrake import _core
from railbrake.validation.cases import AREAS, KINDS
from railbrake.validation.runner import CaseResult, summary

STATUS_TEXT = {"pass": "pass", "fail": "FAIL", "broken": "BROKEN"}


def build_info() -> dict:
    return {"railbrake": RAILBRAKE_VERSION, "core_version": _core.rb_version().decode(),
            "core_build_hash": _core.rb_build_hash().decode()}


def _source_text(source: dict) -> str:
    return "; ".join(f"{k}: {' '.join(str(v).split())}" for k, v in source.items())


def _fmt(values) -> str:
    if values is None:
        return ""
    return ", ".join(f"{v:.5g}" for v in np.atleast_1d(values))


def as_json(results) -> dict:
    cases = []
    for r in results:
        cases.append({
            "id": r.id, "kind": r.kind, "area": r.area, "title": r.title, "quantity": r.quantity,
            "unit": r.unit, "status": r.status,
            "reference": None if r.reference is None else np.atleast_1d(r.reference).tolist(),
            "model": None if r.model is None else np.atleast_1d(r.model).tolist(),
            "difference": r.difference, "tolerance": r.tolerance, "passed": r.passed,
            "reason": r.reason, "source": _source_text(r.source), "details": r.details})
    return {"cases": cases, **summary(results), "build": build_info()}


# ------------------------------------------------------------------ plots

def _plot_png(r: CaseResult) -> str | None:
    """A base64 PNG of model against reference, or None when there is nothing to draw."""
    if r.model is None or r.reference is None:
        return None
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.0, 3.2), dpi=90)
    if r.x is None:
        labels = np.arange(np.atleast_1d(r.reference).size)
        ax.bar(labels - 0.2, np.atleast_1d(r.reference), 0.4, label="reference", color="#888")
        ax.bar(labels + 0.2, np.atleast_1d(r.model), 0.4, label="model", color="#1f77b4")
        ax.set_xticks([])
    else:
        if r.low is not None:   # a one-sided band (a published "more than") drawn to the plot's edge
            finite = np.concatenate([np.atleast_1d(v)[np.isfinite(v)] for v in (r.low, r.high, r.model)])
            edge = (finite.min() - 0.5 * abs(finite.min()), finite.max() + 0.5 * abs(finite.max()))
            ax.fill_between(r.x, np.maximum(r.low, edge[0]), np.minimum(r.high, edge[1]), color="#ccc", alpha=0.7,
                            label="reference scatter")
        ax.plot(r.x, r.reference, "ks", label="reference")
        if r.curve is not None:
            ax.plot(r.curve["x"], r.curve["y"], "-", color="#1f77b4", lw=1, label="model (curve)")
        ax.plot(r.x, r.model, "o", color="#d62728", mfc="none", label="model")
        ax.set_xlabel(r.x_name or "")
    ax.set_ylabel(f"{r.quantity} [{r.unit}]")
    ax.set_title(f"{r.id}: {STATUS_TEXT[r.status]}", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    return base64.b64encode(buffer.getvalue()).decode("ascii")


# ------------------------------------------------------------------ tables by area

def by_area(results) -> dict:
    table = defaultdict(lambda: {k: {"pass": 0, "fail": 0, "broken": 0} for k in KINDS})
    for r in results:
        kind = r.kind if r.kind in KINDS else KINDS[0]
        table[r.area][kind][r.status] += 1
    order = [a for a in AREAS if a in table] + sorted(a for a in table if a not in AREAS)
    return {a: table[a] for a in order}


def _cell(counts: dict) -> str:
    n = sum(counts.values())
    if n == 0:
        return "-"
    extra = "".join(f", {counts[k]} {k}" for k in ("fail", "broken") if counts[k])
    return f"{counts['pass']}/{n} pass{extra}"


_CSS = """body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;font-size:13px;vertical-align:top}
.pass{color:#080}.fail{color:#c00;font-weight:bold}.broken{color:#a0a;font-weight:bold}
.case{border-top:1px solid #ccc;padding-top:.5em;margin-top:1.2em}.small{font-size:12px;color:#555}"""


def to_html(results, title: str = "railbrake verification and validation report") -> str:
    info, counts = build_info(), summary(results)
    e = html.escape
    out = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{e(title)}</title>",
           f"<style>{_CSS}</style></head><body><h1>{e(title)}</h1>",
           f"<p>railbrake {e(info['railbrake'])}, C core {e(info['core_version'])}, core build hash "
           f"<code>{e(info['core_build_hash'])}</code>; generated "
           f"{datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC. {len(results)} cases: {counts['passed']} pass, "
           f"{counts['failed']} fail, {counts['broken']} broken.</p>",
           "<h2>Summary by model area</h2><table><tr><th>area</th>"
           + "".join(f"<th>{k}</th>" for k in KINDS) + "</tr>"]
    for area, kinds in by_area(results).items():
        out.append(f"<tr><td>{e(area)}</td>" + "".join(f"<td>{_cell(kinds[k])}</td>" for k in KINDS) + "</tr>")
    out.append("</table><h2>Cases</h2><table><tr><th>case</th><th>kind</th><th>area</th><th>quantity</th>"
               "<th>difference</th><th>tolerance</th><th>result</th></tr>")
    for r in results:
        diff = "" if r.difference is None else f"{r.difference:.4g} {'%' if r.tolerance.endswith('%') else r.unit}"
        out.append(f"<tr><td><a href='#{e(r.id)}'>{e(r.id)}</a></td><td>{e(r.kind)}</td><td>{e(r.area)}</td>"
                   f"<td>{e(r.quantity)}</td><td>{e(diff)}</td><td>{e(r.tolerance)}</td>"
                   f"<td class='{r.status}'>{STATUS_TEXT[r.status]}</td></tr>")
    out.append("</table>")
    for r in results:
        out.append(f"<div class='case' id='{e(r.id)}'><h3>{e(r.id)}: {e(r.title)}</h3>")
        out.append(f"<p><span class='{r.status}'>{STATUS_TEXT[r.status]}</span> &middot; {e(r.kind)} &middot; "
                   f"{e(r.area)}{' &middot; ' + e(r.reason) if r.reason else ''}</p>")
        png = _plot_png(r)
        if png:
            out.append(f"<img alt='{e(r.id)}' src='data:image/png;base64,{png}'>")
        if r.model is not None:
            out.append("<table>" + (f"<tr><td>{e(r.x_name)}</td><td>{_fmt(r.x)}</td></tr>" if r.x is not None else "")
                       + f"<tr><td>reference [{e(r.unit)}]</td><td>{_fmt(r.reference)}</td></tr>"
                       + (f"<tr><td>scatter</td><td>{_fmt(r.low)} .. {_fmt(r.high)}</td></tr>" if r.low is not None else "")
                       + f"<tr><td>model [{e(r.unit)}]</td><td>{_fmt(r.model)}</td></tr>"
                       + f"<tr><td>tolerance</td><td>{e(r.tolerance)}: {e(r.tolerance_reason)}</td></tr></table>")
        out.append(f"<p class='small'>Source: {e(_source_text(r.source))}</p>")
        if r.details:
            out.append(f"<p class='small'>Details: {e(str(r.details))}</p>")
        out.append("</div>")
    out.append("</body></html>")
    return "\n".join(out)


def _compact(r: CaseResult) -> str:
    """'0.965 / 1' for one-point cases, 'n points' otherwise (the HTML report has them all)."""
    if r.model is None:
        return ""
    model, ref = np.atleast_1d(r.model), np.atleast_1d(r.reference)
    if model.size == 1:
        return f"{model[0]:.4g} / {ref[0]:.4g} {r.unit if r.unit != '-' else ''}".rstrip()
    return f"{model.size} points"


def to_markdown(results) -> str:
    info, counts = build_info(), summary(results)
    lines = ["# Verification and validation", "",
             "Generated by `railbrake validate --markdown FILE` (`make validate`: out/validation.md and "
             "out/validation.html); the HTML report holds the plots, the figures and the full sources. "
             "The case format and the runner: docs/validation-cases.md.", "",
             f"railbrake {info['railbrake']}, C core {info['core_version']}, build hash "
             f"`{info['core_build_hash']}`. {len(results)} cases: {counts['passed']} pass, "
             f"{counts['failed']} fail, {counts['broken']} broken.", "",
             "## By model area", "", "| area | " + " | ".join(KINDS) + " |",
             "|---|" + "---|" * len(KINDS)]
    for area, kinds in by_area(results).items():
        lines.append(f"| {area} | " + " | ".join(_cell(kinds[k]) for k in KINDS) + " |")
    lines += ["", "## Cases", "", "| case | kind | area | model / reference | difference | tolerance | result |",
              "|---|---|---|---|---|---|---|"]
    for r in results:
        diff = "" if r.difference is None else f"{r.difference:.3g} {'%' if r.tolerance.endswith('%') else r.unit}"
        lines.append(f"| {r.id} | {r.kind} | {r.area} | {_compact(r)} | {diff} | {r.tolerance} | {STATUS_TEXT[r.status]} |")
    failing = [r for r in results if r.status != "pass"]
    if failing:
        lines += ["", "## Failing and broken cases (findings)", ""]
        lines += [f"- **{r.id}** ({STATUS_TEXT[r.status]}): {r.reason}" for r in failing]
    lines += ["", "## Sources", ""]
    lines += [f"- {r.id}: {' '.join(str(r.source.get('reference', '')).split())}" for r in results]
    return "\n".join(lines) + "\n"
