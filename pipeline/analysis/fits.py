"""Least-squares trends of the phase metrics over the sweep axes (``fits.nc``).

Two kinds of fit are made for every metric variable of ``metrics.nc`` and every phase:

- an ordinary least-squares **line** against each sweep axis (``speed``, ``radial_load``)
  at every value of the other axis (and of any extra dimension), by
  :func:`scipy.stats.linregress`;
- a **plane with interaction** over both axes, ``z = a + b·x + c·y + d·x·y``, by
  :func:`numpy.linalg.lstsq` with the classical covariance ``s²·(XᵀX)⁻¹``.

Missing cases (NaN) are skipped and the number of points used is reported as ``n``.
A line needs at least 3 points (one residual degree of freedom), a plane at least 5;
with fewer, or with a degenerate design (e.g. a single distinct axis value), every
statistic is NaN and only ``n`` is set.

Variables of ``fits.nc``, for a group ``M``: ``displacement`` (the six δ_r/δ_a range,
mean and std metrics, all in m, along the int8 flag coordinate ``displacement_metric``
whose ``flag_meanings`` name them), ``cage_slip`` and ``peak_contact_pressure``:

- ``M_vs_speed_<stat>`` over ``([displacement_metric,] radial_load, phase)`` and
  ``M_vs_radial_load_<stat>`` over ``([displacement_metric,] speed, phase)``, with
  ``<stat>`` one of :data:`LINE_STATS`;
- ``M_plane_<stat>`` over ``([displacement_metric,] phase)`` with ``<stat>`` one of
  :data:`PLANE_STATS`.

(Packing the displacement metrics keeps the file small enough for the CF checker, whose
run time grows with the square of the number of variables.) :func:`fit_statistic` reads
one statistic of one metric whatever the packing.

This module also reads reference fit files (``sweeps/reference/*.toml``), the published
(or a user's rig) fits the report compares against: :func:`load_reference_fits`.
"""
from __future__ import annotations

import datetime as _dt
import math
import re
import tomllib
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr
from scipy import stats

from rvcore.profile import PHASES

from ..io import encoding_for
from ..errors import ConfigError, UserError
from ..schema import parse_quantity, registry

#: The sweep axes a line is fitted against, in this order.
AXES = ("speed", "radial_load")

#: Metric variables of ``metrics.nc`` that are fitted (those present are used).
FIT_METRICS = (
    "radial_displacement_range", "radial_displacement_mean", "radial_displacement_std",
    "axial_displacement_range", "axial_displacement_mean", "axial_displacement_std",
    "cage_slip", "peak_contact_pressure",
)

#: The displacement metrics are fitted together, along an int8 flag coordinate.
DISPLACEMENT_METRICS = FIT_METRICS[:6]
DISPLACEMENT_GROUP = "displacement"
DISPLACEMENT_COORD = "displacement_metric"

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

_AXIS_LONG = {"speed": "steady inner-ring speed", "radial_load": "steady radial load"}


# --------------------------------------------------------------------------- single fits


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
    t = float(stats.t.ppf(0.5 + level / 2.0, n - 2))
    ybar = np.sum(w * ys) / np.sum(w)
    sst = float(np.sum(w * (ys - ybar) ** 2))
    intercept, slope = float(beta[0]), float(beta[1])
    out.update(
        slope=slope, intercept=intercept, slope_stderr=se_b, intercept_stderr=se_a,
        slope_intercept_covariance=float(cov[0, 1]),
        slope_ci95_lower=slope - t * se_b, slope_ci95_upper=slope + t * se_b,
        intercept_ci95_lower=intercept - t * se_a, intercept_ci95_upper=intercept + t * se_a,
        rsquared=1.0 - float(np.sum(w * resid**2)) / sst if sst > 0 else math.nan,
    )
    return out


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
    t = float(stats.t.ppf(0.5 + level / 2.0, n - 2))
    slope, intercept = float(r.slope), float(r.intercept)
    se_b, se_a = float(r.stderr), float(r.intercept_stderr)
    out.update(
        slope=slope, intercept=intercept, slope_stderr=se_b, intercept_stderr=se_a,
        slope_intercept_covariance=-float(xs.mean()) * se_b**2,
        slope_ci95_lower=slope - t * se_b, slope_ci95_upper=slope + t * se_b,
        intercept_ci95_lower=intercept - t * se_a, intercept_ci95_upper=intercept + t * se_a,
        rsquared=float(r.rvalue) ** 2,
    )
    return out


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
    t = float(stats.t.ppf(0.5 + level / 2.0, dof))
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
    t = float(stats.t.ppf(0.5 + level / 2.0, int(g["n"]) - 2))
    half = t * np.sqrt(np.clip(var, 0.0, None))
    return y, y - half, y + half


