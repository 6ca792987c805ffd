"""Shared NetCDF conventions: names, encodings and the case-status flags.

Files are written by :mod:`pipeline.io.files` (atomic replacement).

The conventions (docs/outputs.md, "NetCDF conventions"): CF-1.8, UDUNITS unit strings, no
``_FillValue`` on coordinates, zlib compression, one case per chunk, float64 data, the
netCDF4 engine. The UDUNITS spelling of every unit comes from :mod:`pipeline.schema.units`.
"""
from __future__ import annotations

import re

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:   # xarray is imported where it is used: `rvsweep check` reads cf_name only
    import xarray as xr

#: Flag values and meanings of the ``case_status`` variable of a combined sweep.
CASE_STATUS = ("ok", "failed", "not_run")

_CF_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def cf_name(key: str) -> str:
    """A CF-valid variable name for a sweep-axis key.

    CF names start with a letter and hold only letters, digits and underscores, so
    ``"friction.mu_static"`` becomes ``"friction_mu_static"`` and
    ``"rows[0].cage.pocket_clearance"`` becomes ``"rows_0_cage_pocket_clearance"``.
    """
    name = re.sub(r"[^A-Za-z0-9_]+", "_", key).strip("_")
    name = re.sub(r"_+", "_", name)
    if not name or not name[0].isalpha():
        name = "axis_" + name
    assert _CF_NAME.match(name), name
    return name


def combined_encoding(ds: xr.Dataset, case_dims, *, complevel: int = 4) -> dict:
    """Encoding of a combined sweep: zlib, one case per chunk, float64, no coordinate fill.

    Parameters
    ----------
    ds : xarray.Dataset
        The combined sweep [-].
    case_dims : sequence of str
        The dimensions that index cases (``speed``, ``radial_load`` and any extra axes);
        a chunk holds one index along each of them and the whole extent of the others
        (``elapsed_time`` or ``phase``), i.e. exactly one case.
    complevel : int
        zlib level [-].
    """
    case_dims = set(case_dims)
    enc = {}
    for name, var in ds.variables.items():
        if name in ds.coords:
            enc[name] = {"_FillValue": None}
            continue
        e = {"zlib": True, "complevel": complevel, "_FillValue": None}
        if var.dtype.kind == "f":
            e["dtype"] = "float64"
        if var.ndim:
            e["chunksizes"] = tuple(1 if d in case_dims else n for d, n in zip(var.dims, var.shape))
        enc[name] = e
    return enc


def encoding_for(ds: xr.Dataset, *, complevel: int = 4) -> dict:
    """netCDF4 encoding: zlib on data, no ``_FillValue`` on coordinates, float64 data, one chunk."""
    return combined_encoding(ds, (), complevel=complevel)


def case_status_variable(codes: np.ndarray, dims) -> xr.DataArray:
    """The int8 ``case_status`` flag variable over the grid (0 ok, 1 failed, 2 not_run)."""
    import xarray as xr

    return xr.DataArray(
        np.asarray(codes, dtype=np.int8), dims=tuple(dims),
        attrs={"long_name": "outcome of the case at this grid point",
               "flag_values": np.arange(len(CASE_STATUS), dtype=np.int8),
               "flag_meanings": " ".join(CASE_STATUS)},
    )


def strip_encoding(ds: xr.Dataset) -> xr.Dataset:
    """A shallow copy of ``ds`` without the on-disk encoding it was read with.

    A dataset read from one file carries that file's chunking, compression and fill
    values in ``.encoding``; writing it again with other settings needs them gone.
    """
    ds = ds.copy()
    for v in ds.variables.values():
        v.encoding = {}
    return ds


def flag_names(coord: xr.DataArray) -> list:
    """The name of each value of a CF flag coordinate (its ``flag_meanings`` by its
    ``flag_values``); a coordinate without flags: its values as strings."""
    return [flag_name(coord, v) for v in np.atleast_1d(np.asarray(coord.values))]


