"""Elastohydrodynamic film thickness of a ball–raceway contact (Hamrock–Dowson) and the
film parameter λ. Pure functions, SI in and out. The contact's geometry comes from
:mod:`rvcore.hertz` (its curvature sums and its exact ellipticity), not from a second
Hertz solution.

The dynamics evaluates :func:`central_film` and :func:`minimum_film` at every loaded
ball–race contact when the lubricated law is active (:func:`rvcore.contact.laws.contact_film`).

Notes
-----
Hamrock & Dowson (1977), fully flooded, isothermal, elliptical contact, the entrainment
(rolling) direction ``x`` along the ellipse's minor axis::

    U = η0·u / (E'·R_x)        G = α·E'        W = w / (E'·R_x²)
    H_c   = h_c/R_x   = 2.69·U^0.67·G^0.53·W^−0.067·(1 − 0.61·e^(−0.73·k))
    H_min = h_min/R_x = 3.63·U^0.68·G^0.49·W^−0.073·(1 − e^(−0.68·k))

with ``η0`` the lubricant's dynamic viscosity at the inlet's temperature and ambient
pressure [Pa s], ``u = (u1 + u2)/2`` the entrainment speed [m s⁻¹], ``α`` the
pressure–viscosity coefficient [Pa⁻¹], ``w`` the contact's normal load [N], ``E'`` the
effective modulus of :func:`rvcore.hertz.effective_modulus` [Pa], ``R_x = 1/ρ_x`` the
effective radius in the rolling direction [m] and ``k = a/b`` the ellipticity [-]
(:attr:`rvcore.hertz.HertzContact.ellipticity`; Hamrock & Dowson used their fit
``k ≈ 1.03·(R_y/R_x)^0.64``, the exact value is used here).

The film parameter ``λ = h_min/σ``, ``σ`` the composite rms roughness
(:func:`rvcore.bearing.lubricant.composite_roughness`).

Validity (Hamrock & Dowson 1977, Part III): fitted on 34 numerical solutions with the
ellipticity from 1 (ball on plate) to 8, the speed parameter over about two decades and
the load parameter over one, for steel, bronze and silicon nitride with paraffinic and
naphthenic mineral oils; Newtonian lubricant, Barus viscosity, smooth surfaces, isothermal
inlet, fully flooded. Outside ``1 ≤ k ≤ 8`` the formula is extrapolated (flagged here). A
grease-lubricated bearing runs starved: the formula is then an upper bound. Measured
films scatter about the formula: Koye & Winer (1981) found their 57 optical
measurements of the minimum film 30 % above it on average.

References
----------
B. J. Hamrock, D. Dowson, "Isothermal elastohydrodynamic lubrication of point contacts,
Part III — Fully flooded results", *J. Lubr. Technol.* 99(2) 264–276, 1977.
B. J. Hamrock, S. R. Schmid, B. O. Jacobson, *Fundamentals of Machine Elements*, the
rolling-element bearing chapter (the same two formulas).
K. A. Koye, W. O. Winer, "An experimental evaluation of the Hamrock and Dowson minimum
film thickness equation for fully flooded EHD point contacts", *J. Lubr. Technol.*
103(2) 284–294, 1981.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .._numba import kernel
from ..hertz import HertzContact, effective_radii  # noqa: F401 (re-exported)
from ..standards.inputs import finite_positive as _positive

__all__ = [
    "ELLIPTICITY_RANGE",
    "FilmThickness",
    "effective_radii",
    "hamrock_dowson",
    "hamrock_dowson_contact",
    "film_parameter",
    "entrainment_speed_pure_rolling",
    "central_film",
    "minimum_film",
    "with_film_columns",
]

#: The ellipticities Hamrock & Dowson (1977) fitted their formulas on [-].
ELLIPTICITY_RANGE = (1.0, 8.0)


@dataclass(frozen=True)
class FilmThickness:
    """Hamrock–Dowson film of one contact.

    Parameters
    ----------
    central, minimum : float
        ``h_c``, ``h_min`` [m].
    speed_parameter, materials_parameter, load_parameter : float
        ``U``, ``G``, ``W`` [-].
    ellipticity : float
        ``k`` [-].
    extrapolated : bool
        True where ``k`` lies outside :data:`ELLIPTICITY_RANGE`.
    """

    central: float
    minimum: float
    speed_parameter: float
    materials_parameter: float
    load_parameter: float
    ellipticity: float
    extrapolated: bool


def hamrock_dowson(load, entrainment_speed, viscosity, pressure_viscosity, e_eff, r_x,
                   ellipticity) -> FilmThickness:
    """Hamrock–Dowson central and minimum film thickness (module Notes).

    Parameters
    ----------
    load : float
        Normal load of the contact ``w`` [N], > 0.
    entrainment_speed : float
        ``u = (u1 + u2)/2`` [m s⁻¹], > 0 (its sign does not matter: ``|u|`` is used).
    viscosity : float
        ``η0`` [Pa s] at the inlet's temperature, ambient pressure.
    pressure_viscosity : float
        ``α`` [Pa⁻¹].
    e_eff : float
        ``E'`` [Pa].
    r_x : float
        Effective radius in the rolling direction [m].
    ellipticity : float
        ``k = a/b ≥ 1`` with ``a`` across the rolling direction [-].

    Returns
    -------
    FilmThickness
    """
    w = _positive("load", load, "N")
    u = _positive("entrainment speed |u|", abs(float(entrainment_speed)), "m/s")
    eta = _positive("viscosity", viscosity, "Pa s")
    alpha = _positive("pressure_viscosity", pressure_viscosity, "1/Pa")
    e = _positive("e_eff", e_eff, "Pa")
    rx = _positive("r_x", r_x, "m")
    k = _positive("ellipticity", ellipticity, "")
    if k < 1.0:
        raise ValueError(f"ellipticity k = {k:.6g} < 1: Hamrock-Dowson's formulas take the rolling "
                         "direction along the ellipse's minor axis (k >= 1)")
    big_u = eta * u / (e * rx)
    big_g = alpha * e
    big_w = w / (e * rx * rx)
    lo, hi = ELLIPTICITY_RANGE
    return FilmThickness(central_film(w, u, eta, alpha, e, rx, k), minimum_film(w, u, eta, alpha, e, rx, k),
                         big_u, big_g, big_w, k, not lo <= k <= hi)


#: Hamrock–Dowson's exponents of the entrainment speed and the load: central and minimum film.
HC_EXP_U, HC_EXP_W, HM_EXP_U, HM_EXP_W = 0.67, -0.067, 0.68, -0.073


@kernel(inline=True)
def central_film(w, u, eta, alpha, e, rx, k):
    """Hamrock–Dowson central film ``h_c`` [m] (module Notes), the one place of its formula
    (:func:`hamrock_dowson` and the dynamics' contacts, :mod:`rvcore.contact.laws`).

    Parameters
    ----------
    w : float
        Normal load [N], > 0.
    u : float
        Entrainment speed ``|u|`` [m s⁻¹], ≥ 0 (0 gives no film).
    eta, alpha : float
        ``η0`` [Pa s], ``α`` [Pa⁻¹].
    e, rx, k : float
        ``E'`` [Pa], ``R_x`` [m], ellipticity ``k`` [-].
    """
    big_u = eta * u / (e * rx)
    big_w = w / (e * rx * rx)
    return rx * 2.69 * big_u ** HC_EXP_U * (alpha * e) ** 0.53 * big_w ** HC_EXP_W * (1.0 - 0.61 * math.exp(-0.73 * k))


@kernel(inline=True)
def minimum_film(w, u, eta, alpha, e, rx, k):
    """Hamrock–Dowson minimum film ``h_min`` [m] (module Notes; arguments as :func:`central_film`)."""
    big_u = eta * u / (e * rx)
    big_w = w / (e * rx * rx)
    return rx * 3.63 * big_u ** HM_EXP_U * (alpha * e) ** 0.49 * big_w ** HM_EXP_W * (1.0 - math.exp(-0.68 * k))


def hamrock_dowson_contact(contact: HertzContact, load, entrainment_speed, viscosity,
                           pressure_viscosity) -> FilmThickness:
    """Hamrock–Dowson film of a contact built by :mod:`rvcore.hertz` [m].

    Parameters
    ----------
    contact : rvcore.hertz.HertzContact
        Its ``x`` must be the rolling direction and its major axis across it
        (``major_axis == "y"``: every ball–raceway contact of :func:`rvcore.hertz.race_contact`).
    load, entrainment_speed, viscosity, pressure_viscosity
        As :func:`hamrock_dowson`.
    """
    if contact.major_axis != "y":
        raise ValueError("the contact's major axis lies along the rolling direction (k < 1 in "
                         "Hamrock-Dowson's terms); their formulas do not cover it")
    r_x, _ = effective_radii(contact)
    return hamrock_dowson(load, entrainment_speed, viscosity, pressure_viscosity,
                          contact.effective_modulus, r_x, contact.ellipticity)


def film_parameter(minimum_film, composite_roughness) -> float:
    """Film parameter ``λ = h_min/σ`` [-].

    Parameters
    ----------
    minimum_film : float
        ``h_min`` [m], ≥ 0.
    composite_roughness : float
        ``σ`` [m], > 0 (:func:`rvcore.bearing.lubricant.composite_roughness`).
    """
    h = float(minimum_film)
    if not (math.isfinite(h) and h >= 0.0):
        raise ValueError(f"minimum film must be a finite thickness >= 0 m, got {minimum_film!r}")
    return h / _positive("composite roughness", composite_roughness, "m")


def entrainment_speed_pure_rolling(relative_speed, pitch_diameter, ball_diameter,
                                   contact_angle=0.0) -> float:
    """Entrainment speed of a ball–raceway contact in pure rolling [m s⁻¹].

    Parameters
    ----------
    relative_speed : float
        ``ω_i − ω_o``, the inner ring's speed relative to the outer [rad s⁻¹].
    pitch_diameter, ball_diameter : float
        ``d_m``, ``D`` [m].
    contact_angle : float
        ``α`` [rad].

    Returns
    -------
    float
        ``u = |ω_i − ω_o|·d_m·(1 − γ²)/4``, ``γ = D·cos α/d_m``, the same at the inner and
        the outer contact [m s⁻¹].

    Notes
    -----
    In pure rolling the cage turns at ``ω_o + (ω_i − ω_o)(1 − γ)/2``; in the cage's frame
    the inner race's surface passes the inner contact at ``(ω_i − ω_c)·d_m(1 − γ)/2`` and
    the ball's surface at the same speed, which gives the formula (Harris & Kotzalas,
    *Essential Concepts of Bearing Technology*, the kinematics chapter; Hamrock & Dowson,
    *Ball Bearing Lubrication*, 1981).
    """
    dm = _positive("pitch_diameter", pitch_diameter, "m")
    d = _positive("ball_diameter", ball_diameter, "m")
    gamma = d * math.cos(float(contact_angle)) / dm
    if not gamma < 1.0:
        raise ValueError(f"D cos(alpha)/d_m = {gamma:.6g} must be < 1")
    return abs(float(relative_speed)) * dm * (1.0 - gamma * gamma) / 4.0


@kernel(inline=True)
def log_films(log_hc1, log_lam1, lu, lq):
    """``(log h_c, log λ)`` [log m, -] of a contact at ``lu = log u_e`` and ``lq = log Q``
    from its arc's unit-film columns (:func:`with_film_columns`)::

        log h_c = log h_c1 + 0.67·log u_e − 0.067·log Q
        log λ   = log λ1  + 0.68·log u_e − 0.073·log Q

    Hamrock–Dowson's central and minimum films as power laws of u and Q at one contact."""
    return log_hc1 + HC_EXP_U * lu + HC_EXP_W * lq, log_lam1 + HM_EXP_U * lu + HM_EXP_W * lq


