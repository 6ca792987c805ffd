"""The one place where case files become a combined sweep (``sweep.nc``'s variables).

:func:`combine_cases` lays case datasets on a grid of sweep axes: the time series over
``(<case dims>, elapsed_time[, sensor])``, the phase metrics over ``(<case dims>,
phase[, sensor])``, NaN where a grid point has no finished case, and the int8
``case_status`` flags (0 ok, 1 failed, 2 not_run). Both the sweep runner (with the grid
of the sweep file, :func:`pipeline.run.runner.write_combined_sweep`) and the analysis of a sweep
folder without ``sweep.nc`` (with the grid read off the case files,
:func:`grid_from_cases`) use it.
"""
from __future__ import annotations

import contextlib
import math
import multiprocessing
import os
from collections import deque
from dataclasses import dataclass

import numpy as np
import xarray as xr

from .case import PER_ROW, VARIABLES, phase_coordinate
from .netcdf import CASE_STATUS, case_status_variable

#: ``comment`` of a time series that was interpolated onto the common time grid.
RESAMPLED_COMMENT = ("linearly interpolated from each case's own output samples (cases/<id>.nc) "
                     "onto the common elapsed_time grid; NaN outside a case's simulated window")

#: Axes read off case files when there is no sweep file, in this order; the first two
#: are always dimensions, the others only when they vary between the files.
CASE_FILE_AXES = ("speed", "radial_load", "axial_load", "realization")


@dataclass
class GridAxis:
    """One dimension of the combined grid.

    ``values`` are the keys a case's position is looked up by (sorted), ``coord`` the
    labelled coordinate written for them (same length).
    """

    name: str
    values: list
    coord: xr.DataArray

    def index(self, value) -> int:
        return self.values.index(value)


@dataclass
class CaseEntry:
    """One grid point: its position, its dataset or file (None when no file) and its state."""

    at: tuple
    data: xr.Dataset | None = None
    state: str = "not_run"
    #: its case file, for :func:`write_streamed` (which reads it when it writes its slab)
    path: object = None


def common_time_grid(times, output_rate: float) -> np.ndarray:
    """A shared ``elapsed_time`` grid [s] for cases whose sample times differ.

    Parameters
    ----------
    times : sequence of ndarray
        Each case's sample times [s].
    output_rate : float
        Samples per second [Hz].

    Notes
    -----
    ``t_k = t_0 + k / f`` for ``k = 0 … floor((t_1 − t_0)·f + 1e-9)``, with ``t_0`` the
    earliest first sample and ``t_1`` the latest last one. The integrator writes every
    m-th step of its own step ``Δt``, so a case's samples are ``m·Δt`` apart rather
    than exactly ``1/f``, and ``Δt`` differs between cases.
    """
    t0 = min(float(t[0]) for t in times if len(t))
    t1 = max(float(t[-1]) for t in times if len(t))
    n = int(math.floor((t1 - t0) * output_rate + 1e-9))
    return t0 + np.arange(n + 1, dtype=np.float64) / output_rate


def _sample_rate(times) -> float:
    """The highest sample rate of the cases [Hz] (used when no output rate is given)."""
    steps = [float(np.median(np.diff(t))) for t in times if len(t) > 1]
    return 1.0 / min(steps) if steps else 1.0


