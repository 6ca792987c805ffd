"""Lubrication at a quasi-static equilibrium: the operating viscosity, ISO 281's κ, a_ISO
and modified rating life L_nm, and the Hamrock–Dowson film of the heaviest-loaded inner
contact in rolling kinematics. SI in and out.

Notes
-----
At the relative speed ``ω`` of the rings (the inner ring's; the outer is fixed):

- ``ν`` the operating viscosity (:func:`rvcore.bearing.lubricant.operating_viscosity`),
  ``ν1`` ISO 281's reference viscosity at ``n = ω·60/2π`` and the first row's ``d_m``,
  ``κ = ν/ν1`` (:mod:`rvcore.standards.iso281_modified`);
- ``a_ISO`` for ball bearings with ``e_C`` (:func:`rvcore.bearing.lubricant.contamination_of`),
  ``C_u = C_0/22·(100/d_m)^0.5`` (ISO 281 Annex B's simplified form, ``C_0`` of ISO 76)
  and ``P`` ISO 281's dynamic equivalent load of the equilibrium's applied loads
  (:func:`rvcore.standards.iso16281.static_life`); ``L_nm = a_1·a_ISO·L10`` with
  ``a_1 = 1`` (90 % reliability), in revolutions;
- the film: the inner-ring contact carrying the largest load, its Hertz ellipse at its
  own contact angle (:func:`rvcore.hertz.race_contact`), the entrainment speed of pure
  rolling (:func:`rvcore.contact.film.entrainment_speed_pure_rolling`), η0 and α of
  :func:`rvcore.bearing.lubricant.contact_lubricant`; ``λ = h_min/σ``.

The lubrication regime from λ, the usual convention (Hamrock, Schmid & Jacobson,
*Fundamentals of Machine Elements*, the lubrication chapter, give the same bounds):
``λ < 1`` boundary, ``1 ≤ λ < 3`` mixed, ``λ ≥ 3`` full film. The film is that of a fully
flooded, isothermal contact: a grease-lubricated bearing runs starved, so it is an upper
bound, and measured films scatter about ±30 % around the formula (Koye & Winer 1981).
"""
from __future__ import annotations

import math

__all__ = ["REGIMES", "regime", "lubrication_at"]

#: The lubrication regimes and the λ each starts at [-].
REGIMES = (("boundary", 0.0), ("mixed", 1.0), ("full film", 3.0))


def regime(film_parameter: float) -> str:
    """The lubrication regime of a film parameter λ [-] (module Notes); "" where λ is NaN."""
    lam = float(film_parameter)
    if not math.isfinite(lam):
        return ""
    name = REGIMES[0][0]
    for n, start in REGIMES:
        if lam >= start:
            name = n
    return name


def _heaviest_inner_contact(bearing, st):
    """(load [N], contact angle [rad], row, inner arc) of the most loaded inner contact; None
    when no inner contact carries a load."""
    best = None
    for j in range(st.ball_loads.shape[0]):
        row_index = int(st.row_of_ball[j])
        row = bearing.rows[row_index]
        for k in range(len(row.inner_arcs)):
            q = float(st.ball_loads[j, k])
            if q > 0.0 and (best is None or q > best[0]):
                angle = float(st.contact_angles[j, k])
                best = (q, angle if math.isfinite(angle) else row.inner_arcs[k].contact_angle, row, k)
    return best


