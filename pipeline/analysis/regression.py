"""Single least-squares fits: weighted and ordinary lines, the interaction plane, bands.

Every function is NaN-safe (missing cases are skipped and counted in ``n``) and returns
a dict keyed by :data:`LINE_STATS` or :data:`PLANE_STATS`. The ``_ci95_`` names are the
file's variable names; the interval's level is the ``level`` argument (default
:data:`LEVEL`).
"""
from __future__ import annotations

import math
import warnings

import numpy as np
from scipy import stats

#: Statistics of one line fit ``y = intercept + slope·x``.
LINE_STATS = (
    "slope", "intercept", "slope_stderr", "intercept_stderr", "slope_intercept_covariance",
    "slope_ci95_lower", "slope_ci95_upper", "intercept_ci95_lower", "intercept_ci95_upper",
    "rsquared", "n",
)

#: Coefficients of the plane ``z = a + b·x + c·y + d·x·y`` (x = speed, y = radial_load).
PLANE_COEFFICIENTS = ("intercept", "speed", "radial_load", "interaction")

#: Statistics of one plane fit.
PLANE_STATS = (
    tuple(PLANE_COEFFICIENTS)
    + tuple(f"{c}_stderr" for c in PLANE_COEFFICIENTS)
    + ("interaction_ci95_lower", "interaction_ci95_upper", "rsquared", "n")
)

#: Confidence level of the reported intervals.
LEVEL = 0.95


def student_t(level: float, dof: int) -> float:
    """Two-sided Student quantile ``t`` such that ``P(|T| ≤ t) = level`` with ``dof`` degrees of freedom."""
    return float(stats.t.ppf(0.5 + level / 2.0, dof))


def _line_result(out: dict, slope, intercept, se_b, se_a, cov, t, rsquared) -> dict:
    """Fill the :data:`LINE_STATS` of ``out`` from a fitted line and its errors."""
    out.update(
        slope=float(slope), intercept=float(intercept), slope_stderr=float(se_b),
        intercept_stderr=float(se_a), slope_intercept_covariance=float(cov),
        slope_ci95_lower=slope - t * se_b, slope_ci95_upper=slope + t * se_b,
        intercept_ci95_lower=intercept - t * se_a, intercept_ci95_upper=intercept + t * se_a,
        rsquared=rsquared,
    )
    return out


def weighted_linear_fit(x, y, sigma, level: float = LEVEL) -> dict:
    """Weighted least-squares line ``y = intercept + slope·x`` with weights ``1/σ²``.

    Parameters
    ----------
    x, y : array_like
        Abscissae and ordinates (ensemble means) [any unit]; NaN points are skipped.
    sigma : array_like
        Standard error of each ``y`` [unit of y]. Where any finite point lacks a positive
        finite σ, the fit falls back to :func:`linear_fit` (ordinary least squares).
    level : float
        Confidence level of the intervals [1].

    Returns
    -------
    dict
        The keys of :data:`LINE_STATS`.

    Notes
    -----
    With ``W = diag(1/σ²)`` and ``X = [1, x]``: ``β = (XᵀWX)⁻¹XᵀWy``. The covariance is
    ``s²·(XᵀWX)⁻¹`` with ``s² = Σ wᵢrᵢ²/(n − 2)`` (the weights fix the relative
    precision; the scatter about the line sets the scale, as ``curve_fit`` does with
    ``absolute_sigma=False``). R² is the weighted coefficient of determination.
    """
    x = np.asarray(x, dtype=np.float64).ravel()
    y = np.asarray(y, dtype=np.float64).ravel()
    sg = np.asarray(sigma, dtype=np.float64).ravel()
    ok = np.isfinite(x) & np.isfinite(y)
    if not np.all(np.isfinite(sg[ok]) & (sg[ok] > 0)):
        return linear_fit(x, y, level)
    n = int(ok.sum())
    out = {k: math.nan for k in LINE_STATS}
    out["n"] = n
    xs, ys, w = x[ok], y[ok], 1.0 / sg[ok] ** 2
    if n < 3 or np.ptp(xs) == 0.0:
        return out
    design = np.column_stack([np.ones(n), xs])
    normal = design.T @ (w[:, None] * design)
    beta = np.linalg.solve(normal, design.T @ (w * ys))
    resid = ys - design @ beta
    s2 = float(np.sum(w * resid**2) / (n - 2))
    cov = s2 * np.linalg.inv(normal)
    se_a, se_b = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
    ybar = np.sum(w * ys) / np.sum(w)
    sst = float(np.sum(w * (ys - ybar) ** 2))
    return _line_result(out, float(beta[1]), float(beta[0]), se_b, se_a, cov[0, 1], student_t(level, n - 2),
                        1.0 - float(np.sum(w * resid**2)) / sst if sst > 0 else math.nan)


