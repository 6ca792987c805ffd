"""The results folder loaded into a :class:`Context`: the combined sweep, its metrics and
fits, ``status.json``, the reference fits and the stored configuration; and what is read
off them everywhere in the report (phase windows, extra dimensions, ensembles, sensors,
the bearing's numbers, status entries matched to the grid)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from rvcore.bearing.geometry import ball_mass, epicyclic_cage_ratio
from rvcore.profile import PHASES

from ..analysis import DISPLACEMENT_COORD, REALIZATION
from ..errors import ConfigError
from ..io.netcdf import flag_name
from ..schema import StoredConfiguration, stored_configuration
from .render import fmt_number

#: The virtual-sensor dimension of sweep.nc and metrics.nc.
SENSOR = "sensor"

#: The row dimension of the per-row variables of a bearing of several rows.
ROW = "row"


@dataclass
class Context:
    """Everything the report is built from.

    ``configuration`` is the sweep's stored configuration
    (:func:`pipeline.schema.stored_configuration`), None when it could not be read; then
    ``config_error`` says why.
    """

    directory: Path
    sweep: xr.Dataset
    metrics: xr.Dataset
    fits: xr.Dataset
    status: dict
    references: list
    reference_path: Path
    configuration: StoredConfiguration | None = None
    config_error: str = ""
    #: Line fits of the sensor metrics (made for the figures; not written to fits.nc).
    sensor_fits: xr.Dataset = field(default_factory=xr.Dataset)
    #: The report's folder (default ``<directory>/report``).
    outdir: Path | None = None
    #: The figures the sections have written, in order.
    figures: list = field(default_factory=list)
    #: The phase windows ``{name: (start, end)}`` [s] and where they come from (:func:`phase_windows`).
    windows: dict = field(default_factory=dict)
    windows_source: str = ""
    #: The study comparison, one dict per reference fit (:func:`.sections_fits.study_comparison`).
    comparison: list = field(default_factory=list)
    #: The stored statics at the extreme operating points (:func:`.loads.read_statics`).
    statics: object = None
    #: The summary values (:func:`.summary.summary_values`) and the CSV written of them.
    summary: object = None
    summary_path: Path | None = None
    #: The headline's targets, key -> value in its column's unit (:func:`.targets.parse_targets`).
    targets: dict = field(default_factory=dict)
    #: The measured traces stored in ``measured/`` (:func:`pipeline.analysis.measured.read_measured`),
    #: their group of ``metrics.nc`` and their fits (dims ``speed``, ``radial_load``); empty when none.
    measured: list = field(default_factory=list)
    measured_metrics: xr.Dataset = field(default_factory=xr.Dataset)
    measured_fits: xr.Dataset = field(default_factory=xr.Dataset)
    #: A dry sweep of the same grid (``rvsweep report --dry``): its folder, phase metrics and
    #: stored configuration (:mod:`.lubricated_vs_dry`); None without one.
    dry_directory: Path | None = None
    dry_metrics: xr.Dataset | None = None
    dry_configuration: StoredConfiguration | None = None

    #: ``statistics.nc`` of a sweep with ``[statistics]`` draws (:mod:`pipeline.analysis.statistics`), else None.
    statistics: xr.Dataset | None = None

    @property
    def report_dir(self) -> Path:
        """Where ``report.md``, ``report.html`` and ``summary.csv`` go."""
        return self.outdir if self.outdir is not None else self.directory / "report"

    def figure_path(self, name: str) -> Path:
        """The path of figure ``name`` in ``figures/``, recorded in :attr:`figures`."""
        path = self.report_dir / "figures" / name
        self.figures.append(path)
        return path


def read_configuration(sweep: xr.Dataset):
    """``(StoredConfiguration or None, error text)`` from ``sweep.nc``'s ``configuration``."""
    try:
        return stored_configuration(str(sweep.attrs.get("configuration", ""))), ""
    except ConfigError as exc:
        return None, str(exc)


def phase_windows(ctx: Context):
    """Phase windows ``{name: (start, end)}`` [s] and a note on them.

    Only from the data's ``phase_start``/``phase_end`` (the windows the core accumulated
    the phase metrics over; every case writes them): those of the first finished case,
    the note saying so when other cases differ. ``{}`` and a note saying they are absent
    when the data hold none.
    """
    for ds in (ctx.metrics, ctx.sweep):
        if "phase_start" not in ds or "phase_end" not in ds:
            continue
        windows, differ = {}, False
        for k, name in enumerate(PHASES):
            a = ds["phase_start"].sel(phase=ds["phase"].values[k]).values.ravel()
            b = ds["phase_end"].sel(phase=ds["phase"].values[k]).values.ravel()
            ok = np.isfinite(a) & np.isfinite(b)
            if not ok.any():
                break
            windows[name] = (float(a[ok][0]), float(b[ok][0]))
            differ |= bool(np.ptp(a[ok]) > 1e-9 or np.ptp(b[ok]) > 1e-9)
        if len(windows) == len(PHASES):
            return windows, ("the sweep's `phase_start`/`phase_end`"
                             + (" (they differ between cases; those of the first finished case are shown)"
                                if differ else ""))
    return {}, ""


