"""The steady operating point of a duty cycle and the bearing's statics there, SI.

A designer reads stiffness and load distribution "at the operating point": the loads the
profile applies in the middle of its steady phase. The statics there (rigid rings, Hertz
at every contact, balls in equilibrium, the ring's weight included) give the ball loads
per row, the tangent stiffness and the rating lives there (:mod:`rvcore.standards.iso16281`).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..standards.palmgren import FrictionMomentError, friction_moment
from ..standards.iso16281 import LifeError, static_life
from ..output_table import STEADY, outputs_of
from ..profile import CH_AXIAL, CH_DIRECTION, CH_MOMENT, CH_RADIAL, PHASES, OperatingPoint, Profile
from .equilibrium import NoEquilibriumError, StaticResult, solve_statics
from .flexible import mode_truncation
from ..standards.iso76 import StaticRatingError, static_safety_factor, static_safety_factor_from_pressure


def steady_time(profile: Profile) -> float:
    """The middle of the profile's steady phase [s]."""
    for name, start, end in profile.phases:
        if name == PHASES[1]:
            return 0.5 * (start + end)
    raise ValueError(f"profile {profile.name!r} has no {PHASES[1]} phase")


def steady_loads(profile: Profile, op: OperatingPoint):
    """Loads the profile applies in the middle of its steady phase.

    Returns
    -------
    radial_load : float
        [N]
    axial_load : float
        [N]
    moment : float
        Tilting moment about the axis normal to the radial load [N m].
    load_angle : float
        Direction of the radial load [rad].
    """
    resolved = profile.resolve(op)
    t = steady_time(profile)
    return tuple(resolved.value(c, t) for c in (CH_RADIAL, CH_AXIAL, CH_MOMENT, CH_DIRECTION))


def steady_statics(bearing, profile: Profile, op: OperatingPoint, *, gravity: bool = True,
                   rings=None, stiffness: bool = True) -> StaticResult:
    """Quasi-static equilibrium, ball loads and (``stiffness``) stiffness at the steady operating
    point; ``rings`` (:class:`rvcore.rings.flexible.FlexibleRings`) as :func:`solve_statics` takes them."""
    fr, fa, m, psi = steady_loads(profile, op)
    return solve_statics(bearing, fr, fa, m, psi, gravity=gravity, stiffness=stiffness, rings=rings)


def steady_outputs(bearing, profile: Profile, op: OperatingPoint, *, gravity: bool = True, rings=None,
                   all_rings=None) -> dict:
    """The ``steady`` outputs of :mod:`rvcore.output_table` for one case, SI; NaN where the
    statics find no equilibrium. ``rings``: the case's flexible rings (its dynamics' orders),
    so that a flexible case's stiffness, lives and film are its rings' (None: rigid);
    ``all_rings``: the same rings with every order the statics keep (the bearing file's),
    against which ``ring_mode_truncation`` measures ``rings``' (:func:`steady_mode_truncation`)."""

    try:
        st = steady_statics(bearing, profile, op, gravity=gravity, rings=rings)
    except NoEquilibriumError:
        return {o.name: float("nan") for o in outputs_of(STEADY)}
    out = dict(zip(("radial_stiffness", "axial_stiffness", "tilting_stiffness"), st.stiffness_scalars()))
    out.update(zip(("radial_stiffness_compliant", "axial_stiffness_compliant", "tilting_stiffness_compliant"),
                   st.free_stiffness_scalars()))
    out["statically_stable"] = float(positive_definite(st.stiffness_matrix, 3 if st.tilt == "held" else 5))
    out.update(_steady_lives(bearing, st))
    out.update(_steady_ratings(bearing, st, abs(op.speed)))
    out.update(steady_lubrication(bearing, st, abs(op.speed)))
    out["ring_mode_truncation"] = steady_mode_truncation(bearing, profile, op, st, gravity=gravity, rings=rings,
                                                         all_rings=all_rings)
    return out


def steady_mode_truncation(bearing, profile: Profile, op: OperatingPoint, st: StaticResult, *,
                           gravity: bool = True, rings=None, all_rings=None) -> float:
    """The flexible rings' truncation figure at the steady operating point [-]
    (:func:`rvcore.statics.flexible.mode_truncation`): the statics ``st`` on ``rings``' kept
    orders against the statics on ``all_rings``' every order. 0 where ``all_rings`` keeps no
    order more; NaN for rigid rings, without ``all_rings``, or where the statics on every
    order find no equilibrium."""
    from .flexible import mode_truncation

    if rings is None or rings.rigid or all_rings is None:
        return float("nan")
    if all(_same_orders(getattr(rings, f.name), getattr(all_rings, f.name)) for f in dataclasses.fields(rings)):
        return 0.0
    try:
        every = steady_statics(bearing, profile, op, gravity=gravity, rings=all_rings, stiffness=False)
    except NoEquilibriumError:
        return float("nan")
    return mode_truncation(st, every)


