"""The step schedule: the fixed step by stretches of the cycle, longer where the loads and
speed are held, and where the ring stands still while its loads fall. SI throughout.

Why
---
A method's step (``time_step`` of :mod:`rvcore.integrate.imex`, :mod:`rvcore.integrate.rk4`)
is sized for the whole cycle, so for its hardest stretch: in the load ramps race contacts
close and balls strike their pockets. Where every channel of the profile (the loads, the
moment, the load's direction and the speed) is held, what sizes the step is the motion
the bearing keeps up by itself; for IMEX that stretch takes the held tableau and its
own, longer step (:func:`rvcore.integrate.imex.imex_time_step` with ``held``). On the
study cycle that is the steady phase, 0.8–3.8 s (the held stretch 0.8–3.79 s).

So is a stretch where the inner ring stands still and no load grows
(:func:`unloading_windows`): the study cycle's unload, 4.3–4.6 s. No ball rolls there, so
none is carried into its pocket or through the load zone, and a contact that the falling
loads open does not close again; the rings follow loads that change over 0.3 s against a
contact oscillation of about 57 µs, so the step is sized by that oscillation too, not by
the friction's stiff modes, which the held tableau damps. Not where the loads rise at
standstill (the load ramp, 0–0.3 s): there contacts close. On the study bearing the
unload then takes 5,100–5,700 steps instead of 7,800–11,400 (3–5 % of a case's); the
phase metrics end at 4.3 s and are unchanged, and the unload's displacements are as close
to those at a tenth of the step as the plain tableau's were (docs/performance.md, "The
unload in the held tableau").

A held stretch ends :data:`HELD_END_MARGIN` before its window does, where the profile
moves on after the window (a channel changes), wherever the run itself ends: so a run cut
in two inside the window or at its end takes the same stretches, at the same steps, as
the whole run. The
last of the window runs at the plain step and tableau, so that what follows the window starts from
the motion the plain tableau carries. The held tableau damps a slow part of the rings'
motion that the physics keeps; ended at the window's edge, the study bearing's
deceleration axial range at 600 °/s, 40 kN + 10 kN (seed 2) came out 1.36 % below a tenth
of the step, ended 2, 5, 10 and 20 ms before it 0.92, 0.57, 0.14 and 0.12 % below
(docs/performance.md, "The held tableau"). The margin costs about 90 steps of a
study case's 95,000.

Each stretch's step divides the output interval, and a held stretch starts and ends on
an output time (inside the held window), so the outputs keep the times
``t_start + k/output_rate`` of a schedule without stretches. The step changes inside the
loop (:func:`rvcore.integrate.loop.integrate`): the state, the phase reductions and the
drive torque's filter run on; the method begins each stretch with its own constants
(``begin_segment``: IMEX's pocket tolerance, its tableau and new tangents).

A schedule is an array of rows, one a stretch, with the columns :data:`SEG_STEPS` (its
steps), :data:`SEG_DT` (their size [s]), :data:`SEG_OUT_EVERY` (steps between output
lines), :data:`SEG_HELD` (1 where the held tableau runs: :func:`held_tableau_windows`), :data:`SEG_TOL` (the
method's ``segment_constant`` at that step), :data:`SEG_LOAD_TOL` (the method's
``load_tolerance``: IMEX's tangents' [N]), and :data:`SEG_SLIP2` and :data:`SEG_SUB_DT` (the
method's ``falling_guard``: where the stretch's step does not keep the friction law's
falling slope within its bound, the squared slip [m² s^-2] above which a step is taken in
substeps, and the longest substep [s]; 0 and 0 where it does). All are sized on the peak
contact load the schedule is given: a run in two parts
(:mod:`rvcore.simulation.shared_start`) sizes each on its own.
"""
from __future__ import annotations

import math

import numpy as np

from ..profile import CH_AXIAL, CH_DIRECTION, CH_MOMENT, CH_RADIAL, CH_SPEED, channel_value

