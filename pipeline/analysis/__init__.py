"""Phase metrics over a sweep, and the fits of their trends."""
from .fits import (DISPLACEMENT_COORD, LINE_STATS, PLANE_STATS, compose_units, default_reference_path,
                   fit_metrics, fit_statistic, line_band, linear_fit, load_reference_fits, plane_fit,
                   udunits_to_pint, write_fits)
from .metrics import (REALIZATION, case_states, load_sweep, nearest, phase_metrics,
                      write_metrics)
