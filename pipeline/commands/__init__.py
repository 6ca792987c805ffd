"""The ``rvsweep`` subcommands, one module each (:mod:`pipeline.cli` dispatches to them).

- :mod:`~pipeline.commands.check`: ``rvsweep check``: validate bearing, profile and sweep files;
- :mod:`~pipeline.commands.sweep`: ``rvsweep sweep``: run a sweep file's cases into ``sweep.nc``;
- :mod:`~pipeline.commands.report`: ``rvsweep report``: metrics, fits and the report of a sweep;
- :mod:`~pipeline.commands.simulate`: ``rvsweep simulate``: one dynamic case as NetCDF;
- :mod:`~pipeline.commands.statics`: ``rvsweep statics``: quasi-static equilibrium under a load;
- :mod:`~pipeline.commands.bench`: ``rvsweep bench``: performance figures;
- :mod:`~pipeline.commands.common`: argument helpers the commands share.
"""
