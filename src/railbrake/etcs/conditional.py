"""Kdry_rst given the train's tolerance: conditional Monte Carlo over the one tolerance drawn per train.

A tolerance drawn once per train (the shipped scatter file's pad friction) moves every car's brake
together, so it dominates the spread of the deceleration ratio within a failure state (on the
16-car preset it carries 98 % of the ratio's variance), and read from the runs alone a level's
quantile would need tens of thousands of runs per state to be known within 0.005. Its distribution
is an input, known exactly: only the rest has to come from the runs. Within each state the ratio
is regressed on the run's draw P of that tolerance,

    ratio = a + b P + e,   e ~ N(0, sigma^2)   (the other tolerances: per car or unit, many small
                                                 independent terms, near normal),

and the state's CDF is the regression's averaged over P's own law (conditional Monte Carlo:
Asmussen & Glynn, Stochastic Simulation (2007), V.4; the control of a known input):

    F_s(x) = E_Z[ F_P((x - a - sigma Z) / b) ],  Z standard normal (b > 0; 1 - F_P for b < 0),

integrated over Z on a fixed grid (ZMAX sd, trapezoid): exact as sigma -> 0, and where sigma
dominates the integrand is smooth. A state's ratio is linear in P to the runs' noise on the
presets (a quadratic term changes the residual's sd by less than 1 %: tests/unit/etcs/
test_conditional.py checks the form on a plant's runs).

The sampling bound of a level is the delta method's (first order in each state's estimates: a and
b with their least-squares covariance sigma^2 (X'X)^-1, sigma with sigma^2 / (2 (n - 2)); the
states independent), each state's share inflated by (t_{0.975, n-2} / z_{0.975})^2 for its few
runs, the bound z_{0.975} times the quantile's standard error: the analytic bound of issue 36's
item 3. Used when the scatter file has exactly one tolerance per train; else the bootstrap of the
runs (railbrake.etcs.bound).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.special import ndtr
from scipy.stats import norm, t as student

ZMAX = 10.0           # the residual's normal integrated over +- this many sd
ZPOINTS = 301
H = 1e-3              # the delta method's differences (ratio units): spans several of the Z grid's steps
Z975 = float(norm.ppf(0.975))
CARRY = 1e-3          # a state carries a level if its share of the quantile's variance is at least this


@dataclass(frozen=True)
class Law:
    """The distribution of the train's tolerance (railbrake.etcs.inputs.Distribution), vectorised."""
    kind: str
    mean: float
    sd: float
    low: float
    high: float

    @classmethod
    def of(cls, d) -> "Law":
        low, high = d.bounds if d.bounds is not None else (-np.inf, np.inf)
        return cls(d.distribution, d.mean or 0.0, d.sd or 0.0, float(low), float(high))

    def cdf(self, p: np.ndarray) -> np.ndarray:
        if self.kind == "uniform":
            return np.clip((p - self.low) / (self.high - self.low), 0.0, 1.0)
        if self.sd == 0.0:
            return (p >= self.mean).astype(float)
        if self.kind == "normal":
            return ndtr((p - self.mean) / self.sd)
        lo, hi = ndtr((self.low - self.mean) / self.sd), ndtr((self.high - self.mean) / self.sd)
        return np.clip((ndtr((np.clip(p, self.low, self.high) - self.mean) / self.sd) - lo) / (hi - lo), 0.0, 1.0)

    def pdf(self, p: np.ndarray) -> np.ndarray:
        inside = (p >= self.low) & (p <= self.high)
        if self.kind == "uniform":
            return np.where(inside, 1.0 / (self.high - self.low), 0.0)
        if self.sd == 0.0:
            return np.zeros_like(p)
        dens = np.exp(-0.5 * ((p - self.mean) / self.sd) ** 2) / (self.sd * np.sqrt(2.0 * np.pi))
        if self.kind == "normal":
            return dens
        mass = ndtr((self.high - self.mean) / self.sd) - ndtr((self.low - self.mean) / self.sd)
        return np.where(inside, dens / mass, 0.0)


_Z = np.linspace(-ZMAX, ZMAX, ZPOINTS)
_W = np.exp(-0.5 * _Z ** 2) * np.where(np.isin(np.arange(ZPOINTS), (0, ZPOINTS - 1)), 0.5, 1.0)
_W /= _W.sum()


