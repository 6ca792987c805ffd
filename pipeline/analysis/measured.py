"""Measured cases in a sweep folder: their metrics beside the simulated ones, and their fits.

``rvsweep compare TRACE.toml --sweep DIR`` stores each comparison as
``DIR/measured/<trace name>.nc`` (:func:`pipeline.analysis.compare.comparison_dataset`:
the measured phase metrics, computed by the core's own phase reductions, under the case
files' names). ``rvsweep report DIR`` reads them (:func:`read_measured`) and adds:

- to ``metrics.nc`` the measured group (:func:`measured_group`): ``measured_<metric>``
  over ``(measured_case, phase)`` and each test's operating point and lag over
  ``measured_case``, an int8 flag coordinate whose ``flag_meanings`` name the traces;
- to ``fits.nc`` the measured fits (:func:`measured_fits`): the measured cases laid on the
  grid of their own operating points (speeds and radial loads) and fitted by the code that
  fits the simulated ones (:func:`pipeline.analysis.fits.fit_metrics`), every variable
  prefixed ``measured_`` and its axes named ``measured_speed`` and ``measured_radial_load``.

A sweep folder without ``measured/`` gives neither: its files are as before.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import UserError
from ..io import phase_coordinate, strip_encoding
from .fits import DISPLACEMENT_METRICS, fit_metrics

#: The folder of a sweep where ``rvsweep compare --sweep`` stores its comparisons.
MEASURED_DIR = "measured"
#: The dimension of the measured cases in ``metrics.nc``.
MEASURED_DIM = "measured_case"
#: The measured phase metrics carried into ``metrics.nc`` (those the comparison holds).
MEASURED_METRICS = tuple(f"{s}_displacement_{k}" for s in ("radial", "axial")
                         for k in ("range", "mean", "std", "min_time", "max_time", "range_at_edge"))
#: Operating-point coordinates of a comparison and their fallbacks: name -> (units, long name).
_POINT = {"speed": ("degree s-1", "steady inner-ring speed of the measured test"),
          "radial_load": ("N", "steady radial load of the measured test"),
          "axial_load": ("N", "steady axial load of the measured test")}


def read_measured(directory) -> list:
    """The comparisons stored in ``<directory>/measured/*.nc``, by file name; [] when none.

    Raises
    ------
    UserError
        One line naming a file that cannot be read or holds no measured phase metric.
    """
    files = sorted((Path(directory) / MEASURED_DIR).glob("*.nc"))
    out = []
    for f in files:
        try:
            with xr.open_dataset(f, engine="netcdf4") as ds:
                ds = strip_encoding(ds.load())
        except Exception as exc:  # netCDF4/HDF5 raise OSError, RuntimeError, ValueError
            why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise UserError(f"{f}: cannot read as NetCDF ({why})") from None
        if not any(m in ds for m in MEASURED_METRICS) or "phase" not in ds.dims:
            raise UserError(f"{f}: not a comparison of rvsweep compare (no measured phase metric)")
        ds.attrs["measured_file"] = f.name
        out.append(ds)
    return out


def measured_group(cases: list) -> xr.Dataset:
    """The measured group of ``metrics.nc`` (see the module docstring).

    Parameters
    ----------
    cases : list of xarray.Dataset
        Comparisons (:func:`read_measured`).

    Returns
    -------
    xarray.Dataset
        ``measured_<metric>`` over ``(measured_case, phase)`` with the case files' units;
        ``measured_case_speed`` [degree s-1], ``measured_case_radial_load``,
        ``measured_case_axial_load`` [N] and ``measured_case_lag`` [s] over
        ``measured_case``; the combined Sprague–Geers error of each series per phase where a
        simulated case was compared. NaN where a comparison lacks one.
    """
    n = len(cases)
    names = [str(c.attrs.get("trace", "")) or Path(c.attrs["measured_file"]).stem for c in cases]
    meanings = []
    for s in names:
        word = "".join(ch if ch.isalnum() or ch in "._-" else "_" for ch in s) or "trace"
        meanings.append(word if word not in meanings else f"{word}_{len(meanings)}")
    flag = {"long_name": "measured test (a trace compared by rvsweep compare --sweep, stored in measured/)",
            "flag_values": np.arange(n, dtype=np.int8), "flag_meanings": " ".join(meanings)}
    n_phase = phase_coordinate().size
    data = {}
    for m in MEASURED_METRICS:
        if not any(m in c for c in cases):
            continue
        arr = np.full((n, n_phase), np.nan)
        for i, c in enumerate(cases):
            if m in c:
                arr[i] = np.asarray(c[m].values, dtype=np.float64)
        data[f"measured_{m}"] = ((MEASURED_DIM, "phase"), arr, {
            "units": c_units(cases, m), "long_name": f"measured: {c_long(cases, m)}"})
    for key, (units, long_name) in _POINT.items():
        data[f"measured_case_{key}"] = (MEASURED_DIM, np.array(
            [float(c[key]) if key in c.coords else math.nan for c in cases]), {"units": units, "long_name": long_name})
    data["measured_case_lag"] = (MEASURED_DIM, np.array([float(c["lag"]) if "lag" in c else math.nan for c in cases]),
                                 {"units": "s", "long_name": "lag of the measured trace behind the simulated cycle"})
    for s in ("radial_displacement", "axial_displacement"):
        v = f"{s}_sprague_geers_combined"
        if any(v in c for c in cases):
            data[f"measured_{v}"] = ((MEASURED_DIM, "phase"), np.array(
                [np.asarray(c[v].values, dtype=np.float64) if v in c else np.full(n_phase, np.nan) for c in cases]),
                {"units": "1", "long_name": f"Sprague-Geers combined error of the simulated {s} against the "
                                            "measured, per phase"})
    return xr.Dataset(data, coords={MEASURED_DIM: (MEASURED_DIM, np.arange(n, dtype=np.int8), flag),
                                    "phase": phase_coordinate()})


def c_units(cases, name) -> str:
    """The units of ``name`` in the first comparison that holds it."""
    return next(str(c[name].attrs.get("units", "1")) for c in cases if name in c)


def c_long(cases, name) -> str:
    """The long name of ``name`` in the first comparison holding it, without 'measured: '."""
    return next(str(c[name].attrs.get("long_name", name)) for c in cases if name in c).removeprefix("measured: ")


def measured_grid(group: xr.Dataset) -> xr.Dataset:
    """The measured displacement metrics laid on the grid of the tests' own speeds and
    radial loads (``speed`` [degree s-1], ``radial_load`` [N], ``phase``), NaN where no test
    ran; tests at one operating point (to 1e-6 relative) are averaged. Tests without a
    known speed or radial load are left out."""
    s = group["measured_case_speed"].values
    r = group["measured_case_radial_load"].values
    ok = np.isfinite(s) & np.isfinite(r)
    speeds = _distinct(s[ok])
    loads = _distinct(r[ok])
    data = {}
    for m in DISPLACEMENT_METRICS:
        v = f"measured_{m}"
        if v not in group:
            continue
        total = np.zeros((speeds.size, loads.size, group.sizes["phase"]))
        count = np.zeros_like(total)
        for i in np.flatnonzero(ok):
            a = int(np.argmin(np.abs(speeds - s[i])))
            b = int(np.argmin(np.abs(loads - r[i])))
            x = group[v].values[i]
            fin = np.isfinite(x)
            total[a, b, fin] += x[fin]
            count[a, b, fin] += 1
        with np.errstate(invalid="ignore"):
            mean = np.where(count > 0, total / np.maximum(count, 1), np.nan)
        data[m] = (("speed", "radial_load", "phase"), mean, {
            "units": group[v].attrs["units"], "long_name": group[v].attrs["long_name"]})
    return xr.Dataset(data, coords={
        "speed": ("speed", speeds, {"units": "degree s-1", "long_name": "steady inner-ring speed of the measured tests"}),
        "radial_load": ("radial_load", loads, {"units": "N", "long_name": "steady radial load of the measured tests"}),
        "phase": group["phase"]})


def _distinct(values) -> np.ndarray:
    """Sorted distinct values, those within 1e-6 relative of the previous one merged."""
    out = []
    for v in np.sort(np.asarray(values, dtype=np.float64)):
        if not out or not math.isclose(v, out[-1], rel_tol=1e-6, abs_tol=1e-12):
            out.append(float(v))
    return np.array(out)


def measured_fits(group: xr.Dataset) -> xr.Dataset:
    """Line and plane fits of the measured displacement metrics by :func:`fit_metrics`, on
    :func:`measured_grid` (dims ``speed``, ``radial_load`` as there; :func:`fits_file_form`
    names them for ``fits.nc``)."""
    grid = measured_grid(group)
    if not grid.data_vars or grid.sizes["speed"] == 0:
        return xr.Dataset()
    return fit_metrics(grid)


def fits_file_form(fits: xr.Dataset) -> xr.Dataset:
    """:func:`measured_fits` as ``fits.nc`` holds it: variables prefixed ``measured_``, axes
    ``measured_speed`` and ``measured_radial_load``."""
    if not fits.data_vars:
        return fits
    out = fits.rename({k: f"measured_{k}" for k in fits.data_vars})
    out = out.rename({d: f"measured_{d}" for d in ("speed", "radial_load") if d in out.dims})
    out.attrs = {}
    return out


def points_on_line(group: xr.Dataset, variable: str, axis: str, fixed_axis: str, fixed: float, phase: int,
                   rel: float = 0.01):
    """The measured tests on one line of a metric figure: those whose ``fixed_axis`` is within
    ``rel`` (relative) of ``fixed`` [coordinate units: degree s-1 or N].

    Returns
    -------
    x, y : ndarray
        Their ``axis`` values [coordinate units] and ``measured_<variable>`` at phase flag
        ``phase`` [its units]; empty when the group holds none.
    """
    v = f"measured_{variable}"
    if not group or v not in group:
        return np.zeros(0), np.zeros(0)
    on = np.isclose(group[f"measured_case_{fixed_axis}"].values, fixed, rtol=rel, atol=0.0)
    x = group[f"measured_case_{axis}"].values[on]
    y = group[v].sel(phase=phase).values[on]
    ok = np.isfinite(x) & np.isfinite(y)
    return x[ok], y[ok]
