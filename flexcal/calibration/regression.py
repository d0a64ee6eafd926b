"""Straight-line fits with their uncertainties: ordinary least squares and errors-in-variables.

``ols`` is the textbook fit (standard errors from the residuals). ``york`` is the
weighted orthogonal-distance line for data with errors on both axes (York, Evensen,
Martínez and Delgado, Am. J. Phys. 72, 367 (2004)): it is what ODRPACK computes for a
straight line, in closed form. ``scipy.odr`` would do, but it is deprecated from SciPy
1.17 and leaves in 1.19; a line needs no general ODR package. Its standard errors are
scaled by the residual variance, as ``scipy.odr``'s ``sd_beta`` are.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq


@dataclass
class LinearFit:
    """y = slope * x + intercept, with standard errors, covariance [[ss, si], [si, ii]] and fit quality."""

    slope: float
    intercept: float
    slope_se: float
    intercept_se: float
    cov: np.ndarray
    r2: float
    rmse: float
    n: int
    method: str
    residuals: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))
    chi2_red: float = float("nan")
    scatter_y: float = 0.0

    def __call__(self, x):
        return self.slope * np.asarray(x, float) + self.intercept

    def inverse(self, y):
        return (np.asarray(y, float) - self.intercept) / self.slope

    def to_dict(self) -> dict:
        return {"form": "y = slope * x + intercept", "method": self.method, "slope": self.slope,
                "intercept": self.intercept, "slope_se": self.slope_se, "intercept_se": self.intercept_se,
                "covariance": np.asarray(self.cov).tolist(), "r2": self.r2, "rmse": self.rmse, "n": self.n,
                "y_scatter": self.scatter_y}


def _check(x, y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.shape != y.shape or x.ndim != 1:
        raise ValueError(f"x and y must be 1-D and of one length, got {x.shape} and {y.shape}")
    if not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise ValueError("x and y must be finite; drop NaN pairs first")
    if x.size < 3 or np.ptp(x) == 0:
        raise ValueError(f"a line needs at least 3 points at 2 or more x values, got {x.size}")
    return x, y


def _quality(x, y, slope, intercept):
    res = y - (slope * x + intercept)
    ss_tot = np.sum((y - y.mean()) ** 2)
    r2 = 1.0 - np.sum(res ** 2) / ss_tot if ss_tot > 0 else float("nan")
    return res, float(r2), float(np.sqrt(np.mean(res ** 2)))


def ols(x, y) -> LinearFit:
    """Ordinary least squares of y on x, by a QR-based solve (numerically careful:
    reproduces NIST StRD certified values)."""
    x, y = _check(x, y)
    a = np.column_stack([x, np.ones_like(x)])
    q, r = np.linalg.qr(a)
    coef = np.linalg.solve(r, q.T @ y)
    res, r2, rmse = _quality(x, y, *coef)
    dof = x.size - 2
    s2 = float(res @ res) / dof if dof > 0 else float("nan")
    rinv = np.linalg.inv(r)
    cov = s2 * (rinv @ rinv.T)
    return LinearFit(float(coef[0]), float(coef[1]), float(np.sqrt(cov[0, 0])), float(np.sqrt(cov[1, 1])),
                     cov, r2, rmse, int(x.size), "ols", res)


def york(x, y, sx, sy, *, scatter: bool = False, tol: float = 1e-12, max_iter: int = 200) -> LinearFit:
    """Weighted orthogonal-distance (errors-in-variables) line.

    Parameters
    ----------
    x, y : (N,) arrays
    sx, sy : float or (N,) arrays
        One-sigma errors of x and y, positive.
    scatter : bool
        Also estimate the scatter of y about the line that ``sx`` and ``sy`` do not
        explain (the sensor's repeatability, for example), and add it to ``sy`` in
        quadrature so that the reduced chi-square is 1. Without it, a tiny ``sy``
        (the spread of a mean of many samples) would let the fit treat y as exact.
        The value found is in the result's ``method`` text.
    """
    if scatter:
        x, y = _check(x, y)
        sy0 = np.broadcast_to(np.asarray(sy, float), y.shape)

        def excess(s):
            return york(x, y, sx, np.hypot(sy0, s)).chi2_red - 1.0

        s = 0.0
        if excess(0.0) > 0:
            hi = float(np.std(y)) + 1.0
            s = float(brentq(excess, 0.0, hi, xtol=1e-9 * hi)) if excess(hi) < 0 else hi
        f = york(x, y, sx, np.hypot(sy0, s))
        f.method = f"odr (York; y scatter {s:.4g} added)"
        f.scatter_y = s
        return f
    x, y = _check(x, y)
    sx = np.broadcast_to(np.asarray(sx, float), x.shape)
    sy = np.broadcast_to(np.asarray(sy, float), y.shape)
    if not (np.all(sx > 0) and np.all(sy > 0) and np.isfinite(sx).all() and np.isfinite(sy).all()):
        raise ValueError("sx and sy must be positive and finite")
    wx, wy = 1.0 / sx ** 2, 1.0 / sy ** 2
    b = ols(x, y).slope
    for _ in range(max_iter):
        w = wx * wy / (wx + b * b * wy)
        xbar, ybar = np.sum(w * x) / w.sum(), np.sum(w * y) / w.sum()
        u, v = x - xbar, y - ybar
        beta = w * (u / wy + b * v / wx)
        b_new = np.sum(w * beta * v) / np.sum(w * beta * u)
        done = abs(b_new - b) <= tol * max(abs(b), 1e-300)
        b = b_new
        if done:
            break
    w = wx * wy / (wx + b * b * wy)
    xbar, ybar = np.sum(w * x) / w.sum(), np.sum(w * y) / w.sum()
    a = ybar - b * xbar
    beta = w * ((x - xbar) / wy + b * (y - ybar) / wx)
    xadj = xbar + beta
    xm = np.sum(w * xadj) / w.sum()
    var_b = 1.0 / np.sum(w * (xadj - xm) ** 2)
    var_a = 1.0 / w.sum() + xm * xm * var_b
    cov_ab = -xm * var_b
    chi2 = float(np.sum(w * (y - b * x - a) ** 2))
    scale = chi2 / (x.size - 2) if x.size > 2 else 1.0
    cov = scale * np.array([[var_b, cov_ab], [cov_ab, var_a]])
    res, r2, rmse = _quality(x, y, b, a)
    fit = LinearFit(float(b), float(a), float(np.sqrt(cov[0, 0])), float(np.sqrt(cov[1, 1])), cov, r2, rmse,
                    int(x.size), "odr (York)", res)
    fit.chi2_red = scale
    return fit
