"""The report's figures: time histories, metrics against speed and load with fit lines
and bands, the sensors' readings and the cage slip. PNGs carry no software or time
metadata and are written atomically."""
from __future__ import annotations

import contextlib
import gc
import io
import math
import multiprocessing
from pathlib import Path

import numpy as np

from rvcore.profile import PHASES

from ..analysis import REALIZATION, line_band
from ..analysis.measured import points_on_line
from ..io import write_bytes_atomic
from .context import (ROW, SENSOR, Context, on_base_grid, edge_flag, ensemble_of, first_realization_text, realizations,
                      rows_of, sensors)
from .render import AXIS_TITLE, CENTRE_LABEL, METRIC_TITLE, PHASE_TITLE, fmt_speed, fmt_number, fmt_kn
from .select import fit_at, fixed_choice

#: Keyword arguments of every ``savefig``: no software, no timestamps in the PNG.
PNG_KWARGS = {"dpi": 100, "format": "png", "metadata": {"Software": None}}


def new_figure(nrows: int, ncols: int, size):
    """A constrained-layout figure of ``size`` [in] and its ``nrows`` × ``ncols`` axes (always 2-D)."""
    # matplotlib is imported here, not at the top, so that importing the report stays cheap
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


#: The figures :func:`save_figure` was given inside :func:`drawn_at_the_end`, or None
#: outside it (then each is drawn at once).
_PENDING = None


def save_figure(fig, path: Path):
    """``fig`` as a PNG at ``path``, written atomically: at once, or at the end of the
    :func:`drawn_at_the_end` block it was saved in."""
    if _PENDING is not None:
        _PENDING.append((fig, path))
        return
    _draw(fig, path)


def _draw(fig, path: Path) -> None:
    buf = io.BytesIO()
    fig.savefig(buf, **PNG_KWARGS)
    write_bytes_atomic(path, buf.getvalue())


def _draw_all(figures) -> None:
    for fig, path in figures:
        _draw(fig, path)


def _draw_in_fork(figures) -> None:
    """:func:`_draw_all` in the forked child, its cyclic garbage collector off: the child
    holds a copy of whatever garbage the parent had not yet collected, a netCDF file left
    open among it, and collecting that here would close the file's HDF5 handle in the
    child too, beside the parent's."""
    gc.disable()
    _draw_all(figures)


@contextlib.contextmanager
def drawn_at_the_end():
    """Figures saved inside the block are drawn when it ends without an error: half of
    them in a forked process where the platform forks, so that a report's figures take
    two cores. Drawing is most of a report's time (6.5 s of the study report's 10 s on the
    Intel Xeon, 2026-11-29): the layout and the rasterization of each figure, its own work.

    The parent collects its garbage first and the child draws from its copy of the
    figures and only writes PNGs (atomically), its garbage collector off
    (:func:`_draw_in_fork`); it ends without the parent's exit
    handlers (``multiprocessing``'s fork start). Should it fail, the parent draws its half
    too. The PNGs are the same bytes either way.
    """
    global _PENDING
    outer, pending = _PENDING, []
    _PENDING = pending
    try:
        yield
    finally:
        _PENDING = outer
    if len(pending) < 2 or "fork" not in multiprocessing.get_all_start_methods():
        _draw_all(pending)
        return
    # the garbage collected here, where its files were opened, not in the child
    gc.collect()
    child = multiprocessing.get_context("fork").Process(target=_draw_in_fork, args=(pending[1::2],), daemon=True)
    child.start()
    try:
        _draw_all(pending[0::2])
    finally:
        child.join()
    if child.exitcode != 0:
        _draw_all(pending[1::2])


def shade_windows(ax, windows):
    """Shade each phase window ``{name: (start, end)}`` [s] of ``ax`` in its colour, labelled."""
    colours = {"startup": "#4c72b0", "steady": "#55a868", "deceleration": "#c44e52"}
    for name, (a, b) in windows.items():
        ax.axvspan(a, b, color=colours.get(name, "#999999"), alpha=0.12, lw=0,
                   label=f"{PHASE_TITLE.get(name, name)} window")


