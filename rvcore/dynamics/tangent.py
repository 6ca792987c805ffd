"""The stiff linear part of the equations of motion, contact by contact. SI throughout.

What the IMEX integrator (:mod:`rvcore.integrate.imex`) treats implicitly is the velocity
dependence of the ball contacts' forces: the friction law at small slip, whose slope
``q·dμ/ds = 1.5·μ_s·q/v_s`` is a stiff viscous damper, and the contact damper; and the
Hertz stiffness of the ball–race contacts. Frozen at a state, they are a damping matrix
``D`` on the generalized velocities (every ball's 6 and the inner ring's 5) and a
stiffness ``K`` on the positions (every ball's centre and the ring's 5)::

    generalized contact force ≈ F(x₀, V₀) − D·(V − V₀) − K·(x − x₀),   D = Σ_contacts Gᵀ·C·G

The stiffness of a race contact is ``K = k_n·∇δ·∇δᵀ + q·∇²δ`` with
``k_n = dq/dδ = 1.5·K_H·δ^0.5`` (the Hertz tangent) and ``∇δ = Gᵀ·n``: the ball's spin
does not move a race contact (its arm is along n), so the same G serves the positions.
``q·∇²δ`` is the normal turning as the ball moves across the groove,
``q/((f − ½)·D)`` ≈ 1e7 N/m at 5 kN (:func:`groove_blocks`); left out, the explicit
stages carry it, and a loaded bearing's energy is not kept at the IMEX step
(tests/core/test_imex_conservation.py: 7e-3 of the oscillation's energy under a thrust, 1.3e-5
with it). The stage matrix is
``M + h·γ·D + (h·γ)²·K``: the caller adds ``h·γ·k_n`` to the normal weight of ``C``
(:func:`contact_blocks` multiplies by h·γ), and :func:`stiffness_blocks` keeps ``h·γ·K``
alone for the stage's right-hand side. The pockets' stiffness stays explicit (their
rates are far below the races'; and a pocket acts on the cage, which is explicit).

with ``u = G·V`` the slip velocity of the contact (ball point against the other body's
point, linear in V) and ``C = −∂F/∂u`` the
3×3 tangent of the force on the ball with respect to the slip. This module writes ``C``
once, and accumulates ``h·γ·GᵀCG`` into the blocks the integrator factors:

- per ball ``k``: ``jwork[k, 0:36]`` the 6×6 ball–ball block ``A`` (row-major), and
  ``jwork[k, 36:66]`` the 6×5 ball–ring block ``B`` (the ring's
  ``(v_x, v_y, v_z, θ̇_x, θ̇_y)``), and ``jwork[k, 72]`` set to 1 where B is written (a
  ball off the inner race has ``B = 0``, which the factorization and solves skip);
- ``schur[0:5, 0:5]`` the ring's block.

Which couplings are stiff decides what is in ``D``. A race contact's friction damper
(≈ 5e3 N s/m at 3.5 kN) is stiff on the ball (rate ≈ 5e5 1/s) and, summed over the
loaded balls, on the ring (25 × 5e3 N s/m on 2.4 kg: ≈ 5e4 1/s, c·h ≈ 1 at 2e-5 s): the
ball–race contacts enter with both bodies. A pocket's is not stiff on the cage: its
friction damper 1.5·Q_p (Q_p ≲ 100 N) and its damper (150 N s/m) summed over 51 pockets on
the 0.47 kg cage give ≲ 3e4 1/s, c·h ≲ 0.6; but they act on a 0.05 kg ball (rate up to
≈ 2e4 1/s and more at start-up), so a pocket contact enters on the ball's side only (the
cage's velocity taken as given over the stage, a W-method approximation of the
Jacobian). The cage–land contact (≲ 50 N on the cage) stays explicit.

A flexible ring's modes (:mod:`rvcore.dynamics.ring_modes`) join ``K`` and ``D`` through the
race contacts: the same normal and groove terms, each rank one along the penetration's
gradient, which reaches the modes as the groove's displacement at the ball
(:func:`modal_blocks`, into ``jwork``'s columns from :data:`J_FX`).

Every function is a kernel (``rvcore._numba.kernel``) on scalars and preallocated arrays; none allocates.

Notes
-----
The tangent of a contact (normal ``n`` of the friction's tangent plane, ``g`` the
penetration gradient the normal force acts along, ``v_t`` the tangential slip,
``s = |v_t|``, ``φ = μ(s)/s``; rvcore.contact.laws for the laws)::

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

from .._numba import kernel

from ..contact.laws import friction_tangent_terms
from ..bearing.laws import LAW_ON

#: Columns of the per-ball Jacobian row ``jwork[k]``: the blocks of ``M + h·γ·D + (h·γ)²·K``
#: (A, B), six columns no longer used (W: the solve packs its factors,
#: :func:`rvcore.integrate.arrowhead.factor`), the coupling flag, and the blocks of ``h·γ·K`` alone
#: (KA: the ball's 3×3 upper triangle xx, xy, xz, yy, yz, zz; KB: ball–ring 3×5 row-major).
J_A, J_B, J_W, J_COUPLED, J_KA, J_KB = 0, 36, 66, 72, 73, 79
N_JWORK = 94
#: A flexible ring's columns of ``jwork``, after :data:`N_JWORK` (only where the bearing has
#: one: :func:`modal_blocks`). Per ball, from ``J_FX``: per family ``f`` (inner radial,
#: inner axial, outer radial, outer axial; :data:`rvcore.dynamics.ring_modes.FAMILIES`) the
#: coupling of its modes' common shape ``φ(θ)`` with the ball's centre (``FX_V + 3f``, 3),
#: and for the inner ring's families with the ring's pose (``FX_P + 5f``, 5); the
#: families' own block per ring (``FX_C + 3ρ``: radial–radial, radial–axial, axial–axial;
#: ρ = 0 inner, 1 outer); each in the stage matrix's weights (``h·γ·c + (h·γ)²·k``) and,
#: at ``FX_VK``, ``FX_PK``, ``FX_CK``, in ``h·γ·K``'s; the ball's azimuth's cosine and sine
#: (``FX_ANG``), a flag set where any term is written (``FX_ON``), and from ``FX_PHI`` the
#: shape ``φ(θ) = (cos kθ, sin kθ)_k`` at the ball's azimuth that the factorization
#: (:func:`rvcore.integrate.arrowhead.factor_modes`) writes, as many values as the largest
#: family has modes, then the harmonics it sums (cos mθ, then sin mθ, m < 2K − 1; the
#: columns' count is ``N_FX`` plus those, ``rvcore.integrate.imex.new_work``).
J_FX = N_JWORK
FX_V, FX_VK, FX_P, FX_PK, FX_C, FX_CK, FX_ANG, FX_ON, FX_PHI = 0, 12, 24, 34, 44, 50, 56, 58, 59
N_FX = FX_PHI
#: Rows of ``schur``: 0–4 the ring's block of ``M + h·γ·D + (h·γ)²·K`` (factored in
#: place), 5 the solve's scratch, 6–10 the ring's block of ``h·γ·K`` (upper triangle).
S_K = 6
N_SCHUR = 11


@kernel(inline=True)
def friction_tangent(q, tx, ty, tz, p, h, lam, law):
    """``(α, β)`` of the friction tangent ``q·φ·P + β·v_t·v_tᵀ`` (module Notes).

    Parameters
    ----------
    q : float
        Normal load [N].
    tx, ty, tz : float
        Tangential slip ``v_t`` [m s^-1].
    p, h, lam : float
        The contact's film: mean Hertz pressure [Pa], central film [m], λ [-]
        (:func:`rvcore.contact.laws.friction_coefficient`).
    law : ndarray
        The friction law's record (:func:`rvcore.bearing.laws.pack_friction_law`).

    Returns
    -------
    alpha : float
        ``q·μ(s)/s`` [N s m^-1].
    beta : float
        ``q·(max(μ', 0) − μ/s)/s²`` [N s^3 m^-3].
    """
    if law[LAW_ON] == 0.0:
        return 0.0, 0.0
    s2 = tx * tx + ty * ty + tz * tz
    g, c = friction_tangent_terms(s2, p, h, lam, law)
    return q * g, q * c


@kernel(inline=True)
def contact_blocks(jwork, k, schur, ring, hg, alpha, w1, p1x, p1y, p1z, w2, p2x, p2y, p2z,
                   w3, p3x, p3y, p3z, ax, ay, az, qx, qy, qz, e1x, e1z):
    """Add one ball contact's ``h·γ·GᵀCG``: its blocks of ``M + h·γ·D``.

    ``C = α·I + Σ w_m·p_m·p_mᵀ`` (module Notes). The ball (state offset ``b``, ``jwork``
    row ``k``) touches at the arm ``a`` from its centre, so its slip is ``v + ω × a``:
    ``G_ball = [I, S]`` with ``S = −[a]×``. With ``ring`` the other body is the inner ring,
    the contact point at ``q`` from the ring centre, ``∂Ω/∂θ̇_x = e1 = (e1x, 0, e1z)``,
    ``∂Ω/∂θ̇_y = ŷ``: ``G_ring = −[I, e1 × q, ŷ × q]``. Otherwise (outer ring, pocket)
    only the ball's side enters.
    """
    # C, symmetric
    c00 = alpha + w1 * p1x * p1x + w2 * p2x * p2x + w3 * p3x * p3x
    c11 = alpha + w1 * p1y * p1y + w2 * p2y * p2y + w3 * p3y * p3y
    c22 = alpha + w1 * p1z * p1z + w2 * p2z * p2z + w3 * p3z * p3z
    c01 = w1 * p1x * p1y + w2 * p2x * p2y + w3 * p3x * p3y
    c02 = w1 * p1x * p1z + w2 * p2x * p2z + w3 * p3x * p3z
    c12 = w1 * p1y * p1z + w2 * p2y * p2z + w3 * p3y * p3z
    # C·S, S = −[a]× = [[0, az, −ay], [−az, 0, ax], [ay, −ax, 0]]
    m00 = -c01 * az + c02 * ay
    m01 = c00 * az - c02 * ax
    m02 = -c00 * ay + c01 * ax
    m10 = -c11 * az + c12 * ay
    m11 = c01 * az - c12 * ax
    m12 = -c01 * ay + c11 * ax
    m20 = -c12 * az + c22 * ay
    m21 = c02 * az - c22 * ax
    m22 = -c02 * ay + c12 * ax
    jw = jwork[k]
    # A: [[C, C·S], [., Sᵀ·C·S]], upper triangle; (Sᵀ·X)[i] = (a × X)[i] column-wise
    jw[J_A + 0] += hg * c00
    jw[J_A + 1] += hg * c01
    jw[J_A + 2] += hg * c02
    jw[J_A + 7] += hg * c11
    jw[J_A + 8] += hg * c12
    jw[J_A + 14] += hg * c22
    jw[J_A + 3] += hg * m00
    jw[J_A + 4] += hg * m01
    jw[J_A + 5] += hg * m02
    jw[J_A + 9] += hg * m10
    jw[J_A + 10] += hg * m11
    jw[J_A + 11] += hg * m12
    jw[J_A + 15] += hg * m20
    jw[J_A + 16] += hg * m21
    jw[J_A + 17] += hg * m22
    # Sᵀ·(C·S): row i of Sᵀ is column i of S
    jw[J_A + 21] += hg * (-az * m10 + ay * m20)
    jw[J_A + 22] += hg * (-az * m11 + ay * m21)
    jw[J_A + 23] += hg * (-az * m12 + ay * m22)
    jw[J_A + 28] += hg * (az * m01 - ax * m21)
    jw[J_A + 29] += hg * (az * m02 - ax * m22)
    jw[J_A + 35] += hg * (-ay * m02 + ax * m12)
    if not ring:
        return
    jw[J_COUPLED] = 1.0      # B is written: the factorization and solves must use it
    r1x, r1y, r1z = -e1z * qy, e1z * qx - e1x * qz, e1x * qy     # e1 × q
    r2x, r2y, r2z = qz, 0.0, -qx                                  # ŷ × q
    # C·r1, C·r2
    s1x = c00 * r1x + c01 * r1y + c02 * r1z
    s1y = c01 * r1x + c11 * r1y + c12 * r1z
    s1z = c02 * r1x + c12 * r1y + c22 * r1z
    s2x = c00 * r2x + c01 * r2y + c02 * r2z
    s2y = c01 * r2x + c11 * r2y + c12 * r2z
    s2z = c02 * r2x + c12 * r2y + c22 * r2z
    # B = G_ballᵀ·C·G_ring = −[[C, C·r1, C·r2], [Sᵀ·C, Sᵀ·C·r1, Sᵀ·C·r2]] (6×5, row-major)
    jw[J_B + 0] -= hg * c00
    jw[J_B + 1] -= hg * c01
    jw[J_B + 2] -= hg * c02
    jw[J_B + 3] -= hg * s1x
    jw[J_B + 4] -= hg * s2x
    jw[J_B + 5] -= hg * c01
    jw[J_B + 6] -= hg * c11
    jw[J_B + 7] -= hg * c12
    jw[J_B + 8] -= hg * s1y
    jw[J_B + 9] -= hg * s2y
    jw[J_B + 10] -= hg * c02
    jw[J_B + 11] -= hg * c12
    jw[J_B + 12] -= hg * c22
    jw[J_B + 13] -= hg * s1z
    jw[J_B + 14] -= hg * s2z
    # rows 3–5: a × (column of C·G_ring); Sᵀ·x = a × x, so row i of Sᵀ·X is (a × X[:, l])_i
    for l in range(5):
        if l == 0:
            xx, xy, xz = c00, c01, c02
        elif l == 1:
            xx, xy, xz = c01, c11, c12
        elif l == 2:
            xx, xy, xz = c02, c12, c22
        elif l == 3:
            xx, xy, xz = s1x, s1y, s1z
        else:
            xx, xy, xz = s2x, s2y, s2z
        jw[J_B + 15 + l] -= hg * (ay * xz - az * xy)
        jw[J_B + 20 + l] -= hg * (az * xx - ax * xz)
        jw[J_B + 25 + l] -= hg * (ax * xy - ay * xx)
    # the ring's block G_ringᵀ·C·G_ring, upper triangle
    schur[0, 0] += hg * c00
    schur[0, 1] += hg * c01
    schur[0, 2] += hg * c02
    schur[1, 1] += hg * c11
    schur[1, 2] += hg * c12
    schur[2, 2] += hg * c22
    schur[0, 3] += hg * s1x
    schur[1, 3] += hg * s1y
    schur[2, 3] += hg * s1z
    schur[0, 4] += hg * s2x
    schur[1, 4] += hg * s2y
    schur[2, 4] += hg * s2z
    schur[3, 3] += hg * (r1x * s1x + r1y * s1y + r1z * s1z)
    schur[3, 4] += hg * (r1x * s2x + r1y * s2y + r1z * s2z)
    schur[4, 4] += hg * (r2x * s2x + r2y * s2y + r2z * s2z)


@kernel(inline=True)
def stiffness_blocks(jwork, k, schur, ring, hk, nx, ny, nz, qx, qy, qz, e1x, e1z):
    """Add one race contact's ``h·γ·K = h·γ·k_n·∇δ·∇δᵀ`` on the positions.

    ``hk = h·γ·k_n`` (``k_n`` the Hertz tangent dq/dδ). The penetration's gradient is
    ``n`` on the ball's centre (its rotation does not move a race contact: the arm is
    along ``n``) and, with ``ring``, ``G_ringᵀ·n = −(n, (e1 × q)·n, (ŷ × q)·n)`` on the
    ring's ``(x, y, z, θx, θy)`` (the same ``G_ring`` as the velocities':
    :func:`contact_blocks`). Written into ``jwork[k, J_KA:J_KB + 15]`` and
    ``schur[S_K:S_K + 5]``; the same ``(h·γ)²·K`` enters ``M + h·γ·D`` through the
    caller's normal weight of :func:`contact_blocks`.
    """
    jw = jwork[k]
    jw[J_KA + 0] += hk * nx * nx
    jw[J_KA + 1] += hk * nx * ny
    jw[J_KA + 2] += hk * nx * nz
    jw[J_KA + 3] += hk * ny * ny
    jw[J_KA + 4] += hk * ny * nz
    jw[J_KA + 5] += hk * nz * nz
    if not ring:
        return
    # g = G_ringᵀ·n
    g0, g1, g2, g3, g4 = ring_gradient(nx, ny, nz, qx, qy, qz, e1x, e1z)
    jw[J_KB + 0] += hk * nx * g0
    jw[J_KB + 1] += hk * nx * g1
    jw[J_KB + 2] += hk * nx * g2
    jw[J_KB + 3] += hk * nx * g3
    jw[J_KB + 4] += hk * nx * g4
    jw[J_KB + 5] += hk * ny * g0
    jw[J_KB + 6] += hk * ny * g1
    jw[J_KB + 7] += hk * ny * g2
    jw[J_KB + 8] += hk * ny * g3
    jw[J_KB + 9] += hk * ny * g4
    jw[J_KB + 10] += hk * nz * g0
    jw[J_KB + 11] += hk * nz * g1
    jw[J_KB + 12] += hk * nz * g2
    jw[J_KB + 13] += hk * nz * g3
    jw[J_KB + 14] += hk * nz * g4
    schur[S_K + 0, 0] += hk * g0 * g0
    schur[S_K + 0, 1] += hk * g0 * g1
    schur[S_K + 0, 2] += hk * g0 * g2
    schur[S_K + 0, 3] += hk * g0 * g3
    schur[S_K + 0, 4] += hk * g0 * g4
    schur[S_K + 1, 1] += hk * g1 * g1
    schur[S_K + 1, 2] += hk * g1 * g2
    schur[S_K + 1, 3] += hk * g1 * g3
    schur[S_K + 1, 4] += hk * g1 * g4
    schur[S_K + 2, 2] += hk * g2 * g2
    schur[S_K + 2, 3] += hk * g2 * g3
    schur[S_K + 2, 4] += hk * g2 * g4
    schur[S_K + 3, 3] += hk * g3 * g3
    schur[S_K + 3, 4] += hk * g3 * g4
    schur[S_K + 4, 4] += hk * g4 * g4


@kernel(inline=True)
def groove_blocks(jwork, k, schur, ring, hg, hk, tx, ty, tz, bx, by, bz, e1x, e1z):
    """Add a race contact's geometric stiffness ``q·∂²δ/∂p²``: ``h·γ·K`` and the stage
    matrix's ``(h·γ)²·K``.

    The penetration ``δ = |p − c| − (f − ½)·D`` is the distance from the groove's
    curvature centre c, whose Hessian in the meridian plane is ``t·tᵀ/|p − c|`` (``t`` the
    unit vector there across ``n``): as the ball moves across the groove the normal turns
    with it, a stiffness ``q/|p − c|``, about 1e7 N/m at 5 kN and ``|p − c|`` ≈ 0.5 mm,
    a few per cent of ``k_n``. ``hk = h·γ·q/|p − c|``; ``b`` is the ball centre from the
    ring centre (the ring's rotations move the groove about it). It acts on the ball's
    centre and the ring's pose only, along ``g = (t; −t, −(e1 × b)·t, −(ŷ × b)·t)``
    (:func:`stiffness_blocks`' gradient with ``t`` for ``n``). The azimuthal part of the
    Hessian, ``q·n_r/ρ``, 300× smaller, stays explicit.
    """
    # written out here rather than through stiffness_blocks: the ring's gradient once and
    # one loop over it for both matrices (the call cost the IMEX step 5 % more, measured)
    jw = jwork[k]
    w = hg * hk
    jw[J_KA + 0] += hk * tx * tx
    jw[J_KA + 1] += hk * tx * ty
    jw[J_KA + 2] += hk * tx * tz
    jw[J_KA + 3] += hk * ty * ty
    jw[J_KA + 4] += hk * ty * tz
    jw[J_KA + 5] += hk * tz * tz
    jw[J_A + 0] += w * tx * tx
    jw[J_A + 1] += w * tx * ty
    jw[J_A + 2] += w * tx * tz
    jw[J_A + 7] += w * ty * ty
    jw[J_A + 8] += w * ty * tz
    jw[J_A + 14] += w * tz * tz
    if not ring:
        return
    jw[J_COUPLED] = 1.0
    g = (-tx, -ty, -tz, -((-e1z * by) * tx + (e1z * bx - e1x * bz) * ty + (e1x * by) * tz),
         -(bz * tx - bx * tz))
    for l in range(5):
        gl = g[l]
        jw[J_KB + l] += hk * tx * gl
        jw[J_KB + 5 + l] += hk * ty * gl
        jw[J_KB + 10 + l] += hk * tz * gl
        jw[J_B + l] += w * tx * gl
        jw[J_B + 5 + l] += w * ty * gl
        jw[J_B + 10 + l] += w * tz * gl
        for c in range(l + 1):
            schur[S_K + c, l] += hk * g[c] * gl
            schur[c, l] += w * g[c] * gl


@kernel(inline=True)
def ring_gradient(vx, vy, vz, qx, qy, qz, e1x, e1z):
    """``G_ringᵀ·v = −(v, (e1 × q)·v, (ŷ × q)·v)``: a direction ``v`` on the ball mapped onto
    the inner ring's ``(x, y, z, θx, θy)`` through the point ``q`` from its centre
    (:func:`contact_blocks`' ``G_ring``) [-, -, -, m, m]."""
    return (-vx, -vy, -vz, -((-e1z * qy) * vx + (e1z * qx - e1x * qz) * vy + (e1x * qy) * vz),
            -(qz * vx - qx * vz))


@kernel(inline=True)
def _ring_terms(jw, at_v, at_c, ar, az, vx, vy, vz, cr, cz):
    """Add a term's radial and axial families' couplings with the ball (``ar·v``, ``az·v``,
    from ``at_v``) and its ring's own block (``ar·cr``, ``ar·cz``, ``az·cz``, from ``at_c``)."""
    jw[at_v] += ar * vx
    jw[at_v + 1] += ar * vy
    jw[at_v + 2] += ar * vz
    jw[at_v + 3] += az * vx
    jw[at_v + 4] += az * vy
    jw[at_v + 5] += az * vz
    jw[at_c] += ar * cr
    jw[at_c + 1] += ar * cz
    jw[at_c + 2] += az * cz


@kernel(inline=True)
def modal_blocks(jwork, k, inner, w, hk, vx, vy, vz, cr, cz, qx, qy, qz, e1x, e1z):
    """Add one rank-1 term of a race contact on a flexible ring, ``∇δ·∇δᵀ`` weighed by ``w``
    in the stage matrix (``h·γ·c + (h·γ)²·k``) and by ``hk`` in ``h·γ·K``, to the modes'
    columns of ``jwork[k]`` (:data:`J_FX`).

    ``∇δ`` is ``v`` on the ball's centre, ``G_ringᵀ·v`` on the inner ring's pose
    (:func:`ring_gradient`, through ``q`` from its centre; ``inner``) and on the ring's modes
    ``cr·φ(θ)`` (radial family) and ``cz·φ(θ)`` (axial), ``φ = (cos kθ, sin kθ)_k``: the
    groove displaced by ``w(θ)·ê_r + u(θ)·ẑ`` moves the contact as the ring would
    (``cr = −v·ê_r``, ``cz = −v·ẑ`` in the ring's frame). The ball's and the pose's own
    blocks are :func:`stiffness_blocks`' and :func:`groove_blocks`'.
    """
    jw = jwork[k]
    base = J_FX
    fr = 0 if inner else 2
    ring = 0 if inner else 1
    wr, wz, kr, kz = w * cr, w * cz, hk * cr, hk * cz
    _ring_terms(jw, base + FX_V + 3 * fr, base + FX_C + 3 * ring, wr, wz, vx, vy, vz, cr, cz)
    _ring_terms(jw, base + FX_VK + 3 * fr, base + FX_CK + 3 * ring, kr, kz, vx, vy, vz, cr, cz)
    jw[base + FX_ON] = 1.0
    if not inner:
        return
    g = ring_gradient(vx, vy, vz, qx, qy, qz, e1x, e1z)
    for c in range(5):
        jw[base + FX_P + c] += wr * g[c]
        jw[base + FX_P + 5 + c] += wz * g[c]
        jw[base + FX_PK + c] += kr * g[c]
        jw[base + FX_PK + 5 + c] += kz * g[c]

