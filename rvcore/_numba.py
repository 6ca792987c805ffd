"""rvcore's numba kernels: the one decorator that compiles them (:func:`kernel`, its flags
and error model), and numba's on-disk cache of them kept consistent with rvcore's sources.

numba validates a cached function against the modification time of the file that
defines it, not of the files its callees live in (numba's documented caching
limitation). rvcore's kernels call across modules and sub-packages (``integrate.loop`` →
``dynamics.rhs`` → ``contact.laws``), so a change to ``contact/laws.py`` alone would leave
a stale compiled ``integrate`` in the cache.

Hence every version of rvcore's sources gets a cache directory of its own, named by the
SHA-256 of all of them, sub-packages included (:func:`cache_dir`), and numba is pointed there before any kernel
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


# Floating-point flags of every kernel (:data:`FAST`): none. Results must be
# bit-identical for the same inputs on any scheduler, i.e. on whatever CPU model a worker
# runs, and numba compiles each kernel for the host CPU (its cache is keyed by it).
# - 'contract' lets LLVM fuse a·b + c into one FMA where the CPU has FMA (one rounding
#   instead of two): an FMA machine and an older one round differently.
# - 'reassoc' lets it reorder sums, and the order it picks follows the vector width
#   (SSE, AVX2, AVX-512): same source, different sums.
# - 'arcp' allows x/y → x·(1/y), and with AVX-512 LLVM may use the approximate vrcp14pd
#   refined by Newton steps: not the correctly rounded quotient.
# - 'afn' allows approximate sqrt/sin/cos, chosen per target.
# - 'nsz' only forgets the sign of zero, harmless to our values, but it lets the backend
#   pick min/max instructions whose ±0 handling differs by target, so an output's bits
#   (a −0.0 written to a file) could differ; alone it would save next to nothing.
# - 'nnan'/'ninf' were never used: a blow-up must show as NaN/Inf.
# Every operation is then IEEE-754 rounded in source order on every x86-64/AArch64 CPU.
# Still CPU-dependent: the system libm's sin/cos (glibc picks an FMA variant at run time),
# used only for the ring tilt and the cage angle. What it costs: docs/performance.md.
FAST = False
# Every kernel compiles with ``error_model="numpy"`` (:data:`ERROR_MODEL`): a division by zero gives ±inf or NaN,
# as IEEE-754 says, instead of raising. A step that blows up (a state gone to inf, then
# 1/inf = 0 as a divisor) then reaches the NaN/Inf check of
# :func:`rvcore.integrate.loop.integrate`, which names the time and the body; under numba's
# default "python" model it escaped as a bare ZeroDivisionError (IMEX at a step 20× its
# own, 2026-11-27). Quotients that do not fault are the same bits under either model.
ERROR_MODEL = "numpy"


def kernel(fn=None, *, inline: bool = False):
    """The one decorator of rvcore's numba kernels: ``@kernel`` or ``@kernel(inline=True)``.

    Every kernel is compiled with the same options: cached on disk (in
    :func:`cache_dir`), without the GIL, with the floating-point flags :data:`FAST` and
    the error model :data:`ERROR_MODEL`. ``inline=True`` inlines the function into its
    callers in numba's IR (``inline="always"``): the small scalar laws, which then
    compile as part of each kernel that calls them.
    """
    from numba import njit

    options = dict(cache=True, nogil=True, fastmath=FAST, error_model=ERROR_MODEL,
                   inline="always" if inline else "never")
    if fn is None:
        return njit(**options)
    return njit(**options)(fn)


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