def combine_cases(axes, entries, *, output_rate: float | None = None, scalars=None):
    """Lay case datasets on the grid of ``axes``.

    Parameters
    ----------
    axes : sequence of GridAxis
        The case dimensions, in order.
    entries : sequence of CaseEntry
        One per case: position on the grid, dataset (None when it has no file) and
        state ('failed' marks a point without data as failed; otherwise not_run).
    output_rate : float, optional
        Samples per second [Hz] of the common time grid, when the cases' sample times
        differ; default the highest rate of the cases.
    scalars : dict, optional
        Scalar coordinates (name -> DataArray), such as the fixed axial load.

    Returns
    -------
    ds : xarray.Dataset
        Data variables (with the case files' attributes), ``case_status``, the grid
        coordinates, ``phase``, ``elapsed_time`` and the sensor coordinates; no global
        attributes.
    resampled : bool
        True when the time series were interpolated onto :func:`common_time_grid`.

    Notes
    -----
    When every case has the same sample times they are ``elapsed_time``; otherwise the
    series are interpolated linearly onto the common grid (their ``comment`` says so).
    The phase metrics are never resampled: they come from every integrator step.
    """
    axes = list(axes)
    loaded = [e.data for e in entries if e.data is not None]
    shape = tuple(len(a.values) for a in axes)
    times = [ds["elapsed_time"].values for ds in loaded]
    resampled = False
    if times and all(t.shape == times[0].shape and np.array_equal(t, times[0]) for t in times):
        elapsed = times[0]
    elif times:
        elapsed = common_time_grid(times, output_rate or _sample_rate(times))
        resampled = True
    else:
        elapsed = np.zeros(0)
    n_t, n_p = len(elapsed), len(phase_coordinate())

    # every case of a sweep has the same sensors: the first case file labels them
    sensor_case = next((ds for ds in loaded if "sensor" in ds.dims), None)
    n_s = sensor_case.sizes["sensor"] if sensor_case is not None else 0
    # a bearing of several rows gives its cage variables (case.PER_ROW) a trailing row
    # dimension; every case of a sweep has the same rows, so the first such file labels it
    row_case = next((ds for ds in loaded if "row" in ds.dims), None)
    n_r = row_case.sizes["row"] if row_case is not None else 0
    # the steady phase's spectra (same window and rate in every case of a sweep)
    freq_case = next((ds for ds in loaded if "frequency" in ds.dims), None)
    n_f = freq_case.sizes["frequency"] if freq_case is not None else 0
    sizes = {"elapsed_time": n_t, "phase": n_p, "sensor": n_s, "row": n_r, "frequency": n_f,
             "kinematic": freq_case.sizes["kinematic"] if freq_case is not None else 0}
    dims_of = {k: dims + (("row",) if n_r and k in PER_ROW else ()) for k, (dims, _, _) in VARIABLES.items()}
    arrays = {k: np.full(shape + tuple(sizes[d] for d in dims), np.nan) for k, dims in dims_of.items()
              if all(sizes[d] for d in dims)}
    status = np.full(shape, CASE_STATUS.index("not_run"), dtype=np.int8)
    for entry in entries:
        ds = entry.data
        if ds is None:
            if entry.state == "failed":
                status[entry.at] = CASE_STATUS.index("failed")
            continue
        status[entry.at] = CASE_STATUS.index("ok")
        t = ds["elapsed_time"].values
        same_spectrum = freq_case is not None and "frequency" in ds.dims and np.array_equal(
            ds["frequency"].values, freq_case["frequency"].values)
        for k, arr in arrays.items():
            if k not in ds:
                continue
            if "frequency" in dims_of[k] and not same_spectrum:   # another window or rate: left NaN
                continue
            v = ds[k].transpose(*dims_of[k]).values
            if resampled and VARIABLES[k][0][:1] == ("elapsed_time",):
                v = np.stack([np.interp(elapsed, t, col, left=np.nan, right=np.nan)
                              for col in v.reshape(len(t), -1).T], axis=-1).reshape((n_t,) + v.shape[1:])
            arr[entry.at] = v

    case_dims = tuple(a.name for a in axes)
    coords = {a.name: a.coord for a in axes}
    coords["phase"] = phase_coordinate()
    if n_t:
        coords["elapsed_time"] = xr.DataArray(
            np.asarray(elapsed, dtype=np.float64), dims="elapsed_time",
            attrs={"units": "s", "long_name": "simulated time since the start of the cycle"})
    coords.update(scalars or {})
    if row_case is not None:
        coords["row"] = xr.DataArray(row_case["row"].values, dims="row", attrs=dict(row_case["row"].attrs))
    if freq_case is not None:
        for name in ("frequency", "kinematic"):
            c = freq_case[name]
            coords[name] = xr.DataArray(c.values, dims=name, attrs=dict(c.attrs))
    if sensor_case is not None:
        for name, c in sensor_case.coords.items():
            if c.dims == ("sensor",):
                coords[name] = xr.DataArray(c.values, dims="sensor", attrs=dict(c.attrs))
    data = {}
    for k, arr in arrays.items():
        attrs = _attrs_of(k, loaded)
        if resampled and VARIABLES[k][0][:1] == ("elapsed_time",):
            attrs["comment"] = RESAMPLED_COMMENT
        data[k] = xr.DataArray(arr, dims=case_dims + dims_of[k], attrs=attrs)
    data["case_status"] = case_status_variable(status, case_dims)
    return xr.Dataset(data_vars=data, coords=coords), resampled


