"""A lubricated traction law for the ball–raceway contacts: Bair–Winer limiting-shear
liquid with Barus viscosity, blended toward boundary friction as the film parameter λ
falls. Scalar kernels (``rvcore._numba.kernel``) with their slopes, in the calling style of the study's
Coulomb/STEP law (:mod:`rvcore.contact.coulomb_step`, :mod:`rvcore.bearing.laws`). SI throughout.

Registered as ``ehl_bair_winer`` (:data:`rvcore.bearing.laws.FRICTION_LAWS`): the
dispatchers of :mod:`rvcore.contact.laws` select these functions for that kind, with each
ball–race contact's mean pressure, central film and λ from
:func:`rvcore.contact.laws.contact_film` (docs/model.md §4.1). The record's columns and
:func:`pack_ehl_traction_law` live in :mod:`rvcore.bearing.laws` (re-exported here).

Notes
-----
The film's shear (Bair & Winer 1979, their limiting-shear-stress liquid in steady,
isothermal, inelastic shear)::

    γ̇ = s/h                      shear rate of the film [s⁻¹], s the sliding speed, h the film
    η(p) = η0·exp(α·p)           Barus viscosity at the contact's pressure p [Pa s]
    τ_L(p) = τ_L0 + γ_L·p        limiting shear stress (Bair & Winer; Johnson & Tevaarwerk)
    γ̇ = −(τ_L/η)·ln(1 − τ/τ_L)   ⇔   τ = τ_L·(1 − exp(−η·γ̇/τ_L))

so the shear stress starts Newtonian, ``τ ≈ η(p)·s/h``, and saturates at ``τ_L``. The law
takes the stress at the contact's mean Hertz pressure ``p = Q/(π a b)`` and the central
film ``h_c`` (a single-point evaluation, not an integral over the ellipse), so the
traction coefficient of the full film is ``μ_f(s) = τ(s)/p``.

Boundary friction and the blend (a stated λ blend, not an asperity load-sharing model):
below λ = 1 a contact is taken as boundary lubricated, above λ = 3 as full film, and
between them the weight of the boundary friction falls along the cubic STEP of
docs/model.md §3 (the classical regimes of the film parameter: boundary λ < 1, mixed
1 ≤ λ ≤ 3, full film λ > 3)::

    w_b(λ) = 1 − STEP(λ, λ_b, 0, λ_f, 1)
    μ_b(s) = STEP(s, −v_b, −μ_b, v_b, μ_b)  for s < v_b,  μ_b above
    μ(s)   = w_b·μ_b(s) + (1 − w_b)·τ(s)/p

Slope cap (numerical, docs/model.md §4.1): the film's compliance ``h/η(p)`` is put in
series with ``1/(c·p)``, so that the slope at zero slip is ``1/(h·p/η(p) + 1/c)`` ≤ c::

    τ(s) = τ_L·(1 − exp(−k·s)),   1/(τ_L·k) = h/η(p) + 1/(c·p)

(c = ∞: Bair–Winer's ``k = η(p)/(h·τ_L)``). The dynamics packs c = 1.5·μ_s/v_s, the study
law's own slope, so the integrators' step is the dry case's; the Newtonian slope of a
real contact (1e6 s/m and more) would cut it a millionfold.

Slope with respect to the sliding speed (what the IMEX tangent needs), ``k`` as above::

    dμ/ds = w_b·μ_b'(s) + (1 − w_b)·(τ_L·k/p)·exp(−k·s)

Every term is ≥ 0 for s ≥ 0, so the dissipation ``μ·Q·s`` is never negative, and μ
never falls with s (no falling part: the whole slope may go into the tangent).

Defaults (:func:`pack_ehl_traction_law`) and their sources:

- ``η0``, ``α``: the lubricant's (:mod:`rvcore.bearing.lubricant`), no default here.
- ``τ_L0 = 0`` Pa and ``γ_L = 0.07``: a limiting shear stress proportional to pressure,
  ``τ_L/p`` of the order measured on mineral oils (Bair & Winer 1979; Höglund 1989 and
  Wikström & Höglund 1994 report γ_L from about 0.04 to 0.09 depending on oil,
  temperature and pressure). The value was chosen within that range, not taken from one
  measurement: give the oil's when it is known.
- ``μ_b = 0.1``, ``v_b = 0.1`` m s⁻¹: the study's static coefficient and its slip speed
  (docs/model.md §4), so a contact without film behaves as the study's law rises.
- ``friction.mu_dynamic`` and ``friction.v_dynamic`` (the study law's fall from μ_s to μ_d
  with the slip) are not used: in a lubricated contact the friction falls as the film
  builds (the Stribeck curve), which this law takes through λ (the blend ``w_b``), λ growing
  with the entrainment speed; a boundary part that also fell with the slip would count the
  fall twice, and would make μ fall with s (an explicit part the IMEX step would carry;
  this law has none). docs/model.md §4.1.
- ``λ_b = 1``, ``λ_f = 3``: the regime bounds above (Hamrock, Schmid & Jacobson,
  *Fundamentals of Machine Elements*, the lubrication chapter).

Range of validity: isothermal (no shear heating: the traction of fast sliding is
overestimated), inelastic (the Maxwell elasticity of Johnson & Tevaarwerk 1977 is left
out, so at small slip the slope is the Barus–Newtonian ``η(p)/(h·p)``, far steeper than a
real contact's elastic slope at Hertz pressures), smooth-film shear at one mean pressure,
steady sliding. With α·p ≳ 20 the Barus viscosity is unrealistically large and the law is
at τ_L for any slip of practical size; the exponent is capped at :data:`BARUS_EXPONENT_MAX`
only to keep the number finite (a numerical guard, not physics).

References
----------
S. Bair, W. O. Winer, "A rheological model for elastohydrodynamic contacts based on
primary laboratory data", *J. Lubr. Technol.* 101(3) 258–265, 1979; and "Shear strength
measurements of lubricants at high pressure", ibid. 251–257.
K. L. Johnson, J. L. Tevaarwerk, "Shear behaviour of elastohydrodynamic oil films",
*Proc. R. Soc. Lond. A* 356, 215–236, 1977.
V. Wikström, E. Höglund, "Investigation of parameters affecting the limiting shear
stress–pressure coefficient", *J. Tribol.* 116(3) 612–620, 1994.
C. Barus, "Isothermals, isopiestics and isometrics relative to viscosity", *Am. J. Sci.*
45, 87–96, 1893.
"""
from __future__ import annotations

