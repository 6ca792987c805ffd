"""Contact laws, written once: Hertz force with the IMPACT damper, the friction law's
functions dispatched on the record's kind (the study's law: :mod:`rvcore.contact.coulomb_step`;
the lubricated law: :mod:`rvcore.contact.traction_ehl`, with each contact's film from
:func:`contact_film`),
and the penetrations of every contact type. SI throughout. (The cubic STEP:
:mod:`rvcore.contact.step`.)
(The inner ring's pose: :mod:`rvcore.contact.pose`.)

Every function is a kernel (``@kernel(inline=True)``, rvcore._numba) on scalars, inlined into its callers,
and allocates nothing. The right-hand side (:func:`rvcore.dynamics.rhs.rhs`), the potential
energy (:func:`rvcore.dynamics.energy.potential_energy`), the statics
(:mod:`rvcore.statics.equilibrium`), the step size (:mod:`rvcore.integrate.step_size`)
and the profiles' smooth-step interpolation (:mod:`rvcore.profile`) all call these, so a
law changed here changes everywhere.

Notes
-----
Cubic step (docs/model.md §3)::

    STEP(x, x0, h0, x1, h1) = h0                          x ≤ x0
                            = h0 + (h1−h0)·Δ²·(3 − 2Δ)    Δ = (x−x0)/(x1−x0)
                            = h1                          x ≥ x1

Normal force (Hertz with the IMPACT damper)::

    Q = K·δ^1.5 + STEP(δ, 0, 0, d_max, c_max)·dδ/dt,   then Q ← max(Q, 0)

Friction (docs/model.md §4), slip speed ``s = |v_t|``::

    μ(s) = STEP(s, −v_s, −μ_s, v_s, μ_s)      s < v_s
         = STEP(s, v_s, μ_s, v_d, μ_d)        v_s ≤ s ≤ v_d
         = μ_d                                 s > v_d
"""
from __future__ import annotations

import math

from .._numba import kernel

from ..bearing.laws import COULOMB_STEP, EHL_BAIR_WINER, EHL_ALPHA, EHL_ETA0, EHL_SIGMA, LAW_EHL0, LAW_KIND, LAW_ON
from . import coulomb_step, film, traction_ehl
from .step import step, step_slope, unit_step, unit_step_slope  # noqa: F401 (STEP, with the laws)
from ..bearing.layout import A_CR, A_CZ, A_RING, A_RMH, A_SIDE, GUIDE_BALL

#: A ball counts as loaded (``loaded_ball_count``, statics and dynamics) when it carries
#: more than this normal load on the inner race *and* on the outer race [N]: it passes
#: load from ring to ring. Why 1 N: a ball out of the load zone is still pressed on one
#: race by its weight and its centrifugal force (0.49 N and 0.25 N for the study's 23 mm
#: ball at 660 °/s), and a statically unloaded contact is the solver's round-off
#: (1e-16 N); a ball of the load zone carries hundreds to thousands of newtons. A steel
#: ball heavier than 1 N (D > 31 mm) resting on the inner race in gravity would count.
LOADED_BALL_LOAD = 1.0


@kernel(inline=True)
def damping_coefficient(delta, c_max, inv_dmax):
    """IMPACT damping ``STEP(δ, 0, 0, d_max, c_max)`` [N s m^-1].

    Parameters
    ----------
    delta : float
        Penetration δ [m].
    c_max : float
        Full damping, reached at ``δ = d_max`` [N s m^-1].
    inv_dmax : float
        ``1/d_max`` [m^-1] (a product, so no division is left in the contact loop).
    """
    return c_max * unit_step(delta * inv_dmax)


@kernel(inline=True)
def hertz_load(k, delta):
    """Hertz load ``K·δ^1.5`` [N] for ``δ ≥ 0`` [m], ``K`` [N m^-1.5].

    The root is of ``|δ|``, the same number for δ ≥ 0: an argument LLVM cannot prove
    non-negative keeps the C library's ``sqrt`` (it may set errno), a call that stops the
    loops of :mod:`rvcore.dynamics.races` from being vectorised.
    """
    return k * delta * math.sqrt(abs(delta))


