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

Usage: ``python tools/compile_bytecode.py``.
"""
from __future__ import annotations

import importlib
import sys

#: What the commands, the sweep's workers and the tests import.
MODULES = (
    "pipeline.cli", "pipeline.report.build", "pipeline.report.figures", "pipeline.run.cluster",
    "pipeline.run.cases", "pipeline.bench", "rvcore.simulation.run", "distributed", "dask.array",
    "xarray.backends.netCDF4_", "matplotlib.pyplot", "matplotlib.backends.backend_agg",
    "scipy.stats", "pytest", "xdist", "hypothesis", "compliance_checker.runner",
)


def main() -> int:
    sys.dont_write_bytecode = False     # what PYTHONDONTWRITEBYTECODE turned off, for this process
    from pipeline.cli import COMMANDS

    names = MODULES + tuple(f"pipeline.commands.{c}" for c in COMMANDS)
    for name in names:
        try:
            importlib.import_module(name)
        except Exception as exc:  # an optional extra not installed: nothing to compile
            print(f"compile_bytecode: {name} not imported ({type(exc).__name__})", file=sys.stderr)
    n = sum(1 for m in list(sys.modules.values())
            if isinstance(getattr(m, "__file__", None), str) and m.__file__.endswith(".py"))
    print(f"bytecode written for the modules the commands import ({n} loaded)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