import math

from .._numba import kernel
from .step import step, step_slope

__all__ = [
    "EHL_ETA0", "EHL_ALPHA", "EHL_TAU_L0", "EHL_GAMMA_L", "EHL_MU_B", "EHL_V_B",
    "EHL_LAMBDA_B", "EHL_LAMBDA_F", "EHL_LAW_SIZE", "BARUS_EXPONENT_MAX", "CURVATURE_X_FLOOR",
    "pack_ehl_traction_law", "boundary_lambda", "boundary_weight", "film_shear_stress",
    "ehl_traction_coefficient", "ehl_traction_slope", "ehl_traction_per_slip",
    "ehl_tangent_curvature", "ehl_tangent_terms", "ehl_slope_at_zero_slip", "ehl_slope_bound",
    "ehl_film_constants", "ehl_coefficient_of", "ehl_slope_of", "ehl_per_slip_of", "ehl_tangent_terms_of",
]

# The record's columns and its packing live in rvcore.bearing.laws (the record is packed by
# rvcore.bearing.layout, a layer below this one); re-exported here.
from ..bearing.laws import (EHL_ALPHA, EHL_ETA0, EHL_GAMMA_L, EHL_LAMBDA_B, EHL_LAMBDA_F,  # noqa: F401
                            EHL_LAW_SIZE, EHL_MU_B, EHL_SIGMA, EHL_SLOPE_CAP, EHL_TAU_L0, EHL_V_B,
                            GAMMA_L_DEFAULT, LAMBDA_B_DEFAULT, LAMBDA_F_DEFAULT, MU_B_DEFAULT,
                            TAU_L0_DEFAULT, V_B_DEFAULT, pack_ehl_traction_law)

#: Cap of the Barus exponent α·p [-]: exp(200) ≈ 7e86, so η(p)/(h·τ_L) stays finite even for a
#: nanometre film (a numerical guard, not physics: α·p of a real contact is below ~60).
BARUS_EXPONENT_MAX = 200.0

#: Smallest ``x = k·s`` the tangent's curvature is evaluated at [-] (a numerical floor).
CURVATURE_X_FLOOR = 1e-20