def legend_outside(fig, ax) -> None:
    """The legend of the lines of ``ax``, outside the axes at the figure's upper right."""
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=9, loc="outside right upper")


def trace_style(k: int, n: int) -> dict:
    """Line style of the ``k``-th of ``n`` traces drawn over each other: the first widest and
    solid, the later ones thinner and dashed, so that a trace drawn over another of the same
    values leaves it visible."""
    dashes = ("-", "--", "-.", ":")
    return {"lw": 1.0 + 1.6 * (n - 1 - k) / max(n - 1, 1), "ls": dashes[k % len(dashes)], "color": f"C{k}"}


#: Lines of a panel closer than this (relative to their values) are drawn as one line,
#: labelled as identical: drawn each, they lie on top of each other and read as missing data.
SAME_WITHIN = 1e-3

#: Markers of the lines of one panel, so that lines drawn close together stay distinct.
MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">", "*")


def _shared_abscissae(lines):
    """``(values, finite, columns)`` of ``lines`` stacked as rows, ``columns`` the abscissae
    where at least two lines are finite; ``(None, None, None)`` without such an abscissa."""
    a = np.asarray([np.asarray(y, dtype=np.float64) for y in lines])
    if a.ndim != 2 or a.shape[0] < 2:
        return None, None, None
    ok = np.isfinite(a)
    cols = ok.sum(axis=0) >= 2
    if not cols.any():
        return None, None, None
    return a, ok, cols


def spread_of(lines) -> float:
    """The largest relative spread between ``lines`` at any abscissa [1].

    Parameters
    ----------
    lines : sequence of array_like
        Equally long y arrays [any one unit]; NaN entries are ignored.

    Returns
    -------
    float
        ``max_x (max_k y_k(x) − min_k y_k(x)) / max_k |y_k(x)|`` over the abscissae where at
        least two lines are finite; 0 where every value is 0; NaN with no such abscissa.
    """
    a, ok, cols = _shared_abscissae(lines)
    if a is None:
        return math.nan
    hi = np.where(ok, a, -np.inf).max(axis=0)[cols]
    lo = np.where(ok, a, np.inf).min(axis=0)[cols]
    mag = np.where(ok, np.abs(a), 0.0).max(axis=0)[cols]
    rel = np.where(mag > 0, (hi - lo) / np.where(mag > 0, mag, 1.0), 0.0)
    return float(rel.max())


#: Lines of a panel that differ by less than this fraction of the panel's y-span lie on top
#: of each other on screen: they are drawn in distinct dash patterns and widths and the
#: legend says they overlap.
OVERLAP_WITHIN = 0.02


def overlap_of(lines) -> float:
    """The largest gap between ``lines`` at any abscissa, as a fraction of their joint span [1]
    (NaN without two finite values at one abscissa; 0 for a zero span)."""
    a, ok, cols = _shared_abscissae(lines)
    if a is None:
        return math.nan
    gap = (np.where(ok, a, -np.inf).max(axis=0) - np.where(ok, a, np.inf).min(axis=0))[cols]
    span = float(np.nanmax(a[ok]) - np.nanmin(a[ok]))
    return float(gap.max() / span) if span > 0 else 0.0


def identical_label(what: str, n: int, spread: float) -> str:
    """'all 3 speeds (identical within 0.02 %)': the label of lines drawn as one."""
    if spread <= 0.0:
        return f"all {n} {what} (identical)"
    return f"all {n} {what} (identical within {fmt_number(spread * 100.0, 1)} %)"


