"""Phase metrics of a sweep (``metrics.nc``), from the core's phase accumulators.

The core accumulates, at every integrator step, the range, mean and standard deviation
of δ_r and δ_a per phase, the mean cage and inner-ring speeds, the cage slip against the
epicyclic speed and the peak Hertz pressure (``pipeline.io.case.PHASE_METRICS``), and,
where the case files carry them, the designer's outputs (drive torque, friction, cage forces, race
sliding, static safety factor, fatigue damage; :data:`DESIGNER_METRICS`) with the
per-case stiffness and rating lives (:data:`SCALARS`). This
module gathers them from ``sweep.nc`` (or, when no ``sweep.nc`` was written, from the
case files) into one dataset over ``(speed, radial_load, phase)``, plus any extra sweep
dimension, with the case status alongside. Missing or failed cases are NaN.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import xarray as xr

from rvcore.output_table import PHASE, STEADY, outputs_of
from rvcore.profile import PHASES

from ..io.netcdf import CASE_STATUS, case_status_variable
from ..io import (PHASE_METRICS, combine_cases, grid_from_cases, read_status, SENSOR_METRICS, VARIABLES, history_line, phase_coordinate, strip_encoding,
                  write_atomic)
from ..errors import UserError
from ..schema import REALIZATION

#: Phase-metric variables in ``metrics.nc`` (those the sweep holds).
METRICS = tuple(PHASE_METRICS) + tuple(SENSOR_METRICS)

#: Metrics whose ensemble mean and standard error ``metrics.nc`` adds over realizations.
ENSEMBLE_METRICS = tuple(m for m in METRICS if m.endswith(("_range", "_mean", "_std")) and "displacement" in m)

_DISPLACEMENT_METRICS = tuple(f"{s}_displacement_{k}" for s in ("radial", "axial") for k in ("range", "mean", "std"))

# Units and long names come from the case files' one table, pipeline.io.VARIABLES; a sweep
# whose case files lack these variables is reported without them.

#: Stiffness at the steady operating point, one scalar per case (no ``phase``):
#: name -> (units, long_name), from the output table (rvcore.output_table).
STIFFNESS = {o.name: (o.units, o.long_name) for o in outputs_of(STEADY, group="stiffness")
             if o.name.endswith("_stiffness")}
#: The same with every other coordinate free (1/C_ii of the compliance), beside each.
COMPLIANT_STIFFNESS = {f"{k}_compliant": VARIABLES[f"{k}_compliant"][1:] for k in STIFFNESS}

#: The designer's phase metrics, over ``phase``: name -> (units, long_name).
DESIGNER_METRICS = {o.name: (o.units, o.long_name) for o in outputs_of(PHASE, group="designer")}

#: The designer's scalars of a case, no ``phase``: the rating lives (in
#: revolutions of the inner ring, units "1"; the duty cycle's also in cycles of the
#: profile) and the cycle's damage.
DESIGNER_SCALARS = {k: v[1:] for k, v in VARIABLES.items()
                    if v[0] == () and k not in STIFFNESS and k not in COMPLIANT_STIFFNESS}

#: Every per-case scalar (no ``phase``) ``metrics.nc`` carries when the sweep holds it.
SCALARS = {**STIFFNESS, **COMPLIANT_STIFFNESS, **DESIGNER_SCALARS}


#: The most elements one read of :func:`read_in_slabs` asks the NetCDF library for. HDF5
#: builds a map of every chunk a read touches (about 6 kB each, kept in its free lists
#: after the read): ``sweep.nc`` has one chunk per case, so one read of a whole variable
#: of 10,000 cases took about 60 MB of resident memory, and 100,000 cases would take ten
#: times that.
SLAB_ELEMENTS = 4096

#: Dimensions of ``sweep.nc`` that make a variable a series per case (read lazily).
_SERIES_DIMS = ("elapsed_time", "frequency", "kinematic")


def _per_case_values(da: xr.DataArray) -> bool:
    """Whether ``da`` holds a few numbers per case (the phase metrics, the case status,
    the per-case scalars): over the grid axes, with no time, frequency or kinematic axis."""
    return "speed" in da.dims and not any(d in da.dims for d in _SERIES_DIMS)


def read_slabs(shape, limit: int | None = None):
    """The index tuples (of slices) that cover an array of ``shape`` in C order, each
    covering at most ``limit`` elements (at least one element of the last dimension).

    The split dimension is the first ``k`` with ``prod(shape[k+1:]) <= limit``; the
    dimensions before it are taken one index at a time, ``k`` in steps of
    ``max(1, limit // prod(shape[k+1:]))``. ``limit``: default :data:`SLAB_ELEMENTS`.
    """
    limit = SLAB_ELEMENTS if limit is None else int(limit)
    shape = tuple(int(n) for n in shape)
    if not shape or math.prod(shape) <= limit:
        return [tuple(slice(0, n) for n in shape)]
    k = next((i for i in range(len(shape)) if math.prod(shape[i + 1:]) <= limit), len(shape) - 1)
    step = max(1, limit // math.prod(shape[k + 1:]))
    rest = tuple(slice(0, n) for n in shape[k + 1:])
    return [tuple(slice(i, i + 1) for i in lead) + (slice(j, min(j + step, shape[k])),) + rest
            for lead in np.ndindex(*shape[:k]) for j in range(0, shape[k], step)]


def read_in_slabs(var: xr.Variable, limit: int | None = None) -> np.ndarray:
    """The values of a lazily opened variable, read a slab of at most ``limit`` elements
    at a time (:func:`read_slabs`) into one array of its dtype: the same values as
    ``var.values``, with the NetCDF library's memory for one read bounded by ``limit``
    instead of growing with the cases (:data:`SLAB_ELEMENTS`)."""
    out = np.empty(var.shape, dtype=var.dtype)
    for key in read_slabs(var.shape, limit):
        out[key] = var[key].values
    return out


def open_results(directory, *, lazy: bool = False) -> xr.Dataset:
    """The combined sweep of a results folder, loaded into memory (or opened lazily).

    Reads ``sweep.nc``; when it is absent (a sweep killed before combining), combines the
    finished ``cases/*.nc`` over ``speed`` and ``radial_load`` (and ``axial_load`` when it
    varies), missing grid points NaN.

    Parameters
    ----------
    directory : path-like
        The sweep's output folder.
    lazy : bool
        Open ``sweep.nc`` without reading its variables: each is read when used, and a
        selection reads only its slab (one case's time series is one chunk), so that what
        the report holds does not grow with the time series of every case. The few
        numbers of each case (phase metrics, case status, per-case scalars: no time,
        frequency or kinematic axis) are read at once, a slab at a time
        (:func:`read_in_slabs`), and held in memory. The caller closes the dataset.
        (Without ``sweep.nc`` the case files are read in full.)

    Raises
    ------
    UserError
        When the folder holds neither ``sweep.nc`` nor any case file.
    """
    directory = Path(directory)
    if not directory.is_dir():
        raise UserError(f"{directory}: no such sweep folder")
    path = directory / "sweep.nc"
    if path.exists():
        try:
            if lazy:
                ds = xr.open_dataset(path, engine="netcdf4")
                lazy_ds = strip_encoding(ds)
                # one assignment of them all (one at a time merged the dataset again each time)
                lazy_ds = lazy_ds.assign({name: v.copy(data=read_in_slabs(v.variable))
                                          for name, v in lazy_ds.data_vars.items() if _per_case_values(v)})
                lazy_ds.set_close(ds.close)
                return lazy_ds
            with xr.open_dataset(path, engine="netcdf4") as ds:
                return strip_encoding(ds.load())
        except Exception as exc:  # netCDF4/HDF5 raise OSError, RuntimeError, ValueError
            why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise UserError(f"{path}: cannot read as NetCDF ({why})") from None
    files = sorted((directory / "cases").glob("*.nc"))
    if not files:
        raise UserError(f"{directory}: neither sweep.nc nor any cases/*.nc to report on")
    cases = []
    for f in files:
        try:
            with xr.open_dataset(f, engine="netcdf4") as ds:
                cases.append(strip_encoding(ds.load()))
        except Exception as exc:  # netCDF4/HDF5 raise OSError, RuntimeError, ValueError
            why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise UserError(f"{f}: cannot read as NetCDF ({why})") from None
    # The grid the sweep asked for is in status.json (every case, finished or not): a
    # sweep killed before combining still reports its whole grid and what is missing.
    try:
        status = read_status(directory)
    except UserError:
        status = {}
    asked = [(e, str(e.get("state", "not_run"))) for e in status.values()]
    axes, entries, fixed = grid_from_cases(cases, asked)
    combined, resampled = combine_cases(axes, entries, scalars=fixed)
    combined.attrs = dict(cases[0].attrs)
    note = "; time series linearly interpolated onto a common elapsed_time grid" if resampled else ""
    combined.attrs["history"] = (str(combined.attrs.get("history", "")).rstrip("\n") + "\n" + history_line(
        f"pipeline.analysis.metrics.open_results: combined {len(files)} case files{note}")).lstrip("\n")
    return combined


def case_states(sweep: xr.Dataset) -> xr.DataArray:
    """Case status over the grid as names (``"ok"``, ``"failed"``, ``"not_run"``, ``"no_data"``).

    ``case_status`` flags are read with their ``flag_meanings``; a case flagged ok whose
    displacement metrics are all NaN is reported as ``"no_data"``; without ``case_status``,
    a case is ok when it has data and ``"not_run"`` otherwise.
    """
    has = None
    for name in _DISPLACEMENT_METRICS:
        if name in sweep:
            v = sweep[name].notnull().any("phase")
            has = v if has is None else (has | v)
    if has is None:
        raise UserError("the sweep holds none of the phase-metric variables "
                        f"({', '.join(_DISPLACEMENT_METRICS)})")
    if "case_status" in sweep:
        cs = sweep["case_status"]
        meanings = str(cs.attrs.get("flag_meanings", " ".join(CASE_STATUS))).split()
        values = np.asarray(cs.attrs.get("flag_values", np.arange(len(meanings)))).ravel().tolist()
        lookup = {int(v): m for v, m in zip(values, meanings)}
        names = np.vectorize(lambda v: lookup.get(int(v), f"flag_{int(v)}") if np.isfinite(v) else "not_run",
                             otypes=[object])(cs.values.astype(float))
        st = xr.DataArray(names, dims=cs.dims, coords=cs.coords)
        st, has = xr.broadcast(st, has)
    else:
        st = xr.DataArray(np.where(has.values, "ok", "not_run").astype(object), dims=has.dims, coords=has.coords)
    st = st.where(~((st == "ok") & ~has), "no_data")
    return st.transpose(*has.dims)


def phase_metrics(sweep: xr.Dataset) -> xr.Dataset:
    """The ``metrics.nc`` dataset of a combined sweep.

    Parameters
    ----------
    sweep : xarray.Dataset
        ``sweep.nc`` content: the phase-metric variables over ``(speed, radial_load,
        phase)`` (plus extra dimensions), coordinate ``speed`` [degree s-1] and
        ``radial_load`` [N].

    Returns
    -------
    xarray.Dataset
        Dims ``(speed, radial_load, [extra...], phase)``: every phase metric present with
        its CF ``units``/``long_name``, the derived ``epicyclic_cage_speed`` [rad s-1] and
        ``case_status`` (int8 flags ok/failed/not_run), and, where the sweep holds them,
        the designer's phase metrics (:data:`DESIGNER_METRICS`) and the per-case scalars
        (:data:`SCALARS`: stiffness and rating lives) over the sweep axes (no ``phase``). The ``phase`` coordinate is the int8 flag coordinate of
        :func:`pipeline.io.case.phase_coordinate`.

    Notes
    -----
    ``cage_slip = 1 − ω̄_c/ω_epi`` (the core's definition), so the epicyclic cage speed the
    slip was measured against is ``ω_epi = ω̄_c/(1 − cage_slip)``; it is NaN where the
    slip is 1 (cage at rest) or missing.
    """
    for axis in ("speed", "radial_load"):
        if axis not in sweep.dims:
            raise UserError(f"the sweep has no '{axis}' dimension (dims: {', '.join(map(str, sweep.dims))})")
    if "phase" not in sweep.dims:
        raise UserError("the sweep has no 'phase' dimension: no phase metrics to report")
    present = [m for m in METRICS if m in sweep.data_vars]
    if not any(m in present for m in _DISPLACEMENT_METRICS):
        raise UserError("the sweep holds none of the phase-metric variables "
                        f"({', '.join(_DISPLACEMENT_METRICS)})")
    extra = [d for d in sweep.dims if d not in ("speed", "radial_load", "phase", "elapsed_time", "sensor", "row")]
    order = ["speed", "radial_load", *extra, "phase"]
    data = {}
    def carried(name: str, units: str, long_name: str) -> xr.DataArray:
        """``sweep[name]`` in ``order``, float64, with its own units/long_name or these."""
        da = sweep[name]
        da = da.transpose(*[d for d in order if d in da.dims], *[d for d in da.dims if d not in order])
        return xr.DataArray(np.asarray(da.values, dtype=np.float64), dims=da.dims,
                            attrs={"units": str(da.attrs.get("units", units)),
                                   "long_name": str(da.attrs.get("long_name", long_name))})

    for name in present:
        _, units, long_name = VARIABLES[name]
        data[name] = carried(name, units, long_name)
        data[name].attrs.update(units=units, long_name=long_name)   # the schema's own, as before
    for name, (units, long_name) in DESIGNER_METRICS.items():
        if name in sweep.data_vars and name not in data and "phase" in sweep[name].dims:
            data[name] = carried(name, *(VARIABLES[name][1:] if name in VARIABLES else (units, long_name)))
    for name, (units, long_name) in SCALARS.items():
        if name not in sweep.data_vars or "phase" in sweep[name].dims:
            continue
        data[name] = carried(name, units, long_name)
    if REALIZATION in sweep.dims:
        data.update(ensemble_statistics(data))
    coords = {}
    for c in order:
        if c == "phase":
            continue
        coords[c] = (c, np.asarray(sweep[c].values), dict(sweep[c].attrs))
    coords["speed"][2].setdefault("units", "degree s-1")
    coords["speed"][2].setdefault("long_name", "steady inner-ring speed")
    coords["radial_load"][2].setdefault("units", "N")
    coords["radial_load"][2].setdefault("long_name", "steady radial load")
    pc = phase_coordinate()
    if sweep.sizes["phase"] != pc.size:
        raise UserError(f"the sweep has {sweep.sizes['phase']} phases; expected {pc.size} ({', '.join(PHASES)})")
    coords["phase"] = pc
    for name, c in sweep.coords.items():
        if name not in coords and (c.ndim == 0 or c.dims in (("sensor",), ("row",))):
            coords[name] = (c.dims, c.values, dict(c.attrs))
    ds = xr.Dataset(data, coords=coords)
    states = case_states(sweep)
    states = states.transpose(*[d for d in order if d in states.dims])
    codes = {s: i for i, s in enumerate(CASE_STATUS)}
    status = np.vectorize(lambda s: codes.get(s, codes["not_run"]), otypes=[np.int8])(states.values)
    ds["case_status"] = case_status_variable(status.astype(np.int8), states.dims)
    ds.attrs = {k: v for k, v in sweep.attrs.items()}
    ds.attrs["Conventions"] = "CF-1.8"
    ds.attrs["title"] = (f"RV main-bearing phase metrics: {sweep.attrs.get('bearing', '') or 'unnamed bearing'}, "
                         f"{sweep.attrs.get('profile', '') or 'unnamed'} cycle, {sweep.sizes['speed']} speeds x "
                         f"{sweep.sizes['radial_load']} radial loads")
    ds.attrs["history"] = (str(sweep.attrs.get("history", "")).rstrip("\n")
                           + "\n" + history_line("pipeline.analysis.metrics.phase_metrics")).lstrip("\n")
    ds.attrs["comment"] = ("Range, mean and standard deviation of delta_r and delta_a (ring centre) and of "
                           "each virtual sensor per phase, with the times of the extremes and a flag where an "
                           "extreme lies within one output interval of the window's edge, from the core's phase "
                           "accumulators (every integrator step); with realizations, the ensemble mean and "
                           "standard error over the random starts; missing or failed cases are NaN "
                           "(see case_status)."
                           + (" Radial, axial and tilting stiffness: the direct terms of the quasi-static "
                              "tangent stiffness at the loads in the middle of the steady phase, one per case."
                              if any(n in ds for n in STIFFNESS) else "")
                           + (" Designer outputs: drive torque, friction, cage forces, race sliding and pv, "
                              "contact angles, static safety factor (ISO 76) and fatigue damage per phase; "
                              "rating lives (ISO/TS 16281, ISO 281) per case, in revolutions of the inner ring."
                              if any(n in ds for n in (*DESIGNER_METRICS, *DESIGNER_SCALARS)) else ""))
    return ds


def ensemble_statistics(data: dict) -> dict:
    """Ensemble mean and standard error over ``realization`` of :data:`ENSEMBLE_METRICS`.

    ``M_ensemble_mean = mean_k M_k`` and ``M_ensemble_stderr = s/√n`` with ``s`` the sample
    standard deviation (ddof 1) of the n finite realizations; NaN where n < 2. Plus
    ``M_at_edge_fraction``: the fraction of realizations whose range is flagged at the
    window's edge.
    """
    out = {}
    for name in ENSEMBLE_METRICS:
        if name not in data or REALIZATION not in data[name].dims:
            continue
        da = data[name]
        n = da.notnull().sum(REALIZATION)
        mean = da.mean(REALIZATION, skipna=True)
        se = (da.std(REALIZATION, ddof=1, skipna=True) / np.sqrt(n)).where(n >= 2)
        units = da.attrs.get("units", "m")
        what = da.attrs.get("long_name", name)
        out[f"{name}_ensemble_mean"] = mean.assign_attrs(units=units, long_name=f"ensemble mean over realizations of: {what}")
        out[f"{name}_ensemble_stderr"] = se.assign_attrs(
            units=units, long_name=f"standard error of the ensemble mean over realizations of: {what}")
        flag = name.replace("_range", "_range_at_edge")
        if name.endswith("_range") and flag in data:
            out[f"{flag}_fraction"] = data[flag].mean(REALIZATION, skipna=True).assign_attrs(
                units="1", long_name=f"fraction of realizations whose {name} has an extreme at the window's edge")
    return out


def write_metrics(metrics: xr.Dataset, path) -> None:
    """Write ``metrics.nc`` atomically (netCDF4, zlib, float64, no ``_FillValue`` on coordinates)."""
    write_atomic(strip_encoding(metrics), path)


def nearest(values, target: float) -> float:
    """The element of ``values`` nearest to ``target`` (first on ties); NaN if empty."""
    values = np.asarray(values, dtype=np.float64)
    if values.size == 0 or not math.isfinite(target):
        return math.nan
    return float(values[int(np.argmin(np.abs(values - target)))])
