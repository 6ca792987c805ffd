"""Phase metrics over a sweep, and the fits of their trends.

- :mod:`~pipeline.analysis.metrics`: a results folder opened, and its phase metrics (``metrics.nc``);
- :mod:`~pipeline.analysis.fits`: least-squares trends of the metrics over the axes (``fits.nc``);
- :mod:`~pipeline.analysis.regression`: single fits: lines, the interaction plane, bands;
- :mod:`~pipeline.analysis.compare`: a measured rig trace beside a simulated case;
- :mod:`~pipeline.analysis.duty`: the duty cycle from a trace's speed and load channels;
- :mod:`~pipeline.analysis.measured`: the measured cases of a sweep folder in its metrics and fits;
- :mod:`~pipeline.analysis.statistics`: percentiles and Sobol' indices over ``[statistics]`` draws (``statistics.nc``).
"""
from ..exports import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    "..schema.reference": ("ReferenceFit", "default_reference_path", "load_reference_fits"),
    ".fits": ("DISPLACEMENT_COORD", "fit_metrics", "fit_statistic", "write_fits"),
    ".metrics": ("DESIGNER_METRICS", "DESIGNER_SCALARS", "REALIZATION", "SCALARS", "STIFFNESS", "case_states",
                 "nearest", "open_results", "phase_metrics", "write_metrics"),
    ".statistics": ("STATISTICS_FILE", "statistics_dataset"),
    ".regression": ("LEVEL", "LINE_STATS", "PLANE_STATS", "line_band", "linear_fit", "plane_fit",
                    "weighted_linear_fit"),
})
