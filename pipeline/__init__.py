"""Orchestration, I/O and reporting for rv-bearing-sweep.

``rvcore`` computes in SI; this package reads the inputs, runs the cases and writes the
files and the report (see ``README.md``):

- :mod:`pipeline.schema`: the input files (bearing, profile, sweep TOML), units, case ids;
- :mod:`pipeline.io`: case datasets, combined sweeps, NetCDF conventions, atomic writing,
  ``status.json``;
- :mod:`pipeline.run`: running a sweep's cases (serially or on dask) into its folder;
- :mod:`pipeline.analysis`: phase metrics (``metrics.nc``) and trend fits (``fits.nc``);
- :mod:`pipeline.report`: the report (Markdown and HTML with figures);
- :mod:`pipeline.commands`: the ``rvsweep`` subcommands;
- :mod:`pipeline.cli`: ``rvsweep``, the command line;
- :mod:`pipeline.bench`: performance figures (``rvsweep bench``);
- :mod:`pipeline.errors`: the errors a user sees as one line.
"""
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("rv-bearing-sweep")
except PackageNotFoundError:  # running from a source tree without an install
    __version__ = "0.0.0+unknown"