@kernel(inline=True)
def hertz_energy(k, delta):
    """Elastic energy ``⅖·K·δ^2.5`` [J] of a Hertz contact, 0 for ``δ ≤ 0`` [m]."""
    if delta <= 0.0:
        return 0.0
    return 0.4 * hertz_load(k, delta) * delta


@kernel(inline=True)
def normal_force(delta, delta_rate, k, c_max, inv_dmax):
    """Hertz force with the IMPACT damper, clipped at zero [N].

    Parameters
    ----------
    delta : float
        Penetration δ > 0 [m].
    delta_rate : float
        dδ/dt [m s^-1].
    k : float
        Hertz constant K [N m^-1.5].
    c_max, inv_dmax : float
        See :func:`damping_coefficient` [N s m^-1], [m^-1].
    """
    q = hertz_load(k, delta) + damping_coefficient(delta, c_max, inv_dmax) * delta_rate
    return q if q > 0.0 else 0.0


#: The film arguments ``(p, h, λ)`` of a contact that has no film of its own (ball–pocket,
#: cage–land, and every contact of a law that needs none): unit pressure [Pa], no film [m],
#: λ = 0 [-], so the lubricated law gives its boundary friction there.
NO_FILM = (1.0, 0.0, 0.0)

#: The film constants (:func:`friction_film_constants`) of a contact without film: the
#: lubricated law's boundary friction alone (:func:`rvcore.contact.traction_ehl.ehl_film_constants`);
#: read by no other law.
NO_FILM_CONSTANTS = (1.0, 0.0, 0.0)


#: The kinds of law (their indices in :data:`rvcore.bearing.laws.FRICTION_LAWS`) the contact
#: loops of :mod:`rvcore.dynamics.races` are copied for, the kind a constant in each copy
#: (:func:`friction_coefficient`); a record of another kind runs a copy that dispatches
#: contact by contact.
FRICTION_KINDS = (COULOMB_STEP, EHL_BAIR_WINER)


@kernel(inline=True)
def friction_kind(law):
    """The record's kind, its law's index in :data:`rvcore.bearing.laws.FRICTION_LAWS` [-]."""
    return law[LAW_KIND]


@kernel(inline=True)
def friction_uses_film(kind):
    """Whether the law of kind ``kind`` (:func:`friction_kind`) needs each contact's film
    ``(p, h, λ)`` (:func:`contact_film`): the contact loops compute it only then."""
    return kind == EHL_BAIR_WINER


@kernel(inline=True)
def film_coefficients(pc3, rx, e_eff, ell, law):
    """An arc's film at unit load and unit entrainment speed, for :func:`contact_film`
    (once per arc, outside the contact loop).

    Parameters
    ----------
    pc3 : float
        ``p_max³/Q`` of the arc's Hertz contact [Pa³ N⁻¹].
    rx, e_eff, ell : float
        Effective radius in the rolling direction [m], effective modulus [Pa] and
        ellipticity k [-] of the arc's Hertz contact.
    law : ndarray
        The friction law's record (η0, α and σ of its lubricated part).

    Returns
    -------
    p1 : float
        Mean Hertz pressure at 1 N, ``⅔·pc3^(1/3)`` [Pa].
    hc1 : float
        Central film at 1 N and 1 m/s [m] (:func:`rvcore.contact.film.central_film`).
    lam1 : float
        λ at 1 N and 1 m/s [-] (:func:`rvcore.contact.film.minimum_film` over σ).
    """
    e0 = LAW_EHL0
    eta, alpha = law[e0 + EHL_ETA0], law[e0 + EHL_ALPHA]
    return ((2.0 / 3.0) * pc3 ** (1.0 / 3.0), film.central_film(1.0, 1.0, eta, alpha, e_eff, rx, ell),
            film.minimum_film(1.0, 1.0, eta, alpha, e_eff, rx, ell) / law[e0 + EHL_SIGMA])