def _attrs_of(name: str, loaded) -> dict:
    """A variable's attributes: those of the first case file that has it, else the defaults."""
    for ds in loaded:
        if name in ds:
            return dict(ds[name].attrs)
    _, units, long_name = VARIABLES[name]
    return {"units": units, "long_name": long_name}


def _case_file_value(key: str, value):
    """A ``status.json`` value (SI, as in ``CaseSpec.point``) as the case files' coordinate
    holds it: speed in degree s-1 to 12 significant digits, the seed as a whole number."""
    if key == "speed":
        return float(f"{math.degrees(float(value)):.12g}")
    if key == "realization":
        return int(value)
    return float(value)


def grid_from_cases(cases, asked=()) -> tuple:
    """The grid of a set of case datasets, read off their scalar coordinates.

    ``speed`` and ``radial_load`` are always dimensions, ``axial_load`` and
    ``realization`` when they vary (:data:`CASE_FILE_AXES`); each coordinate keeps the
    case files' attributes.

    Parameters
    ----------
    cases : sequence of xarray.Dataset
        The finished case files.
    asked : sequence of (dict, str)
        Every case the sweep asked for, as ``(point, state)`` with ``point`` its
        ``status.json`` values (SI) and ``state`` its recorded state: the grid then spans
        them all, and an asked point without a case file is an entry without data (its
        state 'failed', or 'not_run'). Without it the grid spans only the finished cases.

    Returns
    -------
    axes : list of GridAxis
    entries : list of CaseEntry
        One per case, in the order given, state 'ok'; then one per asked point without
        a case.
    fixed : dict
        name -> scalar coordinate of the axes that do not vary (``realization``
        excepted, as in a sweep's ``sweep.nc``).
    """
    asked_points = []
    for point, state in asked:
        try:
            asked_points.append(({k: _case_file_value(k, point[k]) for k in CASE_FILE_AXES if k in point},
                                 state))
        except (TypeError, ValueError):
            continue
    axes, fixed = [], {}
    for i, key in enumerate(CASE_FILE_AXES):
        present = [c for c in cases if key in c.coords]
        if not present:
            continue
        values = sorted({c[key].item() for c in present} | {p[key] for p, _ in asked_points if key in p})
        template = present[0][key]
        if i < 2 or len(values) > 1:
            coord = xr.DataArray(np.asarray(values, dtype=template.dtype), dims=key, attrs=dict(template.attrs))
            axes.append(GridAxis(key, values, coord))
        elif key != "realization":
            fixed[key] = xr.DataArray(template.values, attrs=dict(template.attrs))
    entries = [CaseEntry(tuple(a.index(c[a.name].item()) for a in axes), c, "ok") for c in cases]
    taken = {e.at for e in entries}
    for point, state in asked_points:
        if not all(a.name in point for a in axes):
            continue
        at = tuple(a.index(point[a.name]) for a in axes)
        if at not in taken:
            taken.add(at)
            entries.append(CaseEntry(at, None, "failed" if state == "failed" else "not_run"))
    return axes, entries, fixed


# --------------------------------------------------------------------------- streaming


class CaseFileError(Exception):
    """A case file that cannot be read while combining: ``path`` and the first line of why."""

    def __init__(self, path, why: str):
        super().__init__(f"{path}: {why}")
        self.path, self.why = path, why


#: Attributes netCDF4 shows that xarray moves into ``encoding`` when it reads a file.
_ENCODING_ATTRS = ("coordinates", "_FillValue", "missing_value")


def _nc_attrs(var) -> dict:
    return {k: var.getncattr(k) for k in var.ncattrs() if k not in _ENCODING_ATTRS}