SEG_STEPS, SEG_DT, SEG_OUT_EVERY, SEG_HELD, SEG_TOL, SEG_LOAD_TOL, SEG_SLIP2, SEG_SUB_DT = range(8)
N_SEG = 8

#: How long before its held window's end a held stretch ends [s] (module docstring).
HELD_END_MARGIN = 0.01


def _windows_where(resolved, t_start: float, t_end: float, holds) -> list:
    """The windows ``(a, b)`` [s] within ``[t_start, t_end]`` joined from the intervals
    between consecutive breakpoints of all the channels together for which
    ``holds(value, a, b)`` is true, ``value(c, t)`` the resolved channel ``c`` at ``t``.

    Between two such breakpoints each channel's interpolation (linear or smoothstep) is
    monotone, so what its values at both ends say holds throughout."""
    tables = resolved.channels()
    table, meta = resolved.arrays()

    def value(c, t):
        return channel_value(table, meta, c, t)

    knots = sorted({float(t) for times, _, _ in tables for t in times if t_start < t < t_end}
                   | {t_start, t_end})
    windows = []
    for a, b in zip(knots[:-1], knots[1:]):
        if not holds(value, a, b):
            continue
        if windows and windows[-1][1] == a:
            windows[-1] = (windows[-1][0], b)
        else:
            windows.append((a, b))
    return windows


def held_windows(resolved, t_start: float, t_end: float) -> list:
    """The windows ``(a, b)`` [s] within ``[t_start, t_end]`` over which every channel of
    the resolved profile is constant: between two breakpoints a channel is constant if and
    only if its values at both ends agree (:func:`_windows_where`).
    """
    n = len(resolved.channels())
    return _windows_where(resolved, t_start, t_end,
                          lambda value, a, b: all(value(c, a) == value(c, b) for c in range(n)))


def unloading_windows(resolved, t_start: float, t_end: float) -> list:
    """The windows ``(a, b)`` [s] within ``[t_start, t_end]`` over which the inner ring
    stands still (the speed channel is zero) and no load grows: the radial and axial loads
    and the moment keep their signs and do not grow in magnitude, and the load's direction
    is held (the study cycle's unload, 4.3–4.6 s).

    Between two breakpoints a channel is monotone (:func:`_windows_where`), so one whose
    values at both ends have the same sign (or a zero) and a magnitude no larger at the end
    does not grow in magnitude there.
    """
    def unloading(value, a, b):
        return (value(CH_SPEED, a) == 0.0 and value(CH_SPEED, b) == 0.0
                and value(CH_DIRECTION, a) == value(CH_DIRECTION, b)
                and all(value(c, a) * value(c, b) >= 0.0 and abs(value(c, b)) <= abs(value(c, a))
                        for c in (CH_RADIAL, CH_AXIAL, CH_MOMENT)))

    return _windows_where(resolved, t_start, t_end, unloading)


def held_tableau_windows(resolved, t_start: float, t_end: float) -> list:
    """The windows ``(a, b)`` [s] within ``[t_start, t_end]`` where the held tableau and
    step run: those of :func:`held_windows` and of :func:`unloading_windows`, joined where
    they touch or overlap, in order."""
    joined = []
    for a, b in sorted(held_windows(resolved, t_start, t_end) + unloading_windows(resolved, t_start, t_end)):
        if joined and a <= joined[-1][1]:
            joined[-1] = (joined[-1][0], max(joined[-1][1], b))
        else:
            joined.append((a, b))
    return joined


def _fitted(dt_max: float, output_rate: float):
    """``(out_every, dt)``: the largest step ≤ ``dt_max`` [s] that divides the output
    interval ``1/output_rate`` [s], and the steps in that interval."""
    out_every = max(1, int(math.ceil(1.0 / (output_rate * dt_max) - 1e-9)))
    return out_every, 1.0 / (output_rate * out_every)


