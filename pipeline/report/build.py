"""The sweep report: metrics, fits, figures and the comparison with the study.

:func:`build_report` reads a sweep folder (``sweep.nc`` or, for a sweep killed before
combining, its ``cases/*.nc``; ``status.json``), writes ``metrics.nc`` and ``fits.nc``
beside them and ``report/report.md``, ``report/report.html``, ``report/summary.csv`` and
``report/figures/*.png``,
each file atomically.

The report is written for a bearing designer (issue 10), in this order: the summary per
operating point (:mod:`.summary`: safety factor, lives, start-up torque, cage forces,
sliding, displacements, stiffness; also ``report/summary.csv``) and the cases; the
figures (the designer outputs, time histories, the study's metrics, cage slip,
stiffness, load distribution); the study comparison; the files; and the configuration
as an appendix in engineering units (:mod:`.parameters`).

The report is a list of simple blocks (:mod:`.render`) built by the sections
(:mod:`.summary`, :mod:`.parameters`, :mod:`.sections`, :mod:`.sections_fits`,
:mod:`.stiffness`, :mod:`.loads`) and figures
(:mod:`.figures`) from a :class:`.context.Context`. It holds no timestamps and the PNGs
carry no software or time metadata, so the same sweep gives byte-identical report files.

Every number in the prose is computed from the data, the sweep's stored configuration
(:func:`pipeline.schema.stored_configuration`) or the reference-fit file; nothing is typed
in, and nothing is guessed: the phase windows come only from the data's
``phase_start``/``phase_end``.

Each figure and table says which displacement it shows: δ_r / δ_a at the ring centre, or
the reading of a virtual sensor (``sensor`` dimension) at a point of the ring along a
direction. With an ensemble (``realization`` dimension) the metrics are plotted as the
ensemble mean with ±1 standard-error bars over the faint individual realizations, and the
time histories show the first realization. Ranges whose extreme lies at the edge of the
phase window (``*_range_at_edge``) are drawn hollow and listed in their own section.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from rvcore.profile import PHASES

from ..analysis import (DESIGNER_METRICS, DESIGNER_SCALARS, STIFFNESS, default_reference_path, fit_metrics, load_reference_fits, load_sweep, phase_metrics,
                        write_fits, write_metrics)
from ..io import read_status, write_text_atomic
from .context import (SENSOR, Context, ensemble_text, first_realization_text, phase_windows,
                      read_configuration, realizations, sensors)
from .figures import figure_metric, figure_sensor_metric, figure_sensor_time_histories, figure_time_histories
from .parameters import section_parameters
from .render import (CENTRE_LABEL, METRIC_TITLE, PHASE_TITLE, Bullets, Heading, Image, Para, Warning_, fmt_speed, fmt_number,
                     fmt_kn, render_html, render_markdown)
from .sections import window_coverage, section_cage_slip, section_cases, section_sensors, section_window_edges
from .sections_fits import study_comparison, section_comparison, section_physics, section_plane
from .select import axis_specs, base_states, extreme_points
from .loads import section_load_distribution, solve_extremes
from .stiffness import section_stiffness
from .definitions import section_definitions
from .imperfect import extra_axes_note, section_classes, section_spectrum
from .summary import section_designer_figures, section_summary


#: Sensor metrics fitted for the sensor figures.
_SENSOR_FITTED = tuple(f"{SENSOR}_displacement_{k}" for k in ("range", "mean", "std"))


def _fit_text(ctx: Context) -> str:
    """What our fitted lines are: OLS of the cases or WLS of the ensemble means."""
    seeds = realizations(ctx.metrics)
    if seeds is not None and seeds.size >= 2:
        return ("the weighted least-squares line of the means (weights 1/standard error²; ordinary least "
                "squares where any point lacks a standard error) and its 95 % confidence band")
    return "OLS line and its 95 % confidence band"


def _has_data(ctx: Context, name: str, phase: str) -> bool:
    """Whether metric ``name`` has any finite value in ``phase``."""
    return name in ctx.metrics and bool(ctx.metrics[name].sel(phase=PHASES.index(phase)).notnull().any())


def _metric_caption(ctx: Context, what: str, notes, hollow: int, is_range: bool, has_data: bool = True) -> str:
    """The caption of a metric figure: what is plotted, the fit, the axes, the hollow markers."""
    if not has_data:
        return (f"{what}, " + "; ".join(notes) + ": no finished case holds data in this phase's window, "
                "so there is nothing to plot.")
    ens = ensemble_text(ctx)
    if ens:
        text = (f"{what}. Ensemble mean of {ens} per case with ±1 standard-error bars, the individual "
                f"realizations as faint small points just left of their mean; {_fit_text(ctx)}, ")
    else:
        text = f"{what}. Cases (points), {_fit_text(ctx)}, "
    text += "; ".join(notes) + "."
    if is_range:
        if hollow:
            text += (f" Hollow markers ({hollow} {'realization' if ens else 'case'}{'s' if hollow != 1 else ''}"
                     f"{(' and the mean it belongs to' if hollow == 1 else ' and the means they belong to') if ens else ''}"
                     "): the range has an extreme at the "
                     "window's edge, so it is cut off by the window and is a lower bound.")
        else:
            text += " No range drawn here has an extreme at the window's edge."
    return text


@dataclass
class ReportFiles:
    """Paths written by :func:`build_report`."""

    markdown: Path
    html: Path
    figures: list
    metrics: Path
    fits: Path
    missing: int
    summary: Path | None = None




def _windows_text(windows, source: str) -> str:
    """'Phase windows from …: start-up a–b s, …' or a sentence saying the data hold none."""
    if not windows:
        return ("The data hold no phase windows (`phase_start`/`phase_end`), so none are shaded "
                "and the steady-phase estimates below that need them are left out.")
    return (f"Phase windows from {source}: "
            + ", ".join(f"{PHASE_TITLE.get(k, k)} {fmt_number(a, 4)}–{fmt_number(b, 4)} s" for k, (a, b) in windows.items()) + ".")


def header_line(ctx) -> str:
    """The line under the title: what was run, so that a number in the summary is never
    read without its bearing, cycle, grid, integrator and model version."""
    sweep, conf = ctx.sweep, ctx.configuration
    dims = {d: n for d, n in sweep.sizes.items()
            if d not in ("elapsed_time", "phase", "sensor", "row", "frequency", "kinematic")}
    total = 1
    for n in dims.values():
        total *= n
    def counted(d, n):
        name = str(sweep[d].attrs.get("sweep_key", d)).split(".")[-1].replace("_", " ")
        return f"{n} {name}" + ("" if n == 1 else "es" if name.endswith("s") else "s")

    grid = " × ".join(counted(d, n) for d, n in dims.items())
    grid += f" = {total} case{'s' if total != 1 else ''}"
    parts = [f"bearing {sweep.attrs.get('bearing', '?')}"]
    if conf is not None:
        parts.append(f"profile {conf.profile.name} ({conf.profile.duration:g} s cycle)")
        parts.append(f"grid {grid}")
        parts.append(f"integrator {conf.settings.method.upper()} (step_safety {conf.settings.step_safety:g}"
                     + (f", step {conf.settings.time_step * 1e6:g} µs" if conf.settings.time_step > 0 else "")
                     + f", gravity {'on' if conf.settings.gravity else 'off'})")
        parts.append(f"model version {conf.model_version}")
    else:
        parts += [f"profile {sweep.attrs.get('profile', '?')}", f"grid {grid}"]
    return "**Run:** " + "; ".join(parts) + "."


def build_report(directory, reference=None) -> ReportFiles:
    """Metrics, fits and the report of a finished or partial sweep.

    Parameters
    ----------
    directory : path-like
        The sweep folder (``results/<name>/``).
    reference : path-like, optional
        A reference-fit TOML file; default ``sweeps/reference/study-fits.toml``.

    Returns
    -------
    ReportFiles

    Raises
    ------
    UserError
        When the folder holds no sweep, or the reference file is invalid.
    """
    directory = Path(directory)
    sweep = load_sweep(directory)
    refs = load_reference_fits(reference)
    metrics = phase_metrics(sweep)
    fits = fit_metrics(metrics)
    write_metrics(metrics, directory / "metrics.nc")
    write_fits(fits, directory / "fits.nc")
    configuration, err = read_configuration(sweep)
    ctx = Context(directory=directory, sweep=sweep, metrics=metrics, fits=fits,
                  status=read_status(directory), references=refs,
                  reference_path=Path(reference) if reference else default_reference_path(),
                  configuration=configuration, config_error=err)
    outdir = directory / "report"
    figdir = outdir / "figures"
    figdir.mkdir(parents=True, exist_ok=True)
    windows, windows_src = phase_windows(ctx)

    blocks = [Heading(1, f"Sweep report: {directory.name}"), Para(header_line(ctx))]
    caveats = [c.strip() for c in str(sweep.attrs.get("caveats", "")).split(" | ") if c.strip()]
    if caveats:
        blocks.append(Warning_("**Geometry caveat.** This bearing is not buildable as specified; "
                               "its results are reported with that caveat:\n" + "\n".join(caveats)))
    summary_blocks, summary, summary_path = section_summary(ctx, outdir)
    blocks += extra_axes_note(ctx)
    blocks += summary_blocks
    blocks += section_definitions(ctx)
    blocks += section_cases(ctx)
    figures = []
    designer_blocks, designer_figures = section_designer_figures(ctx, summary, figdir)
    blocks += designer_blocks
    figures += designer_figures
    blocks += section_sensors(ctx)
    sens = sensors(ctx.metrics)
    ens = ensemble_text(ctx)
    if sens:
        ctx.sensor_fits = fit_metrics(ctx.metrics, names=[n for n in _SENSOR_FITTED if n in ctx.metrics])

    blocks.append(Heading(2, "Time histories"))
    cases = extreme_points(ctx, realization=0 if realizations(ctx.sweep) is not None else None)
    if cases:
        first = first_realization_text(ctx)
        which = "; ".join(f"{fmt_speed(s)}, {fmt_kn(l)}" for s, l in cases)
        p = figdir / "time_histories.png"
        figure_time_histories(ctx, windows, p, cases)
        figures.append(p)
        blocks.append(Para(f"δ_r and δ_a at the ring centre of the extreme cases ({which})"
                           + (f", {first} (the other realizations are in `sweep.nc`)" if first else "")
                           + ". " + _windows_text(windows, windows_src) + window_coverage(ctx, windows)))
        blocks.append(Image(f"figures/{p.name}", "time histories of the extreme cases"))
        if sens and "sensor_displacement" in ctx.sweep:
            p = figdir / "sensor_time_histories.png"
            figure_sensor_time_histories(ctx, windows, p, cases)
            figures.append(p)
            blocks.append(Para("Readings of the virtual sensors for the same cases"
                               + (f", {first}" if first else "") + ", one panel per sensor: "
                               + "; ".join(sn.label() for sn in sens) + ". Phase windows shaded as above."))
            blocks.append(Image(f"figures/{p.name}", "sensor readings of the extreme cases"))
    else:
        blocks.append(Para("No case finished; there are no time histories to show."))

    blocks.append(Heading(2, "Metrics against speed and load"))
    if ens:
        blocks.append(Para(f"With {ens}, every metric is shown as the ensemble mean over the realizations "
                           "with ±1 standard-error bars, and each realization as a faint small point."))
    groups = {}
    for ref in refs:
        groups.setdefault((ref.phase, ref.displacement, ref.metric), [])
        if ref.axis not in [g.axis for g in groups[(ref.phase, ref.displacement, ref.metric)]]:
            groups[(ref.phase, ref.displacement, ref.metric)].append(ref)
    for (phase, disp, metric), grefs in groups.items():
        p = figdir / f"metric_{phase}_{disp}_{metric}.png"
        notes, hollow = figure_metric(ctx, grefs, p)
        figures.append(p)
        blocks.append(Heading(3, f"{PHASE_TITLE[phase]} {disp} displacement {METRIC_TITLE[metric]}, "
                                 f"at the ring centre"))
        blocks.append(Para(_metric_caption(ctx, f"{CENTRE_LABEL[disp]}", notes, hollow, metric == "range",
                                           _has_data(ctx, grefs[0].variable, phase))))
        blocks.append(Image(f"figures/{p.name}", f"{phase} {disp} {metric}"))
    if sens:
        pairs = []
        for ref in refs:
            if (ref.phase, ref.metric) not in pairs:
                pairs.append((ref.phase, ref.metric))
        for phase, metric in pairs:
            if f"{SENSOR}_displacement_{metric}" not in ctx.metrics:
                continue
            p = figdir / f"sensor_{phase}_{metric}.png"
            notes, hollow = figure_sensor_metric(ctx, phase, metric, axis_specs(ctx, phase), p)
            figures.append(p)
            blocks.append(Heading(3, f"{PHASE_TITLE[phase]} sensor reading {METRIC_TITLE[metric]}"))
            blocks.append(Para(_metric_caption(
                ctx, "The virtual sensors' readings, a row per sensor (" + "; ".join(sn.label() for sn in sens)
                + ")", notes, hollow, metric == "range", _has_data(ctx, f"{SENSOR}_displacement_{metric}", phase))
                + (" The sensors' lines are fitted for this report and not stored in `fits.nc`."
                   if _has_data(ctx, f"{SENSOR}_displacement_{metric}", phase) else "")))
            blocks.append(Image(f"figures/{p.name}", f"{phase} sensor {metric}"))

    slip_blocks, slip_figures = section_cage_slip(ctx, figdir, extreme_points(ctx))
    blocks += slip_blocks
    figures += slip_figures
    solved, why = solve_extremes(ctx)
    for section in (section_stiffness(ctx, figdir, solved), section_load_distribution(ctx, figdir, solved, why)):
        blocks += section[0]
        figures += section[1]
    blocks += section_window_edges(ctx, windows)
    comparison = study_comparison(ctx)
    blocks += section_comparison(ctx, comparison)
    blocks += section_classes(ctx)
    spectrum_blocks, spectrum_figures = section_spectrum(ctx, figdir)
    blocks += spectrum_blocks
    figures += spectrum_figures
    blocks += section_plane(ctx)
    blocks += section_physics(ctx, comparison, windows)
    blocks.append(Heading(2, "Files"))
    designer = [n for n in (*DESIGNER_METRICS, *DESIGNER_SCALARS) if n in ctx.metrics]
    dims = "speed, radial_load" + (", realization" if ens else "") + ", phase" + (", sensor" if sens else "")
    blocks.append(Bullets([
        "`metrics.nc`: range, mean and std of δ_r and δ_a at the ring centre"
        + (" and of each sensor's reading" if sens else "")
        + ", the times of their extremes and the window-edge flags (`*_range_at_edge`), the cage slip at the "
        "actual (`cage_slip`) and nominal (`cage_slip_nominal`) contact angles, the epicyclic cage speed, the peak "
        f"contact pressure and the phase windows (`phase_start`, `phase_end`) over ({dims})"
        + ("; the ensemble means and standard errors (`*_ensemble_mean`, `*_ensemble_stderr`) and the fraction of "
           "realizations flagged at the window's edge (`*_range_at_edge_fraction`)" if ens else ""),
        *(["`metrics.nc` also: the designer outputs per phase and case ("
            + ", ".join(f"`{n}`" for n in designer) + ")"] if designer else []),
        *(["`metrics.nc` also: the radial, axial and tilting stiffness at the steady operating point "
            "(`radial_stiffness`, `axial_stiffness`, `tilting_stiffness`) over the sweep axes"]
          if any(n in ctx.metrics for n in STIFFNESS) else []),
        "`fits.nc`: line fits along each axis and the interaction plane, per metric and phase"
        + (" (of the ensemble means, weighted by their standard errors)" if ens else "")
        + (", at the ring centre" if sens else ""),
        f"`report/{summary_path.name}`: the summary table at every grid point"]))
    blocks += section_parameters(ctx)

    md = write_text_atomic(outdir / "report.md", render_markdown(blocks))
    ht = write_text_atomic(outdir / "report.html", render_html(blocks, f"Sweep report: {directory.name}"))
    missing = int((base_states(ctx) != "ok").sum())
    return ReportFiles(markdown=md, html=ht, figures=figures, metrics=directory / "metrics.nc",
                       fits=directory / "fits.nc", missing=missing, summary=summary_path)
