"""Imperfect bearings in the report: the tolerance classes of a sweep side by side against
the study's fits, and the steady spectrum with the bearing's kinematic frequencies.

Both read ``sweep.nc``, ``metrics.nc`` and ``fits.nc`` only (docs/model.md §12).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from rvcore.recording.spectra import KINEMATIC_NAMES

from ..io.netcdf import flag_name
from .context import SENSOR, Context, extra_dims
from .figures import new_figure, save_figure
from .render import Heading, Image, Para, Table, fmt_speed, fmt_sci, fmt_number, fmt_kn
from .sections_fits import study_comparison

#: The sweep dimension of ``imperfections.tolerance_class`` (dots become underscores).
CLASS_AXIS = "imperfections_tolerance_class"

#: Which kinematic lines the spectrum figure marks, with their short labels.
_MARKED = {"shaft": "f_i", "cage": "f_c", "outer_ball_pass": "Z·f_c", "inner_ball_pass": "Z·(f_i−f_c)",
           "ball_spin": "f_b"}


def class_name(ctx: Context, value) -> str:
    """The tolerance class a coordinate value stands for (the flag meaning of a category)."""
    return flag_name(ctx.metrics[CLASS_AXIS] if CLASS_AXIS in ctx.metrics.coords else None, value)


def ordered_classes(ctx: Context, values) -> list:
    """Class coordinate values, the perfect bearing first, then the tightest class to the loosest."""
    order = ("none", "", "4", "5", "6", "normal")
    return sorted(values, key=lambda v: order.index(class_name(ctx, v)) if class_name(ctx, v) in order
                  else len(order))


def class_label(value) -> str:
    v = str(value)
    return "perfect" if v in ("none", "") else ("Normal" if v == "normal" else f"class {v}")


def _at(ctx: Context, axis: str, value) -> Context:
    """``ctx`` with every dataset at one value of an extra sweep axis."""
    def pick(ds):
        return ds.sel({axis: value}) if axis in ds.dims else ds
    return dataclasses.replace(ctx, sweep=pick(ctx.sweep), metrics=pick(ctx.metrics), fits=pick(ctx.fits),
                               sensor_fits=pick(ctx.sensor_fits))


def section_classes(ctx: Context) -> list:
    """The study's twelve fits for each tolerance class of the sweep (none: no section)."""
    if CLASS_AXIS not in ctx.fits.dims or not ctx.references:
        return []
    values = ordered_classes(ctx, ctx.fits[CLASS_AXIS].values)
    per_class = {v: study_comparison(_at(ctx, CLASS_AXIS, v)) for v in values}
    label = {v: class_label(class_name(ctx, v)) for v in values}
    blocks = [Heading(2, "Tolerance classes beside the study"),
              Para("The same fits as above for each bearing of the sweep (`imperfections.tolerance_class`): a "
                   "perfect one and ISO 492 specimens whose raceways are eccentric by half the class's runout, "
                   "with waviness-free raceways and balls within the class's grade (docs/model.md §12). Every other "
                   "section of this report shows the first value of the sweep's axis, "
                   f"{class_label(class_name(ctx, ctx.fits[CLASS_AXIS].values[0]))}. Slopes in the study's units; ✓ where the sign agrees with the "
                   "study's.")]
    header = ["study fit", "study slope"] + [label[v] for v in values]
    rows = []
    for k, ref in enumerate(ctx.references):
        cells = [ref.label, f"{fmt_sci(ref.slope)} {ref.slope_units}"]
        for v in values:
            c = per_class[v][k]
            mark = "" if c["agrees"] is None else (" ✓" if c["agrees"] else " ✗")
            cells.append(f"{fmt_sci(c['slope'])}{mark}")
        rows.append(cells)
    blocks.append(Table(header, rows))
    counts = []
    for v in values:
        known = [c for c in per_class[v] if c["agrees"] is not None]
        counts.append(f"{label[v]}: {sum(1 for c in known if c['agrees'])} of {len(known)}")
    blocks.append(Para("Slope signs that agree with the study's: " + "; ".join(counts) + "."))
    blocks.append(Para(_explained(ctx, values, per_class, label)))
    return blocks


def _explained(ctx: Context, values, per_class, label) -> str:
    """Which of the study's trends the runout explains (a perfect bearing's slope far from
    the study's, an imperfect one's within a factor of 3 of it with the same sign) and
    which it does not."""
    base, worst = values[0], values[-1]
    yes, no = [], []
    for k, ref in enumerate(ctx.references):
        p, w = per_class[base][k], per_class[worst][k]
        if not (math.isfinite(w["slope"]) and math.isfinite(p["slope"]) and ref.slope):
            continue
        ratio = w["slope"] / ref.slope
        text = (f"{ref.label} ({fmt_number(ratio, 2)}× the study's slope with {label[worst]}, "
                f"{fmt_number(p['slope'] / ref.slope, 2)}× with {label[base]})")
        (yes if w["agrees"] and 1 / 3 <= ratio <= 3 else no).append(text)
    return ("Within a factor of 3 of the study's slope, with its sign, for the "
            f"{label[worst]} specimen: " + ("; ".join(yes) if yes else "none") + ". Not explained by the "
            "runout: " + ("; ".join(no) if no else "none") + ". A runout moves the ring by e·cos of the angle it "
            "has turned through, so it explains ranges that grow with the angle a phase turns through (its speed); "
            "it leaves the steady means, which average whole revolutions, where the perfect bearing has them.")


