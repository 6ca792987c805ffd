"""The report's first section: what a bearing designer reads, one row per operating point.

Per grid point (speed × radial load; with realizations, the ensemble mean of the finished
ones): the smallest static safety factor over the cycle and the phase it falls in, the
rating lives (of the duty cycle and, from the statics, at the steady operating point),
the peak start-up drive torque, the peak cage forces, the peak race sliding speed and
pv, the steady displacements and the stiffness at the steady operating point, each in
engineering units. A value the sweep does not hold is "—", and the section names the
outputs the sweep lacks (sweeps written before the core computed them).

The table is the one source of these numbers: the summary CSV (``report/summary.csv``,
every grid point) and the designer figures (:func:`section_designer_figures`) read the
same :func:`summary_values`.
"""
from __future__ import annotations

import csv
import io
import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcore.output_table import OUTPUT, SERIES, SPECTRUM
from rvcore.profile import PHASES

from ..analysis import REALIZATION
from ..io import write_text_atomic
from ..schema.parameters import readable_number
from .context import ROW, Context, on_base_grid, ensemble_text, extra_dims, realizations
from .figures import (MARKERS, OVERLAP_WITHIN, SAME_WITHIN, identical_label, new_figure, overlap_of,
                      save_figure, spread_of, trace_style)
from .stiffness import STIFFNESS_DISPLAY
from .render import PHASE_TITLE, Heading, Image, Para, Table, fmt_speed, fmt_number, fmt_kn

#: Most grid points listed in the report's table; a larger grid shows its corners and its
#: middle point there, and every point in ``summary.csv``.
MAX_ROWS = 12

#: Shown for a value the sweep does not hold (or that is undefined at that point).
ABSENT = "—"


@dataclass(frozen=True)
class Column:
    """One quantity of the summary table.

    Parameters
    ----------
    key : str
        Short name (figure file names, tests).
    header : str
        Column header with its engineering unit in brackets.
    variable : str
        The ``metrics.nc`` variable it is read from.
    phase : str or None
        The phase it is taken in; None: a per-case scalar, or (``over`` set) every phase.
    over : str or None
        ``"max"`` or ``"min"``: reduce over the phases (and the rows of a bearing of
        several rows); None: the phase's (or scalar's) own value.
    scale : float
        Multiplies the SI value into the header's unit.
    figure : str or None
        The title of its designer figure; None: no figure.
    short : str
        The y-axis label of its designer figure (a symbol and the unit: a long label
        overlaps the neighbouring panel and the title).
    """

    key: str
    header: str
    variable: str
    phase: str | None = None
    over: str | None = None
    scale: float = 1.0
    figure: str | None = None
    short: str = ""


#: The quantities of the summary table, in column order (after speed and radial load).
COLUMNS = (
    Column("safety", "min static safety factor s₀ = (4200 MPa/p_max)³ (ISO 76) [1]", "static_safety_factor_min",
           over="min", figure="smallest static safety factor s₀ = (4200 MPa/p_max)³ over the cycle [1]",
           short="smallest s₀ [1]"),
    Column("life_mrev", "L10r of the duty cycle [Mrev]", "rating_life_L10r", scale=1e-6,
           figure="rating life L10r of the duty cycle [Mrev]", short="L10r of the cycle [Mrev]"),
    Column("modified_life_mrev", "L_nm of the duty cycle (a_ISO step by step, ISO 281 clause 9) [Mrev]",
           "rating_life_L_nm", scale=1e-6, figure="modified rating life L_nm of the duty cycle [Mrev]",
           short="L_nm of the cycle [Mrev]"),
    Column("life_cycles", "L10r of the duty cycle [cycles]", "rating_life_cycles"),
    Column("static_life", "L10r at the steady point (statics) [Mrev]", "reference_rating_life_L10r", scale=1e-6,
           figure="reference rating life L10r at the steady point [Mrev]", short="L10r, steady point [Mrev]"),
    Column("basic_life", "L10 (ISO 281) at the steady point [Mrev]", "basic_rating_life_L10", scale=1e-6),
    Column("startup_torque", "peak start-up drive torque [N m]", "inner_ring_drive_torque_peak", phase="startup",
           figure="peak start-up drive torque [N m]", short="start-up torque [N m]"),
    Column("pocket_force", "peak ball-pocket force [N]", "max_pocket_force_peak", over="max"),
    Column("land_force", "peak cage-land force [N]", "cage_land_force_peak", over="max"),
    Column("sliding", "peak race sliding speed [m/s]", "max_race_sliding_speed_peak", over="max"),
    Column("pv", "peak race pv [MPa m/s]", "max_race_pv_peak", over="max", scale=1e-6),
    Column("delta_r", "steady δ_r mean [µm]", "radial_displacement_mean", phase="steady", scale=1e6),
    Column("delta_a", "steady δ_a mean [µm]", "axial_displacement_mean", phase="steady", scale=1e6),
    *(Column(name, f"{name.split('_')[0]} stiffness [{unit}]", name, scale=scale)
      for name, (scale, unit, _) in STIFFNESS_DISPLAY.items()),
)


