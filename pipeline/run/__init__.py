"""Running a sweep: cases, scheduling on dask."""
from .cases import run_one_case
from .runner import run_sweep, summary
