"""Running a sweep: cases, scheduling on dask, status."""
from .runner import read_status, run_one_case, run_sweep, status_counts, summary
