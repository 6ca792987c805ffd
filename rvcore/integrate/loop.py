"""The integration loop: one fixed-step method per call, the accumulators and the
blow-up checks. SI throughout.

The loop owns what every method shares: the right-hand side at each step's state (its
diagnostics are the outputs' signals, :mod:`rvcore.output_table`), the blow-up checks, the
output lines, the per-phase reductions (:mod:`rvcore.recording.plan`) and the drive torque's
filter. It knows no method by name: a step is the method's ``evaluate`` and ``step``
(:mod:`rvcore.integrate.methods`, :mod:`rvcore.integrate.protocol`), its size the
method's ``time_step`` by the stretches of the step schedule
(:mod:`rvcore.integrate.schedule`), each begun by the method's ``begin_segment``.
"""
from __future__ import annotations

import math

import numpy as np

from .._numba import kernel

from ..dynamics.energy import gravity_potential, kinetic_energy, ring_load_coefficients
from ..dynamics.races import SCRATCH_SIZE
from ..dynamics.rhs import D_MAX_PEN, D_PEN_BALL
from ..recording.plan import (SL_LOAD_POWER_STEP, SL_POWER_STEP, SL_TORQUE_BAND, SL_TORQUE_STEP, add_integral_end,
                              fill_state_signals, in_window, reduce_step, write_series)
from .methods import NAMES, begin_segment, evaluate, method, step
from .schedule import SEG_DT, SEG_LOAD_TOL, SEG_OUT_EVERY, SEG_STEPS, SEG_TOL
from .protocol import S_REFRESHES, S_SUBSTEPPED, S_SUBSTEPS

OK, NONFINITE, PENETRATION, ENERGY = 0, 1, 2, 3

#: The loop's own values a run hands on to the call that continues it (``carry``,
#: :func:`integrate`): the drive torque's two filter stages [N m], the end weight of the
#: step just taken [s], its start [s], whether no step has been taken yet (1/0), the
#: output lines written, and whether the schedule's last stretch ends the run (1/0; 0
#: for a run continued by another call, :class:`Scratch`).
C_TORQUE_F1, C_TORQUE_F2, C_END_HALF, C_T_PREV, C_FIRST, C_N_OUT, C_ENDS = range(7)
N_CARRY = 7

#: Bandwidth of the drive torque whose peak is reported (``inner_ring_drive_torque_peak``)
#: [Hz]: two cascaded first-order low-passes of this corner (a critically damped
#: second-order filter, as a torque transducer or the drive's current loop would see it)
#: on the contacts' part ``−M_c·e``; the prescribed ``I_p·ω̇`` is added unfiltered. Why:
#: the instantaneous torque carries the contact oscillation (ω_n ≈ 1.1e5 rad/s, 17 kHz on
#: the study bearing) through the friction, a chatter whose sampled peak depends on the
#: step and is no load a drive train transmits. 1 kHz keeps the bearing's kinematic
#: ripple (the ball pass is 50 Hz at 660 °/s: attenuated by 0.25 %) and takes the 17 kHz
#: chatter down 300×.
TORQUE_BANDWIDTH = 1.0e3

