"""The figures' common ground: matplotlib's backend and a new figure, saved and closed.

Outside a Jupyter kernel the backend is the non-interactive Agg (the CLI and reports only write
files); inside one the kernel's inline backend stays, so a figure a script asks for shows."""

from __future__ import annotations

import sys

import matplotlib

if "ipykernel" not in sys.modules:
    matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from railbrake.errors import InputError  # noqa: E402


MAX_PANELS = 20   # rows or columns of one figure: a software limit on what is drawn

def new_figure(nrows: int = 1, ncols: int = 1, **kwargs):
    from railbrake._args import whole
    nrows, ncols = whole("nrows", nrows, 1, MAX_PANELS), whole("ncols", ncols, 1, MAX_PANELS)
    kwargs.setdefault("figsize", (8, 4.5 * nrows))
    kwargs.setdefault("constrained_layout", True)
    return plt.subplots(nrows, ncols, **kwargs)


def save(fig, path):
    """The figure written to path and closed (returns path); path None: the open figure itself."""
    if path is None:
        return fig
    from railbrake import _args, atomic
    path = _args.path("path", path)
    if not path.parent.is_dir():
        raise InputError(f"path = {_args.show(str(path))}: no folder {path.parent} to write it into")
    atomic.save_figure(fig, path, dpi=120)   # whole or absent
    plt.close(fig)
    return path