@dataclass
class CaseScan:
    """What the combined grid needs to know of its case files, gathered one file at a time
    in memory bounded by one case (:func:`scan_case_files`).

    ``times`` are the first file's sample times [s]; ``same_times`` whether every file has
    them; ``t_first``/``t_last`` the earliest first and latest last sample [s];
    ``min_step`` the smallest median sample spacing [s]; ``sensor``/``row``/``spectrum``
    the coordinates (name -> (values, attrs)) of the first file with that dimension;
    ``attrs`` each variable's attributes from the first file that has it; ``global_attrs``
    the first file's global attributes.
    """

    n_files: int = 0
    times: np.ndarray | None = None
    same_times: bool = True
    t_first: float = math.inf
    t_last: float = -math.inf
    min_step: float = math.inf
    sensor: dict | None = None
    row: dict | None = None
    spectrum: dict | None = None
    attrs: dict = None
    global_attrs: dict = None
    #: a scan of the first file only (:func:`first_file_scan`): the write checks that every
    #: other file agrees with it (:class:`NeedsFullScan` otherwise)
    partial: bool = False
    names: frozenset = frozenset()
    dims: frozenset = frozenset()

    def elapsed(self, output_rate: float | None):
        """``(elapsed_time [s], resampled)`` as :func:`combine_cases` chooses them."""
        if not self.n_files:
            return np.zeros(0), False
        if self.same_times:
            return self.times, False
        rate = output_rate or (1.0 / self.min_step if math.isfinite(self.min_step) else 1.0)
        n = int(math.floor((self.t_last - self.t_first) * rate + 1e-9))
        return self.t_first + np.arange(n + 1, dtype=np.float64) / rate, True


def _coords_over(nc, dim: str) -> dict:
    """name -> (values, attrs) of the variables of ``nc`` over ``(dim,)`` alone, in file order."""
    return {name: (np.asarray(v[...]), _nc_attrs(v)) for name, v in nc.variables.items()
            if v.dimensions == (dim,)}


def scan_case_files(paths) -> CaseScan:
    """Scan case files, one open at a time, for what the combined grid needs (:class:`CaseScan`).

    Raises
    ------
    CaseFileError
        For the first file that cannot be read.
    """
    import netCDF4

    scan = CaseScan(attrs={}, global_attrs={})
    for path in paths:
        try:
            with netCDF4.Dataset(path, "r") as nc:
                nc.set_auto_mask(False)
                t = np.asarray(nc.variables["elapsed_time"][...], dtype=np.float64)
                if scan.n_files == 0:
                    scan.times = t
                    scan.global_attrs = {k: nc.getncattr(k) for k in nc.ncattrs()}
                elif scan.same_times and not (t.shape == scan.times.shape and np.array_equal(t, scan.times)):
                    scan.same_times = False
                if len(t):
                    scan.t_first = min(scan.t_first, float(t[0]))
                    scan.t_last = max(scan.t_last, float(t[-1]))
                if len(t) > 1:
                    scan.min_step = min(scan.min_step, float(np.median(np.diff(t))))
                dims = nc.dimensions
                scan.names |= frozenset(nc.variables)
                scan.dims |= frozenset(dims)
                if scan.sensor is None and "sensor" in dims:
                    scan.sensor = {k: c for k, c in _coords_over(nc, "sensor").items() if k not in VARIABLES}
                if scan.row is None and "row" in dims:
                    scan.row = {"row": _coords_over(nc, "row")["row"]}
                if scan.spectrum is None and "frequency" in dims:
                    scan.spectrum = {"frequency": _coords_over(nc, "frequency")["frequency"],
                                     "kinematic": _coords_over(nc, "kinematic")["kinematic"]}
                for name in VARIABLES:
                    if name not in scan.attrs and name in nc.variables:
                        scan.attrs[name] = _nc_attrs(nc.variables[name])
        except Exception as exc:  # netCDF4/HDF5 raise OSError, RuntimeError, KeyError, ...
            raise CaseFileError(path, str(exc).splitlines()[0] if str(exc) else type(exc).__name__) from None
        scan.n_files += 1
    return scan


class NeedsFullScan(Exception):
    """A case file does not agree with the first (other sample times, another variable or
    dimension): the grid needs :func:`scan_case_files` of every file."""