# FAST (rvcore._numba: no fast-math flags) keeps IEEE semantics, so the non-finite check
# below works and the state sums are rounded in the same order on every CPU.
@kernel
def integrate(y, t_start, segments, params, rows, arcs, pockets, table, meta,
              phases, sensors, out, out_time, acc, series, reductions, diag, bdiag, work, pen_limit, ke_limit,
              cos_nominal, code, jwork, schur, inner, state, carry):
    """Advance ``y`` in place through the step schedule ``segments`` with the method of
    ``code`` (its place in :data:`rvcore.integrate.methods.METHODS`; :class:`Scratch`
    holds its scratch ``work``, ``jwork``, ``schur``, ``inner``, its counters ``state`` and
    the loop's own ``carry``).

    ``segments[s]`` is a stretch of the schedule (:mod:`rvcore.integrate.schedule`): its
    steps, their size [s], the steps between output lines, whether the loads and speed
    are held over it, and the method's constants for that step
    (:data:`rvcore.integrate.schedule.SEG_STEPS` …); the stretches follow one another,
    each starting where the last ended. Every ``out_every`` steps of a stretch (and at
    the first and last step) a line of ``out`` is written, the columns of the series plan
    ``series``, and its time into ``out_time``. At every step the state at the step's
    start is reduced into each accumulator line of ``acc`` whose window (``phases[k] =
    (start, end)``; the last line the whole cycle) holds it, by the reduction plan
    ``reductions`` (:func:`rvcore.recording.plan.build_plan`). ``sensors`` holds rows
    ``(px, py, pz, dx, dy, dz)``; ``cos_nominal[r]`` is cos α of row r's nominal contact
    angle.

    Returns
    -------
    status : int
        ``OK`` or the blow-up kind.
    t_fail : float
        Simulated time of the failure [s].
    where : int
        State index (non-finite) or ball state offset (penetration) of the culprit.
    n_out : int
        Lines written to ``out``.
    substepped : int
        Steps the method took again in substeps (IMEX: :func:`rvcore.integrate.imex.imex_step`).
    refreshes : int
        Steps at which the method evaluated and factored its tangents (substeps not
        counted).
    """
    n = y.size
    k1 = work[0]
    n_out = int(carry[C_N_OUT])
    n_ph = phases.shape[0]
    n_seg = segments.shape[0]
    torque_f1, torque_f2 = carry[C_TORQUE_F1], carry[C_TORQUE_F2]
    end_half = carry[C_END_HALF]   # the trapezoid's end weight of the step just taken
    gravity = gravity_potential(y, params, rows)
    t_seg = t_start        # where the stretch starts
    t = t_start
    first = carry[C_FIRST] != 0.0  # the run's first step
    t_prev = t_start if first else carry[C_T_PREV]   # the start of the step just taken
    ends = carry[C_ENDS] != 0.0
    for sg in range(n_seg):
        n_steps = int(segments[sg, SEG_STEPS])
        dt = segments[sg, SEG_DT]
        out_every = int(segments[sg, SEG_OUT_EVERY])
        last = sg == n_seg - 1 and ends
        half = 0.5 * dt
        # the band-limited drive torque (TORQUE_BANDWIDTH): two first-order stages, exact
        # for a torque held over each step, started at the first step's torque
        decay = 1.0 - math.exp(-2.0 * math.pi * TORQUE_BANDWIDTH * dt)
        # the method's constants for this stretch's step (IMEX: the pocket check's
        # tolerance, the held tableau where the loads are held; new tangents)
        begin_segment(code, segments[sg], work, state)
        for i in range(n_steps + 1):
            if i == n_steps and not last:
                break          # the next stretch's first step starts here
            t = t_seg + i * dt
            # the outputs' signals at the step's state (the stages skip the costly ones), and
            # whatever else the method takes from that evaluation (IMEX: its tangents)
            evaluate(code, t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur,
                     state)
            # blow-up checks on the state at t: x − x is 0 for a finite x, NaN otherwise (an
            # or over the state, which vectorises where a sum in order would not)
            bad = False
            for m in range(n):
                s = y[m] + k1[m]
                bad |= (s - s) != 0.0
            if bad:
                for m in range(n):
                    if not (math.isfinite(y[m]) and math.isfinite(k1[m])):
                        return NONFINITE, t, m, n_out, state[S_SUBSTEPPED], state[S_REFRESHES]
            if diag[D_MAX_PEN] > pen_limit:
                return PENETRATION, t, int(diag[D_PEN_BALL]), n_out, state[S_SUBSTEPPED], state[S_REFRESHES]
            fill_state_signals(diag, y, t, dt, table, meta, rows, bdiag, sensors, cos_nominal, params)
            if not first:
                # the step just taken started at t − dt, or in the last stretch
                tp = t - dt if i > 0 else t_prev
                for k in range(n_ph + 1):
                    if in_window(phases, k, n_ph, tp):
                        add_integral_end(acc[k], reductions, diag, end_half)
            if i < n_steps:
                for k in range(n_ph + 1):
                    if in_window(phases, k, n_ph, t):
                        reduce_step(acc[k], reductions, diag, t, 0, half)
            if i % out_every == 0 or i == n_steps:
                if kinetic_energy(y, params, rows) > ke_limit:
                    return ENERGY, t, -1, n_out, state[S_SUBSTEPPED], state[S_REFRESHES]
                write_series(out[n_out], series, diag)
                out_time[n_out] = t
                n_out += 1
            if i == n_steps:
                break
            # the loads' and gravity's work over the step: the fall of their potential across
            # it, the loads held at the step's midpoint. Exact for constant loads (the step's
            # displacement is its stages' weighted velocities, Σ b_i·v(Y_i)·h); the sampled
            # power F·v would alias the ring's vibration (rvcore.recording.plan.ENERGIES).
            q0, q1, q2, q3, q4 = y[0], y[1], y[2], y[3], y[4]
            # the step's drive torque Σ b_i·T(Y_i): the moment whose impulse the step gave
            # the balls, and its power Σ b_i·T(Y_i)·ω(t_i), the work that impulse did (the
            # drive's energy); the prescribed spin's I_p·ω̇ weighed over the stages alike; a
            # step taken in substeps adds their integrals (rvcore.recording.plan.add_substep_integrals)
            # and ends on a substep's weight
            torque, power, inertial, divisor = step(code, t, y, dt, params, rows, arcs, pockets, table, meta,
                                                    diag, bdiag, work, jwork, schur, state, inner, acc,
                                                    reductions, phases)
            end_half = half / divisor
            t_prev = t
            a0, a1, a2, a3, a4 = ring_load_coefficients(t + half, table, meta)
            gravity_after = gravity_potential(y, params, rows)
            diag[SL_LOAD_POWER_STEP] = (a0 * (y[0] - q0) + a1 * (y[1] - q1) + a2 * (y[2] - q2)
                                        + a3 * (y[3] - q3) + a4 * (y[4] - q4) + gravity - gravity_after) / dt
            gravity = gravity_after
            # the peak is band-limited (TORQUE_BANDWIDTH) in its contacts' part only: the
            # prescribed spin's I_p·ω̇ is known exactly, and its jumps at the profile's corners
            # would only lag; it is weighed over the stages as the step's torque is, so that
            # the filter sees the contacts' part alone
            if first:
                torque_f1 = torque_f2 = torque - inertial
            # the band-limited torque at t, the time whose phase it goes to: the filter's
            # output before this step's torque enters it (after, it is the output at t + dt,
            # which put the filter's decay over one step after a profile's corner into the
            # next phase's peak: an error growing as the step squared)
            diag[SL_TORQUE_BAND] = inertial + torque_f2
            if not first:
                torque_f1 += decay * (torque - inertial - torque_f1)
                torque_f2 += decay * (torque_f1 - torque_f2)
            first = False
            diag[SL_TORQUE_STEP] = torque
            diag[SL_POWER_STEP] = power
            for k in range(n_ph + 1):
                if in_window(phases, k, n_ph, t):
                    reduce_step(acc[k], reductions, diag, t, 1, half)
        t_seg = t_seg + n_steps * dt
    carry[C_TORQUE_F1], carry[C_TORQUE_F2], carry[C_END_HALF] = torque_f1, torque_f2, end_half
    carry[C_T_PREV], carry[C_FIRST], carry[C_N_OUT] = t_prev, 1.0 if first else 0.0, n_out
    return OK, t, -1, n_out, state[S_SUBSTEPPED], state[S_REFRESHES]


