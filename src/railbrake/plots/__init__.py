"""Plots for the CLI, reports and scripts (matplotlib). Human units on axes.

Outside a Jupyter kernel the backend is the non-interactive Agg (the CLI and reports only write
files); inside one the kernel's inline backend stays, so a figure a script asks for shows
(railbrake.plots.figures, imported first so every module here draws on it)."""

from railbrake.plots.figures import new_figure, save

__all__ = ["new_figure", "save"]
