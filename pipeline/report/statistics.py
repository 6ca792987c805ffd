"""Tolerance statistics in the report: the draws' distributions per tolerance class along the
study's two fitted lines with the study's fits marked, the percentiles and the Sobol' table.

Reads ``metrics.nc`` and ``statistics.nc`` only (:mod:`pipeline.analysis.statistics`).
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.metrics import nearest
from ..analysis.statistics import CONFIDENCE, QUANTILES, SOBOL_PHASES, STATISTICS_FILE, draws_of
from ..io.netcdf import flag_names
from ..schema.statistics import DRAW, SAMPLE
from .context import Context
from .figures import new_figure, save_figure
from .imperfect import CLASS_AXIS, class_label, class_name, ordered_classes
from .render import Heading, Image, Para, Table, fmt_kn, fmt_number, fmt_speed

_PHASE_TITLE = {"startup": "start-up", "steady": "steady", "deceleration": "deceleration"}


def _classes(ctx: Context) -> list:
    """The class coordinate values, tightest first ([None] without a class axis)."""
    if CLASS_AXIS not in ctx.metrics.dims:
        return [None]
    return ordered_classes(ctx, ctx.metrics[CLASS_AXIS].values)


def _label(ctx: Context, v) -> str:
    return "this bearing" if v is None else class_label(class_name(ctx, v))


def _draws(ctx: Context, name: str, phase: str, cls, point: dict) -> np.ndarray:
    """The finite draws of metric ``name`` in ``phase`` at ``point`` (class ``cls``) [m]."""
    da = draws_of(ctx.metrics[name])
    if "phase" in da.dims:
        da = da.isel(phase=flag_names(ctx.metrics["phase"]).index(phase))
    if cls is not None:
        da = da.sel({CLASS_AXIS: cls})
    da = da.sel(point)
    da = da.isel({d: 0 for d in da.dims if d != DRAW})
    x = np.asarray(da.values, dtype=np.float64)
    return x[np.isfinite(x)]


def _line_figure(ctx: Context, axis: str, fits: list, fixed_axis: str, fixed: float, file: str) -> str:
    """Box plots of the draws against ``axis`` at ``fixed_axis`` = ``fixed``, one panel per
    study fit (its line dashed), a box per class at every grid value."""
    classes = _classes(ctx)
    n = len(fits)
    cols = min(3, n)
    rows = int(math.ceil(n / cols))
    fig, axes = new_figure(rows, cols, (4.2 * cols, 3.3 * rows))
    xs = np.asarray(ctx.metrics[axis].values, dtype=np.float64)
    scale = 1.0 if axis == "speed" else 1e-3
    spacing = np.min(np.diff(np.sort(xs))) * scale if xs.size > 1 else 1.0
    span = np.ptp(xs) * scale
    width = min(0.7 * spacing, 0.2 * span if span > 0 else spacing) / max(len(classes), 1)
    for k, ref in enumerate(fits):
        ax = axes[k // cols, k % cols]
        for m, cls in enumerate(classes):
            data, pos = [], []
            for x in xs:
                d = _draws(ctx, ref.variable, ref.phase, cls, {axis: x, fixed_axis: fixed})
                if d.size:
                    data.append(d * 1e6)
                    pos.append(x * scale + (m - (len(classes) - 1) / 2) * width)
            if data:
                bp = ax.boxplot(data, positions=pos, widths=width * 0.9, whis=(5, 95), showfliers=False,
                                patch_artist=True, manage_ticks=False)
                for patch in bp["boxes"]:
                    patch.set(facecolor=f"C{m}", alpha=0.5)
                ax.plot([], [], color=f"C{m}", lw=6, alpha=0.5, label=_label(ctx, cls))
        grid = np.linspace(xs.min(), xs.max(), 50)
        y = (ref.intercept_si() + ref.slope_in_coordinate_units() * grid) * 1e6
        ax.plot(grid * scale, y, "k--", lw=1.0, label="study's fit")
        ax.set_title(f"{_PHASE_TITLE.get(ref.phase, ref.phase)} {ref.displacement} {ref.metric}", fontsize=9)
        ax.set_xlabel("speed [deg/s]" if axis == "speed" else "radial load [kN]", fontsize=9)
        ax.set_ylabel("[µm]", fontsize=9)
        ax.grid(True, lw=0.3)
        if k == 0:
            ax.legend(fontsize=7)
    for k in range(n, rows * cols):
        axes[k // cols, k % cols].set_visible(False)
    path = ctx.figure_path(file)
    save_figure(fig, path)
    return path.name


def _sobol_table(ctx: Context, cls, point: dict) -> Table | None:
    st = ctx.statistics
    names = [v for v in st.data_vars if v.startswith("sobol_first_order_") and not v.endswith(("_ci_low", "_ci_high"))]
    if not names:
        return None
    inputs = [str(x) for x in st["tolerance_input"].values]
    rows = []
    for v in names:
        out = v.removeprefix("sobol_first_order_")
        da = st[v]
        sel = {k: val for k, val in point.items() if k in da.dims}
        if cls is not None and CLASS_AXIS in da.dims:
            sel[CLASS_AXIS] = cls
        phases = [None]
        if "phase" in da.dims:
            phases = [(p, name) for p, name in zip(da["phase"].values, flag_names(da["phase"]))
                      if name in SOBOL_PHASES]
        for ph in phases:
            s = dict(sel) if ph is None else {**sel, "phase": ph[0]}

            def cell(name, kind):
                a = st[name].sel(s)
                a = a.isel({d: 0 for d in a.dims if d != "tolerance_input"})
                lo = st[f"{name}_ci_low"].sel(s)
                lo = lo.isel({d: 0 for d in lo.dims if d != "tolerance_input"})
                hi = st[f"{name}_ci_high"].sel(s)
                hi = hi.isel({d: 0 for d in hi.dims if d != "tolerance_input"})
                return [(float(a.values[j]), float(lo.values[j]), float(hi.values[j])) for j in range(len(inputs))]

            s1 = cell(v, "first")
            stt = cell(f"sobol_total_order_{out}", "total")
            label = out.replace("_", " ") + ("" if ph is None else f", {_PHASE_TITLE.get(ph[1], ph[1])}")
            rows.append([label] + [f"{fmt_number(a[0], 2)} [{fmt_number(a[1], 2)}, {fmt_number(a[2], 2)}] / "
                                   f"{fmt_number(b[0], 2)} [{fmt_number(b[1], 2)}, {fmt_number(b[2], 2)}]"
                                   for a, b in zip(s1, stt)])
    return Table(["output"] + inputs, rows)


def section_statistics(ctx: Context) -> list:
    """The tolerance statistics (none without ``[statistics]`` draws)."""
    st = ctx.statistics
    if st is None:
        return []
    conf = ctx.configuration
    spec = getattr(conf, "statistics", None) if conf is not None else None
    n = ctx.metrics.sizes[DRAW] * (2 if SAMPLE in ctx.metrics.dims else 1)
    blocks = [Heading(2, "Tolerance statistics"),
              Para(f"Each grid point ran {ctx.metrics.sizes[DRAW]} draws of the bearing's imperfections within its "
                   "tolerance class (`[statistics]`, docs/inputs.md)"
                   + (f" by {spec['method']} sampling, seed {spec['seed']}, over "
                      + ", ".join(f"`{x}`" for x in spec["inputs"]) if isinstance(spec, dict) else "")
                   + f"; the distributions below are of {n} draws per point"
                   + (" (Saltelli's A and B)" if SAMPLE in ctx.metrics.dims else "")
                   + f". Percentiles {', '.join(f'{q:g}' for q in QUANTILES)} of every phase metric and designer output, "
                   f"with {CONFIDENCE:.0%} bootstrap intervals, are in `{STATISTICS_FILE}`.")]
    refs = ctx.references or []
    for axis, fixed_axis, file, what in (("speed", "radial_load", "statistics_speed.png", "speed"),
                                         ("radial_load", "speed", "statistics_load.png", "radial load")):
        fits = [r for r in refs if r.axis == axis and r.variable in ctx.metrics]
        if not fits or ctx.metrics.sizes.get(axis, 0) < 2:
            continue
        fixed = nearest(ctx.metrics[fixed_axis].values, fits[0].fixed_coordinate)
        name = _line_figure(ctx, axis, fits, fixed_axis, fixed, file)
        at = fmt_kn(fixed) if fixed_axis == "radial_load" else fmt_speed(fixed)
        blocks += [Para(f"Against {what} at {at} (the study's line): boxes from the 25th to the 75th percentile "
                        "with the median, whiskers from the 5th to the 95th, a colour per tolerance class; dashed: "
                        "the study's fit."),
                   Image(f"figures/{name}", f"distributions of the draws against {what}")]
    table_blocks = []
    if "speed" in ctx.metrics.dims and "radial_load" in ctx.metrics.dims:
        load = nearest(ctx.metrics["radial_load"].values, 30e3)
        speed = float(np.max(ctx.metrics["speed"].values))
        for cls in _classes(ctx):
            table = _sobol_table(ctx, cls, {"speed": speed, "radial_load": load})
            if table is not None:
                label = _label(ctx, cls)
                table_blocks += [Para(f"{label[0].upper()}{label[1:]} at {fmt_speed(speed)}, {fmt_kn(load)}: first-order / "
                                      f"total Sobol' index of each output against each input, with {CONFIDENCE:.0%} "
                                      "bootstrap intervals (every grid point's are in "
                                      f"`{STATISTICS_FILE}`)."), table]
    if table_blocks:
        blocks += [Heading(3, "Which tolerance drives each range (Sobol' indices)"), *table_blocks]
    return blocks
