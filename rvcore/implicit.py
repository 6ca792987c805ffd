"""The stiff linear part of the equations of motion, contact by contact. SI throughout.

What the IMEX integrator (:mod:`rvcore.imex`) treats implicitly is the velocity
dependence of the contact forces: the friction law at small slip, whose slope
``q·dμ/ds = 1.5·μ_s·q/v_s`` is a stiff viscous damper, and the contact damper. Frozen at a
state, it is a damping matrix ``D`` on the generalized velocities (every ball's 6, each
cage's 4, the inner ring's 5)::

    generalized contact force ≈ f(x, V) − D·(V − V₀),   D = Σ_contacts Gᵀ·C·G

with ``u = G·V`` the slip velocity of the contact (ball point against the other body's
point; ``G`` the linear map, the prescribed ring spin left out) and ``C = −∂F/∂u`` the
3×3 tangent of the force on the ball with respect to the slip. This module writes ``C``
once, and accumulates ``h·γ·GᵀCG`` into the blocks the integrator factors:

- per ball ``k``: ``jwork[k, 0:36]`` the 6×6 ball–ball block ``A`` (row-major), and
  ``jwork[k, 36:90]`` the 6×9 ball–(ring, own cage) block ``B``: columns 0–4 the ring's
  ``(v_x, v_y, v_z, θ̇_x, θ̇_y)``, 5–8 the cage's ``(v_x, v_y, v_z, φ̇)``;
- ``schur[0:m, 0:m]`` the (ring, cages) block, ring at 0–4, row r's cage at ``5 + 4r``;
- ``dv`` (indexed like the state vector) ``D·V``: the damping forces at the state.

Every function is ``@njit`` on scalars and preallocated arrays; none allocates.

Notes
-----
The tangent of a contact (normal ``n`` of the friction's tangent plane, ``g`` the
penetration gradient the normal force acts along, ``v_t`` the tangential slip,
``s = |v_t|``, ``φ = μ(s)/s``; rvcore.contact for the laws)::

    C = q·φ·(I − n·nᵀ) + q·(μ'⁺(s) − φ)/s² · v_t·v_tᵀ + c(δ)·g·gᵀ

The first two terms are the exact derivative of ``−F_t = q·φ(s)·v_t``: ``q·φ`` across the
slip and ``q·μ'(s)`` along it. ``μ'⁺ = max(μ', 0)``: where the law falls from μ_s to
μ_d (v_s < s < v_d) its negative slope, at most 1.5·(μ_s − μ_d)/(v_d − v_s), 11× below
the slope at zero slip for the study's law, stays explicit, so that ``D`` is positive
semi-definite and every block SPD. Below v_s, ``(μ' − φ)/s² = −μ_s/v_s³`` exactly (the
law is a cubic there), so nothing is divided by a small slip. The dependence of the
friction on the normal load through the damper (``φ·v_t·c·gᵀ``, non-symmetric and
small) is left explicit.
"""
from __future__ import annotations

from numba import njit

from .contact import FAST, friction_per_slip, step_slope

#: Columns of the per-ball Jacobian row ``jwork[k]``.
J_A, J_B, J_W = 0, 36, 90
N_JWORK = 96
#: The scratch row (``jwork[n_balls]``): G (3×11, row-major) at 0, C·G at 33.
J_G, J_CG = 0, 33
N_COLS = 11


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def friction_tangent(q, tx, ty, tz, friction_on, mu_s, v_s, mu_d, v_d, inv_vs):
    """``(α, β)`` of the friction tangent ``q·φ·P + β·v_t·v_tᵀ`` (module Notes).

    Parameters
    ----------
    q : float
        Normal load [N].
    tx, ty, tz : float
        Tangential slip ``v_t`` [m s^-1].
    friction_on : bool
    mu_s, v_s, mu_d, v_d, inv_vs : float
        The friction law (rvcore.contact.friction_coefficient) [-], [m s^-1], [s m^-1].

    Returns
    -------
    alpha : float
        ``q·μ(s)/s`` [N s m^-1].
    beta : float
        ``q·(max(μ', 0) − μ/s)/s²`` [N s^3 m^-3].
    """
    if not friction_on:
        return 0.0, 0.0
    s2 = tx * tx + ty * ty + tz * tz
    alpha = q * friction_per_slip(s2, mu_s, v_s, mu_d, v_d, inv_vs)
    if s2 * inv_vs * inv_vs < 1.0:
        return alpha, -q * mu_s * inv_vs * inv_vs * inv_vs
    s = s2 ** 0.5
    if s <= v_d:
        slope = max(step_slope(s, v_s, mu_s, v_d, mu_d), 0.0)
    else:
        slope = 0.0
    return alpha, (q * slope - alpha) / s2


@njit(cache=True, nogil=True)
def g_ball(sc, ax, ay, az):
    """Columns 0–5 of G: a ball's ``(v, ω)`` → slip at the arm ``a``: ``[I, −[a]×]``."""
    for i in range(3):
        for k in range(6):
            sc[J_G + N_COLS * i + k] = 0.0
    sc[J_G + 0] = 1.0
    sc[J_G + N_COLS + 1] = 1.0
    sc[J_G + 2 * N_COLS + 2] = 1.0
    # u = v + ω × a: ∂u/∂ω = −[a]×
    sc[J_G + 4], sc[J_G + 5] = az, -ay
    sc[J_G + N_COLS + 3], sc[J_G + N_COLS + 5] = -az, ax
    sc[J_G + 2 * N_COLS + 3], sc[J_G + 2 * N_COLS + 4] = ay, -ax


