"""The IMEX block solve (:mod:`rvcore.integrate.arrowhead`) against a dense solve.

The stage matrix ``M + h·γ·D + (h·γ)²·K`` is block-arrowhead: each ball's 6×6 block couples
only to the inner ring's five rates. :func:`~rvcore.integrate.arrowhead.factor` factors it
through the Schur complement on the ring, each ball's Cholesky in a vectorised loop over the
balls, and :func:`~rvcore.integrate.arrowhead.solve` solves with those factors. Here the
same matrix is assembled densely, from random symmetric positive definite blocks, and
solved with numpy: the two must agree to rounding. A matrix that is not positive definite
must give NaN, as ``math.sqrt`` of a negative pivot did, so that the integrator's blow-up
check stops the run.
"""
from __future__ import annotations

import numpy as np
import pytest

from rvcore.bearing.layout import BALL_STATES, R_BALL0, R_POCKET0, R_Z, compile_bearing
from rvcore.dynamics.tangent import J_A, J_B, J_COUPLED
from rvcore.integrate.arrowhead import factor, solve
from rvcore.integrate.imex import W_M, W_SF, new_work
from tests.core.physics_cases import section_bearing


def _random_system(seed: int, z: int = 12):
    """A compiled section bearing's layout with random blocks: every ball's A (SPD), B
    (half the balls coupled to the ring, the others 0 and their flag clear) and the ring's
    D, no stiffness blocks (K = 0). Returns the kernels' arrays and the dense matrix over
    the unknowns with their state indices."""
    rng = np.random.default_rng(seed)
    model = compile_bearing(section_bearing(z), gravity=False)
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
