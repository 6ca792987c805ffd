"""Every file the pipeline writes, written atomically; the one timestamp.

The content goes to a temporary name in the target's own folder
(``.<name>.@<host>.<pid>.<random>.tmp``, so that the rename stays within one file
system), is flushed and fsync'ed, and is then renamed onto the final name with
``os.replace``, which is atomic on POSIX and Windows: a killed process leaves the old
file or the new one, never half a file. :func:`remove_stale_temporaries` clears what
killed writers of this host left behind; the host in the name keeps it from judging a
writer on another host of a shared file system by a process id of its own.
"""
from __future__ import annotations

import contextlib
import datetime
import errno
import hashlib
import os
import re
import socket
import tempfile
import time
from pathlib import Path

import xarray as xr

from ..errors import UserError
from .netcdf import encoding_for, write_netcdf

TEMP_SUFFIX = ".tmp"

#: A temporary file's name: the target's, the writer's host (``@`` and :func:`host_tag`)
#: and process id, mkstemp's random part. The form without a host is that of files
#: written before the host was named (judged as this host's).
_TEMP_NAME = re.compile(r"^\..+?(?:\.@(?P<host>[A-Za-z0-9_-]+))?\.(?P<pid>\d+)\.[^.]+" + re.escape(TEMP_SUFFIX) + "$")


def host_tag(name: str | None = None) -> str:
    """This host's name (``socket.gethostname()``, or ``name``) as it goes into a temporary
    file's name: letters, digits, ``_`` and ``-`` (anything else ``-``), at most 63."""
    return re.sub(r"[^A-Za-z0-9_-]", "-", socket.gethostname() if name is None else name)[:63] or "-"

#: Test hook: ``NAME:SECONDS`` makes :func:`write_atomic` of the file named NAME sleep for
#: SECONDS once its temporary file holds the data (before the fsync and the rename), in
#: whichever process writes it (a worker or the sweep's own), so that a test can send a
#: signal inside that case's write (tests/pipeline/test_trust.py). The pause starts by
#: writing the temporary file's path into the file named by :data:`PAUSED_ENV`. Unset in
#: normal use.
PAUSE_ENV = "RVSWEEP_TEST_PAUSE_IN_WRITE"
PAUSED_ENV = "RVSWEEP_TEST_PAUSED_FILE"

#: errno values that mean the place, not the data, is at fault: the sweep stops.
_PLACE_ERRORS = (errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES, errno.EPERM, errno.EIO)


class WriteError(UserError):
    """A file could not be written because of where it goes (a full disk, a read-only
    file system, no permission): one line naming the file and the reason. Work stops; a
    rerun resumes."""


def write_error(path: Path, exc: BaseException) -> WriteError:
    """The one-line :class:`WriteError` for ``exc`` raised while writing ``path``."""
    if isinstance(exc, OSError) and exc.errno:
        why = os.strerror(exc.errno)
    elif _disk_full(path.parent):   # HDF5's word for it is "NetCDF: HDF error"
        why = os.strerror(errno.ENOSPC)
    else:
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    return WriteError(f"{path}: cannot write ({why}); finished files are kept, "
                      "run the same command again once that is fixed")


def _disk_full(folder: Path) -> bool:
    """Whether the file system of ``folder`` has (almost) no space left for us.

    netCDF/HDF5 reports a failed write on a full disk as ``NetCDF: HDF error`` rather
    than as ``ENOSPC``; the free space tells the two apart."""
    try:
        st = os.statvfs(folder)
    except OSError:
        return False
    return st.f_bavail * st.f_frsize < 1 << 20 or (st.f_files and st.f_favail == 0)


def _place_fault(path: Path, exc: BaseException) -> bool:
    """Whether ``exc`` from writing ``path`` is the place's fault (full, read-only, denied)."""
    if isinstance(exc, OSError) and exc.errno in _PLACE_ERRORS:
        return True
    return isinstance(exc, (OSError, RuntimeError)) and _disk_full(path.parent)


