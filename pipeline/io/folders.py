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
import stat
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


def _open_lock(path: Path, what: str) -> int:
    """Open (or create) the lock file without following a symbolic link.

    A symlink (or a hard link, or anything that is not a plain file) named
    ``.rvsweep.lock`` is refused in one line and left as it is: the lock is truncated and
    written, and through a link that would overwrite its target (any file, for root).
    ``O_NOFOLLOW`` refuses a symlink in the kernel, with no window between a check and
    the open; ``O_NONBLOCK`` keeps a FIFO of that name from blocking the open.
    """
    flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(path, flags, 0o666)
    except OSError as exc:
        if exc.errno == errno.ELOOP or path.is_symlink():
            raise UserError(f"{what}: {path} is a symbolic link; refusing to follow it "
                            "(remove it: a sweep creates its own lock file)") from None
        raise UserError(f"{what}: cannot open the lock file {path} ({_why(exc)})") from None
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode) or info.st_nlink > 1:
        os.close(fd)
        what_it_is = "a hard link to another file" if stat.S_ISREG(info.st_mode) else "not a plain file"
        raise UserError(f"{what}: {path} is {what_it_is}; refusing to use it as the lock "
                        "(remove it: a sweep creates its own lock file)")
    return fd


@contextlib.contextmanager
def sweep_lock(folder, what: str | None = None):
    """Hold an exclusive lock on ``folder`` for the block, or raise a one-line
    :class:`UserError` when another process holds it.

    ``fcntl.flock`` on ``<folder>/.rvsweep.lock``: the kernel drops the lock when its
    holder exits, however it exits (``kill -9`` included), so a killed run never leaves
    a stale lock; the file itself may stay and means nothing unlocked. Its text (pid and
    host of the holder) is only for the message. A lock that is a symbolic link, a hard
    link or not a plain file is refused (:func:`_open_lock`), its target untouched. Where ``fcntl`` does not exist
    (Windows) the block runs unlocked.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        yield
        return
    path = Path(folder) / LOCK_FILE
    fd = _open_lock(path, what or str(folder))
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