def _check_columns() -> None:
    """Every column reads an output of the output table (rvcore.output_table), a per-case one
    (metrics.nc holds no series): a renamed output fails at import, not in a report."""
    for col in COLUMNS:
        row = OUTPUT.get(col.variable)
        if row is None or row.kind in (SERIES, SPECTRUM):
            raise ValueError(f"pipeline.report.summary: column {col.key!r} reads {col.variable!r}, "
                             "which is no per-case output of rvcore.output_table")


_check_columns()


def _reduce(a: np.ndarray, axis: int, how: str) -> np.ndarray:
    """NaN-ignoring min/max/mean of ``a`` along ``axis``; NaN (and no warning) where all are NaN."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return {"min": np.nanmin, "max": np.nanmax, "mean": np.nanmean}[how](a, axis=axis)


def _grid(ctx: Context, name: str) -> np.ndarray | None:
    """``name`` of ``metrics.nc`` as an array ``(speed, radial_load, [phase], [row], [realization])``
    at the first value of any other sweep dimension; None when the sweep lacks it."""
    m = on_base_grid(ctx.metrics, first_realization=False)
    if name not in m:
        return None
    da = m[name]
    order = [d for d in ("speed", "radial_load", "phase", ROW, REALIZATION) if d in da.dims]
    rest = [d for d in da.dims if d not in order]
    if rest:   # a dimension the summary does not know (a sensor): its first entry
        da = da.isel({d: 0 for d in rest})
    da = da.transpose(*order)
    a = np.asarray(da.values, dtype=np.float64)
    # Broadcast to (speed, radial_load, phase, row, realization) so each reduction has its axis.
    shape = []
    for d in ("speed", "radial_load", "phase", ROW, REALIZATION):
        shape.append(da.sizes[d] if d in da.dims else 1)
    return a.reshape(shape)


def _column_values(ctx: Context, col: Column):
    """``(values (speed, radial_load) in the column's unit, phase index array or None)``;
    None when the sweep lacks the variable.

    Reduced over the row (and, with ``over``, the phase) per realization first, then the
    ensemble mean over the realizations that hold a value. The phase index returned is
    where the ensemble-mean value is extreme (``over`` set), -1 where no phase holds one.
    """
    a = _grid(ctx, col.variable)
    if a is None:
        return None, None
    how = col.over or "max"
    a = _reduce(a, 3, how)                            # rows of a bearing of several rows
    where = None
    if col.phase is not None:
        a = a[:, :, PHASES.index(col.phase), :]
    elif col.over is not None:
        per_phase = _reduce(a, 3, "mean")             # (speed, load, phase): ensemble mean per phase
        filled = np.where(np.isnan(per_phase), np.inf if how == "min" else -np.inf, per_phase)
        where = (np.argmin if how == "min" else np.argmax)(filled, axis=2)
        where = np.where(np.isnan(per_phase).all(axis=2), -1, where)
        a = _reduce(a, 2, how)
    else:
        a = a[:, :, 0, :]
    return _reduce(a, 2, "mean") * col.scale, where


@dataclass
class Summary:
    """The summary of a sweep: the grid, every column's values and the safety factor's phase.

    ``values[key]`` is ``(speed, radial_load)`` in the column's unit, None when the sweep
    lacks the variable; ``safety_phase`` the phase index (−1: none) of the smallest safety
    factor, None without one; ``safety_time`` the time of it [s] (without realizations).
    """

    speeds: np.ndarray
    loads: np.ndarray
    values: dict
    safety_phase: np.ndarray | None
    safety_time: np.ndarray | None

    def lacking(self) -> list:
        """The variables of :data:`COLUMNS` the sweep lacks, in column order."""
        return [c.variable for c in COLUMNS if self.values[c.key] is None]

    def phase_text(self, i: int, j: int) -> str:
        """'start-up' (or 'start-up, 0.62 s') where s₀ is smallest at grid point (i, j)."""
        if self.safety_phase is None or self.safety_phase[i, j] < 0:
            return ABSENT
        k = int(self.safety_phase[i, j])
        text = PHASE_TITLE[PHASES[k]]
        if self.safety_time is not None and math.isfinite(self.safety_time[i, j]):
            text += f", {fmt_number(self.safety_time[i, j], 3)} s"
        return text


def summary_values(ctx: Context) -> Summary:
    """Every column of :data:`COLUMNS` over the grid (see :class:`Summary`)."""
    m = on_base_grid(ctx.metrics, first_realization=False)
    values, phase, time = {}, None, None
    for col in COLUMNS:
        values[col.key], where = _column_values(ctx, col)
        if col.key == "safety" and where is not None:
            phase = where
            t = _grid(ctx, "static_safety_factor_min_time")
            if t is not None and realizations(ctx.metrics) is None:
                t = t[:, :, :, 0, 0]
                time = np.array([[t[i, j, k] if k >= 0 else math.nan for j, k in enumerate(row)]
                                 for i, row in enumerate(where)])
    return Summary(np.asarray(m["speed"].values, dtype=np.float64),
                   np.asarray(m["radial_load"].values, dtype=np.float64), values, phase, time)


def _shown_points(n_speed: int, n_load: int) -> list:
    """Grid indices shown in the report: all of a grid of at most :data:`MAX_ROWS` points,
    otherwise the four corners and the middle point, in grid order."""
    if n_speed * n_load <= MAX_ROWS:
        return [(i, j) for i in range(n_speed) for j in range(n_load)]
    picked = {(i, j) for i in (0, n_speed - 1) for j in (0, n_load - 1)} | {(n_speed // 2, n_load // 2)}
    return sorted(picked)


def table_cell(v: float, digits: int = 3) -> str:
    """``v`` to ``digits`` significant digits (below a million written out: 1200), a larger or
    very small one as ``1.23×10⁷``; "∞" for +inf (a life without load), "—" for NaN."""
    if v is not None and math.isinf(v) and v > 0:
        return "∞"   # an unloaded bearing's life
    if v is None or not math.isfinite(v):
        return ABSENT
    text = fmt_number(v, digits)
    if "e+" in text and abs(v) < 1e6:   # 1.2e+03: plain 1200, rounded to the digits
        text = f"{float(text):.0f}"
    return readable_number(text)


def summary_rows(s: Summary, points) -> list:
    """The table's rows (strings) at grid indices ``points``."""
    rows = []
    for i, j in points:
        row = [fmt_speed(s.speeds[i]), fmt_kn(s.loads[j])]
        for col in COLUMNS:
            v = s.values[col.key]
            row.append(table_cell(None if v is None else float(v[i, j])))
            if col.key == "safety":
                row.append(s.phase_text(i, j))
        rows.append(row)
    return rows


def summary_header() -> list:
    """The table's header: speed, radial load, then :data:`COLUMNS` (and the phase of s₀)."""
    out = ["speed [°/s]", "radial load [kN]"]
    for col in COLUMNS:
        out.append(col.header)
        if col.key == "safety":
            out.append("s₀ smallest in")
    return out


def summary_csv(s: Summary) -> str:
    """Every grid point as CSV: the table's header, values to 6 significant digits, empty
    where the table shows "—"."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(summary_header())
    for i in range(s.speeds.size):
        for j in range(s.loads.size):
            row = [f"{s.speeds[i]:.6g}", f"{s.loads[j] / 1e3:.6g}"]
            for col in COLUMNS:
                v = s.values[col.key]
                x = math.nan if v is None else float(v[i, j])
                row.append(f"{x:.6g}" if not math.isnan(x) else "")
                if col.key == "safety":
                    p = s.phase_text(i, j)
                    row.append("" if p == ABSENT else p)
            w.writerow(row)
    return buf.getvalue()


def section_summary(ctx: Context) -> list:
    """The blocks of the section 'Summary per operating point'; writes ``summary.csv`` in
    the report's folder (:attr:`Context.summary_path`), of :attr:`Context.summary`
    (computed here when unset)."""
    if ctx.summary is None:
        ctx.summary = summary_values(ctx)
    s = ctx.summary
    ctx.report_dir.mkdir(parents=True, exist_ok=True)
    csv_path = ctx.summary_path = write_text_atomic(ctx.report_dir / "summary.csv", summary_csv(s))
    points = _shown_points(s.speeds.size, s.loads.size)
    total = s.speeds.size * s.loads.size
    ens = ensemble_text(ctx)
    blocks = [Heading(2, "Summary per operating point")]
    text = ("**What the columns are.** One row per operating point (steady speed and radial load of the "
            "profile)" + (f"; each value the ensemble mean over the finished realizations of {ens}" if ens else "")
            + ". s₀ = (4200 MPa / largest Hertz pressure)³, ISO 76's load ratio C₀/P₀ (ball bearings), its smallest value over "
            "the whole cycle and the phase it falls in; L10r of the duty cycle: ISO/TS 16281 reference rating "
            "life with the equivalent contact loads accumulated over the ring's revolutions at every integrator "
            "step (Palmgren–Miner), in million revolutions of the inner ring and in cycles of the profile; "
            "L10r and L10 at the steady point: from the quasi-static load distribution (ISO/TS 16281) and from "
            "the applied load (ISO 281) at the loads in the middle of the steady phase; peak forces, sliding "
            "speed and pv: the largest over the cycle; δ_r, δ_a at the ring centre; stiffness: the direct "
            "terms of the quasi-static tangent stiffness at the steady point.")
    extra = extra_dims(ctx.metrics)
    if extra:
        text += (" Other sweep dimensions are held at their first value ("
                 + ", ".join(f"{d} index 0" for d in extra) + "), as in the figures.")
    lacking = s.lacking()
    if lacking:
        blocks.append(Para("This sweep lacks " + ", ".join(f"`{n}`" for n in lacking)
                           + " (written by a version of the core that did not compute "
                           + ("it" if len(lacking) == 1 else "them") + f"): {ABSENT} in "
                           + ("its column." if len(lacking) == 1 else "their columns.")))
    if len(points) < total:
        blocks.append(Para(f"The grid has {total} points; shown are the four corners and the middle point. "
                           f"Every point is in `report/{csv_path.name}` (same columns)."))
    else:
        blocks.append(Para(f"Every grid point is shown; the same table is in `report/{csv_path.name}`."))
    blocks.append(Table(summary_header(), summary_rows(s, points), sticky=True))
    blocks.append(Para(f"{ABSENT} in a row where a column has data elsewhere: no finished case at that point "
                       "(see Cases), or the value is undefined there (no loaded contact: no safety factor)."))
    blocks.append(Para(text))   # the definitions below the numbers: the table is what the designer reads first
    return blocks


def figure_designer(s: Summary, col: Column, path: Path, ens: bool) -> list:
    """``col`` against speed (a line per radial load) and against radial load (a line per speed).

    Lines of one panel identical within :data:`.figures.SAME_WITHIN` (the same at every
    speed, as a quasi-static quantity is) are drawn as one line labelled so; other lines
    differ in marker and colour. Returns the notes on the panels whose lines were merged.
    """
    import textwrap

    import matplotlib

    v = s.values[col.key]
    fig, axes = new_figure(1, 2, (10.0, 4.0))
    # a sequential map for many lines, its pale end cut off (yellow on white is unreadable);
    # distinct colours for up to ten
    cmap = matplotlib.colormaps["viridis"]
    notes = []
    for ax, axis in zip(axes[0], ("speed", "radial_load")):
        x = s.speeds if axis == "speed" else s.loads / 1e3
        others = s.loads if axis == "speed" else s.speeds
        ys = [v[:, k] if axis == "speed" else v[k, :] for k in range(len(others))]
        spread = spread_of(ys)
        what = "radial loads" if axis == "speed" else "speeds"
        if len(others) > 1 and math.isfinite(spread) and spread <= SAME_WITHIN:
            label = identical_label(what, len(others), spread)
            ax.plot(x, ys[0], "-o", ms=4, lw=1.4, color="C0", label=label)
            notes.append(f"against {'speed' if axis == 'speed' else 'radial load'}: {label}, drawn as one line")
        else:
            overlap = overlap_of(ys)
            close = len(others) > 1 and math.isfinite(overlap) and overlap <= OVERLAP_WITHIN
            for k, o in enumerate(others):
                colour = f"C{k}" if len(others) <= 10 else cmap(0.85 * k / max(len(others) - 1, 1))
                style = trace_style(k, len(others)) if close else {"lw": 1.0, "ls": "-"}
                style["color"] = colour
                ax.plot(x, ys[k], marker=MARKERS[k % len(MARKERS)], ms=4, mfc="none" if close and k else colour,
                        label=fmt_kn(o) if axis == "speed" else fmt_speed(o), **style)
            if close:
                label = (f"the {len(others)} {what}' lines overlap (within {fmt_number(spread * 100, 1)} %)")
                notes.append(f"against {'speed' if axis == 'speed' else 'radial load'}: {label}; drawn in "
                             "distinct dashes and markers")
        if col.key == "safety":   # ISO 76's reference: s₀ = 1 is the peak pressure of 4200 MPa
            ax.axhline(1.0, color="C3", lw=0.8, ls="--", label="s₀ = 1 (4200 MPa)")
        ax.set_xlabel("steady speed [°/s]" if axis == "speed" else "radial load [kN]")
        ax.set_ylabel(col.short or col.header, fontsize=9)
        ax.grid(True, lw=0.3)
        title = "radial load" if axis == "speed" else "speed"
        if notes and notes[-1].startswith("against " + ("speed" if axis == "speed" else "radial load") + ": the "):
            title += f": lines overlap\n(within {fmt_number(spread * 100, 1)} %)"
        ax.legend(fontsize=8, title=title, title_fontsize=8)
    title = col.figure + (" (ensemble means)" if ens else "")
    fig.suptitle("\n".join(textwrap.wrap(title, 95)), fontsize=10)
    save_figure(fig, path)
    return notes


def section_designer_figures(ctx: Context) -> list:
    """The designer outputs of :data:`COLUMNS` with a figure, against speed and radial load,
    where the sweep holds them (of :attr:`Context.summary`)."""
    s = ctx.summary if ctx.summary is not None else summary_values(ctx)
    cols = [c for c in COLUMNS if c.figure and s.values[c.key] is not None
            and bool(np.isfinite(s.values[c.key]).any())]
    if not cols:
        return []
    ens = bool(ensemble_text(ctx))
    blocks = [Heading(2, "Designer outputs against speed and load"),
              Para("The quantities of the summary table that a design turns on, at every grid point: against "
                   "the steady speed with a line per radial load, and against the radial load with a line per "
                   "speed" + ("; ensemble means over the finished realizations" if ens else "") + ".")]
    for col in cols:
        p = ctx.figure_path(f"designer_{col.key}.png")
        notes = figure_designer(s, col, p, ens)
        blocks.append(Heading(3, col.header))
        if notes:
            blocks.append(Para("; ".join(n[0].upper() + n[1:] for n in notes) + "."))
        blocks.append(Image(f"figures/{p.name}", col.figure))
    return blocks