# --------------------------------------------------------------------------- units


def _unit_terms(units: str) -> dict:
    """UDUNITS-style product string (``"degree s-1"``) to ``{token: exponent}``."""
    terms: dict = {}
    for tok in str(units).split():
        if tok == "1":
            continue
        m = re.fullmatch(r"([A-Za-z_]+)(-?\d+)?", tok)
        if not m:
            raise ValueError(f"cannot compose units {units!r}")
        terms[m.group(1)] = terms.get(m.group(1), 0) + int(m.group(2) or 1)
    return terms


def compose_units(numerator: str, *denominators: str, power: int = 1) -> str:
    """``numerator**power / (denominators...)`` as a UDUNITS string.

    >>> compose_units("m", "degree s-1")
    'm s degree-1'
    """
    terms: dict = {}
    for k, v in _unit_terms(numerator).items():
        terms[k] = terms.get(k, 0) + power * v
    for d in denominators:
        for k, v in _unit_terms(d).items():
            terms[k] = terms.get(k, 0) - v
    pos = [f"{k}{'' if v == 1 else v}" for k, v in terms.items() if v > 0]
    neg = [f"{k}{v}" for k, v in terms.items() if v < 0]
    return " ".join(pos + neg) or "1"


def udunits_to_pint(units: str) -> str:
    """A UDUNITS product string as a pint expression (``"degree s-1"`` → ``"degree*s**-1"``)."""
    terms = _unit_terms(units)
    if not terms:
        return "dimensionless"
    return "*".join(f"{k}**{v}" if v != 1 else k for k, v in terms.items())


# --------------------------------------------------------------------------- whole datasets


def _along(da: xr.DataArray, core: tuple, func) -> dict:
    """Apply ``func(values over core dims) -> dict`` at every index of the other dims."""
    other = [d for d in da.dims if d not in core]
    arr = da.transpose(*other, *core).values
    lead = arr.shape[: len(other)]
    flat = arr.reshape((-1,) + arr.shape[len(other):])
    rows = [func(v) for v in flat]
    template = da.isel({d: 0 for d in core}, drop=True)
    out = {}
    for key in rows[0] if rows else ():
        vals = np.array([r[key] for r in rows]).reshape(lead)
        if key == "n":
            vals = vals.astype(np.int32)
        out[key] = xr.DataArray(vals, dims=other, coords={c: template.coords[c] for c in template.coords})
    return out


def _line_attrs(metric: str, mu: str, mlong: str, axis: str, au: str, stat: str) -> dict:
    other = [a for a in AXES if a != axis]
    at = f" at each {other[0]}" if other else ""
    what = f"{mlong} against {_AXIS_LONG.get(axis, axis)}"
    units = {
        "slope": compose_units(mu, au), "intercept": mu,
        "slope_stderr": compose_units(mu, au), "intercept_stderr": mu,
        "slope_intercept_covariance": compose_units(mu, au, power=2),
        "slope_ci95_lower": compose_units(mu, au), "slope_ci95_upper": compose_units(mu, au),
        "intercept_ci95_lower": mu, "intercept_ci95_upper": mu, "rsquared": "1", "n": "1",
    }[stat]
    label = {
        "slope": "OLS slope", "intercept": "OLS intercept",
        "slope_stderr": "standard error of the OLS slope",
        "intercept_stderr": "standard error of the OLS intercept",
        "slope_intercept_covariance": "covariance of the OLS slope and intercept",
        "slope_ci95_lower": "lower bound of the 95 % confidence interval of the OLS slope",
        "slope_ci95_upper": "upper bound of the 95 % confidence interval of the OLS slope",
        "intercept_ci95_lower": "lower bound of the 95 % confidence interval of the OLS intercept",
        "intercept_ci95_upper": "upper bound of the 95 % confidence interval of the OLS intercept",
        "rsquared": "coefficient of determination R^2 of the OLS line",
        "n": "number of finite points in the OLS line",
    }[stat]
    return {"units": units, "long_name": f"{label} of {what}{at}"[:400]}


