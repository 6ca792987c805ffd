"""Compile to bytecode, once, every module that rvsweep, its dask workers and the tests import.

``make venv`` runs this after the install (tools/install_venv.sh: uv, or pip with
``--no-compile``), which compiles nothing. Where PYTHONDONTWRITEBYTECODE is
set (this project's machines, many containers) Python never caches the bytecode it compiles,
so every process compiled its 1,400 imported modules again: 3.4 s a process (``rvsweep
--help`` 5 s, each of a sweep's workers, each test process). pip's own compile step writes
bytecode for every installed file instead (scipy's and the others' tests too) and adds about
20 s to the install; this imports what the commands import with the bytecode cache on, so
that each of those modules is compiled once and written. A module imported later than these
is compiled in memory as before. Python reads bytecode whatever PYTHONDONTWRITEBYTECODE
says, and compiles a source again in memory when it is newer than its bytecode, so an edited
file is never read stale.

The imports run in two processes where there are two CPUs.

Which files those imports load is the same for the same installed packages, so the list is
kept per user (beside the kernels' cache, ``rvcore._numba.cache_root``:
``<root>/bytecode/<key>.json``), keyed by
the Python version, every installed distribution's name and version and the groups below.
A venv of packages seen before then compiles those files without importing them (the
project's own sources all, whatever the list says): 3.6 s against 6.5-6.7 s of imports on
a fresh clone on the project's 2-core machine (1,773 files), since an import also runs
each module. A list that names a file no longer there is skipped over; a venv of other packages
imports, as the first one did, and keeps its list.

Usage: ``python tools/compile_bytecode.py``; ``--cache-root`` prints that root.
"""
from __future__ import annotations

import hashlib
import importlib
import json
import os
import py_compile
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The project's own packages: compiled whole when a kept list is used.
PROJECT = ("pipeline", "rvcore")

#: What the commands, the sweep's workers and the tests import, in two groups of about equal
#: import time (7.1 s in one process, 4.6 s in two, on the project's 2-core machine,
#: 2026-11-29); the commands' own modules go with the first.
GROUPS = (
    ("pipeline.cli", "pipeline.report.build", "pipeline.report.figures", "pipeline.bench",
     "matplotlib.pyplot", "matplotlib.backends.backend_agg", "scipy.stats",
     "compliance_checker.runner"),
    ("rvcore.simulation.run", "pipeline.run.cluster", "pipeline.run.cases", "distributed",
     "dask.array", "xarray.backends.netCDF4_", "pytest", "xdist", "hypothesis"),
)


def compile_group(names) -> list:
    """Import ``names``; the source files of every module loaded."""
    for name in names:
        try:
            importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name != name.split(".")[0]:   # the test extras are not installed for a sweep: nothing to say
                print(f"compile_bytecode: {name} not imported ({exc})", file=sys.stderr)
        except Exception as exc:  # noqa: BLE001 - a broken install: said, and the rest compiled
            print(f"compile_bytecode: {name} not imported ({type(exc).__name__})", file=sys.stderr)
    return sorted({m.__file__ for m in list(sys.modules.values())
                   if isinstance(getattr(m, "__file__", None), str) and m.__file__.endswith(".py")})


def group_names(k: int) -> tuple:
    """Group ``k``'s modules; the first also takes every ``pipeline.commands`` module."""
    if k:
        return GROUPS[k]
    from pipeline.cli import COMMANDS

    return GROUPS[0] + tuple(f"pipeline.commands.{c}" for c in COMMANDS)


def cache_root() -> Path:
    """The per-user root of this project's caches, ``rvcore._numba.cache_root`` (the
    kernels' too), read from its file: importing ``rvcore`` would import numba."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("_rvcore_numba", ROOT / "rvcore" / "_numba.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.cache_root()


def list_path() -> Path:
    """Where the list of this environment's imported files is kept: named by a hash of the
    Python version, the installed distributions (name and version) and :data:`GROUPS`."""
    from importlib import metadata

    dists = sorted(f"{d.metadata['Name']}=={d.version}".lower() for d in metadata.distributions())
    key = hashlib.sha256(json.dumps([sys.version, dists, GROUPS]).encode()).hexdigest()[:24]
    return cache_root() / "bytecode" / f"{key}.json"


def _places() -> dict:
    """Where listed files are kept relative to: this venv's site-packages and the project."""
    import sysconfig

    return {"site": Path(sysconfig.get_paths()["purelib"]), "project": ROOT}


def to_list(files) -> list:
    """``files`` as [place, relative path] where under a :func:`_places` folder (others, the
    standard library's, were compiled with Python itself)."""
    out = []
    for f in files:
        path = Path(f).resolve()
        for place, base in _places().items():
            if path.is_relative_to(base.resolve()):
                out.append([place, path.relative_to(base.resolve()).as_posix()])
                break
    return out


def from_list(entries) -> list:
    """The files of a kept list in this venv and tree, and every source of :data:`PROJECT`."""
    places = _places()
    files = {str(places[p] / rel) for p, rel in entries if p in places}
    for package in PROJECT:
        files.update(str(f) for f in (ROOT / package).rglob("*.py"))
    return sorted(f for f in files if os.path.isfile(f))


def _compile_files(files) -> int:
    for f in files:
        py_compile.compile(f, quiet=1)
    return len(files)


def compile_listed(files) -> int:
    """Compile ``files`` (no import) in two processes where there are two CPUs."""
    if (os.cpu_count() or 1) < 2:
        return _compile_files(files)
    with ProcessPoolExecutor(2) as pool:
        return sum(pool.map(_compile_files, [files[0::2], files[1::2]]))


def keep_list(path: Path, files) -> None:
    """Write the list atomically; a folder that cannot be written keeps nothing, quietly."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}")
        tmp.write_text(json.dumps(to_list(files)))
        os.replace(tmp, path)
    except OSError:
        pass


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    sys.dont_write_bytecode = False     # what PYTHONDONTWRITEBYTECODE turned off, for this process
    if argv[:1] == ["--group"]:           # a child of the parallel run below
        print(json.dumps(compile_group(group_names(int(argv[1])))))
        return 0
    if argv[:1] == ["--cache-root"]:      # for tools/install_venv.sh
        print(cache_root())
        return 0
    kept = list_path()
    try:
        entries = json.loads(kept.read_text())
    except (OSError, ValueError):
        entries = None
    if entries:
        n = compile_listed(from_list(entries))
        print(f"bytecode written for the {n} files that the commands import (the list kept for "
              f"these packages)")
        return 0
    if (os.cpu_count() or 1) < 2:
        groups = [compile_group(group_names(0) + group_names(1))]
        how = "in one process"
    else:
        # Two processes at once; a module both import is written by each, atomically
        # (importlib writes a temporary file and renames it), so either copy is whole.
        children = [subprocess.Popen([sys.executable, __file__, "--group", str(k)],
                                     stdout=subprocess.PIPE, text=True)
                    for k in range(len(GROUPS))]
        outputs = [child.communicate()[0] for child in children]
        if any(child.returncode for child in children):
            print("compile_bytecode: a group failed", file=sys.stderr)
            return 1
        groups = [json.loads(out.splitlines()[-1]) for out in outputs]
        how = "in two processes"
    keep_list(kept, sorted(set().union(*groups)))
    loaded = " and ".join(str(len(g)) for g in groups)
    print(f"bytecode written for the modules the commands import ({loaded} loaded {how})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
