"""Shared NetCDF writing: atomic replacement, encodings and CF attributes.

Every file the pipeline writes goes through :func:`write_atomic` (or
:func:`write_text_atomic`): the content is written to a temporary name in the target's
own folder, flushed to disk, and then renamed onto the final name with ``os.replace``,
so a killed process leaves either the old file or the new one, never half a file.

The conventions (pipeline.md, "NetCDF conventions"): CF-1.8, UDUNITS unit strings, no
``_FillValue`` on coordinates, zlib compression, one case per chunk, float64 data, the
netCDF4 engine.
"""
from __future__ import annotations

import datetime as _dt
import os
import re
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

#: UDUNITS spelling of the SI unit of each kind of :data:`pipeline.units.SI_UNITS`.
UDUNITS = {
    "length": "m",
    "mass": "kg",
    "time": "s",
    "force": "N",
    "moment": "N m",
    "angle": "rad",
    "angular_speed": "rad s-1",
    "speed": "m s-1",
    "density": "kg m-3",
    "pressure": "Pa",
    "stiffness_hertz": "N m-1.5",
    "stiffness": "N m-1",
    "damping": "N s m-1",
    "inertia": "kg m2",
    "frequency": "Hz",
    "dimensionless": "1",
}

#: Flag values and meanings of the ``case_status`` variable of a combined sweep.
CASE_STATUS = ("ok", "failed", "not_run")

TEMP_SUFFIX = ".tmp"

_CF_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def utc_stamp() -> str:
    """The current UTC time as ``YYYY-MM-DDThh:mm:ssZ`` (the ``history`` line prefix)."""
    return _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def history_line(text: str) -> str:
    """One timestamped ``history`` line (CF: one line per processing step)."""
    return f"{utc_stamp()} {text}"


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


def _temp_path(path: Path) -> Path:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.{os.getpid()}.",
                               suffix=TEMP_SUFFIX)
    os.close(fd)
    return Path(tmp)


def _fsync(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def write_atomic(ds: xr.Dataset, path, encoding: dict | None = None) -> Path:
    """Write ``ds`` to ``path`` atomically with the netCDF4 engine.

    Parameters
    ----------
    ds : xarray.Dataset
        The data [-].
    path : str or Path
        The final file name; its folder must exist [-].
    encoding : dict, optional
        Per-variable netCDF encoding (default :func:`pipeline.case.encoding_for`).

    Notes
    -----
    The data go to a temporary file ``.<name>.<pid>.<random>.tmp`` in the same folder
    (so that the rename is within one file system), are fsync'ed, and the temporary
    file is then renamed onto ``path`` with ``os.replace``, which is atomic on POSIX
    and Windows. On any error the temporary file is removed and ``path`` is untouched.
    """
    from .case import encoding_for

    path = Path(path)
    tmp = _temp_path(path)
    try:
        ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4",
                     encoding=encoding_for(ds) if encoding is None else encoding)
        _fsync(tmp)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def write_text_atomic(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (temporary file, fsync, ``os.replace``)."""
    path = Path(path)
    tmp = _temp_path(path)
    try:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def remove_stale_temporaries(folder) -> list:
    """Delete temporary files left in ``folder`` by killed writers on this host.

    A temporary file carries its writer's process id (see :func:`write_atomic`); it
    is removed only when that process no longer exists, so a writer still at work
    keeps its file.

    Returns
    -------
    list of Path
        The files removed.
    """
    removed = []
    folder = Path(folder)
    if not folder.is_dir():
        return removed
    for tmp in folder.glob(f".*{TEMP_SUFFIX}"):
        m = re.match(r"^\..+\.(\d+)\.[^.]+" + re.escape(TEMP_SUFFIX) + "$", tmp.name)
        if not m:
            continue
        pid = int(m.group(1))
        if pid != os.getpid() and _alive(pid):
            continue
        try:
            tmp.unlink()
            removed.append(tmp)
        except OSError:
            pass
    return removed


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


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


def case_status_variable(codes: np.ndarray, dims) -> xr.DataArray:
    """The int8 ``case_status`` flag variable over the grid (0 ok, 1 failed, 2 not_run)."""
    return xr.DataArray(
        np.asarray(codes, dtype=np.int8), dims=tuple(dims),
        attrs={"long_name": "outcome of the case at this grid point",
               "flag_values": np.arange(len(CASE_STATUS), dtype=np.int8),
               "flag_meanings": " ".join(CASE_STATUS)},
    )