def phase_ylim(t, ys, windows, pad: float = 0.08):
    """The y-limits of a time history fitted to the phase windows, and what lies beyond them.

    The ring settles onto its balls from t = 0 while the loads ramp up, and unloads after the
    last phase: those transients can be far larger than the phases' motion and, scaled to,
    flatten it. The limits are fitted to the samples inside the phase windows only.

    Parameters
    ----------
    t : array_like
        Sample times [s].
    ys : sequence of array_like
        The traces drawn [any one unit], each sampled at ``t``.
    windows : dict
        ``{phase: (start, end)}`` [s]; empty: no limits.
    pad : float
        Margin added on each side [fraction of the span in the windows].

    Returns
    -------
    tuple or None
        ``(lower, upper, outside_min, outside_max)`` [unit of ``ys``]: the limits, and the
        extremes of the samples outside the windows (NaN without any); None without windows
        or finite samples inside them.
    """
    if not windows:
        return None
    t = np.asarray(t, dtype=np.float64)
    inside = np.zeros(t.shape, bool)
    for a, b in windows.values():
        inside |= (t >= a) & (t <= b)
    a = np.asarray([np.asarray(y, dtype=np.float64) for y in ys]) if len(ys) else np.empty((0, t.size))
    ins = a[:, inside]
    ins = ins[np.isfinite(ins)]
    if not ins.size:
        return None
    lo, hi = float(ins.min()), float(ins.max())
    margin = pad * (hi - lo) if hi > lo else max(abs(hi) * 0.05, 1e-3)
    out = a[:, ~inside]
    out = out[np.isfinite(out)]
    omin, omax = (float(out.min()), float(out.max())) if out.size else (math.nan, math.nan)
    return lo - margin, hi + margin, omin, omax


def _settling_marks(ax, t, windows, lim) -> str:
    """Grey out the times outside the phase windows, set the y-limits ``lim`` of
    :func:`phase_ylim` and say, on the panel, how far the trace runs off them; returns the
    off-scale text ('' when nothing runs off)."""
    lo, hi, omin, omax = lim
    starts = [a for a, _ in windows.values()]
    ends = [b for _, b in windows.values()]
    t0, t1 = float(np.nanmin(t)), float(np.nanmax(t))
    ax.axvspan(t0, min(starts), color="0.55", alpha=0.18, lw=0, hatch="//", label="load ramps, settling: not scaled to")
    if max(ends) < t1:
        ax.axvspan(max(ends), t1, color="0.55", alpha=0.18, lw=0, hatch="//")
    ax.set_ylim(lo, hi)
    off = []
    if math.isfinite(omin) and omin < lo:
        off.append(f"down to {fmt_number(omin, 3)}")
    if math.isfinite(omax) and omax > hi:
        off.append(f"up to {fmt_number(omax, 3)}")
    if off:
        text = "off scale outside the phases: " + ", ".join(off)
        ax.text(0.005, 0.02, text + " µm", transform=ax.transAxes, fontsize=7.5, color="0.25", va="bottom",
                bbox={"facecolor": "white", "alpha": 0.8, "lw": 0, "pad": 1.5})
        return text
    return ""


