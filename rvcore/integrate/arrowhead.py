"""The IMEX scheme's linear algebra: ``M + h·γ·D + (h·γ)²·K`` factored and solved through
the Schur complement on the ring. SI throughout.

The matrix is block-arrowhead: every ball's 6×6 block (its centre's velocity and its spin)
couples only to the ring's five rates, so :func:`factor` and :func:`solve` are O(Z), with
the blocks :func:`rvcore.dynamics.rhs.rhs_jac` accumulates (the columns of
:mod:`rvcore.dynamics.tangent`). :func:`factor` copies them a row at a time into a layout
of one quantity a row of balls and factors them there, in which LLVM vectorises the
factorization's and the solve's loops over the balls (:func:`solve`, Notes). The scheme
that calls them: :mod:`rvcore.integrate.imex`.
"""
from __future__ import annotations

import math

from .._numba import kernel

from ..dynamics.tangent import (FX_ANG, FX_C, FX_CK, FX_ON, FX_P, FX_PHI, FX_V, J_A, J_B, J_COUPLED, J_FX,
                                J_KA, J_KB, S_K)
from ..dynamics.ring_modes import FX_ORDER, family_record, modal_offset
from ..dynamics.races import W
from ..bearing.layout import BALL_STATES, R_BALL0, R_POCKET0, R_Z


#: The packed factors of one row (:func:`factor`), a quantity ``f`` of the row's ball ``j``
#: at ``f·WS + j``: U's upper triangle (the diagonal as reciprocals), X = U⁻ᵀ·B, the
#: blocks of ``h·γ·K``, the coupling flag, the ball's masses, and the solve's own
#: quantities (the ball's ê_x, then its velocities, w and the result in turn). Constant
#: distances and indices from 0, so that LLVM vectorises the loops over the balls
#: (rvcore.dynamics.races, "The scratch").
WS = W
(U00, U01, U02, U03, U04, U05, U11, U12, U13, U14, U15, U22, U23, U24, U25, U33, U34, U35, U44, U45,
 U55) = range(21)
_U_COLUMNS = (0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 14, 15, 16, 17, 21, 22, 23, 28, 29, 35)
F_X, F_KA, F_KB, F_COUPLED, F_M, F_EX, F_V = 21, 51, 57, 72, 73, 79, 82
N_SOLVE_FIELDS = 88


@kernel
def factor(jwork, schur, rows, mass, sf):
    """Factor ``M + h·γ·D + (h·γ)²·K`` from the blocks :func:`rvcore.dynamics.rhs.rhs_jac`
    accumulated in ``jwork``, into the packed factors ``sf`` (row ``r`` from
    ``r·N_SOLVE_FIELDS·WS``) that :func:`solve` reads.

    Per ball: ``A = Uᵀ·U`` (Cholesky) and ``X = U⁻ᵀ·B``; then the ring's Schur complement
    ``S = M_ring + h·γ·D_ring − Σ Xᵀ·X`` and ``S = Uᵀ·U`` in place in ``schur``. ``mass``
    is the state-indexed mass (0 at positions). A ball with no inner-race contact has
    ``B = 0`` (``J_COUPLED`` clear, set by :func:`rvcore.dynamics.tangent.contact_blocks`
    when it writes B): its ``X`` is 0, left out of ``S`` here and skipped in :func:`solve`.

    Notes
    -----
    The blocks are first copied into the packed layout (a quantity a row of balls), where
    each ball's Cholesky and ``X`` are one loop over the row's balls that LLVM vectorises
    (:func:`_factor_balls`); ``S``'s sums over the balls stay a loop in the balls' order.
    The diagonals of U (the balls' and the ring's) are stored as their reciprocals: they
    are only ever divisors, and a multiplication costs a fraction of a division.
    """
    for i in range(5):
        schur[i, i] += mass[5 + i]
    for r in range(rows.shape[0]):
        b0, p0, nz = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0]), int(rows[r, R_Z])
        s = sf[r * N_SOLVE_FIELDS * WS:(r + 1) * N_SOLVE_FIELDS * WS]
        for j in range(nz):
            k = p0 + j
            b = b0 + BALL_STATES * j + 3
            for i in range(21):
                s[i * WS + j] = jwork[k, J_A + _U_COLUMNS[i]]
            for i in range(30):
                s[(F_X + i) * WS + j] = jwork[k, J_B + i]
            for i in range(6):
                s[(F_KA + i) * WS + j] = jwork[k, J_KA + i]
                s[(F_M + i) * WS + j] = mass[b + i]
            for i in range(15):
                s[(F_KB + i) * WS + j] = jwork[k, J_KB + i]
            s[F_COUPLED * WS + j] = jwork[k, J_COUPLED]
        _factor_balls(s, nz)
        # S −= XᵀX (upper triangle), ball by ball
        for j in range(nz):
            if s[F_COUPLED * WS + j] == 0.0:
                continue
            x = F_X * WS + j
            for c in range(5):
                for d in range(c, 5):
                    schur[c, d] -= (s[x + c * WS] * s[x + d * WS]
                                    + s[x + (5 + c) * WS] * s[x + (5 + d) * WS]
                                    + s[x + (10 + c) * WS] * s[x + (10 + d) * WS]
                                    + s[x + (15 + c) * WS] * s[x + (15 + d) * WS]
                                    + s[x + (20 + c) * WS] * s[x + (20 + d) * WS]
                                    + s[x + (25 + c) * WS] * s[x + (25 + d) * WS])
    # Cholesky of S (upper triangle; reciprocal diagonal, as the balls')
    for i in range(5):
        t = schur[i, i]
        for l in range(i):
            t -= schur[l, i] ** 2
        inv = 1.0 / math.sqrt(t)
        schur[i, i] = inv
        for c in range(i + 1, 5):
            t = schur[i, c]
            for l in range(i):
                t -= schur[l, i] * schur[l, c]
            schur[i, c] = t * inv


@kernel(inline=True)
def _root(x):
    """``√x``, NaN for ``x < 0`` (a pivot of a matrix that is not positive definite), as
    ``math.sqrt`` gives; taken of ``|x|`` so that LLVM, which then knows the argument is
    not negative, calls no C library ``sqrt`` (it may set errno) and vectorises the loop
    (as :func:`rvcore.contact.laws.hertz_load`)."""
    return math.sqrt(abs(x)) if x >= 0.0 else math.nan


