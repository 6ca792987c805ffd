"""Selecting from the results: the finished grid points, the extreme cases, one metric or
fit at a grid point, and where each study fit's other axis is held."""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from rvcore.profile import PHASES

from ..analysis import REALIZATION, case_states, fit_statistic, nearest
from .context import ROW, SENSOR, Context, on_base_grid, ensemble_of, status_lookup
from .render import fmt_speed, fmt_number, fmt_kn



def finished_points(ctx: Context, realization=None):
    """Grid points ``[(speed, load)]`` that finished.

    Parameters
    ----------
    realization : int, optional
        With an ensemble: the points whose realization of this index finished; default
        those where any realization finished.
    """
    ok = base_states(ctx) == "ok"
    if REALIZATION in ok.dims:
        ok = ok.isel({REALIZATION: realization}) if realization is not None else ok.any(REALIZATION)
    pts = []
    for s in ok["speed"].values:
        for l in ok["radial_load"].values:
            if bool(ok.sel(speed=s, radial_load=l).item()):
                pts.append((float(s), float(l)))
    return pts


def base_states(ctx: Context):
    """Case states over ``(speed, radial_load[, realization])`` at the first value of any other axis."""
    st = case_states(ctx.sweep)
    extra = [d for d in st.dims if d not in ("speed", "radial_load", REALIZATION)]
    st = st.isel({d: 0 for d in extra}) if extra else st
    return st.transpose("speed", "radial_load", *[d for d in st.dims if d == REALIZATION])


def unlisted_points(ctx: Context) -> set:
    """The ``(speed °/s, load N)`` grid points that no entry of status.json names: a sweep of
    listed cases (``[[cases]]``) combined onto the full grid of their values leaves them
    empty, asked for by nobody. Empty when status.json names no point of the grid."""
    matched, _ = status_lookup(ctx)
    listed = {(s, l) for (s, l, _) in matched}
    if not listed:
        return set()
    return {(float(s), float(l)) for s in ctx.metrics["speed"].values for l in ctx.metrics["radial_load"].values
            if (float(s), float(l)) not in listed}


def missing_cases(ctx: Context) -> int:
    """Cases of :func:`base_states` that the sweep asked for and that did not finish ok."""
    st = base_states(ctx)
    unlisted = unlisted_points(ctx)
    bad = st != "ok"
    if unlisted:
        asked = xr.DataArray([[(float(s), float(l)) not in unlisted for l in st["radial_load"].values]
                              for s in st["speed"].values], dims=("speed", "radial_load"),
                             coords={"speed": st["speed"], "radial_load": st["radial_load"]})
        bad = bad & asked
    return int(bad.sum())


def extreme_points(ctx: Context, realization=None):
    """The finished grid points nearest to the four corners of the grid (see :func:`finished_points`)."""
    pts = finished_points(ctx, realization)
    if not pts:
        return []
    s = np.array([p[0] for p in pts])
    l = np.array([p[1] for p in pts])
    srange = max(np.ptp(s), 1e-12)
    lrange = max(np.ptp(l), 1e-12)
    out = []
    for cs in (s.min(), s.max()):
        for cl in (l.min(), l.max()):
            d = ((s - cs) / srange) ** 2 + ((l - cl) / lrange) ** 2
            k = int(np.argmin(d))
            if pts[k] not in out:
                out.append(pts[k])
    return out


def metric_stat(ctx: Context, name: str, speed: float, load: float, phase: str, sensor=None, row=None):
    """A phase metric at one grid point and its standard error [its units].

    With realizations, the ensemble mean and its standard error; otherwise the value and
    NaN. ``sensor`` is the sensor flag of a sensor metric (default the first), ``row``
    the row of a per-row metric (default the first). NaN, NaN when the metric is absent.
    """
    m = on_base_grid(ctx.metrics, first_realization=False)
    if name not in m:
        return math.nan, math.nan
    sel = {"speed": speed, "radial_load": load, "phase": PHASES.index(phase)}
    if SENSOR in m[name].dims:
        sel[SENSOR] = sensor if sensor is not None else m[SENSOR].values[0]
    if ROW in m[name].dims:
        sel[ROW] = row if row is not None else m[ROW].values[0]
    if REALIZATION in m[name].dims:
        mean, se = ensemble_of(m, name, sel)
        return float(mean.item()), float(se.item())
    return float(m[name].sel(sel).item()), math.nan


def metric_value(ctx: Context, name: str, speed: float, load: float, phase: str, sensor=None) -> float:
    """A phase metric at one grid point [its units]: the ensemble mean when there are
    realizations; at sensor flag ``sensor`` (default the first) for a sensor metric."""
    return metric_stat(ctx, name, speed, load, phase, sensor)[0]


def axis_specs(ctx: Context, phase: str | None = None) -> list:
    """``[(axis, fixed_axis, fixed, note)]``: the axes the study's fits of ``phase`` (any phase
    when it has none) are drawn against, at the grid value nearest to the study's fixed one."""
    refs = [r for r in ctx.references if r.phase == phase] or list(ctx.references)
    out, seen = [], set()
    for r in refs:
        if r.axis in seen:
            continue
        seen.add(r.axis)
        fixed, note = fixed_choice(ctx, r.fixed_axis, r.fixed_coordinate)
        out.append((r.axis, r.fixed_axis, fixed, note))
    if not out:
        for axis, other in (("speed", "radial_load"), ("radial_load", "speed")):
            fixed = float(ctx.metrics[other].values[0])
            out.append((axis, other, fixed, f"at {fmt_speed(fixed) if other == 'speed' else fmt_kn(fixed)}"))
    return out


def fmt_mean_se(mean: float, se: float, scale: float = 1.0, digits: int = 3) -> str:
    """'mean ± se' (or the mean alone when se is NaN) after multiplying by ``scale``."""
    if math.isfinite(se):
        return f"{fmt_number(mean * scale, digits)} ± {fmt_number(se * scale, 2)}"
    return fmt_number(mean * scale, digits)


def fit_at(ctx: Context, variable: str, axis: str, fixed_axis: str, fixed: float, phase: str,
           sensor=None) -> dict:
    """Statistics of our line fit of ``variable`` along ``axis`` at ``fixed`` (SI / coordinate
    units); a sensor metric's from :attr:`Context.sensor_fits` at sensor flag ``sensor``."""
    f = on_base_grid(ctx.sensor_fits if variable.startswith(f"{SENSOR}_") else ctx.fits)
    out = {}
    for stat in ("slope", "intercept", "slope_stderr", "intercept_stderr", "slope_intercept_covariance",
                 "slope_ci95_lower", "slope_ci95_upper", "rsquared", "n"):
        try:
            da = fit_statistic(f, variable, axis, stat)
        except KeyError:
            return {}
        sel = {fixed_axis: fixed, "phase": PHASES.index(phase)}
        if SENSOR in da.dims:
            sel[SENSOR] = sensor if sensor is not None else da[SENSOR].values[0]
        out[stat] = float(da.sel(sel).item())
    return out


def fixed_choice(ctx: Context, fixed_axis: str, wanted: float):
    """Nearest available value of ``fixed_axis`` to ``wanted`` [coordinate units] and a note."""
    values = ctx.metrics[fixed_axis].values
    got = nearest(values, wanted)
    fmt = fmt_speed if fixed_axis == "speed" else fmt_kn
    if math.isclose(got, wanted, rel_tol=1e-6, abs_tol=1e-9):
        return got, f"at {fmt(got)}"
    return got, f"at {fmt(got)} (nearest available to the study's {fmt(wanted)})"

