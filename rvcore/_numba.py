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

The directory is the same for every install of the same sources on the same CPU model
(:func:`cache_dir`: a user-wide root / the sources' hash / the CPU's key), and the
kernels are found in it by a locator that does not look at the install's path
(:class:`SourceKeyedLocator`): numba's own locators name a sub-directory after the
SHA-1 of the module's absolute path, so every clone, venv, CI run and cluster host
compiled again (about a minute of CPU). That is safe because the directory is already
named by the contents of every source: two installs that share it run the same code.
Within it numba keys each kernel by its module's name, its qualified name and line, the
module file's SHA-256 (numba's source stamp), the signature, and the CPU's name and
features; a different numba version overwrites its own entries.

The first process to compile holds :func:`compile_lock` while it does (rvcore's
``warm_up``), so that workers started together on one host compile once and the others
load; :func:`compiled_kernels` counts what this process compiled, and
``RVSWEEP_COMPILE_NOTICES=1`` prints a line a kernel as it is compiled.
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import re
import shutil
import sys
import time
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent

#: The environment variable that sets the cache's root (:func:`cache_root`).
CACHE_ENV = "RVSWEEP_CACHE_DIR"

#: Kernels this process compiled (not loaded from the cache), by qualified name, with
#: the seconds each took (:func:`compiled_kernels`).
_COMPILED: list[tuple[str, float]] = []
_LISTENING = False

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


def cache_root() -> Path:
    """The root of the kernels' cache, shared by every install of this user:
    ``$RVSWEEP_CACHE_DIR``, else ``$NUMBA_CACHE_DIR``, else
    ``$XDG_CACHE_HOME/rv-bearing-sweep``, else ``~/.cache/rv-bearing-sweep``."""
    for name in (CACHE_ENV, "NUMBA_CACHE_DIR"):
        if os.environ.get(name):
            return Path(os.environ[name]).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "rv-bearing-sweep"


def cpu_key() -> str:
    """The CPU model the kernels are compiled for, as a directory name: numba's target
    CPU name (``NUMBA_CPU_NAME`` if set, else the host's), the first 8 hex digits of the
    SHA-256 of its feature string (``NUMBA_CPU_FEATURES`` if set, else the host's), and
    numba's version: ``znver3-1a2b3c4d-numba0.68.1``."""
    import numba
    from llvmlite import binding as ll
    from numba.core.codegen import get_host_cpu_features

    name = numba.config.CPU_NAME or ll.get_host_cpu_name()
    features = numba.config.CPU_FEATURES if numba.config.CPU_FEATURES is not None else get_host_cpu_features()
    digest = hashlib.sha256(str(features).encode()).hexdigest()[:8]
    return re.sub(r"[^A-Za-z0-9_.-]", "_", f"{name}-{digest}-numba{numba.__version__}")


def cache_dir() -> Path:
    """The numba cache directory of these sources on this CPU:
    ``<cache_root()>/rvcore-<hash>/<cpu_key()>``, the hash that of every source
    (:func:`sources_hash`), the same for every install of them."""
    return cache_root() / f"rvcore-{sources_hash()[:16]}" / cpu_key()


#: The directory :func:`use_source_keyed_cache` chose, read by :class:`SourceKeyedLocator`.
_ACTIVE: Path | None = None


def _make_locator_class():
    """:class:`SourceKeyedLocator`, built on first use (numba is imported lazily)."""
    from numba.core.caching import _CacheLocator, _SourceFileBackedLocatorMixin

    class SourceKeyedLocator(_SourceFileBackedLocatorMixin, _CacheLocator):
        """numba's cache locator for rvcore's kernels: ``<cache_dir()>/<sub-package>``,
        with no trace of the install's path (module docstring). Functions outside
        rvcore, or with no active directory, are left to numba's own locators."""

        def __init__(self, py_func, py_file, sub):
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = str(_ACTIVE / sub)

        def get_cache_path(self):
            return self._cache_path

        @classmethod
        def from_function(cls, py_func, py_file):
            if _ACTIVE is None:
                return None
            try:
                rel = Path(py_file).resolve().relative_to(_PACKAGE)
            except (ValueError, OSError):
                return None
            sub = "_".join(rel.parent.parts) or "_root"
            self = cls(py_func, py_file, sub)
            try:
                self.ensure_cache_path()
            except OSError:
                return None
            return self

    return SourceKeyedLocator