def first_file_scan(paths) -> CaseScan:
    """:func:`scan_case_files` of the first of ``paths`` only, counting them all.

    In a sweep every case usually has the first's sample times and variables; then this
    is the full scan's result, and :func:`write_streamed` opens each file once. It checks
    each file against it and raises :class:`NeedsFullScan` when one differs.
    """
    paths = list(paths)
    scan = scan_case_files(paths[:1])
    scan.n_files, scan.partial = len(paths), True
    return scan


def _placeholder(shape, dtype=np.float64):
    """A lazy array of ``shape`` that is never computed: it declares a variable whose
    data :func:`write_streamed` writes itself, one case at a time."""
    import dask.array as da

    return da.empty(shape, dtype=dtype, chunks=shape or -1)


#: Bytes of HDF5 chunk cache a combined variable keeps while it is written: a few
#: one-case chunks, so that memory does not grow with the number of cases.
_WRITE_CACHE_CHUNKS = 4


def write_streamed(path, axes, entries, scan: CaseScan, *, output_rate: float | None = None,
                   scalars=None, attrs=None, encoding_of=None) -> bool:
    """Write the combined grid of ``entries`` to the netCDF file ``path``, one case at a time.

    The result is the file that :func:`combine_cases` followed by a write of its dataset
    gives (the same variables, dimensions, coordinates, attributes, chunking and values),
    but no more than one case's data is held at a time: the variables are declared (by
    xarray, so that names, attributes and encodings are those of any write), then each
    case's slab is read from its file (by forked readers, a few cases ahead, where there are
    two CPUs: :func:`_readers`) and written into its one-case chunk (by h5py), in the grid's
    order, so that the file is the same bytes either way. Where
    the case file stores a variable as one chunk of that shape, type and compression (a
    case file of this package), its compressed bytes are copied as they are
    (:func:`_case_slabs`): no inflating and deflating again (the study's 150 case files
    in 4.5 s instead of 9.7; docs/performance.md, "Sweeps at scale").

    Parameters
    ----------
    path : str or Path
        The file to write (a temporary name; the caller renames it) [-].
    axes : sequence of GridAxis
    entries : sequence of CaseEntry
        One per grid point, with ``path`` the case file (None when it has none).
    scan : CaseScan
        :func:`scan_case_files` of the entries' files.
    output_rate : float, optional
        Samples per second of the common time grid when the cases' times differ [Hz].
    scalars : dict, optional
        Scalar coordinates (name -> DataArray).
    attrs : dict, optional
        Global attributes.
    encoding_of : callable, optional
        ``encoding_of(dataset, case_dims) -> dict`` (default :func:`pipeline.io.netcdf.combined_encoding`).

    Returns
    -------
    bool
        Whether the time series were interpolated onto :func:`common_time_grid`.

    Notes
    -----
    A case's time series on the common grid: ``x(t_k) = interp(t_k; t_case, x_case)``,
    NaN outside the case's window, exactly as :func:`combine_cases`.
    """
    import h5py

    from .netcdf import combined_encoding, declare_netcdf

    axes = list(axes)
    shape = tuple(len(a.values) for a in axes)
    elapsed, resampled = scan.elapsed(output_rate)
    n_t, n_p = len(elapsed), len(phase_coordinate())
    n_s = len(scan.sensor["sensor"][0]) if scan.sensor else 0
    n_r = len(scan.row["row"][0]) if scan.row else 0
    n_f = len(scan.spectrum["frequency"][0]) if scan.spectrum else 0
    sizes = {"elapsed_time": n_t, "phase": n_p, "sensor": n_s, "row": n_r, "frequency": n_f,
             "kinematic": len(scan.spectrum["kinematic"][0]) if scan.spectrum else 0}
    dims_of = {k: dims + (("row",) if n_r and k in PER_ROW else ()) for k, (dims, _, _) in VARIABLES.items()}
    kept = [k for k, dims in dims_of.items() if all(sizes[d] for d in dims)]
    status = np.full(shape, CASE_STATUS.index("not_run"), dtype=np.int8)
    for entry in entries:
        if entry.path is not None:
            status[entry.at] = CASE_STATUS.index("ok")
        elif entry.state == "failed":
            status[entry.at] = CASE_STATUS.index("failed")

    case_dims = tuple(a.name for a in axes)
    coords = {a.name: a.coord for a in axes}
    coords["phase"] = phase_coordinate()
    if n_t:
        coords["elapsed_time"] = xr.DataArray(
            np.asarray(elapsed, dtype=np.float64), dims="elapsed_time",
            attrs={"units": "s", "long_name": "simulated time since the start of the cycle"})
    coords.update(scalars or {})
    for group, dim in ((scan.row, "row"), (scan.spectrum, None), (scan.sensor, "sensor")):
        for name, (values, a) in (group or {}).items():
            coords[name] = xr.DataArray(values, dims=dim or name, attrs=dict(a))
    data = {}
    for k in kept:
        a = dict(scan.attrs[k]) if k in scan.attrs else {"units": VARIABLES[k][1], "long_name": VARIABLES[k][2]}
        if resampled and VARIABLES[k][0][:1] == ("elapsed_time",):
            a["comment"] = RESAMPLED_COMMENT
        data[k] = xr.DataArray(_placeholder(shape + tuple(sizes[d] for d in dims_of[k])),
                               dims=case_dims + dims_of[k], attrs=a)
    # written one grid point at a time too: HDF5 holds a written chunk (here one byte) in
    # about 7 kB until the file closes, so a whole write of it grew with the cases
    data["case_status"] = case_status_variable(status, case_dims).copy(data=_placeholder(shape, np.int8))
    layout = xr.Dataset(data_vars=data, coords=coords, attrs=dict(attrs or {}))
    encoding = (encoding_of or combined_encoding)(layout, case_dims)

    declare_netcdf(layout, path, encoding)   # the variables declared, not written
    spectrum_freq = scan.spectrum["frequency"][0] if scan.spectrum else None
    files = {e.at: e.path for e in entries if e.path is not None}
    trailing = {k: tuple(sizes[d] for d in dims_of[k]) for k in kept}
    largest = max([8 * int(np.prod(t)) for t in trailing.values()] + [1])
    with contextlib.ExitStack() as stack:
        # the readers forked before the combined file is opened here (no HDF5 file open in them)
        readers = stack.enter_context(_readers(len(files)))
        out = stack.enter_context(h5py.File(path, "r+", rdcc_nbytes=max(_WRITE_CACHE_CHUNKS * largest, 1 << 16),
                                            rdcc_nslots=521, rdcc_w0=1.0))
        targets = {k: out[k] for k in kept}
        copyable = {k: (_filters(v.id), v.dtype, trailing[k]) for k, v in targets.items()
                    if v.chunks is not None and tuple(v.chunks) == (1,) * len(shape) + trailing[k]
                    and trailing[k]}
        flags = out["case_status"]
        first_keys = _root_names(next(iter(files.values()))) if files and scan.partial else None
        common = (kept, dims_of, elapsed, resampled, spectrum_freq, first_keys, scan if scan.partial else None,
                  copyable)
        # read in the order written: the grid's
        slabs = _read_ahead(readers, ((files[at],) + common for at in np.ndindex(*shape) if at in files))
        for at in np.ndindex(*shape):   # every grid point, asked or not: each chunk written once
            case = next(slabs) if at in files else {}
            for k, var in targets.items():
                v = case.get(k)
                if isinstance(v, _RawChunk):
                    var.id.write_direct_chunk(at + (0,) * len(trailing[k]), v.data, v.filter_mask)
                    continue
                var[at] = np.full(trailing[k], np.nan) if v is None else v
            flags[at] = status[at]
    return resampled


