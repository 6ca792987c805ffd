"""Orchestration, I/O and reporting for rv-bearing-sweep.

Layers (see ``README.md``): ``rvcore`` computes in SI; ``pipeline.case`` turns one
computed case into a labelled ``xarray.Dataset``; ``pipeline.sweep`` runs grids of cases
with dask; ``pipeline.report`` fits trends and writes the report.
"""
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("rv-bearing-sweep")
except PackageNotFoundError:  # running from a source tree without an install
    __version__ = "0.0.0+unknown"
