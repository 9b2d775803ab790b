"""Plots for the CLI and reports (matplotlib, non-interactive backend). Human units on axes."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402


def new_figure(nrows: int = 1, ncols: int = 1, **kwargs):
    kwargs.setdefault("figsize", (8, 4.5 * nrows))
    kwargs.setdefault("constrained_layout", True)
    return plt.subplots(nrows, ncols, **kwargs)


def save(fig, path) -> None:
    fig.savefig(path, dpi=120)
    plt.close(fig)
