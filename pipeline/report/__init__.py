"""The fit report: Markdown and HTML with PNG figures."""
from ..exports import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    ".build": ("build_report",),
    ".context": ("ensemble_statistics", "sensors"),
})
