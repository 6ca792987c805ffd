"""Report sections on the displacements: the time histories of the extreme cases and the
study's metrics against speed and load, at the ring centre and at the virtual sensors."""
from __future__ import annotations

from rvcore.profile import PHASES

from .context import SENSOR, Context, ensemble_text, first_realization_text, realizations, sensors
from .figures import figure_metric, figure_sensor_metric, figure_sensor_time_histories, figure_time_histories
from .render import CENTRE_LABEL, METRIC_TITLE, PHASE_TITLE, Heading, Image, Para, fmt_kn, fmt_number, fmt_speed
from .sections import window_coverage
from .select import axis_specs, extreme_points


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
        text += (" A range cannot be negative: where the 95 % band (or the line) would go below zero it is cut "
                 "at zero. The fit stays a straight line in the range itself, as the study's fits are, so that "
                 "its slope compares with theirs; a fit in log space would stay positive but change that slope.")
        if hollow:
            text += (f" Hollow markers ({hollow} {'realization' if ens else 'case'}{'s' if hollow != 1 else ''}"
                     f"{(' and the mean it belongs to' if hollow == 1 else ' and the means they belong to') if ens else ''}"
                     "): the range has an extreme at the "
                     "window's edge, so it is cut off by the window and is a lower bound.")
        else:
            text += " No range drawn here has an extreme at the window's edge."
    return text


def _windows_text(windows, source: str) -> str:
    """'Phase windows from …: start-up a–b s, …' or a sentence saying the data hold none."""
    if not windows:
        return ("The data hold no phase windows (`phase_start`/`phase_end`), so none are shaded "
                "and the steady-phase estimates below that need them are left out.")
    return (f"Phase windows from {source}: "
            + ", ".join(f"{PHASE_TITLE.get(k, k)} {fmt_number(a, 4)}–{fmt_number(b, 4)} s"
                        for k, (a, b) in windows.items()) + ".")


def section_time_histories(ctx: Context) -> list:
    """δ_r and δ_a at the ring centre (and the sensors' readings) of the extreme cases."""
    blocks = [Heading(2, "Time histories")]
    cases = extreme_points(ctx, realization=0 if realizations(ctx.sweep) is not None else None)
    if not cases:
        return blocks + [Para("No case finished; there are no time histories to show.")]
    first = first_realization_text(ctx)
    which = "; ".join(f"{fmt_speed(s)}, {fmt_kn(load)}" for s, load in cases)
    p = ctx.figure_path("time_histories.png")
    off = figure_time_histories(ctx, ctx.windows, p, cases)
    scaled = ""
    if ctx.windows:
        scaled = (" The y-axes are fitted to the phase windows: before the first window the ring settles onto its "
                  "balls from its initial position while the loads ramp up, and after the last it unloads; those "
                  "times are drawn, hatched grey, but not scaled to"
                  + (" (" + "; ".join(off) + ")" if off else "") + ".")
    blocks.append(Para(f"δ_r and δ_a at the ring centre of the extreme cases ({which})"
                       + (f", {first} (the other realizations are in `sweep.nc`)" if first else "")
                       + ". " + _windows_text(ctx.windows, ctx.windows_source) + window_coverage(ctx, ctx.windows)
                       + scaled))
    blocks.append(Image(f"figures/{p.name}", "time histories of the extreme cases"))
    sens = sensors(ctx.metrics)
    if sens and "sensor_displacement" in ctx.sweep:
        p = ctx.figure_path("sensor_time_histories.png")
        figure_sensor_time_histories(ctx, ctx.windows, p, cases)
        blocks.append(Para("Readings of the virtual sensors for the same cases"
                           + (f", {first}" if first else "") + ", one panel per sensor: "
                           + "; ".join(sn.label() for sn in sens) + ". Phase windows shaded as above."))
        blocks.append(Image(f"figures/{p.name}", "sensor readings of the extreme cases"))
    return blocks


def _centre_metric_figures(ctx: Context) -> list:
    """A figure per (phase, displacement, metric) of the study's fits, at the ring centre."""
    groups = {}
    for ref in ctx.references:
        grefs = groups.setdefault((ref.phase, ref.displacement, ref.metric), [])
        if ref.axis not in [g.axis for g in grefs]:
            grefs.append(ref)
    blocks = []
    for (phase, disp, metric), grefs in groups.items():
        p = ctx.figure_path(f"metric_{phase}_{disp}_{metric}.png")
        notes, hollow = figure_metric(ctx, grefs, p)
        blocks.append(Heading(3, f"{PHASE_TITLE[phase]} {disp} displacement {METRIC_TITLE[metric]}, "
                                 f"at the ring centre"))
        blocks.append(Para(_metric_caption(ctx, f"{CENTRE_LABEL[disp]}", notes, hollow, metric == "range",
                                           _has_data(ctx, grefs[0].variable, phase))))
        blocks.append(Image(f"figures/{p.name}", f"{phase} {disp} {metric}"))
    return blocks


def _sensor_metric_figures(ctx: Context) -> list:
    """A figure per (phase, metric) of the study's fits, a row per virtual sensor."""
    sens = sensors(ctx.metrics)
    if not sens:
        return []
    pairs = []
    for ref in ctx.references:
        if (ref.phase, ref.metric) not in pairs:
            pairs.append((ref.phase, ref.metric))
    blocks = []
    for phase, metric in pairs:
        name = f"{SENSOR}_displacement_{metric}"
        if name not in ctx.metrics:
            continue
        p = ctx.figure_path(f"sensor_{phase}_{metric}.png")
        notes, hollow = figure_sensor_metric(ctx, phase, metric, axis_specs(ctx, phase), p)
        has_data = _has_data(ctx, name, phase)
        blocks.append(Heading(3, f"{PHASE_TITLE[phase]} sensor reading {METRIC_TITLE[metric]}"))
        blocks.append(Para(_metric_caption(
            ctx, "The virtual sensors' readings, a row per sensor (" + "; ".join(sn.label() for sn in sens)
            + ")", notes, hollow, metric == "range", has_data)
            + (" The sensors' lines are fitted for this report and not stored in `fits.nc`." if has_data else "")))
        blocks.append(Image(f"figures/{p.name}", f"{phase} sensor {metric}"))
    return blocks


def section_metrics(ctx: Context) -> list:
    """The study's metrics against speed and load with our fits, at the ring centre and the sensors."""
    blocks = [Heading(2, "Metrics against speed and load")]
    ens = ensemble_text(ctx)
    if ens:
        blocks.append(Para(f"With {ens}, every metric is shown as the ensemble mean over the realizations "
                           "with ±1 standard-error bars, and each realization as a faint small point."))
    return blocks + _centre_metric_figures(ctx) + _sensor_metric_figures(ctx)