def flag_name(coord, value, default=None) -> str:
    """The name one value of a CF flag coordinate stands for (its ``flag_meanings`` by its
    ``flag_values``, which default to 0, 1, …); ``default`` (or the value as a string)
    where ``coord`` is None, has no flags or lacks the value."""
    fallback = str(value) if default is None else default
    meanings = str(coord.attrs.get("flag_meanings", "")).split() if coord is not None else []
    if not meanings or np.asarray(value).dtype.kind not in "iu":
        return fallback
    flags = [int(v) for v in np.atleast_1d(coord.attrs.get("flag_values", np.arange(len(meanings))))]
    v = int(value)
    return meanings[flags.index(v)] if v in flags and flags.index(v) < len(meanings) else fallback


def declare_netcdf(layout: xr.Dataset, path, encoding: dict) -> None:
    """Create the netCDF-4 file ``path`` as xarray writes ``layout`` with ``encoding`` (its
    dimensions, variables, attributes, chunking and filters, and the values of its numpy
    variables), leaving the values of its dask variables unwritten, for the caller to
    write by h5py (the variables declared with placeholders: :func:`write_netcdf`,
    :func:`pipeline.io.combine.write_streamed`).

    No dask computation runs, and the synchronous scheduler keeps xarray from taking a
    distributed lock while a Client is active."""
    import dask

    try:
        from xarray.backends.writers import to_netcdf as _declare
    except ImportError:   # xarray before 2025.x
        from xarray.backends.api import to_netcdf as _declare
    with dask.config.set(scheduler="synchronous"):
        _, store = _declare(layout, str(path), engine="netcdf4", format="NETCDF4",
                            encoding=encoding, multifile=True)
    store.close()


#: Files declared by :func:`declare_netcdf` without global attributes, as bytes, by
#: :func:`_layout_key`: a process that writes many files of one layout (a sweep's worker,
#: its case files) declares it once. The few most recent are kept.
_DECLARED: dict = {}
_DECLARED_KEPT = 4


def _layout_key(layout, encoding: dict, lazy) -> str:
    """A hash of everything :func:`declare_netcdf` writes of ``layout`` but its global
    attributes: the dimensions, and each variable's name, dimensions, type, shape,
    attributes and encoding, and the values of those it writes (all but ``lazy``)."""
    import hashlib

    h = hashlib.sha256(repr(sorted(layout.sizes.items())).encode())
    for k, v in layout.variables.items():
        enc = encoding[k] if k in encoding else v.encoding
        h.update(repr((k, v.dims, v.dtype.str, v.shape, sorted(enc.items()),
                       [(a, np.asarray(x).tolist() if isinstance(x, np.ndarray) else x)
                        for a, x in v.attrs.items()])).encode())
        if k not in lazy:
            values = np.asarray(v.values)
            h.update(values.tobytes() if values.dtype.kind in "biufc" else repr(values.tolist()).encode())
    return h.hexdigest()


def _declare_as_before(layout, path, encoding: dict, lazy) -> None:
    """:func:`declare_netcdf` of ``layout`` into ``path``: a file of a layout declared
    before in this process is copied from its bytes (:data:`_DECLARED`) and gets its
    global attributes from xarray's own netCDF4 store, as a declaration writes them: the
    dataset's, then those xarray adds itself (``coordinates``).

    A study case file's declaration took about 75 ms of a worker's 0.13 s write (138
    variables; netCDF-C defines each, with its attributes and dimension scales); the copy
    and its attributes about 25 ms (docs/performance.md, "Sweeps at scale")."""
    import dask
    from xarray.backends.netCDF4_ import NetCDF4DataStore

    bare = layout.copy()
    bare.attrs = {}
    key = _layout_key(bare, encoding, set(lazy))
    blob, added = _DECLARED.get(key, (None, ()))
    if set(added) & set(layout.attrs):   # xarray would have refused or merged them
        declare_netcdf(layout, path, encoding)
        return
    if blob is None:
        declare_netcdf(bare, path, encoding)
        with open(path, "rb") as f:
            blob = f.read()
    else:
        with open(path, "wb") as f:
            f.write(blob)
        if not layout.attrs:
            return
    # the synchronous scheduler: a plain lock, not a distributed one (declare_netcdf)
    with dask.config.set(scheduler="synchronous"):
        store = NetCDF4DataStore.open(str(path), mode="a", format="NETCDF4")
        try:
            nc = store.ds
            extra = {k: nc.getncattr(k) for k in nc.ncattrs()}   # xarray's own, for the bare layout
            if key not in _DECLARED:
                _DECLARED[key] = (blob, tuple(extra))
                while len(_DECLARED) > _DECLARED_KEPT:
                    _DECLARED.pop(next(iter(_DECLARED)))
            if set(extra) & set(layout.attrs):
                collide = True
            else:
                collide = False
                if layout.attrs:
                    for k in extra:
                        nc.delncattr(k)
                    store.set_attributes(dict(layout.attrs))
                    store.set_attributes(extra)
        finally:
            store.close()
    if collide:
        declare_netcdf(layout, path, encoding)