@kernel(inline=True)
def contact_film(q, ue, p1, hc1, lam1):
    """The film arguments ``(p, h_c, λ)`` of a ball–race contact for the record's law.

    Parameters
    ----------
    q : float
        Normal load [N] (floored at 1e-6 N, so an open contact's values stay finite; they
        multiply a zero load).
    ue : float
        Entrainment speed ``|u_e|`` [m s⁻¹] (:func:`rvcore.dynamics.races.arc_contacts`;
        floored at 1e-30 m/s: no film).
    p1, hc1, lam1 : float
        The arc's :func:`film_coefficients` [Pa], [m], [-].

    Returns
    -------
    p : float
        Mean Hertz pressure ``⅔·p_max = p1·Q^(1/3)`` [Pa].
    h : float
        Hamrock–Dowson central film ``hc1·u^0.67·Q^−0.067`` [m].
    lam : float
        ``h_min/σ = lam1·u^0.68·Q^−0.073`` [-].

    Notes
    -----
    Hamrock–Dowson's films are power laws of u and Q at a given contact
    (:mod:`rvcore.contact.film`), so the arc's coefficients at 1 N and 1 m/s and two
    logarithms give them: three exponentials a contact instead of seven powers.
    """
    return contact_film_or_boundary(q, ue, p1, hc1, lam1, -math.inf)


#: Relative margin of :func:`boundary_film_exponent` [-]: far above the rounding of one
#: ``exp`` and one ``log`` (a few 1e-16), so a contact it calls boundary has λ < λ_b
#: however its λ would have rounded.
BOUNDARY_EXPONENT_MARGIN = 1e-9


@kernel(inline=True)
def boundary_film_exponent(lam1, law):
    """The exponent ``x_b`` [-] of λ's power law (:func:`contact_film`: ``λ = lam1·e^x``,
    ``x = 0.68·ln u − 0.073·ln Q``) below which a contact is certainly boundary
    lubricated for the record's law: ``ln(λ_b/lam1)`` less
    :data:`BOUNDARY_EXPONENT_MARGIN` (−∞ where the law has no such λ_b), with ``λ_b``
    from :func:`rvcore.contact.traction_ehl.boundary_lambda`. There the law's friction
    is its boundary part alone (weight exactly 1, its film part multiplied by 0), so
    :func:`contact_film_or_boundary` skips the film's exponentials."""
    lam_b = traction_ehl.boundary_lambda(_ehl(law))
    if not lam_b > 0.0:
        return -math.inf
    return math.log(lam_b / lam1) - BOUNDARY_EXPONENT_MARGIN


@kernel(inline=True)
def contact_film_or_boundary(q, ue, p1, hc1, lam1, x_b):
    """:func:`contact_film`, or :data:`NO_FILM` where the contact is boundary lubricated
    (λ's exponent below ``x_b``, :func:`boundary_film_exponent`): the same friction
    either way, bit for bit, the boundary contacts without their three exponentials.

    Parameters as :func:`contact_film`; ``x_b`` [-]. Returns ``(p, h_c, λ)`` [Pa], [m], [-].
    """
    return contact_film_of_logs(math.log(max(q, 1e-6)), math.log(max(ue, 1e-30)), p1, hc1, lam1, x_b)


@kernel(inline=True)
def contact_film_of_logs(lw, lu, p1, hc1, lam1, x_b):
    """:func:`contact_film_or_boundary` from ``lw = ln max(Q, 1e-6 N)`` and
    ``lu = ln max(u_e, 1e-30 m/s)`` (Q [N], u_e [m s⁻¹]), for a caller that has them."""
    x = film.HM_EXP_U * lu + film.HM_EXP_W * lw
    if x < x_b:
        return NO_FILM
    return (p1 * math.exp(lw * (1.0 / 3.0)), hc1 * math.exp(film.HC_EXP_U * lu + film.HC_EXP_W * lw),
            lam1 * math.exp(x))


@kernel(inline=True)
def _ehl(law):
    """The lubricated law's sub-record (a view, no copy)."""
    return law[LAW_EHL0:]