def figure_time_histories(ctx: Context, windows, path: Path, cases) -> list:
    """δ_r and δ_a at the ring centre of ``cases`` [(speed °/s, load N)] against time, in µm.

    The first realization of an ensemble; the phase ``windows`` [s] shaded. The y-limits fit
    the phase windows (:func:`phase_ylim`): the settling from t = 0 and the load ramps are
    drawn, greyed, and not scaled to. Returns the off-scale notes, one per panel that has one.
    """
    sw = on_base_grid(ctx.sweep)
    fig, axes = new_figure(2, 1, (10.0, 6.0))
    t = sw["elapsed_time"].values
    notes = []
    for k, (name, label) in enumerate((("radial_displacement", "δ_r at the ring centre [µm]"),
                                       ("axial_displacement", "δ_a at the ring centre [µm]"))):
        ax = axes[k, 0]
        shade_windows(ax, windows)
        ys = []
        if name in sw:
            for k_case, (s, l) in enumerate(cases):
                y = sw[name].sel(speed=s, radial_load=l).values * 1e6
                ys.append(y)
                ax.plot(t, y, label=f"{fmt_speed(s)}, {fmt_kn(l)}", **trace_style(k_case, len(cases)))
        lim = phase_ylim(t, ys, windows)
        if lim is not None:
            off = _settling_marks(ax, t, windows, lim)
            if off:
                notes.append(f"{label.split(' [')[0]}: {off} µm")
        ax.set_ylabel(label)
        ax.grid(True, lw=0.3)
    axes[1, 0].set_xlabel("elapsed time [s]")
    legend_outside(fig, axes[0, 0])
    first = first_realization_text(ctx)
    axes[0, 0].set_title("Inner-ring displacements at the ring centre of the extreme cases, phase windows shaded"
                         + (f"\n{first}" if first else ""), fontsize=10)
    save_figure(fig, path)
    return notes


def figure_sensor_time_histories(ctx: Context, windows, path: Path, cases) -> None:
    """The virtual sensors' readings of ``cases`` against time, one panel per sensor, in µm.

    The first realization of an ensemble; the phase ``windows`` [s] shaded.
    """
    sw = on_base_grid(ctx.sweep)
    sens = sensors(ctx.sweep)
    fig, axes = new_figure(len(sens), 1, (10.0, 1.0 + 2.5 * len(sens)))
    t = sw["elapsed_time"].values
    for k, sn in enumerate(sens):
        ax = axes[k, 0]
        shade_windows(ax, windows)
        ys = []
        for k_case, (s, l) in enumerate(cases):
            y = sw["sensor_displacement"].sel({"speed": s, "radial_load": l, SENSOR: sn.value}).values * 1e6
            ys.append(y)
            ax.plot(t, y, label=f"{fmt_speed(s)}, {fmt_kn(l)}", **trace_style(k_case, len(cases)))
        lim = phase_ylim(t, ys, windows)
        if lim is not None:
            _settling_marks(ax, t, windows, lim)
        ax.set_title(sn.label(code=False), fontsize=8)
        ax.set_ylabel(f"{sn.name} [µm]")
        ax.grid(True, lw=0.3)
    axes[-1, 0].set_xlabel("elapsed time [s]")
    legend_outside(fig, axes[0, 0])
    first = first_realization_text(ctx)
    fig.suptitle("Virtual sensor readings of the extreme cases, phase windows shaded"
                 + (f"\n{first}" if first else ""), fontsize=10)
    save_figure(fig, path)


