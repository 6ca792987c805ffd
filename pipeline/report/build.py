"""The sweep report: metrics, fits, figures and the comparison with the study.

:func:`build_report` reads a sweep folder (``sweep.nc`` or, for a sweep killed before
combining, its ``cases/*.nc``; ``status.json``), writes ``metrics.nc`` and ``fits.nc``
beside them and ``report/report.md``, ``report/report.html``, ``report/summary.csv`` and
``report/figures/*.png`` (and, for a sweep with ``[statistics]`` draws, ``statistics.nc``),
each file atomically.

The report is written for a bearing designer, in this order: the headline (the worst
design numbers over the sweep, where they occur and their pass/fail against the user's
targets; :mod:`.headline`), the summary per
operating point (:mod:`.summary`: safety factor, lives, start-up torque, cage forces,
sliding, displacements, stiffness; also ``report/summary.csv``) and the cases; the
figures (the designer outputs, time histories, the study's metrics, cage slip,
stiffness, load distribution); the study comparison; the files; and the configuration
as an appendix in engineering units (:mod:`.parameters`).

The report is a list of simple blocks (:mod:`.render`): :data:`SECTIONS` lists the
sections in their order, each a function ``section(ctx) -> list of blocks`` of a
:class:`.context.Context` (:mod:`.summary`, :mod:`.definitions`, :mod:`.sections`,
:mod:`.sections_metrics`, :mod:`.stiffness`, :mod:`.loads`, :mod:`.sections_fits`,
:mod:`.imperfect`, :mod:`.measured`, :mod:`.statistics`, :mod:`.physics`, :mod:`.parameters`,
:mod:`.lubrication`, :mod:`.lubricated_vs_dry`: a lubricated sweep beside a dry one of the same grid, ``rvsweep report DIR --dry DIR2``), which writes its figures
(:mod:`.figures`) through :meth:`.context.Context.figure_path`. It holds no timestamps and the PNGs
carry no software or time metadata, so the same sweep gives byte-identical report files.

Every number in the prose is read or computed from the data (``sweep.nc``, ``metrics.nc``,
``fits.nc``, ``statics.nc``), the sweep's stored configuration
(:func:`pipeline.schema.stored_configuration`) or the reference-fit file; nothing is typed
in, no physics is solved again, and nothing is guessed: the phase windows come only from the data's
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

import xarray as xr

from ..analysis import (DESIGNER_METRICS, DESIGNER_SCALARS, STATISTICS_FILE, STIFFNESS, default_reference_path,
                        fit_metrics, load_reference_fits, open_results, phase_metrics, statistics_dataset,
                        write_fits, write_metrics)
from ..analysis.measured import fits_file_form, measured_fits, measured_group, read_measured
from ..schema.statistics import DRAW
from ..io import read_status, write_text_atomic
from ..io.statics import STATICS_FILE
from .context import SENSOR, Context, ensemble_text, phase_windows, read_configuration, sensors
from .definitions import section_definitions
from .figures import drawn_at_the_end
from .headline import section_headline
from .imperfect import extra_axes_note, section_classes, section_spectrum
from .loads import section_load_distribution, stored_statics
from .measured import section_measured
from .parameters import section_parameters
from .physics import section_physics
from .render import Bullets, Heading, Para, Warning_, render_html, render_markdown
from .sections import section_cage_slip, section_cases, section_sensors, section_window_edges
from .sections_fits import section_comparison, section_plane, study_comparison
from .sections_metrics import section_metrics, section_time_histories
from .select import base_states, missing_cases
from .statistics import section_statistics
from .stiffness import section_stiffness
from .lubrication import section_lubrication
from .lubricated_vs_dry import check_same_grid, load_dry, section_lubricated_vs_dry
from .summary import section_designer_figures, section_summary, summary_values

#: Sensor metrics fitted for the sensor figures.
_SENSOR_FITTED = tuple(f"{SENSOR}_displacement_{k}" for k in ("range", "mean", "std"))


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


def section_title(ctx: Context) -> list:
    """The title, the run line and, for a bearing not buildable as specified, its caveats."""
    blocks = [Heading(1, f"Sweep report: {ctx.directory.name}"), Para(header_line(ctx))]
    caveats = [c.strip() for c in str(ctx.sweep.attrs.get("caveats", "")).split(" | ") if c.strip()]
    if caveats:
        blocks.append(Warning_("**Geometry caveat.** This bearing is not buildable as specified; "
                               "its results are reported with that caveat:\n" + "\n".join(caveats)))
    return blocks


def section_files(ctx: Context) -> list:
    """What each file the sweep and the report wrote holds."""
    ens = ensemble_text(ctx)
    sens = sensors(ctx.metrics)
    designer = [n for n in (*DESIGNER_METRICS, *DESIGNER_SCALARS) if n in ctx.metrics]
    dims = "speed, radial_load" + (", realization" if ens else "") + ", phase" + (", sensor" if sens else "")
    return [Heading(2, "Files"), Bullets([
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
        *([f"`{STATICS_FILE}`: the quasi-static load distribution at the extreme operating points (every "
           "ball's load and contact angle per raceway arc, each row's load), solved when the sweep ran"]
          if stored_statics(ctx).corners else []),
        *([f"`measured/`: {len(ctx.measured)} rig trace(s) compared by `rvsweep compare --sweep`; their phase "
           "metrics in `metrics.nc` (`measured_*` over `measured_case`), their fits in `fits.nc` (`measured_*` over "
           "`measured_speed`, `measured_radial_load`)"] if ctx.measured else []),
        f"`report/{ctx.summary_path.name}`: the summary table at every grid point"])]


#: The report's sections in their order: each ``section(ctx) -> list of blocks``. The
#: headline comes first (:mod:`.headline`: the worst design numbers, where they occur and
#: their verdicts, and how the run differs from the study's), then the designer's summary, then the cases and the figures, the study comparison,
#: the files and the configuration as an appendix.
SECTIONS = (
    section_title, section_headline, extra_axes_note, section_summary, section_definitions, section_cases,
    section_designer_figures, section_sensors, section_time_histories, section_metrics, section_cage_slip,
    section_stiffness, section_lubrication, section_lubricated_vs_dry, section_load_distribution, section_window_edges,
    section_comparison, section_measured, section_classes, section_statistics,
    section_spectrum, section_plane, section_physics, section_files, section_parameters,
)


def load_context(directory: Path, reference=None, targets=None, dry=None) -> Context:
    """The results folder read for the report: the sweep, its metrics and fits (written as
    ``metrics.nc`` and ``fits.nc``), the status, the references, the stored configuration
    and statics, and what the sections share (phase windows, the study comparison, the
    summary values). ``sweep.nc`` is opened lazily (:func:`pipeline.analysis.open_results`):
    the metrics are read in full, a time series only for the cases a section draws; the
    caller closes ``ctx.sweep``. ``dry``: a dry sweep's folder of the same grid
    (:mod:`.lubricated_vs_dry`), read and its grid checked before anything is written."""
    dry_metrics = dry_configuration = None
    if dry is not None:
        dry_metrics, dry_configuration = load_dry(directory, Path(dry))
    sweep = open_results(directory, lazy=True)
    try:   # closed here on an error, not by the garbage collector (HDF5 can crash closing a file there)
        metrics = phase_metrics(sweep)
        if dry_metrics is not None:
            check_same_grid(metrics, dry_metrics, directory, Path(dry))
        fits = fit_metrics(metrics)
        measured = read_measured(directory)
        measured_metrics = measured_group(measured) if measured else xr.Dataset()
        measured_fit = measured_fits(measured_metrics) if measured else xr.Dataset()
        write_metrics(xr.merge([metrics, measured_metrics], combine_attrs="override") if measured else metrics,
                      directory / "metrics.nc")
        write_fits(xr.merge([fits, fits_file_form(measured_fit)], combine_attrs="override")
                   if measured_fit.data_vars else fits, directory / "fits.nc")
        configuration, err = read_configuration(sweep)
        ctx = Context(directory=directory, sweep=sweep, metrics=metrics, fits=fits,
                      status=read_status(directory), references=load_reference_fits(reference),
                      reference_path=Path(reference) if reference else default_reference_path(),
                      configuration=configuration, config_error=err, targets=dict(targets or {}),
                      measured=measured, measured_metrics=measured_metrics, measured_fits=measured_fit,
                      dry_directory=Path(dry) if dry is not None else None, dry_metrics=dry_metrics,
                      dry_configuration=dry_configuration)
        if sensors(metrics):
            ctx.sensor_fits = fit_metrics(metrics, names=[n for n in _SENSOR_FITTED if n in metrics])
        if DRAW in metrics.dims:
            ctx.statistics = statistics_dataset(metrics)
            write_metrics(ctx.statistics, directory / STATISTICS_FILE)
        ctx.windows, ctx.windows_source = phase_windows(ctx)
        ctx.comparison = study_comparison(ctx)
        ctx.summary = summary_values(ctx)
        stored_statics(ctx)
    except BaseException:
        sweep.close()
        raise
    return ctx


def build_report(directory, reference=None, targets=None, dry=None) -> ReportFiles:
    """Metrics, fits and the report of a finished or partial sweep.

    Parameters
    ----------
    directory : path-like
        The sweep folder (``results/<name>/``).
    reference : path-like, optional
        A reference-fit TOML file; default ``sweeps/reference/study-fits.toml``.
    targets : dict, optional
        The headline's targets, key -> value in its summary column's unit (s₀ [1], L10r
        [Mrev], start-up torque [N m], k_r and k_a [N/µm], k_θ [N m/mrad]), as
        :func:`.targets.parse_targets` returns them; default none (no pass/fail mark).
    dry : path-like, optional
        A dry sweep of the same grid, compared point by point with this (lubricated) one
        (:mod:`.lubricated_vs_dry`); default none.

    Returns
    -------
    ReportFiles

    Raises
    ------
    UserError
        When the folder holds no sweep, or the reference file is invalid.
    """
    directory = Path(directory)
    ctx = load_context(directory, reference, targets, dry)
    try:
        (ctx.report_dir / "figures").mkdir(parents=True, exist_ok=True)
        with drawn_at_the_end():   # the figures on two cores
            blocks = [block for section in SECTIONS for block in section(ctx)]
        title = f"Sweep report: {directory.name}"
        md = write_text_atomic(ctx.report_dir / "report.md", render_markdown(blocks))
        ht = write_text_atomic(ctx.report_dir / "report.html", render_html(blocks, title))
        missing = missing_cases(ctx)
    finally:
        ctx.sweep.close()
    return ReportFiles(markdown=md, html=ht, figures=ctx.figures, metrics=directory / "metrics.nc",
                       fits=directory / "fits.nc", missing=missing, summary=ctx.summary_path)