def _plane_attrs(mu: str, mlong: str, au: dict, stat: str) -> dict:
    base = stat.replace("_stderr", "").replace("_ci95_lower", "").replace("_ci95_upper", "")
    coef_units = {
        "intercept": mu,
        "speed": compose_units(mu, au["speed"]),
        "radial_load": compose_units(mu, au["radial_load"]),
        "interaction": compose_units(mu, au["speed"], au["radial_load"]),
    }
    if stat in ("rsquared", "n"):
        units = "1"
    else:
        units = coef_units[base]
    names = {"intercept": "a", "speed": "b (speed)", "radial_load": "c (radial load)",
             "interaction": "d (speed x radial load interaction)"}
    if stat == "rsquared":
        label = "coefficient of determination R^2 of the plane fit"
    elif stat == "n":
        label = "number of finite points in the plane fit"
    elif stat.endswith("_stderr"):
        label = f"standard error of coefficient {names[base]} of the plane fit"
    elif stat.endswith("_ci95_lower"):
        label = f"lower bound of the 95 % confidence interval of {names[base]} of the plane fit"
    elif stat.endswith("_ci95_upper"):
        label = f"upper bound of the 95 % confidence interval of {names[base]} of the plane fit"
    else:
        label = f"coefficient {names[base]} of the plane fit"
    return {"units": units,
            "long_name": f"{label} z = a + b*speed + c*radial_load + d*speed*radial_load of {mlong}"}


