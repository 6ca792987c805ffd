"""Measured traces in the report: each rig trace stored in the sweep's ``measured/``
(``rvsweep compare TRACE.toml --sweep DIR``) over the simulated case it was compared with,
in time and in the steady spectrum, the phase windows shaded; the agreement per phase; and
the fits of the measured cases beside ours and the study's.

Reads only the stored comparisons (:func:`pipeline.analysis.measured.read_measured`), the
measured fits and the study comparison of the context; no section when the folder holds
no measured trace.
"""
from __future__ import annotations

import math

import numpy as np

from rvcore.profile import PHASES
from rvcore.recording.spectra import KINEMATIC_NAMES

from ..analysis import fit_statistic, nearest
from .context import Context
from .figures import legend_outside, new_figure, save_figure, shade_windows
from .render import PHASE_TITLE, Heading, Image, Para, Table, fmt_kn, fmt_number, fmt_sci, fmt_speed, fmt_unit

_SERIES = (("radial_displacement", "δ_r at the ring centre"), ("axial_displacement", "δ_a at the ring centre"))
_MARKED = {"shaft": "f_i", "cage": "f_c", "outer_ball_pass": "Z·f_c", "inner_ball_pass": "Z·(f_i−f_c)"}


def _name(ds) -> str:
    return str(ds.attrs.get("trace", "")) or str(ds.attrs.get("measured_file", "trace"))


def _stem(ds) -> str:
    return "".join(c if c.isalnum() or c in "_-" else "_" for c in _name(ds))


def _windows(ds) -> dict:
    if "phase_start" not in ds or "phase_end" not in ds:
        return {}
    return {p: (float(a), float(b)) for p, a, b in zip(PHASES, ds["phase_start"].values, ds["phase_end"].values)}


def _point(ds) -> str:
    parts = []
    if "speed" in ds.coords:
        parts.append(fmt_speed(float(ds["speed"])))
    for key in ("radial_load", "axial_load"):
        if key in ds.coords:
            parts.append(f"{fmt_kn(float(ds[key]))} {'radial' if key == 'radial_load' else 'axial'}")
    return ", ".join(parts) or "not given"


def figure_overlay(ds, path) -> None:
    """δ_r and δ_a measured (as aligned) and simulated against time [µm], windows shaded."""
    fig, axes = new_figure(2, 1, (10.0, 6.0))
    t = ds["elapsed_time"].values
    for k, (n, label) in enumerate(_SERIES):
        ax = axes[k, 0]
        shade_windows(ax, _windows(ds))
        if n in ds:
            ax.plot(t, ds[n].values * 1e6, lw=1.8, color="C0", label="measured (shifted by the lag)")
        if f"{n}_simulated" in ds:
            ax.plot(t, ds[f"{n}_simulated"].values * 1e6, lw=1.0, ls="--", color="C1", label="simulated")
        ax.set_ylabel(f"{label} [µm]")
        ax.grid(True, lw=0.3)
    axes[1, 0].set_xlabel("elapsed time [s]")
    legend_outside(fig, axes[0, 0])
    axes[0, 0].set_title(f"Trace '{_name(ds)}' beside the simulated case, phase windows shaded", fontsize=10)
    save_figure(fig, path)


def figure_spectra(ds, path) -> bool:
    """The steady spectra, measured and simulated [µm], the kinematic lines marked; False
    when the comparison holds no spectrum."""
    if "frequency" not in ds.dims or ds.sizes["frequency"] < 4:
        return False
    f = ds["frequency"].values
    fig, axes = new_figure(2, 1, (10.0, 6.0))
    kin = ds["kinematic_frequency"].values if "kinematic_frequency" in ds else np.zeros(0)
    for k, (n, label) in enumerate(_SERIES):
        ax = axes[k, 0]
        for tail, style in (("", {"lw": 1.6, "color": "C0", "label": "measured"}),
                            ("_simulated", {"lw": 1.0, "ls": "--", "color": "C1", "label": "simulated"})):
            v = f"{n}_spectrum{tail}"
            if v in ds:
                ax.semilogy(f[1:], np.maximum(ds[v].values[1:] * 1e6, 1e-9), **style)
        for j, key in enumerate(KINEMATIC_NAMES[:len(_MARKED)]):
            if j < kin.size and math.isfinite(kin[j]) and kin[j] < f[-1]:
                ax.axvline(kin[j], color="0.3", lw=0.8, ls=":")
                ax.text(kin[j], 0.97, " " + _MARKED[key], rotation=90, va="top", ha="left", fontsize=8,
                        transform=ax.get_xaxis_transform())
        ax.set_ylabel(f"{label} [µm]")
        ax.grid(True, lw=0.3, which="both")
    axes[1, 0].set_xlabel("frequency [Hz]")
    legend_outside(fig, axes[0, 0])
    axes[0, 0].set_title(f"Steady spectra of trace '{_name(ds)}' and of the simulated case", fontsize=10)
    save_figure(fig, path)
    return True


def _agreement_rows(ds) -> list:
    rows = []
    for n, label in _SERIES:
        if f"{n}_range" not in ds:
            continue
        for k, p in enumerate(PHASES):
            def um(v):
                return fmt_number(float(ds[v].values[k]) * 1e6, 4) if v in ds else "–"

            sg = [fmt_number(float(ds[f"{n}_sprague_geers_{e}"].values[k]), 3)
                  if f"{n}_sprague_geers_{e}" in ds else "–" for e in ("magnitude", "phase", "combined")]
            rows.append([_name(ds), label, PHASE_TITLE[p], um(f"{n}_range"), um(f"{n}_range_simulated"),
                         um(f"{n}_mean"), um(f"{n}_mean_simulated"), *sg])
    return rows


