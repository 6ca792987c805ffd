"""The report's comparison of a lubricated sweep with a dry one of the same grid
(``rvsweep report DIR --dry DIR2``, issue 40).

A sweep whose bearing runs the lubricated contact law (``friction.law = "ehl_bair_winer"``,
docs/model.md §4.1) is compared point by point with a sweep of the same grid run with the
study's dry law (``coulomb_step``, §4), given as ``--dry``: the steady cage slip
(``cage_slip``), the steady drive torque (``inner_ring_drive_torque_mean``) and the radial
displacement's range in each phase (``radial_displacement_range``: start-up, steady,
deceleration), each beside the dry law's, and the median over the grid of each lubricated
value over the dry one. Nothing is solved again: both columns are the two sweeps' own phase
metrics (``metrics.nc`` of each, computed by :func:`pipeline.analysis.phase_metrics`); with an
ensemble, the ensemble means (:func:`.select.metric_stat`).

Why a second sweep and not the law as a sweep axis: the study grid and its dry sweep
(``sweeps/study.toml``) exist already, and the lubricated grid
(``sweeps/study-lubricated.toml``) is the same grid with the law fixed, so the two are run
and resumed as any sweep; the grids must match (:func:`check_same_grid`, before any work).
"""
from __future__ import annotations

import math
import statistics
from types import SimpleNamespace

import numpy as np

from rvcore.bearing.laws import DRY_LAW, LUBRICATED_LAW

from ..errors import UserError
from .context import Context
from .render import Bullets, Heading, Para, Table, Warning_, fmt_kn, fmt_number, fmt_speed
from .select import finished_points, metric_stat

#: The compared quantities: (metric, phase, column label, factor from SI, digits).
QUANTITIES = (
    ("cage_slip", "steady", "cage slip, steady [%]", 100.0, 3),
    ("inner_ring_drive_torque_mean", "steady", "drive torque, steady [N m]", 1.0, 4),
    ("radial_displacement_range", "startup", "δ_r range, start-up [µm]", 1e6, 4),
    ("radial_displacement_range", "steady", "δ_r range, steady [µm]", 1e6, 4),
    ("radial_displacement_range", "deceleration", "δ_r range, deceleration [µm]", 1e6, 4),
)
#: The grid axes that must match between the two sweeps.
GRID_AXES = ("speed", "radial_load")


def sweep_law(configuration) -> str:
    """The friction law of a sweep's stored configuration ('' when it could not be read)."""
    if configuration is None:
        return ""
    return str(getattr(configuration.bearing.contact, "law", DRY_LAW))


def check_same_grid(metrics, dry_metrics, directory, dry_directory) -> None:
    """The two sweeps' grids (:data:`GRID_AXES`, and the realizations' count) are the same,
    or a :class:`pipeline.errors.UserError` naming the axis and both values (one line)."""
    for axis in GRID_AXES:
        a = np.asarray(metrics[axis].values, dtype=np.float64) if axis in metrics.coords else np.array([])
        b = np.asarray(dry_metrics[axis].values, dtype=np.float64) if axis in dry_metrics.coords else np.array([])
        if a.shape != b.shape or not np.allclose(a, b, rtol=1e-9, atol=0.0):
            raise UserError(f"--dry {dry_directory}: its {axis} axis {fmt_values(b)} is not {directory.name}'s "
                            f"{fmt_values(a)}; the comparison needs a dry sweep of the same grid")


def fmt_values(values) -> str:
    """An axis's values as '[120, 180, …]' (at most six, 4 significant digits)."""
    shown = [fmt_number(float(v), 4) for v in np.asarray(values).ravel()[:6]]
    return "[" + ", ".join(shown) + (", …" if np.asarray(values).size > 6 else "") + "]"


def comparison_rows(ctx: Context) -> list:
    """``[(speed, load, [(lubricated, dry), …])]`` at every grid point finished in both sweeps,
    a pair per :data:`QUANTITIES` entry, in display units."""
    dry = SimpleNamespace(metrics=ctx.dry_metrics)
    out = []
    for sp, ld in finished_points(ctx):
        pairs = []
        for name, phase, _, scale, _ in QUANTITIES:
            wet_v = metric_stat(ctx, name, sp, ld, phase)[0] * scale
            dry_v = metric_stat(dry, name, sp, ld, phase)[0] * scale
            pairs.append((wet_v, dry_v))
        out.append((sp, ld, pairs))
    return out


