"""A braking model's one-file HTML report and its text table."""

from __future__ import annotations

import html
import io

import numpy as np
from scipy.stats import norm

from railbrake import atomic
from railbrake.etcs import confidence, mixture
from railbrake.etcs.model import BrakingModel, braking_distance


def table_text(m: BrakingModel) -> str:
    head = "V from km/h  A m/s2 " + " ".join(f"{f'EBCL {i}':>11}" for i in range(len(confidence.EBCL)))
    rows = [f"{v:>11.0f}  {a:6.3f} " + " ".join(f"{k:>11.2f}" for k in step)
            for v, a, step in zip(m.speed_steps_kmh, m.a_brake_emergency, m.kdry_coded())]
    return "\n".join(["Kdry_rst (coded) per speed step and EBCL", head, *rows,
                      f"Kwet_rst {m.kwet_coded():.2f} ({m.kwet:.4f}), T_brake_emergency {m.t_brake_emergency:.2f} s"])


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


def write(m: BrakingModel, path) -> None:
    buffer = io.StringIO()
    fig = figure(m)
    fig.savefig(buffer, format="svg")
    import matplotlib.pyplot as plt
    plt.close(fig)
    levels = range(len(confidence.EBCL))
    distances = "".join(
        f"<tr><td>{i}</td><td>{confidence.EBCL[i] * 100:.7g} %</td><td>{braking_distance(m, i, 0.0):.0f}</td>"
        f"<td>{braking_distance(m, i, 1.0):.0f}</td></tr>" for i in levels)
    kdry = "".join(f"<tr><td>{v:.0f}</td><td>{a:.3f}</td>" + "".join(f"<td>{k:.2f}</td>" for k in step) + "</tr>"
                   for v, a, step in zip(m.speed_steps_kmh, m.a_brake_emergency, m.kdry_coded()))
    deciding = "".join(f"<tr><td>{i}</td>" + "".join(f"<td>{html.escape(d[i])}</td>" for d in m.deciding) + "</tr>"
                       for i in levels)
    atomic.write_text(path, f"""<!doctype html><html><head><meta charset="utf-8"><title>ETCS braking model: {html.escape(m.train)}</title>
<style>body{{font-family:sans-serif;max-width:70em}}td,th{{padding:2px 8px;text-align:right}}</style></head><body>
<h1>ETCS braking model: {html.escape(m.train)}</h1>
<p>T_brake_emergency {m.t_brake_emergency:.2f} s; Kwet_rst {m.kwet_coded():.2f} ({m.kwet:.4f}, the worse EN 15595
test pair); {m.runs} whole-train runs.</p>
<h2>A_brake_emergency and Kdry_rst (coded) per speed step and M_NVEBCL</h2>
<table><tr><th>V from km/h</th><th>A m/s²</th>{''.join(f'<th>{i}</th>' for i in levels)}</tr>{kdry}</table>
<h2>Deceleration ratio per speed step</h2>{buffer.getvalue()[buffer.getvalue().find('<svg'):]}
<h2>The failure state most likely at each level's quantile</h2>
<table><tr><th>M_NVEBCL</th>{''.join(f'<th>from {v:.0f} km/h</th>' for v in m.speed_steps_kmh)}</tr>{deciding}</table>
<h2>Emergency braking distance from the initial speed (m)</h2>
<table><tr><th>M_NVEBCL</th><th>EBCL</th><th>M_NVAVADH 0</th><th>M_NVAVADH 1</th></tr>{distances}</table>
</body></html>""")
