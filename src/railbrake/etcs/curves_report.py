"""The braking curves' plot and one-file HTML page."""

from __future__ import annotations

import html
import io

from railbrake import atomic

STYLES = {"EBD": ("#b00", "-"), "EBI": ("#e33", "--"), "SBD": ("#06c", "-"), "SBI1": ("#39f", "--"),
          "SBI2": ("#f80", "--"), "W": ("#fb0", ":"), "P": ("#2a2", "-"), "I": ("#888", ":"), "GUI": ("#a5c", "-.")}


def figure(result: dict):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 5))
    for name, points in result["curves"].items():
        color, style = STYLES.get(name, ("k", "-"))
        ax.plot([p[0] for p in points], [p[1] for p in points], style, color=color, label=name)
    ax.axvline(result["eoa_m"], color="k", lw=0.8)
    ax.text(result["eoa_m"], 0, " EoA", va="bottom", fontsize=8)
    if result["svl_m"] != result["eoa_m"]:
        ax.axvline(result["svl_m"], color="k", lw=0.8, ls="--")
        ax.text(result["svl_m"], 5, " SvL", va="bottom", fontsize=8)
    ax.set_xlabel("distance along the track, m")
    ax.set_ylabel("speed, km/h")
    ax.set_title(f"{result['train']} on {result['track']}: ETCS braking curves")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def write(result: dict, html_path, png_path=None) -> None:
    import matplotlib.pyplot as plt
    fig = figure(result)
    buffer = io.StringIO()
    fig.savefig(buffer, format="svg")
    if png_path is not None:
        atomic.save_figure(fig, png_path, dpi=120)
    plt.close(fig)
    svg = buffer.getvalue()
    nv = "".join(f"<tr><td>{html.escape(str(k))}</td><td>{html.escape(str(v))}</td></tr>"
                 for k, v in result["national_values"].items())
    ts = "".join(f"<tr><td>{k}</td><td>{v:.3f}</td></tr>" for k, v in result["times_s"].items())
    top = "".join(f"<tr><td>{n}</td><td>{c[0][0]:.0f}</td><td>{c[0][1]:.0f}</td></tr>"
                  for n, c in result["curves"].items())
    atomic.write_text(html_path, f"""<!doctype html><html><head><meta charset="utf-8"><title>ETCS braking curves: {html.escape(result['train'])}</title>
<style>body{{font-family:sans-serif;max-width:70em}}td,th{{padding:2px 8px;text-align:right}}</style></head><body>
<h1>ETCS braking curves: {html.escape(result['train'])} on {html.escape(result['track'])}</h1>
<p>EoA {result['eoa_m']:.0f} m, SvL {result['svl_m']:.0f} m, target speed 0; UNISIG SUBSET-026 3.13.</p>
{svg[svg.find('<svg'):]}
<h2>Where each curve starts (top speed)</h2><table><tr><th>curve</th><th>distance m</th><th>km/h</th></tr>{top}</table>
<h2>Times (s)</h2><table>{ts}</table>
<h2>National values</h2><table>{nv}</table>
</body></html>""")