def linear_fit(x, y, level: float = LEVEL) -> dict:
    """Ordinary least-squares line ``y = intercept + slope·x``, NaN-safe.

    Parameters
    ----------
    x : array_like
        Abscissae [any unit].
    y : array_like
        Ordinates [any unit]; NaN (missing cases) are skipped with their ``x``.
    level : float
        Confidence level of the intervals [1].

    Returns
    -------
    dict
        The keys of :data:`LINE_STATS`. ``n`` is the number of finite points used; with
        ``n < 3`` or a single distinct ``x`` every other entry is NaN.

    Notes
    -----
    The fit is :func:`scipy.stats.linregress`. With ``s_b`` and ``s_a`` its slope and
    intercept standard errors and ``x̄`` the mean abscissa, the covariance of the two is
    ``cov(a, b) = −x̄·s_b²``, and the intervals are ``b ± t·s_b`` and ``a ± t·s_a`` with
    ``t`` the two-sided Student quantile for ``n − 2`` degrees of freedom. The standard
    error of the fitted line at ``x₀`` is ``√(s_a² + x₀²·s_b² + 2·x₀·cov(a, b))``
    (:func:`line_band`).
    """
    x = np.asarray(x, dtype=np.float64).ravel()
    y = np.asarray(y, dtype=np.float64).ravel()
    ok = np.isfinite(x) & np.isfinite(y)
    n = int(ok.sum())
    out = {k: math.nan for k in LINE_STATS}
    out["n"] = n
    if n < 3:
        return out
    xs, ys = x[ok], y[ok]
    if np.ptp(xs) == 0.0:
        return out
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        r = stats.linregress(xs, ys)
    se_b = float(r.stderr)
    return _line_result(out, float(r.slope), float(r.intercept), se_b, float(r.intercept_stderr),
                        -float(xs.mean()) * se_b**2, student_t(level, n - 2), float(r.rvalue) ** 2)


def plane_fit(x, y, z, level: float = LEVEL) -> dict:
    """Least-squares plane with interaction ``z = a + b·x + c·y + d·x·y``, NaN-safe.

    Parameters
    ----------
    x, y : array_like
        The two regressors [any units], same shape as ``z``.
    z : array_like
        The response [any unit]; NaN points are skipped.
    level : float
        Confidence level of the interaction interval [1].

    Returns
    -------
    dict
        The keys of :data:`PLANE_STATS` (``intercept`` = a, ``speed`` = b,
        ``radial_load`` = c, ``interaction`` = d). With ``n ≤ 4`` or a rank-deficient
        design every entry but ``n`` is NaN.

    Notes
    -----
    With the design ``X = [1, x, y, x·y]`` the coefficients solve ``min ‖X·β − z‖``
    (:func:`numpy.linalg.lstsq`, on columns scaled to unit norm for conditioning) and
    their covariance is ``s²·(XᵀX)⁻¹`` with ``s² = ‖z − X·β‖²/(n − 4)``; ``R² = 1 −
    RSS/TSS``. The interval on ``d`` is ``d ± t·s_d`` with ``n − 4`` degrees of freedom.
    """
    x = np.asarray(x, dtype=np.float64).ravel()
    y = np.asarray(y, dtype=np.float64).ravel()
    z = np.asarray(z, dtype=np.float64).ravel()
    ok = np.isfinite(x) & np.isfinite(y) & np.isfinite(z)
    n = int(ok.sum())
    out = {k: math.nan for k in PLANE_STATS}
    out["n"] = n
    p = len(PLANE_COEFFICIENTS)
    if n <= p:
        return out
    xs, ys, zs = x[ok], y[ok], z[ok]
    design = np.column_stack([np.ones(n), xs, ys, xs * ys])
    scale = np.sqrt((design**2).sum(axis=0))
    if np.any(scale == 0.0):
        return out
    scaled = design / scale
    coef_s, _, rank, _ = np.linalg.lstsq(scaled, zs, rcond=None)
    if rank < p:
        return out
    resid = zs - scaled @ coef_s
    rss = float(resid @ resid)
    dof = n - p
    s2 = rss / dof
    _, sing, vt = np.linalg.svd(scaled, full_matrices=False)
    cov_s = s2 * (vt.T / sing**2) @ vt
    coef = coef_s / scale
    cov = cov_s / np.outer(scale, scale)
    se = np.sqrt(np.diag(cov))
    tss = float(((zs - zs.mean()) ** 2).sum())
    t = student_t(level, dof)
    for k, name in enumerate(PLANE_COEFFICIENTS):
        out[name] = float(coef[k])
        out[f"{name}_stderr"] = float(se[k])
    out["interaction_ci95_lower"] = out["interaction"] - t * out["interaction_stderr"]
    out["interaction_ci95_upper"] = out["interaction"] + t * out["interaction_stderr"]
    out["rsquared"] = 1.0 - rss / tss if tss > 0 else math.nan
    return out


def line_band(fit: dict, x, level: float = LEVEL):
    """The fitted line and its confidence band at ``x``.

    Parameters
    ----------
    fit : dict or mapping
        ``slope``, ``intercept``, ``slope_stderr``, ``intercept_stderr``,
        ``slope_intercept_covariance`` and ``n`` of a :func:`linear_fit`.
    x : array_like
        Abscissae [unit of the fit's x].
    level : float
        Confidence level [1].

    Returns
    -------
    y, lower, upper : ndarray
        The line and the band of the mean response [unit of the fit's y].

    Notes
    -----
    ``ŷ = a + b·x``, ``s(ŷ) = √(s_a² + x²·s_b² + 2·x·cov(a, b))``, band ``ŷ ± t·s(ŷ)``
    with ``n − 2`` degrees of freedom.
    """
    x = np.asarray(x, dtype=np.float64)
    g = {k: float(fit[k]) for k in ("slope", "intercept", "slope_stderr", "intercept_stderr",
                                     "slope_intercept_covariance", "n")}
    y = g["intercept"] + g["slope"] * x
    if not g["n"] >= 3 or not math.isfinite(g["slope"]):
        nan = np.full_like(x, np.nan)
        return y, nan, nan
    var = g["intercept_stderr"] ** 2 + x**2 * g["slope_stderr"] ** 2 + 2 * x * g["slope_intercept_covariance"]
    t = student_t(level, int(g["n"]) - 2)
    half = t * np.sqrt(np.clip(var, 0.0, None))
    return y, y - half, y + half

