"""One step of classical RK4, the reference integrator. SI throughout.

Four evaluations of the right-hand side, the first of them at the step's start, made by
the loop (:func:`rvcore.integrate.loop.integrate`) for the diagnostics and handed in as
``work[0]``. Why a fixed step and how large: :mod:`rvcore.integrate.step_size`.
"""
from __future__ import annotations

from .._numba import kernel

from ..dynamics.rhs import D_DRIVE_POWER, D_DRIVE_TORQUE, rhs_stage

#: The weights b, by which both integrators weigh the stages' drive torques (their nodes
#: are 0, ½, ½, 1 alike; rvcore.integrate.imex keeps b̂ = b for that reason).
B1, B2, B3, B4 = 1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0
#: Rows of ``work``: the four stage derivatives and the stage state.
N_WORK = 5


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