#: Case files read ahead of the writer per reading process: what the parent holds at most
#: is this many cases' slabs a reader, whatever the number of cases.
_READ_AHEAD = 2

#: The most processes that read case files while :func:`write_streamed` writes (one a CPU;
#: the combine's writer is the parent, so more do not pay on a few cores).
MAX_READERS = 2


@contextlib.contextmanager
def _readers(n_files: int):
    """Processes that read case files for :func:`write_streamed` while it writes: forked,
    one a CPU, at most :data:`MAX_READERS`; None where the platform does not fork, there
    are fewer than two, or there are few files.

    On the study's 150 case files on the project's 2-core machine, the combine took
    3.8-4.1 s against 6.7-7.1 s reading them here (2026-11-29): a file's read, 35 ms, is
    most of the combine, its write into ``sweep.nc`` about 12 ms."""
    from concurrent.futures import ProcessPoolExecutor

    n = min(MAX_READERS, os.cpu_count() or 1)
    if n < 2 or n_files < 8 or "fork" not in multiprocessing.get_all_start_methods():
        yield None
        return
    pool = ProcessPoolExecutor(n, mp_context=multiprocessing.get_context("fork"))
    try:
        # every reader forked now, before the caller opens a file (a fork starts them all at
        # the first task)
        pool.submit(int).result()
        yield pool
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _slabs_or_error(args):
    """:func:`_case_slabs` in a reader: its slabs, or the error to raise in the parent (a
    :class:`CaseFileError` or :class:`NeedsFullScan` by its arguments, which pickle)."""
    try:
        return _case_slabs(*args), None
    except NeedsFullScan as exc:
        return None, ("full", str(exc), "")
    except CaseFileError as exc:
        return None, ("file", exc.path, exc.why)


