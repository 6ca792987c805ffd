"""The fit report: Markdown and HTML with PNG figures."""
from .build import build_report
from .context import ensemble_statistics, sensors
