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

The single fits are in :mod:`pipeline.analysis.regression`; the reference fit files
(``sweeps/reference/*.toml``) that the report compares against are read by
:mod:`pipeline.schema.reference`.
"""
from __future__ import annotations

import numpy as np
import xarray as xr

from ..io import history_line, strip_encoding, write_atomic
from ..schema.reference import AXES
from ..schema.units import compose_units
from .regression import LEVEL, LINE_STATS, PLANE_STATS, linear_fit, plane_fit, weighted_linear_fit

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

_AXIS_LONG = {"speed": "steady inner-ring speed", "radial_load": "steady radial load"}


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


def percent(level: float) -> str:
    """A confidence level as the long names write it: ``0.95`` -> ``"95 %"``."""
    return f"{100.0 * level:.10g} %"


def _line_attrs(metric: str, mu: str, mlong: str, axis: str, au: str, stat: str, level: float = LEVEL) -> dict:
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
        "slope_ci95_lower": f"lower bound of the {percent(level)} confidence interval of the OLS slope",
        "slope_ci95_upper": f"upper bound of the {percent(level)} confidence interval of the OLS slope",
        "intercept_ci95_lower": f"lower bound of the {percent(level)} confidence interval of the OLS intercept",
        "intercept_ci95_upper": f"upper bound of the {percent(level)} confidence interval of the OLS intercept",
        "rsquared": "coefficient of determination R^2 of the OLS line",
        "n": "number of finite points in the OLS line",
    }[stat]
    return {"units": units, "long_name": f"{label} of {what}{at}"[:400]}


def _plane_attrs(mu: str, mlong: str, au: dict, stat: str, level: float = LEVEL) -> dict:
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
        label = f"lower bound of the {percent(level)} confidence interval of {names[base]} of the plane fit"
    elif stat.endswith("_ci95_upper"):
        label = f"upper bound of the {percent(level)} confidence interval of {names[base]} of the plane fit"
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
                v.attrs = _line_attrs(group, mu, mlong, axis, axis_units[axis], stat, level)
                data[f"{group}_vs_{axis}_{stat}"] = v
        if all(a in da.dims for a in AXES):
            gx, gy = np.meshgrid(metrics[AXES[0]].values, metrics[AXES[1]].values, indexing="ij")
            res = _along(da, AXES, lambda v: plane_fit(gx, gy, v, level))
            for stat in PLANE_STATS:
                v = res[stat]
                v.attrs = _plane_attrs(mu, mlong, axis_units, stat, level)
                data[f"{group}_plane_{stat}"] = v
    ds = xr.Dataset(data)
    for c in ds.coords:
        if c in metrics.coords:
            ds[c].attrs = dict(metrics[c].attrs)
        elif c in coords_attrs:
            ds[c].attrs = coords_attrs[c]
    ds.attrs = dict(metrics.attrs)
    ds.attrs["title"] = str(metrics.attrs.get("title", "RV main-bearing phase metrics")).replace(
        "phase metrics", "least-squares fits of the phase metrics", 1)
    ds.attrs["history"] = (str(metrics.attrs.get("history", "")).rstrip("\n") + "\n" + history_line("pipeline.analysis.fits.fit_metrics")).lstrip("\n")
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
    """Write ``fits.nc`` atomically (netCDF4, zlib, no ``_FillValue`` on coordinates)."""
    write_atomic(strip_encoding(fits), path)


# --------------------------------------------------------------------------- reference fits
