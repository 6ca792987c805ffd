"""Every file the pipeline writes, written atomically; the one timestamp.

The content goes to a temporary name in the target's own folder
(``.<name>.<pid>.<random>.tmp``, so that the rename stays within one file system), is
flushed and fsync'ed, and is then renamed onto the final name with ``os.replace``,
which is atomic on POSIX and Windows: a killed process leaves the old file or the new
one, never half a file. :func:`remove_stale_temporaries` clears what killed writers
left behind.
"""
from __future__ import annotations

import contextlib
import datetime
import os
import re
import tempfile
from pathlib import Path

import xarray as xr

from .netcdf import encoding_for

TEMP_SUFFIX = ".tmp"


def utc_stamp() -> str:
    """The current UTC time as ``YYYY-MM-DDThh:mm:ssZ`` (the ``history`` line prefix)."""
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def history_line(text: str) -> str:
    """One timestamped ``history`` line (CF: one line per processing step)."""
    return f"{utc_stamp()} {text}"


def _umask() -> int:
    """The process's umask. Linux shows it in /proc (read-only, so safe beside other
    threads); elsewhere it can only be read by setting it and setting it back."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _temp_path(path: Path) -> Path:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.{os.getpid()}.",
                               suffix=TEMP_SUFFIX)
    try:
        # mkstemp creates 0600 whatever the umask; the final file should have the mode any
        # tool would give it (0666 less the umask), so others may read the results.
        os.fchmod(fd, 0o666 & ~_umask())
    finally:
        os.close(fd)
    return Path(tmp)


@contextlib.contextmanager
def _replacing(path: Path):
    """Yield a temporary name next to ``path``; rename it onto ``path`` when the block ends.

    On any error the temporary file is removed and ``path`` is untouched.
    """
    tmp = _temp_path(path)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


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
        Per-variable netCDF encoding (default :func:`pipeline.io.netcdf.encoding_for`).

    Notes
    -----
    The data go to a temporary file ``.<name>.<pid>.<random>.tmp`` in the same folder
    (so that the rename is within one file system), are fsync'ed, and the temporary
    file is then renamed onto ``path`` with ``os.replace``, which is atomic on POSIX
    and Windows. On any error the temporary file is removed and ``path`` is untouched.
    """
    path = Path(path)
    with _replacing(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4",
                     encoding=encoding_for(ds) if encoding is None else encoding)
        _fsync(tmp)
    return path


def write_text_atomic(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (temporary file, fsync, ``os.replace``)."""
    return write_bytes_atomic(path, text.encode("utf-8"))


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


def write_bytes_atomic(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temporary file, fsync, ``os.replace``)."""
    path = Path(path)
    with _replacing(path) as tmp, open(tmp, "wb") as fh:
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())
    return path