def measured_fit_at(ctx: Context, variable: str, axis: str, fixed_axis: str, wanted: float, phase: str) -> dict:
    """The measured line fit of ``variable`` along ``axis`` at the measured value of
    ``fixed_axis`` nearest ``wanted`` [coordinate units]: its statistics and ``fixed``."""
    f = ctx.measured_fits
    if not f.data_vars or fixed_axis not in f.coords:
        return {}
    fixed = nearest(f[fixed_axis].values, wanted)
    out = {"fixed": fixed}
    for stat in ("slope", "intercept", "slope_ci95_lower", "slope_ci95_upper", "n"):
        try:
            da = fit_statistic(f, variable, axis, stat)
        except KeyError:
            return {}
        out[stat] = float(da.sel({fixed_axis: fixed, "phase": PHASES.index(phase)}).item())
    return out


def _fits_rows(ctx: Context) -> list:
    rows = []
    for c in ctx.comparison:
        ref = c["ref"]
        m = measured_fit_at(ctx, ref.variable, ref.axis, ref.fixed_axis, ref.fixed_coordinate, ref.phase)
        if m and math.isfinite(m["slope"]):
            s, _ = ref.to_reference_units(m["slope"], m["intercept"])
            lo, _ = ref.to_reference_units(m["slope_ci95_lower"], 0.0)
            hi, _ = ref.to_reference_units(m["slope_ci95_upper"], 0.0)
            fmt = fmt_speed if ref.fixed_axis == "speed" else fmt_kn
            measured = f"{fmt_sci(s)} [{fmt_sci(lo)}, {fmt_sci(hi)}] at {fmt(m['fixed'])}"
            n = str(int(m["n"]))
        else:
            measured, n = "n/a (fewer than 3 tests on the line)", str(int(m.get("n", 0))) if m else "0"
        rows.append([ref.label, f"{fmt_sci(ref.slope)} {fmt_unit(ref.slope_units)}",
                     f"{fmt_sci(c['slope'])} {c['note'].removeprefix('at ')}", measured, n])
    return rows


def section_measured(ctx: Context) -> list:
    """The measured traces of ``measured/`` beside the model (none: no section)."""
    if not ctx.measured:
        return []
    blocks = [Heading(2, "Measured traces beside the model"),
              Para(f"{len(ctx.measured)} rig trace(s) stored in `measured/` by `rvsweep compare TRACE.toml --sweep "
                   "DIR`: each converted to metres with its sensor's sign, low-passed where its trace file asks, "
                   "resampled onto the simulated case's output interval and shifted by the lag that maximises "
                   "their cross-correlation. The measured phase metrics come from the core's own phase "
                   "reductions fed with the measured samples, the spectra from the case files' spectrum code; "
                   "both sit in `metrics.nc` as `measured_*` over `measured_case` and their fits in `fits.nc` "
                   "as `measured_*` over `measured_speed`/`measured_radial_load`. The metric figures above mark the "
                   "measured tests on their lines (red ×, those within 1 % of the line's speed or load).")]
    rows = []
    for ds in ctx.measured:
        lag = float(ds["lag"]) if "lag" in ds else math.nan
        case = str(ds.attrs.get("case", "")).rsplit("/", 1)[-1] or "none"
        rows.append([_name(ds), _point(ds), case, fmt_number(lag * 1e3, 4)])
    blocks.append(Table(["trace", "operating point", "simulated case", "lag [ms]"], rows))
    for ds in ctx.measured:
        if "elapsed_time" in ds.dims and ds.sizes["elapsed_time"] > 1:
            path = ctx.figure_path(f"measured_{_stem(ds)}_traces.png")
            figure_overlay(ds, path)
            blocks.append(Image(f"figures/{path.name}", f"measured and simulated displacements of {_name(ds)}"))
        path = ctx.report_dir / "figures" / f"measured_{_stem(ds)}_spectra.png"
        if figure_spectra(ds, path):
            ctx.figures.append(path)
            blocks.append(Image(f"figures/{path.name}", f"measured and simulated steady spectra of {_name(ds)}"))
    blocks.append(Para("Agreement per phase: ranges and means in µm, measured and simulated; Sprague–Geers "
                       "errors of the simulated series against the measured (M magnitude, P phase, C combined; "
                       "Sprague & Geers 2004): M = a − 1 for a simulation a times the measurement, P = 0 in phase."))
    blocks.append(Table(["trace", "series", "phase", "range meas.", "range sim.", "mean meas.", "mean sim.",
                         "SG M", "SG P", "SG C"], [r for ds in ctx.measured for r in _agreement_rows(ds)]))
    if ctx.comparison:
        blocks.append(Para("The study's fits, ours and the measured tests' (the same least-squares code on the "
                           "measured cases laid on the grid of their own speeds and loads), slopes in the study's "
                           "units, the measured slope's 95 % interval in brackets:"))
        blocks.append(Table(["study fit", "study slope", "our slope, at", "measured slope", "measured n"],
                            _fits_rows(ctx)))
    return blocks