def extra_dims(ds) -> list:
    """Extra sweep dimensions of ``ds``: all but the grid axes, phase, time, the packed
    displacement metrics, the ensemble (``realization``), the sensors, the rows of a
    bearing of several rows (``row``) and the spectra's ``frequency`` and ``kinematic``."""
    return [d for d in ds.dims if d not in ("speed", "radial_load", "phase", "elapsed_time", DISPLACEMENT_COORD,
                                            REALIZATION, SENSOR, ROW, "frequency", "kinematic")]


def on_base_grid(ds, first_realization: bool = True):
    """``ds`` at the first value of every extra sweep dimension.

    Parameters
    ----------
    ds : xarray.Dataset or xarray.DataArray
    first_realization : bool
        Also take the first realization (for time series); False keeps the ``realization``
        dimension (for ensemble statistics). The ``sensor`` dimension is always kept.
    """
    sel = {d: 0 for d in extra_dims(ds)}
    if first_realization and REALIZATION in ds.dims:
        sel[REALIZATION] = 0
    return ds.isel(sel) if sel else ds


# --------------------------------------------------------------------------- ensembles and sensors


def realizations(ds):
    """Seeds of the ``realization`` dimension (float array), or None without one."""
    if REALIZATION not in ds.dims:
        return None
    if REALIZATION in ds.coords:
        return np.asarray(ds[REALIZATION].values, dtype=np.float64)
    return np.arange(ds.sizes[REALIZATION], dtype=np.float64)


def ensemble_text(ctx: Context) -> str:
    """'N = 2 realizations (seeds 0, 1)'; '' without an ensemble."""
    seeds = realizations(ctx.metrics)
    if seeds is None:
        return ""
    shown = ", ".join(fmt_number(v, 6) for v in seeds[:8]) + (", …" if seeds.size > 8 else "")
    return f"N = {seeds.size} realization{'s' if seeds.size != 1 else ''} (seed{'s' if seeds.size != 1 else ''} {shown})"


def first_realization_text(ctx: Context) -> str:
    """'the first realization (seed 0) of N = 2'; '' without an ensemble."""
    seeds = realizations(ctx.sweep)
    if seeds is None:
        return ""
    return f"the first realization (seed {fmt_number(seeds[0], 6)}) of N = {seeds.size}"


def ensemble_statistics(da: xr.DataArray):
    """Mean and standard error of the mean over ``realization``, NaN-safe and silent.

    Parameters
    ----------
    da : xarray.DataArray
        With a ``realization`` dimension [any unit].

    Returns
    -------
    mean, stderr : xarray.DataArray
        ``mean = Σ x_k / n`` and ``stderr = s/√n`` with ``s`` the sample standard deviation
        (ddof 1) of the n finite realizations [unit of ``da``]; NaN where n = 0 (mean) or
        n < 2 (stderr), as ``pipeline.analysis.metrics.ensemble_statistics``.
    """
    n = da.notnull().sum(REALIZATION)
    mean = da.sum(REALIZATION, skipna=True) / n.where(n > 0)
    var = ((da - mean) ** 2).sum(REALIZATION, skipna=True) / (n - 1).where(n >= 2)
    return mean, np.sqrt(var / n.where(n >= 2))


def ensemble_of(m: xr.Dataset, name: str, sel: dict):
    """Ensemble mean and standard error of metric ``name`` at ``sel``.

    ``metrics.nc``'s ``<name>_ensemble_mean``/``_ensemble_stderr`` where it has them,
    otherwise :func:`ensemble_statistics` of the realizations.
    """
    mean_name, se_name = f"{name}_ensemble_mean", f"{name}_ensemble_stderr"
    if mean_name in m and se_name in m:
        return m[mean_name].sel(sel), m[se_name].sel(sel)
    return ensemble_statistics(m[name].sel(sel))


def edge_flag(m: xr.Dataset, name: str, sel: dict):
    """``<x>_range_at_edge`` at ``sel`` for a range metric ``<x>_range``, else None."""
    if not name.endswith("_range"):
        return None
    flag = name.removesuffix("_range") + "_range_at_edge"
    return m[flag].sel(sel) if flag in m else None


