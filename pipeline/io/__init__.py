"""Variables, NetCDF files, atomic writing and the results folder's status.

- :mod:`~pipeline.io.case`: one case's arrays as a labelled dataset (the case file's variables);
- :mod:`~pipeline.io.combine`: case datasets laid on a grid of sweep axes (``sweep.nc``'s variables);
- :mod:`~pipeline.io.netcdf`: NetCDF conventions: CF names, encodings, the case-status flags;
- :mod:`~pipeline.io.files`: atomic writing of every file, ``history`` lines;
- :mod:`~pipeline.io.folders`: output folders checked before work, the one-sweep-per-folder lock;
- :mod:`~pipeline.io.status`: ``status.json``, where each case of a sweep stands.
"""
from ..exports import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    ".case": ("PHASE_METRICS", "REFERENCES", "SENSOR_METRICS", "VARIABLES", "case_dataset", "git_commit",
              "phase_coordinate", "write_case"),
    ".files": ("WriteError", "file_digest", "history_line", "remove_stale_temporaries", "utc_stamp",
               "write_atomic", "write_bytes_atomic", "write_text_atomic"),
    ".netcdf": ("CASE_STATUS", "case_status_variable", "cf_name", "combined_encoding", "encoding_for",
                "strip_encoding"),
    ".status": ("STATUS_FILE", "STATUS_LOG", "CaseState", "StatusLog", "read_status", "status_counts",
                "write_status"),
    ".combine": ("CaseEntry", "GridAxis", "combine_cases", "common_time_grid", "grid_from_cases"),
})
