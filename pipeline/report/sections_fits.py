"""Report sections comparing our fits with the study's: the Tables 3 and 4 comparison and
the speed-load interaction (the plain-words paragraph on them is :mod:`.physics`)."""
from __future__ import annotations

import math

import numpy as np

from rvcore.profile import PHASES

from ..analysis import fit_statistic
from .context import Context, ensemble_text, on_base_grid, realizations, sensors
from .render import PHASE_TITLE, Heading, Para, Table, fmt_number, fmt_sci, fmt_unit
from .select import fit_at, fixed_choice


def study_comparison(ctx: Context):
    """One dict per reference fit: the study's fit and ours in the study's units."""
    rows = []
    for ref in ctx.references:
        fixed, note = fixed_choice(ctx, ref.fixed_axis, ref.fixed_coordinate)
        fit = fit_at(ctx, ref.variable, ref.axis, ref.fixed_axis, fixed, ref.phase)
        row = {"ref": ref, "fixed": fixed, "note": note, "fit": fit}
        if fit and math.isfinite(fit["slope"]):
            s, i = ref.to_reference_units(fit["slope"], fit["intercept"])
            lo, _ = ref.to_reference_units(fit["slope_ci95_lower"], 0.0)
            hi, _ = ref.to_reference_units(fit["slope_ci95_upper"], 0.0)
            row.update(slope=s, intercept=i, lo=lo, hi=hi, r2=fit["rsquared"], n=fit["n"],
                       agrees=bool(np.sign(s) == np.sign(ref.slope)),
                       significant=bool(lo > 0 or hi < 0))
        else:
            row.update(slope=math.nan, intercept=math.nan, lo=math.nan, hi=math.nan,
                       r2=math.nan, n=fit.get("n", 0) if fit else 0, agrees=None, significant=False)
        rows.append(row)
    return rows


def section_comparison(ctx: Context) -> list:
    """Our line fits beside the study's (:attr:`Context.comparison`) in the study's units."""
    comparison = ctx.comparison
    blocks = [Heading(2, "Fits beside the study's (Tables 3 and 4)")]
    ens = ensemble_text(ctx)
    what = (f"Weighted least-squares lines of the ensemble means ({ens}; weights 1/standard error², ordinary "
            "least squares for a line where any point lacks a standard error) of our phase metrics"
            if ens else "Ordinary least-squares lines of our phase metrics")
    sens = sensors(ctx.metrics)
    blocks.append(Para(
        f"{what}, δ_r and δ_a at the ring centre, in the study's units, beside the fits of "
        f"`{ctx.reference_path.name}`. Each line is fitted at the value of the other axis named in "
        "'at'; the slope's 95 % confidence interval is in brackets. 'Sign agrees' compares the slopes' "
        "signs; '(interval spans 0)' marks a slope our data cannot tell from zero. "
        + ("The study's δ come from laser sensors on the ring, which also see the ring's tilt; the sensor "
           "figures above show our virtual sensors' readings." if sens else
           "The study's δ come from laser sensors on the ring, which also see the ring's tilt; a sweep with "
           "`[[sensors]]` reports such readings too.")))
    rows = []
    for c in comparison:
        ref = c["ref"]
        if c["agrees"] is None:
            sign = "n/a (too few cases)"
        else:
            flat = "" if c["significant"] else (
                " (interval spans 0)" if math.isfinite(c["lo"]) else " (no resolvable slope)")
            sign = ("yes" if c["agrees"] else "no") + flat
        rows.append([
            ref.label, c["note"].removeprefix("at "),
            f"{fmt_sci(ref.slope)} {fmt_unit(ref.slope_units)}", f"{fmt_number(ref.intercept, 4)} {fmt_unit(ref.intercept_units)}",
            f"{fmt_sci(c['slope'])} [{fmt_sci(c['lo'])}, {fmt_sci(c['hi'])}] {fmt_unit(ref.slope_units)}",
            f"{fmt_sci(c['intercept'])} {fmt_unit(ref.intercept_units)}", fmt_number(c["r2"]), str(int(c["n"])), sign,
        ])
    blocks.append(Table(["study fit", "at", "study slope", "study intercept", "our slope [95 % CI]",
                         "our intercept", "our R²", "n", "sign agrees"], rows))
    n_agree = sum(1 for c in comparison if c["agrees"])
    n_known = sum(1 for c in comparison if c["agrees"] is not None)
    blocks.append(Para(f"{n_agree} of {n_known} slope signs agree with the study"
                       + (f" ({len(comparison) - n_known} could not be fitted)." if n_known < len(comparison) else ".")))
    return blocks


def section_plane(ctx: Context) -> list:
    """The interaction d of the plane fits z = a + b·speed + c·load + d·speed·load."""
    f = on_base_grid(ctx.fits)
    groups = []
    for ref in ctx.references:
        key = (ref.phase, ref.variable)
        if key not in groups:
            groups.append(key)
    rows = []
    for phase, var in groups:
        sel = {"phase": PHASES.index(phase)}
        try:
            fit_statistic(f, var, "plane", "interaction")
        except KeyError:
            continue
        g = lambda s: float(fit_statistic(f, var, "plane", s).sel(sel).item())  # noqa: E731
        conv = 1e3  # m -> mm; per (degree s-1 N) unchanged
        rows.append([f"{PHASE_TITLE[phase]} {var.replace('_displacement_', ' ')}",
                     f"{fmt_sci(g('interaction') * conv)} ± {fmt_sci(g('interaction_stderr') * conv)}",
                     f"[{fmt_sci(g('interaction_ci95_lower') * conv)}, {fmt_sci(g('interaction_ci95_upper') * conv)}]",
                     fmt_number(g("rsquared")), str(int(g("n")))])
    if not rows:
        return []
    return [Heading(2, "Interaction of speed and load"),
            Para("Plane fits z = a + b·speed + c·load + d·speed·load over the whole grid"
                 + (" (of the ensemble means, unweighted)" if realizations(ctx.metrics) is not None else "")
                 + ", δ_r and δ_a at the ring centre; the interaction d in mm per (°/s·N) with its standard error:"),
            Table(["metric", "d ± standard error", "95 % CI", "R²", "n"], rows)]