def _metric_panel(ax, ctx: Context, name: str, axis: str, fixed_axis: str, fixed: float, phase: str, *,
                  sensor=None, row=None, scale: float = 1e6, colour: str = "k", marker: str = "o",
                  label: str = "cases", realization_label: str | None = "individual realizations",
                  dodge: float = 0.0) -> int:
    """Plot one phase metric against ``axis`` at ``fixed`` on ``ax``; return the hollow markers drawn.

    Without an ensemble: one marker per case. With one: the ensemble mean with ±1
    standard-error bars and each realization as a faint small marker, drawn 2.5 % of the
    axis span to the left of its mean so that the bars do not hide it. A range whose
    ``_range_at_edge`` flag is set is drawn hollow (a mean marker when any of its
    realizations is). Values are multiplied by ``scale`` (1e6: m to µm; 100: 1 to %);
    ``axis`` values in °/s or kN, shifted by ``dodge`` times the axis span (to set two
    series side by side). ``row`` picks the row of a per-row metric (default the first).
    """
    m = on_base_grid(ctx.metrics, first_realization=False)
    if name not in m:
        return 0
    sel = {fixed_axis: fixed, "phase": PHASES.index(phase)}
    if sensor is not None:
        sel[SENSOR] = sensor
    if ROW in m[name].dims:
        sel[ROW] = row if row is not None else m[ROW].values[0]
    da = m[name].sel(sel)
    if not bool(da.notnull().any()):
        ax.text(0.5, 0.5, "no data in this phase's window", transform=ax.transAxes, ha="center",
                va="center", fontsize=8, color="0.4")
        return 0
    flag = edge_flag(m, name, sel)
    x = m[axis].values.astype(float)
    xs = x / 1e3 if axis == "radial_load" else x
    span = float(np.ptp(xs)) if xs.size > 1 and np.ptp(xs) > 0 else max(abs(float(xs[0])), 1.0)
    xs = xs + dodge * span
    def points(xv, yv, hollow, **kw):
        if not xv.size:
            return
        style = dict(ls="none", marker=marker, color=colour, **kw)
        if hollow:
            style.update(mfc="none", mec=colour)
        ax.plot(xv, yv, **style)

    if REALIZATION in da.dims:
        vals = da.transpose(axis, REALIZATION).values * scale
        fl = (flag.transpose(axis, REALIZATION).values == 1) if flag is not None else np.zeros(vals.shape, bool)
        xr_ = xs - 0.025 * span
        for k in range(vals.shape[1]):
            points(xr_[~fl[:, k]], vals[~fl[:, k], k], False, ms=2.5, alpha=0.35)
            points(xr_[fl[:, k]], vals[fl[:, k], k], True, ms=2.5, alpha=0.5)
        mean, se = ensemble_of(m, name, sel)
        mean = mean.transpose(axis).values * scale
        se = se.transpose(axis).values * scale
        any_fl = fl.any(axis=1)
        ax.errorbar(xs, mean, yerr=se, fmt="none", ecolor=colour, elinewidth=1.0, capsize=3)
        points(xs[~any_fl], mean[~any_fl], False, ms=5)
        points(xs[any_fl], mean[any_fl], True, ms=5, mew=1.2)
        ax.plot([], [], ls="none", marker=marker, color=colour, ms=5, label=label)   # legend keys, filled
        if realization_label:
            ax.plot([], [], ls="none", marker=marker, ms=2.5, color=colour, alpha=0.35, label=realization_label)
        return int(fl.sum())
    y = da.transpose(axis).values * scale
    fl = (flag.transpose(axis).values == 1) if flag is not None else np.zeros(y.shape, bool)
    points(xs[~fl], y[~fl], False, ms=4)
    points(xs[fl], y[fl], True, ms=4, mew=1.2)
    ax.plot([], [], ls="none", marker=marker, color=colour, ms=4, label=label)   # legend key, filled
    return int(fl.sum())


#: Suffixes of the phase metrics that cannot be negative (a range max − min, a standard deviation).
NON_NEGATIVE = ("_range", "_std")


def is_non_negative(variable: str) -> bool:
    """Whether metric ``variable`` cannot be negative (:data:`NON_NEGATIVE`)."""
    return variable.endswith(NON_NEGATIVE)


def plotted_band(fit: dict, grid, non_negative: bool):
    """The fitted line and its 95 % band at ``grid`` as drawn [the fit's units].

    Parameters
    ----------
    fit : dict
        A line fit's statistics (:func:`pipeline.analysis.line_band`).
    grid : array_like
        Abscissae [the fit's x unit].
    non_negative : bool
        The metric cannot be negative (a range, a standard deviation).

    Returns
    -------
    y, lower, upper : ndarray

    Notes
    -----
    For a quantity that cannot be negative, the line and both band edges are clipped at
    zero: ``max(0, ŷ ∓ t·s(ŷ))``. The band is a confidence set for the mean response, and
    the mean of a non-negative quantity lies in [0, ∞), so intersecting the set with it
    loses no coverage. The fit itself stays linear in the metric, as the study's published
    fits (Tables 3 and 4) are, so that its slope remains comparable with theirs; a fit in
    log space would keep the band positive too, but its slope would no longer be the
    study's quantity.
    """
    yl, lo, hi = line_band(fit, grid)
    if non_negative:
        yl, lo, hi = (np.clip(a, 0.0, None) for a in (yl, lo, hi))
    return yl, lo, hi


