"""The integration loop: one fixed-step method per call, the accumulators and the
blow-up checks. SI throughout.

The loop owns what every method shares: the right-hand side at each step's state (its
diagnostics are the outputs' signals, :mod:`rvcore.output_table`), the blow-up checks, the
output lines, the per-phase reductions (:mod:`rvcore.recording.plan`) and the drive torque's
filter. A step is one call of the method's step function: :func:`rvcore.integrate.rk4.rk4_step`
(the reference) or :func:`rvcore.integrate.imex.imex_step`; the step's size comes from
:mod:`rvcore.integrate.step_size`.
"""
from __future__ import annotations

import math

import numpy as np
from .._numba import kernel

from ..recording.plan import (SL_POWER_STEP, SL_TORQUE_BAND, SL_TORQUE_STEP, add_integral_end, add_substep_integrals,
                         fill_state_signals,
                         reduce_step,
                         write_series)
from ..dynamics.energy import kinetic_energy
from .imex import GAMMA, SUBSTEPS, TANGENT_MAX_STEPS, imex_step
from ..dynamics.rhs import D_DRIVE_POWER, D_DRIVE_TORQUE, D_MAX_PEN, D_PEN_BALL, rhs, rhs_jac
from ..bearing.layout import P_RING_IP
from ..profile import CH_SPEED, channel_rate
from ..dynamics.races import SCRATCH_SIZE
from .rk4 import B1, B2, B3, B4, rk4_step

OK, NONFINITE, PENETRATION, ENERGY = 0, 1, 2, 3

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

#: The integrators, by their ``solver.method`` names; the loop takes the index.
METHODS = ("rk4", "imex")
RK4, IMEX = 0, 1


@kernel(inline=True)
def _in_window(phases, k, n_ph, t):
    """Whether accumulator line ``k`` takes a step from ``t``: its phase's window holds
    ``t``, or it is the whole cycle's line (``k == n_ph``)."""
    return k == n_ph or phases[k, 0] <= t < phases[k, 1]


