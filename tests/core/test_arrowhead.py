"""The IMEX block solve (:mod:`rvcore.integrate.arrowhead`) against a dense solve.

The stage matrix ``M + h·γ·D + (h·γ)²·K`` is block-arrowhead: each ball's 6×6 block couples
only to the inner ring's five rates. :func:`~rvcore.integrate.arrowhead.factor` factors it
through the Schur complement on the ring, each ball's Cholesky in a vectorised loop over the
balls, and :func:`~rvcore.integrate.arrowhead.solve` solves with those factors. Here the
same matrix is assembled densely, from random symmetric positive definite blocks, and
solved with numpy: the two must agree to rounding. A matrix that is not positive definite
must give NaN, as ``math.sqrt`` of a negative pivot did, so that the integrator's blow-up
check stops the run.

With flexible rings the stage matrix gains the rings' modes as unknowns
(:func:`~rvcore.integrate.arrowhead.factor_modes`,
:func:`~rvcore.integrate.arrowhead.solve_coupled`): each ball's coupling to a family's modes
is a 3-vector times the family's shape ``φ(θ) = (cos kθ, sin kθ)_k`` at the ball's azimuth
(:func:`rvcore.dynamics.tangent.modal_blocks`), the inner ring's pose couples through a
5-vector the same way, and a ring's two families couple among themselves through a 2×2 core
a ball. Those blocks, random, are assembled densely here from that definition, with the
stiffness terms ``h·γ·K`` that act on the positions in the right-hand side, at orders that
take the lanes' path and the plain one (:data:`~rvcore.integrate.arrowhead.LANES`).
"""
from __future__ import annotations

import numpy as np
import pytest

from rvcore.bearing.layout import BALL_STATES, R_BALL0, R_POCKET0, R_Z, compile_bearing
from rvcore.dynamics.ring_modes import FX_ORDER, family_record, modal_offset, truncated, with_ring_modes
from rvcore.dynamics.tangent import (FX_ANG, FX_C, FX_CK, FX_ON, FX_P, FX_PK, FX_V, FX_VK, J_A, J_B, J_COUPLED,
                                     J_FX)
from rvcore.integrate.arrowhead import LANES, factor, factor_modes, solve, solve_coupled
from rvcore.integrate.imex import W_M, W_SET, W_SF, new_work
from rvcore.rings.flexible import flexible_rings
from rvcore.rings.support import Foundation
from tests.core.physics_cases import section_bearing


def _random_system(seed: int, z: int = 12, model=None):
    """A compiled section bearing's layout (or ``model``'s) with random blocks: every
    ball's A (SPD), B (half the balls coupled to the ring, the others 0 and their flag
    clear) and the ring's D, no stiffness blocks (K = 0). Returns the kernels' arrays and
    the dense matrix over the unknowns with their state indices."""
    rng = np.random.default_rng(seed)
    model = compile_bearing(section_bearing(z), gravity=False) if model is None else model
    work, jwork, schur = new_work(model, 1e-9, 1.0)
    mass = work[W_M]
    rows = model.rows
    unknowns = list(range(5, 10))
    blocks = []
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        for j in range(int(rows[r, R_Z])):
            g = rng.normal(size=(6, 6))
            a = g @ g.T + 0.5 * np.eye(6)
            coupled = j % 2 == 0
            b = 0.3 * rng.normal(size=(6, 5)) if coupled else np.zeros((6, 5))
            jwork[p0 + j, J_A:J_A + 36] = a.ravel()
            jwork[p0 + j, J_B:J_B + 30] = b.ravel()
            jwork[p0 + j, J_COUPLED] = 1.0 if coupled else 0.0
            at = b0 + BALL_STATES * j + 3
            blocks.append((list(range(at, at + 6)), a, b))
            unknowns += list(range(at, at + 6))
    g = rng.normal(size=(5, 5))
    d = g @ g.T + 5.0 * np.eye(5)
    schur[:5, :5] = np.triu(d)
    # the dense matrix: M + the blocks, over the unknowns' state indices
    where = {s: i for i, s in enumerate(unknowns)}
    dense = np.diag(mass[unknowns])
    ring = [where[s] for s in range(5, 10)]
    dense[np.ix_(ring, ring)] += d
    for states, a, b in blocks:
        ball = [where[s] for s in states]
        dense[np.ix_(ball, ball)] += a
        dense[np.ix_(ball, ring)] += b
        dense[np.ix_(ring, ball)] += b.T
    return model, work, jwork, schur, mass, np.array(unknowns), dense


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_factor_and_solve_equal_a_dense_solve(seed):
    model, work, jwork, schur, mass, unknowns, dense = _random_system(seed)
    sf = work[W_SF:].reshape(-1)
    factor(jwork, schur, model.rows, mass, sf)
    v = np.random.default_rng(100 + seed).normal(size=model.n_states)
    expected = np.linalg.solve(dense, mass[unknowns] * v[unknowns])
    untouched = np.setdiff1d(np.arange(model.n_states), unknowns)
    before = v.copy()
    solve(v, schur, model.rows, mass, sf)
    assert np.allclose(v[unknowns], expected, rtol=1e-10, atol=1e-12 * np.abs(expected).max())
    # the positions and the cage are not the solve's unknowns: left as they were
    assert np.array_equal(v[untouched], before[untouched])