@njit(cache=True, nogil=True)
def g_ring(sc, c0, qx, qy, qz, e1x, e1z):
    """Columns ``c0 … c0+4`` of G: minus the ring point's velocity ``v + Ω × q`` by the
    ring's ``(v_x, v_y, v_z, θ̇_x, θ̇_y)``; ``∂Ω/∂θ̇_x = e1 = (e1x, 0, e1z)``,
    ``∂Ω/∂θ̇_y = ŷ`` (rvcore.contact.ring_angular_velocity)."""
    for i in range(3):
        for k in range(3):
            sc[J_G + N_COLS * i + c0 + k] = -1.0 if i == k else 0.0
    # −(e1 × q) and −(ŷ × q)
    sc[J_G + c0 + 3] = -(0.0 * qz - e1z * qy)
    sc[J_G + N_COLS + c0 + 3] = -(e1z * qx - e1x * qz)
    sc[J_G + 2 * N_COLS + c0 + 3] = -(e1x * qy - 0.0 * qx)
    sc[J_G + c0 + 4] = -qz
    sc[J_G + N_COLS + c0 + 4] = 0.0
    sc[J_G + 2 * N_COLS + c0 + 4] = qx


@njit(cache=True, nogil=True)
def g_cage(sc, c0, rx, ry):
    """Columns ``c0 … c0+3`` of G: minus the cage point's velocity ``v + φ̇·ẑ × ρ`` by the
    cage's ``(v_x, v_y, v_z, φ̇)``; ``ρ = (rx, ry, ·)`` from the cage centre [m]."""
    for i in range(3):
        for k in range(3):
            sc[J_G + N_COLS * i + c0 + k] = -1.0 if i == k else 0.0
    sc[J_G + c0 + 3] = ry
    sc[J_G + N_COLS + c0 + 3] = -rx
    sc[J_G + 2 * N_COLS + c0 + 3] = 0.0


@njit(cache=True, nogil=True, fastmath=FAST, error_model="numpy")
def accumulate(jwork, k, sc, schur, dv, y, n_ball, n_other, bcol0, z0, vb0, vo0, hg, alpha,
               w1, p1x, p1y, p1z, w2, p2x, p2y, p2z, w3, p3x, p3y, p3z):
    """Add one contact's ``h·γ·GᵀCG`` to the blocks and ``GᵀC·(G·V)`` to ``dv``.

    ``sc`` holds G: ``n_ball`` (6 or 0) ball columns, then ``n_other`` columns of the
    other body (the ring's 5 or a cage's 4; 0 for the fixed outer ring). ``C = α·I +
    Σ w_m·p_m·p_mᵀ``. ``k`` is the ball (its ``jwork`` row), ``bcol0`` the other body's
    first column in the ball's B block (0 ring, 5 cage), ``z0`` its first row in ``schur``,
    ``vb0`` and ``vo0`` the state indices of the ball's and the other body's first
    velocity.
    """
    nc = n_ball + n_other
    # u_lin = G·V, and C·u_lin
    ux, uy, uz = 0.0, 0.0, 0.0
    for c in range(nc):
        v = y[vb0 + c] if c < n_ball else y[vo0 + c - n_ball]
        ux += sc[J_G + c] * v
        uy += sc[J_G + N_COLS + c] * v
        uz += sc[J_G + 2 * N_COLS + c] * v
    d1 = w1 * (p1x * ux + p1y * uy + p1z * uz)
    d2 = w2 * (p2x * ux + p2y * uy + p2z * uz)
    d3 = w3 * (p3x * ux + p3y * uy + p3z * uz)
    fx = alpha * ux + d1 * p1x + d2 * p2x + d3 * p3x
    fy = alpha * uy + d1 * p1y + d2 * p2y + d3 * p3y
    fz = alpha * uz + d1 * p1z + d2 * p2z + d3 * p3z
    for c in range(nc):
        gx, gy, gz = sc[J_G + c], sc[J_G + N_COLS + c], sc[J_G + 2 * N_COLS + c]
        if c < n_ball:
            dv[vb0 + c] += gx * fx + gy * fy + gz * fz
        else:
            dv[vo0 + c - n_ball] += gx * fx + gy * fy + gz * fz
        # C·G[:, c]
        e1 = w1 * (p1x * gx + p1y * gy + p1z * gz)
        e2 = w2 * (p2x * gx + p2y * gy + p2z * gz)
        e3 = w3 * (p3x * gx + p3y * gy + p3z * gz)
        sc[J_CG + c] = alpha * gx + e1 * p1x + e2 * p2x + e3 * p3x
        sc[J_CG + N_COLS + c] = alpha * gy + e1 * p1y + e2 * p2y + e3 * p3y
        sc[J_CG + 2 * N_COLS + c] = alpha * gz + e1 * p1z + e2 * p2z + e3 * p3z
    for c in range(nc):
        gx, gy, gz = sc[J_G + c], sc[J_G + N_COLS + c], sc[J_G + 2 * N_COLS + c]
        for d in range(c, nc):
            h = hg * (gx * sc[J_CG + d] + gy * sc[J_CG + N_COLS + d] + gz * sc[J_CG + 2 * N_COLS + d])
            if d < n_ball:                       # ball–ball: the upper triangle of A
                jwork[k, J_A + 6 * c + d] += h
            elif c < n_ball:                     # ball–other: B
                jwork[k, J_B + 9 * c + bcol0 + d - n_ball] += h
            else:                                # other–other: the upper triangle of S
                schur[z0 + c - n_ball, z0 + d - n_ball] += h
