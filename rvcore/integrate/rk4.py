"""One step of classical RK4, the reference integrator. SI throughout.

Four evaluations of the right-hand side, the first of them at the step's start, made by
the loop (:func:`rvcore.integrate.loop.integrate`) for the diagnostics and handed in as
``work[0]``. Why a fixed step and how large: :mod:`rvcore.integrate.step_size`.
"""
from __future__ import annotations

import math

import numpy as np

from .._numba import kernel

from ..bearing.laws import FRICTION_LAW_SIZE, LAW_ON
from ..bearing.layout import P_DAMP_C, P_DAMPING, P_LAW, P_RING_IP
from ..contact.laws import friction_slope_at_zero_slip
from ..dynamics.rhs import D_DRIVE_POWER, D_DRIVE_TORQUE, rhs, rhs_stage
from ..profile import CH_SPEED, channel_rate
from .step_size import modal_steps, row_rates

#: The weights b, by which both integrators weigh the stages' drive torques (their nodes
#: are 0, ½, ½, 1 alike; rvcore.integrate.imex keeps b̂ = b for that reason).
B1, B2, B3, B4 = 1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0
#: Rows of ``work``: the four stage derivatives and the stage state.
N_WORK = 5
#: RK4's stability limits on ``|λ·dt|``: on the imaginary axis (2√2) and on the negative
#: real axis (2.785) (:mod:`rvcore.integrate.step_size`).
RK4_IMAG_LIMIT = 2.0 * math.sqrt(2.0)
RK4_REAL_LIMIT = 2.785


@kernel
def rk4_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work):
    """Advance ``y`` by one RK4 step of ``dt``; ``work[0]`` holds ``F(t, y)`` on entry.

    Returns ``Σ_{i≥2} b_i·T(Y_i)`` and ``Σ_{i≥2} b_i·T(Y_i)·ω(t_i)``, the later stages'
    shares of the step's drive torque [N m] and power [W] (the first stage's the caller
    has).
    """
    n = y.size
    half = 0.5 * dt
    k1, k2, k3, k4, tmp = work[0], work[1], work[2], work[3], work[4]
    for m in range(n):
        tmp[m] = y[m] + half * k1[m]
    rhs_stage(t + half, tmp, k2, params, rows, arcs, pockets, table, meta, diag, bdiag)
    torque, power = B2 * diag[D_DRIVE_TORQUE], B2 * diag[D_DRIVE_POWER]
    for m in range(n):
        tmp[m] = y[m] + half * k2[m]
    rhs_stage(t + half, tmp, k3, params, rows, arcs, pockets, table, meta, diag, bdiag)
    torque += B3 * diag[D_DRIVE_TORQUE]
    power += B3 * diag[D_DRIVE_POWER]
    for m in range(n):
        tmp[m] = y[m] + dt * k3[m]
    rhs_stage(t + dt, tmp, k4, params, rows, arcs, pockets, table, meta, diag, bdiag)
    torque += B4 * diag[D_DRIVE_TORQUE]
    power += B4 * diag[D_DRIVE_POWER]
    sixth = dt / 6.0
    for m in range(n):
        y[m] += sixth * (k1[m] + 2.0 * (k2[m] + k3[m]) + k4[m])
    return torque, power


# ---- the method's protocol (rvcore.integrate.protocol)
#: Right-hand sides a step evaluates.
STAGES = 4


