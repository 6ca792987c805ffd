"""Running a sweep: cases, scheduling on dask.

- :mod:`~pipeline.run.runner`: a sweep's run into its folder, and ``sweep.nc`` (:func:`run_sweep`);
- :mod:`~pipeline.run.cases`: one case computed (on any worker) and labelled (here);
- :mod:`~pipeline.run.cluster`: where the cases run: serially, on a local or an existing dask cluster;
- :mod:`~pipeline.run.estimate`: a sweep's cost said before it starts.
"""
from ..exports import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    ".cases": ("run_one_case",),
    ".runner": ("run_sweep", "summary"),
})
