"""What a sweep will cost, said before it starts: case count, a rough time, compiling.

The time is a rough model of a case on one core of this project's 2-core machine, fitted
per integrator (:data:`_MODEL`) to the cases' seconds in a sweep's ``status.json``:

    seconds = per_case + T·√Z / step_safety · (per_cycle + per_cycle_load · P)

with ``T`` the simulated time [s], ``Z`` the balls and ``P`` the larger of the radial and
axial loads [N]. ``per_case`` is what a case costs whatever it simulates (its statics and
file); the rest grows with the ball count's square root (each step costs in proportion
to the balls, but more balls share the load and allow a longer step) and with the load
(the derived step shrinks as the contact load grows, more slowly than the radial load
beside a fixed axial one, hence the constant beside the load term). With a fixed
``time_step`` a case costs ``per_ball_step`` a ball and a step instead. A flexible ring
multiplies it by :data:`FLEXIBLE_COST`, the lubricated law by :data:`LUBRICATED_COST`.
Another machine or a loaded one moves it: it is for "a minute or an hour", not for
planning.
"""
from __future__ import annotations

import math
import os
import sys
from typing import NamedTuple


class _Cost(NamedTuple):
    per_case: float        # [s]
    per_cycle: float       # [s] per (s of cycle × √balls / step_safety)
    per_cycle_load: float  # [s N^-1] per (s of cycle × √balls / step_safety)
    per_ball_step: float   # [s] per ball per step, at a fixed time_step


#: Each integrator's model (module docstring), from `make sweep` and `make smoke` on a
#: fresh clone of this project's 2-core machine:
#:
#: - ``imex``, the default: MODEL_VERSION 23, 2026-11-30. The study sweep's 150 cases
#:   took 533.7 s of the cores, on average 3.30, 3.44, 3.44, 3.67 and 3.93 s at 20, 25,
#:   30, 35 and 40 kN radial (51 balls, 4.6 s cycle); the smoke sweep's 0.29 s (12 balls,
#:   0.46 s cycle). A ball-step 0.77–0.82 µs (``rvsweep bench --balls 51``, the short
#:   cycle; docs/performance.md).
#: - ``rk4``: MODEL_VERSION 9. A smoke case 3.0 s, a study case 20.0, 26.8 and 31.5 s at
#:   20, 30 and 40 kN; a ball-step 0.41 µs (``rvsweep bench``: 102 ns a ball a right-hand
#:   side, four a step).
_MODEL = {
    "imex": _Cost(per_case=0.14, per_cycle=0.0617, per_cycle_load=7.65e-7, per_ball_step=0.8e-6),
    "rk4": _Cost(per_case=1.8, per_cycle=0.164, per_cycle_load=1.40e-5, per_ball_step=0.41e-6),
}
#: A case with a flexible ring against the same bearing with rigid rings [-]: ``rvsweep
#: bench``'s ``flexible_cost_ratio``, 1.74–1.88× (docs/performance.md).
FLEXIBLE_COST = 1.8
#: A case with the lubricated law (``ehl_bair_winer``) against the dry one [-]: ``rvsweep
#: bench``'s ``lubricated_cost_ratio``, 1.03× at 120 °/s to 1.20× at 660 °/s
#: (docs/performance.md).
LUBRICATED_COST = 1.1

#: Above either, ``rvsweep sweep`` starts only with ``--yes``.
CONFIRM_CASES = 1000
CONFIRM_SECONDS = 4 * 3600.0


def case_seconds(spec) -> float:
    """The rough time of one case on one core [s] (module docstring)."""
    from rvcore.bearing.laws import LUBRICATED_LAW

    from .cases import flexible

    s = spec.settings
    cost = _MODEL.get(s.method, _MODEL["rk4"])
    factor = ((FLEXIBLE_COST if flexible(spec.bearing) else 1.0)
              * (LUBRICATED_COST if spec.bearing.contact.law == LUBRICATED_LAW else 1.0))
    duration = (s.end_time or spec.profile.duration) - s.start_time
    balls = sum(row.ball_count for row in spec.bearing.rows)
    if s.time_step > 0:
        return factor * (cost.per_case + cost.per_ball_step * balls * duration / s.time_step)
    op = spec.operating_point
    peak = max(abs(op.radial_load), abs(op.axial_load), 1e3)
    per_cycle = duration * math.sqrt(balls) / max(s.step_safety, 1e-9)
    return factor * (cost.per_case + per_cycle * (cost.per_cycle + cost.per_cycle_load * peak))


def sweep_seconds(specs, workers: int) -> float:
    """The rough wall time of ``specs`` on ``workers`` cores [s]: their sum shared out,
    but never less than the longest case."""
    times = [case_seconds(c) for c in specs]
    return max(sum(times) / max(workers, 1), max(times, default=0.0))


def duration_text(seconds: float) -> str:
    """``"40 s"``, ``"12 min"``, ``"3.5 h"``: as rough as the estimate."""
    if seconds < 90:
        return f"{max(1, round(seconds, -1 if seconds >= 20 else 0)):.0f} s"
    if seconds < 90 * 60:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def local_workers(requested: int | None, n_cases: int) -> int:
    """How many processes the local cluster will have (as :func:`cluster.client` sizes it)."""
    return max(1, min(int(requested or os.cpu_count() or 1), max(n_cases, 1)))


def kernels_need_compiling() -> bool:
    """Whether the next run compiles the numba kernels: no cached kernel in the cache
    directory of rvcore's present sources (``rvcore._numba.cache_dir``)."""
    try:
        from rvcore._numba import cache_dir
    except ImportError:
        return False
    try:
        return not any(cache_dir().rglob("*.nbi"))
    except OSError:
        return True


def say_if_compiling(stream=None) -> bool:
    """Print one line when the kernels are about to be compiled; True if they are."""
    if not kernels_need_compiling():
        return False
    print("compiling the numba kernels (once per rvcore's sources and CPU model, for every "
          "clone; 1-2 minutes on a 2-core machine) ...", file=stream or sys.stderr, flush=True)
    return True
