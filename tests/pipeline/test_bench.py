"""The benchmark's pieces run against the current integrator (no timings are asserted).

``rvsweep bench`` calls the numba integrator directly, outside ``run_case``; a change to
the integrator's signature once broke it unnoticed. This runs its scipy comparison on a
1 ms window so that such a break fails here. Speed itself is measured by the command,
never asserted.
"""
from __future__ import annotations

import math

from pipeline.bench import scipy_comparison


def test_scipy_comparison_runs_and_matches_accuracy():
    figures = scipy_comparison(window=1e-3, repeats=1)
    # DOP853 was driven to at least our accuracy on the same window, and both ran
    assert math.isfinite(figures["scipy_ratio"]) and figures["scipy_ratio"] > 0, figures