@kernel(inline=True)
def friction_coefficient(s, p, h, lam, law):
    """μ(s) of the record's law [-] at the slip speed ``s`` ≥ 0 [m s^-1]
    (``coulomb_step``: :func:`rvcore.contact.coulomb_step.coefficient`;
    ``ehl_bair_winer``: :func:`rvcore.contact.traction_ehl.ehl_traction_coefficient`).

    ``p`` [Pa], ``h`` [m] and ``lam`` [-] are the contact's mean Hertz pressure, central
    film and film parameter (:func:`contact_film`; :data:`NO_FILM` where it has none),
    read by the laws that need them. Each law function here dispatches on the record's
    kind ``law[LAW_KIND]`` (:func:`friction_kind`) with a branch a law, so only the
    record's law is computed; a kind no law has gives NaN, which the integrator's blow-up
    check reports. The contact loops of :mod:`rvcore.dynamics.races` take the kind as a
    constant instead, in a copy of the loop a law (:data:`FRICTION_KINDS`,
    :func:`friction_per_slip_of`): there the branches fold away, each copy holds its own
    law's code alone, and the study law's loops are vectorised.
    """
    kind = friction_kind(law)
    if kind == COULOMB_STEP:
        mu = coulomb_step.coefficient(s, law)
    elif kind == EHL_BAIR_WINER:
        mu = traction_ehl.ehl_traction_coefficient(s, p, h, lam, _ehl(law))
    else:
        mu = math.nan
    return mu


@kernel(inline=True)
def friction_slope(s, p, h, lam, law):
    """dμ/ds of :func:`friction_coefficient` at ``s`` ≥ 0 [s m^-1]."""
    kind = friction_kind(law)
    if kind == COULOMB_STEP:
        d = coulomb_step.slope(s, law)
    elif kind == EHL_BAIR_WINER:
        d = traction_ehl.ehl_traction_slope(s, p, h, lam, _ehl(law))
    else:
        d = math.nan
    return d


@kernel(inline=True)
def friction_slope_at_zero_slip(law):
    """dμ/ds at s = 0 [s m^-1], at its largest over the contact's film where the law has
    one (:func:`rvcore.contact.traction_ehl.ehl_slope_bound`): the law acts as a viscous
    damper ``c_f = Q·dμ/ds`` at small slip; the explicit step is sized from it
    (:func:`rvcore.integrate.rk4.rk4_time_step`)."""
    kind = friction_kind(law)
    if kind == COULOMB_STEP:
        d = coulomb_step.slope_at_zero_slip(law)
    elif kind == EHL_BAIR_WINER:
        d = traction_ehl.ehl_slope_bound(_ehl(law))
    else:
        d = math.nan
    return d


def friction_falling_slope(law) -> float:
    """The steepest fall of μ with the slip, ``|min dμ/ds|`` [s m^-1] (0 for a law that
    never falls, as the lubricated one): an explicit stage's rate where the law falls
    (:mod:`rvcore.integrate.step_size`)."""
    if law[LAW_KIND] == COULOMB_STEP:
        return coulomb_step.falling_slope(law)
    if law[LAW_KIND] == EHL_BAIR_WINER:
        return 0.0
    raise ValueError(f"no friction law of kind {law[LAW_KIND]!r}")


@kernel(inline=True)
def friction_per_slip(s2, p, h, lam, law):
    """``μ(s)/s`` [s m^-1] from the squared slip speed ``s2 = s²`` [m² s^-2], without
    dividing by a small slip (:func:`rvcore.contact.coulomb_step.per_slip`,
    :func:`rvcore.contact.traction_ehl.ehl_traction_per_slip`; film arguments as
    :func:`friction_coefficient`)."""
    kind = friction_kind(law)
    f0, f1, f2 = friction_film_constants_of(kind, p, h, lam, law)
    return friction_per_slip_of(kind, s2, f0, f1, f2, law)


@kernel(inline=True)
def friction_film_constants(p, h, lam, law):
    """What the record's law takes of a contact's film ``(p, h, λ)`` [Pa], [m], [-]
    (:func:`contact_film`): three numbers, its **film constants**, computed once per film
    (the dynamics hold them through a step's stages, :func:`rvcore.dynamics.races.arc_film`)
    and read by the functions of this module that end in ``_of``, the contact loops' path.
    ``ehl_bair_winer``: :func:`rvcore.contact.traction_ehl.ehl_film_constants`; a law that
    needs no film returns its arguments (and reads nothing of them)."""
    return friction_film_constants_of(friction_kind(law), p, h, lam, law)