def file_digest(path) -> str:
    """The SHA-256 of a file's bytes, as hex [-].

    Recorded in ``status.json`` when a case file is written and compared before the file
    is reused, so that a file changed since (flipped bytes, a copy of another case) is
    found without reading its variables. Reading is the cost: about 1 ms per MB.
    """
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _pause_for_tests(path: Path, tmp: Path) -> None:
    spec = os.environ.get(PAUSE_ENV)
    if not spec:
        return
    name, _, seconds = spec.rpartition(":")
    if path.name == name:
        if os.environ.get(PAUSED_ENV):
            Path(os.environ[PAUSED_ENV]).write_text(f"{tmp}\n")
        time.sleep(float(seconds or 60))


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


def temp_path(path: Path) -> Path:
    """A new, empty temporary file beside ``path``, named for its writer
    (``.<name>.@<host>.<pid>.<random>.tmp``, module docstring), with the mode a plain
    file would get."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.@{host_tag()}.{os.getpid()}.",
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
    tmp = temp_path(path)
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
    A failure that is the place's fault (a full disk, a read-only file system, no
    permission) raises :class:`WriteError`: one line naming ``path`` and the reason.
    No distributed lock is taken, whatever dask client is active: while a distributed
    Client is active, xarray would take a scheduler-wide write lock (a round trip to the
    scheduler, and where a signal could leave the write hung); the synchronous scheduler
    gives it a plain in-process lock instead (:func:`pipeline.io.netcdf.write_netcdf`).
    """
    path = Path(path)
    with netcdf_atomic(path) as tmp:
        write_netcdf(ds, tmp, encoding_for(ds) if encoding is None else encoding)
        _pause_for_tests(path, tmp)
    return path


@contextlib.contextmanager
def netcdf_atomic(path):
    """Yield a temporary name beside ``path`` for a netCDF writer; when the block ends the
    file is fsync'ed and renamed onto ``path`` (as :func:`write_atomic`, whose errors it
    raises: :class:`WriteError` when the place is at fault)."""
    path = Path(path)
    try:
        with _replacing(path) as tmp:
            yield tmp
            _fsync(tmp)
    except (OSError, RuntimeError) as exc:
        if _place_fault(path, exc):
            raise write_error(path, exc) from None
        raise


def write_text_atomic(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (temporary file, fsync, ``os.replace``)."""
    return write_bytes_atomic(path, text.encode("utf-8"))


def remove_stale_temporaries(folder) -> list:
    """Delete temporary files left in ``folder`` by killed writers on this host.

    A temporary file carries its writer's host and process id (see :func:`write_atomic`);
    it is removed only when it is this host's and that process no longer exists, so a
    writer still at work keeps its file. A file of another host (a worker of a cluster
    whose hosts share the folder) is left alone, whatever its process id means here: a
    run on that host clears it, or whoever removes the folder.

    Returns
    -------
    list of Path
        The files removed.
    """
    removed = []
    folder = Path(folder)
    if not folder.is_dir():
        return removed
    here = host_tag()
    for tmp in folder.glob(f".*{TEMP_SUFFIX}"):
        m = _TEMP_NAME.match(tmp.name)
        if not m or (m.group("host") is not None and m.group("host") != here):
            continue
        pid = int(m.group("pid"))
        if pid != os.getpid() and process_alive(pid):
            continue
        try:
            tmp.unlink()
            removed.append(tmp)
        except OSError:
            pass
    return removed


def process_alive(pid: int) -> bool:
    """Whether process ``pid`` of this host can still run (write a file).

    A process that has exited but not yet been reaped by its parent (a zombie: a worker
    just killed, whose parent's watcher has not yet joined it) still answers
    ``kill(pid, 0)``; on Linux its state in ``/proc/<pid>/stat`` tells it apart, and it
    counts as gone."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:   # it ended meanwhile; or no /proc (not Linux): take it as running
        return not Path("/proc/self").is_dir()
    # "pid (comm) S ...": the state follows the last ')' (comm may hold one)
    return stat[stat.rfind(")") + 2:][:1] not in ("Z", "X")


def write_bytes_atomic(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temporary file, fsync, ``os.replace``)."""
    path = Path(path)
    try:
        with _replacing(path) as tmp, open(tmp, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
    except OSError as exc:
        raise write_error(path, exc) from None
    return path