def fit_metrics(metrics: xr.Dataset, names=None, level: float = LEVEL) -> xr.Dataset:
    """Line fits along each sweep axis and the interaction-plane fit, per metric and phase.

    Parameters
    ----------
    metrics : xarray.Dataset
        ``metrics.nc`` content: variables over ``speed`` [degree s-1], ``radial_load`` [N],
        ``phase`` and possibly extra dimensions, over which the fits broadcast.
    names : sequence of str, optional
        Metric variables to fit; default the :data:`FIT_METRICS` present.
    level : float
        Confidence level of the intervals [1].

    Returns
    -------
    xarray.Dataset
        The ``fits.nc`` content (see the module docstring), CF attributes on every
        variable; global attributes copied from ``metrics``.
    """
    if names is None:
        names = [m for m in FIT_METRICS if m in metrics.data_vars]
    sigmas = {}
    if "realization" in metrics.dims:
        # fit the ensemble means, weighted by their standard errors
        means = {}
        for m in names:
            mean = metrics.get(f"{m}_ensemble_mean")
            means[m] = (mean if mean is not None else metrics[m].mean("realization", keep_attrs=True))
            means[m].attrs = dict(metrics[m].attrs)
            if f"{m}_ensemble_stderr" in metrics:
                sigmas[m] = metrics[f"{m}_ensemble_stderr"]
        metrics = metrics.drop_dims("realization").assign(means)
    axis_units = {a: str(metrics[a].attrs.get("units", "1")) for a in AXES if a in metrics.coords}
    groups = _groups(metrics, names)
    data = {}
    coords_attrs = {}
    for group, members in groups.items():
        if group == DISPLACEMENT_GROUP:
            flag = xr.DataArray(np.arange(len(members), dtype=np.int8), dims=DISPLACEMENT_COORD)
            da = xr.concat([metrics[m] for m in members], dim=flag, coords="minimal", compat="override")
            da = da.transpose(DISPLACEMENT_COORD, *[d for d in da.dims if d != DISPLACEMENT_COORD])
            sd = (xr.concat([sigmas[m] for m in members], dim=flag, coords="minimal", compat="override")
                  .transpose(*da.dims) if all(m in sigmas for m in members) else None)
            coords_attrs[DISPLACEMENT_COORD] = {
                "long_name": "displacement metric (the fitted phase metric of metrics.nc)",
                "flag_values": np.arange(len(members), dtype=np.int8),
                "flag_meanings": " ".join(members)}
            mu = str(metrics[members[0]].attrs.get("units", "m"))
            mlong = f"the displacement metric named by {DISPLACEMENT_COORD}"
        else:
            da = metrics[members[0]]
            sd = sigmas[members[0]].transpose(*da.dims) if members[0] in sigmas else None
            mu = str(da.attrs.get("units", "1"))
            mlong = str(da.attrs.get("long_name", group))
        for axis in AXES:
            if axis not in da.dims:
                continue
            x = np.asarray(metrics[axis].values, dtype=np.float64)
            if sd is None:
                res = _along(da, (axis,), lambda v, x=x: linear_fit(x, v, level))
            else:   # value and standard error side by side along a helper dimension
                pair = xr.concat([da, sd], dim="_value_stderr")
                res = _along(pair, (axis, "_value_stderr"),
                             lambda v, x=x: weighted_linear_fit(x, v[:, 0], v[:, 1], level))
            for stat in LINE_STATS:
                v = res[stat]
                v.attrs = _line_attrs(group, mu, mlong, axis, axis_units[axis], stat)
                data[f"{group}_vs_{axis}_{stat}"] = v
        if all(a in da.dims for a in AXES):
            gx, gy = np.meshgrid(metrics[AXES[0]].values, metrics[AXES[1]].values, indexing="ij")
            res = _along(da, AXES, lambda v: plane_fit(gx, gy, v, level))
            for stat in PLANE_STATS:
                v = res[stat]
                v.attrs = _plane_attrs(mu, mlong, axis_units, stat)
                data[f"{group}_plane_{stat}"] = v
    ds = xr.Dataset(data)
    for c in ds.coords:
        if c in metrics.coords:
            ds[c].attrs = dict(metrics[c].attrs)
        elif c in coords_attrs:
            ds[c].attrs = coords_attrs[c]
    ds.attrs = dict(metrics.attrs)
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    ds.attrs["title"] = str(metrics.attrs.get("title", "RV main-bearing phase metrics")).replace(
        "phase metrics", "least-squares fits of the phase metrics", 1)
    ds.attrs["history"] = (str(metrics.attrs.get("history", "")).rstrip("\n") + f"\n{stamp} pipeline.fits.fit_metrics").lstrip("\n")
    ds.attrs["comment"] = (
        "Per metric M (the six displacement metrics packed as M = displacement along the "
        "displacement_metric flag coordinate): M_vs_<axis>_<stat> are ordinary least-squares lines "
        "(scipy.stats.linregress) against <axis> at every value of the other axes; with realizations, the "
        "lines fit the ensemble means weighted by 1/stderr^2 (weighted least squares); M_plane_<stat> is the plane "
        "z = a + b*speed + c*radial_load + d*speed*radial_load (numpy.linalg.lstsq). Missing cases are "
        "skipped; n counts the points used; fewer than 3 (line) or 5 (plane) points give NaN."
    )
    return ds


def _groups(metrics: xr.Dataset, names) -> dict:
    """Fitted variables by group: the displacement metrics (all in m) together, others alone."""
    groups: dict = {}
    disp = [n for n in names if n in DISPLACEMENT_METRICS]
    units = {str(metrics[n].attrs.get("units", "")) for n in disp}
    if disp and len(units) == 1:
        groups[DISPLACEMENT_GROUP] = disp
    else:
        disp = []
    for n in names:
        if n not in disp:
            groups[n] = [n]
    return groups


def fit_statistic(fits: xr.Dataset, metric: str, fit: str, stat: str) -> xr.DataArray:
    """One statistic of the fits of one metric, whatever the packing of ``fits.nc``.

    Parameters
    ----------
    fits : xarray.Dataset
        :func:`fit_metrics` output (or ``fits.nc``).
    metric : str
        A metric variable of ``metrics.nc`` (e.g. ``"radial_displacement_mean"``).
    fit : str
        An axis of :data:`AXES` (the line fits along it) or ``"plane"``.
    stat : str
        One of :data:`LINE_STATS` or :data:`PLANE_STATS`.

    Raises
    ------
    KeyError
        When ``fits`` holds no such statistic.
    """
    kind = "plane" if fit == "plane" else f"vs_{fit}"
    direct = f"{metric}_{kind}_{stat}"
    if direct in fits.data_vars:
        return fits[direct]
    packed = f"{DISPLACEMENT_GROUP}_{kind}_{stat}"
    if packed in fits.data_vars and DISPLACEMENT_COORD in fits.coords:
        meanings = str(fits[DISPLACEMENT_COORD].attrs.get("flag_meanings", "")).split()
        if metric in meanings:
            value = fits[DISPLACEMENT_COORD].values[meanings.index(metric)]
            return fits[packed].sel({DISPLACEMENT_COORD: value}, drop=True)
    raise KeyError(f"fits hold no {stat!r} of the {fit} fit of {metric!r}")