def _same_orders(kept, every) -> bool:
    """Whether two families of modes keep the same orders (both rigid: None)."""
    if kept is None or every is None:
        return kept is every
    return np.array_equal(kept.orders, every.orders)


def steady_lubrication(bearing, st: StaticResult, speed: float) -> dict:
    """κ, a_ISO, L_nm, the operating viscosity and the film of the heaviest-loaded inner
    contact at the equilibrium and ``speed`` [rad s^-1]
    (:func:`rvcore.statics.lubrication.lubrication_at`); the rows' operating clearance
    [m]. NaN where not defined (no speed, not rated)."""
    from ..bearing.lubricant import LubricantError
    from .lubrication import lubrication_at

    nan = float("nan")
    out = {"operating_clearance": float(bearing.rows[0].radial_clearance)}
    names = {"modified_rating_life_L_nm": "modified_rating_life_L_nm", "a_iso_steady": "a_iso",
             "kappa_steady": "kappa", "operating_viscosity": "operating_viscosity",
             "film_thickness_min_steady": "film_thickness_min", "film_parameter_steady": "lambda"}
    try:
        r = lubrication_at(bearing, st, speed) if speed > 0.0 else {}
    except (LubricantError, ValueError):
        r = {}
    for name, key in names.items():
        v = r.get(key, nan)
        out[name] = float(v) if v is not None and math.isfinite(v) else nan
    return out


def positive_definite(k, n: int = 5) -> bool:
    """Whether the leading ``n`` × ``n`` block of the tangent stiffness ``k`` is positive
    definite (a Cholesky factorisation of its symmetric part exists): definiteness does not
    depend on the coordinates' units (a congruence), so the mixed-unit matrix serves."""
    block = np.asarray(k, dtype=float)[:n, :n]
    try:
        np.linalg.cholesky(0.5 * (block + block.T))
    except np.linalg.LinAlgError:
        return False
    return True


def _steady_ratings(bearing, st: StaticResult, speed: float) -> dict:
    """ISO 76's s0 both ways and Palmgren's friction moment at the equilibrium (the loads it
    carries, the ring's weight included) and ``speed`` [rad s^-1]; NaN where not rated."""

    fr, fa = float(np.hypot(*st.applied[:2])), float(abs(st.applied[2]))
    nan = float("nan")
    s0 = float(static_safety_factor_from_pressure(st.max_contact_pressure))
    out = {"static_safety_factor_steady": s0 if math.isfinite(s0) else nan}
    try:
        cat = static_safety_factor(bearing, fr, fa)["static_safety_factor"]
        out["static_safety_factor_catalogue"] = cat if math.isfinite(cat) else nan
    except (LifeError, StaticRatingError):
        out["static_safety_factor_catalogue"] = nan
    try:
        m = friction_moment(bearing, fr, fa, speed)
        out.update({"friction_moment_palmgren": m["friction_moment_N_m"],
                    "friction_moment_palmgren_load": m["load_moment_N_m"],
                    "friction_moment_palmgren_viscous": m["viscous_moment_N_m"]})
    except (LifeError, StaticRatingError, FrictionMomentError):
        out.update(dict.fromkeys(("friction_moment_palmgren", "friction_moment_palmgren_load",
                                  "friction_moment_palmgren_viscous"), nan))
    return out


def _steady_lives(bearing, st: StaticResult) -> dict:
    """L10 and L10r [rev] at the equilibrium (:func:`rvcore.standards.iso16281.static_life`, the loads the
    equilibrium carries, the ring's weight included); NaN where infinite or not rated."""

    try:
        life = static_life(bearing, st)
    except LifeError:
        return {"basic_rating_life_L10": float("nan"), "reference_rating_life_L10r": float("nan")}
    rev = {"basic_rating_life_L10": life["basic_rating_life_L10_Mrev"] * 1e6,
           "reference_rating_life_L10r": life["reference_rating_life_L10r_Mrev"] * 1e6}
    return {k: (v if math.isfinite(v) else float("nan")) for k, v in rev.items()}