def _raise(error):
    kind, path, why = error
    if kind == "full":
        raise NeedsFullScan(path)
    raise CaseFileError(path, why)


def _read_ahead(readers, jobs):
    """:func:`_case_slabs` of each of ``jobs`` (its arguments), in order: read in ``readers``
    up to :data:`_READ_AHEAD` a reader ahead, or here one at a time when there are none.
    A reader that dies leaves the rest to this process."""
    from concurrent.futures.process import BrokenProcessPool

    jobs = iter(jobs)
    if readers is None:
        for args in jobs:
            yield _case_slabs(*args)
        return
    window = deque()    # (args, its future, or None where the pool broke before it was sent)

    def fill():
        while len(window) < _READ_AHEAD * MAX_READERS and (not window or window[-1][1] is not None):
            args = next(jobs, None)
            if args is None:
                return
            try:
                window.append((args, readers.submit(_slabs_or_error, args)))
            except BrokenProcessPool:   # a reader died since the last result was taken
                window.append((args, None))

    fill()
    while window:
        args, future = window.popleft()
        try:
            if future is None:
                raise BrokenProcessPool("a reader died before this file was sent")
            case, error = future.result()
        except BrokenProcessPool:
            for args in [args] + [a for a, _ in window] + list(jobs):
                yield _case_slabs(*args)
            return
        if error is not None:
            _raise(error)
        fill()
        yield case


@dataclass
class _RawChunk:
    """A case variable's one chunk as stored (compressed), to be written unchanged into its
    combined variable's one-case chunk (the same shape, type and filters)."""

    data: bytes
    filter_mask: int


def _filters(dataset_id) -> tuple:
    """The HDF5 filter pipeline of a dataset (its h5py ``DatasetID``): ((filter id, flags,
    parameters), …)."""
    plist = dataset_id.get_create_plist()
    return tuple(plist.get_filter(i)[:3] for i in range(plist.get_nfilters()))


def _root_names(path) -> frozenset:
    """The names of the HDF5 datasets at the root of a netCDF-4 file (its variables and
    dimensions)."""
    import h5py

    with h5py.File(path, "r") as f:
        return frozenset(f.keys())


def _int_attribute(object_id, name: bytes):
    """An integer attribute of an HDF5 object as a tuple, or None where it has none."""
    from h5py import h5a

    if not h5a.exists(object_id, name):
        return None
    attr = h5a.open(object_id, name)
    values = np.empty(attr.shape, dtype=attr.dtype)
    attr.read(values)
    return tuple(int(x) for x in np.atleast_1d(values))


def _dimension_names(f, dataset_id, dim_ids) -> tuple:
    """The netCDF dimensions of a variable of the netCDF-4 file ``f`` (h5py), in order: its
    ``_Netcdf4Coordinates`` (dimension ids) named by ``dim_ids`` (id -> name, from the
    dimensions' ``_Netcdf4Dimid``), else its HDF5 dimension scales (``DIMENSION_LIST``,
    slower); () for a scalar."""
    if dataset_id.rank == 0:
        return ()
    ids = _int_attribute(dataset_id, b"_Netcdf4Coordinates")
    if ids is not None and len(ids) == dataset_id.rank and all(i in dim_ids for i in ids):
        return tuple(dim_ids[i] for i in ids)
    import h5py

    refs = h5py.Dataset(dataset_id).attrs["DIMENSION_LIST"]
    return tuple(f[r[0]].name.lstrip("/") for r in refs)