@kernel
def _factor_balls(s, nz):
    """Every ball of a row, in the packed layout: ``A + M_b = Uᵀ·U`` in place of A's upper
    triangle (row by row of U, the textbook loop's operation order; reciprocal diagonal)
    and ``X = U⁻ᵀ·B`` in place of B (forward substitution, column by column)."""
    for j in range(nz):
        m = F_M * WS + j
        u00 = _root((s[U00 * WS + j] + s[m]))
        i0 = 1.0 / u00
        u01 = s[U01 * WS + j] * i0
        u02 = s[U02 * WS + j] * i0
        u03 = s[U03 * WS + j] * i0
        u04 = s[U04 * WS + j] * i0
        u05 = s[U05 * WS + j] * i0
        u11 = _root((s[U11 * WS + j] + s[m + WS] - u01 * u01))
        i1 = 1.0 / u11
        u12 = (s[U12 * WS + j] - u01 * u02) * i1
        u13 = (s[U13 * WS + j] - u01 * u03) * i1
        u14 = (s[U14 * WS + j] - u01 * u04) * i1
        u15 = (s[U15 * WS + j] - u01 * u05) * i1
        u22 = _root((s[U22 * WS + j] + s[m + 2 * WS] - u02 * u02 - u12 * u12))
        i2 = 1.0 / u22
        u23 = (s[U23 * WS + j] - u02 * u03 - u12 * u13) * i2
        u24 = (s[U24 * WS + j] - u02 * u04 - u12 * u14) * i2
        u25 = (s[U25 * WS + j] - u02 * u05 - u12 * u15) * i2
        u33 = _root((s[U33 * WS + j] + s[m + 3 * WS] - u03 * u03 - u13 * u13 - u23 * u23))
        i3 = 1.0 / u33
        u34 = (s[U34 * WS + j] - u03 * u04 - u13 * u14 - u23 * u24) * i3
        u35 = (s[U35 * WS + j] - u03 * u05 - u13 * u15 - u23 * u25) * i3
        u44 = _root((s[U44 * WS + j] + s[m + 4 * WS] - u04 * u04 - u14 * u14 - u24 * u24 - u34 * u34))
        i4 = 1.0 / u44
        u45 = (s[U45 * WS + j] - u04 * u05 - u14 * u15 - u24 * u25 - u34 * u35) * i4
        u55 = _root((s[U55 * WS + j] + s[m + 5 * WS] - u05 * u05 - u15 * u15 - u25 * u25 - u35 * u35
                            - u45 * u45))
        i5 = 1.0 / u55
        s[U00 * WS + j], s[U01 * WS + j], s[U02 * WS + j] = i0, u01, u02
        s[U03 * WS + j], s[U04 * WS + j], s[U05 * WS + j] = u03, u04, u05
        s[U11 * WS + j], s[U12 * WS + j], s[U13 * WS + j] = i1, u12, u13
        s[U14 * WS + j], s[U15 * WS + j] = u14, u15
        s[U22 * WS + j], s[U23 * WS + j], s[U24 * WS + j] = i2, u23, u24
        s[U25 * WS + j] = u25
        s[U33 * WS + j], s[U34 * WS + j], s[U35 * WS + j] = i3, u34, u35
        s[U44 * WS + j], s[U45 * WS + j] = i4, u45
        s[U55 * WS + j] = i5
    for c in range(5):     # a column at a time: the loop over the balls innermost
        for j in range(nz):
            i0, u01, u02, u03, u04, u05 = (s[U00 * WS + j], s[U01 * WS + j], s[U02 * WS + j], s[U03 * WS + j],
                                           s[U04 * WS + j], s[U05 * WS + j])
            i1, u12, u13, u14, u15 = s[U11 * WS + j], s[U12 * WS + j], s[U13 * WS + j], s[U14 * WS + j], s[U15 * WS + j]
            i2, u23, u24, u25 = s[U22 * WS + j], s[U23 * WS + j], s[U24 * WS + j], s[U25 * WS + j]
            i3, u34, u35 = s[U33 * WS + j], s[U34 * WS + j], s[U35 * WS + j]
            i4, u45, i5 = s[U44 * WS + j], s[U45 * WS + j], s[U55 * WS + j]
            x = (F_X + c) * WS + j
            x0 = s[x] * i0
            x1 = (s[x + 5 * WS] - u01 * x0) * i1
            x2 = (s[x + 10 * WS] - u02 * x0 - u12 * x1) * i2
            x3 = (s[x + 15 * WS] - u03 * x0 - u13 * x1 - u23 * x2) * i3
            x4 = (s[x + 20 * WS] - u04 * x0 - u14 * x1 - u24 * x2 - u34 * x3) * i4
            x5 = (s[x + 25 * WS] - u05 * x0 - u15 * x1 - u25 * x2 - u35 * x3 - u45 * x4) * i5
            s[x], s[x + 5 * WS], s[x + 10 * WS] = x0, x1, x2
            s[x + 15 * WS], s[x + 20 * WS], s[x + 25 * WS] = x3, x4, x5


@kernel(inline=True)
def _back_substitute(s, j, x0, x1, x2, x3, x4, x5):
    """``U⁻¹·x`` with the ball ``j``'s factor ``U`` as :func:`factor` leaves it in the packed
    ``s`` (upper triangle, reciprocal diagonal)."""
    x5 = x5 * s[U55 * WS + j]
    x4 = (x4 - s[U45 * WS + j] * x5) * s[U44 * WS + j]
    x3 = (x3 - s[U34 * WS + j] * x4 - s[U35 * WS + j] * x5) * s[U33 * WS + j]
    x2 = (x2 - s[U23 * WS + j] * x3 - s[U24 * WS + j] * x4 - s[U25 * WS + j] * x5) * s[U22 * WS + j]
    x1 = (x1 - s[U12 * WS + j] * x2 - s[U13 * WS + j] * x3 - s[U14 * WS + j] * x4
          - s[U15 * WS + j] * x5) * s[U11 * WS + j]
    x0 = (x0 - s[U01 * WS + j] * x1 - s[U02 * WS + j] * x2 - s[U03 * WS + j] * x3 - s[U04 * WS + j] * x4
          - s[U05 * WS + j] * x5) * s[U00 * WS + j]
    return x0, x1, x2, x3, x4, x5


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
        x0, x1, x2, x3, x4, x5 = _back_substitute(s, j, w0, w1, w2, w3, w4, w5)
        s[v], s[v + WS], s[v + 2 * WS], s[v + 3 * WS], s[v + 4 * WS], s[v + 5 * WS] = x0, x1, x2, x3, x4, x5


