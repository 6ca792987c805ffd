"""Keep numba's on-disk cache of rvcore's kernels consistent with rvcore's sources.

numba validates a cached function against the modification time of the file that
defines it, not of the files its callees live in (numba's documented caching
limitation). rvcore's kernels call across modules (``integrator`` → ``kernels`` →
``contact``), so a change to ``contact.py`` alone would leave a stale compiled
``integrate`` in the cache. :func:`drop_stale_numba_cache` hashes every rvcore source
and deletes rvcore's cache files when the hash differs from the one stored beside them.
"""
from __future__ import annotations

import hashlib
import os
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent
_STAMP = "rvcore-sources.sha256"


def sources_hash() -> str:
    """SHA-256 of every ``rvcore/*.py`` file, in name order."""
    h = hashlib.sha256()
    for path in sorted(_PACKAGE.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _cache_dirs():
    """Where numba may keep rvcore's cache: ``__pycache__`` beside the sources, and the
    mirrored tree under ``NUMBA_CACHE_DIR`` when that is set."""
    yield _PACKAGE / "__pycache__"
    root = os.environ.get("NUMBA_CACHE_DIR")
    if root:
        yield from (p for p in Path(root).rglob("rvcore") if p.is_dir())


def drop_stale_numba_cache() -> None:
    """Delete rvcore's ``*.nbi``/``*.nbc`` files if the sources changed since they were built."""
    digest = sources_hash()
    for folder in _cache_dirs():
        stamp = folder / _STAMP
        try:
            if folder == _PACKAGE / "__pycache__":
                folder.mkdir(exist_ok=True)   # stamp it before numba writes the first kernels
            if stamp.is_file() and stamp.read_text().strip() == digest:
                continue
            for f in list(folder.glob("*.nbi")) + list(folder.glob("*.nbc")):
                f.unlink(missing_ok=True)
            if folder.is_dir():
                stamp.write_text(digest + "\n")
        except OSError:   # a read-only install: numba then caches elsewhere or not at all
            continue
