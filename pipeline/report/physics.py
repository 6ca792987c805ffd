"""The plain-words section on where our physics agrees with the study and where not.

The section is a list of paragraphs, each from one small function that writes it only
when the data it speaks of are there (a fit, a metric, a window), and whose every number
is read off the data: the centrifugal load of a ball at the highest speed against the
contact loads, the speed trends of the steady means, the steady mean axial displacement,
the load trends, the transient ranges and the tally of agreeing slopes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvcore.bearing.geometry import centrifugal_ball_load

from ..analysis import nearest
from .context import SENSOR, Context, bearing_numbers, on_base_grid, realizations, sensors
from .render import Heading, Para, fmt_kn, fmt_number, fmt_sci, fmt_speed, fmt_unit
from .select import finished_points, metric_value

#: The two ring-centre displacements and their symbols.
_DISPLACEMENTS = (("radial", "δ_r"), ("axial", "δ_a"))


@dataclass(frozen=True)
class Span:
    """The finished speeds' span [°/s] and the point the centrifugal paragraph is written at:
    the highest speed with the radial load [N] nearest to the study's speed line."""

    slowest: float
    fastest: float
    load: float


def find_comparison(comparison, phase: str, displacement: str, metric: str, axis: str):
    """The comparison row of the study's fit of ``metric`` of ``displacement`` in ``phase``
    along ``axis``, or None when the reference file has no such fit."""
    for c in comparison:
        r = c["ref"]
        if (r.phase, r.displacement, r.metric, r.axis) == (phase, displacement, metric, axis):
            return c
    return None


def _span(ctx: Context, points: list) -> Span:
    speeds = sorted({p[0] for p in points})
    c = find_comparison(ctx.comparison, "steady", "radial", "mean", "speed")
    want = c["fixed"] if c else nearest(ctx.metrics["radial_load"].values, 30e3)
    fastest = [p for p in points if p[0] == speeds[-1]]
    return Span(speeds[0], speeds[-1], min(fastest, key=lambda p: abs(p[1] - want))[1])


def _cage_speed(ctx: Context, s: float, load: float, bn: dict):
    """The steady cage speed ω_c [rad/s] at one point and where it comes from: the stored
    epicyclic speed, else the measured cage speed and slip, else the geometry."""
    w_c = metric_value(ctx, "epicyclic_cage_speed", s, load, "steady")
    if math.isfinite(w_c):
        return w_c, "the epicyclic cage speed at the loaded balls' actual contact angles"
    slip = metric_value(ctx, "cage_slip", s, load, "steady")
    w_c = metric_value(ctx, "cage_speed_mean", s, load, "steady") / (1.0 - slip) if slip != 1.0 else math.nan
    if math.isfinite(w_c) or not (math.isfinite(bn["D"]) and math.isfinite(bn["d_m"])):
        return w_c, "the epicyclic cage speed implied by the measured cage speed and slip"
    w_i = metric_value(ctx, "inner_ring_speed_mean", s, load, "steady")
    w_i = w_i if math.isfinite(w_i) else math.radians(s)
    a = bn["alpha"] if math.isfinite(bn["alpha"]) else 0.0
    return (w_i * bn["cage_ratio"],
            f"ω_c = ω_i/2·(1 − D·cos α/d_m) with α = {fmt_number(math.degrees(a))}°"
            + ("" if math.isfinite(bn["alpha"]) else " (no contact angle in the configuration)"))


def _steady_contact_load(ctx: Context, s: float, load: float) -> float:
    """The largest inner contact load [N] averaged over the steady window, every realization."""
    sw = on_base_grid(ctx.sweep, first_realization=False)
    if "max_inner_contact_load" not in sw or "steady" not in ctx.windows:
        return math.nan
    t = sw["elapsed_time"].values
    a, b = ctx.windows["steady"]
    ser = sw["max_inner_contact_load"].sel(speed=s, radial_load=load).transpose(..., "elapsed_time").values
    sel = ser.reshape(-1, t.size)[:, (t >= a) & (t < b)]
    return float(sel[np.isfinite(sel)].mean()) if np.isfinite(sel).any() else math.nan