def test_a_matrix_that_is_not_positive_definite_gives_nan():
    model, work, jwork, schur, mass, unknowns, dense = _random_system(3)
    rows = model.rows
    k = int(rows[0, R_POCKET0]) + 1
    b = int(rows[0, R_BALL0]) + BALL_STATES + 3
    # the ball's first pivot, A_00 + m, made negative
    jwork[k, J_A] = -2.0 * mass[b] - 1.0
    sf = work[W_SF:].reshape(-1)
    factor(jwork, schur, rows, mass, sf)
    v = np.ones(model.n_states)
    solve(v, schur, rows, mass, sf)
    assert np.isnan(v[b:b + 6]).all()


# --------------------------------------------------------------------------- flexible rings

def _shape(c: float, s: float, n: int) -> np.ndarray:
    """``φ(θ) = (cos kθ, sin kθ)``, k < n, at the azimuth of cosine ``c`` and sine ``s``."""
    theta = np.arctan2(s, c)
    k = np.arange(n)
    return np.column_stack([np.cos(k * theta), np.sin(k * theta)]).ravel()


def _random_flexible_system(seed: int, order: int, hg: float = 2e-5):
    """The section bearing with both rings flexible on a seat, its modes to ``order``, the
    arrowhead blocks of :func:`_random_system` and random modal blocks: at four balls in
    five a coupling (``V``, and ``P`` on the inner ring's pose) and each ring's 2×2 core
    (SPD) in the stage matrix's weights, and the same kinds of terms at random in ``h·γ·K``
    (``VK``, ``PK``, ``CK``). Returns the kernels' arrays, the dense stage matrix over the
    velocity unknowns (the ring's rates, the balls' velocities and spins, the modes'
    rates), the dense ``h·γ·K`` from the positions those unknowns integrate (0 on the
    spins), and the unknowns' state indices with their positions'."""
    rng = np.random.default_rng(1000 + seed)
    bearing = section_bearing(12)
    seat = Foundation(1e9, 1e9)
    rings = truncated(flexible_rings(bearing, inner=seat, outer=seat, outer_shoulder_diameter=0.362,
                                     max_order=order), order)
    model = with_ring_modes(compile_bearing(bearing, gravity=False), rings, order)
    model, work, jwork, schur, mass, rigid, dense_rigid = _random_system(seed, model=model)
    params, rows = model.params, model.rows
    families = [family_record(params, f) for f in range(4)]
    nm = modal_offset(params, 4)
    at = [modal_offset(params, f) for f in range(4)]
    velocities = [s0 + 2 * n + i for n, s0, _ in families for i in range(2 * n)]
    unknowns = np.concatenate([rigid, velocities])
    where = {s: i for i, s in enumerate(unknowns)}
    # the position each unknown integrates: the ring's pose, a ball's centre, a mode's
    # amplitude (-1: a ball's spin)
    positions = np.full(len(unknowns), -1)
    positions[[where[s] for s in range(5, 10)]] = np.arange(5)
    positions[len(rigid):] = [s0 + i for n, s0, _ in families for i in range(2 * n)]
    size, m0 = len(unknowns), len(rigid)
    dense, hgk = np.zeros((size, size)), np.zeros((size, size))
    dense[:m0, :m0] = dense_rigid
    weights = np.concatenate([mass[rigid], np.zeros(nm)])
    for f, (n, s0, d0) in enumerate(families):
        for i in range(n):
            m, k, c = params[d0 + FX_ORDER * i + 1:d0 + FX_ORDER * i + 4]
            for q in range(2):
                u = m0 + at[f] + 2 * i + q
                dense[u, u] += m + hg * c + hg * hg * k
                hgk[u, u] += hg * k
                weights[u] = m
    ring = [where[s] for s in range(5, 10)]
    for r in range(rows.shape[0]):
        b0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
        for j in range(int(rows[r, R_Z])):
            jw = jwork[p0 + j]
            centre = [where[b0 + BALL_STATES * j + 3 + c] for c in range(3)]
            positions[centre] = b0 + BALL_STATES * j + np.arange(3)
            theta = rng.uniform(0.0, 2.0 * np.pi)
            jw[J_FX + FX_ANG], jw[J_FX + FX_ANG + 1] = np.cos(theta), np.sin(theta)
            if rng.uniform() < 0.2:
                continue
            jw[J_FX + FX_ON] = 1.0
            phi = [_shape(np.cos(theta), np.sin(theta), families[f][0]) for f in range(4)]
            modes = [m0 + at[f] + np.arange(2 * families[f][0]) for f in range(4)]
            for f in range(4):
                for col, matrix, scale in ((FX_V, dense, 0.05), (FX_VK, hgk, 0.05)):
                    v = scale * rng.normal(size=3)
                    jw[J_FX + col + 3 * f:J_FX + col + 3 * f + 3] = v
                    matrix[np.ix_(centre, modes[f])] += np.outer(v, phi[f])
                    matrix[np.ix_(modes[f], centre)] += np.outer(phi[f], v)
                if f < 2:       # the inner ring's families: its pose too
                    for col, matrix in ((FX_P, dense), (FX_PK, hgk)):
                        p = 0.05 * rng.normal(size=5)
                        jw[J_FX + col + 5 * f:J_FX + col + 5 * f + 5] = p
                        matrix[np.ix_(ring, modes[f])] += np.outer(p, phi[f])
                        matrix[np.ix_(modes[f], ring)] += np.outer(phi[f], p)
            for rho in range(2):    # each ring's own core: radial–radial, radial–axial, axial–axial
                g = rng.normal(size=(2, 2))
                core = g @ g.T + 0.5 * np.eye(2)
                ck = rng.normal(size=(2, 2))
                ck = 0.1 * (ck + ck.T)
                for col, block, matrix in ((FX_C, core, dense), (FX_CK, ck, hgk)):
                    jw[J_FX + col + 3 * rho:J_FX + col + 3 * rho + 3] = block[0, 0], block[0, 1], block[1, 1]
                    for a in range(2):
                        for b in range(2):
                            fa, fb = 2 * rho + a, 2 * rho + b
                            matrix[np.ix_(modes[fa], modes[fb])] += block[a, b] * np.outer(phi[fa], phi[fb])
    assert np.linalg.eigvalsh(dense).min() > 0.0
    return model, work, jwork, schur, mass, unknowns, positions, weights, dense, hgk, hg