@dataclass(frozen=True)
class SensorInfo:
    """One virtual displacement sensor of the sweep.

    Parameters
    ----------
    value : int
        Its flag value on the ``sensor`` coordinate.
    name : str
        Its name (from the coordinate's ``flag_meanings``).
    position : tuple of float
        The ring point it reads, bearing frame [m].
    direction : tuple of float
        Its unit measuring direction [1].
    """

    value: int
    name: str
    position: tuple
    direction: tuple

    def where(self) -> str:
        """'at (x, y, z) mm along (dx, dy, dz)'."""
        pos = ", ".join(fmt_number(v * 1e3 + 0.0, 5) for v in self.position)
        d = ", ".join(fmt_number(v + 0.0, 3) for v in self.direction)
        return f"at ({pos}) mm along ({d})"

    def label(self, code: bool = True) -> str:
        """'sensor `name` at (x, y, z) mm along (dx, dy, dz)' (name in backticks with ``code``)."""
        name = f"`{self.name}`" if code else self.name
        return f"sensor {name} {self.where()}"


def rows_of(ds, name: str) -> list:
    """The ``row`` values of variable ``name`` of ``ds`` ([None] when it has no row dimension)."""
    if name not in ds or ROW not in ds[name].dims:
        return [None]
    return [int(v) for v in np.asarray(ds[ROW].values).ravel()] if ROW in ds.coords else list(range(ds.sizes[ROW]))


def sensors(ds) -> list:
    """The sensors of ``ds``'s ``sensor`` dimension as :class:`SensorInfo`, [] without one."""
    if SENSOR not in ds.dims:
        return []
    c = ds[SENSOR]
    values = [int(v) for v in np.asarray(c.values).ravel()]
    out = []
    for k, v in enumerate(values):
        name = flag_name(c, np.int64(v), f"{SENSOR}_{v}")

        def vec(prefix):
            return tuple(float(ds[f"{prefix}_{a}"].values[k]) if f"{prefix}_{a}" in ds.coords else math.nan
                         for a in "xyz")

        out.append(SensorInfo(v, name, vec("sensor_position"), vec("sensor_direction")))
    return out



def bearing_numbers(ctx: Context) -> dict:
    """The first row's ball diameter ``D`` [m], ball density ``rho`` [kg m-3], ball mass
    ``m_b`` [kg], pitch diameter ``d_m`` [m], nominal (outer) contact angle ``alpha``
    [rad] and epicyclic cage ratio ``cage_ratio`` [-] at it (0 deg without an arc;
    :func:`rvcore.bearing.geometry.epicyclic_cage_ratio`), read from the stored
    configuration's :class:`rvcore.bearing.geometry.Bearing`; NaN each without a readable
    configuration."""
    conf = ctx.configuration
    if conf is None:
        return dict.fromkeys(("D", "rho", "m_b", "d_m", "alpha", "cage_ratio"), math.nan)
    b = conf.bearing
    row = b.rows[0]
    alpha = row.outer_arcs[0].contact_angle if row.outer_arcs else math.nan
    return {"D": row.ball_diameter, "rho": b.ball_material.density, "m_b": ball_mass(row, b.ball_material),
            "d_m": row.pitch_diameter, "alpha": alpha,
            "cage_ratio": epicyclic_cage_ratio(row, alpha if math.isfinite(alpha) else 0.0)}


#: Keys of a status.json entry that are not axis values.
_STATUS_KEYS = ("state", "reason", "traceback", "seconds", "index", "units", "sha256")


def status_lookup(ctx: Context):
    """status.json entries matched to the grid by their SI point values.

    Returns ``({(speed °/s, load N, seed or None): (state, reason, id)}, [(id, state,
    reason, axis values)])``: the matched entries and those not on the grid. ``seed`` is
    the entry's ``realization`` when the grid has that dimension and names that seed.
    """
    speeds = ctx.metrics["speed"].values
    loads = ctx.metrics["radial_load"].values
    seeds = realizations(ctx.metrics)
    matched, unmatched = {}, []

    def on_grid(values, x):
        hit = [float(v) for v in values if math.isclose(v, x, rel_tol=1e-6)]
        return hit[0] if hit else None

    for cid, e in sorted(ctx.status.items()):
        values = {k: v for k, v in e.items() if k not in _STATUS_KEYS}
        state, reason = str(e.get("state", "")), str(e.get("reason", "") or "")
        speed, load = values.get("speed"), values.get("radial_load")
        s = on_grid(speeds, math.degrees(speed)) if isinstance(speed, (int, float)) else None
        l = on_grid(loads, float(load)) if isinstance(load, (int, float)) else None
        r = values.get(REALIZATION)
        seed = (on_grid(seeds, float(r)) if seeds is not None and isinstance(r, (int, float)) else None)
        if s is not None and l is not None:
            matched.setdefault((s, l, seed), (state, reason, cid))
        else:
            unmatched.append((cid, state, reason, values))
    return matched, unmatched
