"""Designs: which factor values each point of a study takes.

grid: the full factorial of the levels; zip: the i-th level of every factor together;
latin-hypercube and sobol: ``scipy.stats.qmc`` samples of the unit cube mapped onto the ranges
(or onto the levels of a list); list: the points written in the study. A Sobol design is
Saltelli's scheme A, B, AB_i (N (d + 2) points) so that the report can give Sobol indices
(scipy.stats.sobol_indices). The designs' random numbers come from the study's SeedSequence.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from railbrake.campaign.study import Study


@dataclass
class Point:
    values: dict                 # factor name -> file value
    block: str = ""              # sobol: A, B or AB<i>
    sample: int = -1             # sobol: row of the base samples


def _unit_cube(study: Study, points: np.ndarray, block: str = ""):
    for row, u in enumerate(points):
        yield Point({f.name: f.at(float(x)) for f, x in zip(study.factors, u)}, block, row if block else -1)


def _sobol(study: Study, generator: np.random.Generator):
    from scipy.stats import qmc   # scipy.stats takes about a second to import: only for these designs
    d, n = len(study.factors), study.spec.design.samples
    base = qmc.Sobol(2 * d, scramble=study.spec.design.scramble, seed=generator).random(n)
    a, b = base[:, :d], base[:, d:]
    yield from _unit_cube(study, a, "A")
    yield from _unit_cube(study, b, "B")
    for i in range(d):
        ab = a.copy()
        ab[:, i] = b[:, i]
        yield from _unit_cube(study, ab, f"AB{i}")


def points(study: Study, generator: np.random.Generator):
    """The design's points, one at a time (a grid of 10^5 points is never a list); the samples of
    a latin-hypercube or Sobol design are drawn at the first point, as one array of numbers."""
    design = study.spec.design
    names = [f.name for f in study.factors]
    if design.kind == "grid":
        return (Point(dict(zip(names, combo))) for combo in itertools.product(*(f.levels for f in study.factors)))
    if design.kind == "zip":
        return (Point(dict(zip(names, combo))) for combo in zip(*(f.levels for f in study.factors)))
    if design.kind == "latin-hypercube":
        from scipy.stats import qmc
        sample = qmc.LatinHypercube(len(names), seed=generator).random(design.samples)
        return _unit_cube(study, sample)
    if design.kind == "sobol":
        return _sobol(study, generator)
    return (Point(dict(p)) for p in design.points)
