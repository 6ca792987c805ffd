"""Compile to bytecode, once, every module that rvsweep, its dask workers and the tests import.

``make venv`` runs this after ``pip install --no-compile``. Where PYTHONDONTWRITEBYTECODE is
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

Usage: ``python tools/compile_bytecode.py``.
"""
from __future__ import annotations

import importlib
import os
import subprocess
import sys

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


def compile_group(names) -> int:
    """Import ``names``; the number of source modules loaded."""
    for name in names:
        try:
            importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name != name.split(".")[0]:   # the test extras are not installed for a sweep: nothing to say
                print(f"compile_bytecode: {name} not imported ({exc})", file=sys.stderr)
        except Exception as exc:  # noqa: BLE001 - a broken install: said, and the rest compiled
            print(f"compile_bytecode: {name} not imported ({type(exc).__name__})", file=sys.stderr)
    return sum(1 for m in list(sys.modules.values())
               if isinstance(getattr(m, "__file__", None), str) and m.__file__.endswith(".py"))


def group_names(k: int) -> tuple:
    """Group ``k``'s modules; the first also takes every ``pipeline.commands`` module."""
    if k:
        return GROUPS[k]
    from pipeline.cli import COMMANDS

    return GROUPS[0] + tuple(f"pipeline.commands.{c}" for c in COMMANDS)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    sys.dont_write_bytecode = False     # what PYTHONDONTWRITEBYTECODE turned off, for this process
    if argv[:1] == ["--group"]:           # a child of the parallel run below
        print(compile_group(group_names(int(argv[1]))))
        return 0
    if (os.cpu_count() or 1) < 2:
        loaded = f"{compile_group(group_names(0) + group_names(1))} loaded"
    else:
        # Two processes at once; a module both import is written by each, atomically
        # (importlib writes a temporary file and renames it), so either copy is whole.
        children = [subprocess.Popen([sys.executable, __file__, "--group", str(k)],
                                     stdout=subprocess.PIPE, text=True)
                    for k in range(len(GROUPS))]
        counts = [child.communicate()[0] for child in children]
        if any(child.returncode for child in children):
            print("compile_bytecode: a group failed", file=sys.stderr)
            return 1
        loaded = " and ".join(c.split()[-1] for c in counts) + " loaded in two processes"
    print(f"bytecode written for the modules the commands import ({loaded})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
