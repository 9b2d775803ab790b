"""`railbrake campaign report DIR`: one self-contained HTML file (plots inline as PNG) and a
Markdown summary: the study, the assessed cases with pass/fail, the KPIs against the factors,
heat maps for two factors, Sobol indices for a Sobol design, the tuning, the failed runs."""

from __future__ import annotations

import base64
import html
import io
import json
import math
from pathlib import Path

import numpy as np

from railbrake import atomic, config
from railbrake.campaign import dataset
from railbrake.campaign.assess import assess, rank, worst
from railbrake.campaign.study import StudyFile
from railbrake.errors import InputError

PLOTTED = ("delta_s_pct", "kwet", "adhesion_utilisation", "air_drawn_kg", "air_consumed_kg",
           "stopping_distance_m", "min_supply_bar", "max_slip")
# short column labels of the assessed cases (EN 15595's symbols), so the table fits a page
LABELS = {"stopping_distance_m": "s", "deceleration_distance_m": "s_d", "delta_s_pct": "dS", "kwet": "Kwet",
          "adhesion_utilisation": "utilisation", "air_drawn_kg": "air", "air_consumed_kg": "air used",
          "min_supply_bar": "min supply", "max_slip": "slip", "wheel_lock_events": "locks",
          "safety_timer_trips": "timer trips", "valve_switchings": "switchings",
          "max_sliding_energy_kj": "sliding"}
UNITS = {"stopping_distance_m": "m", "deceleration_distance_m": "m", "delta_s_pct": "%", "air_drawn_kg": "kg",
         "air_consumed_kg": "kg", "min_supply_bar": "bar", "stopping_time_s": "s", "max_sliding_energy_kj": "kJ"}
LEVELS_AS_CELLS = 8     # a numeric factor with this many levels or fewer gets one heat-map cell per level
SI_TO_DISPLAY = {"m/s": ("km/h", 3.6), "Pa": ("bar", 1e-5)}   # factor axes in the units engineers read


class Campaign:
    """A dataset folder: its study, manifest and rows (dicts, SI)."""

    def __init__(self, folder: Path):
        self.folder = Path(folder)
        self.manifest = dataset.read_manifest(self.folder) or {}
        text = (self.folder / "study.yaml").read_text()
        self.study = config.parse_yaml(text, StudyFile, str(self.folder / "study.yaml"))
        table = dataset.read(self.folder)
        self.rows = table.to_pylist()
        self.factors = list(self.manifest.get("factor_order") or self.manifest.get("factors") or {})
        self.units = self.manifest.get("factors") or {}
        self.kinds = self.manifest.get("kinds") or {}
        self.kpis = self.manifest.get("kpis") or []

    def ok(self) -> list[dict]:
        return [r for r in self.rows if r["status"] == dataset.STATUS_OK]

    def failed(self) -> list[dict]:
        return [r for r in self.rows if r["status"] != dataset.STATUS_OK]

    def initial_speed(self, row: dict) -> float:
        if row.get("initial_speed") is not None:
            return row["initial_speed"]
        from railbrake.campaign import configuration
        return configuration.resolve(self.study.base).scenario.spec.initial_speed

    def assessed(self) -> list[dict] | None:
        if self.study.assessment is None:
            return None
        return assess(self.rows, self.factors, self.study.assessment, self.initial_speed)

    def ranking(self, cases: list[dict] | None = None) -> list[dict] | None:
        """The levels of the assessment's `rank` factor, best first (assess.rank), or None."""
        a = self.study.assessment
        if a is None or a.rank is None:
            return None
        return rank(self.assessed() if cases is None else cases, a.rank, a)


def _display(c: Campaign, factor: str, values):
    unit = c.units.get(factor, "")
    label, scale = SI_TO_DISPLAY.get(unit, (unit, 1.0))
    return [v * scale if isinstance(v, (int, float)) else v for v in values], label


def _png(fig) -> str:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90, bbox_inches="tight")
    import matplotlib.pyplot as plt
    plt.close(fig)
    return base64.b64encode(buffer.getvalue()).decode()


def _positions(values):
    """Numbers stay numbers; categories get positions 0, 1, ... in their first-seen order."""
    if all(isinstance(v, (int, float)) or v is None for v in values):
        return values, None
    labels = list(dict.fromkeys(str(v) for v in values))
    return [labels.index(str(v)) for v in values], labels


