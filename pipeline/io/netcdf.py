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