@kernel(inline=True)
def friction_film_constants_of(kind, p, h, lam, law):
    """:func:`friction_film_constants` of the law of kind ``kind`` (:func:`friction_kind`)."""
    if kind == EHL_BAIR_WINER:
        f0, f1, f2 = traction_ehl.ehl_film_constants(p, h, lam, _ehl(law))
    else:
        f0, f1, f2 = p, h, lam
    return f0, f1, f2


@kernel(inline=True)
def friction_per_slip_of(kind, s2, f0, f1, f2, law):
    """:func:`friction_per_slip` of the law of kind ``kind`` (:func:`friction_kind`; a
    constant of :data:`FRICTION_KINDS` in a loop copied for it) [s m^-1], from the
    contact's film constants ``f0, f1, f2`` (:func:`friction_film_constants`)."""
    if kind == COULOMB_STEP:
        g = coulomb_step.per_slip(s2, law)
    elif kind == EHL_BAIR_WINER:
        g = traction_ehl.ehl_per_slip_of(s2, f0, f1, f2, _ehl(law))
    else:
        g = math.nan
    return g


@kernel(inline=True)
def friction_tangent_curvature(s2, p, h, lam, law):
    """``(max(μ', 0) − μ/s)/s²`` [s^3 m^-3] at ``s2 = s²``: the coefficient of
    ``v_t·v_tᵀ`` in the friction force's tangent (:func:`rvcore.dynamics.tangent.friction_tangent`;
    :func:`rvcore.contact.coulomb_step.tangent_curvature`,
    :func:`rvcore.contact.traction_ehl.ehl_tangent_curvature`)."""
    kind = friction_kind(law)
    if kind == COULOMB_STEP:
        c = coulomb_step.tangent_curvature(s2, law)
    elif kind == EHL_BAIR_WINER:
        c = traction_ehl.ehl_tangent_curvature(s2, p, h, lam, _ehl(law))
    else:
        c = math.nan
    return c


@kernel(inline=True)
def friction_tangent_terms(s2, p, h, lam, law):
    """``(μ/s, (max(μ', 0) − μ/s)/s²)`` [s m^-1], [s^3 m^-3] at ``s2 = s²``:
    :func:`friction_per_slip` and :func:`friction_tangent_curvature` together
    (:func:`friction_tangent_terms_of` of the film's constants)."""
    kind = friction_kind(law)
    f0, f1, f2 = friction_film_constants_of(kind, p, h, lam, law)
    return friction_tangent_terms_of(s2, f0, f1, f2, law)


@kernel(inline=True)
def friction_tangent_terms_of(s2, f0, f1, f2, law):
    """:func:`friction_tangent_terms` from the contact's film constants
    (:func:`friction_film_constants`), the lubricated law's sharing its exponential
    (:func:`rvcore.contact.traction_ehl.ehl_tangent_terms_of`)."""
    kind = friction_kind(law)
    if kind == COULOMB_STEP:
        g, c = coulomb_step.per_slip(s2, law), coulomb_step.tangent_curvature(s2, law)
    elif kind == EHL_BAIR_WINER:
        g, c = traction_ehl.ehl_tangent_terms_of(s2, f0, f1, f2, _ehl(law))
    else:
        g, c = math.nan, math.nan
    return g, c


@kernel(inline=True)
def friction_force(ux, uy, uz, nx, ny, nz, q, f0, f1, f2, law, kind):
    """Friction on the ball at a contact of unit normal ``n`` [N].

    ``u`` is the slip velocity of the ball's material point against the other body's
    [m s^-1]; its tangential part ``v_t = u − (u·n)·n`` gives ``−μ(|v_t|)·q·v_t/|v_t|``
    (zero at zero slip). ``q`` is the normal load [N]; ``f0, f1, f2`` the contact's film
    constants (:func:`friction_film_constants`; :data:`NO_FILM_CONSTANTS` without film);
    ``kind`` the record's kind (:func:`friction_kind`, or a constant of
    :data:`FRICTION_KINDS` in a loop copied for it).
    """
    un = ux * nx + uy * ny + uz * nz
    tx = ux - un * nx
    ty = uy - un * ny
    tz = uz - un * nz
    g = -q * friction_per_slip_of(kind, tx * tx + ty * ty + tz * tz, f0, f1, f2, law)
    return g * tx, g * ty, g * tz


