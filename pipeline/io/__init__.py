"""Variables, NetCDF files and results folders."""
from .case import (PHASE_METRICS, REFERENCES, SENSOR_METRICS, VARIABLES, case_dataset, encoding_for,
                   git_commit, phase_coordinate, write_case)
from .netcdf import (CASE_STATUS, UDUNITS, case_status_variable, cf_name, combined_encoding,
                     history_line, remove_stale_temporaries, write_atomic, write_text_atomic)