def kpi_plots(c: Campaign, rows: list[dict], kpis: list[str]) -> list[tuple[str, str]]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plots = []
    for kpi in kpis:
        fig, axes = plt.subplots(1, len(c.factors), figsize=(4 * len(c.factors), 3.2), squeeze=False)
        for ax, factor in zip(axes[0], c.factors):
            pairs = [(r.get(factor), r.get(kpi)) for r in rows if r.get(kpi) is not None and r.get(factor) is not None]
            x, label = _display(c, factor, [p[0] for p in pairs])
            x, categories = _positions(x)
            ax.plot(x, [p[1] for p in pairs], "o", alpha=0.7)
            if categories:
                ax.set_xticks(range(len(categories)), categories, rotation=20)
            ax.set_xlabel(f"{factor}{f' ({label})' if label else ''}")
            ax.set_ylabel(f"{kpi}{f' ({UNITS[kpi]})' if kpi in UNITS else ''}")
            ax.grid(alpha=0.3)
        fig.tight_layout()
        plots.append((f"{kpi} against the factors", _png(fig)))
    return plots


def heat_map(c: Campaign, rows: list[dict], kpi: str) -> tuple[str, str] | None:
    """Mean of a KPI over the cells of the first two factors (numbers binned in 6)."""
    if len(c.factors) < 2:
        return None
    import matplotlib.pyplot as plt
    fx, fy = c.factors[:2]
    cells = [(r.get(fx), r.get(fy), r.get(kpi)) for r in rows if r.get(kpi) is not None]
    if not cells:
        return None
    axes = []
    for k, f in enumerate((fx, fy)):
        values, label = _display(c, f, [cell[k] for cell in cells])
        pos, cats = _positions(values)
        if cats is None and len(set(pos)) <= LEVELS_AS_CELLS:   # few levels: one cell each
            levels = sorted(set(pos))
            pos, cats = [levels.index(v) for v in pos], [f"{v:.4g}" for v in levels]
            f = f"{f} ({label})" if label else f
        if cats is None:
            edges = np.unique(np.quantile(pos, np.linspace(0, 1, 7)))
            index = np.clip(np.searchsorted(edges, pos, side="right") - 1, 0, max(len(edges) - 2, 0))
            ticks = [f"{0.5 * (edges[i] + edges[i + 1]):.4g}" for i in range(max(len(edges) - 1, 1))] \
                if len(edges) > 1 else [f"{edges[0]:.4g}"]
            axes.append((index, ticks, f"{f} ({label})" if label else f))
        else:
            axes.append((np.array(pos), cats, f))
    grid = np.full((len(axes[1][1]), len(axes[0][1])), np.nan)
    for i in range(grid.shape[0]):
        for j in range(grid.shape[1]):
            chosen = [cell[2] for cell, a, b in zip(cells, axes[0][0], axes[1][0]) if a == j and b == i]
            if chosen:
                grid[i, j] = float(np.mean(chosen))
    fig, ax = plt.subplots(figsize=(5.5, 4))
    image = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
    ax.set_xticks(range(len(axes[0][1])), axes[0][1], rotation=20)
    ax.set_yticks(range(len(axes[1][1])), axes[1][1])
    ax.set_xlabel(axes[0][2])
    ax.set_ylabel(axes[1][2])
    fig.colorbar(image, label=kpi)
    return f"heat map of {kpi}: {fx} x {fy}", _png(fig)


def sobol(c: Campaign, kpis: list[str]) -> dict | None:
    """First-order and total Sobol indices (scipy.stats.sobol_indices on the A, B, AB_i blocks)."""
    if c.manifest.get("design") != "sobol":
        return None
    from scipy.stats import sobol_indices
    n, d = int(c.manifest["samples"]), len(c.factors)
    out = {}
    for kpi in kpis:
        blocks: dict = {}
        for r in c.ok():
            if r.get(kpi) is not None:
                blocks.setdefault((r["block"], r["sample"]), []).append(r[kpi])
        try:
            f = lambda b: np.array([[np.mean(blocks[(b, i)]) for i in range(n)]])   # noqa: E731
            result = sobol_indices(func={"f_A": f("A"), "f_B": f("B"),
                                         "f_AB": np.stack([f(f"AB{i}") for i in range(d)])}, n=n)
        except (KeyError, ValueError):   # a failed run leaves a hole: no indices for this KPI
            continue
        first, total = np.ravel(result.first_order), np.ravel(result.total_order)   # one output: (d,)
        out[kpi] = {factor: {"first": float(first[i]), "total": float(total[i])}
                    for i, factor in enumerate(c.factors)}
    return out


GROUP = "\u00a0"   # thousands are grouped with a no-break space: 13 380, never 1.338e+04


def _fmt(value) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        if abs(value) >= 1000:      # long distances, air masses: whole units, digits grouped
            return f"{value:,.0f}".replace(",", GROUP)
        return f"{value:.4g}"
    return str(value)


def _case_columns(c: Campaign) -> list[str]:
    air = next((k for k in ("air_drawn_kg", "air_consumed_kg") if k in c.kpis), None)
    return ["passed"] + c.factors + ["stopping_distance_m", "deceleration_distance_m", "delta_s_pct", "kwet",
                        "adhesion_utilisation"] + ([air] if air else []) + \
        [k for k in ("min_supply_bar", "max_slip", "valve_switchings", "max_sliding_energy_kj", "wheel_lock_events",
                     "safety_timer_trips") if k in c.kpis]


