"""Running a sweep: cases, scheduling on dask."""
from ..io import read_status, status_counts  # noqa: F401  (status lives in pipeline.io)
from .runner import run_one_case, run_sweep, summary