@kernel(inline=True)
def ball_contact_force(q, gx, gy, gz, ux, uy, uz, nx, ny, nz, ax, ay, az, f0, f1, f2, law, kind):
    """Force [N] and moment about the ball centre [N m] of one contact on a ball.

    Normal load ``q`` along ``−g`` (g: the penetration's gradient, unit), friction by
    ``law`` (when it is on) from the slip ``u`` [m s^-1] tangential to the surface normal
    ``n`` (unit), acting at the arm ``a`` from the ball centre [m], with the contact's film
    constants ``f0, f1, f2`` (:func:`friction_film_constants`), the law of kind ``kind``
    (:func:`friction_force`). Returns ``(fx, fy, fz, mx, my, mz)``.
    """
    # the friction computed either way and selected (unit_step, Notes): its loads of the law
    # inside a branch would keep LLVM from vectorising the loops of rvcore.dynamics.races
    on = law[LAW_ON] != 0.0
    ftx, fty, ftz = friction_force(ux, uy, uz, nx, ny, nz, q, f0, f1, f2, law, kind)
    fx, fy, fz = -q * gx, -q * gy, -q * gz
    return (fx + ftx if on else fx, fy + fty if on else fy, fz + ftz if on else fz,
            ay * ftz - az * fty if on else 0.0, az * ftx - ax * ftz if on else 0.0,
            ax * fty - ay * ftx if on else 0.0)


@kernel(inline=True)
def arc_penetration(plx, ply, plz, rho, inv_rho, cr, cz, rmh, side, half_d, mid):
    """Penetration of a ball into one groove arc, in the ring's own frame.

    Parameters
    ----------
    plx, ply, plz : float
        Ball centre in the ring frame, axial coordinate relative to the row plane [m].
    rho, inv_rho : float
        ``√(plx² + ply²)`` [m] and its inverse [m^-1] (computed once per ring).
    cr, cz : float
        Arc centre: distance from the axis and axial offset [m].
    rmh : float
        ``(f − ½)·D`` [m].
    side : float
        0, or ±1 for an arc that exists only on that side of the groove mid-plane [-].
    half_d : float
        Ball radius [m].
    mid : float
        Axial position of the groove's mid-plane [m]: 0, or the groove's axial shift (an
        imperfection's and a flexible ring's, which ``cz`` includes; the arcs move with it).

    Returns
    -------
    delta : float
        Penetration [m] (≤ 0: no contact; −1 when the arc does not exist there).
    nx, ny, nz : float
        Unit normal C→P in the ring frame [-].
    """
    dr = rho - cr
    dz = plz - cz
    dist = math.sqrt(dr * dr + dz * dz)
    delta = dist - rmh
    inv = 1.0 / dist
    nr = dr * inv
    nz = dz * inv
    nx = nr * plx * inv_rho
    ny = nr * ply * inv_rho
    if side != 0.0 and side * (plz - mid + half_d * nz) < 0.0:
        delta = -1.0
    return delta, nx, ny, nz