@kernel(inline=True)
def boundary_lambda(law):
    """``λ_b`` [-]: at and below it the law's friction is its boundary part alone
    (:func:`boundary_weight` exactly 1), whatever the film's pressure and thickness."""
    return law[EHL_LAMBDA_B]


@kernel(inline=True)
def boundary_weight(lam, law):
    """Weight of boundary friction ``w_b = 1 − STEP(λ, λ_b, 0, λ_f, 1)`` [-] at λ [-]."""
    return 1.0 - step(lam, law[EHL_LAMBDA_B], 0.0, law[EHL_LAMBDA_F], 1.0)


@kernel(inline=True)
def _film_constants(p, h, law):
    """``(τ_L, k)``: the limiting shear stress [Pa] and ``k = 1/(τ_L·(h/η(p) + 1/(c·p)))`` [s m⁻¹]
    (``η(p)/(h·τ_L)`` without a cap, c = ∞)."""
    tau_l = law[EHL_TAU_L0] + law[EHL_GAMMA_L] * p
    eta = law[EHL_ETA0] * math.exp(min(law[EHL_ALPHA] * p, BARUS_EXPONENT_MAX))
    # the film's compliance h/η in series with the cap's 1/(c·p) (module Notes, "Slope cap")
    return tau_l, 1.0 / (tau_l * (h / eta + 1.0 / (law[EHL_SLOPE_CAP] * p)))


@kernel(inline=True)
def film_shear_stress(s, p, h, law):
    """Shear stress of the film ``τ = τ_L·(1 − exp(−η(p)·s/(h·τ_L)))`` [Pa].

    Parameters
    ----------
    s : float
        Sliding speed ≥ 0 [m s⁻¹].
    p : float
        Contact pressure (the mean Hertz pressure) > 0 [Pa].
    h : float
        Film thickness (central) > 0 [m].
    law : ndarray
        :func:`pack_ehl_traction_law`.
    """
    tau_l, k = _film_constants(p, h, law)
    return -tau_l * math.expm1(-k * s)


@kernel(inline=True)
def _boundary(s, law):
    mu_b, v_b = law[EHL_MU_B], law[EHL_V_B]
    rising = step(s, -v_b, -mu_b, v_b, mu_b)
    return rising if s < v_b else mu_b


@kernel(inline=True)
def _boundary_slope(s, law):
    mu_b, v_b = law[EHL_MU_B], law[EHL_V_B]
    return step_slope(s, -v_b, -mu_b, v_b, mu_b) if s < v_b else 0.0


@kernel(inline=True)
def ehl_film_constants(p, h, lam, law):
    """``(w_b, g, k)``: what the law takes of a contact's film, once per film (the dynamics
    hold it through a step's stages, :func:`rvcore.dynamics.races.arc_film`).

    Parameters
    ----------
    p : float
        Mean Hertz pressure [Pa], > 0.
    h : float
        Central film thickness [m].
    lam : float
        Film parameter λ [-].
    law : ndarray
        :func:`pack_ehl_traction_law`.

    Returns
    -------
    w_b : float
        Weight of boundary friction [-] (:func:`boundary_weight`).
    g : float
        The film's slope at zero slip ``τ_L·k/p`` [s m⁻¹] (0 where ``w_b = 1``).
    k : float
        ``1/(τ_L·(h/η(p) + 1/(c·p)))`` [s m⁻¹] (module Notes; 0 where ``w_b = 1``).

    Notes
    -----
    With these the film's part of the law is (module Notes)::

        τ/p = g·(1 − e^(−k·s))/k,    d(τ/p)/ds = g·e^(−k·s)

    Where λ ≤ λ_b (``w_b = 1`` exactly) the film's part is multiplied by 0 and not
    evaluated: ``(1, 0, 0)``, also the constants of a contact without film
    (:data:`rvcore.contact.laws.NO_FILM_CONSTANTS`).
    """
    w = boundary_weight(lam, law)
    if w == 1.0:
        return 1.0, 0.0, 0.0
    tau_l, k = _film_constants(p, h, law)
    return w, tau_l * k / p, k


@kernel(inline=True)
def ehl_coefficient_of(s, w, g, k, law):
    """μ [-] at the sliding speed ``s`` ≥ 0 [m s⁻¹] from the film's constants
    (:func:`ehl_film_constants`)."""
    if w == 1.0:
        return _boundary(s, law)
    return w * _boundary(s, law) - (1.0 - w) * g * math.expm1(-k * s) / k


