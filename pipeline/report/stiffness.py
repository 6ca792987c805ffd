"""The bearing's stiffness at the steady operating point, against every sweep axis.

``metrics.nc`` carries, per case, the direct terms of the quasi-static tangent stiffness
at the loads in the middle of the steady phase (:data:`pipeline.analysis.STIFFNESS`):
radial [N m-1] along the radial load, axial [N m-1] and tilting [N m rad-1] about the axis
normal to the radial load. The report plots them in N/µm and N m/mrad against each
numeric sweep axis, and computes the centrifugal load of a ball at the sweep's highest
speed to show why the quasi-static stiffness leaves the speed out.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rvcore.bearing.geometry import ball_mass, epicyclic_cage_ratio
from rvcore.bearing.geometry import centrifugal_ball_load as centrifugal_force

from ..analysis import REALIZATION, STIFFNESS
from .context import SENSOR, Context
from .figures import MARKERS, SAME_WITHIN, identical_label, new_figure, save_figure, spread_of
from .loads import stored_statics
from .render import Heading, Image, Para, fmt_number

#: Suffix of the compliant stiffness (1/C_ii, every other coordinate free) beside each direct one.
COMPLIANT = "_compliant"

#: Engineering scale and unit of each stiffness: (factor from SI, unit, symbol).
STIFFNESS_DISPLAY = {"radial_stiffness": (1e-6, "N/µm", "k_r"), "axial_stiffness": (1e-6, "N/µm", "k_a"),
            "tilting_stiffness": (1e-3, "N m/mrad", "k_θ")}

#: Axes preferred for the lines of a panel (the first that varies and is not the x axis).
_SERIES_ORDER = ("radial_load", "axial_load", "moment", "speed")

#: Most lines per panel.
_MAX_LINES = 5

#: Dimensions that are not sweep axes.
_NOT_AXES = (REALIZATION, SENSOR, "row", "phase", "elapsed_time")


def _axis_display(ctx: Context, axis: str):
    """(factor, label) of a sweep axis: °/s for speed, kN and kN m for forces and moments."""
    c = ctx.metrics[axis]
    units = str(c.attrs.get("units", ""))
    name = "steady speed" if axis == "speed" else str(c.attrs.get("long_name", axis)).removeprefix("sweep axis ")
    if axis == "speed":
        return 1.0, "steady speed [°/s]"
    if units == "N":
        return 1e-3, f"{name} [kN]"
    if units in ("N m", "N.m", "m N"):
        return 1e-3, f"{name} [kN m]"
    return 1.0, f"{name} [{units}]" if units and units != "1" else name


def _axis_name(ctx: Context, axis: str) -> str:
    return _axis_display(ctx, axis)[1].split(" [")[0]


def _value_text(ctx: Context, axis: str, index: int) -> str:
    """The ``index``-th value of ``axis`` in its display unit ('30 kN', '120 °/s')."""
    factor, label = _axis_display(ctx, axis)
    unit = label.split(" [")[1].rstrip("]") if " [" in label else ""
    return f"{fmt_number(float(ctx.metrics[axis].values[index]) * factor, 4)} {unit}".strip()


def stiffness_axes(ctx: Context) -> list:
    """The numeric sweep axes with more than one value that the stiffness is stored over."""
    present = [n for n in STIFFNESS if n in ctx.metrics]
    if not present:
        return []
    dims = ctx.metrics[present[0]].dims
    return [d for d in dims if d not in _NOT_AXES and ctx.metrics.sizes[d] > 1 and d in ctx.metrics.coords
            and np.asarray(ctx.metrics[d].values).dtype.kind == "f"]


def _lines_axis(axes: list, axis: str):
    for a in _SERIES_ORDER:
        if a in axes and a != axis:
            return a
    rest = [a for a in axes if a != axis]
    return rest[0] if rest else None


def _line(ctx: Context, name: str, held: dict, axis: str, other, p: int) -> np.ndarray:
    """Stiffness ``name`` along ``axis`` at index ``p`` of ``other`` (and ``held``), as floats [SI];
    a row or sensor dimension, which would not belong here, at its first entry."""
    da = ctx.metrics[name].isel({d: k for d, k in held.items() if d in ctx.metrics[name].dims})
    line = da.isel({other: p}) if other is not None else da
    extra = [d for d in line.dims if d != axis]
    if extra:
        line = line.isel({d: 0 for d in extra})
    return np.asarray(line.values, dtype=np.float64)


def figure_stiffness(ctx: Context, axes: list, path: Path) -> list:
    """A row per stiffness, a column per sweep axis, a line per value of another axis.

    Where a column's lines are identical within :data:`.figures.SAME_WITHIN` (the quasi-static
    stiffness is the same at every speed), they are drawn as one line labelled so; other
    lines differ in marker and colour. Returns the notes on where each column's other axes
    are held (and which lines were merged).
    """
    present = [n for n in STIFFNESS if n in ctx.metrics]
    fig, grid = new_figure(len(present), len(axes), (4.6 * len(axes), 0.9 + 2.8 * len(present)))
    notes = []
    for j, axis in enumerate(axes):
        other = _lines_axis(axes, axis)
        fx, xlabel = _axis_display(ctx, axis)
        held = {}
        for d in ctx.metrics[present[0]].dims:
            if d not in (axis, other) and d not in ("row", SENSOR):
                held[d] = 0
        picks = [0]
        if other is not None:
            n = ctx.metrics.sizes[other]
            picks = sorted(set(np.linspace(0, n - 1, min(n, _MAX_LINES)).round().astype(int).tolist()))
        olabel = _axis_display(ctx, other)[1] if other is not None else ""
        held_text = [f"{_axis_name(ctx, d)} {_value_text(ctx, d, 0)}" for d in held if d in axes]
        # one line for all values of the other axis where they are identical, in every stiffness
        names = present + [f"{n}{COMPLIANT}" for n in present if f"{n}{COMPLIANT}" in ctx.metrics]
        spread = max((spread_of([_line(ctx, n, held, axis, other, p) for p in picks]) for n in names),
                     default=math.nan) if other is not None and len(picks) > 1 else math.nan
        merged = math.isfinite(spread) and spread <= SAME_WITHIN
        other_name = _axis_name(ctx, other) if other is not None else ""
        what = other_name + ("s" if not other_name.endswith("s") else "es") if other is not None else ""
        merged_label = identical_label(what, len(picks), spread) if merged else ""
        notes.append(f"against {_axis_name(ctx, axis)}"
                     + (f", a line per {other_name}" if other is not None and not merged else "")
                     + (f", one line for {merged_label}" if merged else "")
                     + (f", at {', '.join(held_text)}" if held_text else ""))
        x = np.asarray(ctx.metrics[axis].values, dtype=np.float64) * fx
        for i, name in enumerate(present):
            ax = grid[i, j]
            scale, unit, sym = STIFFNESS_DISPLAY[name]
            for m, p in enumerate(picks[:1] if merged else picks):
                y = _line(ctx, name, held, axis, other, p) * scale
                label = merged_label if merged else (_value_text(ctx, other, p) if other is not None else None)
                ok = np.isfinite(y)
                ax.plot(x[ok], y[ok], marker=MARKERS[m % len(MARKERS)], ms=4, lw=1.0, color=f"C{m}", label=label)
                compliant = f"{name}{COMPLIANT}"
                if compliant in ctx.metrics:   # the same line with the other coordinates free, dashed
                    yc = _line(ctx, compliant, held, axis, other, p) * scale
                    okc = np.isfinite(yc)
                    ax.plot(x[okc], yc[okc], marker=MARKERS[m % len(MARKERS)], ms=3, lw=1.0, ls="--",
                            mfc="none", color=f"C{m}")
            ax.set_xlabel(xlabel)
            ax.set_ylabel(f"{sym} [{unit}]")
            ax.ticklabel_format(axis="y", useOffset=False)
            ax.grid(True, lw=0.3)
            if other is not None and i == 0:
                ax.legend(fontsize=8, title=olabel if not merged else None, title_fontsize=8)
    fig.suptitle("Stiffness at the steady operating point (quasi-static tangent stiffness)\n"
                 "solid: direct (the other coordinates held); dashed: compliant (the others free)", fontsize=10)
    save_figure(fig, path)
    return notes


def centrifugal_ball_load(ctx: Context):
    """The largest centrifugal load of a ball at the sweep's highest speed [N], and that speed [°/s].

    ``F_c = m_b·(d_m/2)·ω_c²`` with ``ω_c = ω_i·½(1 − D·cos α/d_m)`` the epicyclic cage
    speed (the ball's orbital speed), per row of the stored configuration; NaN without one.
    """
    conf = ctx.configuration
    speeds = np.asarray(ctx.metrics["speed"].values, dtype=np.float64)
    w_deg = float(np.nanmax(speeds)) if speeds.size else math.nan
    if conf is None or not math.isfinite(w_deg):
        return math.nan, w_deg
    b = conf.bearing
    w_i = math.radians(w_deg)
    forces = [centrifugal_force(ball_mass(r, b.ball_material), r.pitch_diameter / 2.0, w_i * epicyclic_cage_ratio(r))
              for r in b.rows]
    return max(forces), w_deg


def section_stiffness(ctx: Context) -> list:
    """The "Stiffness at the operating point" section: figure and the speed argument.

    The centrifugal load is compared with the largest contact load of the stored statics
    at the extreme cases (:func:`.loads.stored_statics`).
    """
    blocks = [Heading(2, "Stiffness at the operating point")]
    present = [n for n in STIFFNESS if n in ctx.metrics]
    if not present:
        blocks.append(Para("The sweep holds no stiffness at the operating point (`radial_stiffness`, "
                           "`axial_stiffness`, `tilting_stiffness`): it was written by a version that did not "
                           "compute them."))
        return blocks
    text = ("The radial stiffness k_r (along the radial load), the axial stiffness k_a and the tilting "
            "stiffness k_θ (about the axis normal to the radial load) are the direct terms of the quasi-static "
            "tangent stiffness of the inner ring at the steady loads (those the profile applies in the middle "
            "of its steady phase): Hertz's law at every contact, the balls in equilibrium, rigid rings, "
            "differentiated about the equilibrium. A direct term is the load per unit displacement in its own "
            "direction with every other coordinate held; beside it (dashed) the compliant stiffness 1/C_ii, "
            "C = K⁻¹, with every other coordinate free, which is what a single load change meets (with the "
            "ring's tilt free, a radial load also tilts the ring, and the compliant k_r is much lower). "
            f"The inner ring's tilt was {ctx.sweep.attrs.get('inner_ring_tilt', 'free')} "
            "(`inner_ring.tilt`). They are in N/µm and N m/mrad. Being quasi-static, they do not "
            "depend on the speed except through the loads.")
    fc, w = centrifugal_ball_load(ctx)
    if math.isfinite(fc):
        qmax = max((c.max_contact_load for c in stored_statics(ctx).corners if c.solved), default=math.nan)
        text += (f" That is sound here: at the sweep's highest speed, {fmt_number(w, 4)} °/s, a ball's centrifugal load "
                 f"m_b·(d_m/2)·ω_c², with ω_c the epicyclic cage speed from the stored geometry, is at most "
                 f"{fmt_number(fc, 3)} N")
        text += (f", against contact loads of up to {fmt_number(qmax / 1e3, 3)} kN at the extreme operating points "
                 f"(see the load distribution)." if math.isfinite(qmax) else ".")
    missing = [n for n in STIFFNESS if n not in ctx.metrics]
    if missing:
        text += f" The sweep holds no {', '.join(f'`{n}`' for n in missing)}."
    blocks.append(Para(text))
    axes = stiffness_axes(ctx)
    if not axes:
        vals = "; ".join(f"{STIFFNESS_DISPLAY[n][2]} = {fmt_number(float(np.nanmean(ctx.metrics[n].values)) * STIFFNESS_DISPLAY[n][0], 4)} "
                         f"{STIFFNESS_DISPLAY[n][1]}" for n in present)
        blocks.append(Para(f"The sweep has no axis with more than one value to plot against: {vals}."))
        return blocks
    p = ctx.figure_path("stiffness.png")
    notes = figure_stiffness(ctx, axes, p)
    blocks.append(Para("Stiffness at the steady operating point, a row per stiffness and a column per sweep axis: "
                       + "; ".join(notes) + ". Missing or failed cases are left out."))
    blocks.append(Image(f"figures/{p.name}", "stiffness at the steady operating point against the sweep axes"))
    return blocks