def step_schedule(method, model, peak_contact_load: float, resolved, t_start: float, t_end: float,
                  output_rate: float, *, safety: float = 0.8, time_step: float = 0.0) -> np.ndarray:
    """The step schedule of a run from ``t_start`` to ``t_end`` [s] (module docstring).

    Parameters
    ----------
    method : module
        The method (:data:`rvcore.integrate.methods.METHODS`): its ``time_step``,
        ``segment_constant``, ``load_tolerance`` and ``falling_guard``.
    model : CompiledBearing
    peak_contact_load : float
        The case's peak contact load [N], on which the steps are sized.
    resolved : rvcore.profile.ResolvedProfile
    t_start, t_end : float
        The run's window [s].
    output_rate : float
        Output lines per second [Hz]; every step divides its interval.
    safety : float
        The steps' share of their bounds [-] (``SolverSettings.step_safety``).
    time_step : float
        A step set by hand [s] (``SolverSettings.time_step``; 0: none): then the schedule
        is one stretch of it, the held windows too.

    Returns
    -------
    ndarray (n, N_SEG)
        One row a stretch, the columns ``SEG_*``.
    """
    if time_step > 0:
        out_every, dt = _fitted(time_step, output_rate)
        held_every, dt_held = out_every, dt
    else:
        out_every, dt = _fitted(method.time_step(model, peak_contact_load, safety=safety), output_rate)
        held_every, dt_held = _fitted(method.time_step(model, peak_contact_load, safety=safety, held=True),
                                      output_rate)
    rows = []
    k = 0                      # the output line where the next stretch starts
    if dt_held > dt:
        upper = max(t_end, resolved.duration)
        for a, b in held_tableau_windows(resolved, t_start, upper):
            if a >= t_end:
                break
            if b < upper:           # the profile moves on after the window, wherever the run ends
                b -= HELD_END_MARGIN
            k_a = max(int(math.ceil((a - t_start) * output_rate - 1e-9)), k)
            k_b = int(math.floor((min(b, t_end) - t_start) * output_rate + 1e-9))
            if t_start + k_b / output_rate > t_end or k_b <= k_a:
                continue
            if k_a > k:
                rows.append([(k_a - k) * out_every, dt, out_every, 0.0] + [0.0] * (N_SEG - 4))
            rows.append([(k_b - k_a) * held_every, dt_held, held_every, 1.0] + [0.0] * (N_SEG - 4))
            k = k_b
    t_last = t_start + k / output_rate
    n_last = int(math.ceil((t_end - t_last) / dt - 1e-6))
    if n_last > 0 or not rows:
        rows.append([n_last, dt, out_every, 0.0] + [0.0] * (N_SEG - 4))
    schedule = np.array(rows, dtype=float)
    for row in schedule:
        row[SEG_TOL] = method.segment_constant(model, peak_contact_load, row[SEG_DT])
        row[SEG_LOAD_TOL] = method.load_tolerance(peak_contact_load)
        row[SEG_SLIP2], row[SEG_SUB_DT] = method.falling_guard(model, peak_contact_load, safety=safety,
                                                               held=row[SEG_HELD] != 0.0)
    return schedule


def uniform_schedule(n_steps: int, dt: float, out_every: int, constant: float = 0.0,
                     load_tolerance: float = 0.0) -> np.ndarray:
    """One stretch of ``n_steps`` steps of ``dt`` [s], an output line every ``out_every``,
    the method's ``constant`` (:data:`SEG_TOL`; IMEX: its pocket tolerance [J]) and
    ``load_tolerance`` (:data:`SEG_LOAD_TOL`; IMEX: its tangents' [N])."""
    return np.array([[n_steps, dt, out_every, 0.0, constant, load_tolerance, 0.0, 0.0]], dtype=float)


def output_lines(schedule: np.ndarray) -> int:
    """The most output lines a run of ``schedule`` writes."""
    return int(sum(int(s[SEG_STEPS]) // int(s[SEG_OUT_EVERY]) + 1 for s in schedule)) + 1
