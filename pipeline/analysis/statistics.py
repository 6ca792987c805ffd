"""Tolerance statistics of a sweep with ``[statistics]`` draws (``statistics.nc``; issue 43).

From ``metrics.nc`` (:func:`pipeline.analysis.metrics.phase_metrics`) over its ``draw`` axis
(:mod:`pipeline.schema.statistics`), per grid point:

- the 5th, 50th and 95th percentiles of every phase metric and designer output, with
  bootstrap confidence intervals (:func:`percentiles`);
- with ``sensitivity``, the first-order and total Sobol' indices of the start-up and
  steady ranges and of L10r against the named tolerance inputs, with bootstrap confidence
  intervals (:func:`sobol_table`).

The same functions take any outputs laid out as the sweep lays out its cases (a
``sample`` axis ``A``, ``B``, ``AB_<input>`` and a ``draw`` axis): the tests run the
Ishigami function through them (tests/pipeline/test_statistics.py).
"""
from __future__ import annotations

import numpy as np
import xarray as xr

from ..io import history_line
from ..io.netcdf import flag_names
from ..schema.statistics import DRAW, SAMPLE

#: The percentiles ``statistics.nc`` gives [percent].
QUANTILES = (5.0, 50.0, 95.0)
#: Confidence level of every interval.
CONFIDENCE = 0.95
#: Bootstrap resamples of every interval.
RESAMPLES = 999
#: The bootstrap's seed: the same metrics give the same statistics.nc.
BOOTSTRAP_SEED = 0
#: Fewest finite draws a percentile is given from.
MIN_DRAWS = 8
#: The outputs whose Sobol' indices are computed (the ranges in every phase; the report
#: shows the start-up and steady ones) and the phases the report's table shows.
SOBOL_OUTPUTS = ("radial_displacement_range", "axial_displacement_range", "sensor_displacement_range",
                 "reference_rating_life_L10r", "rating_life_L10r")
SOBOL_PHASES = ("startup", "steady")

#: The file :func:`pipeline.report.build.build_report` writes.
STATISTICS_FILE = "statistics.nc"


def percentiles(values, q=QUANTILES, *, confidence=CONFIDENCE, n_resamples=RESAMPLES, seed=BOOTSTRAP_SEED):
    """Percentiles of each row of ``values`` with percentile-bootstrap confidence intervals.

    Parameters
    ----------
    values : array_like (m, n)
        m outputs, n draws each; NaN draws are left out row by row.
    q : sequence of float
        Percentiles [percent].
    confidence : float
        Level of the intervals [-].
    n_resamples : int
    seed : int
        Of the bootstrap's resampling.

    Returns
    -------
    estimate, low, high : ndarray (m, len(q))
        NaN where a row has fewer than :data:`MIN_DRAWS` finite draws.

    Notes
    -----
    The estimate is ``numpy.percentile`` (linear interpolation between order statistics);
    the interval is the percentile bootstrap of :func:`scipy.stats.bootstrap`, resampling
    the draws with replacement. The draws are a quasi-random (Sobol') or stratified (LHS)
    sample, not an independent one: the bootstrap, which assumes independence, then
    overstates the interval a little, the safe side.
    """
    from scipy.stats import bootstrap

    x = np.atleast_2d(np.asarray(values, dtype=np.float64))
    m = x.shape[0]
    est, lo, hi = (np.full((m, len(q)), np.nan) for _ in range(3))
    finite = np.isfinite(x)
    full = finite.all(axis=1)
    groups = [np.flatnonzero(full)] + [np.array([i]) for i in np.flatnonzero(~full)]
    for rows in groups:
        if rows.size == 0:
            continue
        data = x[rows][:, finite[rows[0]]]
        if data.shape[1] < MIN_DRAWS:
            continue
        const = np.ptp(data, axis=1) == 0
        for j, p in enumerate(q):
            est[rows, j] = np.percentile(data, p, axis=1)
            lo[rows[const], j] = hi[rows[const], j] = est[rows[const], j]
            if (~const).any():
                res = bootstrap((data[~const],), lambda a, axis, p=p: np.percentile(a, p, axis=axis),
                                vectorized=True, axis=-1, method="percentile", confidence_level=confidence,
                                n_resamples=n_resamples, rng=seed, batch=50)
                lo[rows[~const], j] = res.confidence_interval.low
                hi[rows[~const], j] = res.confidence_interval.high
    return est, lo, hi


