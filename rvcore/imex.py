"""The coupled implicit–explicit integrator: friction at small slip and contact damping
implicit in every stage, the Hertz contacts and everything else explicit. SI throughout.

Why, and which scheme
---------------------
RK4's step is set by the friction law's slope at zero slip, ``c_f = 1.5·μ_s·Q/v_s``
≈ 5.3e3 N s/m per race contact at the study's 3.55 kN, a real-axis rate
λ_f ≈ 5.4e5 1/s that limits RK4 to 5.2e-6 s (:func:`rvcore.integrator.stable_time_step`).
The contact oscillation, ω_n = √(2k/m_b) ≈ 1.1e5 rad/s, would allow 5× more. The
friction is stiff through the rings too: a ball drags the inner ring and its cage
(``rvcore.implicit``), so the implicit part must couple every ball with the ring and the
cages, in every stage.

The scheme is an additive Runge–Kutta (IMEX-ARK) method of order 2 on
``dy/dt = f(y) + g(y)``: ``g(y) = −M⁻¹·D·(V − V_n)`` is the stiff damping of
:mod:`rvcore.implicit` about the step's start, with ``D`` the exact velocity tangent of
the friction and damper forces there (frozen over the step; any ``D`` keeps the order),
and ``f = F − g`` the rest, whose velocity tangent is then zero at that state.
Linearising about ``V_n`` (not about V = 0) keeps ``f`` and ``g`` each small: a ball
orbiting at 20 m/s has a near-zero slip but ``D·V`` of thousands of g, and splitting that
large pair left a 10 % error in the balls' centrifugal force balance at this step. Explicit tableau: classical RK4 (``c = 0, ½, ½, 1``), kept for its
imaginary-axis stability (|λ·h| ≤ 2√2) on the contact oscillation. Implicit tableau: an
ESDIRK with the same nodes and a constant diagonal γ (:data:`GAMMA`), so one
factorization serves the three implicit stages::

    Ŷ_i = y_n + h·Σ_{j<i} (a_ij·F_j + (â_ij − a_ij)·g_j)
    (M + h·γ·D)·(V_i − V_n) = M·(V̂_i − V_n) ,   g_i = (V_i − V̂_i)/(h·γ),   g_1 = 0
    y_{n+1} = y_n + h·Σ_i (b_i·F_i + (b̂_i − b_i)·g_i)

with ``F_i = F(Y_i)`` the full right-hand side: four evaluations per step, as RK4.
``M + h·γ·D`` is block-arrowhead (each ball coupled only to the ring; which couplings
are in ``D`` and why: :mod:`rvcore.implicit`); it is solved exactly through the Schur
complement on the ring, O(Z) per stage.
Both tableaux satisfy the order-2 conditions, the coupling ones included
(``Σ b·ĉ = Σ b̂·c = ½`` with ``c = ĉ``).

Step
----
What remains explicit: the Hertz contact oscillation, the friction law's negative slope
between v_s and v_d (at most 1.5·(μ_s − μ_d)/(v_d − v_s)·Q), and slow terms (gyroscopic
coupling of the ring, gravity). :func:`stable_time_step` takes the step from the first
two (:data:`IMAG_LIMIT`: why it is 1.4, not the explicit tableau's 2.8).
On the study case (Q = 3.55 kN): ω_n ≈ 1.1e5 rad/s → about 1.0e-5 s at safety 0.8,
against RK4's 4.1e-6 s.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .implicit import J_A, J_B, J_COUPLED, J_W, N_JWORK
from .kernels import rhs_stage
from .model import (BALL_STATES, P_RING_IT, P_RING_M, R_BALL0, R_IB,
                    R_MB, R_POCKET0, R_Z)

# ---- the tableaux (explicit a, b; implicit â, b̂), nodes c = (0, ½, ½, 1)
A21, A32, A43 = 0.5, 0.5, 1.0
B1, B2, B3, B4 = 1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0
GAMMA = 1.0 / 6.0
I21 = 1.0 / 3.0
I31, I32 = 5.0 / 36.0, 7.0 / 36.0
I41, I42, I43 = 1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0
IB1, IB2, IB3, IB4 = 1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0
#: Limit on |ω_n·h| (ω_n the contact oscillation), the damping implicit. The scheme is
#: stable on the undamped oscillator to 2.8 (RK4's explicit tableau), but with the
#: friction damper implicit the ball's coupled modes are not: on ẍ = −ω²x − c·ẋ (c
#: implicit) the amplification exceeds 1 for ω·h ≥ 1.5 once c·h ≳ 20, and on the
#: 12-ball section at 300 rad/s (tests/core/test_dynamics.py) a step at ω·h = 2.1 leaves a
#: step-locked ball oscillation that spoils the centrifugal balance by 10 % (0.85 % at
#: ω·h = 1.05). 1.4 keeps the checks of model.md §9 within their tolerances at the
#: default step_safety.
IMAG_LIMIT = 1.4

#: Rows of ``work``: F_1..F_4, the stage state, g_1..g_4, 1/mass, mass.
W_F, W_TMP, W_G, W_INVM, W_M = 0, 4, 5, 9, 10
N_WORK = 11


def new_work(model):
    """``(work, jwork, schur)`` for :func:`rvcore.integrator.integrate` with the IMEX method."""
    n = model.n_states
    work = np.zeros((N_WORK, n))
    inv_m = work[W_INVM]
    p, rows = model.params, model.rows
    inv_m[5:8] = 1.0 / p[P_RING_M]
    inv_m[8:10] = 1.0 / p[P_RING_IT]
    for r in range(rows.shape[0]):     # the implicit unknowns: the ring's and balls' velocities
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            inv_m[b + 3:b + 6] = 1.0 / rows[r, R_MB]
            inv_m[b + 6:b + 9] = 1.0 / rows[r, R_IB]
    work[W_M] = np.where(inv_m > 0, 1.0 / np.where(inv_m > 0, inv_m, 1.0), 0.0)
    return work, np.zeros((model.n_balls + 1, N_JWORK)), np.zeros((6, 5))


@njit(cache=True, nogil=True)
def factor(jwork, schur, rows, mass):
    """Factor ``M + h·γ·D`` from the blocks :func:`rvcore.kernels.rhs_jac` accumulated.

    Per ball: ``A = Uᵀ·U`` (Cholesky, U in A's upper triangle) and ``X = U⁻ᵀ·B`` in place
    of B; then the ring's Schur complement ``S = M_ring + h·γ·D_ring − Σ Xᵀ·X`` and
    ``S = Uᵀ·U`` in place. ``mass`` is the state-indexed mass (0 at positions). A ball
    with no inner-race contact has ``B = 0``: flagged, and skipped here and in
    :func:`solve`.
    """
    for i in range(5):
        schur[i, i] += mass[5 + i]
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        for j in range(int(rows[r, R_Z])):
            jw = jwork[p0 + j]
            b = b0 + BALL_STATES * j
            for i in range(6):
                jw[J_A + 7 * i] += mass[b + 3 + i]
            # Cholesky A = UᵀU, upper triangle
            for i in range(6):
                s = jw[J_A + 7 * i]
                for l in range(i):
                    s -= jw[J_A + 6 * l + i] ** 2
                d = math.sqrt(s)
                jw[J_A + 7 * i] = d
                inv = 1.0 / d
                for c in range(i + 1, 6):
                    s = jw[J_A + 6 * i + c]
                    for l in range(i):
                        s -= jw[J_A + 6 * l + i] * jw[J_A + 6 * l + c]
                    jw[J_A + 6 * i + c] = s * inv
            coupled = False
            for i in range(30):
                if jw[J_B + i] != 0.0:
                    coupled = True
                    break
            jw[J_COUPLED] = 1.0 if coupled else 0.0
            if not coupled:
                continue
            # X = U⁻ᵀ B (forward substitution, column by column), and S −= XᵀX
            for c in range(5):
                for i in range(6):
                    s = jw[J_B + 5 * i + c]
                    for l in range(i):
                        s -= jw[J_A + 6 * l + i] * jw[J_B + 5 * l + c]
                    jw[J_B + 5 * i + c] = s / jw[J_A + 7 * i]
            for c in range(5):
                for d in range(c, 5):
                    s = 0.0
                    for i in range(6):
                        s += jw[J_B + 5 * i + c] * jw[J_B + 5 * i + d]
                    schur[c, d] -= s
    # Cholesky of S (upper triangle)
    for i in range(5):
        s = schur[i, i]
        for l in range(i):
            s -= schur[l, i] ** 2
        d = math.sqrt(s)
        schur[i, i] = d
        for c in range(i + 1, 5):
            s = schur[i, c]
            for l in range(i):
                s -= schur[l, i] * schur[l, c]
            schur[i, c] = s / d


@njit(cache=True, nogil=True)
def solve(v, jwork, schur, rows, mass):
    """Overwrite the velocities of the balls and the ring in the state ``v`` with
    ``(M + h·γ·D)⁻¹·M·v`` (factors of :func:`factor`); the rest is untouched."""
    rz = schur[5]
    for i in range(5):
        rz[i] = mass[5 + i] * v[5 + i]
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        for j in range(int(rows[r, R_Z])):
            jw = jwork[p0 + j]
            b = b0 + BALL_STATES * j
            for i in range(6):     # w = U⁻ᵀ·M_b·v_b
                s = mass[b + 3 + i] * v[b + 3 + i]
                for l in range(i):
                    s -= jw[J_A + 6 * l + i] * jw[J_W + l]
                jw[J_W + i] = s / jw[J_A + 7 * i]
            if jw[J_COUPLED] != 0.0:
                for c in range(5):     # r_ring −= Xᵀ·w
                    s = 0.0
                    for i in range(6):
                        s += jw[J_B + 5 * i + c] * jw[J_W + i]
                    rz[c] -= s
    # S·Z = r: Uᵀ then U
    for i in range(5):
        s = rz[i]
        for l in range(i):
            s -= schur[l, i] * rz[l]
        rz[i] = s / schur[i, i]
    for i in range(4, -1, -1):
        s = rz[i]
        for l in range(i + 1, 5):
            s -= schur[i, l] * rz[l]
        rz[i] = s / schur[i, i]
    for i in range(5):
        v[5 + i] = rz[i]
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        for j in range(int(rows[r, R_Z])):
            jw = jwork[p0 + j]
            b = b0 + BALL_STATES * j
            if jw[J_COUPLED] != 0.0:
                for i in range(6):     # w − X·Z
                    s = jw[J_W + i]
                    for c in range(5):
                        s -= jw[J_B + 5 * i + c] * rz[c]
                    jw[J_W + i] = s
            for i in range(5, -1, -1):   # v_b = U⁻¹·(w − X·Z)
                s = jw[J_W + i]
                for l in range(i + 1, 6):
                    s -= jw[J_A + 6 * i + l] * v[b + 3 + l]
                v[b + 3 + i] = s / jw[J_A + 7 * i]


@njit(cache=True, nogil=True, inline="always")
def _implicit_stage(i, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    a1, a2, a3, i1, i2, i3, c):
    """Stage ``i`` (1–3, 0-based): Ŷ, the solve, g_i and F_i (module docstring)."""
    n = y.size
    tmp, g, f = work[W_TMP], work[W_G + i], work[W_F + i]
    f0, f1, f2 = work[W_F], work[W_F + 1], work[W_F + 2]
    g0, g1, g2 = work[W_G], work[W_G + 1], work[W_G + 2]
    mass, inv_m = work[W_M], work[W_INVM]
    for m in range(n):
        s = a1 * f0[m] + (i1 - a1) * g0[m]
        if i >= 2:
            s += a2 * f1[m] + (i2 - a2) * g1[m]
        if i >= 3:
            s += a3 * f2[m] + (i3 - a3) * g2[m]
        tmp[m] = y[m] + dt * s
        g[m] = tmp[m]          # V̂, for g_i below
        if mass[m] > 0.0:      # the solve is for the increment V − V_n
            tmp[m] -= y[m]
    solve(tmp, jwork, schur, rows, mass)
    inv_hg = 1.0 / (dt * GAMMA)
    for m in range(n):
        if mass[m] > 0.0:
            tmp[m] += y[m]
            g[m] = (tmp[m] - g[m]) * inv_hg
        else:
            g[m] = 0.0
    rhs_stage(t + c * dt, tmp, f, params, rows, arcs, pockets, table, meta, diag, bdiag)


@njit(cache=True, nogil=True)
def imex_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur):
    """Advance ``y`` by one IMEX step of ``dt``.

    On entry ``work[W_F]`` holds ``F(y)``, and ``jwork`` and ``schur`` the blocks that
    :func:`rvcore.kernels.rhs_jac` accumulated at ``(t, y)`` with ``h·γ = dt·GAMMA``.
    """
    n = y.size
    factor(jwork, schur, rows, work[W_M])
    g0 = work[W_G]
    for m in range(n):
        g0[m] = 0.0       # g(y_n) = −M⁻¹·D·(V_n − V_n)
    _implicit_stage(1, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    A21, 0.0, 0.0, I21, 0.0, 0.0, 0.5)
    _implicit_stage(2, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    0.0, A32, 0.0, I31, I32, 0.0, 0.5)
    _implicit_stage(3, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    0.0, 0.0, A43, I41, I42, I43, 1.0)
    f0, f1, f2, f3 = work[W_F], work[W_F + 1], work[W_F + 2], work[W_F + 3]
    g1, g2, g3 = work[W_G + 1], work[W_G + 2], work[W_G + 3]
    for m in range(n):
        y[m] += dt * (B1 * f0[m] + B2 * f1[m] + B3 * f2[m] + B4 * f3[m]
                      + (IB1 - B1) * g0[m] + (IB2 - B2) * g1[m] + (IB3 - B3) * g2[m] + (IB4 - B4) * g3[m])


def stable_time_step(model, peak_contact_load: float, *, safety: float = 0.8,
                     dynamic_margin: float = 1.0) -> float:
    """The fixed IMEX step [s] from the rates that stay explicit.

    Notes
    -----
    Per row, with ``Q = dynamic_margin·peak_contact_load``, ``k = 1.5·K^(2/3)·Q^(1/3)``
    for the stiffest arc and the two race contacts of a ball::

        ω_n = √(2k/m_b)                                  (contact oscillation)
        λ_− = 2·Q·|min μ'|·max(1/m_b, r²/I_b)             (the law's falling slope)
        dt  = safety · min(IMAG_LIMIT/ω_n, 2.785/λ_−)

    ``|min μ'| = 1.5·(μ_s − μ_d)/(v_d − v_s)``, the cubic STEP's steepest slope.
    """
    from .integrator import RK4_REAL_LIMIT, row_rates
    from .model import P_FRICTION, P_MU_D, P_MU_S, P_V_D, P_V_S

    q = max(dynamic_margin * peak_contact_load, 1.0)
    p = model.params
    falling = 1.5 * max(p[P_MU_S] - p[P_MU_D], 0.0) / (p[P_V_D] - p[P_V_S]) * p[P_FRICTION]
    dts = []
    for omega, m, rot in row_rates(model, q):
        lam = 2.0 * q * falling * max(1.0 / m, rot)
        dts.append(min(IMAG_LIMIT / omega, RK4_REAL_LIMIT / lam if lam > 0 else np.inf))
    return safety * min(dts)