class Scratch:
    """What a run keeps between the calls of :func:`advance` that make it up: the method's
    scratch and counters (``work``, ``jwork``, ``schur``, ``state``, the substeps'
    integrals ``inner``) and the loop's own values (``carry``, :data:`N_CARRY`).

    A run split in two (:mod:`rvcore.simulation.shared_start`): the first call with
    ``ends=False`` stops where its schedule ends; a second with the same ``Scratch`` and
    the rest of the schedule goes on as if the stretches were one schedule's, each begun
    by the method's ``begin_segment``. :meth:`copy` lets one start serve several runs.
    """

    def __init__(self, method_name: str, model, schedule, diag, ends: bool = True):
        m = method(method_name)
        self.method_name = method_name
        self.work, self.jwork, self.schur = m.new_work(model, schedule[0, SEG_TOL], schedule[0, SEG_LOAD_TOL])
        self.state = m.new_state()
        self.inner = np.zeros(diag.size - SCRATCH_SIZE)
        self.carry = np.zeros(N_CARRY)
        self.carry[C_FIRST] = 1.0
        self.carry[C_ENDS] = 1.0 if ends else 0.0

    def copy(self) -> "Scratch":
        """An independent copy (every array copied)."""
        new = object.__new__(Scratch)
        new.method_name = self.method_name
        for name in ("work", "jwork", "schur", "state", "inner", "carry"):
            setattr(new, name, getattr(self, name).copy())
        return new


def advance(method_name: str, y, t_start, schedule, model, table, meta, phases, sensors, out, acc, plan, diag,
            bdiag, pen_limit, ke_limit, cos_nominal, out_time=None, scratch: Scratch = None):
    """:func:`integrate` with the method named ``method_name``
    (:data:`rvcore.integrate.methods.METHODS`) through the step schedule ``schedule``
    (:mod:`rvcore.integrate.schedule`), the plan's arrays and the method's scratch.

    ``out_time`` receives the output lines' times [s] (default: discarded). ``scratch``
    (:class:`Scratch`): a run made of several calls, continued in place; default: a run
    of this call alone. Returns ``(status, t_fail, where, n_out, substepped, refreshes)``
    as :func:`integrate`, and ``substeps_taken``, the substeps computed in the steps taken
    again (``state[S_SUBSTEPS]``); the counters are the run's, over all its calls.
    """
    if scratch is None:
        scratch = Scratch(method_name, model, schedule, diag)
    elif scratch.method_name != method_name:
        raise ValueError(f"a run of {scratch.method_name!r} cannot go on with {method_name!r}")
    if out_time is None:
        out_time = np.zeros(out.shape[0])
    s = scratch
    status, t_fail, where, n_out, substepped, refreshes = integrate(
        y, t_start, schedule, model.params, model.rows, model.arcs, model.pockets,
        table, meta, phases, sensors, out, out_time, acc, plan.series, plan.reductions, diag, bdiag, s.work,
        pen_limit, ke_limit, cos_nominal, NAMES.index(method_name), s.jwork, s.schur, s.inner, s.state, s.carry)
    return status, t_fail, where, n_out, int(substepped), int(refreshes), int(s.state[S_SUBSTEPS])
