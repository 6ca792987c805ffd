"""Variables, NetCDF files, atomic writing and the results folder's status."""
from .case import (PHASE_METRICS, REFERENCES, SENSOR_METRICS, VARIABLES, case_dataset,
                   git_commit, phase_coordinate, write_case)
from .files import (history_line, remove_stale_temporaries, utc_stamp, write_atomic,
                    write_bytes_atomic, write_text_atomic)
from .netcdf import (CASE_STATUS, case_status_variable, cf_name, combined_encoding, encoding_for,
                     strip_encoding)
from .status import STATUS_FILE, CaseState, read_status, status_counts, write_status
from .combine import CaseEntry, GridAxis, combine_cases, common_time_grid, grid_from_cases