def _display_row(c: Campaign, row: dict, columns: list[str]) -> list[str]:
    cells = []
    for col in columns:
        value = row.get(col)
        if col in c.units and isinstance(value, (int, float)):
            value = _display(c, col, [value])[0][0]
        cells.append(_fmt(value))
    return cells


def _header(c: Campaign, col: str, labels: dict | None = None) -> str:
    if col in c.units and c.units[col]:
        return f"{col} ({SI_TO_DISPLAY.get(c.units[col], (c.units[col],))[0]})"
    name = (labels or {}).get(col, col)
    return f"{name} ({UNITS[col]})" if col in UNITS else name


def _html_table(headers, rows) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(v)}</td>" for v in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _md_table(headers, rows) -> str:
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(v.replace("|", "/") for v in row) + " |" for row in rows]
    return "\n".join(lines)


def _points_table(c: Campaign) -> tuple[str, list, list]:
    """Per design point: the factors and the KPIs' means over the seeds."""
    kpis = [k for k in ("stopping_distance_m", "adhesion_utilisation", "air_drawn_kg", "air_consumed_kg",
                        "min_supply_bar", "max_slip", "wheel_lock_events") if k in c.kpis]
    points: dict = {}
    for r in c.ok():
        points.setdefault(r["point"], []).append(r)
    rows = []
    for point in sorted(points):
        group = points[point]
        mean = {k: float(np.mean([g[k] for g in group if g.get(k) is not None] or [np.nan])) for k in kpis}
        rows.append([str(point)] + _display_row(c, {**group[0], **mean}, c.factors + kpis))
    return ("Design points (means over the seeds)", ["point"] + [_header(c, k) for k in c.factors + kpis], rows)


# the ranking table: (column of assess.rank's levels, header)
RANKING_COLUMNS = (("rank", "mean rank"), ("worst_delta_s_pct", "worst dS (%)"), ("kwet", "Kwet"),
                   ("adhesion_utilisation", "utilisation"), ("air_drawn_kg", "air per stop (kg)"),
                   ("valve_switchings", "valve switchings per stop"),
                   ("max_sliding_energy_kj", "sliding energy, worst axle (kJ)"),
                   ("safety_timer_trips", "timer trips"), ("wheel_lock_events", "locks"),
                   ("failed_cases", "failed cases"))


def ranking_table(c: Campaign, levels: list[dict]) -> tuple[str, list, list]:
    factor = c.study.assessment.rank
    rows = [[str(i + 1), str(level[factor])] + [_fmt(level[k]) for k, _ in RANKING_COLUMNS]
            for i, level in enumerate(levels)]
    on = ", ".join(levels[0]["ranked_on"]) if levels else ""
    return (f"Ranking of {factor} (mean of the ranks on {on}; Kwet is the worst dS transformed)",
            ["place", factor] + [h for _, h in RANKING_COLUMNS], rows)


def sections(c: Campaign) -> tuple[list[tuple[str, list, list]], dict]:
    """Tables (title, headers, rows) and the JSON summary, shared by HTML and Markdown."""
    tables = []
    summary = {"study": c.study.name, "runs": len(c.rows), "ok": len(c.ok()), "failed": len(c.failed())}
    cases = c.assessed()
    if cases is not None:
        columns = _case_columns(c)   # the verdict first: on the page whatever the table's width
        ordered = sorted(cases, key=lambda case: case["passed"])      # failed cases first (stable)
        rows = [_display_row(c, case, columns) + ["; ".join(case["reasons"])] for case in ordered]
        tables.append(("Assessed cases (EN 15595 style), failed first",
                       [_header(c, k, LABELS) for k in columns] + ["why not"], rows))
        summary["assessment"] = worst(cases)
        summary["cases"] = len(cases)
        summary["failed_cases"] = sum(not case["passed"] for case in cases)
        levels = c.ranking(cases)
        if levels is not None:
            tables.append(ranking_table(c, levels))
            summary["ranking"] = levels
    else:
        tables.append(_points_table(c))
    tuning = c.folder / "tuning" / "summary.json"
    if tuning.is_file():
        try:
            t = json.loads(tuning.read_text())
            rows = [["default", _fmt(t["default"]["worst_delta_s_pct"]), _fmt(t["default"]["locks"]), ""],
                    ["tuned", _fmt(t["tuned"]["worst_delta_s_pct"]), _fmt(t["tuned"]["locks"]),
                     ", ".join(f"{k} = {v:.4g}" for k, v in t["tuned"]["params"].items())]]
            cases = t.get("cases", "all")
            cases = "all cases" if cases == "all" else "cases " + ", ".join(cases)
            tables.append((f"WSP tuning ({t['evaluations']} evaluations, {t.get('objective', '')}, {cases})", ["WSP", "worst dS (%)", "locks", "parameters"],
                           rows))
        except (ValueError, KeyError, TypeError, AttributeError) as exc:
            raise InputError(f"{tuning}: damaged ({exc.__class__.__name__}: {exc}): not a tuning summary; "
                             "tune again or remove it") from None
        summary["tuning"] = t
    indices = sobol(c, [k for k in c.kpis if k in PLOTTED or k == "stopping_distance_m"])
    if indices:
        rows = [[kpi, f, _fmt(v["first"]), _fmt(v["total"])] for kpi, by in indices.items() for f, v in by.items()]
        tables.append(("Sobol indices", ["KPI", "factor", "first order", "total"], rows))
        summary["sobol"] = indices
    failed = [[r["key"][:12], str(r["point"]), str(r["replicate"]), r.get("error") or ""] for r in c.failed()]
    tables.append(("Failed runs", ["key", "point", "replicate", "error"], failed))
    return tables, summary