def _fit_line(ax, ctx: Context, variable: str, axis: str, fixed_axis: str, fixed: float, phase: str,
              sensor=None) -> None:
    """Our fitted line of ``variable`` and its 95 % band on ``ax`` [µm against °/s or kN]; the
    band of a non-negative metric clipped at zero (:func:`plotted_band`), and its axis too."""
    fit = fit_at(ctx, variable, axis, fixed_axis, fixed, phase, sensor)
    non_negative = is_non_negative(variable)
    if fit and math.isfinite(fit["slope"]):
        x = ctx.metrics[axis].values.astype(float)
        grid = np.linspace(np.nanmin(x), np.nanmax(x), 50)
        yl, lo, hi = plotted_band(fit, grid, non_negative)
        gs = grid / 1e3 if axis == "radial_load" else grid
        seeds = realizations(ctx.metrics)
        kind = "WLS" if seeds is not None and seeds.size >= 2 else "OLS"
        ax.plot(gs, yl * 1e6, "-", color="C0", lw=1.2, label=f"{kind} fit (R² = {fmt_number(fit['rsquared'])})")
        ax.fill_between(gs, lo * 1e6, hi * 1e6, color="C0", alpha=0.2, lw=0,
                        label="95 % band" + (", cut at 0" if non_negative and bool((lo <= 0).any()) else ""))
    if non_negative and ax.get_ylim()[0] < 0:
        ax.set_ylim(bottom=0.0)


def _finish_panel(ax, axis: str, ylabel: str, title: str, hollow: int) -> None:
    """Axis labels, title, grid and legend of a metric panel (and the hollow-marker key)."""
    if hollow:
        ax.plot([], [], ls="none", marker="o", mfc="none", mec="0.3", label="extreme at window edge")
    ax.set_xlabel("steady speed [°/s]" if axis == "speed" else "radial load [kN]")
    ax.set_ylabel(ylabel)
    ax.ticklabel_format(axis="y", useOffset=False)
    ax.set_title(title, fontsize=8)
    ax.grid(True, lw=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)


def _ensemble_label(ctx: Context) -> str:
    return "ensemble mean ± 1 SE" if realizations(ctx.metrics) is not None else "cases"


def figure_metric(ctx: Context, refs, path: Path):
    """One panel per reference axis of a (phase, displacement, metric) group, at the ring centre.

    Returns
    -------
    notes : list of str
        Where each panel's other axis is held ('against speed at 30 kN').
    hollow : int
        Markers drawn hollow (range with an extreme at the window's edge).
    """
    r0 = refs[0]
    fig, axes = new_figure(1, len(refs), (4.6 * len(refs), 3.6))
    notes, hollow = [], 0
    sym = "δ_r" if r0.displacement == "radial" else "δ_a"
    for k, ref in enumerate(refs):
        ax = axes[0, k]
        fixed, note = fixed_choice(ctx, ref.fixed_axis, ref.fixed_coordinate)
        notes.append(f"against {AXIS_TITLE[ref.axis]} {note}")
        n = _metric_panel(ax, ctx, ref.variable, ref.axis, ref.fixed_axis, fixed, ref.phase,
                          label=_ensemble_label(ctx))
        hollow += n
        _fit_line(ax, ctx, ref.variable, ref.axis, ref.fixed_axis, fixed, ref.phase)
        mx, my = points_on_line(ctx.measured_metrics, ref.variable, ref.axis, ref.fixed_axis, fixed,
                                PHASES.index(ref.phase))
        if mx.size:
            ax.plot(mx / 1e3 if ref.axis == "radial_load" else mx, my * 1e6, "x", color="C3", ms=8, mew=1.8,
                    label="measured tests (measured/)", zorder=5)
        _finish_panel(ax, ref.axis, f"{PHASE_TITLE[r0.phase]} {r0.metric} of {sym} [µm]", note, n)
    fig.suptitle(f"{PHASE_TITLE[r0.phase]}: {r0.displacement} displacement {METRIC_TITLE[r0.metric]}, "
                 f"{CENTRE_LABEL[r0.displacement]}", fontsize=10)
    save_figure(fig, path)
    return notes, hollow