@kernel(inline=True)
def pocket_penetration(dxp, dyp, dzp, cth, sth, pocket_r, h, cage_ri, cage_ro):
    """Ball–pocket contact: a cylindrical pocket with its axis radial through the cage centre.

    Parameters
    ----------
    dxp, dyp, dzp : float
        Ball centre relative to the cage centre, axial from the row plane [m].
    cth, sth : float
        cos and sin of the pocket's azimuth (cage angle + pocket offset) [-].
    pocket_r : float
        Pocket radius [m].
    h : float
        Ball radius [m].
    cage_ri, cage_ro : float
        Inner and outer radius of the cage ring [m].

    Returns
    -------
    delta : float
        Penetration [m]; −1 where there is no contact (and where the ball's section at
        the cage ring has shrunk to nothing: the ball is past the ring's edge).
    ax, ay, az : float
        Arm from the ball centre to the contact point [m]; the force is −Q·∇δ, along the
        arm (a sphere's normal passes through its centre).
    a_sec : float
        Radius of the ball's section where it meets the pocket wall, |arm| [m].
    """
    rad = dxp * cth + dyp * sth            # ball station along the pocket axis
    tan = -dxp * sth + dyp * cth           # offset across it, circumferential
    dperp2 = tan * tan + dzp * dzp
    # the ball's section is never wider than h: no contact unless dperp + h > pocket_r
    near = dperp2 > (pocket_r - h) * (pocket_r - h)
    dperp = math.sqrt(dperp2)
    # the cage ring spans [cage_ri, cage_ro]: the ball meets the pocket wall at the
    # station nearest its centre, where its section radius is a_sec
    station = min(max(rad, cage_ri), cage_ro) - rad
    a_sec = math.sqrt(max(h * h - station * station, 0.0))
    delta = dperp + a_sec - pocket_r
    touch = near & (delta > 0.0) & (dperp > 0.0) & (a_sec > 1e-3 * h)
    inv = 1.0 / dperp
    ax = a_sec * ((-tan * sth) * inv) + station * cth
    ay = a_sec * ((tan * cth) * inv) + station * sth
    az = a_sec * (dzp * inv)
    # one return of selects (unit_step, Notes)
    return (delta if touch else -1.0, ax if touch else 0.0, ay if touch else 0.0, az if touch else 0.0,
            a_sec if near else h)


@kernel(inline=True)
def spherical_pocket_penetration(dxp, dyp, dzp, cth, sth, pitch_r, pocket_r, h):
    """Ball–pocket contact of a ball-guided cage: a spherical pocket of radius ``pocket_r``
    centred on the cage's pitch circle (radius ``pitch_r`` [m]) at the pocket's azimuth.

    Why spherical: a ball-guided (ball-riding) cage, e.g. a pressed-steel cage, is centred
    by the balls, its pockets formed around them, so that a radial or axial shift of the
    cage closes the pocket play as a circumferential one does. A cylindrical pocket with a
    radial axis (:func:`pocket_penetration`) holds a shifted cage only through the
    circumferential contacts of the balls 90° away, and those balls are free to slide
    along their orbit where they carry no load (all of them without friction): a ball-guided
    cage built from it drifted millimetres off the axis (docs/validation.md, "A second bearing family").

    Arguments and returns as :func:`pocket_penetration` (``a_sec`` is the ball radius: the
    normal passes through both centres).
    """
    ex = dxp - pitch_r * cth
    ey = dyp - pitch_r * sth
    dist = math.sqrt(ex * ex + ey * ey + dzp * dzp)
    delta = dist + h - pocket_r
    touch = (delta > 0.0) & (dist > 0.0)
    s = h / dist
    return delta if touch else -1.0, ex * s if touch else 0.0, ey * s if touch else 0.0, dzp * s if touch else 0.0, h


@kernel(inline=True)
def cage_pocket_penetration(guide, dxp, dyp, dzp, cth, sth, pitch_r, pocket_r, h, cage_ri, cage_ro):
    """The pocket contact of a cage of guidance ``guide`` (rvcore.bearing.layout.GUIDE_*): spherical
    pockets for a ball-guided cage (:func:`spherical_pocket_penetration`), cylindrical ones
    for a land-guided cage (:func:`pocket_penetration`). Returns as those."""
    ball = guide == GUIDE_BALL
    sd, sx, sy, sz, ss = spherical_pocket_penetration(dxp, dyp, dzp, cth, sth, pitch_r, pocket_r, h)
    cd, cx, cy, cz, cs = pocket_penetration(dxp, dyp, dzp, cth, sth, pocket_r, h, cage_ri, cage_ro)
    return (sd if ball else cd, sx if ball else cx, sy if ball else cy, sz if ball else cz, ss if ball else cs)