def write_fits(fits: xr.Dataset, path) -> None:
    """Write ``fits.nc`` (netCDF4, zlib, no ``_FillValue`` on coordinates)."""
    _write(fits, path)


def _write(ds: xr.Dataset, path) -> None:
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    ds = ds.copy()
    for v in ds.variables.values():
        v.encoding = {}
    ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding_for(ds))
    tmp.replace(path)


# --------------------------------------------------------------------------- reference fits


#: Units a reference fit's slope must convert to, per axis (pint expressions).
_SLOPE_DIMENSION = {"speed": "m/(rad/s)", "radial_load": "m/N"}
#: pint expression of our coordinate units, per axis.
AXIS_PINT_UNITS = {"speed": "degree/s", "radial_load": "N"}
_FIXED_KIND = {"speed": "angular_speed", "radial_load": "force"}

_TOP_KEYS = {"title", "source", "description", "fits"}
_FIT_KEYS = {"table", "row", "label", "phase", "displacement", "metric", "axis", "fixed_axis",
             "fixed_value", "slope", "slope_units", "intercept", "intercept_units", "remarks",
             "source"}
_REQUIRED = ("table", "row", "phase", "displacement", "metric", "axis", "fixed_axis",
             "fixed_value", "slope", "slope_units", "intercept", "intercept_units")


@dataclass(frozen=True)
class ReferenceFit:
    """One published (or user-supplied) linear fit ``y = intercept + slope·x``.

    Parameters
    ----------
    table : str
        The table it comes from (e.g. ``"Table 3"``).
    row : int
        Row number in that table, from 1.
    label : str
        Human-readable origin, e.g. ``"Table 3, row 1: Start-up, Radial Variation Range"``.
    phase : str
        One of :data:`rvcore.profile.PHASES`.
    displacement : str
        ``"radial"`` or ``"axial"``.
    metric : str
        ``"range"``, ``"mean"`` or ``"std"``.
    axis, fixed_axis : str
        The fitted axis and the axis held fixed (``"speed"`` / ``"radial_load"``).
    fixed_value : float
        Value of the fixed axis [rad s^-1 for speed, N for load].
    fixed_text : str
        The fixed value as written in the file.
    slope, intercept : float
        In ``slope_units`` and ``intercept_units`` (pint expressions).
    remarks, source : str
    """

    table: str
    row: int
    label: str
    phase: str
    displacement: str
    metric: str
    axis: str
    fixed_axis: str
    fixed_value: float
    fixed_text: str
    slope: float
    slope_units: str
    intercept: float
    intercept_units: str
    remarks: str = ""
    source: str = ""

    @property
    def variable(self) -> str:
        """The metric variable of ``metrics.nc`` this fit describes."""
        return f"{self.displacement}_displacement_{self.metric}"

    @property
    def fixed_coordinate(self) -> float:
        """The fixed value in our coordinate units [degree s-1 or N]."""
        return math.degrees(self.fixed_value) if self.fixed_axis == "speed" else self.fixed_value

    def slope_in_coordinate_units(self) -> float:
        """The slope in m per coordinate unit [m (degree s-1)-1 or m N-1]."""
        q = registry().Quantity(self.slope, self.slope_units)
        return float(q.to(f"m/({AXIS_PINT_UNITS[self.axis]})").magnitude)

    def intercept_si(self) -> float:
        """The intercept [m]."""
        return float(registry().Quantity(self.intercept, self.intercept_units).to("m").magnitude)

    def to_reference_units(self, slope_coord: float, intercept_m: float):
        """Our slope [m per coordinate unit] and intercept [m] in this fit's units."""
        ureg = registry()
        s = ureg.Quantity(slope_coord, f"m/({AXIS_PINT_UNITS[self.axis]})").to(self.slope_units).magnitude
        i = ureg.Quantity(intercept_m, "m").to(self.intercept_units).magnitude
        return float(s), float(i)