def sobol_table(f_a, f_b, f_ab, *, confidence=CONFIDENCE, n_resamples=RESAMPLES, seed=BOOTSTRAP_SEED):
    """First-order and total Sobol' indices of s outputs against d inputs, with intervals.

    Parameters
    ----------
    f_a, f_b : array_like (s, n)
        The outputs on Saltelli's matrices A and B (n a power of 2).
    f_ab : array_like (d, s, n)
        On ``AB_i``: A with input i's columns from B.
    confidence : float
    n_resamples : int
    seed : int

    Returns
    -------
    dict
        ``first_order``, ``total_order`` (s, d) and their ``*_low``, ``*_high``; all NaN
        where an output has a non-finite value in any matrix (a failed case).

    Notes
    -----
    :func:`scipy.stats.sobol_indices` with the precomputed outputs (Saltelli et al. 2010's
    estimators: ``S_i = mean(f_B (f_ABi − f_A)) / V`` and ``S_Ti = mean((f_A − f_ABi)²) / (2V)``);
    the intervals are the percentile bootstrap over the n rows of the design (each
    resample through the same function), seeded so that they are reproducible.
    """
    from scipy.stats import bootstrap, sobol_indices

    f_a, f_b, f_ab = (np.asarray(v, dtype=np.float64) for v in (f_a, f_b, f_ab))
    d, s, n = f_ab.shape
    out = {k: np.full((s, d), np.nan) for k in ("first_order", "total_order", "first_order_low",
                                               "first_order_high", "total_order_low", "total_order_high")}
    ok = np.isfinite(f_a).all(axis=1) & np.isfinite(f_b).all(axis=1) & np.isfinite(f_ab).all(axis=(0, 2))
    ok &= np.var(np.concatenate([f_a, f_b], axis=1), axis=1) > 0
    if not ok.any():
        return out
    a, b, ab = f_a[ok], f_b[ok], f_ab[:, ok]

    def indices(idx):
        r = sobol_indices(func={"f_A": a[:, idx], "f_B": b[:, idx], "f_AB": ab[..., idx]}, n=n)
        return np.concatenate([np.reshape(r.first_order, (-1,)), np.reshape(r.total_order, (-1,))])

    est = indices(np.arange(n))
    res = bootstrap((np.arange(n),), indices, vectorized=False, method="percentile", confidence_level=confidence,
                    n_resamples=n_resamples, rng=seed)
    k = ok.sum() * d
    for name, vec in (("", est), ("_low", res.confidence_interval.low), ("_high", res.confidence_interval.high)):
        out[f"first_order{name}"][ok] = np.reshape(vec[:k], (-1, d))
        out[f"total_order{name}"][ok] = np.reshape(vec[k:], (-1, d))
    return out


def draws_of(da: xr.DataArray) -> xr.DataArray:
    """The independent draws of an output, over ``draw``: with ``sample``, A's and B's
    (2N), else every draw."""
    if SAMPLE not in da.dims:
        return da
    names = flag_names(da[SAMPLE])
    parts = [da.isel({SAMPLE: names.index(s)}, drop=True) for s in ("A", "B") if s in names]
    out = xr.concat(parts, dim=DRAW, coords="minimal", compat="override")
    return out.drop_vars(DRAW, errors="ignore")


def saltelli(da: xr.DataArray, inputs=None):
    """``(f_A, f_B, f_AB, inputs)`` of an output laid out over ``sample`` and ``draw``,
    every other dimension stacked as the s outputs (in ``da``'s order)."""
    names = flag_names(da[SAMPLE])
    inputs = list(inputs) if inputs is not None else [s[3:] for s in names if s.startswith("AB_")]
    other = [d for d in da.dims if d not in (SAMPLE, DRAW)]
    x = da.transpose(*other, SAMPLE, DRAW).values.reshape(-1, len(names), da.sizes[DRAW])
    f_a = x[:, names.index("A")]
    f_b = x[:, names.index("B")]
    f_ab = np.stack([x[:, names.index(f"AB_{i}")] for i in inputs])
    return f_a, f_b, f_ab, inputs


def _attrs(da, what: str, units=None) -> dict:
    return {"units": str(da.attrs.get("units", "1")) if units is None else units,
            "long_name": f"{what} of: {da.attrs.get('long_name', da.name)}"}