def _register_locator() -> None:
    """Put :class:`SourceKeyedLocator` first among numba's locators (once)."""
    from numba.core.caching import CacheImpl

    if not any(getattr(c, "__name__", "") == "SourceKeyedLocator" and c.__module__ == __name__
               for c in CacheImpl._locator_classes):
        CacheImpl._locator_classes.insert(0, _make_locator_class())


def _register_compile_listener() -> None:
    """Count (and with ``RVSWEEP_COMPILE_NOTICES=1`` print) every rvcore kernel this
    process compiles: numba's ``numba:compile`` event fires on a cache miss only."""
    from numba.core import event

    class _Notices(event.Listener):
        def __init__(self):
            self._start = {}

        def on_start(self, ev):
            self._start[id(ev.data["dispatcher"])] = time.perf_counter()

        def on_end(self, ev):
            d = ev.data["dispatcher"]
            mod = getattr(d.py_func, "__module__", "") or ""
            if not (mod == "rvcore" or mod.startswith("rvcore.")):
                return
            seconds = time.perf_counter() - self._start.pop(id(d), time.perf_counter())
            name = f"{mod}.{d.py_func.__qualname__}"
            _COMPILED.append((name, seconds))
            if os.environ.get("RVSWEEP_COMPILE_NOTICES"):
                print(f"rvcore: compiled {name} in {seconds:.1f} s (pid {os.getpid()})", file=sys.stderr,
                      flush=True)

    global _LISTENING
    if not _LISTENING:
        event.register("numba:compile", _Notices())
        _LISTENING = True


def compiled_kernels() -> list[tuple[str, float]]:
    """The rvcore kernels this process compiled rather than loaded from the cache:
    ``(module.qualname, seconds)`` in order [s]."""
    return list(_COMPILED)


def cache_report() -> dict:
    """Where this process's rvcore lives and caches, and what it compiled:
    ``{"package": path, "cache_dir": path or None, "compiled": [(name, seconds), ...]}``
    (what a cluster's workers are asked, ``client.run(cache_report)``)."""
    return {"package": str(_PACKAGE), "cache_dir": str(_ACTIVE) if _ACTIVE else None,
            "compiled": compiled_kernels()}


@contextlib.contextmanager
def compile_lock():
    """Hold an exclusive lock on ``<cache_dir()>/compile.lock`` (POSIX ``flock``) for the
    block: processes of one host that compile the kernels together then compile once,
    the others waiting and loading. Without ``fcntl`` or a writable directory, no lock."""
    try:
        import fcntl
    except ImportError:       # not POSIX
        yield
        return
    try:
        f = open((_ACTIVE or cache_dir()) / "compile.lock", "a+b")
    except OSError:
        yield
        return
    with f:
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX)
        except OSError:
            pass
        yield


def use_source_keyed_cache() -> None:
    """Point numba's cache for rvcore's kernels at :func:`cache_dir` (call before any
    kernel is defined), register the locator that finds them there whatever the
    install's path, and remove the directories of other sources that nobody has used
    for a day.

    Where the directory cannot be made, the one beside the sources
    (``__pycache__/rvcore-<hash>/<cpu>`` inside the package) is tried; where neither can, numba
    keeps its default.
    """
    global _ACTIVE
    import numba

    here = cache_dir()
    for candidate in (here, _PACKAGE / "__pycache__" / here.parent.name / here.name):
        try:
            candidate.mkdir(parents=True, exist_ok=True)
            os.utime(candidate.parent)          # "used": kept by the clean-up below
        except OSError:
            continue
        here = candidate
        break
    else:
        return
    _ACTIVE = here
    numba.config.CACHE_DIR = str(here)
    _register_locator()
    _register_compile_listener()
    now = time.time()
    for other in here.parent.parent.glob("rvcore-*"):
        try:
            if other != here.parent and now - other.stat().st_mtime > _KEEP_SECONDS:
                shutil.rmtree(other, ignore_errors=True)
        except OSError:
            continue
