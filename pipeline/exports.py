"""Names a package re-exports from its modules, imported on first use (PEP 562).

A command such as ``rvsweep --help`` or ``rvsweep check`` needs a few names of
:mod:`pipeline.io` or :mod:`pipeline.schema`, not xarray, numba and dask behind the rest:
so the packages' ``__init__`` modules name where each of their names lives, and a name's
module is imported when the name is first read.
"""
from __future__ import annotations

import importlib
import sys


def attach(package: str, exports: dict[str, tuple[str, ...]]):
    """``(__getattr__, __dir__, __all__)`` for ``package``: each of ``exports``' modules
    (relative to ``package``: ``".case"``, ``"..schema.reference"``) maps to the names it
    gives. A name read is imported from its module and kept in the package."""
    where = {name: module for module, names in exports.items() for name in names}
    names = sorted(where)

    def __getattr__(name: str):
        try:
            module = where[name]
        except KeyError:
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        value = getattr(importlib.import_module(module, package), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__():
        return sorted(set(names) | set(vars(sys.modules[package])))

    return __getattr__, __dir__, names
