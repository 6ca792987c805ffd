"""The report's lubrication section: the film, λ and κ at the steady operating point and along
the duty cycle against the sweep axes, the lubrication regime of each phase, and ISO 281's
modified life L_nm beside L10 and L10r, at the steady point and over the cycle.

``metrics.nc`` carries, per case, the steady point's lubrication scalars
(:func:`rvcore.statics.operating.steady_lubrication`): the Hamrock–Dowson minimum film of
the heaviest-loaded inner contact (``film_thickness_min_steady`` [m]), its λ
(``film_parameter_steady``), ISO 281's κ (``kappa_steady``) and a_ISO (``a_iso_steady``),
and the lives ``basic_rating_life_L10``, ``reference_rating_life_L10r`` and
``modified_rating_life_L_nm`` [rev]. The figure shows the film in µm, λ and κ against each
numeric sweep axis, a line per value of another axis (at most five), the rest at their
first value; dotted lines mark λ = 1 and 3 (boundary / mixed / full film) and κ = 0.1, 1
and 4 (ISO 281's range and a_ISO's branches).

Along the cycle (the dynamics, :mod:`rvcore.recording.plan`): per phase the smallest
Hamrock–Dowson film over the loaded contacts and its λ, their minimum and step mean
(``film_thickness_minimum_min``/``_mean``, ``film_parameter_min``/``_mean``), κ's
(``kappa_min``/``_mean``), and per case the cycle's ``rating_life_L10r``,
``rating_life_L_nm``, ``a_iso_cycle`` and ``kappa_below_scope_fraction``. A phase's regime
is that of its mean λ, its worst that of its smallest (:data:`rvcore.statics.lubrication.REGIMES`).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from rvcore.profile import PHASES
from rvcore.statics.lubrication import REGIMES, regime

from .context import SENSOR, Context
from .figures import MARKERS, new_figure, save_figure
from .render import Heading, Image, Para, Table, fmt_number

#: The plotted outputs: name -> (factor from SI, axis label, reference lines).
PANELS = {"film_thickness_min_steady": (1e6, "h_min [µm]", ()),
          "film_parameter_steady": (1.0, "λ = h_min/σ [-]", (1.0, 3.0)),
          "kappa_steady": (1.0, "κ = ν/ν1 [-]", (0.1, 1.0, 4.0))}
#: The lives shown side by side [rev].
LIVES = ("basic_rating_life_L10", "reference_rating_life_L10r", "modified_rating_life_L_nm")
#: The duty cycle's lives beside them [rev] (and, after them, a_ISO of the cycle and the
#: share of its revolutions below κ = 0.1).
CYCLE_LIVES = ("rating_life_L10r", "rating_life_L_nm")
#: The phase metrics along the cycle: name -> (factor from SI, axis label, reference lines).
CYCLE_PANELS = {"film_thickness_minimum_mean": (1e6, "mean h_min [µm]", ()),
                "film_parameter_mean": (1.0, "mean λ [-]", (1.0, 3.0)),
                "kappa_mean": (1.0, "mean κ [-]", (0.1, 1.0, 4.0))}
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


def _line(ctx: Context, name: str, axis: str, other, p: int, phase: int = 0) -> np.ndarray:
    da = ctx.metrics[name]
    sel = {d: 0 for d in da.dims if d not in (axis, other)}
    if other is not None and other in da.dims:
        sel[other] = p
    if "phase" in da.dims:
        sel["phase"] = phase
    return np.asarray(da.isel(sel).values, dtype=np.float64)


def figure_cycle(ctx: Context, axes: list, path: Path) -> None:
    """Along the cycle: a row per panel of :data:`CYCLE_PANELS`, a column per sweep axis, a
    line per phase (the other axes at their first value)."""
    present = [n for n in CYCLE_PANELS if n in ctx.metrics]
    fig, grid = new_figure(len(present), len(axes), (4.6 * len(axes), 0.9 + 2.6 * len(present)))
    for j, axis in enumerate(axes):
        fx, ux = _display(ctx, axis)
        x = np.asarray(ctx.metrics[axis].values, dtype=np.float64) * fx
        for i, name in enumerate(present):
            ax = grid[i, j]
            scale, label, refs = CYCLE_PANELS[name]
            for k, phase in enumerate(PHASES[:ctx.metrics.sizes.get("phase", 0)]):
                y = _line(ctx, name, axis, None, 0, k) * scale
                ok = np.isfinite(y) & (y > 0 if name == "kappa_mean" else True)
                ax.plot(x[ok], y[ok], marker=MARKERS[k % len(MARKERS)], ms=4, lw=1.0, color=f"C{k}", label=phase)
            for r in refs:
                ax.axhline(r, color="0.5", lw=0.7, ls=":")
            if name == "kappa_mean":
                ax.set_yscale("log")
            ax.set_xlabel(f"{axis} [{ux}]" if ux else axis)
            ax.set_ylabel(label)
            ax.grid(True, lw=0.3)
            if i == 0:
                ax.legend(fontsize=8, title="phase", title_fontsize=8)
    fig.suptitle("Along the duty cycle, mean over each phase: the smallest Hamrock-Dowson film of the loaded\n"
                 "contacts (fully flooded: an upper bound under grease), its λ, and κ\ndotted: λ = 1, 3 "
                 "(boundary | mixed | full film); κ = 0.1, 1, 4 (ISO 281)", fontsize=10)
    save_figure(fig, path)


def phase_regimes(ctx: Context) -> list:
    """The lubrication regime of each phase at each speed (the other axes at their first
    value): a :class:`Table`, or nothing where the sweep has no film along the cycle.

    A phase's regime is that of its step-mean λ; its worst, that of its smallest λ
    (:func:`rvcore.statics.lubrication.regime`)."""
    names = ("film_parameter_mean", "film_parameter_min", "kappa_mean", "kappa_min", "film_thickness_minimum_mean")
    if not all(n in ctx.metrics for n in names) or "phase" not in ctx.metrics["film_parameter_mean"].dims:
        return []
    speeds = (np.atleast_1d(ctx.metrics["speed"].values) if "speed" in ctx.metrics.coords else [math.nan])
    rows = []
    for k, w in enumerate(speeds):
        for p, phase in enumerate(PHASES[:ctx.metrics.sizes["phase"]]):
            v = {}
            for n in names:
                da = ctx.metrics[n]
                sel = {d: (k if d == "speed" else p if d == "phase" else 0) for d in da.dims}
                v[n] = float(da.isel(sel).values)
            lam_mean, lam_min = v["film_parameter_mean"], v["film_parameter_min"]
            rows.append([fmt_number(float(w), 4), phase, fmt_number(v["film_thickness_minimum_mean"] * 1e6, 3),
                         fmt_number(lam_mean, 3), regime(lam_mean) or "–", fmt_number(lam_min, 3),
                         regime(lam_min) or "–", fmt_number(v["kappa_mean"], 3), fmt_number(v["kappa_min"], 3)])
    return [Table(["speed [°/s]", "phase", "mean h_min [µm]", "mean λ", "regime", "smallest λ", "at its worst",
                   "mean κ", "smallest κ"], rows)]


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
    cycle = ((*CYCLE_LIVES, "a_iso_cycle", "kappa_below_scope_fraction")
             if all(n in ctx.metrics for n in (*CYCLE_LIVES, "a_iso_cycle", "kappa_below_scope_fraction")) else ())
    rows = []
    for k, w in enumerate(np.atleast_1d(ctx.metrics["speed"].values)):
        vals = []
        for n in (*LIVES, "a_iso_steady", "kappa_steady", *cycle):
            da = ctx.metrics[n]
            sel = {d: (k if d == "speed" else 0) for d in da.dims}
            v = float(da.isel(sel).values)
            vals.append(v * (1e-6 if n in LIVES or n in CYCLE_LIVES else 1.0))
        rows.append([fmt_number(float(w), 4)] + [fmt_number(v, 4) if math.isfinite(v) else "–" for v in vals])
    header = ["speed [°/s]", "L10 [10⁶ rev]", "L10r [10⁶ rev]", "L_nm [10⁶ rev]", "a_ISO [-]", "κ [-]"]
    if cycle:
        header += ["cycle L10r [10⁶ rev]", "cycle L_nm [10⁶ rev]", "cycle a_ISO [-]", "revolutions at κ < 0.1 [-]"]
    return [Table(header, rows)]


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
        "and measured films scatter about ±30 % around the formula. Below κ = 0.1 ISO 281 does not apply: "
        "a_ISO is taken there at κ = 0.1 (about 0.1) and the share of the cycle's revolutions run below it is "
        "given." + _regime_counts(ctx)))
    regimes = phase_regimes(ctx)
    if regimes:
        bounds = ", ".join(f"{name} from λ = {start:g}" for name, start in REGIMES)
        blocks.append(Para(
            "Along the duty cycle (the dynamics at every integrator step): the smallest Hamrock–Dowson film over "
            "the loaded ball–race contacts, each at its own Hertz ellipse, load and entrainment speed from the "
            "model's velocities, its λ and κ at the instantaneous speed, per phase. A phase's regime is that of "
            f"its mean λ, its worst that of its smallest ({bounds}: the usual convention, Hamrock, Schmid & "
            "Jacobson, *Fundamentals of Machine Elements*). At start and stop the speed passes through 0, where "
            "no film forms and κ = 0: the smallest values are those of the standstill."))
        blocks += regimes
    blocks.append(Para(
        "The lives: L10 (ISO 281, P = X·F_r + Y·F_a at the steady loads) includes neither the ball-load "
        "distribution nor lubrication; L10r (ISO/TS 16281, from the ball loads) the load distribution, at the "
        "steady point and, as 'cycle L10r', over the duty cycle (Palmgren–Miner at every integrator step); L_nm "
        "= a_ISO·L10 at the steady point adds κ, the contamination e_C and the fatigue load limit C_u; 'cycle "
        "L_nm' is the cycle's L10r with each step's damage divided by that step's a_ISO (its κ at the "
        "instantaneous speed, e_C·C_u over its equivalent reference load): ISO/TS 16281's modified reference "
        "rating life accumulated step by step, so the ramps' low κ counts where they load the bearing. All at "
        "90 % reliability (a_1 = 1), in 10⁶ revolutions of the inner ring."))
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
    if any(n in ctx.metrics for n in CYCLE_PANELS) and "phase" in ctx.metrics.dims:
        p = ctx.figure_path("lubrication_cycle.png")
        figure_cycle(ctx, axes, p)
        blocks.append(Para("Along the cycle: the step means per phase of the smallest film, its λ and κ, a column "
                           "per sweep axis, a line per phase; other axes at their first value."))
        blocks.append(Image(f"figures/{p.name}", "film thickness, lambda and kappa per phase of the duty cycle "
                                                 "against the sweep axes"))
    return blocks