def rk4_time_step(model, peak_contact_load: float, *, safety: float = 0.8,
                  dynamic_margin: float = 1.0) -> float:
    """The fixed RK4 step [s] from the stiffest contact and friction rates.

    Parameters
    ----------
    model : rvcore.bearing.layout.CompiledBearing
    peak_contact_load : float
        Largest quasi-static ball–race load over the cycle [N].
    safety : float
        Fraction of the stability limit [-].
    dynamic_margin : float
        Factor on the quasi-static load for dynamic overshoot [-].

    Notes
    -----
    Per row, with ``Q = dynamic_margin·peak_contact_load``, ``K`` the stiffest arc,
    ``k = 1.5·K^(2/3)·Q^(1/3)``, ``c_f = Q·dμ/ds`` at zero slip
    (:func:`rvcore.contact.laws.friction_slope_at_zero_slip`, the law's own slope) and the two
    race contacts of a ball::

        ω_n = √(2k/m_b)                        (contact oscillation)
        λ   = 2·(c_f·max(1/m_b, r²/I_b) + c_max/m_b)   (friction and damping, real axis)
        dt  = safety · min(2√2/ω_n, 2.785/λ)

    and a flexible ring's modes on the same limits at their rates with the contacts'
    stiffness on them (:func:`rvcore.integrate.step_size.modal_steps`).
    """
    q = max(dynamic_margin * peak_contact_load, 1.0)
    p = model.params
    law = p[P_LAW:P_LAW + FRICTION_LAW_SIZE]
    c_f = friction_slope_at_zero_slip(law) * q * law[LAW_ON]
    dts = []
    for omega, m, rot in row_rates(model, q):
        lam = 2.0 * (c_f * max(1.0 / m, rot) + p[P_DAMP_C] * p[P_DAMPING] / m)
        dts.append(min(RK4_IMAG_LIMIT / omega, RK4_REAL_LIMIT / lam if lam > 0 else np.inf))
    dts.extend(modal_steps(model, q, RK4_IMAG_LIMIT, RK4_REAL_LIMIT))
    return safety * min(dts)


def new_work(model, pocket_tolerance=0.0, load_tolerance=0.0):
    """``(work, jwork, schur)`` for the loop: the stage rows (RK4 has no tangents; the
    tolerances are IMEX's, unused here)."""
    return np.zeros((N_WORK, model.n_states)), np.zeros((1, 1)), np.zeros((1, 1))


def time_step(model, peak_contact_load: float, *, safety: float = 0.8, held: bool = False) -> float:
    """RK4's fixed step [s] (:func:`rk4_time_step`), held loads or not: its bounds are
    stability limits, which hold loads do not lift."""
    return rk4_time_step(model, peak_contact_load, safety=safety)


def load_tolerance(peak_contact_load: float) -> float:
    """A stretch's load tolerance for :func:`begin_segment`: none (0; RK4 has no tangents)."""
    return 0.0


def segment_constant(model, peak_contact_load: float, time_step: float) -> float:
    """A stretch's constant for :func:`begin_segment`: none (0)."""
    return 0.0


def falling_guard(model, peak_contact_load: float, *, safety: float = 0.8, held: bool = False):
    """None (``(0, 0)``): RK4's step keeps the friction law's falling slope within its bound
    everywhere (:func:`rk4_time_step`)."""
    return 0.0, 0.0


@kernel(inline=True)
def begin_segment(segment, work, state):
    """A stretch of the step schedule begins: nothing to set."""
    return


def new_state():
    """The counters of a run (:mod:`rvcore.integrate.protocol`; RK4 keeps none of its own)."""
    from .protocol import new_state as new_counters

    return new_counters()


def rhs_evaluations(n_steps: int, substeps: int) -> int:
    """Right-hand sides of a run: four a step and the last step's end."""
    return STAGES * n_steps + 1


@kernel(inline=True)
def evaluate(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state):
    """The right-hand side at the step's start into ``work[0]`` (its diagnostics the
    outputs' signals)."""
    rhs(t, y, work[0], params, rows, arcs, pockets, table, meta, diag, bdiag)


@kernel(inline=True)
def step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state, inner,
         acc, reductions, phases):
    """One step (:func:`rk4_step`) after :func:`evaluate`. Returns the step's drive torque
    ``Σ b_i·T(Y_i)`` [N m], its power ``Σ b_i·T(Y_i)·ω(t_i)`` [W], the prescribed spin's
    ``I_p·ω̇`` weighed alike [N m], and the divisor of the step's trapezoid end weight (1)."""
    torque = B1 * diag[D_DRIVE_TORQUE]
    power = B1 * diag[D_DRIVE_POWER]
    later, later_power = rk4_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work)
    torque += later
    power += later_power
    return torque, power, stage_weighted_inertia(t, dt, params, table, meta), 1.0


@kernel(inline=True)
def stage_weighted_inertia(t, dt, params, table, meta):
    """The prescribed spin's ``I_p·ω̇`` weighed over the stages as the step's torque is
    (nodes 0, ½, ½, 1, weights b; IMEX shares them) [N m]."""
    half = 0.5 * dt
    return params[P_RING_IP] * (B1 * channel_rate(table, meta, CH_SPEED, t)
                                + (B2 + B3) * channel_rate(table, meta, CH_SPEED, t + half)
                                + B4 * channel_rate(table, meta, CH_SPEED, t + dt))