def centrifugal_paragraph(ctx: Context, span: Span) -> str:
    """The centrifugal load of a ball at the highest speed against the steady contact load."""
    bn = bearing_numbers(ctx)
    s, load = span.fastest, span.load
    w_c, w_c_src = _cage_speed(ctx, s, load, bn)
    r = bn["d_m"] / 2.0
    f_c = centrifugal_ball_load(bn["m_b"], r, w_c)
    q = _steady_contact_load(ctx, s, load)
    if not (math.isfinite(f_c) and math.isfinite(q) and q > 0):
        missing = [k for k, v in (("ball diameter", bn["D"]), ("ball density", bn["rho"]),
                                  ("pitch diameter", bn["d_m"]), ("cage speed", w_c), ("contact load", q))
                   if not math.isfinite(v)]
        return ("**Centrifugal loading.** The centrifugal force on a ball could not be estimated: "
                f"missing {', '.join(missing)} in the configuration or the data.")
    return (f"**Centrifugal loading.** At the highest speed, {fmt_speed(s)} with {fmt_kn(load)} radial load, "
            f"the cage turns at ω_c = {fmt_number(math.degrees(w_c), 4)} °/s ({w_c_src}). A ball of "
            f"m_b = {fmt_number(bn['m_b'])} kg (D = {fmt_number(bn['D'] * 1e3)} mm, ρ = {fmt_number(bn['rho'], 4)} "
            f"kg/m³) on the pitch radius d_m/2 = {fmt_number(r * 1e3, 4)} mm feels F_c = m_b·(d_m/2)·ω_c² = "
            f"{fmt_number(f_c)} N, while the largest inner-race contact load averages {fmt_number(q / 1e3)} kN "
            "over the steady phase" + (" (all realizations)" if realizations(ctx.sweep) is not None else "")
            + f": F_c is {fmt_number(100 * f_c / q, 2)} % of it. Whatever a speed does to the steady "
            "displacements through centrifugal force is therefore of that relative order, so speed trends in "
            "the steady δ should be tiny.")


def _span_change(c, span: float) -> float:
    """Change of our fitted line over ``span`` [coordinate units], in mm."""
    fit = c["fit"]
    if not fit or not math.isfinite(fit.get("slope", math.nan)):
        return math.nan
    return fit["slope"] * span * 1e3


def speed_trend_paragraphs(ctx: Context, span: Span) -> list:
    """Our steady means' change over the speed span beside the study's, per displacement."""
    out = []
    for disp, sym in _DISPLACEMENTS:
        c = find_comparison(ctx.comparison, "steady", disp, "mean", "speed")
        if c is None:
            continue
        width = span.fastest - span.slowest
        ours_um = _span_change(c, width) * 1e3
        study_um = c["ref"].slope_in_coordinate_units() * width * 1e6 if width > 0 else math.nan
        if not math.isfinite(ours_um):
            out.append(f"**Steady mean {sym} against speed.** Too few cases {c['note']} to fit a line.")
            continue
        agree = "the same sign as" if c["agrees"] else "the opposite sign to"
        ratio = abs(study_um / ours_um) if ours_um != 0 else math.inf
        out.append(
            f"**Steady mean {sym} against speed** ({c['note']}). Ours changes by {fmt_number(ours_um)} µm "
            f"from {fmt_speed(span.slowest)} to {fmt_speed(span.fastest)} (R² = {fmt_number(c['r2'])}), {agree} "
            f"the study's fit, which changes by {fmt_number(study_um)} µm over the same span, "
            f"{fmt_number(ratio)} times as much. "
            + ("Our interval on the slope spans zero: within our data the speed has no resolvable "
               "effect. " if not c["significant"] else "")
            + ("A centrifugal force of the size above cannot produce a trend as large as the study's; "
               "we do not reproduce it." if ratio > 10 else
               "The two are of a similar order." if 0.5 <= ratio <= 2 else "").rstrip())
    return out


def _axial_sensor_sentence(ctx: Context, speed: float, load: float) -> str:
    """' Sensor `x` at … reads a steady mean of … mm there.' for each sensor aimed along the axis."""
    out = []
    for sn in sensors(ctx.metrics):
        if not abs(sn.direction[2]) >= 0.9:
            continue
        v = metric_value(ctx, f"{SENSOR}_displacement_mean", speed, load, "steady", sn.value)
        if math.isfinite(v):
            out.append(f" The {sn.label()}, which also sees the ring's tilt, reads a steady mean of "
                       f"{fmt_number(v * 1e3, 3)} mm there.")
    return "".join(out)


