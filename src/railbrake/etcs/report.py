"""A braking model's one-file HTML report and its text table."""

from __future__ import annotations

import html
import io

import numpy as np
from scipy.stats import norm

from railbrake import atomic
from railbrake.etcs import confidence, importance, mixture
from railbrake.etcs.model import BrakingModel, braking_distance


def table_text(m: BrakingModel) -> str:
    head = "V from km/h  A m/s2 " + " ".join(f"{f'EBCL {i}':>11}" for i in range(len(confidence.EBCL)))
    rows = [f"{v:>11.0f}  {a:6.3f} " + " ".join(f"{k:>11.2f}" for k in step)
            for v, a, step in zip(m.speed_steps_kmh, m.a_brake_emergency, m.kdry_coded())]
    return "\n".join(["Kdry_rst (coded) per speed step and EBCL", head, *rows,
                      f"Kwet_rst {m.kwet_coded():.2f} ({m.kwet:.4f}), T_brake_emergency {m.t_brake_emergency:.2f} s",
                      *(f"warning: {w}" for w in m.warnings)])


def figure(m: BrakingModel):
    """The deceleration ratio's distribution per speed step on a normal probability scale, the ten
    confidence levels marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 5))
    for j, v in enumerate(m.speed_steps_kmh):
        states = [mixture.State.of(s["probability"], r[j], s["label"]) for s, r in zip(m.states, m.ratios)]
        low, high = min(float(s.ratios[0]) for s in states), max(float(s.ratios[-1]) for s in states)
        x = np.linspace(low - 0.05, high + 0.02, 400)
        cdf = np.array([mixture.mixture_cdf(states, xi) for xi in x])
        keep = (cdf > 1e-12) & (cdf < 1 - 1e-12)
        ax.plot(x[keep], norm.ppf(cdf[keep]), label=f"from {v:.0f} km/h")
    for i, c in enumerate(confidence.EBCL):
        ax.axhline(norm.ppf(1 - c), color="grey", lw=0.5)
        ax.text(ax.get_xlim()[0], norm.ppf(1 - c), f" M_NVEBCL {i}", va="bottom", fontsize=7, color="grey")
    ax.set_xlabel("deceleration ratio to A_brake_emergency")
    ax.set_ylabel("probit of P(ratio below)")
    ax.legend(fontsize=8)
    return fig


def _rows(cells: list) -> str:
    return "".join("<tr>" + "".join(f"<td>{c}</td>" for c in row) + "</tr>" for row in cells)


def write(m: BrakingModel, path, max_states: int = 40) -> None:
    """The report: inputs and their digests, initial speed, A_brake_emergency, Kdry_rst coded with
    the unrounded values and their bounds, the deciding states, Kwet_rst and its test pairs, the
    failure states (the most likely `max_states`) and each failure's effect alone, the warnings."""
    from railbrake.etcs.export import inputs_of
    buffer = io.StringIO()
    fig = figure(m)
    fig.savefig(buffer, format="svg")
    import matplotlib.pyplot as plt
    plt.close(fig)
    esc = html.escape
    levels = range(len(confidence.EBCL))
    names = "".join(f"<th>{i}<br>{confidence.ebcl_text(i)}</th>" for i in levels)
    bounds = m.kdry_bounds or [[(0.0, 0.0)] * len(confidence.EBCL)] * len(m.kdry)
    kdry = _rows([[f"{v:.0f}", f"{a:.3f}"] + [f"<b>{c:.2f}</b><br>{k:.4f} &minus;{b[0]:.4f} +{b[1]:.4f}"
                                              for c, k, b in zip(coded, raw, bnd)]
                  for v, a, coded, raw, bnd in zip(m.speed_steps_kmh, m.a_brake_emergency, m.kdry_coded(), m.kdry,
                                                   bounds)])
    deciding = _rows([[i] + [esc(d[i]) for d in m.deciding] for i in levels])
    distances = _rows([[i, confidence.ebcl_text(i), f"{braking_distance(m, i, 0.0):.0f}",
                        f"{braking_distance(m, i, 1.0):.0f}"] for i in levels])
    pairs = _rows([[f"{p['speed_kmh']:.0f}", f"{p['dry_deceleration_distance_m']:.1f}",
                    f"{p['reduced_deceleration_distance_m']:.1f}", f"{p['increase_percent']:.2f}",
                    f"{p['kwet']:.4f}"] for p in m.kwet_pairs])
    kwet_steps = _rows([[f"{v:.0f}", f"{k:.4f}", f"{c:.2f}"]
                        for v, k, c in zip(m.speed_steps_kmh, m.kwet_steps or [m.kwet] * len(m.kdry),
                                           m.kwet_steps_coded())])
    states = _rows([[esc(s["label"]), f"{s['probability']:.3e}", s["runs"],
                     " ".join(f"{r:.3f}" for r in s["mean_ratio"])] for s in m.states[:max_states]])
    effects_ = _rows([[esc(e.get("common_cause") or e["kind"]), e["unit"], esc(str(e["car_type"] or "")),
                       " ".join(f"{r:.3f}" for r in e["ratio"]),
                       f"{e['drop_of_share']:.2f}" if "drop_of_share" in e else "",
                       "no effect on this brake" if e["no_effect"] else ""] for e in m.effects])
    ranked = _rows([[i, confidence.ebcl_text(i)] + [f"{esc(e['name'])} ({e['type']}): +{e['largest_gain']:.4f}"
                                                    for e in level["ranking"][:importance.TOP]]
                    for i, level in enumerate(m.importance)])
    warnings_ = "".join(f"<li>{esc(w)}</li>" for w in m.warnings) or "<li>none</li>"
    inputs = inputs_of(m)
    files = "".join(f"<li>{k}: {esc(v['name'])} (SHA-256 {v['sha256']})</li>" if v else f"<li>{k}: none</li>"
                    for k, v in inputs.items())
    svg = buffer.getvalue()[buffer.getvalue().find('<svg'):]
    atomic.write_text(path, f"""<!doctype html><html><head><meta charset="utf-8"><title>ETCS braking model: {esc(m.train)}</title>
<style>body{{font-family:sans-serif;max-width:80em}}td,th{{padding:2px 8px;text-align:right}}</style></head><body>
<h1>ETCS braking model: {esc(m.train)}</h1>
<p>Emergency brake from the initial speed {m.initial_speed_kmh:.0f} km/h; T_brake_emergency {m.t_brake_emergency:.2f} s;
{m.runs} whole-train runs; failure states left out (counted as no brake): {m.unenumerated_probability:.2e}.</p>
<ul>{files}<li>dry condition {esc(m.spec.dry_condition)}, reduced condition {esc(m.spec.reduced_condition)},
seed {m.spec.seed}</li></ul>
<h2>Warnings</h2><ul>{warnings_}</ul>
<h2>A_brake_emergency and Kdry_rst per speed step and M_NVEBCL</h2>
<p>Coded (rounded down from the lower end of the 95 % sampling bound, less the step allowance), then the unrounded
value and its bound ({esc(m.bound_method)}). Step allowance per speed step (the runs' {m.spec.step_ms:g} ms step against 1 ms):
{' '.join(f'{a:.5f}' for a in m.step_allowance) or 'none'}.</p>
<table><tr><th>V from km/h</th><th>A m/s²</th>{names}</tr>{kdry}</table>
<h2>Deceleration ratio per speed step</h2>{svg}
<h2>The deciding failure state at each level</h2>
<table><tr><th>M_NVEBCL</th>{''.join(f'<th>from {v:.0f} km/h</th>' for v in m.speed_steps_kmh)}</tr>{deciding}</table>
<h2>Kwet_rst: EN 15595 test pairs ({esc(m.spec.reduced_condition)})</h2>
<table><tr><th>from km/h</th><th>dry m</th><th>reduced m</th><th>increase %</th><th>Kwet</th></tr>{pairs}</table>
<table><tr><th>V from km/h</th><th>Kwet_rst</th><th>coded</th></tr>{kwet_steps}</table>
<h2>Emergency braking distance from the initial speed (m)</h2>
<table><tr><th>M_NVEBCL</th><th>EBCL</th><th>M_NVAVADH 0</th><th>M_NVAVADH 1</th></tr>{distances}</table>
<h2>What moves Kdry_rst most</h2>
<p>Per M_NVEBCL, the failures, common-cause groups and tolerances whose removal (probability zero, tolerance at
nominal) would raise the unrounded Kdry_rst most, with the largest gain over the speed steps (from the runs made:
exact for the failures, first order for the tolerances).</p>
<table><tr><th>M_NVEBCL</th><th>EBCL</th>{''.join(f'<th>{k + 1}</th>' for k in range(importance.TOP))}</tr>{ranked}</table>
<h2>Each failure alone</h2>
<table><tr><th>failure</th><th>unit</th><th>car type</th><th>ratio per step</th><th>drop / unit share</th><th></th></tr>{effects_}</table>
<h2>Failure states (the {min(max_states, len(m.states))} most likely of {len(m.states)})</h2>
<table><tr><th>state</th><th>probability</th><th>runs</th><th>mean ratio per step</th></tr>{states}</table>
</body></html>""")
