"""The IMEX scheme's linear algebra: ``M + h·γ·D + (h·γ)²·K`` factored and solved through
the Schur complement on the ring. SI throughout.

The matrix is block-arrowhead: every ball's 6×6 block (its centre's velocity and its spin)
couples only to the ring's five rates, so :func:`factor` and :func:`solve` are O(Z), with
the blocks :func:`rvcore.kernels.rhs_jac` accumulates (the columns of
:mod:`rvcore.implicit`). The scheme that calls them: :mod:`rvcore.imex`.
"""
from __future__ import annotations

import math

from numba import njit

from .implicit import J_A, J_B, J_COUPLED, J_KA, J_KB, J_W, S_K
from .model import BALL_STATES, R_BALL0, R_POCKET0, R_Z


@njit(cache=True, nogil=True, error_model="numpy")
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


@njit(cache=True, nogil=True, error_model="numpy")
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