def default_reference_path() -> Path:
    """The study's published fits, ``sweeps/reference/study-fits.toml``, as shipped."""
    from ..schema.shipped import REFERENCE_FITS, shipped_file

    return shipped_file(REFERENCE_FITS)


def load_reference_fits(path=None) -> list:
    """Read and validate a reference-fit file.

    Parameters
    ----------
    path : path-like, optional
        The TOML file; default :func:`default_reference_path`.

    Returns
    -------
    list of ReferenceFit

    Raises
    ------
    ConfigError
        On an unknown key, a missing key, a bad value or unconvertible units, naming the
        file, the key, the value and the reason.
    """
    path = Path(path) if path is not None else default_reference_path()
    try:
        with open(path, "rb") as fh:
            doc = tomllib.load(fh)
    except FileNotFoundError:
        raise UserError(f"{path}: reference-fit file not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(path, None, None, f"not valid TOML ({exc})") from None
    for key in doc:
        if key not in _TOP_KEYS:
            raise ConfigError(path, key, doc[key], f"unknown key (expected one of {', '.join(sorted(_TOP_KEYS))})")
    fits = doc.get("fits")
    if not isinstance(fits, list) or not fits:
        raise ConfigError(path, "fits", fits, "needs at least one [[fits]] table")
    ureg = registry()
    out = []
    for i, f in enumerate(fits):
        where = f"fits[{i}]"
        if not isinstance(f, dict):
            raise ConfigError(path, where, f, "must be a table")
        for key in f:
            if key not in _FIT_KEYS:
                raise ConfigError(path, f"{where}.{key}", f[key],
                                  f"unknown key (expected one of {', '.join(sorted(_FIT_KEYS))})")
        for key in _REQUIRED:
            if key not in f:
                raise ConfigError(path, f"{where}.{key}", None, "missing")

        def choice(key, allowed):
            v = f[key]
            if v not in allowed:
                raise ConfigError(path, f"{where}.{key}", v, f"must be one of {', '.join(allowed)}")
            return v

        phase = choice("phase", PHASES)
        displacement = choice("displacement", ("radial", "axial"))
        metric = choice("metric", ("range", "mean", "std"))
        axis = choice("axis", AXES)
        fixed_axis = choice("fixed_axis", AXES)
        if fixed_axis == axis:
            raise ConfigError(path, f"{where}.fixed_axis", fixed_axis, f"must differ from axis ({axis!r})")
        fixed = parse_quantity(f["fixed_value"], _FIXED_KIND[fixed_axis], file=path, key=f"{where}.fixed_value")
        for key in ("slope", "intercept"):
            if isinstance(f[key], bool) or not isinstance(f[key], (int, float)) or not math.isfinite(f[key]):
                raise ConfigError(path, f"{where}.{key}", f[key], "must be a finite number")
        row = f["row"]
        if isinstance(row, bool) or not isinstance(row, int) or row < 1:
            raise ConfigError(path, f"{where}.row", row, "must be a positive integer")
        for key, target in (("slope_units", _SLOPE_DIMENSION[axis]), ("intercept_units", "m")):
            try:
                ureg.Quantity(1.0, str(f[key])).to(target)
            except Exception as exc:  # pint raises several types
                raise ConfigError(path, f"{where}.{key}", f[key],
                                  f"must convert to {target} ({exc.__class__.__name__})") from None
        out.append(ReferenceFit(
            table=str(f["table"]), row=row,
            label=str(f.get("label", f"{f['table']}, row {row}")),
            phase=phase, displacement=displacement, metric=metric, axis=axis,
            fixed_axis=fixed_axis, fixed_value=fixed, fixed_text=str(f["fixed_value"]),
            slope=float(f["slope"]), slope_units=str(f["slope_units"]),
            intercept=float(f["intercept"]), intercept_units=str(f["intercept_units"]),
            remarks=str(f.get("remarks", "")), source=str(f.get("source", doc.get("source", ""))),
        ))
    return out