def section_spectrum(ctx: Context) -> list:
    """The steady spectrum of the radial sensor (or δ_r) at the sweep's highest speed and
    radial load, a line per tolerance class, the kinematic frequencies marked."""
    sweep = ctx.sweep
    name = f"{SENSOR}_displacement_spectrum" if f"{SENSOR}_displacement_spectrum" in sweep else \
        "radial_displacement_spectrum"
    if name not in sweep or "frequency" not in sweep.dims or sweep.sizes["frequency"] < 4:
        return []
    point = {"speed": sweep["speed"].values.max(), "radial_load": sweep["radial_load"].values.max()}
    da = sweep[name].sel(point)
    kin = sweep["kinematic_frequency"].sel(point)
    classes = ordered_classes(ctx, sweep[CLASS_AXIS].values) if CLASS_AXIS in sweep.dims else [None]
    fig, axes = new_figure(1, 1, (9.0, 4.2))
    ax = axes[0, 0]
    f = sweep["frequency"].values
    for m, v in enumerate(classes):
        line = da.sel({CLASS_AXIS: v}) if v is not None else da
        extra = {d: 0 for d in line.dims if d != "frequency"}
        amp = np.asarray(line.isel(extra).values, dtype=np.float64) * 1e6
        ax.semilogy(f[1:], np.maximum(amp[1:], 1e-9), lw=1.0, color=f"C{m}",
                    label=class_label(class_name(ctx, v)) if v is not None else "this sweep")
        k = kin.sel({CLASS_AXIS: v}) if v is not None and CLASS_AXIS in kin.dims else kin
        freqs = np.asarray(k.isel({d: 0 for d in k.dims if d != "kinematic"}).values, dtype=np.float64)
    top = 0.0
    for j, key in enumerate(KINEMATIC_NAMES[:len(_MARKED)]):
        fk = freqs[j]
        if math.isfinite(fk) and fk < f[-1]:
            ax.axvline(fk, color="0.3", lw=0.8, ls="--")
            ax.text(fk, 0.97, " " + _MARKED[key], rotation=90, va="top", ha="left", fontsize=8,
                    transform=ax.get_xaxis_transform())
            top = max(top, fk)
    ax.set_xlim(0.0, min(f[-1], 2.6 * top) if top else f[-1])
    lo, hi = ax.get_ylim()
    ax.set_ylim(max(lo, hi * 1e-6), hi * 3.0)   # room for the labels; six decades below the top
    ax.set_xlabel("frequency [Hz]", fontsize=10)
    ax.set_ylabel("amplitude [µm]", fontsize=10)
    ax.grid(True, lw=0.3, which="both")
    ax.legend(fontsize=9)
    what = "the radial sensor's reading" if name.startswith(SENSOR) else "δ_r at the ring centre"
    fig.suptitle(f"Steady spectrum of {what} at {fmt_speed(point['speed'])}, {fmt_kn(point['radial_load'])}", fontsize=11)
    path = ctx.figure_path("steady_spectrum.png")
    save_figure(fig, path)
    blocks = [Heading(2, "Steady spectrum"),
              Para(f"Amplitude spectrum of {what} over the steady phase (mean removed, Hann window: a sinusoid "
                   "of amplitude A reads A at a bin centre, down to 0.85 A between bins) at the sweep's highest speed and radial load"
                   + (", a line per tolerance class" if classes[0] is not None else "")
                   + ". Dashed: the bearing's kinematic frequencies at that speed (rolling without slip at the "
                   "nominal contact angle): shaft f_i, cage f_c, outer ball pass Z·f_c, inner ball pass "
                   "Z·(f_i − f_c), ball spin f_b. A perfect bearing under radial load shows the outer ball pass "
                   "(its varying compliance); an eccentric inner raceway adds f_i, waviness and ball sizes their "
                   "own lines. The amplitudes at every kinematic frequency and its second harmonic, each a "
                   "least-squares sinusoid fit at that frequency (not the peak read here), are in "
                   "`sweep.nc` (`*_kinematic_amplitude`)."),
              Image(f"figures/{path.name}", "steady spectrum with the kinematic frequencies")]
    return blocks


def extra_axes_note(ctx: Context) -> list:
    """A line saying which value of each extra sweep axis the report's sections show."""
    extra = [d for d in extra_dims(ctx.metrics) if d in ctx.metrics.coords]
    if not extra:
        return []
    parts = [f"`{d}` = {class_name(ctx, ctx.metrics[d].values[0]) if d == CLASS_AXIS else ctx.metrics[d].values[0]}"
             for d in extra]
    return [Para("This sweep has further axes; the sections below show their first values ("
                 + ", ".join(parts) + ") unless a section says otherwise.")]
