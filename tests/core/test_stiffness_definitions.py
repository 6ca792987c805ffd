"""The two stiffnesses a designer reads, each checked against its definition.

- *direct*: ``K_ii``, the load per unit displacement with every other coordinate held;
- *compliant*: ``1/C_ii`` with ``C = K⁻¹``, the load per unit displacement when only that
  load changes and the ring moves freely in every other coordinate.

The compliant one is checked by its definition, re-solving the statics with one load
changed and the others held constant; the direct one against a stiffness assembled here
from Hertz theory, ball by ball.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from rvcore import hertz
from rvcore.statics.equilibrium import solve_statics
from rvcore.statics.stiffness import load_frame

from .physics_cases import STUDY_D, STUDY_DM, section_bearing, series_stiffness

F_R, F_A = 30e3, 10e3


@pytest.fixture(scope="module")
def bearing():
    return section_bearing(16)


@pytest.fixture(scope="module")
def statics(bearing):
    return solve_statics(bearing, F_R, F_A, gravity=False)


def test_compliant_stiffness_is_the_inverse_of_the_statics_under_one_changed_load(bearing, statics):
    """Change one load by ±0.5 % (central difference), hold the other loads: the ring's
    displacement along that load gives ``dF/du``, within 1 % of ``1/C_ii``."""
    k_r, k_a, k_t = statics.free_stiffness_scalars()
    d_r, d_a = 0.005 * F_R, 0.005 * F_A
    up = solve_statics(bearing, F_R + d_r, F_A, gravity=False, stiffness=False)
    dn = solve_statics(bearing, F_R - d_r, F_A, gravity=False, stiffness=False)
    assert 2 * d_r / (up.radial_displacement - dn.radial_displacement) == pytest.approx(k_r, rel=0.01)
    up = solve_statics(bearing, F_R, F_A + d_a, gravity=False, stiffness=False)
    dn = solve_statics(bearing, F_R, F_A - d_a, gravity=False, stiffness=False)
    assert 2 * d_a / (up.axial_displacement - dn.axial_displacement) == pytest.approx(k_a, rel=0.01)
    # the tilting moment turns about the axis normal to the radial load (+y at ψ = 0)
    d_m = 20.0
    up = solve_statics(bearing, F_R, F_A, d_m, gravity=False, stiffness=False)
    dn = solve_statics(bearing, F_R, F_A, -d_m, gravity=False, stiffness=False)
    assert 2 * d_m / (up.displacement[4] - dn.displacement[4]) == pytest.approx(k_t, rel=0.01)
    # freeing the other coordinates can only soften (C's diagonal ≥ 1/K's)
    direct = statics.stiffness_scalars()
    assert all(free < d for free, d in zip((k_r, k_a, k_t), direct))


def test_direct_stiffness_matches_hertz_ball_by_ball(bearing, statics):
    """``K = Σ_j Gᵀ·(k_j·n·nᵀ + (Q_j/ℓ_j)·(I − n·nᵀ))·G``: each ball a spring between the
    curvature centres of its two grooves.

    In a statics without centrifugal force ball j sits on the line through the centres
    of curvature of its inner and outer grooves, at the contact angle a_j (the same at
    both races) and azimuth ψ_j: outward normal ``n = (cos a cos ψ, cos a sin ψ, sin a)``.
    Its two Hertz contacts in series make a spring of length
    ``ℓ = (f_i + f_o − 1)·D + δ`` with ``Q = K_n·δ^1.5`` (``K_n`` from both contacts'
    Hertz constants), hence the axial stiffness ``k_j = dQ/dδ = 1.5·K_n^(2/3)·Q^(1/3)``
    along ``n`` and the string stiffness ``Q/ℓ`` across it (a loaded spring turning: at
    small contact angles this is most of the axial stiffness). The inner centre ``c``
    moves with the ring by ``t + θ × c``: ``G = [I, −[c]×]`` over ``u = (x, y, z, θ_x, θ_y)``.
    Within 3 % (the balls' positions between the arcs are the statics'; the rest is exact).
    """
    row = bearing.rows[0]
    e = hertz.effective_modulus(208e9, 0.3, 208e9, 0.3)
    alpha = row.nominal_contact_angle
    f_i, f_o = row.inner_arcs[0].curvature_ratio, row.outer_arcs[0].curvature_ratio
    k_i = hertz.race_contact(STUDY_D, STUDY_DM, f_i, alpha, "inner", e).stiffness
    k_o = hertz.race_contact(STUDY_D, STUDY_DM, f_o, alpha, "outer", e).stiffness
    k_n = series_stiffness(k_i, k_o)
    inner = int(np.flatnonzero(statics.arc_rings == 0)[0])
    k = np.zeros((5, 5))
    for j in range(statics.ball_loads.shape[0]):
        q = statics.ball_loads[j, inner]
        if q <= 0.0:
            continue
        a, psi = statics.contact_angles[j, inner], statics.azimuths[j]
        rho, z = statics.ball_positions[j]
        n = np.array([math.cos(a) * math.cos(psi), math.cos(a) * math.sin(psi), math.sin(a)])
        p = np.array([rho * math.cos(psi), rho * math.sin(psi), z])
        delta = (q / k_n) ** (2.0 / 3.0)
        c = p + (f_i - 0.5) * STUDY_D * n - statics.displacement[:3]
        spring = (1.5 * k_n ** (2.0 / 3.0) * q ** (1.0 / 3.0) * np.outer(n, n)
                  + q / ((f_i + f_o - 1.0) * STUDY_D + delta) * (np.eye(3) - np.outer(n, n)))
        skew = np.array([[0.0, -c[2], c[1]], [c[2], 0.0, -c[0]], [-c[1], c[0], 0.0]])
        g = np.hstack([np.eye(3), -skew[:, :2]])
        k += g.T @ spring @ g
    t = load_frame(0.0)
    expected = t @ k @ t.T
    direct = statics.stiffness_scalars()
    for got, want in zip(direct, (expected[0, 0], expected[2, 2], expected[4, 4])):
        assert got == pytest.approx(want, rel=0.03)