def axial_mean_paragraph(ctx: Context, span: Span) -> list:
    """The study's steady mean δ_a at the slowest speed beside ours, against the ball diameter."""
    c = find_comparison(ctx.comparison, "steady", "axial", "mean", "speed")
    if c is None:
        return []
    ref = c["ref"]
    s_lo = span.slowest
    study_mm = (ref.intercept_si() + ref.slope_in_coordinate_units() * s_lo) * 1e3
    ours = metric_value(ctx, "axial_displacement_mean", s_lo, c["fixed"], "steady") * 1e3
    if not math.isfinite(ours):
        return []
    fa = float(np.atleast_1d(ctx.metrics["axial_load"].values)[0]) if "axial_load" in ctx.metrics.coords else math.nan
    d = bearing_numbers(ctx)["D"]
    pct = 100 * study_mm / (d * 1e3) if math.isfinite(d) else math.nan
    far = ours == 0 or abs(study_mm / ours) > 10
    return [f"**Mean axial displacement.** The study's steady mean δ_a at {fmt_speed(s_lo)} is "
            f"{fmt_number(study_mm, 4)} mm (its fit, intercept {fmt_number(ref.intercept, 4)} "
            f"{fmt_unit(ref.intercept_units)}); ours at the same point is {fmt_number(ours, 3)} mm"
            + (f", so the study's is {fmt_number(abs(study_mm / ours))} times ours" if ours != 0 else "")
            + (f". {fmt_number(study_mm, 3)} mm is {fmt_number(pct, 2)} % of the ball diameter"
               if math.isfinite(pct) else "")
            + (f", while the axial load is {fmt_kn(fa)}" if math.isfinite(fa) else "")
            + (": in our model δ_a is the contact deflection plus the take-up of internal clearance, "
               "and the study's value is far beyond that; it most likely includes an offset of its "
               "own datum that the text does not describe." if far else
               ": the two are of a similar order.")
            + _axial_sensor_sentence(ctx, s_lo, c["fixed"])]


def load_trend_paragraphs(ctx: Context) -> list:
    """Our steady means' slope against the radial load beside the study's, per displacement."""
    out = []
    for disp, sym in _DISPLACEMENTS:
        c = find_comparison(ctx.comparison, "steady", disp, "mean", "radial_load")
        if c is None or not math.isfinite(c["slope"]):
            continue
        units = fmt_unit(c["ref"].slope_units)
        out.append(
            f"**Steady mean {sym} against load** ({c['note']}). Our slope is {fmt_sci(c['slope'])} "
            f"{units}, the study's {fmt_sci(c['ref'].slope)} {units}: "
            + ("the signs agree" if c["agrees"] else "the signs differ")
            + (", and ours is significant at 95 %." if c["significant"] else
               ", but ours cannot be told from zero at 95 %.")
            + (" More load compresses the Hertz contacts further." if disp == "radial" else ""))
    return out


def transient_paragraph(ctx: Context, span: Span) -> list:
    """How many start-up and deceleration range slopes have the study's sign, and our start-up's
    angular acceleration over the grid."""
    trans = [c for c in ctx.comparison if c["ref"].phase in ("startup", "deceleration") and c["agrees"] is not None]
    if not trans:
        return []
    acc = ""
    a, b = ctx.windows.get("startup", (0.0, 0.0))
    if b > a:
        acc = (f" Our start-up ramps the speed over {fmt_number(b - a)} s, an angular acceleration of "
               f"{fmt_number(span.slowest / (b - a), 4)} to {fmt_number(span.fastest / (b - a), 4)} °/s² "
               f"over the grid, the quantity the study attributes the transient ranges to.")
    n_agree = sum(1 for c in trans if c["agrees"])
    return [f"**Transient ranges.** {n_agree} of {len(trans)} start-up and deceleration range "
            f"slopes have the study's sign.{acc}"]


def tally_paragraph(ctx: Context) -> str:
    """How many of the fitted slopes agree in sign with the study's."""
    n_agree = sum(1 for c in ctx.comparison if c["agrees"])
    n_known = sum(1 for c in ctx.comparison if c["agrees"] is not None)
    if n_known:
        return f"Altogether {n_agree} of {n_known} fitted slopes agree in sign with the study."
    return "None of the reference fits could be compared: each needs at least 3 finished cases along its axis."


def section_physics(ctx: Context) -> list:
    """The plain-words paragraphs: where our physics agrees with the study and where not."""
    blocks = [Heading(2, "Where our physics agrees with the study and where it does not")]
    points = finished_points(ctx)
    if not points:
        return blocks + [Para("No case finished, so there is nothing to compare.")]
    span = _span(ctx, points)
    paras = [centrifugal_paragraph(ctx, span), *speed_trend_paragraphs(ctx, span),
             *axial_mean_paragraph(ctx, span), *load_trend_paragraphs(ctx), *transient_paragraph(ctx, span),
             tally_paragraph(ctx)]
    return blocks + [Para(p) for p in paras]