def median_ratios(rows: list) -> list:
    """The median over the grid of lubricated/dry for each quantity (NaN where no point has both)."""
    out = []
    for k in range(len(QUANTITIES)):
        r = [w / d for _, _, pairs in rows for w, d in [pairs[k]] if math.isfinite(w) and math.isfinite(d) and d != 0]
        out.append(statistics.median(r) if r else math.nan)
    return out


def section_lubricated_vs_dry(ctx: Context) -> list:
    """The lubricated sweep beside the dry one (module docstring); a note on a lubricated sweep
    given no ``--dry``; nothing for a dry sweep without one."""
    law = sweep_law(getattr(ctx, "configuration", None))
    dry_metrics = getattr(ctx, "dry_metrics", None)
    if dry_metrics is None:
        if law != LUBRICATED_LAW:
            return []
        return [Heading(2, "Lubricated against dry"),
                Para("This sweep runs the lubricated contact law (`ehl_bair_winer`, docs/model.md §4.1). To see its "
                     "cage slip, drive torque and transient ranges beside the dry law's, run the same grid with the "
                     "study's law (e.g. `sweeps/study.toml` beside `sweeps/study-lubricated.toml`) and give its folder: "
                     "`rvsweep report DIR --dry DRY_DIR`.")]
    dry_law = sweep_law(getattr(ctx, "dry_configuration", None))
    blocks = [Heading(2, "Lubricated against dry")]
    name = getattr(ctx, "dry_directory", None)
    blocks.append(Para(
        f"Each grid point of this sweep (law `{law or '?'}`) beside the same point of the dry sweep "
        f"`{name.name if name is not None else '?'}` (law `{dry_law or '?'}`): both columns are the sweeps' own "
        "phase metrics" + (" (ensemble means)" if "realization" in ctx.metrics.dims else "")
        + ". Cage slip `cage_slip` = 1 − ω̄_c/ω_epi (positive: the cage lags), the drive torque the steady mean of "
        "the moment the ring's prescribed spin needs, δ_r range the radial displacement's range over each phase "
        "(start-up, steady, deceleration)."))
    warnings = []
    if law != LUBRICATED_LAW:
        warnings.append(f"this sweep's law is `{law or 'unreadable'}`, not `{LUBRICATED_LAW}`")
    if dry_law != DRY_LAW:
        warnings.append(f"the --dry sweep's law is `{dry_law or 'unreadable'}`, not `{DRY_LAW}`")
    if warnings:
        blocks.append(Warning_("**Not a lubricated-against-dry pair:** " + "; ".join(warnings) + "."))
    rows = comparison_rows(ctx)
    if not rows:
        blocks.append(Para("No grid point finished in this sweep: nothing to compare."))
        return blocks
    header = ["speed", "radial load"]
    for _, _, label, _, _ in QUANTITIES:
        header += [f"{label} lubricated", "dry"]
    table = []
    for sp, ld, pairs in rows:
        line = [fmt_speed(sp).replace(" °/s", ""), fmt_kn(ld).replace(" kN", "")]
        for (w, d), (_, _, _, _, digits) in zip(pairs, QUANTITIES):
            line += [fmt_number(w, digits), fmt_number(d, digits)]
        table.append(line)
    header[0], header[1] = "speed [°/s]", "radial load [kN]"
    blocks.append(Table(header, table))
    ratios = median_ratios(rows)
    blocks.append(Bullets([f"{label}: lubricated/dry, median over the grid, {fmt_number(r, 3)}"
                           for (_, _, label, _, _), r in zip(QUANTITIES, ratios)]))
    return blocks


def load_dry(directory, dry_directory):
    """The dry sweep's phase metrics and stored configuration, for :class:`.context.Context`
    (``dry_metrics``, ``dry_configuration``): read before any file of the report is written;
    a :class:`pipeline.errors.UserError` (one line) when ``dry_directory`` holds no sweep or
    its grid differs (:func:`check_same_grid` is called by :func:`pipeline.report.build.load_context`)."""
    from ..analysis import open_results, phase_metrics
    from .context import read_configuration

    sweep = open_results(dry_directory, lazy=True)
    try:
        metrics = phase_metrics(sweep)
        configuration, _ = read_configuration(sweep)
    finally:
        sweep.close()
    return metrics, configuration