@kernel(inline=True)
def ehl_slope_of(s, w, g, k, law):
    """dμ/ds [s m⁻¹] at ``s`` ≥ 0 [m s⁻¹] from the film's constants (:func:`ehl_film_constants`)."""
    if w == 1.0:
        return _boundary_slope(s, law)
    return w * _boundary_slope(s, law) + (1.0 - w) * g * math.exp(-k * s)


@kernel(inline=True)
def ehl_traction_coefficient(s, p, h, lam, law):
    """Traction coefficient μ [-] at the sliding speed ``s`` ≥ 0 [m s⁻¹].

    Parameters
    ----------
    s : float
        Sliding speed ``|v_t|`` [m s⁻¹] (the slide-to-roll ratio times the entrainment
        speed).
    p : float
        Mean Hertz pressure ``Q/(π a b)`` [Pa], > 0.
    h : float
        Central film thickness [m], > 0.
    lam : float
        Film parameter λ = h_min/σ [-].
    law : ndarray
        :func:`pack_ehl_traction_law`.
    """
    w, g, k = ehl_film_constants(p, h, lam, law)
    return ehl_coefficient_of(s, w, g, k, law)


@kernel(inline=True)
def ehl_traction_slope(s, p, h, lam, law):
    """dμ/ds of :func:`ehl_traction_coefficient` [s m⁻¹] (same parameters)."""
    w, g, k = ehl_film_constants(p, h, lam, law)
    return ehl_slope_of(s, w, g, k, law)


@kernel(inline=True)
def ehl_slope_at_zero_slip(p, h, lam, law):
    """dμ/ds at s = 0 [s m⁻¹]: ``w_b·1.5·μ_b/v_b + (1 − w_b)·η(p)/(h·p)``."""
    return ehl_traction_slope(0.0, p, h, lam, law)


@kernel(inline=True)
def _boundary_per_slip(s, s2, law):
    """The boundary part of ``μ/s`` [s m⁻¹] at ``s`` [m s⁻¹], ``s2 = s²``: the study law's cubic
    ``μ_b·(1.5 − 0.5·x²)/v_b``, ``x = s/v_b``, below v_b (docs/model.md §4), ``μ_b/s`` above."""
    inv_vb = 1.0 / law[EHL_V_B]
    x2 = s2 * inv_vb * inv_vb
    return law[EHL_MU_B] * (1.5 - 0.5 * x2) * inv_vb if x2 < 1.0 else law[EHL_MU_B] / s


@kernel(inline=True)
def _boundary_curvature(s, s2, law):
    """The boundary part of :func:`ehl_tangent_curvature` [s³ m⁻³]: ``−μ_b/v_b³`` below v_b,
    ``−μ_b/s³`` above."""
    inv_vb = 1.0 / law[EHL_V_B]
    if s2 * inv_vb * inv_vb < 1.0:
        return -law[EHL_MU_B] * inv_vb * inv_vb * inv_vb
    return -law[EHL_MU_B] / (s * s2)


@kernel(inline=True)
def _film_per_slip(x, em1):
    """``(1 − e^(−x))/x`` [-] (1 at x = 0, a series below x = 1e-5) from ``em1 = expm1(−x)``."""
    return 1.0 - 0.5 * x + x * x / 6.0 if x < 1e-5 else -em1 / x


@kernel(inline=True)
def _film_curvature(x, em1):
    """``φ(x)/x²`` [-], ``φ = e^(−x) − (1 − e^(−x))/x``, from ``em1 = expm1(−x)``
    (``e^(−x) = 1 + em1``); the series ``−1/(2x) + 1/3 − x/8 + x²/30`` below x = 1e-3."""
    if x < 1e-3:
        return -0.5 / x + 1.0 / 3.0 - x / 8.0 + x * x / 30.0
    return (1.0 + em1 + em1 / x) / (x * x)


@kernel(inline=True)
def ehl_per_slip_of(s2, w, g, k, law):
    """``μ(s)/s`` [s m⁻¹] from ``s2 = s²`` [m² s⁻²] and the film's constants
    (:func:`ehl_film_constants`), with nothing divided by a small slip.

    The film's part is ``g·(1 − e^(−ks))/(ks)``; the boundary part below v_b is the
    study law's cubic ``μ_b·(1.5 − 0.5·x²)/v_b``, ``x = s/v_b`` (docs/model.md §4).
    """
    s = math.sqrt(s2)
    bnd = _boundary_per_slip(s, s2, law)
    if w == 1.0:    # λ ≤ λ_b: the film's part is multiplied by 0 (its expm1 skipped)
        return bnd
    x = k * s
    return w * bnd + (1.0 - w) * (g * _film_per_slip(x, math.expm1(-x)))