def statistics_dataset(metrics: xr.Dataset) -> xr.Dataset:
    """``statistics.nc`` of a sweep's metrics with a ``draw`` axis.

    Parameters
    ----------
    metrics : xarray.Dataset
        :func:`pipeline.analysis.metrics.phase_metrics` of a sweep with ``[statistics]``.

    Returns
    -------
    xarray.Dataset
        For every float variable ``M`` over ``draw`` (but ``case_status`` and the
        window-edge flags): ``M_percentile`` over the grid dimensions and ``percentile``
        (5, 50, 95), with ``M_percentile_ci_low`` and ``_ci_high``; ``draws_used`` the
        finite draws of δ_r's range per point. With a ``sample`` axis: ``sobol_first_order_M``
        and ``sobol_total_order_M`` over the grid dimensions and ``tolerance_input``, with
        ``*_ci_low`` and ``*_ci_high``, for the outputs of :data:`SOBOL_OUTPUTS`.
    """
    if DRAW not in metrics.dims:
        raise ValueError("the metrics have no draw axis: the sweep has no [statistics] table")
    data, coords = {}, {}
    for name, da in metrics.data_vars.items():
        if DRAW not in da.dims or name == "case_status" or "at_edge" in name or da.dtype.kind not in "fiu":
            continue
        x = draws_of(da)
        other = [d for d in x.dims if d != DRAW]
        est, lo, hi = percentiles(x.transpose(*other, DRAW).values.reshape(-1, x.sizes[DRAW]))
        shape = [x.sizes[d] for d in other] + [len(QUANTILES)]
        dims = (*other, "percentile")
        data[f"{name}_percentile"] = xr.DataArray(est.reshape(shape), dims=dims, attrs=_attrs(da, "percentile over the draws"))
        data[f"{name}_percentile_ci_low"] = xr.DataArray(lo.reshape(shape), dims=dims, attrs=_attrs(
            da, f"lower end of the {CONFIDENCE:.0%} bootstrap confidence interval of the percentile"))
        data[f"{name}_percentile_ci_high"] = xr.DataArray(hi.reshape(shape), dims=dims, attrs=_attrs(
            da, f"upper end of the {CONFIDENCE:.0%} bootstrap confidence interval of the percentile"))
    if "radial_displacement_range" in metrics:
        x = draws_of(metrics["radial_displacement_range"]).notnull().any("phase")
        data["draws_used"] = x.sum(DRAW).astype(np.int32).assign_attrs(
            units="1", long_name="draws with data (a failed or missing case is not counted)")
    if SAMPLE in metrics.dims:
        inputs = None
        for name in SOBOL_OUTPUTS:
            if name not in metrics or SAMPLE not in metrics[name].dims:
                continue
            da = metrics[name]
            f_a, f_b, f_ab, inputs = saltelli(da, inputs)
            res = sobol_table(f_a, f_b, f_ab)
            other = [d for d in da.dims if d not in (SAMPLE, DRAW)]
            shape = [da.sizes[d] for d in other] + [len(inputs)]
            dims = (*other, "tolerance_input")
            for kind, what in (("first_order", "first-order Sobol' index"), ("total_order", "total Sobol' index")):
                for suffix, text in (("", what), ("_low", f"lower end of the {CONFIDENCE:.0%} bootstrap confidence "
                                                          f"interval of the {what}"),
                                     ("_high", f"upper end of the {CONFIDENCE:.0%} bootstrap confidence interval "
                                               f"of the {what}")):
                    var = f"sobol_{kind}_{name}" + ("_ci" + suffix if suffix else "")
                    data[var] = xr.DataArray(res[kind + suffix].reshape(shape), dims=dims,
                                             attrs=_attrs(da, text, units="1"))
            coords.update({d: metrics[d] for d in other if d in metrics.coords})
        if inputs is not None:
            coords["tolerance_input"] = xr.DataArray(np.array(inputs, dtype=object), dims="tolerance_input",
                                                     attrs={"units": "1", "long_name": "named tolerance input "
                                                            "of the [statistics] table"})
    ds = xr.Dataset(data)
    for d in ds.dims:
        if d in metrics.coords and d not in coords:
            coords[d] = metrics[d]
    coords["percentile"] = xr.DataArray(np.array(QUANTILES), dims="percentile",
                                        attrs={"units": "percent", "long_name": "percentile of the draws"})
    ds = ds.assign_coords({k: v for k, v in coords.items() if k in ds.dims})
    for name, c in metrics.coords.items():
        if name not in ds.coords and c.ndim == 0:
            ds = ds.assign_coords({name: c})
    ds.attrs = {k: v for k, v in metrics.attrs.items() if k not in ("comment",)}
    ds.attrs["Conventions"] = "CF-1.8"
    ds.attrs["title"] = "RV main-bearing tolerance statistics: percentiles over the draws and Sobol' indices"
    ds.attrs["history"] = (str(metrics.attrs.get("history", "")).rstrip("\n") + "\n"
                           + history_line("pipeline.analysis.statistics.statistics_dataset")).lstrip("\n")
    ds.attrs["comment"] = (f"Percentiles {', '.join(f'{q:g}' for q in QUANTILES)} over the draws of the sweep's "
                           f"[statistics] table (with a Saltelli design: its A and B draws), with {CONFIDENCE:.0%} "
                           f"percentile-bootstrap confidence intervals ({RESAMPLES} resamples, seed "
                           f"{BOOTSTRAP_SEED}); Sobol' indices by scipy.stats.sobol_indices (Saltelli 2010) with "
                           "bootstrap intervals. NaN: fewer than "
                           f"{MIN_DRAWS} finite draws, or a failed case in the Saltelli design.")
    return ds