def _case_slabs(path, names, dims_of, elapsed, resampled, spectrum_freq, first_keys=None,
                first=None, copyable=None) -> dict:
    """name -> the case's array in the combined variable's trailing dims (on the common
    time grid when ``resampled``), or its :class:`_RawChunk` where the stored chunk can be
    copied as it is; absent when the file lacks it or its spectrum differs.

    A chunk is copied where ``copyable`` (name -> (filters, dtype, one case's shape) of the
    combined variable whose chunks hold one case) has the name, and the case's variable is one chunk of the
    combined chunk's shape and the same type, filters and dimension order, not packed
    (``scale_factor``/``add_offset``) and not resampled: its bytes then decode to the very
    values a write of the array would store. Any other variable is read, reordered (and
    resampled) as an array, the values as stored (netCDF4 with its mask off reads the same).

    With ``first`` (a :func:`first_file_scan`) and ``first_keys`` (the datasets at the
    first file's root), raises :class:`NeedsFullScan` when the file has other sample
    times, or a variable or dimension the first file has not."""
    import h5py
    from h5py import h5a, h5d

    out = {}
    copyable = copyable or {}
    try:
        with h5py.File(path, "r") as nc:
            present = frozenset(nc.keys())
            t = np.asarray(nc["elapsed_time"][()], dtype=np.float64)
            if first is not None and not (t.shape == first.times.shape and np.array_equal(t, first.times)
                                          and (first_keys is None or present <= first_keys)):
                raise NeedsFullScan(str(path))
            same_spectrum = (spectrum_freq is not None and "frequency" in present
                             and np.array_equal(np.asarray(nc["frequency"][()]), spectrum_freq))
            fid = nc.id
            dim_ids = {}
            for d in {d for k in names for d in dims_of[k]} & present:
                i = _int_attribute(h5d.open(fid, d.encode()), b"_Netcdf4Dimid")
                if i is not None and len(i) == 1:
                    dim_ids[i[0]] = d
            for k in names:
                if k not in present:
                    continue
                if "frequency" in dims_of[k] and not same_spectrum:   # another window or rate: left NaN
                    continue
                var = h5d.open(fid, k.encode())
                packed = h5a.exists(var, b"scale_factor") or h5a.exists(var, b"add_offset")
                series = resampled and VARIABLES[k][0][:1] == ("elapsed_time",)
                dims = _dimension_names(nc, var, dim_ids)
                if (k in copyable and not packed and not series and dims == dims_of[k]
                        and var.dtype == copyable[k][1] and var.shape == copyable[k][2]):
                    plist = var.get_create_plist()
                    if (plist.get_layout() == h5d.CHUNKED and plist.get_chunk() == var.shape
                            and _filters(var) == copyable[k][0]):
                        mask, data = var.read_direct_chunk((0,) * var.rank)
                        out[k] = _RawChunk(data, mask)
                        continue
                dataset = h5py.Dataset(var)
                v = dataset[()]
                if packed:
                    v = v * dataset.attrs.get("scale_factor", 1.0) + dataset.attrs.get("add_offset", 0.0)
                v = np.asarray(v, dtype=np.float64)
                order = [dims.index(d) for d in dims_of[k]]
                v = np.transpose(v, order) if order != sorted(order) else v
                if series:
                    v = np.stack([np.interp(elapsed, t, col, left=np.nan, right=np.nan)
                                  for col in v.reshape(len(t), -1).T], axis=-1).reshape((len(elapsed),) + v.shape[1:])
                out[k] = v
    except NeedsFullScan:
        raise
    except Exception as exc:  # h5py/HDF5 raise OSError, KeyError, ValueError, ...
        raise CaseFileError(path, str(exc).splitlines()[0] if str(exc) else type(exc).__name__) from None
    return out
