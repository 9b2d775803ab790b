"""The figures' common ground: matplotlib's backend and a new figure, saved and closed.

Outside a Jupyter kernel the backend is the non-interactive Agg (the CLI and reports only write
files); inside one the kernel's inline backend stays, so a figure a script asks for shows."""

from __future__ import annotations

import sys

import matplotlib

if "ipykernel" not in sys.modules:
    matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402


def new_figure(nrows: int = 1, ncols: int = 1, **kwargs):
    kwargs.setdefault("figsize", (8, 4.5 * nrows))
    kwargs.setdefault("constrained_layout", True)
    return plt.subplots(nrows, ncols, **kwargs)


def save(fig, path):
    """The figure written to path and closed (returns path); path None: the open figure itself."""
    if path is None:
        return fig
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