def headline(summary: dict) -> str:
    """The verdict first: failed assessments (when the study has an assessment), then the runs."""
    runs = f"{summary['runs']} runs, {summary['failed']} of them failed to run"
    if "cases" not in summary:
        return f"{'FAILED' if summary['failed'] else 'All ran'}: {runs}."
    if summary["failed_cases"]:
        return f"FAILED: {summary['failed_cases']} of {summary['cases']} assessed cases fail; {runs}."
    return f"PASSED: all {summary['cases']} assessed cases pass; {runs}."


# A 1400 px screen and an A4 page: the verdict is the first column, cells wrap their headers, the
# table may scroll sideways on screen; in print it shrinks to the page in landscape.
STYLE = ("body{font-family:sans-serif;margin:1.5em;max-width:1400px}"
         ".wide{overflow-x:auto;max-width:100%}table{border-collapse:collapse;font-size:12px}"
         "td,th{border:1px solid #bbb;padding:2px 4px;text-align:right}th{overflow-wrap:anywhere;max-width:9em}"
         "td:first-child,th:first-child{text-align:center;font-weight:bold}img{max-width:100%}"
         ".verdict{font-size:1.3em;font-weight:bold}"
         "@page{size:A4 landscape;margin:10mm}"
         "@media print{body{margin:0;max-width:none}table{font-size:8px;width:100%}.wide{overflow:visible}"
         "img{max-width:100%;page-break-inside:avoid}tr{page-break-inside:avoid}}")


def write(folder: Path, output: Path) -> dict:
    return render(Campaign(folder), output)


def render(c: Campaign, output: Path) -> dict:
    """The HTML report at `output` and its Markdown summary beside it; returns the JSON summary."""
    tables, summary = sections(c)
    cases = c.assessed()
    rows = cases if cases is not None else c.ok()
    kpis = [k for k in PLOTTED if any(r.get(k) is not None for r in rows)]
    figures = kpi_plots(c, rows, kpis) if c.factors else []
    for kpi in kpis[:3]:
        figure = heat_map(c, rows, kpi)
        if figure:
            figures.append(figure)
    title = c.study.title or c.study.name
    verdict = headline(summary)
    intro = (f"Study <b>{html.escape(c.study.name)}</b> on <code>{html.escape(c.study.base)}</code>: "
             f"{c.study.design.kind} design, factors {html.escape(', '.join(c.factors))}. railbrake "
             f"{html.escape(str(c.manifest.get('railbrake_version')))}, core "
             f"{html.escape(str(c.manifest.get('core_build_hash'))[:12])}.")
    body = [f"<h1>{html.escape(title)}</h1><p class='verdict'>{html.escape(verdict)}</p><p>{intro}</p>"]
    for name, headers, table_rows in tables:
        table = f"<div class='wide'>{_html_table(headers, table_rows)}</div>" if table_rows else "<p>none</p>"
        body.append(f"<h2>{html.escape(name)}</h2>" + table)
    for name, image in figures:
        body.append(f"<h2>{html.escape(name)}</h2><img alt='{html.escape(name)}' src='data:image/png;base64,{image}'>")
    output = Path(output)
    output.parent.mkdir(parents=True, exist_ok=True)
    atomic.write_text(output, f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
                      f"<style>{STYLE}</style></head><body>{''.join(body)}</body></html>")
    md = [f"# {title}", "", f"**{verdict}**", "",
          f"Study `{c.study.name}` on `{c.study.base}`: {c.study.design.kind} design. Plots: {output.name}.", ""]
    for name, headers, table_rows in tables:
        md += [f"## {name}", "", _md_table(headers, table_rows) if table_rows else "none", ""]
    atomic.write_text(output.with_suffix(".md"), "\n".join(md))
    return summary