@dataclass
class Fits:
    """Every state's regression on the train's tolerance (arrays over the states)."""
    law: Law
    probability: np.ndarray
    a: np.ndarray
    b: np.ndarray
    sigma: np.ndarray
    n: np.ndarray
    cov_ab: np.ndarray        # (states, 2, 2): the covariance of (a, b)
    var_sigma: np.ndarray

    @classmethod
    def of(cls, law: Law, probabilities, ratios: list, factors: list) -> "Fits":
        """The fits of states' samples `ratios` (one 1-D array each) against their runs' draws
        `factors` of the train's tolerance."""
        rows = [_fit(np.asarray(r, float), np.asarray(p, float)) for r, p in zip(ratios, factors)]
        a, b, sigma, n, cov, var_sigma = (np.array(x) for x in zip(*rows))
        return cls(law, np.asarray(probabilities, float), a, b, sigma, n, cov, var_sigma)

    def cdfs(self, x: float, a=None, b=None, sigma=None) -> np.ndarray:
        """Each state's CDF at x (its fit, or the a, b, sigma given)."""
        a = self.a if a is None else a
        b = self.b if b is None else b
        sigma = self.sigma if sigma is None else sigma
        shifted = x - a[:, None] - sigma[:, None] * _Z[None, :]
        flat = np.abs(b) < 1e-12
        safe_b = np.where(flat, 1.0, b)[:, None]
        f = self.law.cdf(shifted / safe_b)
        f = np.where((b < 0.0)[:, None], 1.0 - f, f) @ _W
        if flat.any():   # no slope: the residual's normal alone (a step without spread)
            z = (x - a) / np.where(sigma > 0.0, sigma, 1.0)
            f = np.where(flat, np.where(sigma > 0.0, ndtr(z), (x >= a).astype(float)), f)
        return f

    def mixture_cdf(self, x: float, missing: float = 0.0) -> float:
        return float(missing + self.probability @ self.cdfs(x))

    def quantile(self, level: float, missing: float = 0.0) -> float:
        """x with the mixture's CDF at `level` (the states left out count as ratio 0)."""
        if missing >= level:
            return 0.0
        lo = float(np.min(self.a + np.minimum(self.b * self.law.low if np.isfinite(self.law.low) else -10.0,
                                              self.b * self.law.high if np.isfinite(self.law.high) else -10.0)
                          - (ZMAX + 1.0) * self.sigma)) - 1.0
        hi = float(np.max(self.a + np.abs(self.b) * (self.law.high if np.isfinite(self.law.high) else 10.0)
                          + (ZMAX + 1.0) * self.sigma)) + 1.0
        return brentq(lambda x: self.mixture_cdf(x, missing) - level, lo, hi, xtol=1e-10, rtol=1e-12)

    def bound(self, level: float, x: float) -> tuple[float, np.ndarray]:
        """(half-width of the 95 % bound of the quantile x at `level`, each state's share of its
        variance): the delta method, each state's variance inflated for its few runs."""
        h = H
        f_x = (self.probability @ (self.cdfs(x + h) - self.cdfs(x - h))) / (2 * h)   # the mixture's density
        if f_x <= 0.0:
            return 0.0, np.zeros_like(self.probability)
        da = (self.cdfs(x, a=self.a + h) - self.cdfs(x, a=self.a - h)) / (2 * h)
        db = (self.cdfs(x, b=self.b + h) - self.cdfs(x, b=self.b - h)) / (2 * h)
        ds = (self.cdfs(x, sigma=self.sigma + h) - self.cdfs(x, sigma=np.maximum(self.sigma - h, 0.0))) / \
            (h + np.minimum(self.sigma, h))
        g = np.stack([da, db], axis=1)
        var_f = np.einsum("si,sij,sj->s", g, self.cov_ab, g) + ds ** 2 * self.var_sigma
        inflation = (student.ppf(0.975, np.maximum(self.n - 2, 1)) / Z975) ** 2
        per_state = self.probability ** 2 * var_f * inflation
        total = float(per_state.sum())
        shares = per_state / total if total > 0.0 else per_state
        return Z975 * np.sqrt(total) / f_x, shares


def _fit(r: np.ndarray, p: np.ndarray) -> tuple:
    """(a, b, sigma, n, cov(a, b), var(sigma)) of the least squares r = a + b p + e."""
    n = r.size
    if n < 3 or np.ptp(p) == 0.0 or np.ptp(r) == 0.0:   # no slope to read: the mean and spread alone
        sd = float(r.std(ddof=1)) if n > 1 else 0.0
        cov = np.diag([sd ** 2 / n, 0.0])
        return float(r.mean()), 0.0, sd, n, cov, sd ** 2 / (2.0 * max(n - 1, 1))
    x = np.column_stack([np.ones(n), p])
    xtx_inv = np.linalg.inv(x.T @ x)
    coef = xtx_inv @ (x.T @ r)
    resid = r - x @ coef
    s2 = float(resid @ resid) / (n - 2)
    return float(coef[0]), float(coef[1]), float(np.sqrt(s2)), n, s2 * xtx_inv, s2 / (2.0 * (n - 2))