@kernel
def solve(v, schur, rows, mass, sf):
    """Overwrite the velocities of the balls and the ring in the increment ``v`` with
    ``(M + h·γ·D + (h·γ)²·K)⁻¹·(M·v_v − h·γ·K·v_x)`` (the stage's velocity increment, its
    positions ``v_x`` being ``ê_x``; module docstring) with the factors :func:`factor` left
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


# ---- a flexible ring's modes (rvcore.dynamics.ring_modes) beside the arrowhead system

#: Rows of the modes' block ``fx`` after its ``nm × nm`` Schur complement (``nm`` the modal
#: unknowns, :func:`rvcore.dynamics.ring_modes.modal_offset`): ``Z = U_r⁻ᵀ·Y`` (5 rows), the
#: modes' right-hand side, then, flat, the harmonic sums (:func:`factor_modes`) and each
#: row's packed modal factors (:data:`MP_V`…).
FX_Y, FX_RM, FX_FLAT = 0, 5, 6
#: The family pairs ``(f, g)``, ``f ≤ g``, of the harmonic sums, in their order.
N_PAIRS = 10
#: The sums over the balls that run along a family's modes (the solve's shape forces,
#: :func:`factor_modes`' ``Y``) when the largest family has at most 8 orders: over all 16
#: lanes, those past a family's own left over, into accumulators of their own
#: (:data:`N_LANE_SUMS` of them after the harmonic sums), and the harmonic sums a family
#: pair at a time, cos and sin in one loop (:func:`harmonic_width`). Each sum still takes
#: the balls in their order: the same bits. Which form LLVM vectorises was measured, not
#: assumed (docs/performance.md, "Flexible rings in the dynamics"): the solve's four
#: families at once with the constant length 16 (a length known only at run time was
#: slower), ``factor_modes``' sums with a length known only at run time (vectorised behind
#: a check that the views do not overlap; with the constant 16, unrolled and left scalar).
LANES = 16
N_SOLVE_LANE_SUMS, N_Y_LANE_SUMS = 4, 20      # the solve's (a family each), Y's (5 components × 4 families)
N_LANE_SUMS = N_SOLVE_LANE_SUMS + N_Y_LANE_SUMS
#: The packed modal factors of one row, a quantity ``q`` of the row's ball ``j`` at
#: ``q·WS + j`` (as :func:`factor`'s, so that the solve's loops over the balls vectorise):
#: per family ``V_f`` and ``h·γ·K``'s ``VK_f`` (3 each), for the inner ring's families
#: ``P_f`` and ``PK_f`` (5 each), ``h·γ·K``'s own blocks per ring (3 each), ``A_b⁻¹·V_f``
#: (6 each), ``A_b⁻¹·B_b`` (6×5); the solve's own (the ball's ê_x or y, the families'
#: shape values, their terms, the ball's force, σ_f, its correction); :func:`factor_modes`'
#: own (the ball's families' own block per ring in the stage matrix's weights, 3 each, its
#: flag, per family ``U⁻ᵀ·V_f`` (6) and ``y_f`` (5), the 10 family pairs' ``H``); from
#: ``MP_PHI`` the shape ``φ``.
(MP_V, MP_VK, MP_P, MP_PK, MP_CK, MP_Q, MP_AB, MP_EX, MP_SH, MP_T, MP_FB, MP_SG, MP_CR,
 MP_C, MP_ON, MP_X, MP_Y, MP_H, MP_PHI) = (0, 12, 24, 34, 44, 50, 74, 104, 107, 111, 115, 118, 122, 128, 134, 135,
                                           159, 179, 189)


def _packed_size(max_orders: int) -> int:
    """Quantities of a row's packed modal factors (:data:`MP_PHI` and the shape)."""
    return MP_PHI + 2 * max_orders