@pytest.mark.parametrize("order", [6, 7, 8])
def test_the_coupled_solve_with_a_flexible_ring_equals_a_dense_solve(order):
    """The stage matrix with both rings' modes to ``order`` (6 and 7 take the lanes' path,
    ``2·(order + 1) ≤ LANES``; 8 the plain one): :func:`factor`, :func:`factor_modes` and
    :func:`solve_coupled` against numpy's solve of ``S·e = W·ê_v − h·γ·K·ê_x`` (``W`` the
    balls', ring's and modes' masses), and the modes' positions ``ê_x + h·γ·e`` and rates."""
    assert (2 * (order + 1) <= LANES) == (order < 8)
    model, work, jwork, schur, mass, unknowns, positions, weights, dense, hgk, hg = _random_flexible_system(
        order, order)
    rows, params = model.rows, model.params
    sf, fx = work[W_SF:].reshape(-1), work[int(work[W_SET, 2]):]
    factor(jwork, schur, rows, mass, sf)
    factor_modes(jwork, schur, rows, params, fx, hg, sf)
    v = np.random.default_rng(200 + order).normal(size=model.n_states)
    x = np.where(positions >= 0, v[np.maximum(positions, 0)], 0.0)
    expected = np.linalg.solve(dense, weights * v[unknowns] - hgk @ x)
    before, g = v.copy(), np.zeros(model.n_states)
    solve_coupled(v, g, schur, rows, mass, sf, jwork, params, fx, hg)
    assert np.allclose(v[unknowns], expected, rtol=1e-9, atol=1e-11 * np.abs(expected).max())
    # the modes (the last unknowns): their positions moved by h·γ·e, their rates in g
    nm = modal_offset(params, 4)
    modal, moved = unknowns[-nm:], positions[-nm:]
    assert np.allclose(v[moved], before[moved] + hg * v[modal], rtol=1e-12, atol=0.0)
    assert np.array_equal(g[moved], v[modal])
    # the balls' and the ring's positions and the cages are not the solve's to change
    untouched = np.setdiff1d(np.arange(model.n_states), np.concatenate([unknowns, moved]))
    assert np.array_equal(v[untouched], before[untouched])
