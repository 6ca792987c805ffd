"""The IMEX scheme's linear algebra: ``M + h·γ·D + (h·γ)²·K`` factored and solved through
the Schur complement on the ring. SI throughout.

The matrix is block-arrowhead: every ball's 6×6 block (its centre's velocity and its spin)
couples only to the ring's five rates, so :func:`factor` and :func:`solve` are O(Z), with
the blocks :func:`rvcore.dynamics.rhs.rhs_jac` accumulates (the columns of
:mod:`rvcore.dynamics.tangent`). :func:`pack` copies the factors a row at a time into a layout
of one quantity a row of balls, in which LLVM vectorises the solve's loops over the
balls (:func:`solve`, Notes). The scheme that calls them: :mod:`rvcore.integrate.imex`.
"""
from __future__ import annotations

import math

from .._numba import kernel

from ..dynamics.tangent import J_A, J_B, J_COUPLED, J_KA, J_KB, S_K
from ..dynamics.races import W
from ..bearing.layout import BALL_STATES, R_BALL0, R_POCKET0, R_Z


@kernel
def factor(jwork, schur, rows, mass):
    """Factor ``M + h·γ·D + (h·γ)²·K`` from the blocks :func:`rvcore.dynamics.rhs.rhs_jac`
    accumulated.

    Per ball: ``A = Uᵀ·U`` (Cholesky, U in A's upper triangle) and ``X = U⁻ᵀ·B`` in place
    of B; then the ring's Schur complement ``S = M_ring + h·γ·D_ring − Σ Xᵀ·X`` and
    ``S = Uᵀ·U`` in place. ``mass`` is the state-indexed mass (0 at positions). A ball
    with no inner-race contact has ``B = 0`` (``J_COUPLED`` clear, set by
    :func:`rvcore.dynamics.tangent.contact_blocks` when it writes B): skipped here and in
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


#: The packed factors of one row (:func:`pack`), a quantity ``f`` of the row's ball ``j``
#: at ``f·WS + j``: U's upper triangle (the diagonal as reciprocals, as :func:`factor`
#: leaves it), X = U⁻ᵀ·B, the blocks of ``h·γ·K``, the coupling flag, the ball's masses,
#: and the solve's own quantities (the ball's ê_x, then its velocities, w and the
#: result in turn). Constant distances and indices from 0, so that LLVM vectorises the
#: loops over the balls (rvcore.dynamics.races, "The scratch").
WS = W
(U00, U01, U02, U03, U04, U05, U11, U12, U13, U14, U15, U22, U23, U24, U25, U33, U34, U35, U44, U45,
 U55) = range(21)
_U_COLUMNS = (0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 14, 15, 16, 17, 21, 22, 23, 28, 29, 35)
F_X, F_KA, F_KB, F_COUPLED, F_M, F_EX, F_V = 21, 51, 57, 72, 73, 79, 82
N_SOLVE_FIELDS = 88


@kernel
def pack(jwork, rows, mass, sf):
    """Copy the factors :func:`factor` left in ``jwork`` and the balls' masses into ``sf``,
    row ``r`` from ``r·N_SOLVE_FIELDS·WS``, for :func:`solve`."""
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        o = r * N_SOLVE_FIELDS * WS
        for j in range(int(rows[r, R_Z])):
            k = p0 + j
            b = b0 + BALL_STATES * j + 3
            for i in range(21):
                sf[o + i * WS + j] = jwork[k, J_A + _U_COLUMNS[i]]
            for i in range(30):
                sf[o + (F_X + i) * WS + j] = jwork[k, J_B + i]
            for i in range(6):
                sf[o + (F_KA + i) * WS + j] = jwork[k, J_KA + i]
                sf[o + (F_M + i) * WS + j] = mass[b + i]
            for i in range(15):
                sf[o + (F_KB + i) * WS + j] = jwork[k, J_KB + i]
            sf[o + F_COUPLED * WS + j] = jwork[k, J_COUPLED]


@kernel
def _forward(s, nz, x0, x1, x2, x3, x4):
    """Every ball of a row: ``w = U⁻ᵀ·(M_b·v_b − h·γ·K·ê_x)`` in place of its velocities."""
    for j in range(nz):
        bx, by, bz = s[F_EX * WS + j], s[(F_EX + 1) * WS + j], s[(F_EX + 2) * WS + j]
        ka0, ka1, ka2 = s[F_KA * WS + j], s[(F_KA + 1) * WS + j], s[(F_KA + 2) * WS + j]
        ka3, ka4, ka5 = s[(F_KA + 3) * WS + j], s[(F_KA + 4) * WS + j], s[(F_KA + 5) * WS + j]
        coupled = s[F_COUPLED * WS + j] != 0.0
        # h·γ·K·ê_x on the ball's centre, and the ring's share
        fx = ka0 * bx + ka1 * by + ka2 * bz
        fy = ka1 * bx + ka3 * by + ka4 * bz
        fz = ka2 * bx + ka4 * by + ka5 * bz
        kb = F_KB * WS + j
        fx = fx + (s[kb] * x0 + s[kb + WS] * x1 + s[kb + 2 * WS] * x2 + s[kb + 3 * WS] * x3
                   + s[kb + 4 * WS] * x4) if coupled else fx
        fy = fy + (s[kb + 5 * WS] * x0 + s[kb + 6 * WS] * x1 + s[kb + 7 * WS] * x2 + s[kb + 8 * WS] * x3
                   + s[kb + 9 * WS] * x4) if coupled else fy
        fz = fz + (s[kb + 10 * WS] * x0 + s[kb + 11 * WS] * x1 + s[kb + 12 * WS] * x2 + s[kb + 13 * WS] * x3
                   + s[kb + 14 * WS] * x4) if coupled else fz
        m, v = F_M * WS + j, F_V * WS + j
        w0 = (s[m] * s[v] - fx) * s[U00 * WS + j]
        w1 = (s[m + WS] * s[v + WS] - fy - s[U01 * WS + j] * w0) * s[U11 * WS + j]
        w2 = (s[m + 2 * WS] * s[v + 2 * WS] - fz - s[U02 * WS + j] * w0 - s[U12 * WS + j] * w1) * s[U22 * WS + j]
        w3 = (s[m + 3 * WS] * s[v + 3 * WS] - s[U03 * WS + j] * w0 - s[U13 * WS + j] * w1
              - s[U23 * WS + j] * w2) * s[U33 * WS + j]
        w4 = (s[m + 4 * WS] * s[v + 4 * WS] - s[U04 * WS + j] * w0 - s[U14 * WS + j] * w1
              - s[U24 * WS + j] * w2 - s[U34 * WS + j] * w3) * s[U44 * WS + j]
        w5 = (s[m + 5 * WS] * s[v + 5 * WS] - s[U05 * WS + j] * w0 - s[U15 * WS + j] * w1
              - s[U25 * WS + j] * w2 - s[U35 * WS + j] * w3 - s[U45 * WS + j] * w4) * s[U55 * WS + j]
        s[v], s[v + WS], s[v + 2 * WS], s[v + 3 * WS], s[v + 4 * WS], s[v + 5 * WS] = w0, w1, w2, w3, w4, w5


@kernel
def _backward(s, nz, z0, z1, z2, z3, z4):
    """Every ball of a row: ``U⁻¹·(w − X·Z)`` in place of its w."""
    for j in range(nz):
        v = F_V * WS + j
        w0, w1, w2 = s[v], s[v + WS], s[v + 2 * WS]
        w3, w4, w5 = s[v + 3 * WS], s[v + 4 * WS], s[v + 5 * WS]
        coupled = s[F_COUPLED * WS + j] != 0.0
        x = F_X * WS + j
        w0 = w0 - (s[x] * z0 + s[x + WS] * z1 + s[x + 2 * WS] * z2 + s[x + 3 * WS] * z3
                   + s[x + 4 * WS] * z4) if coupled else w0
        w1 = w1 - (s[x + 5 * WS] * z0 + s[x + 6 * WS] * z1 + s[x + 7 * WS] * z2 + s[x + 8 * WS] * z3
                   + s[x + 9 * WS] * z4) if coupled else w1
        w2 = w2 - (s[x + 10 * WS] * z0 + s[x + 11 * WS] * z1 + s[x + 12 * WS] * z2 + s[x + 13 * WS] * z3
                   + s[x + 14 * WS] * z4) if coupled else w2
        w3 = w3 - (s[x + 15 * WS] * z0 + s[x + 16 * WS] * z1 + s[x + 17 * WS] * z2 + s[x + 18 * WS] * z3
                   + s[x + 19 * WS] * z4) if coupled else w3
        w4 = w4 - (s[x + 20 * WS] * z0 + s[x + 21 * WS] * z1 + s[x + 22 * WS] * z2 + s[x + 23 * WS] * z3
                   + s[x + 24 * WS] * z4) if coupled else w4
        w5 = w5 - (s[x + 25 * WS] * z0 + s[x + 26 * WS] * z1 + s[x + 27 * WS] * z2 + s[x + 28 * WS] * z3
                   + s[x + 29 * WS] * z4) if coupled else w5
        x5 = w5 * s[U55 * WS + j]
        x4 = (w4 - s[U45 * WS + j] * x5) * s[U44 * WS + j]
        x3 = (w3 - s[U34 * WS + j] * x4 - s[U35 * WS + j] * x5) * s[U33 * WS + j]
        x2 = (w2 - s[U23 * WS + j] * x3 - s[U24 * WS + j] * x4 - s[U25 * WS + j] * x5) * s[U22 * WS + j]
        x1 = (w1 - s[U12 * WS + j] * x2 - s[U13 * WS + j] * x3 - s[U14 * WS + j] * x4
              - s[U15 * WS + j] * x5) * s[U11 * WS + j]
        x0 = (w0 - s[U01 * WS + j] * x1 - s[U02 * WS + j] * x2 - s[U03 * WS + j] * x3 - s[U04 * WS + j] * x4
              - s[U05 * WS + j] * x5) * s[U00 * WS + j]
        s[v], s[v + WS], s[v + 2 * WS], s[v + 3 * WS], s[v + 4 * WS], s[v + 5 * WS] = x0, x1, x2, x3, x4, x5


@kernel
def solve(v, schur, rows, mass, sf):
    """Overwrite the velocities of the balls and the ring in the increment ``v`` with
    ``(M + h·γ·D + (h·γ)²·K)⁻¹·(M·v_v − h·γ·K·v_x)`` (the stage's velocity increment, its
    positions ``v_x`` being ``ê_x``; module docstring) with the factors :func:`pack` left
    in ``sf`` (reciprocal diagonals), the ring's factor and ``h·γ·K`` block in ``schur``
    and the state-indexed ``mass``; the rest is untouched. ``schur[5]`` is its scratch.

    Notes
    -----
    The balls' parts are loops over a row's balls (:func:`_forward`, :func:`_backward`),
    the ring's sums over the balls a loop of their own, in the balls' order: the same
    operations in the same order as one loop a ball, the same bits.
    """
    rz = schur[5]
    x0, x1, x2, x3, x4 = v[0], v[1], v[2], v[3], v[4]
    for i in range(5):     # the ring's M·v − h·γ·K_rr·x (upper triangle stored)
        s = mass[5 + i] * v[5 + i]
        for l in range(5):
            s -= (schur[S_K + i, l] if l >= i else schur[S_K + l, i]) * v[l]
        rz[i] = s
    for r in range(rows.shape[0]):
        b0, nz = int(rows[r, R_BALL0]), int(rows[r, R_Z])
        s = sf[r * N_SOLVE_FIELDS * WS:(r + 1) * N_SOLVE_FIELDS * WS]
        for j in range(nz):
            b = b0 + BALL_STATES * j
            for i in range(3):
                s[(F_EX + i) * WS + j] = v[b + i]
            for i in range(6):
                s[(F_V + i) * WS + j] = v[b + 3 + i]
        _forward(s, nz, x0, x1, x2, x3, x4)
        for j in range(nz):     # the ring's row, ball by ball: K_brᵀ·ê_x,ball and Xᵀ·w
            if s[F_COUPLED * WS + j] == 0.0:
                continue
            bx, by, bz = s[F_EX * WS + j], s[(F_EX + 1) * WS + j], s[(F_EX + 2) * WS + j]
            kb, x, vv = F_KB * WS + j, F_X * WS + j, F_V * WS + j
            for c in range(5):
                rz[c] -= s[kb + c * WS] * bx + s[kb + (5 + c) * WS] * by + s[kb + (10 + c) * WS] * bz
            w0, w1, w2 = s[vv], s[vv + WS], s[vv + 2 * WS]
            w3, w4, w5 = s[vv + 3 * WS], s[vv + 4 * WS], s[vv + 5 * WS]
            for c in range(5):
                rz[c] -= (s[x + c * WS] * w0 + s[x + (5 + c) * WS] * w1 + s[x + (10 + c) * WS] * w2
                          + s[x + (15 + c) * WS] * w3 + s[x + (20 + c) * WS] * w4 + s[x + (25 + c) * WS] * w5)
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
        b0, nz = int(rows[r, R_BALL0]), int(rows[r, R_Z])
        s = sf[r * N_SOLVE_FIELDS * WS:(r + 1) * N_SOLVE_FIELDS * WS]
        _backward(s, nz, z0, z1, z2, z3, z4)
        for j in range(nz):
            b = b0 + BALL_STATES * j + 3
            for i in range(6):
                v[b + i] = s[(F_V + i) * WS + j]
