"""The fit report: Markdown and HTML with PNG figures."""
from .build import build_report, ensemble_statistics, sensors