# FAST (rvcore._numba: no fast-math flags) keeps IEEE semantics, so the non-finite check
# below works and the state sums are rounded in the same order on every CPU.
@kernel
def integrate(y, t_start, dt, n_steps, out_every, params, rows, arcs, pockets, table, meta,
              phases, sensors, out, acc, series, reductions, diag, bdiag, work, pen_limit, ke_limit,
              cos_nominal, method, jwork, schur, inner):
    """Advance ``y`` in place by ``n_steps`` steps of ``dt`` of ``method`` (``RK4`` or
    ``IMEX``; :func:`advance` allocates the scratch for it).

    Every ``out_every`` steps (and at the first and last step) a line of ``out`` is
    written, the columns of the series plan ``series``. At every step the state at the
    step's start is reduced into each accumulator line of ``acc`` whose window
    (``phases[k] = (start, end)``; the last line the whole cycle) holds it, by the
    reduction plan ``reductions`` (:func:`rvcore.recording.plan.build_plan`). ``sensors``
    holds rows ``(px, py, pz, dx, dy, dz)``; ``cos_nominal[r]`` is cos α of row r's
    nominal contact angle.

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
        IMEX steps taken again in substeps (:func:`rvcore.integrate.imex.imex_step`); 0 for RK4.
    refreshes : int
        Steps that evaluated and factored the IMEX tangents (substeps not counted); 0 for
        RK4.
    """
    n = y.size
    k1 = work[0]
    n_out = 0
    half = 0.5 * dt
    n_ph = phases.shape[0]
    # the band-limited drive torque (TORQUE_BANDWIDTH): two first-order stages, exact for
    # a torque held over each step, started at the first step's torque
    decay = 1.0 - math.exp(-2.0 * math.pi * TORQUE_BANDWIDTH * dt)
    torque_f1, torque_f2 = 0.0, 0.0
    since = TANGENT_MAX_STEPS  # steps since the IMEX tangents were evaluated
    stale = True               # the IMEX tangents no longer fit the contacts' loads
    refreshes = 0
    substepped = 0
    end_half = half        # the trapezoid's end weight of the step just taken
    for i in range(n_steps + 1):
        t = t_start + i * dt
        # the outputs' signals at the step's state (the stages skip the costly ones); the
        # IMEX scheme's tangents from the same evaluation where the contacts' loads have
        # moved from those they were taken at, after TANGENT_MAX_STEPS steps, and after a
        # step taken in substeps (they stay frozen in between: rvcore.integrate.imex, "Step")
        refresh = stale or since >= TANGENT_MAX_STEPS
        if refresh:
            since = 0
            if method == IMEX:
                refreshes += 1
        if method == IMEX and refresh:
            rhs_jac(t, y, k1, params, rows, arcs, pockets, table, meta, diag, bdiag, dt * GAMMA, jwork, schur)
        else:
            rhs(t, y, k1, params, rows, arcs, pockets, table, meta, diag, bdiag)
        # blow-up checks on the state at t
        total = 0.0
        for m in range(n):
            total += y[m] + k1[m]
        if not math.isfinite(total):
            for m in range(n):
                if not (math.isfinite(y[m]) and math.isfinite(k1[m])):
                    return NONFINITE, t, m, n_out, substepped, refreshes
        if diag[D_MAX_PEN] > pen_limit:
            return PENETRATION, t, int(diag[D_PEN_BALL]), n_out, substepped, refreshes
        fill_state_signals(diag, y, t, dt, table, meta, rows, bdiag, sensors, cos_nominal)
        if i > 0:
            tp = t - dt
            for k in range(n_ph + 1):
                if _in_window(phases, k, n_ph, tp):
                    add_integral_end(acc[k], reductions, diag, end_half)
        if i < n_steps:
            for k in range(n_ph + 1):
                if _in_window(phases, k, n_ph, t):
                    reduce_step(acc[k], reductions, diag, t, 0, half)
        if i % out_every == 0 or i == n_steps:
            if kinetic_energy(y, params, rows) > ke_limit:
                return ENERGY, t, -1, n_out, substepped, refreshes
            write_series(out[n_out], series, diag)
            n_out += 1
        if i == n_steps:
            break
        # the step's drive torque Σ b_i·T(Y_i): the moment whose impulse the step gave
        # the balls (both methods weigh the stages' forces by the same b), and its power
        # Σ b_i·T(Y_i)·ω(t_i), the work that impulse did (the drive's energy)
        torque = B1 * diag[D_DRIVE_TORQUE]
        power = B1 * diag[D_DRIVE_POWER]
        if method == IMEX:
            later, later_power, again, stale = imex_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag,
                                                         bdiag, work, jwork, schur, refresh, inner)
            torque += later
            power += later_power
            since = since + 1
            end_half = half
            if again:      # the integrals over its substeps (rvcore.recording.plan.add_substep_integrals)
                substepped += 1
                end_half = half / SUBSTEPS
                for k in range(n_ph + 1):
                    if _in_window(phases, k, n_ph, t):
                        add_substep_integrals(acc[k], reductions, inner, dt / SUBSTEPS)
        else:
            later, later_power = rk4_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work)
            torque += later
            power += later_power
        # the peak is band-limited (TORQUE_BANDWIDTH) in its contacts' part only: the
        # prescribed spin's I_p·ω̇ is known exactly, and its jumps at the profile's corners
        # would only lag. It is weighed over the stages as the step's torque is (both
        # methods' nodes are 0, ½, ½, 1), so that the filter sees the contacts' part alone
        inertial = params[P_RING_IP] * (B1 * channel_rate(table, meta, CH_SPEED, t)
                                        + (B2 + B3) * channel_rate(table, meta, CH_SPEED, t + half)
                                        + B4 * channel_rate(table, meta, CH_SPEED, t + dt))
        if i == 0:
            torque_f1 = torque_f2 = torque - inertial
        # the band-limited torque at t, the time whose phase it goes to: the filter's
        # output before this step's torque enters it (after, it is the output at t + dt,
        # which put the filter's decay over one step after a profile's corner into the
        # next phase's peak: an error growing as the step squared)
        diag[SL_TORQUE_BAND] = inertial + torque_f2
        if i > 0:
            torque_f1 += decay * (torque - inertial - torque_f1)
            torque_f2 += decay * (torque_f1 - torque_f2)
        diag[SL_TORQUE_STEP] = torque
        diag[SL_POWER_STEP] = power
        for k in range(n_ph + 1):
            if _in_window(phases, k, n_ph, t):
                reduce_step(acc[k], reductions, diag, t, 1, half)
    return OK, t_start + n_steps * dt, -1, n_out, substepped, refreshes


def new_work(model, method: str, pocket_tolerance: float, load_tolerance: float):
    """The scratch arrays ``(work, jwork, schur)`` that :func:`integrate` needs for ``method``
    (``pocket_tolerance`` [J] and ``load_tolerance`` [N]: the IMEX pocket check's and
    tangents', :func:`rvcore.integrate.imex.imex_step`)."""
    if method == "rk4":
        from .rk4 import N_WORK

        return np.zeros((N_WORK, model.n_states)), np.zeros((1, 1)), np.zeros((1, 1))
    from . import imex

    return imex.new_work(model, pocket_tolerance, load_tolerance)


def advance(method: str, y, t_start, dt, n_steps, out_every, model, table, meta, phases, sensors, out,
            acc, plan, diag, bdiag, pen_limit, ke_limit, cos_nominal, pocket_tolerance, load_tolerance):
    """:func:`integrate` with ``method`` by name (:data:`METHODS`), the plan's arrays and
    the method's scratch.

    ``pocket_tolerance`` [J] and ``load_tolerance`` [N] are the IMEX pocket check's and
    tangents' (:func:`rvcore.integrate.step_size.pocket_energy_tolerance`,
    :func:`rvcore.integrate.step_size.tangent_load_tolerance`). Returns ``(status, t_fail, where,
    n_out, substepped, refreshes)`` as :func:`integrate`.
    """
    if method not in METHODS:
        raise ValueError(f"unknown integrator {method!r}: use one of {', '.join(METHODS)}")
    work, jwork, schur = new_work(model, method, pocket_tolerance, load_tolerance)
    return integrate(y, t_start, dt, n_steps, out_every, model.params, model.rows, model.arcs, model.pockets,
                     table, meta, phases, sensors, out, acc, plan.series, plan.reductions, diag, bdiag, work,
                     pen_limit, ke_limit, cos_nominal, METHODS.index(method), jwork, schur,
                     np.zeros(diag.size - SCRATCH_SIZE))