@kernel(inline=True)
def land_penetration(xc, yc, land_clearance):
    """Cage–land contact of an outer-land-guided cage centred at ``(xc, yc)`` [m].

    Returns ``(delta, nx, ny)``: the penetration ``|r_c| − clearance`` [m] (≤ 0: none)
    and the unit outward normal [-] (0, 0 when the cage is not touching).
    """
    ecc = math.sqrt(xc * xc + yc * yc)
    delta = ecc - land_clearance
    if delta <= 0.0:
        return delta, 0.0, 0.0
    return delta, xc / ecc, yc / ecc


@kernel(inline=True)
def race_arc_penetration(arcs, a, plx, ply, plz, rho_l, inv_rho_l, px, py, pzr, rho_b, inv_rho_b,
                         half_d, dr_inner, dr_outer, d_half, slope_inner, slope_outer, dz_inner, dz_outer,
                         zslope_inner, zslope_outer):
    """Penetration of a ball into arc ``a`` of either ring (:func:`arc_penetration`).

    An inner-ring arc (``arcs[a, A_RING] == 0``) is taken in the ring frame, the ball
    centre being ``(plx, ply, plz)`` there (:func:`rvcore.contact.pose.to_ring_frame`); an outer-ring arc in
    the fixed frame, the ball centre being ``(px, py, pzr)`` with ``pzr`` from the row
    plane [m]. ``rho_*`` [m] and ``inv_rho_*`` [m^-1] are their distances from the axis.
    An imperfect bearing (:func:`rvcore.dynamics.raceway.ball_offsets`) moves the inner or outer
    groove radially by ``dr_inner``/``dr_outer`` at this ball, with the slopes
    ``slope_*`` = dΔr/dφ along the ring, and axially by ``dz_inner``/``dz_outer`` with the
    slopes ``zslope_*`` = dΔz/dφ, and has the ball larger by ``2·d_half`` [m]; all 0 for a
    perfect one.

    Returns ``(inner, delta, nx, ny, nz)``: whether the arc is on the inner ring, the
    penetration [m] and the unit normal C→P in that ring's frame [-].

    Notes
    -----
    The groove's curvature centres lie on the curve ``(c_r + Δr(φ))·ê_r(φ) + (c_z + Δz(φ))·ê_z``;
    the normal from it to the ball is perpendicular to the curve's tangent
    ``Δr'·ê_r + c_r·ê_φ + Δz'·ê_z``, so it leaves the meridian plane by
    ``n_φ = −(n_r·Δr' + n_z·Δz')/c_r`` (to first order in Δr/c_r and Δz/c_r, as the
    penetration): an eccentric raceway's normals point from its own centre, not the
    ring's, and a tilted groove's lean with its plane.
    """
    inner = arcs[a, A_RING] == 0.0
    if inner:
        cr = arcs[a, A_CR] + dr_inner
        delta, nx, ny, nz = arc_penetration(plx, ply, plz, rho_l, inv_rho_l, cr, arcs[a, A_CZ] + dz_inner,
                                            arcs[a, A_RMH] - d_half, arcs[a, A_SIDE], half_d, dz_inner)
        slope, zslope, ux, uy = slope_inner, zslope_inner, plx * inv_rho_l, ply * inv_rho_l
    else:
        cr = arcs[a, A_CR] + dr_outer
        delta, nx, ny, nz = arc_penetration(px, py, pzr, rho_b, inv_rho_b, cr, arcs[a, A_CZ] + dz_outer,
                                            arcs[a, A_RMH] - d_half, arcs[a, A_SIDE], half_d, dz_outer)
        slope, zslope, ux, uy = slope_outer, zslope_outer, px * inv_rho_b, py * inv_rho_b
    if slope != 0.0 or zslope != 0.0:
        n_phi = -(nx * ux + ny * uy) * slope / cr
        if zslope != 0.0:
            n_phi -= nz * zslope / cr
        scale = 1.0 / math.sqrt(1.0 + n_phi * n_phi)
        nx, ny, nz = (nx - n_phi * uy) * scale, (ny + n_phi * ux) * scale, nz * scale
    return inner, delta, nx, ny, nz
