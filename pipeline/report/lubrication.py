"""The report's lubrication section: the film, λ and κ at the steady operating point against
the sweep axes, and ISO 281's modified life L_nm beside L10 and L10r.

``metrics.nc`` carries, per case, the steady point's lubrication scalars
(:func:`rvcore.statics.operating.steady_lubrication`): the Hamrock–Dowson minimum film of
the heaviest-loaded inner contact (``film_thickness_min_steady`` [m]), its λ
(``film_parameter_steady``), ISO 281's κ (``kappa_steady``) and a_ISO (``a_iso_steady``),
and the lives ``basic_rating_life_L10``, ``reference_rating_life_L10r`` and
``modified_rating_life_L_nm`` [rev]. The figure shows the film in µm, λ and κ against each
numeric sweep axis, a line per value of another axis (at most five), the rest at their
first value; dotted lines mark λ = 1 and 3 (boundary / mixed / full film) and κ = 0.1, 1
and 4 (ISO 281's range and a_ISO's branches).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .context import SENSOR, Context
from .figures import MARKERS, new_figure, save_figure
from .render import Heading, Image, Para, Table, fmt_number

#: The plotted outputs: name -> (factor from SI, axis label, reference lines).
PANELS = {"film_thickness_min_steady": (1e6, "h_min [µm]", ()),
          "film_parameter_steady": (1.0, "λ = h_min/σ [-]", (1.0, 3.0)),
          "kappa_steady": (1.0, "κ = ν/ν1 [-]", (0.1, 1.0, 4.0))}
#: The lives shown side by side [rev].
LIVES = ("basic_rating_life_L10", "reference_rating_life_L10r", "modified_rating_life_L_nm")
_NOT_AXES = ("realization", SENSOR, "row", "phase", "elapsed_time")
_ORDER = ("radial_load", "speed", "axial_load", "moment")


def _axes(ctx: Context) -> list:
    name = next(n for n in PANELS if n in ctx.metrics)
    return [d for d in ctx.metrics[name].dims if d not in _NOT_AXES and ctx.metrics.sizes[d] > 1
            and d in ctx.metrics.coords and np.asarray(ctx.metrics[d].values).dtype.kind == "f"]


def _display(ctx: Context, axis: str):
    """(factor, unit) of a sweep axis for the figure: °/s, kN, or its own unit."""
    units = str(ctx.metrics[axis].attrs.get("units", ""))
    if axis == "speed":
        return 1.0, "°/s"
    if units == "N":
        return 1e-3, "kN"
    return 1.0, "" if units == "1" else units


def _line(ctx: Context, name: str, axis: str, other, p: int) -> np.ndarray:
    da = ctx.metrics[name]
    sel = {d: 0 for d in da.dims if d not in (axis, other)}
    if other is not None and other in da.dims:
        sel[other] = p
    return np.asarray(da.isel(sel).values, dtype=np.float64)


def figure_lubrication(ctx: Context, axes: list, path: Path) -> list:
    """A row per panel of :data:`PANELS`, a column per sweep axis; returns the notes."""
    present = [n for n in PANELS if n in ctx.metrics]
    fig, grid = new_figure(len(present), len(axes), (4.6 * len(axes), 0.9 + 2.6 * len(present)))
    notes = []
    for j, axis in enumerate(axes):
        other = next((a for a in _ORDER if a in axes and a != axis), None)
        fx, ux = _display(ctx, axis)
        x = np.asarray(ctx.metrics[axis].values, dtype=np.float64) * fx
        picks = [0]
        if other is not None:
            n = ctx.metrics.sizes[other]
            picks = sorted(set(np.linspace(0, n - 1, min(n, 5)).round().astype(int).tolist()))
            fo, uo = _display(ctx, other)
        notes.append(f"against {axis}" + (f", a line per {other}" if other is not None else ""))
        for i, name in enumerate(present):
            ax = grid[i, j]
            scale, label, refs = PANELS[name]
            for m, p in enumerate(picks):
                y = _line(ctx, name, axis, other, p) * scale
                ok = np.isfinite(y)
                lab = (f"{fmt_number(float(ctx.metrics[other].values[p]) * fo, 4)} {uo}".strip()
                       if other is not None else None)
                ax.plot(x[ok], y[ok], marker=MARKERS[m % len(MARKERS)], ms=4, lw=1.0, color=f"C{m}", label=lab)
            for r in refs:
                ax.axhline(r, color="0.5", lw=0.7, ls=":")
            if name == "kappa_steady":
                ax.set_yscale("log")
            ax.set_xlabel(f"{axis} [{ux}]" if ux else axis)
            ax.set_ylabel(label)
            ax.grid(True, lw=0.3)
            if other is not None and i == 0:
                ax.legend(fontsize=8, title=other, title_fontsize=8)
    fig.suptitle("Lubrication at the steady operating point (Hamrock-Dowson film of the heaviest-loaded inner "
                 "contact, pure rolling, fully flooded: an upper bound under grease)\ndotted: λ = 1, 3 "
                 "(boundary | mixed | full film); κ = 0.1, 1, 4 (ISO 281)", fontsize=10)
    save_figure(fig, path)
    return notes


def _regime_counts(ctx: Context) -> str:
    lam = np.asarray(ctx.metrics["film_parameter_steady"].values, dtype=np.float64).ravel()
    lam = lam[np.isfinite(lam)]
    if not lam.size:
        return ""
    b, m = int((lam < 1.0).sum()), int(((lam >= 1.0) & (lam < 3.0)).sum())
    return (f" At the steady point, {b} of the {lam.size} cases run in boundary lubrication (λ < 1), {m} mixed "
            f"(1 ≤ λ < 3) and {lam.size - b - m} in full film (λ ≥ 3).")


def _life_table(ctx: Context) -> list:
    """L10, L10r and L_nm [10^6 rev] and a_ISO at each speed (the other axes at their first value)."""
    if "speed" not in ctx.metrics.coords or not all(n in ctx.metrics for n in LIVES):
        return []
    rows = []
    for k, w in enumerate(np.atleast_1d(ctx.metrics["speed"].values)):
        vals = []
        for n in (*LIVES, "a_iso_steady", "kappa_steady"):
            da = ctx.metrics[n]
            sel = {d: (k if d == "speed" else 0) for d in da.dims}
            v = float(da.isel(sel).values)
            vals.append(v * (1e-6 if n in LIVES else 1.0))
        rows.append([fmt_number(float(w), 4)] + [fmt_number(v, 4) if math.isfinite(v) else "–" for v in vals])
    return [Table(["speed [°/s]", "L10 [10⁶ rev]", "L10r [10⁶ rev]", "L_nm [10⁶ rev]", "a_ISO [-]", "κ [-]"], rows)]


def section_lubrication(ctx: Context) -> list:
    """The "Lubrication" section: figure, regimes and the three lives side by side."""
    blocks = [Heading(2, "Lubrication and the modified life")]
    if not any(n in ctx.metrics for n in PANELS):
        blocks.append(Para("The sweep holds no lubrication outputs (`film_thickness_min_steady`, "
                           "`film_parameter_steady`, `kappa_steady`): it was written by a version that did not "
                           "compute them."))
        return blocks
    blocks.append(Para(
        "At the steady operating point (the statics there): the lubricant's viscosity at the operating "
        "temperature (ASTM D341 from the bearing file's `[lubricant]` and `[temperature]`), ISO 281:2007's "
        "viscosity ratio κ = ν/ν1, its life modification factor a_ISO and the modified rating life "
        "L_nm = a_ISO·L10 (a_1 = 1, 90 % reliability); the Hamrock–Dowson minimum film of the heaviest-loaded "
        "inner contact at its own load and contact angle in pure rolling, and λ = h_min/σ. L10 (ISO 281, "
        "P = X·F_r + Y·F_a) includes no lubrication, L10r (ISO/TS 16281, from the ball loads) the load "
        "distribution but no lubrication; L_nm adds κ, the contamination e_C and the fatigue load limit. The "
        "films are those of a fully flooded, isothermal contact: grease starvation makes them upper bounds, "
        "and measured films scatter about ±30 % around the formula. Below κ = 0.1 ISO 281 does not apply. "
        "The lubrication regime per phase of the cycle needs the dynamics' film along the cycle, which this "
        "sweep's case files do not carry." + _regime_counts(ctx)))
    blocks += _life_table(ctx)
    axes = _axes(ctx)
    if not axes:
        return blocks
    p = ctx.figure_path("lubrication.png")
    notes = figure_lubrication(ctx, axes, p)
    blocks.append(Para("Film, λ and κ at the steady operating point, a column per sweep axis: " + "; ".join(notes)
                       + "; other axes at their first value. Missing or failed cases are left out."))
    blocks.append(Image(f"figures/{p.name}", "film thickness, lambda and kappa at the steady point against the "
                                             "sweep axes"))
    return blocks
