"""The coupled implicit–explicit integrator: the ball–race Hertz stiffness, friction at
small slip and contact damping implicit in every stage, everything else explicit. SI
throughout.

Why, and which scheme
---------------------
RK4's step is set by the friction law's slope at zero slip, ``c_f = 1.5·μ_s·Q/v_s``
≈ 5.3e3 N s/m per race contact at the study's 3.55 kN, a real-axis rate
λ_f ≈ 5.4e5 1/s that limits RK4 to 5.2e-6 s (:func:`rvcore.timestep.rk4_time_step`),
and behind it by the contact oscillation, ω_n = √(2k/m_b) ≈ 1.1e5 rad/s. Both are
implicit here. The friction is stiff through the rings too: a ball drags the inner ring
and its cage (``rvcore.implicit``), so the implicit part couples every ball with the
ring, in every stage.

The scheme is an additive Runge–Kutta (IMEX-ARK) method on ``dy/dt = f(t, y) + g(t, y)``
with ``g = J·(y − ỹ(t))``: ``J`` the frozen tangent of :mod:`rvcore.implicit` on the
implicit unknowns (the ring's pose and rates, every ball's centre, velocity and spin)::

    J = [[0, I], [−M⁻¹·K, −M⁻¹·D]]

``K`` the Hertz stiffness of the ball–race contacts on the positions (with the groove's
geometric stiffness, :func:`rvcore.implicit.groove_blocks`), ``D`` the velocity
tangent of the friction and dampers, and ``f = F − g`` the rest. The splitting is exact
for any ``J`` and any reference ``ỹ``: the pair's order does not depend on them, only its
stability, so ``J`` may be frozen over several steps (:data:`JAC_EVERY`). Explicit tableau:
classical RK4 (``c = 0, ½, ½, 1``). Implicit tableau: an ESDIRK with the same nodes, the
same weights ``b̂ = b`` and the constant diagonal γ = 1/6, so one factorization serves
the three implicit stages. Stage i (e the deviation from the reference)::

    ê   = h·Σ_{j<i} (a_ij·F_j + (â_ij − a_ij)·g_j) − (ỹ_i − y_n)
    e_x = ê_x + h·γ·e_v
    (M + h·γ·D + (h·γ)²·K)·e_v = M·ê_v − h·γ·K·ê_x
    Y_i = ỹ_i + e,   g_i = (e − ê)/(h·γ)   (g_x = e_v),   g_1 = 0
    y_{n+1} = y_n + h·Σ_i b_i·F_i

with ``F_i = F(Y_i)`` the full right-hand side: four evaluations per step, as RK4.
``M + h·γ·D + (h·γ)²·K`` is block-arrowhead (each ball coupled only to the ring); it is
solved exactly through the Schur complement on the ring, O(Z) per stage. With ``b̂ = b``
the velocity update weighs the stages' full forces by ``b`` alone, so ``Σ b_i·T(Y_i)`` is
the drive torque whose impulse the step gave the balls (the step's torque that
:func:`rvcore.integrator.integrate` accumulates). A change to ``b̂ ≠ b`` must change that.

The implicit tableau: all-pass
------------------------------
Its stability function is ``R(z) = ((1 + z/6)/(1 − z/6))³`` (that of three trapezoidal
steps of h/3), so ``|R(iy)| = 1``: the contact oscillation, now in the implicit part, is
integrated without numerical damping at any ω_n·h, and the energy its ring-downs carry
leaves through the damper, not the scheme. It is the only such function the structure
allows: with the denominator ``(1 − γz)³``, ``|R(iy)| = 1`` needs the numerator
``(1 + γz)³``, and ``R = e^z + O(z²)`` then fixes γ = 1/6; its z³ coefficient is
1/6 + 1/108, so the implicit tableau, and the pair, are of order 2 (order 3 and
``|R(iy)| = 1`` exclude each other here). Of the one-parameter family of tableaux with
this R (rows summing to c, ``b̂ = b``), the entries below keep the stage values of a stiff
mode smallest (about 2× the step's start at most, on the real and imaginary axes). The price:
an all-pass function cannot be L-stable, ``R(−x) → −1`` as x → ∞, so a stiff friction
mode is damped per step by ``|R(−λ_f·h)|`` only, which bounds the step (below).

Reference
---------
Linearised about ``y_n``, a ball's orbit is not a small deviation: over a step its
centre leaves the tangent by v²h²/(2ρ) (about 1 µm at 300 rad/s and 25 µs), which the
implicit Hertz stiffness reads as a change of penetration, and the explicit stages'
O(h²) error of the orbit's position turns into stage forces of order (ω_n·h)²·m_b·a.
So the balls' stages are deviations from ``ỹ(t)``: ``y_n`` turned about the bearing's
axis at the ball's orbital speed (centre, velocity and spin), and ``ê`` subtracts the
explicit row's own quadrature of ``ỹ'`` (the row's one entry, at the previous node) where
it would subtract ``ỹ_i − y_n``: then a ball on that orbit stays on it exactly, and the
centrifugal balance (docs/model.md §9.7) does not depend on the step. The ring and cages are
not turned (``ỹ = y_n`` for the ring; the cages are explicit).

Step
----
What bounds it (:func:`rvcore.timestep.imex_time_step`):

- the stiff friction modes, implicit, damped per step by ``|R(−λ_f·h)|``: the step keeps
  ``λ_f·h ≤`` :data:`FRICTION_LIMIT`, where that factor is :data:`FRICTION_DAMPING`.
  Beyond it the friction's slip oscillates from step to step, and the law's saturation
  turns that into a chatter that dissipates energy the physics does not (the energy
  balances of tests/core/test_energy_balance.py break); λ_f is RK4's friction-and-damping
  rate (:func:`rvcore.timestep.rk4_time_step`), so the IMEX step is
  ``FRICTION_LIMIT/2.785`` ≈ 8.2 times RK4's wherever friction binds RK4;
- the friction law's falling slope between v_s and v_d, explicit (at most
  ``1.5·(μ_s − μ_d)/(v_d − v_s)·Q``), on RK4's real-axis limit;
- a race contact that closes within a step: its stiffness is not in the step's
  tangents, so for that step it is explicit, on the explicit tableau's imaginary-axis
  limit, ``ω_c·h ≤`` :data:`ONSET_LIMIT` = 2√2 with ``ω_c = ω_n/√2`` (one contact: a
  rattling ball's other side is open) at the peak contact load. A case with no load and
  no speed (the ring's weight alone, balls rattling) blows up just past it.

Once a contact is in the tangents its oscillation does not bound the step: the tableau
is A-stable and keeps it undamped; its phase per step is ``6·atan(ω_n·h/6)`` against ω_n·h, a frequency error of
about (ω_n·h)²/108. The pockets' stiffness and the cage–land contact stay explicit
(``rvcore.implicit``): their rates are far below the race contacts' (a ball on a 100 N
pocket contact: 4e4 rad/s against ω_n 1.1e5), within the explicit stages' limits at
these steps.

The tangents and the factorization are evaluated every :data:`JAC_EVERY` steps (the
splitting stays exact with a frozen ``J``; between, the step costs four right-hand sides
and three solves).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .implicit import J_A, J_B, J_COUPLED, J_KA, J_KB, J_W, N_JWORK, N_SCHUR, S_K
from .kernels import D_DRIVE_TORQUE, rhs_stage
from .model import (BALL_STATES, P_RING_IT, P_RING_M, P_TILT_HELD, R_BALL0, R_IB,
                    R_MB, R_POCKET0, R_Z)

# ---- the tableaux (explicit a, b; implicit â, b̂), nodes c = (0, ½, ½, 1)
A21, A32, A43 = 0.5, 0.5, 1.0
B1, B2, B3, B4 = 1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0
#: The implicit tableau: the ESDIRK whose stability function is the all-pass
#: ((1 + z/6)/(1 − z/6))³ (module docstring), γ = 1/6, b̂ = b, rows summing to c. Free
#: entries I32, I42, I43 (one of them free within the family: I43 = ½ keeps the stage
#: values smallest); the rest follow from the row sums.
GAMMA = 1.0 / 6.0
I32 = 4.0 / 27.0
I42, I43 = 17.0 / 54.0, 0.5
I21 = 0.5 - GAMMA
I31 = 0.5 - GAMMA - I32
I41 = 1.0 - GAMMA - I42 - I43
IB1, IB2, IB3, IB4 = B1, B2, B3, B4
#: Largest ``λ_f·h`` (λ_f the friction's rate at zero slip, on the negative real axis):
#: where the implicit tableau damps a friction mode by at least :data:`FRICTION_DAMPING`
#: per step. ``R(−x) = ((6 − x)/(6 + x))³`` tends to −1 as x → ∞ (an all-pass function
#: cannot be L-stable), so the step must keep x below the root of ``|R(−x)| = ρ``:
#: ``x = 6·(1 + ρ^⅓)/(1 − ρ^⅓)``.
FRICTION_DAMPING = 0.2
FRICTION_LIMIT = 6.0 * (1.0 + FRICTION_DAMPING ** (1.0 / 3.0)) / (1.0 - FRICTION_DAMPING ** (1.0 / 3.0))
#: Limit on ``ω_c·h`` for a race contact that closes within a step: its stiffness is not
#: in the tangents of the step's start, so for that step it is explicit, on the explicit
#: tableau's imaginary-axis limit 2√2. ``ω_c = ω_n/√2``, one contact on the ball (the
#: other side open, as for a ball that rattles) at the peak contact load.
ONSET_LIMIT = 2.0 * math.sqrt(2.0)
#: Steps one evaluation of the tangents and one factorization serve (module docstring,
#: "Step"): every other step costs a right-hand side without the tangents and no
#: factorization.
JAC_EVERY = 2

#: Rows of ``work``: F_1..F_4, the stage state, g_1..g_4, 1/mass, mass (both 0 off the
#: implicit velocities), 1 at the implicit velocities and 1 at the implicit positions (the
#: balls' centres, the ring's pose; 0 elsewhere: masks that keep the stage's loop free of
#: branches), and the balls' reference offset ỹ − y_n.
W_F, W_TMP, W_G, W_INVM, W_M, W_ISV, W_ISP, W_OFF = 0, 4, 5, 9, 10, 11, 12, 13
N_WORK = 14


def new_work(model):
    """``(work, jwork, schur)`` for :func:`rvcore.integrator.integrate` with the IMEX method."""
    n = model.n_states
    work = np.zeros((N_WORK, n))
    inv_m = work[W_INVM]
    p, rows = model.params, model.rows
    inv_m[5:8] = 1.0 / p[P_RING_M]
    # a held ring's tilts (InnerRing.tilt "held") are constrained: an inertia 1e12 times
    # its own keeps the implicit solve from giving them a rate (its coupling to the
    # balls then drops out of the Schur complement to 1e-12), and the right-hand side
    # reads them as 0 whatever they hold
    inv_m[8:10] = 1.0 / (p[P_RING_IT] * (1e12 if p[P_TILT_HELD] != 0.0 else 1.0))
    work[W_ISP, 0:5] = 1.0
    for r in range(rows.shape[0]):     # the implicit unknowns: the ring's and balls' velocities
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            inv_m[b + 3:b + 6] = 1.0 / rows[r, R_MB]
            inv_m[b + 6:b + 9] = 1.0 / rows[r, R_IB]
            work[W_ISP, b:b + 3] = 1.0
    work[W_M] = np.where(inv_m > 0, 1.0 / np.where(inv_m > 0, inv_m, 1.0), 0.0)
    work[W_ISV] = np.where(inv_m > 0, 1.0, 0.0)
    return work, np.zeros((model.n_balls + 1, N_JWORK)), np.zeros((N_SCHUR, 5))


@njit(cache=True, nogil=True)
def factor(jwork, schur, rows, mass):
    """Factor ``M + h·γ·D + (h·γ)²·K`` from the blocks :func:`rvcore.kernels.rhs_jac`
    accumulated.

    Per ball: ``A = Uᵀ·U`` (Cholesky, U in A's upper triangle) and ``X = U⁻ᵀ·B`` in place
    of B; then the ring's Schur complement ``S = M_ring + h·γ·D_ring − Σ Xᵀ·X`` and
    ``S = Uᵀ·U`` in place. ``mass`` is the state-indexed mass (0 at positions). A ball
    with no inner-race contact has ``B = 0`` (``J_COUPLED`` clear, set by
    :func:`rvcore.implicit.contact_blocks` when it writes B): skipped here and in
    :func:`solve`.

    Notes
    -----
    The diagonals of U (the balls' and the ring's) are stored as their reciprocals: they
    are only ever divisors, and a multiplication costs a fraction of a division. The
    ball's 6×6 block lives in scalar locals (no allocation, no index arithmetic in the
    inner loops; the 5 columns of B share them).
    """
    for i in range(5):
        schur[i, i] += mass[5 + i]
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        for j in range(int(rows[r, R_Z])):
            k = p0 + j
            b = b0 + BALL_STATES * j + 3
            # Cholesky A = UᵀU, row by row of U (same operation order as the textbook loop)
            u00 = math.sqrt(jwork[k, J_A + 0] + mass[b])
            i0 = 1.0 / u00
            u01 = jwork[k, J_A + 1] * i0
            u02 = jwork[k, J_A + 2] * i0
            u03 = jwork[k, J_A + 3] * i0
            u04 = jwork[k, J_A + 4] * i0
            u05 = jwork[k, J_A + 5] * i0
            u11 = math.sqrt(jwork[k, J_A + 7] + mass[b + 1] - u01 * u01)
            i1 = 1.0 / u11
            u12 = (jwork[k, J_A + 8] - u01 * u02) * i1
            u13 = (jwork[k, J_A + 9] - u01 * u03) * i1
            u14 = (jwork[k, J_A + 10] - u01 * u04) * i1
            u15 = (jwork[k, J_A + 11] - u01 * u05) * i1
            u22 = math.sqrt(jwork[k, J_A + 14] + mass[b + 2] - u02 * u02 - u12 * u12)
            i2 = 1.0 / u22
            u23 = (jwork[k, J_A + 15] - u02 * u03 - u12 * u13) * i2
            u24 = (jwork[k, J_A + 16] - u02 * u04 - u12 * u14) * i2
            u25 = (jwork[k, J_A + 17] - u02 * u05 - u12 * u15) * i2
            u33 = math.sqrt(jwork[k, J_A + 21] + mass[b + 3] - u03 * u03 - u13 * u13 - u23 * u23)
            i3 = 1.0 / u33
            u34 = (jwork[k, J_A + 22] - u03 * u04 - u13 * u14 - u23 * u24) * i3
            u35 = (jwork[k, J_A + 23] - u03 * u05 - u13 * u15 - u23 * u25) * i3
            u44 = math.sqrt(jwork[k, J_A + 28] + mass[b + 4] - u04 * u04 - u14 * u14 - u24 * u24
                            - u34 * u34)
            i4 = 1.0 / u44
            u45 = (jwork[k, J_A + 29] - u04 * u05 - u14 * u15 - u24 * u25 - u34 * u35) * i4
            u55 = math.sqrt(jwork[k, J_A + 35] + mass[b + 5] - u05 * u05 - u15 * u15 - u25 * u25
                            - u35 * u35 - u45 * u45)
            i5 = 1.0 / u55
            jwork[k, J_A + 0], jwork[k, J_A + 1], jwork[k, J_A + 2] = i0, u01, u02
            jwork[k, J_A + 3], jwork[k, J_A + 4], jwork[k, J_A + 5] = u03, u04, u05
            jwork[k, J_A + 7], jwork[k, J_A + 8], jwork[k, J_A + 9] = i1, u12, u13
            jwork[k, J_A + 10], jwork[k, J_A + 11] = u14, u15
            jwork[k, J_A + 14], jwork[k, J_A + 15], jwork[k, J_A + 16] = i2, u23, u24
            jwork[k, J_A + 17] = u25
            jwork[k, J_A + 21], jwork[k, J_A + 22], jwork[k, J_A + 23] = i3, u34, u35
            jwork[k, J_A + 28], jwork[k, J_A + 29] = i4, u45
            jwork[k, J_A + 35] = i5
            if jwork[k, J_COUPLED] == 0.0:
                continue
            # X = U⁻ᵀ B (forward substitution, column by column)
            for c in range(5):
                x0 = jwork[k, J_B + c] * i0
                x1 = (jwork[k, J_B + 5 + c] - u01 * x0) * i1
                x2 = (jwork[k, J_B + 10 + c] - u02 * x0 - u12 * x1) * i2
                x3 = (jwork[k, J_B + 15 + c] - u03 * x0 - u13 * x1 - u23 * x2) * i3
                x4 = (jwork[k, J_B + 20 + c] - u04 * x0 - u14 * x1 - u24 * x2 - u34 * x3) * i4
                x5 = (jwork[k, J_B + 25 + c] - u05 * x0 - u15 * x1 - u25 * x2 - u35 * x3 - u45 * x4) * i5
                jwork[k, J_B + c], jwork[k, J_B + 5 + c], jwork[k, J_B + 10 + c] = x0, x1, x2
                jwork[k, J_B + 15 + c], jwork[k, J_B + 20 + c], jwork[k, J_B + 25 + c] = x3, x4, x5
            # S −= XᵀX (upper triangle)
            for c in range(5):
                for d in range(c, 5):
                    schur[c, d] -= (jwork[k, J_B + c] * jwork[k, J_B + d]
                                    + jwork[k, J_B + 5 + c] * jwork[k, J_B + 5 + d]
                                    + jwork[k, J_B + 10 + c] * jwork[k, J_B + 10 + d]
                                    + jwork[k, J_B + 15 + c] * jwork[k, J_B + 15 + d]
                                    + jwork[k, J_B + 20 + c] * jwork[k, J_B + 20 + d]
                                    + jwork[k, J_B + 25 + c] * jwork[k, J_B + 25 + d])
    # Cholesky of S (upper triangle; reciprocal diagonal, as the balls')
    for i in range(5):
        s = schur[i, i]
        for l in range(i):
            s -= schur[l, i] ** 2
        inv = 1.0 / math.sqrt(s)
        schur[i, i] = inv
        for c in range(i + 1, 5):
            s = schur[i, c]
            for l in range(i):
                s -= schur[l, i] * schur[l, c]
            schur[i, c] = s * inv


@njit(cache=True, nogil=True)
def solve(v, jwork, schur, rows, mass):
    """Overwrite the velocities of the balls and the ring in the increment ``v`` with
    ``(M + h·γ·D + (h·γ)²·K)⁻¹·(M·v_v − h·γ·K·v_x)`` (the stage's velocity increment, its
    positions ``v_x`` being ``ê_x``; module docstring) with the factors of :func:`factor`
    (reciprocal diagonals) and the ``h·γ·K`` blocks of
    :func:`rvcore.implicit.stiffness_blocks`; the rest is untouched.
    ``jwork[:, J_W:J_W + 6]`` and ``schur[5]`` are its scratch."""
    rz = schur[5]
    x0, x1, x2, x3, x4 = v[0], v[1], v[2], v[3], v[4]
    for i in range(5):     # the ring's M·v − h·γ·K_rr·x (upper triangle stored)
        s = mass[5 + i] * v[5 + i]
        for l in range(5):
            s -= (schur[S_K + i, l] if l >= i else schur[S_K + l, i]) * v[l]
        rz[i] = s
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        for j in range(int(rows[r, R_Z])):
            k = p0 + j
            b = b0 + BALL_STATES * j + 3
            # h·γ·K·ê_x on the ball's centre, and the ring's share
            bx, by, bz = v[b - 3], v[b - 2], v[b - 1]
            fx = jwork[k, J_KA + 0] * bx + jwork[k, J_KA + 1] * by + jwork[k, J_KA + 2] * bz
            fy = jwork[k, J_KA + 1] * bx + jwork[k, J_KA + 3] * by + jwork[k, J_KA + 4] * bz
            fz = jwork[k, J_KA + 2] * bx + jwork[k, J_KA + 4] * by + jwork[k, J_KA + 5] * bz
            if jwork[k, J_COUPLED] != 0.0:
                fx += (jwork[k, J_KB + 0] * x0 + jwork[k, J_KB + 1] * x1 + jwork[k, J_KB + 2] * x2
                       + jwork[k, J_KB + 3] * x3 + jwork[k, J_KB + 4] * x4)
                fy += (jwork[k, J_KB + 5] * x0 + jwork[k, J_KB + 6] * x1 + jwork[k, J_KB + 7] * x2
                       + jwork[k, J_KB + 8] * x3 + jwork[k, J_KB + 9] * x4)
                fz += (jwork[k, J_KB + 10] * x0 + jwork[k, J_KB + 11] * x1 + jwork[k, J_KB + 12] * x2
                       + jwork[k, J_KB + 13] * x3 + jwork[k, J_KB + 14] * x4)
                for c in range(5):     # the ring's row: K_brᵀ·ê_x,ball
                    rz[c] -= jwork[k, J_KB + c] * bx + jwork[k, J_KB + 5 + c] * by + jwork[k, J_KB + 10 + c] * bz
            # w = U⁻ᵀ·(M_b·v_b − f)
            w0 = (mass[b] * v[b] - fx) * jwork[k, J_A + 0]
            w1 = (mass[b + 1] * v[b + 1] - fy - jwork[k, J_A + 1] * w0) * jwork[k, J_A + 7]
            w2 = (mass[b + 2] * v[b + 2] - fz - jwork[k, J_A + 2] * w0 - jwork[k, J_A + 8] * w1) * jwork[k, J_A + 14]
            w3 = (mass[b + 3] * v[b + 3] - jwork[k, J_A + 3] * w0 - jwork[k, J_A + 9] * w1
                  - jwork[k, J_A + 15] * w2) * jwork[k, J_A + 21]
            w4 = (mass[b + 4] * v[b + 4] - jwork[k, J_A + 4] * w0 - jwork[k, J_A + 10] * w1
                  - jwork[k, J_A + 16] * w2 - jwork[k, J_A + 22] * w3) * jwork[k, J_A + 28]
            w5 = (mass[b + 5] * v[b + 5] - jwork[k, J_A + 5] * w0 - jwork[k, J_A + 11] * w1
                  - jwork[k, J_A + 17] * w2 - jwork[k, J_A + 23] * w3 - jwork[k, J_A + 29] * w4) * jwork[k, J_A + 35]
            jwork[k, J_W + 0], jwork[k, J_W + 1], jwork[k, J_W + 2] = w0, w1, w2
            jwork[k, J_W + 3], jwork[k, J_W + 4], jwork[k, J_W + 5] = w3, w4, w5
            if jwork[k, J_COUPLED] != 0.0:
                for c in range(5):     # r_ring −= Xᵀ·w
                    rz[c] -= (jwork[k, J_B + c] * w0 + jwork[k, J_B + 5 + c] * w1
                              + jwork[k, J_B + 10 + c] * w2 + jwork[k, J_B + 15 + c] * w3
                              + jwork[k, J_B + 20 + c] * w4 + jwork[k, J_B + 25 + c] * w5)
    # S·Z = r: Uᵀ then U
    for i in range(5):
        s = rz[i]
        for l in range(i):
            s -= schur[l, i] * rz[l]
        rz[i] = s * schur[i, i]
    for i in range(4, -1, -1):
        s = rz[i]
        for l in range(i + 1, 5):
            s -= schur[i, l] * rz[l]
        rz[i] = s * schur[i, i]
    z0, z1, z2, z3, z4 = rz[0], rz[1], rz[2], rz[3], rz[4]
    v[5], v[6], v[7], v[8], v[9] = z0, z1, z2, z3, z4
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        for j in range(int(rows[r, R_Z])):
            k = p0 + j
            b = b0 + BALL_STATES * j + 3
            w0, w1, w2 = jwork[k, J_W + 0], jwork[k, J_W + 1], jwork[k, J_W + 2]
            w3, w4, w5 = jwork[k, J_W + 3], jwork[k, J_W + 4], jwork[k, J_W + 5]
            if jwork[k, J_COUPLED] != 0.0:     # w − X·Z
                w0 -= (jwork[k, J_B + 0] * z0 + jwork[k, J_B + 1] * z1 + jwork[k, J_B + 2] * z2
                       + jwork[k, J_B + 3] * z3 + jwork[k, J_B + 4] * z4)
                w1 -= (jwork[k, J_B + 5] * z0 + jwork[k, J_B + 6] * z1 + jwork[k, J_B + 7] * z2
                       + jwork[k, J_B + 8] * z3 + jwork[k, J_B + 9] * z4)
                w2 -= (jwork[k, J_B + 10] * z0 + jwork[k, J_B + 11] * z1 + jwork[k, J_B + 12] * z2
                       + jwork[k, J_B + 13] * z3 + jwork[k, J_B + 14] * z4)
                w3 -= (jwork[k, J_B + 15] * z0 + jwork[k, J_B + 16] * z1 + jwork[k, J_B + 17] * z2
                       + jwork[k, J_B + 18] * z3 + jwork[k, J_B + 19] * z4)
                w4 -= (jwork[k, J_B + 20] * z0 + jwork[k, J_B + 21] * z1 + jwork[k, J_B + 22] * z2
                       + jwork[k, J_B + 23] * z3 + jwork[k, J_B + 24] * z4)
                w5 -= (jwork[k, J_B + 25] * z0 + jwork[k, J_B + 26] * z1 + jwork[k, J_B + 27] * z2
                       + jwork[k, J_B + 28] * z3 + jwork[k, J_B + 29] * z4)
            # v_b = U⁻¹·(w − X·Z)
            x5 = w5 * jwork[k, J_A + 35]
            x4 = (w4 - jwork[k, J_A + 29] * x5) * jwork[k, J_A + 28]
            x3 = (w3 - jwork[k, J_A + 22] * x4 - jwork[k, J_A + 23] * x5) * jwork[k, J_A + 21]
            x2 = (w2 - jwork[k, J_A + 15] * x3 - jwork[k, J_A + 16] * x4 - jwork[k, J_A + 17] * x5) * jwork[k, J_A + 14]
            x1 = (w1 - jwork[k, J_A + 8] * x2 - jwork[k, J_A + 9] * x3 - jwork[k, J_A + 10] * x4
                  - jwork[k, J_A + 11] * x5) * jwork[k, J_A + 7]
            x0 = (w0 - jwork[k, J_A + 1] * x1 - jwork[k, J_A + 2] * x2 - jwork[k, J_A + 3] * x3
                  - jwork[k, J_A + 4] * x4 - jwork[k, J_A + 5] * x5) * jwork[k, J_A + 0]
            v[b], v[b + 1], v[b + 2], v[b + 3], v[b + 4], v[b + 5] = x0, x1, x2, x3, x4, x5


@njit(cache=True, nogil=True, inline="always")
def _implicit_stage(i, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    a1, a2, a3, i1, i2, i3, c):
    """Stage ``i`` (1–3, 0-based): Ŷ, the solve, g_i and F_i (module docstring). ``i1``
    weighs g_1, which is 0 (the reference at t_n is y_n): it drops out."""
    n = y.size
    tmp, g, f = work[W_TMP], work[W_G + i], work[W_F + i]
    f0, f1, f2 = work[W_F], work[W_F + 1], work[W_F + 2]
    g1, g2 = work[W_G + 1], work[W_G + 2]
    mass, isv, isp = work[W_M], work[W_ISV], work[W_ISP]
    for m in range(n):
        s = a1 * f0[m]         # g_1 = 0: the reference at t_n is y_n
        if i >= 2:
            s += a2 * f1[m] + (i2 - a2) * g1[m]
        if i >= 3:
            s += a3 * f2[m] + (i3 - a3) * g2[m]
        tmp[m] = dt * s        # Ŷ − y_n
    # The balls' stages are solved as deviations from a reference ỹ(t): y_n turned about
    # the bearing's axis at the ball's orbital speed Ω = (x·v_y − y·v_x)/ρ² (centre,
    # velocity and spin; module docstring, "Reference"). ê = Ŷ − y_n − h·a·ỹ'(t_prev)
    # (the explicit row's own quadrature of ỹ', one node back) and Y = ỹ(t_i) + e, so that
    # a ball on that orbit stays on it exactly. Rotations are Cayley's (orthogonal).
    off = work[W_OFF]
    ap = a1 if i == 1 else (a2 if i == 2 else a3)
    cp = 0.0 if i == 1 else 0.5        # the node of the explicit row's one entry
    for r in range(rows.shape[0]):
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            px, py, vx, vy = y[b], y[b + 1], y[b + 3], y[b + 4]
            om = (px * vy - py * vx) / (px * px + py * py)
            phi = om * c * dt
            d = 1.0 / (1.0 + 0.25 * phi * phi)
            cm1, sn = -0.5 * phi * phi * d, phi * d
            php = om * cp * dt
            dp = 1.0 / (1.0 + 0.25 * php * php)
            cp1, snp = 1.0 - 0.5 * php * php * dp, php * dp
            w = dt * ap * om
            for o in (0, 3, 6):         # centre, velocity, spin: the x and y components
                ux, uy = y[b + o], y[b + o + 1]
                off[b + o] = cm1 * ux - sn * uy
                off[b + o + 1] = sn * ux + cm1 * uy
                # h·a·Ω·(ẑ × R(φ_prev)·u)
                tmp[b + o] -= w * -(snp * ux + cp1 * uy)
                tmp[b + o + 1] -= w * (cp1 * ux - snp * uy)
    for m in range(n):
        g[m] = tmp[m]          # ê, for g_i below
    solve(tmp, jwork, schur, rows, mass)
    hg = dt * GAMMA
    inv_hg = 1.0 / hg
    # the positions: e_x = ê_x + h·γ·e_v and g_x = e_v (the velocities still increments)
    for m in range(5):
        g[m] = tmp[m + 5]
        tmp[m] = tmp[m] + hg * g[m]
    for r in range(rows.shape[0]):
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            for m in range(b, b + 3):
                g[m] = tmp[m + 3]
                tmp[m] = tmp[m] + hg * g[m]
    # the velocities: g_v = (e_v − ê_v)/(h·γ); 0 off the implicit unknowns
    for m in range(n):
        g[m] = isv[m] * ((tmp[m] - g[m]) * inv_hg) + isp[m] * g[m]
        tmp[m] += y[m] + off[m]
    rhs_stage(t + c * dt, tmp, f, params, rows, arcs, pockets, table, meta, diag, bdiag)
    return diag[D_DRIVE_TORQUE]


@njit(cache=True, nogil=True)
def imex_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, refresh):
    """Advance ``y`` by one IMEX step of ``dt``.

    On entry ``work[W_F]`` holds ``F(y)``, and ``jwork`` and ``schur`` the blocks that
    :func:`rvcore.kernels.rhs_jac` accumulated with ``h·γ = dt·GAMMA``: at ``(t, y)``
    when ``refresh`` (then factored here), or as factored at an earlier step.
    Returns ``Σ_{i≥2} b_i·T(Y_i)``, the later stages' share of the step's drive torque
    [N m] (the first stage's, ``b_1·T(y)``, the caller has).
    """
    n = y.size
    if refresh:
        factor(jwork, schur, rows, work[W_M])
    torque = B2 * _implicit_stage(1, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    A21, 0.0, 0.0, I21, 0.0, 0.0, 0.5)
    torque += B3 * _implicit_stage(2, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    0.0, A32, 0.0, I31, I32, 0.0, 0.5)
    torque += B4 * _implicit_stage(3, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    0.0, 0.0, A43, I41, I42, I43, 1.0)
    f0, f1, f2, f3 = work[W_F], work[W_F + 1], work[W_F + 2], work[W_F + 3]
    # b̂ = b: the g_i drop out of the update (module docstring)
    for m in range(n):
        y[m] += dt * (B1 * f0[m] + B2 * f1[m] + B3 * f2[m] + B4 * f3[m])
    return torque
