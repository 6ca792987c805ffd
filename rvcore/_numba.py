"""Keep numba's on-disk cache of rvcore's kernels consistent with rvcore's sources.

numba validates a cached function against the modification time of the file that
defines it, not of the files its callees live in (numba's documented caching
limitation). rvcore's kernels call across modules (``integrator`` → ``kernels`` →
``contact``), so a change to ``contact.py`` alone would leave a stale compiled
``integrate`` in the cache.

Hence every version of rvcore's sources gets a cache directory of its own, named by the
SHA-256 of all of them (:func:`cache_dir`), and numba is pointed there before any kernel
is defined (:func:`use_source_keyed_cache`). A stamp beside one shared cache would not
do: a process started from the old sources, still running (a sweep's workers, a test),
can write kernels compiled from them after a process of the new sources has dropped the
cache and stamped it, and every later run would compute with them.
"""
from __future__ import annotations

import hashlib
import os
import shutil
import time
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent

#: Cache directories of other sources older than this are removed [s].
_KEEP_SECONDS = 86400.0


def sources_hash() -> str:
    """SHA-256 of every ``.py`` file under ``rvcore/``, sub-packages included, each with
    its path relative to the package, in path order."""
    h = hashlib.sha256()
    for path in sorted(_PACKAGE.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        h.update(path.relative_to(_PACKAGE).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def cache_dir() -> Path:
    """The numba cache directory of these sources: ``rvcore-<hash>`` in ``__pycache__``
    beside them, or under ``NUMBA_CACHE_DIR`` when that is set."""
    root = os.environ.get("NUMBA_CACHE_DIR")
    base = Path(root) if root else _PACKAGE / "__pycache__"
    return base / f"rvcore-{sources_hash()[:16]}"


def use_source_keyed_cache() -> None:
    """Point numba's cache at :func:`cache_dir` (call before any kernel is defined), and
    remove the directories of other sources that nobody has written to for a day.

    Where the directory cannot be made (a read-only install), numba keeps its default.
    """
    import numba

    here = cache_dir()
    try:
        here.mkdir(parents=True, exist_ok=True)
    except OSError:
        return
    numba.config.CACHE_DIR = str(here)
    now = time.time()
    for other in here.parent.glob("rvcore-*"):
        try:
            if other != here and now - other.stat().st_mtime > _KEEP_SECONDS:
                shutil.rmtree(other, ignore_errors=True)
        except OSError:
            continue