#: Encoding keys under which xarray would change a variable's values on the way to disk.
_VALUE_ENCODINGS = ("scale_factor", "add_offset", "units", "calendar")


def _filled_after(var, enc: dict) -> bool:
    """Whether :func:`write_netcdf` writes ``var``'s values itself: a numeric numpy array
    of at least one value, stored as its own type with no packing or time encoding, so
    that xarray's encoding leaves its values as they are."""
    return (isinstance(var.data, np.ndarray) and var.dtype.kind in "fiu" and var.size > 0
            and np.dtype(enc.get("dtype", var.dtype)) == var.dtype
            and not any(k in enc for k in _VALUE_ENCODINGS))


def write_netcdf(ds: xr.Dataset, path, encoding: dict) -> None:
    """Write ``ds`` to the netCDF-4 file ``path`` with ``encoding``: the file xarray's
    ``to_netcdf(engine="netcdf4")`` writes, sooner.

    Notes
    -----
    The file is declared by xarray (:func:`declare_netcdf`: names, attributes, encodings,
    the dimensions' coordinates and every variable whose values xarray would change), then
    the other variables' values are written by h5py, each in one call into its dataset as
    declared (its chunks and filters). netCDF4-python's own write took about 0.5 ms a
    variable: a study case file of 138 variables in 0.135 s, against about 0.08 s so
    (docs/performance.md, "Sweeps at scale"). With a dask variable in ``ds`` it is written
    by xarray as a whole.
    """
    import dask
    import dask.array as da

    variables = ds.variables   # Variables, not DataArrays: 0.1 ms less each
    index = set(ds.indexes)
    # a variable's encoding is the one given for it, else its own (as xarray takes it)
    names = [k for k, v in variables.items()
             if k not in index and _filled_after(v, encoding[k] if k in encoding else v.encoding)]
    if not names or any(not isinstance(v.data, np.ndarray) for v in variables.values()):
        with dask.config.set(scheduler="synchronous"):
            ds.to_netcdf(path, engine="netcdf4", format="NETCDF4", encoding=encoding)
        return
    import h5py
    import xarray as xr
    from h5py import h5d, h5s

    placeholders = {}   # one never-computed dask array a shape and type
    for k in names:
        v = variables[k]
        if (v.shape, v.dtype) not in placeholders:
            placeholders[v.shape, v.dtype] = da.empty(v.shape, dtype=v.dtype, chunks=v.shape or -1,
                                                      name=f"rvsweep-placeholder-{len(placeholders)}")
    lazy = {k: xr.Variable(variables[k].dims, placeholders[variables[k].shape, variables[k].dtype],
                           variables[k].attrs, variables[k].encoding) for k in names}
    # the same variables in the same order (the file's), the numeric ones lazy
    layout = ds.assign({k: v for k, v in lazy.items() if k in ds.data_vars}).assign_coords(
        {k: v for k, v in lazy.items() if k in ds.coords})
    _declare_as_before(layout, path, encoding, names)
    with h5py.File(path, "r+") as f:
        fid = f.id
        for k in names:
            v = variables[k]
            h5d.open(fid, k.encode()).write(h5s.ALL, h5s.ALL, np.require(v.values, v.dtype, "C"))
