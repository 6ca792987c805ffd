"""Output places checked before any work, and the lock that keeps one sweep per folder.

A command that would fail only when it writes (after a case has been computed, or with a
traceback from deep inside netCDF) checks its output place first and says in one line
what is wrong with it. :func:`sweep_lock` keeps two ``rvsweep sweep`` runs out of one
folder: both would compute every case.
"""
from __future__ import annotations

import contextlib
import errno
import os
import socket
import tempfile
from pathlib import Path

from ..errors import UserError

LOCK_FILE = ".rvsweep.lock"


def _why(exc: OSError) -> str:
    return os.strerror(exc.errno) if exc.errno else str(exc)


def _probe(folder: Path, what: str) -> None:
    """Create and delete a file in ``folder``: the only sure test that we may write there
    (permissions, a read-only mount, ACLs and root all answer it the same way)."""
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".rvsweep-probe-"):
            pass
    except OSError as exc:
        raise UserError(f"{what}: cannot write in {folder} ({_why(exc)})") from None


def writable_folder(path, what: str) -> Path:
    """Make ``path`` a folder we can write in (created with its parents), or raise a
    one-line :class:`UserError` starting with ``what`` (e.g. ``"--out results"``)."""
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise UserError(f"{what}: {folder} is a file, not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UserError(f"{what}: cannot create the folder {folder} ({_why(exc)})") from None
    _probe(folder, what)
    return folder


def writable_file(path, what: str) -> Path:
    """Check that ``path`` can be written as a file (its folder created when missing),
    or raise a one-line :class:`UserError` starting with ``what``."""
    target = Path(path)
    if target.is_dir() or str(path).endswith(os.sep):
        raise UserError(f"{what}: {target} is a folder; give a file name, e.g. {target / 'case.nc'}")
    if target.exists() and not os.access(target, os.W_OK):
        raise UserError(f"{what}: {target} exists and is read-only")
    writable_folder(target.parent if str(target.parent) else Path("."), what)
    return target


@contextlib.contextmanager
def sweep_lock(folder, what: str | None = None):
    """Hold an exclusive lock on ``folder`` for the block, or raise a one-line
    :class:`UserError` when another process holds it.

    ``fcntl.flock`` on ``<folder>/.rvsweep.lock``: the kernel drops the lock when its
    holder exits, however it exits (``kill -9`` included), so a killed run never leaves
    a stale lock; the file itself may stay and means nothing unlocked. Its text (pid and
    host of the holder) is only for the message. Where ``fcntl`` does not exist
    (Windows) the block runs unlocked.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        yield
        return
    path = Path(folder) / LOCK_FILE
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            if exc.errno not in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise
            holder = os.pread(fd, 200, 0).decode("utf-8", "replace").strip() or "another process"
            raise UserError(f"{what or folder}: in use by another rvsweep sweep ({holder}); "
                            f"wait for it to finish or give another --out") from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"pid {os.getpid()} on {socket.gethostname()}\n".encode(), 0)
        yield
    finally:
        os.close(fd)   # closing the descriptor releases the lock