def with_film_columns(model, bearing):
    """``model`` (:func:`rvcore.bearing.layout.compile_bearing`) with its arcs' unit-film
    columns filled: ``log h_c`` [log m] and ``log λ`` [-] of each arc's Hertz contact at 1 N
    and 1 m/s with ``bearing``'s lubricant (:func:`rvcore.bearing.lubricant.contact_lubricant`),
    from which the dynamics take every loaded contact's film as
    ``log h = log h1 + e_u·log u + e_w·log Q`` (Hamrock–Dowson's power laws).

    Parameters
    ----------
    model : rvcore.bearing.layout.CompiledBearing
    bearing : rvcore.bearing.geometry.Bearing

    Returns
    -------
    rvcore.bearing.layout.CompiledBearing
        A copy with new ``arcs``.
    """
    from dataclasses import replace

    from ..bearing.layout import A_EEFF, A_ELL, A_LOG_HC1, A_LOG_LAM1, A_RX
    from ..bearing.lubricant import contact_lubricant

    eta0, alpha, sigma = contact_lubricant(bearing)
    arcs = model.arcs.copy()
    for a in range(arcs.shape[0]):
        rx, e, k = arcs[a, A_RX], arcs[a, A_EEFF], arcs[a, A_ELL]
        arcs[a, A_LOG_HC1] = math.log(central_film(1.0, 1.0, eta0, alpha, e, rx, k))
        arcs[a, A_LOG_LAM1] = math.log(minimum_film(1.0, 1.0, eta0, alpha, e, rx, k) / sigma)
    return replace(model, arcs=arcs)
