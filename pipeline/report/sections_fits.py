"""Report sections comparing our fits with the study's: the Tables 3 and 4 comparison,
the speed-load interaction, and the plain-words physics paragraph."""
from __future__ import annotations

import math

import numpy as np

from rvcore.profile import PHASES

from ..analysis import fit_statistic, nearest
from .context import SENSOR, Context, on_base_grid, ensemble_text, bearing_numbers, realizations, sensors
from .render import PHASE_TITLE, Heading, Para, Table, fmt_speed, fmt_sci, fmt_number, fmt_kn, fmt_unit
from .select import fit_at, fixed_choice, metric_value, finished_points


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


def section_comparison(ctx: Context, comparison):
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


def section_plane(ctx: Context):
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


def _find_ref(comparison, phase, displacement, metric, axis):
    for c in comparison:
        r = c["ref"]
        if (r.phase, r.displacement, r.metric, r.axis) == (phase, displacement, metric, axis):
            return c
    return None


def section_physics(ctx: Context, comparison, windows):
    """The plain-words paragraph: where our physics agrees with the study and where not."""
    blocks = [Heading(2, "Where our physics agrees with the study and where it does not")]
    paras = []
    pts = finished_points(ctx)
    if not pts:
        return blocks + [Para("No case finished, so there is nothing to compare.")]
    speeds = sorted({p[0] for p in pts})
    s_lo, s_hi = speeds[0], speeds[-1]
    c_rs = _find_ref(comparison, "steady", "radial", "mean", "speed")
    want_load = c_rs["fixed"] if c_rs else nearest(ctx.metrics["radial_load"].values, 30e3)
    at_hi = [p for p in pts if p[0] == s_hi]
    case = min(at_hi, key=lambda p: abs(p[1] - want_load))
    s, load = case

    # Centrifugal force against the contact loads.
    bn = bearing_numbers(ctx)
    w_i = metric_value(ctx, "inner_ring_speed_mean", s, load, "steady")
    if not math.isfinite(w_i):
        w_i = math.radians(s)
    w_c = metric_value(ctx, "epicyclic_cage_speed", s, load, "steady")
    w_c_src = "the epicyclic cage speed at the loaded balls' actual contact angles"
    if not math.isfinite(w_c):
        slip = metric_value(ctx, "cage_slip", s, load, "steady")
        w_c = metric_value(ctx, "cage_speed_mean", s, load, "steady") / (1.0 - slip) if slip != 1.0 else math.nan
        w_c_src = "the epicyclic cage speed implied by the measured cage speed and slip"
    D, d_m, alpha = bn["D"], bn["d_m"], bn["alpha"]
    if not math.isfinite(w_c) and math.isfinite(D) and math.isfinite(d_m):
        a = alpha if math.isfinite(alpha) else 0.0
        w_c = 0.5 * w_i * (1.0 - D * math.cos(a) / d_m)
        w_c_src = (f"ω_c = ω_i/2·(1 − D·cos α/d_m) with α = {fmt_number(math.degrees(a))}°"
                   + ("" if math.isfinite(alpha) else " (no contact angle in the configuration)"))
    m_b = bn["m_b"]
    r = d_m / 2.0
    f_c = m_b * r * w_c**2
    q = math.nan
    sw = on_base_grid(ctx.sweep, first_realization=False)
    if "max_inner_contact_load" in sw and "steady" in windows:
        t = sw["elapsed_time"].values
        a, b = windows["steady"]
        mask = (t >= a) & (t < b)
        ser = sw["max_inner_contact_load"].sel(speed=s, radial_load=load).transpose(..., "elapsed_time").values
        sel = ser.reshape(-1, t.size)[:, mask]   # every realization's steady samples
        if np.isfinite(sel).any():
            q = float(sel[np.isfinite(sel)].mean())
    if math.isfinite(f_c) and math.isfinite(q) and q > 0:
        paras.append(
            f"**Centrifugal loading.** At the highest speed, {fmt_speed(s)} with {fmt_kn(load)} radial load, "
            f"the cage turns at ω_c = {fmt_number(math.degrees(w_c), 4)} °/s ({w_c_src}). A ball of m_b = {fmt_number(m_b)} kg "
            f"(D = {fmt_number(D * 1e3)} mm, ρ = {fmt_number(bn['rho'], 4)} kg/m³) on the pitch radius "
            f"d_m/2 = {fmt_number(r * 1e3, 4)} mm feels F_c = m_b·(d_m/2)·ω_c² = {fmt_number(f_c)} N, while the largest "
            f"inner-race contact load averages {fmt_number(q / 1e3)} kN over the steady phase"
            + (" (all realizations)" if realizations(ctx.sweep) is not None else "") + ": F_c is "
            f"{fmt_number(100 * f_c / q, 2)} % of it. Whatever a speed does to the steady displacements through "
            f"centrifugal force is therefore of that relative order, so speed trends in the steady δ "
            f"should be tiny.")
    else:
        missing = [k for k, v in (("ball diameter", D), ("ball density", bn["rho"]),
                                  ("pitch diameter", d_m), ("cage speed", w_c), ("contact load", q))
                   if not math.isfinite(v)]
        paras.append("**Centrifugal loading.** The centrifugal force on a ball could not be estimated: "
                     f"missing {', '.join(missing)} in the configuration or the data.")

    # Speed trends of the steady means.
    for disp, sym in (("radial", "δ_r"), ("axial", "δ_a")):
        c = _find_ref(comparison, "steady", disp, "mean", "speed")
        if c is None:
            continue
        ref = c["ref"]
        span = s_hi - s_lo
        ours_um = _span_change(c, span) * 1e3
        study_um = ref.slope_in_coordinate_units() * span * 1e6 if span > 0 else math.nan
        if not math.isfinite(ours_um):
            paras.append(f"**Steady mean {sym} against speed.** Too few cases {c['note']} to fit a line.")
            continue
        agree = "the same sign as" if c["agrees"] else "the opposite sign to"
        ratio = abs(study_um / ours_um) if ours_um != 0 else math.inf
        paras.append(
            f"**Steady mean {sym} against speed** ({c['note']}). Ours changes by {fmt_number(ours_um)} µm "
            f"from {fmt_speed(s_lo)} to {fmt_speed(s_hi)} (R² = {fmt_number(c['r2'])}), {agree} the study's fit, which "
            f"changes by {fmt_number(study_um)} µm over the same span, {fmt_number(ratio)} times as much. "
            + ("Our interval on the slope spans zero: within our data the speed has no resolvable "
               "effect. " if not c["significant"] else "")
            + ("A centrifugal force of the size above cannot produce a trend as large as the study's; "
               "we do not reproduce it." if ratio > 10 else
               "The two are of a similar order." if 0.5 <= ratio <= 2 else "").rstrip())

    # The study's ~2 mm axial offset.
    c = _find_ref(comparison, "steady", "axial", "mean", "speed")
    if c is not None:
        ref = c["ref"]
        study_mm = (ref.intercept_si() + ref.slope_in_coordinate_units() * s_lo) * 1e3
        ours = metric_value(ctx, "axial_displacement_mean", s_lo, c["fixed"], "steady") * 1e3
        fa = float(np.atleast_1d(ctx.metrics["axial_load"].values)[0]) if "axial_load" in ctx.metrics.coords else math.nan
        if math.isfinite(ours):
            pct = 100 * study_mm / (D * 1e3) if math.isfinite(D) else math.nan
            far = ours == 0 or abs(study_mm / ours) > 10
            paras.append(
                f"**Mean axial displacement.** The study's steady mean δ_a at {fmt_speed(s_lo)} is "
                f"{fmt_number(study_mm, 4)} mm (its fit, intercept {fmt_number(ref.intercept, 4)} {fmt_unit(ref.intercept_units)}); "
                f"ours at the same point is {fmt_number(ours, 3)} mm"
                + (f", so the study's is {fmt_number(abs(study_mm / ours))} times ours" if ours != 0 else "")
                + (f". {fmt_number(study_mm, 3)} mm is {fmt_number(pct, 2)} % of the ball diameter" if math.isfinite(pct) else "")
                + (f", while the axial load is {fmt_kn(fa)}" if math.isfinite(fa) else "")
                + (": in our model δ_a is the contact deflection plus the take-up of internal clearance, "
                   "and the study's value is far beyond that; it most likely includes an offset of its "
                   "own datum that the text does not describe." if far else
                   ": the two are of a similar order.")
                + _axial_sensor_sentence(ctx, s_lo, c["fixed"]))

    # Load trends.
    for disp, sym in (("radial", "δ_r"), ("axial", "δ_a")):
        c = _find_ref(comparison, "steady", disp, "mean", "radial_load")
        if c is None or not math.isfinite(c["slope"]):
            continue
        ref = c["ref"]
        paras.append(
            f"**Steady mean {sym} against load** ({c['note']}). Our slope is {fmt_sci(c['slope'])} "
            f"{fmt_unit(ref.slope_units)}, the study's {fmt_sci(ref.slope)} {fmt_unit(ref.slope_units)}: "
            + ("the signs agree" if c["agrees"] else "the signs differ")
            + (", and ours is significant at 95 %." if c["significant"] else
               ", but ours cannot be told from zero at 95 %.")
            + (" More load compresses the Hertz contacts further." if disp == "radial" else ""))

    # Transients.
    trans = [c for c in comparison if c["ref"].phase in ("startup", "deceleration") and c["agrees"] is not None]
    if trans:
        n_agree = sum(1 for c in trans if c["agrees"])
        acc = ""
        if "startup" in windows:
            a, b = windows["startup"]
            if b > a:
                acc = (f" Our start-up ramps the speed over {fmt_number(b - a)} s, an angular acceleration of "
                       f"{fmt_number(s_lo / (b - a), 4)} to {fmt_number(s_hi / (b - a), 4)} °/s² "
                       f"over the grid, the quantity the study attributes the transient ranges to.")
        paras.append(f"**Transient ranges.** {n_agree} of {len(trans)} start-up and deceleration range "
                     f"slopes have the study's sign.{acc}")
    n_agree = sum(1 for c in comparison if c["agrees"])
    n_known = sum(1 for c in comparison if c["agrees"] is not None)
    if n_known:
        paras.append(f"Altogether {n_agree} of {n_known} fitted slopes agree in sign with the study.")
    else:
        paras.append("None of the reference fits could be compared: each needs at least 3 finished "
                     "cases along its axis.")
    return blocks + [Para(p) for p in paras]


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


def _span_change(c, span: float) -> float:
    """Change of our fitted line over ``span`` [coordinate units], in mm."""
    fit = c["fit"]
    if not fit or not math.isfinite(fit.get("slope", math.nan)):
        return math.nan
    return fit["slope"] * span * 1e3