@kernel(inline=True)
def ehl_traction_per_slip(s2, p, h, lam, law):
    """``μ(s)/s`` [s m⁻¹] from ``s2 = s²`` [m² s⁻²] (:func:`ehl_per_slip_of`; film
    arguments as :func:`ehl_traction_coefficient`)."""
    w, g, k = ehl_film_constants(p, h, lam, law)
    return ehl_per_slip_of(s2, w, g, k, law)


@kernel(inline=True)
def ehl_tangent_terms_of(s2, w, g, k, law):
    """``(μ/s, (μ' − μ/s)/s²)`` [s m⁻¹], [s³ m⁻³] at ``s2 = s²`` from the film's constants
    (:func:`ehl_film_constants`): what the IMEX tangent takes
    (:func:`rvcore.dynamics.tangent.friction_tangent`), with one square root and one
    ``expm1`` for both.

    The film's curvature is ``g·k²·φ(x)/x²``, ``x = k·s``, ``φ = e^(−x) − (1 − e^(−x))/x``;
    it grows as ``−1/(2x)`` when s → 0, but the tangent's term ``coefficient·v_t·v_tᵀ``
    vanishes there like ``s``: at s = 0 exactly the boundary part alone is returned
    (``−μ_b/v_b³``), the film's term being multiplied by ``v_t = 0``. Below x = 1e-3 the
    series ``φ/x² = −1/(2x) + 1/3 − x/8 + x²/30`` is used, and x is held at
    :data:`CURVATURE_X_FLOOR` at least, so the coefficient stays finite: the tangent's term
    along v_t then errs by at most ``x_floor/2`` times the zero-slip slope.
    """
    s = math.sqrt(s2)
    if w == 1.0:    # λ ≤ λ_b: the film's parts are multiplied by 0 (as ehl_per_slip_of)
        return _boundary_per_slip(s, s2, law), _boundary_curvature(s, s2, law)
    x = k * s
    xc = max(x, CURVATURE_X_FLOOR)
    # expm1 at the curvature's x serves both: where the per-slip part reads it (x ≥ 1e-5)
    # the floor (1e-20) does not act, so xc = x there
    em1 = math.expm1(-xc)
    per_slip = w * _boundary_per_slip(s, s2, law) + (1.0 - w) * (g * _film_per_slip(x, em1))
    bnd = _boundary_curvature(s, s2, law)
    if s2 == 0.0:
        return per_slip, w * bnd
    return per_slip, w * bnd + (1.0 - w) * (g * k * k * _film_curvature(xc, em1))


@kernel(inline=True)
def ehl_tangent_terms(s2, p, h, lam, law):
    """:func:`ehl_tangent_terms_of` from the film (film arguments as
    :func:`ehl_traction_coefficient`)."""
    w, g, k = ehl_film_constants(p, h, lam, law)
    return ehl_tangent_terms_of(s2, w, g, k, law)


@kernel(inline=True)
def ehl_tangent_curvature(s2, p, h, lam, law):
    """``(μ' − μ/s)/s²`` [s³ m⁻³] at ``s2 = s²``: the coefficient of ``v_t·v_tᵀ`` in the
    friction force's tangent (as :func:`rvcore.contact.laws.friction_tangent_curvature`;
    :func:`ehl_tangent_terms_of`)."""
    return ehl_tangent_terms(s2, p, h, lam, law)[1]


@kernel(inline=True)
def ehl_slope_bound(law):
    """An upper bound of dμ/ds at s = 0 over every p, h and λ [s m⁻¹]:
    ``max(1.5·μ_b/v_b, c)``, the boundary law's slope and the cap (module Notes,
    "Slope cap"), the blend of the two being a weighted mean. What the step size is made
    from (:func:`rvcore.integrate.rk4.rk4_time_step`); infinite without a cap."""
    return max(1.5 * law[EHL_MU_B] / law[EHL_V_B], law[EHL_SLOPE_CAP])