def figure_sensor_metric(ctx: Context, phase: str, metric: str, specs, path: Path):
    """Sensor metric ``sensor_displacement_<metric>`` of ``phase``: a row per sensor, a column
    per ``(axis, fixed_axis, fixed)`` of ``specs``; fit lines from :attr:`Context.sensor_fits`.

    Returns
    -------
    notes : list of str
    hollow : int
    """
    name = f"{SENSOR}_displacement_{metric}"
    sens = sensors(ctx.metrics)
    fig, axes = new_figure(len(sens), len(specs), (4.6 * len(specs), 0.6 + 3.0 * len(sens)))
    notes, hollow = [], 0
    for j, (axis, fixed_axis, fixed, note) in enumerate(specs):
        notes.append(f"against {AXIS_TITLE[axis]} {note}")
        for i, sn in enumerate(sens):
            ax = axes[i, j]
            n = _metric_panel(ax, ctx, name, axis, fixed_axis, fixed, phase, sensor=sn.value,
                              label=_ensemble_label(ctx))
            hollow += n
            _fit_line(ax, ctx, name, axis, fixed_axis, fixed, phase, sensor=sn.value)
            _finish_panel(ax, axis, f"{PHASE_TITLE[phase]} {metric} of {sn.name} [µm]",
                          f"{sn.label(code=False)}\n{note}", n)
    fig.suptitle(f"{PHASE_TITLE[phase]}: sensor reading {METRIC_TITLE[metric]}", fontsize=10)
    save_figure(fig, path)
    return notes, hollow


#: Cage-slip variables and their labels: against the actual and the nominal contact angle.
CAGE_SLIPS = (("cage_slip", "actual contact angles"), ("cage_slip_nominal", "nominal contact angle"))


def figure_cage_slip(ctx: Context, phase: str, specs, path: Path) -> list:
    """Cage slip of ``phase`` [%] against each ``(axis, fixed_axis, fixed)`` of ``specs``, both
    definitions of :data:`CAGE_SLIPS` present, a series per row of a bearing of several
    rows; returns the notes."""
    fig, axes = new_figure(1, len(specs), (4.6 * len(specs), 3.6))
    notes = []
    for j, (axis, fixed_axis, fixed, note) in enumerate(specs):
        ax = axes[0, j]
        notes.append(f"against {AXIS_TITLE[axis]} {note}")
        for k, (name, what) in enumerate(CAGE_SLIPS):
            if name not in ctx.metrics:
                continue
            rows = rows_of(ctx.metrics, name)
            for i, r in enumerate(rows):
                n = k * len(rows) + i
                _metric_panel(ax, ctx, name, axis, fixed_axis, fixed, phase, row=r, scale=100.0,
                              colour=f"C{n}", marker="os"[k],
                              label=f"{name}" + (f", row {r}" if r is not None else "") + f": {what}",
                              realization_label=None,
                              dodge=0.012 * (2 * n - (2 * len(rows) - 1)) / len(rows))
        ax.axhline(0.0, color="0.5", lw=0.6)
        _finish_panel(ax, axis, f"{PHASE_TITLE[phase]} cage slip [%]", note, 0)
    fig.suptitle(f"{PHASE_TITLE[phase]}: cage slip 1 − ω̄_c/ω_epi", fontsize=10)
    save_figure(fig, path)
    return notes

