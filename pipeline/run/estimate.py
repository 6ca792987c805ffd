"""What a sweep will cost, said before it starts: case count, a rough time, compiling.

The time is a rough model fitted to `make sweep` and `make smoke` on a fresh clone of
this project's 2-core machine (MODEL_VERSION 9, RK4, step_safety 0.8; the seconds of each
case in the sweep's status.json): a smoke case (12 balls, 0.46 s cycle, 30 kN) costs
3.0 s of one core, a study case (51 balls, 4.6 s cycle, 2 sensors) 20.0, 26.8 and 31.5 s at
20, 30 and 40 kN radial (means over speeds and draws). A case costs a fixed part (the
statics, the start, the files: about 1.8 s) and a part per simulated second, which grows
with the ball count's square root (each step costs in proportion to the balls, but more
balls share the load and allow a longer step) and with the load (the derived step
shrinks with the contact load, ``rvcore.integrate.rk4.rk4_time_step``; the peak contact load
grows more slowly than the radial load beside a fixed axial one, hence a constant beside
the load term). With a fixed ``time_step`` a step costs about 0.41 us per ball
(``rvsweep bench``: 102 ns per ball per right-hand side, four per RK4 step). Another
machine, a loaded one or another method moves it: it is for "a minute or an hour", not
for planning.
"""
from __future__ import annotations

import math
import os
import sys

#: Seconds of one core per case, whatever it simulates.
_PER_CASE = 1.8
#: Seconds of one core per (second of cycle x sqrt(balls) / step_safety), at no load ...
_PER_CYCLE = 0.164
#: ... and per newton of peak load on top.
_PER_CYCLE_LOAD = 1.40e-5
#: Seconds of one core per ball per step at a fixed time_step (RK4).
_PER_BALL_STEP = 0.41e-6
#: IMEX's cost of a case relative to the RK4 model above, fitted to the study sweep's
#: cases with IMEX, the default since MODEL_VERSION 12 (`make sweep` on a fresh clone,
#: 2026-11-29, MODEL_VERSION 19: their cores took 821.5 s in all, 4.62 s a case at 20 kN
#: and 6.63 s at 40 kN on average; 0.153 gave 820 s, 4.59 s and 6.35 s), times 0.874,
#: what MODEL_VERSION 20's longer step where the loads are held took of 19's in `make
#: sweep` runs side by side (768 s against 879.5 s of the cores), times 0.918, what
#: MODEL_VERSION 21's start shared by a grid's speeds took of 20's (1,431.7 s against
#: 1,559.7 s of the cores in two pairs; a sweep whose speeds share no start is
#: overestimated by that much).
_METHOD = {"rk4": 1.0, "imex": 0.123}

#: Above either, ``rvsweep sweep`` starts only with ``--yes``.
CONFIRM_CASES = 1000
CONFIRM_SECONDS = 4 * 3600.0


def case_seconds(spec) -> float:
    """The rough time of one case on one core [s] (module docstring)."""
    s = spec.settings
    duration = (s.end_time or spec.profile.duration) - s.start_time
    balls = sum(row.ball_count for row in spec.bearing.rows)
    method = _METHOD.get(s.method, 1.0)
    if s.time_step > 0:
        return _PER_CASE + _PER_BALL_STEP * balls * duration / s.time_step * method
    op = spec.operating_point
    peak = max(abs(op.radial_load), abs(op.axial_load), 1e3)
    per_cycle = duration * math.sqrt(balls) / max(s.step_safety, 1e-9)
    return _PER_CASE + per_cycle * (_PER_CYCLE + _PER_CYCLE_LOAD * peak) * method


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
    print("compiling the numba kernels (once after an install or an rvcore change; about "
          "a minute on a 2-core machine) ...", file=stream or sys.stderr, flush=True)
    return True