def lubrication_at(bearing, st, speed: float) -> dict:
    """Lubrication outputs at an equilibrium ``st`` and ring speed ``speed`` (module Notes).

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    st : rvcore.statics.equilibrium.StaticResult
    speed : float
        Inner-ring speed relative to the outer ring [rad s⁻¹], > 0.

    Returns
    -------
    dict
        ``operating_viscosity`` [m² s⁻¹], ``reference_viscosity_nu1`` [m² s⁻¹], ``kappa``
        [-] (not limited), ``kappa_outside_iso281`` (κ < 0.1), ``a_iso`` [-],
        ``ep_rule`` (bool), ``contamination_factor`` [-], ``fatigue_load_limit`` [N],
        ``equivalent_load`` [N], ``basic_rating_life_L10`` [rev],
        ``modified_rating_life_L_nm`` [rev], ``film_thickness_central``,
        ``film_thickness_min`` [m], ``film_contact_load`` [N], ``entrainment_speed``
        [m s⁻¹], ``composite_roughness`` [m], ``lambda`` [-], ``regime`` (str),
        ``film_extrapolated`` (the ellipticity lies outside Hamrock–Dowson's fit). NaN
        (and "") where a value is not defined (no loaded inner contact, no rating).
    """
    from ..bearing.lubricant import contact_lubricant, contamination_of, operating_viscosity
    from ..contact.film import entrainment_speed_pure_rolling, film_parameter, hamrock_dowson_contact
    from ..hertz import effective_modulus, race_contact
    from ..standards.iso16281 import LifeError, static_life
    from ..standards.iso281_modified import (a_iso_ball, fatigue_load_limit_ball, modified_rating_life,
                                             reference_viscosity)
    from ..standards.iso76 import StaticRatingError, bearing_static_load_rating

    nan = math.nan
    w = abs(float(speed))
    if not w > 0.0:
        raise ValueError("lubrication outputs need a speed > 0 rad/s")
    dm = bearing.rows[0].pitch_diameter
    nu = operating_viscosity(bearing)
    nu1 = reference_viscosity(w, dm)
    kappa = nu / nu1
    ec = contamination_of(bearing)
    out = {"operating_viscosity": nu, "reference_viscosity_nu1": nu1, "kappa": kappa,
           "kappa_outside_iso281": bool(kappa < 0.1), "contamination_factor": ec}
    try:
        life = static_life(bearing, st)
        p = float(life["equivalent_load_N"])
        l10 = float(life["basic_rating_life_L10_Mrev"]) * 1e6
        cu = fatigue_load_limit_ball(bearing_static_load_rating(bearing), dm)
        a = a_iso_ball(kappa, ec * cu / p if p > 0.0 else math.inf, bearing.lubricant.ep_additives, ec) \
            if p > 0.0 else {"a_iso": nan, "ep_rule": False}
        lnm = modified_rating_life(l10, a["a_iso"]) if p > 0.0 and math.isfinite(l10) else nan
        out.update({"a_iso": a["a_iso"], "ep_rule": bool(a["ep_rule"]), "fatigue_load_limit": cu,
                    "equivalent_load": p, "basic_rating_life_L10": l10 if math.isfinite(l10) else nan,
                    "modified_rating_life_L_nm": lnm})
    except (LifeError, StaticRatingError, ValueError):
        out.update({"a_iso": nan, "ep_rule": False, "fatigue_load_limit": nan, "equivalent_load": nan,
                    "basic_rating_life_L10": nan, "modified_rating_life_L_nm": nan})
    eta0, alpha, sigma = contact_lubricant(bearing)
    out["composite_roughness"] = sigma
    best = _heaviest_inner_contact(bearing, st)
    if best is None:
        out.update({"film_thickness_central": nan, "film_thickness_min": nan, "film_contact_load": 0.0,
                    "entrainment_speed": nan, "lambda": nan, "regime": "", "film_extrapolated": False})
        return out
    q, angle, row, k = best
    rm, bm = bearing.ring_material, bearing.ball_material
    e_eff = effective_modulus(rm.youngs_modulus, rm.poisson_ratio, bm.youngs_modulus, bm.poisson_ratio)
    contact = race_contact(row.ball_diameter, row.pitch_diameter, row.inner_arcs[k].curvature_ratio,
                           angle, "inner", e_eff)
    u = entrainment_speed_pure_rolling(w, row.pitch_diameter, row.ball_diameter, angle)
    film = hamrock_dowson_contact(contact, q, u, eta0, alpha)
    lam = film_parameter(film.minimum, sigma) if sigma > 0.0 else math.inf
    out.update({"film_thickness_central": film.central, "film_thickness_min": film.minimum,
                "film_contact_load": q, "entrainment_speed": u, "lambda": lam, "regime": regime(lam),
                "film_extrapolated": bool(film.extrapolated)})
    return out