def modal_block_rows(n_modes: int, max_orders: int, width: int, n_rows: int) -> int:
    """Rows of width ``width`` the modes' block ``fx`` takes: ``n_modes`` modal unknowns,
    ``max_orders`` orders in the largest family, ``n_rows`` rows of balls."""
    flat = _rows_at(max_orders) + n_rows * _packed_size(max_orders) * WS
    return n_modes + FX_FLAT + -(-flat // width)


@kernel(inline=True)
def harmonic_width(max_orders):
    """The room of each harmonic sum (cos or sin of one family pair) and of a ball's
    harmonics in ``jwork``: :data:`LANES` where the sums run along the lanes (``2·K ≤
    LANES``), else the ``2·K − 1`` harmonics themselves (``K`` the largest family's
    orders)."""
    return LANES if 2 * max_orders <= LANES else 2 * max_orders - 1


@kernel(inline=True)
def _lanes_at(max_orders):
    """Where the lanes' accumulators start in the flat part of ``fx``, after the harmonic
    sums: the solve's :data:`N_SOLVE_LANE_SUMS`, then ``Y``'s :data:`N_Y_LANE_SUMS`, each
    :data:`LANES` long."""
    return 2 * N_PAIRS * harmonic_width(max_orders)


@kernel(inline=True)
def _rows_at(max_orders):
    """Where the rows' packed modal factors start in the flat part of ``fx``: after the
    harmonic sums and the lanes' accumulators."""
    return _lanes_at(max_orders) + N_LANE_SUMS * LANES


@kernel(inline=True)
def _max_orders(params):
    n = 0
    for f in range(4):
        n = max(n, family_record(params, f)[0])
    return n


@kernel
def _modal_balls(s, mp, nz):
    """Every ball of a row, from its factors (``s``, :func:`factor`) and its couplings
    (``mp``): per family ``x_f = U⁻ᵀ·V_f`` (``MP_X``), ``y_f = P_f − Xᵀ·x_f`` (``MP_Y``)
    and ``A_b⁻¹·V_f = U⁻¹·x_f`` (``MP_Q``); ``A_b⁻¹·B_b = U⁻¹·X`` (``MP_AB``); the
    family pairs' ``H = core − x_f·x_g`` (``MP_H``). A ball without a contact on a flexible
    ring (``MP_ON`` 0) gets 0 in ``MP_Q``, one not coupled to the ring 0 in ``MP_AB``: a
    ball coupled to the ring takes its part of ``A⁻¹·C`` through the ring even without
    modes of its own. Loops over the balls innermost (vectorised)."""
    for f in range(4):
        v = (MP_V + 3 * f) * WS
        x = (MP_X + 6 * f) * WS
        y = (MP_Y + 5 * f) * WS
        q = (MP_Q + 6 * f) * WS
        for j in range(nz):
            i0, i1, i2 = s[U00 * WS + j], s[U11 * WS + j], s[U22 * WS + j]
            i3, i4, i5 = s[U33 * WS + j], s[U44 * WS + j], s[U55 * WS + j]
            u01, u02, u03 = s[U01 * WS + j], s[U02 * WS + j], s[U03 * WS + j]
            u04, u05 = s[U04 * WS + j], s[U05 * WS + j]
            u12, u13, u14, u15 = s[U12 * WS + j], s[U13 * WS + j], s[U14 * WS + j], s[U15 * WS + j]
            u23, u24, u25 = s[U23 * WS + j], s[U24 * WS + j], s[U25 * WS + j]
            u34, u35, u45 = s[U34 * WS + j], s[U35 * WS + j], s[U45 * WS + j]
            x0 = mp[v + j] * i0
            x1 = (mp[v + WS + j] - u01 * x0) * i1
            x2 = (mp[v + 2 * WS + j] - u02 * x0 - u12 * x1) * i2
            x3 = (-u03 * x0 - u13 * x1 - u23 * x2) * i3
            x4 = (-u04 * x0 - u14 * x1 - u24 * x2 - u34 * x3) * i4
            x5 = (-u05 * x0 - u15 * x1 - u25 * x2 - u35 * x3 - u45 * x4) * i5
            mp[x + j], mp[x + WS + j], mp[x + 2 * WS + j] = x0, x1, x2
            mp[x + 3 * WS + j], mp[x + 4 * WS + j], mp[x + 5 * WS + j] = x3, x4, x5
            # A_b⁻¹·V_f = U⁻¹·(U⁻ᵀ·V_f), for the solve's back substitution
            x0, x1, x2, x3, x4, x5 = _back_substitute(s, j, x0, x1, x2, x3, x4, x5)
            on = mp[MP_ON * WS + j] != 0.0
            mp[q + j] = x0 if on else 0.0
            mp[q + WS + j] = x1 if on else 0.0
            mp[q + 2 * WS + j] = x2 if on else 0.0
            mp[q + 3 * WS + j] = x3 if on else 0.0
            mp[q + 4 * WS + j] = x4 if on else 0.0
            mp[q + 5 * WS + j] = x5 if on else 0.0
        for c in range(5):      # y_f = P_f − Xᵀ·(U⁻ᵀV_f)
            xc = (F_X + c) * WS
            for j in range(nz):
                t = mp[(MP_P + 5 * f + c) * WS + j] if f < 2 else 0.0
                x0, x1, x2 = mp[x + j], mp[x + WS + j], mp[x + 2 * WS + j]
                x3, x4, x5 = mp[x + 3 * WS + j], mp[x + 4 * WS + j], mp[x + 5 * WS + j]
                t = t - (s[xc + j] * x0 + s[xc + 5 * WS + j] * x1 + s[xc + 10 * WS + j] * x2
                         + s[xc + 15 * WS + j] * x3 + s[xc + 20 * WS + j] * x4 + s[xc + 25 * WS + j] * x5
                         ) if s[F_COUPLED * WS + j] != 0.0 else t
                mp[y + c * WS + j] = t
    for c in range(5):      # A_b⁻¹·B_b = U⁻¹·X, column by column
        for j in range(nz):
            live = s[F_COUPLED * WS + j] != 0.0
            xc = (F_X + c) * WS + j
            x0, x1, x2, x3, x4, x5 = _back_substitute(s, j, s[xc], s[xc + 5 * WS], s[xc + 10 * WS],
                                                      s[xc + 15 * WS], s[xc + 20 * WS], s[xc + 25 * WS])
            q = (MP_AB + c) * WS + j
            mp[q] = x0 if live else 0.0
            mp[q + 5 * WS] = x1 if live else 0.0
            mp[q + 10 * WS] = x2 if live else 0.0
            mp[q + 15 * WS] = x3 if live else 0.0
            mp[q + 20 * WS] = x4 if live else 0.0
            mp[q + 25 * WS] = x5 if live else 0.0
    pair = 0
    for f in range(4):
        o = (MP_X + 6 * f) * WS
        for g in range(f, 4):
            q = (MP_X + 6 * g) * WS
            h = (MP_H + pair) * WS
            # the contacts' own block (0 across rings)
            core = (MP_C + 3 * (f // 2) + (f % 2) + (g % 2)) * WS
            same = f // 2 == g // 2
            for j in range(nz):
                mp[h + j] = (mp[core + j] if same else 0.0) - (
                    mp[o + j] * mp[q + j] + mp[o + WS + j] * mp[q + WS + j] + mp[o + 2 * WS + j] * mp[q + 2 * WS + j]
                    + mp[o + 3 * WS + j] * mp[q + 3 * WS + j] + mp[o + 4 * WS + j] * mp[q + 4 * WS + j]
                    + mp[o + 5 * WS + j] * mp[q + 5 * WS + j])
            pair += 1


@kernel
def factor_modes(jwork, schur, rows, params, fx, hg, sf):
    """The Schur complement of the stage matrix on a flexible ring's modes, factored.

    After :func:`factor` (which leaves each ball's ``U`` and ``X = U⁻ᵀ·B`` in the packed
    ``sf`` and the ring's factor in ``schur``). The stage matrix ``[[A, C], [Cᵀ, D]]``: ``A``
    the arrowhead system (balls and pose), ``D`` the modes' ``M_k + h·γ·c_k + (h·γ)²·K_k``
    plus the contacts' own block on them, ``C`` the contacts' coupling of the modes with the
    balls and the pose (:func:`rvcore.dynamics.tangent.modal_blocks`, rank one a term)::

        S = D − Cᵀ·A⁻¹·C = D − Σ_b P_bᵀ·P_b − Yᵀ·S_r⁻¹·Y,   P_b = U_b⁻ᵀ·C_b,
        Y = C_r − Σ_b X_bᵀ·P_b

    ``S_r`` the ring's complement. Per ball every family's coupling is one 3-vector ``V_f``
    times the shape ``φ(θ)``, so ``P_b = Σ_f (U⁻ᵀ·V_f)·φ_fᵀ`` and the balls' part is
    ``Σ_b Σ_fg H_fg·φ_f·φ_gᵀ`` with ``H = core − (U⁻ᵀV_f)·(U⁻ᵀV_g)``: summed as the harmonics
    ``Σ_b H·(cos mθ, sin mθ)``, m ≤ 2K, and expanded by the product formulas. Then
    ``S = UᵀU`` in place in ``fx[:nm]`` (upper triangle, reciprocal diagonal, as :func:`factor`;
    its transpose in the lower triangle, for the solve's back substitution along rows).
    ``hg = h·γ`` [s].

    Notes
    -----
    Each row's couplings are first copied into the packed modal factors (``MP_*``), where
    each ball's own algebra is a loop over the balls that LLVM vectorises
    (:func:`_modal_balls`); the sums over the balls (the harmonics, ``Y``) stay a loop in the
    balls' order, each ball's terms added along the modes (:data:`LANES`).
    """
    nm = modal_offset(params, 4)
    nmax = _max_orders(params)
    nh = 2 * nmax - 1
    hl = harmonic_width(nmax)
    along = hl == LANES      # Y's sums along the lanes (LANES)
    size = MP_PHI + 2 * nmax
    hs = fx[nm + FX_FLAT:].reshape(-1)
    for i in range(2 * N_PAIRS * hl):
        hs[i] = 0.0
    # Y's sums along the lanes: a family's, per component c, at (4·c + f)·LANES
    lanes = hs[_lanes_at(nmax) + N_SOLVE_LANE_SUMS * LANES:_rows_at(nmax)]
    for i in range(lanes.size):
        lanes[i] = 0.0
    at = _rows_at(nmax)
    for i in range(nm + FX_RM):      # S and Y
        for c in range(nm):
            fx[i, c] = 0.0
    y0 = nm + FX_Y
    family_n = (family_record(params, 0)[0], family_record(params, 1)[0], family_record(params, 2)[0],
                family_record(params, 3)[0])
    family_at = (0, modal_offset(params, 1), modal_offset(params, 2), modal_offset(params, 3))
    for r in range(rows.shape[0]):
        p0, nz = int(rows[r, R_POCKET0]), int(rows[r, R_Z])
        mp = hs[at + r * size * WS:at + (r + 1) * size * WS]
        s = sf[r * N_SOLVE_FIELDS * WS:(r + 1) * N_SOLVE_FIELDS * WS]
        for j in range(nz):     # the couplings, a quantity a row of balls
            jw = jwork[p0 + j]
            for i in range(24):
                mp[(MP_V + i) * WS + j] = jw[J_FX + FX_V + i]      # V, VK
            for i in range(20):
                mp[(MP_P + i) * WS + j] = jw[J_FX + FX_P + i]      # P, PK
            for i in range(6):
                mp[(MP_CK + i) * WS + j] = jw[J_FX + FX_CK + i]
                mp[(MP_C + i) * WS + j] = jw[J_FX + FX_C + i]
            mp[MP_ON * WS + j] = jw[J_FX + FX_ON]
        _modal_balls(s, mp, nz)
        for j in range(nz):     # the sums over the balls, in their order
            jw = jwork[p0 + j]
            if jw[J_FX + FX_ON] == 0.0:
                for i in range(size - MP_PHI):
                    mp[(MP_PHI + i) * WS + j] = 0.0
                continue
            # the harmonics (cos mθ, sin mθ), m < nh, by the rotation recurrence, into the
            # ball's columns after the shape φ (its first orders), then added a pair at a
            # time along them (each sum still takes the balls in their order)
            c1, s1 = jw[J_FX + FX_ANG], jw[J_FX + FX_ANG + 1]
            harm = jw[J_FX + FX_PHI + 2 * nmax:J_FX + FX_PHI + 2 * nmax + 2 * hl]
            cm, sm = 1.0, 0.0
            for m in range(nh):
                if 2 * m < nh:
                    jw[J_FX + FX_PHI + 2 * m], jw[J_FX + FX_PHI + 2 * m + 1] = cm, sm
                harm[m], harm[hl + m] = cm, sm
                cm, sm = cm * c1 - sm * s1, sm * c1 + cm * s1
            for pair in range(N_PAIRS):     # its cos and sin sums in one loop
                h = mp[(MP_H + pair) * WS + j]
                tcs = hs[2 * pair * hl:(2 * pair + 2) * hl]
                for m in range(2 * hl):
                    tcs[m] += h * harm[m]
            if along:
                phi = jw[J_FX + FX_PHI:J_FX + FX_PHI + hl]
                for c in range(5):
                    for f in range(4):
                        value = mp[(MP_Y + 5 * f + c) * WS + j]
                        target = lanes[(4 * c + f) * hl:(4 * c + f + 1) * hl]
                        for i in range(hl):     # hl, not LANES: a loop of unknown length vectorises
                            target[i] += value * phi[i]
            else:
                phi = jw[J_FX + FX_PHI:J_FX + FX_PHI + 2 * nmax]
                for c in range(5):
                    yc = fx[y0 + c]
                    for f in range(4):
                        n, of = family_n[f], family_at[f]
                        value = mp[(MP_Y + 5 * f + c) * WS + j]
                        target = yc[of:of + 2 * n]
                        for i in range(2 * n):
                            target[i] += value * phi[i]
            for i in range(size - MP_PHI):
                mp[(MP_PHI + i) * WS + j] = jw[J_FX + FX_PHI + i]
    if along:
        for c in range(5):
            for f in range(4):
                n, of = family_n[f], family_at[f]
                _lanes_to(lanes[(4 * c + f) * LANES:(4 * c + f + 1) * LANES], fx[y0 + c, of:of + 2 * n])
    # the balls' part from the harmonic sums (upper triangle), then the modes' own diagonal
    pair = 0
    for f in range(4):
        nf, of = family_record(params, f)[0], modal_offset(params, f)
        for g in range(f, 4):
            ng, og = family_record(params, g)[0], modal_offset(params, g)
            hc_at, hs_at = 2 * pair * hl, (2 * pair + 1) * hl
            for i in range(nf):
                for i2 in range(ng):
                    d = abs(i - i2)
                    cd, cs = hs[hc_at + d], hs[hc_at + i + i2]
                    sd, ss = (hs[hs_at + d] if i >= i2 else -hs[hs_at + d]), hs[hs_at + i + i2]
                    row, col = of + 2 * i, og + 2 * i2
                    fx[row, col] += 0.5 * (cd + cs)           # cos·cos
                    fx[row, col + 1] += 0.5 * (ss - sd)       # cos·sin
                    fx[row + 1, col] += 0.5 * (ss + sd)       # sin·cos
                    fx[row + 1, col + 1] += 0.5 * (cd - cs)   # sin·sin
            pair += 1
    for f in range(4):
        n, s0, d0 = family_record(params, f)
        of = modal_offset(params, f)
        for i in range(n):
            m, k, c = params[d0 + FX_ORDER * i + 1], params[d0 + FX_ORDER * i + 2], params[d0 + FX_ORDER * i + 3]
            for s in range(2):
                fx[of + 2 * i + s, of + 2 * i + s] += m + hg * c + hg * hg * k
    # − Yᵀ·S_r⁻¹·Y = −ZᵀZ, Z = U_r⁻ᵀ·Y (in place of Y)
    for col in range(nm):
        for i in range(5):
            s = fx[y0 + i, col]
            for l in range(i):
                s -= schur[l, i] * fx[y0 + l, col]
            fx[y0 + i, col] = s * schur[i, i]
    for row in range(nm):
        for col in range(row, nm):
            fx[row, col] -= (fx[y0, row] * fx[y0, col] + fx[y0 + 1, row] * fx[y0 + 1, col]
                             + fx[y0 + 2, row] * fx[y0 + 2, col] + fx[y0 + 3, row] * fx[y0 + 3, col]
                             + fx[y0 + 4, row] * fx[y0 + 4, col])
    # Cholesky (upper triangle, reciprocal diagonal; right-looking, so that the inner loops
    # run along rows), two pivots at a time: each row below takes both pivot rows' updates
    # in one pass, in the order one at a time gave them (the same bits, half the passes)
    # with views from the loops' first index (an index LLVM knows to be ≥ 0 vectorises)
    for i in range(0, nm, 2):
        _pivot_row(fx, i, nm)
        if i + 1 == nm:
            break
        u = fx[i, i + 1]
        target, source = fx[i + 1, i + 1:nm], fx[i, i + 1:nm]
        for c in range(nm - i - 1):
            target[c] -= u * source[c]
        _pivot_row(fx, i + 1, nm)
        for k in range(i + 2, nm):
            u0, u1 = fx[i, k], fx[i + 1, k]
            target, s0, s1 = fx[k, k:nm], fx[i, k:nm], fx[i + 1, k:nm]
            for c in range(nm - k):
                target[c] = (target[c] - u0 * s0[c]) - u1 * s1[c]
    for i in range(nm):     # U's columns as the lower triangle's rows, for the back substitution
        for c in range(i + 1, nm):
            fx[c, i] = fx[i, c]


@kernel(inline=True)
def _field(s, q, nz):
    """Quantity ``q`` of a row's balls in the packed factors, as a view from index 0."""
    return s[q * WS:q * WS + nz]


@kernel(inline=True)
def _shape_values(s, nz, v, a0, n0, a1, n1, a2, n2, a3, n3, nmax, at):
    """Every ball of a row: ``s[(at + f)·WS + j] = φ(θ_j)·v[a_f : a_f + 2n_f]``, the four
    families' displacement at the ball from their amplitudes (the shape ``φ`` in ``MP_PHI``)."""
    c0, c1 = s[at * WS:at * WS + nz], s[(at + 1) * WS:(at + 1) * WS + nz]
    c2, c3 = s[(at + 2) * WS:(at + 2) * WS + nz], s[(at + 3) * WS:(at + 3) * WS + nz]
    for j in range(nz):
        c0[j], c1[j], c2[j], c3[j] = 0.0, 0.0, 0.0, 0.0
    for i in range(0, 2 * nmax, 2):     # two terms a pass (2·nmax is even), in their order
        e0 = v[a0 + i] if i < 2 * n0 else 0.0
        e1 = v[a1 + i] if i < 2 * n1 else 0.0
        e2 = v[a2 + i] if i < 2 * n2 else 0.0
        e3 = v[a3 + i] if i < 2 * n3 else 0.0
        f0 = v[a0 + i + 1] if i + 1 < 2 * n0 else 0.0
        f1 = v[a1 + i + 1] if i + 1 < 2 * n1 else 0.0
        f2 = v[a2 + i + 1] if i + 1 < 2 * n2 else 0.0
        f3 = v[a3 + i + 1] if i + 1 < 2 * n3 else 0.0
        ph = s[(MP_PHI + i) * WS:(MP_PHI + i) * WS + nz]
        pk = s[(MP_PHI + i + 1) * WS:(MP_PHI + i + 1) * WS + nz]
        for j in range(nz):
            c0[j] = (c0[j] + ph[j] * e0) + pk[j] * f0
            c1[j] = (c1[j] + ph[j] * e1) + pk[j] * f1
            c2[j] = (c2[j] + ph[j] * e2) + pk[j] * f2
            c3[j] = (c3[j] + ph[j] * e3) + pk[j] * f3


@kernel(inline=True)
def _shape_forces(s, nz, jwork, p0, rm, n0, o1, n1, o2, n2, o3, n3, lanes):
    """``rm[o_f + i] −= Σ_j φ_i(θ_j)·s[(MP_T + f)·WS + j]``: the four families' terms at the
    balls onto their modes (ball by ball, along the shape ``φ`` each ball keeps in ``jwork``;
    views from index 0, which LLVM vectorises). With ``lanes`` (:data:`LANES` accumulators
    a family, else empty) along all of them."""
    r0, r1, r2, r3 = rm[0:2 * n0], rm[o1:o1 + 2 * n1], rm[o2:o2 + 2 * n2], rm[o3:o3 + 2 * n3]
    if lanes.size:
        a0, a1, a2, a3 = lanes[0:LANES], lanes[LANES:2 * LANES], lanes[2 * LANES:3 * LANES], lanes[3 * LANES:]
        _lanes_from(a0, r0)
        _lanes_from(a1, r1)
        _lanes_from(a2, r2)
        _lanes_from(a3, r3)
        for j in range(nz):
            phi = jwork[p0 + j, J_FX + FX_PHI:J_FX + FX_PHI + LANES]
            t0, t1 = s[MP_T * WS + j], s[(MP_T + 1) * WS + j]
            t2, t3 = s[(MP_T + 2) * WS + j], s[(MP_T + 3) * WS + j]
            for i in range(LANES):
                a0[i] -= t0 * phi[i]
                a1[i] -= t1 * phi[i]
                a2[i] -= t2 * phi[i]
                a3[i] -= t3 * phi[i]
        _lanes_to(a0, r0)
        _lanes_to(a1, r1)
        _lanes_to(a2, r2)
        _lanes_to(a3, r3)
        return
    for j in range(nz):
        phi = jwork[p0 + j, J_FX + FX_PHI:]
        t0, t1 = s[MP_T * WS + j], s[(MP_T + 1) * WS + j]
        t2, t3 = s[(MP_T + 2) * WS + j], s[(MP_T + 3) * WS + j]
        for i in range(2 * n0):
            r0[i] -= t0 * phi[i]
        for i in range(2 * n1):
            r1[i] -= t1 * phi[i]
        for i in range(2 * n2):
            r2[i] -= t2 * phi[i]
        for i in range(2 * n3):
            r3[i] -= t3 * phi[i]


@kernel(inline=True)
def _pivot_row(fx, i, nm):
    """Row ``i`` of the modes' Cholesky factor: its pivot's reciprocal root and the row
    scaled by it."""
    inv = 1.0 / math.sqrt(fx[i, i])
    fx[i, i] = inv
    row = fx[i, i + 1:nm]
    for c in range(nm - i - 1):
        row[c] *= inv


@kernel(inline=True)
def _lanes_from(lanes, values):
    """The first ``values.size`` lanes from ``values``."""
    for i in range(values.size):
        lanes[i] = values[i]


@kernel(inline=True)
def _lanes_to(lanes, values):
    """``values`` from the first ``values.size`` lanes."""
    for i in range(values.size):
        values[i] = lanes[i]


@kernel
def _modal_terms(s, nz, x0, x1, x2, x3, x4):
    """Every ball of a row: the modes' ``h·γ·K`` on the ball (``MP_FB``) and on the modes
    (``MP_T``) from the shape values ``MP_SH`` and the ball's ê_x (``MP_EX``), the pose's
    ê_x ``x``; a quantity at a time, along views (vectorised)."""
    sh0, sh1, sh2, sh3 = _field(s, MP_SH, nz), _field(s, MP_SH + 1, nz), _field(s, MP_SH + 2, nz), _field(s, MP_SH + 3, nz)
    ex, ey, ez = _field(s, MP_EX, nz), _field(s, MP_EX + 1, nz), _field(s, MP_EX + 2, nz)
    for c in range(3):
        out = _field(s, MP_FB + c, nz)
        k0, k1 = _field(s, MP_VK + c, nz), _field(s, MP_VK + 3 + c, nz)
        k2, k3 = _field(s, MP_VK + 6 + c, nz), _field(s, MP_VK + 9 + c, nz)
        for j in range(nz):
            out[j] = sh0[j] * k0[j] + sh1[j] * k1[j] + sh2[j] * k2[j] + sh3[j] * k3[j]
    c0, c1, c2 = _field(s, MP_CK, nz), _field(s, MP_CK + 1, nz), _field(s, MP_CK + 2, nz)
    c3, c4, c5 = _field(s, MP_CK + 3, nz), _field(s, MP_CK + 4, nz), _field(s, MP_CK + 5, nz)
    for f in range(2):      # the inner ring's families: the pose's part too
        out = _field(s, MP_T + f, nz)
        kx, ky, kz = _field(s, MP_VK + 3 * f, nz), _field(s, MP_VK + 3 * f + 1, nz), _field(s, MP_VK + 3 * f + 2, nz)
        p0, p1, p2 = _field(s, MP_PK + 5 * f, nz), _field(s, MP_PK + 5 * f + 1, nz), _field(s, MP_PK + 5 * f + 2, nz)
        p3, p4 = _field(s, MP_PK + 5 * f + 3, nz), _field(s, MP_PK + 5 * f + 4, nz)
        ca, cb = (c0, c1) if f == 0 else (c1, c2)
        for j in range(nz):
            t = kx[j] * ex[j] + ky[j] * ey[j] + kz[j] * ez[j]
            t += p0[j] * x0 + p1[j] * x1 + p2[j] * x2 + p3[j] * x3 + p4[j] * x4
            out[j] = t + (ca[j] * sh0[j] + cb[j] * sh1[j])
    for f in range(2, 4):
        out = _field(s, MP_T + f, nz)
        kx, ky, kz = _field(s, MP_VK + 3 * f, nz), _field(s, MP_VK + 3 * f + 1, nz), _field(s, MP_VK + 3 * f + 2, nz)
        ca, cb = (c3, c4) if f == 2 else (c4, c5)
        for j in range(nz):
            t = kx[j] * ex[j] + ky[j] * ey[j] + kz[j] * ez[j]
            out[j] = t + (ca[j] * sh2[j] + cb[j] * sh3[j])


@kernel
def _coupling_terms(s, nz, y0, y1, y2, y3, y4):
    """Every ball of a row: add ``Cᵀ·y``'s factor per family, ``V_f·y_b + P_f·y_r``, to
    ``MP_T`` (the ball's y in ``MP_EX``, the ring's ``y``); a family at a time, along views
    (vectorised)."""
    bx, by, bz = _field(s, MP_EX, nz), _field(s, MP_EX + 1, nz), _field(s, MP_EX + 2, nz)
    for f in range(4):
        out = _field(s, MP_T + f, nz)
        vx, vy, vz = _field(s, MP_V + 3 * f, nz), _field(s, MP_V + 3 * f + 1, nz), _field(s, MP_V + 3 * f + 2, nz)
        if f < 2:
            p0, p1, p2 = _field(s, MP_P + 5 * f, nz), _field(s, MP_P + 5 * f + 1, nz), _field(s, MP_P + 5 * f + 2, nz)
            p3, p4 = _field(s, MP_P + 5 * f + 3, nz), _field(s, MP_P + 5 * f + 4, nz)
            for j in range(nz):
                u = vx[j] * bx[j] + vy[j] * by[j] + vz[j] * bz[j]
                u += p0[j] * y0 + p1[j] * y1 + p2[j] * y2 + p3[j] * y3 + p4[j] * y4
                out[j] += u
        else:
            for j in range(nz):
                out[j] += vx[j] * bx[j] + vy[j] * by[j] + vz[j] * bz[j]


@kernel(inline=True)
def _ring_share(s, nz):
    """``Σ_j Σ_f MP_SH_f·PK_f`` over a row's balls (the modes' ``h·γ·K`` on the pose's five
    coordinates; five sums in one pass)."""
    e0, e1, e2, e3, e4 = 0.0, 0.0, 0.0, 0.0, 0.0
    for j in range(nz):
        sh0, sh1 = s[MP_SH * WS + j], s[(MP_SH + 1) * WS + j]
        e0 += sh0 * s[MP_PK * WS + j] + sh1 * s[(MP_PK + 5) * WS + j]
        e1 += sh0 * s[(MP_PK + 1) * WS + j] + sh1 * s[(MP_PK + 6) * WS + j]
        e2 += sh0 * s[(MP_PK + 2) * WS + j] + sh1 * s[(MP_PK + 7) * WS + j]
        e3 += sh0 * s[(MP_PK + 3) * WS + j] + sh1 * s[(MP_PK + 8) * WS + j]
        e4 += sh0 * s[(MP_PK + 4) * WS + j] + sh1 * s[(MP_PK + 9) * WS + j]
    return e0, e1, e2, e3, e4


@kernel
def _ball_corrections(s, nz, z0, z1, z2, z3, z4):
    """Every ball of a row: its part of ``A⁻¹·C·e_m``, ``Σ_f σ_f·A_b⁻¹V_f − A_b⁻¹B_b·z``, into
    ``MP_CR`` (σ_f in ``MP_SG``, the ring's ``z``); a component at a time, along views."""
    g0, g1, g2, g3 = _field(s, MP_SG, nz), _field(s, MP_SG + 1, nz), _field(s, MP_SG + 2, nz), _field(s, MP_SG + 3, nz)
    for i in range(6):
        out = _field(s, MP_CR + i, nz)
        q0, q1 = _field(s, MP_Q + i, nz), _field(s, MP_Q + 6 + i, nz)
        q2, q3 = _field(s, MP_Q + 12 + i, nz), _field(s, MP_Q + 18 + i, nz)
        b0, b1, b2 = _field(s, MP_AB + 5 * i, nz), _field(s, MP_AB + 5 * i + 1, nz), _field(s, MP_AB + 5 * i + 2, nz)
        b3, b4 = _field(s, MP_AB + 5 * i + 3, nz), _field(s, MP_AB + 5 * i + 4, nz)
        for j in range(nz):
            out[j] = (g0[j] * q0[j] + g1[j] * q1[j] + g2[j] * q2[j] + g3[j] * q3[j]
                      - (b0[j] * z0 + b1[j] * z1 + b2[j] * z2 + b3[j] * z3 + b4[j] * z4))


@kernel
def solve_coupled(v, g, schur, rows, mass, sf, jwork, params, fx, hg):
    """:func:`solve` with a flexible ring's modes among the unknowns: the stage's velocity
    increments of the balls, the ring and the modes from ``ê`` in ``v`` (the stage matrix
    ``[[A, C], [Cᵀ, D]]`` of :func:`factor_modes`, its right-hand side ``M·ê_v − h·γ·K·ê_x``
    with the contacts' stiffness on the modes in ``K``), by block elimination::

        A·y = r_A,   S·e_m = r_m − Cᵀ·y,   e_A = y − A⁻¹·C·e_m

    one solve of the arrowhead system (:func:`solve`), one of ``S``, and ``A⁻¹·C·e_m`` from
    what :func:`factor_modes` left: the ring's part ``z = S_r⁻¹·Y·e_m``, each ball's
    ``Σ_f σ_f·A_b⁻¹V_f − A_b⁻¹B_b·z`` (``σ_f = φ_f·e_m``). Then, for the modes (their
    positions, as the stage does the balls'): ``e_x = ê_x + h·γ·e_v`` and ``g_x = e_v`` into
    ``g``. ``hg = h·γ`` [s]; ``fx`` the modes' block (``jwork`` is not read: the packed
    factors are in ``fx``)."""
    nm = modal_offset(params, 4)
    rm = fx[nm + FX_RM]
    nmax = _max_orders(params)
    size = MP_PHI + 2 * nmax
    flat = fx[nm + FX_FLAT:].reshape(-1)
    at = _rows_at(nmax)
    lanes_at = _lanes_at(nmax)
    lanes = flat[lanes_at:lanes_at + (N_SOLVE_LANE_SUMS * LANES if harmonic_width(nmax) == LANES else 0)]
    n0, a0, _ = family_record(params, 0)
    n1, a1, _ = family_record(params, 1)
    n2, a2, _ = family_record(params, 2)
    n3, a3, _ = family_record(params, 3)
    o1, o2, o3 = 2 * n0, 2 * (n0 + n1), 2 * (n0 + n1 + n2)
    # the modes' own M·ê_v − h·γ·K·ê_x
    for f in range(4):
        n, s0, d0 = family_record(params, f)
        of = modal_offset(params, f)
        for i in range(n):
            m, k = params[d0 + FX_ORDER * i + 1], params[d0 + FX_ORDER * i + 2]
            for q in range(2):
                rm[of + 2 * i + q] = m * v[s0 + 2 * n + 2 * i + q] - hg * k * v[s0 + 2 * i + q]
    # the contacts' h·γ·K between the modes and the balls, the pose and themselves
    e0, e1, e2, e3, e4 = 0.0, 0.0, 0.0, 0.0, 0.0
    x0, x1, x2, x3, x4 = v[0], v[1], v[2], v[3], v[4]
    for r in range(rows.shape[0]):
        b0, nz = int(rows[r, R_BALL0]), int(rows[r, R_Z])
        s = flat[at + r * size * WS:at + (r + 1) * size * WS]
        for j in range(nz):
            b = b0 + BALL_STATES * j
            s[MP_EX * WS + j], s[(MP_EX + 1) * WS + j], s[(MP_EX + 2) * WS + j] = v[b], v[b + 1], v[b + 2]
        _shape_values(s, nz, v, a0, n0, a1, n1, a2, n2, a3, n3, nmax, MP_SH)
        _modal_terms(s, nz, x0, x1, x2, x3, x4)
        d0, d1, d2, d3, d4 = _ring_share(s, nz)
        e0 += d0
        e1 += d1
        e2 += d2
        e3 += d3
        e4 += d4
        for j in range(nz):
            b = b0 + BALL_STATES * j
            v[b + 3] -= s[MP_FB * WS + j] / mass[b + 3]
            v[b + 4] -= s[(MP_FB + 1) * WS + j] / mass[b + 4]
            v[b + 5] -= s[(MP_FB + 2) * WS + j] / mass[b + 5]
    v[5] -= e0 / mass[5]
    v[6] -= e1 / mass[6]
    v[7] -= e2 / mass[7]
    v[8] -= e3 / mass[8]
    v[9] -= e4 / mass[9]
    solve(v, schur, rows, mass, sf)
    # r_m − h·γ·K_m·ê_x − Cᵀ·y
    for r in range(rows.shape[0]):
        b0, nz = int(rows[r, R_BALL0]), int(rows[r, R_Z])
        s = flat[at + r * size * WS:at + (r + 1) * size * WS]
        for j in range(nz):
            b = b0 + BALL_STATES * j
            s[MP_EX * WS + j], s[(MP_EX + 1) * WS + j], s[(MP_EX + 2) * WS + j] = v[b + 3], v[b + 4], v[b + 5]
        _coupling_terms(s, nz, v[5], v[6], v[7], v[8], v[9])
        _shape_forces(s, nz, jwork, int(rows[r, R_POCKET0]), rm, n0, o1, n1, o2, n2, o3, n3, lanes)
    # S·e_m = r: Uᵀ (along U's rows) then U, two unknowns a pass (each value takes their
    # terms in the order one at a time gave them: the same bits)
    for i in range(0, nm, 2):
        e0 = rm[i] * fx[i, i]
        rm[i] = e0
        if i + 1 == nm:
            break
        e1 = (rm[i + 1] - fx[i, i + 1] * e0) * fx[i + 1, i + 1]
        rm[i + 1] = e1
        target, s0, s1 = rm[i + 2:nm], fx[i, i + 2:nm], fx[i + 1, i + 2:nm]
        for c in range(nm - i - 2):
            target[c] = (target[c] - s0[c] * e0) - s1[c] * e1
    for i in range(nm - 1, -1, -2):
        e0 = rm[i] * fx[i, i]
        rm[i] = e0
        if i == 0:
            break
        e1 = (rm[i - 1] - fx[i, i - 1] * e0) * fx[i - 1, i - 1]
        rm[i - 1] = e1
        target, s0, s1 = rm[:i - 1], fx[i, :i - 1], fx[i - 1, :i - 1]      # U[l, i], kept in the lower triangle
        for l in range(i - 1):
            target[l] = (target[l] - s0[l] * e0) - s1[l] * e1
    # A⁻¹·C·e_m: the ring's z = S_r⁻¹·Y·e_m = U_r⁻¹·(Z·e_m) (Z = U_r⁻ᵀ·Y in fx), then the balls'
    y0 = nm + FX_Y
    t0 = t1 = t2 = t3 = t4 = 0.0
    for m in range(nm):
        e = rm[m]
        t0 += fx[y0, m] * e
        t1 += fx[y0 + 1, m] * e
        t2 += fx[y0 + 2, m] * e
        t3 += fx[y0 + 3, m] * e
        t4 += fx[y0 + 4, m] * e
    z4 = t4 * schur[4, 4]
    z3 = (t3 - schur[3, 4] * z4) * schur[3, 3]
    z2 = (t2 - schur[2, 3] * z3 - schur[2, 4] * z4) * schur[2, 2]
    z1 = (t1 - schur[1, 2] * z2 - schur[1, 3] * z3 - schur[1, 4] * z4) * schur[1, 1]
    z0 = (t0 - schur[0, 1] * z1 - schur[0, 2] * z2 - schur[0, 3] * z3 - schur[0, 4] * z4) * schur[0, 0]
    v[5] -= z0
    v[6] -= z1
    v[7] -= z2
    v[8] -= z3
    v[9] -= z4
    for r in range(rows.shape[0]):
        b0, nz = int(rows[r, R_BALL0]), int(rows[r, R_Z])
        s = flat[at + r * size * WS:at + (r + 1) * size * WS]
        _shape_values(s, nz, rm, 0, n0, o1, n1, o2, n2, o3, n3, nmax, MP_SG)
        _ball_corrections(s, nz, z0, z1, z2, z3, z4)
        for j in range(nz):
            b = b0 + BALL_STATES * j
            for i in range(6):
                v[b + 3 + i] -= s[(MP_CR + i) * WS + j]
    # the modes
    for f in range(4):
        n, s0, _ = family_record(params, f)
        of = modal_offset(params, f)
        for i in range(2 * n):
            ev = rm[of + i]
            v[s0 + 2 * n + i] = ev
            v[s0 + i] += hg * ev
            g[s0 + i] = ev
