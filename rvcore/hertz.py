"""Hertz point-contact constants from the complete elliptic integrals (docs/model.md §3, §9.1).

Set-up code, run once per contact type: plain numpy/scipy, no numba. Everything is SI.

Two elastic bodies touch at a point. Their principal planes are aligned: ``x`` is the
rolling direction, ``y`` the transverse direction. Body ``i`` has the principal
curvatures ``ρ_ix`` and ``ρ_iy`` [1/m], positive where the surface is convex and
negative where it is concave. The contact ellipse has the semi-major axis ``a`` and the
semi-minor axis ``b``. The major axis lies along the direction with the smaller
curvature sum (recorded as :attr:`HertzContact.major_axis`).

Notes
-----
Curvature sums and the ellipticity (Harris; Hamrock)::

    ρ_x = ρ_1x + ρ_2x ,   ρ_y = ρ_1y + ρ_2y ,   Σρ = ρ_x + ρ_y ,   R = 1/Σρ
    F(ρ) = |ρ_x − ρ_y| / Σρ
    r = max(ρ_x, ρ_y) / min(ρ_x, ρ_y) = (1 + F(ρ)) / (1 − F(ρ))       (= R_y/R_x)

Both ``ρ_x`` and ``ρ_y`` must be positive. Otherwise the surfaces conform in one plane
and the contact is not a Hertz point contact.

The ellipticity ``κ = a/b ≥ 1`` is solved exactly (``scipy.optimize.brentq``) from::

    F(ρ) = [(κ² + 1)·ℰ − 2ℱ] / [(κ² − 1)·ℰ]   ⇔   r = (κ²ℰ − ℱ) / (ℱ − ℰ)

Here ``ℱ = K(m)`` and ``ℰ = E(m)`` are the complete elliptic integrals of the first and
second kind. Their parameter is ``m = e² = 1 − 1/κ²`` (scipy's convention). Near
``κ = 1``, the numerator and denominator above both vanish like ``m²`` and ``m``. The
root is therefore found on the same relation written with Carlson's symmetric integral
``R_D`` (``scipy.special.elliprd``), which has no cancellation::

    ℱ − ℰ = (m/3)·R_D(0, 1−m, 1) ,   ℰ − (1−m)·ℱ = (m(1−m)/3)·R_D(0, 1, 1−m)
    ⇒   r = R_D(0, 1, 1/κ²) / R_D(0, 1/κ², 1)

``ℱ`` and ``ℰ`` are then evaluated with ``scipy.special.ellipkm1(1/κ²)`` and
``scipy.special.ellipe(1 − 1/κ²)``. The circular case (``F(ρ) = 0``) is ``κ = 1``,
``ℱ = ℰ = π/2``.

Effective modulus (Hamrock)::

    E' = 2 / [(1 − ν₁²)/E₁ + (1 − ν₂²)/E₂]          (= E/(1 − ν²) for two equal solids)

Contact ellipse, approach and stiffness for a normal load ``Q`` (Harris; Hamrock)::

    a = (6 κ² ℰ Q R / (π E'))^(1/3)
    b = (6 ℰ Q R / (π κ E'))^(1/3)
    δ = ℱ · [ 9/(2 ℰ R) · (Q / (π κ E'))² ]^(1/3)
    Q = K δ^1.5 ,   K = π κ E' · sqrt(2 ℰ R / 9) / ℱ^1.5
    p_max = 3 Q / (2 π a b)

Ball–raceway curvatures (ball diameter ``D``, pitch diameter ``d_m``, contact angle
``α``, groove curvature ratio ``f``)::

    γ = D cos α / d_m
    ball:  ρ_1x = ρ_1y = 2/D
    inner race:  ρ_2x = +(2/D)·γ/(1 − γ) ,   ρ_2y = −1/(f D)
    outer race:  ρ_2x = −(2/D)·γ/(1 + γ) ,   ρ_2y = −1/(f D)

Ball in a cylindrical cage pocket of diameter ``D_p``: ``ρ_2x = −2/D_p`` in the plane
normal to the pocket axis and ``ρ_2y = 0`` along the pocket axis.

Hamrock–Brewe closed forms, a cross-check only (``r = R_y/R_x ≥ 1``)::

    κ ≈ 1.0339 r^0.636 ,   ℰ ≈ 1.0003 + 0.5968 / r ,   ℱ ≈ 1.5277 + 0.6023 ln r

References
----------
T. A. Harris, M. N. Kotzalas, *Essential Concepts of Bearing Technology*, 5th ed., ch. 6.
B. J. Hamrock, D. Dowson, *Ball Bearing Lubrication*, Wiley 1981, ch. 3 (with Brewe).
K. L. Johnson, *Contact Mechanics*, CUP 1985, §3.7.
B. C. Carlson, DLMF §19.25 (complete integrals in symmetric form).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipe, ellipkm1, elliprd

#: The two raceways' labels, shared by every module that names a ring (rvcore.bearing.geometry
#: re-exports them).
INNER = 0
OUTER = 1

__all__ = [
    "HertzContact",
    "effective_modulus",
    "point_contact",
    "race_contact",
    "pocket_contact",
    "spherical_pocket_contact",
    "hamrock_brewe",
    "effective_radii",
]


@dataclass(frozen=True)
class HertzContact:
    """Hertz constants of one point contact. Build it with :func:`point_contact`.

    Parameters
    ----------
    curvature_sum : float
        ``Σρ`` [1/m].
    curvature_difference : float
        ``F(ρ)`` [-], in [0, 1).
    ellipticity : float
        ``κ = a/b ≥ 1`` [-].
    elliptic_k : float
        ``ℱ``: complete elliptic integral of the first kind at ``m = e² = 1 − 1/κ²`` [-].
    elliptic_e : float
        ``ℰ``: complete elliptic integral of the second kind at the same ``m`` [-].
    effective_modulus : float
        ``E'`` [Pa].
    stiffness : float
        ``K`` in ``Q = K δ^1.5`` [N m^-1.5].
    a_coefficient : float
        Semi-major axis ``a = a_coefficient · Q^(1/3)`` [m N^-1/3].
    b_coefficient : float
        Semi-minor axis ``b = b_coefficient · Q^(1/3)`` [m N^-1/3].
    major_axis : str
        ``"x"`` or ``"y"``: the direction of the semi-major axis ``a`` (the one with the
        smaller curvature sum). The circular case reports ``"y"``.

    Notes
    -----
    The equations are in the module docstring.
    """

    curvature_sum: float
    curvature_difference: float
    ellipticity: float
    elliptic_k: float
    elliptic_e: float
    effective_modulus: float
    stiffness: float
    a_coefficient: float
    b_coefficient: float
    major_axis: str = "y"

    # Every method below takes a normal load Q [N] (float or array_like, >= 0; a negative
    # one raises ValueError) and returns a float or an ndarray of the same shape. The
    # ellipse's size and pressure scale as Q^(1/3), so they share one helper.

    @staticmethod
    def _cube_root_law(coefficient, load):
        """``coefficient · Q^(1/3)`` with Q checked by :func:`_loads`."""
        return coefficient * np.cbrt(_loads(load))

    def deflection(self, load):
        """Elastic approach ``δ = (Q/K)^(2/3)`` [m] under the normal load Q [N]."""
        return (_loads(load) / self.stiffness) ** (2.0 / 3.0)

    def load(self, deflection):
        """Normal load ``Q = K·δ^1.5`` [N] at the approach δ [m] (float or array_like),
        zero for ``δ <= 0`` (no adhesion)."""
        d = np.maximum(np.asarray(deflection, dtype=float), 0.0)
        return (self.stiffness * d**1.5)[()]

    def semi_axes(self, load):
        """Semi-major and semi-minor axes ``(a, b)`` of the contact ellipse [m] under Q [N]."""
        return (self._cube_root_law(self.a_coefficient, load),
                self._cube_root_law(self.b_coefficient, load))

    def max_pressure(self, load):
        """Maximum contact pressure ``p_max = 3Q/(2πab)`` [Pa] (the ellipse's centre) under Q [N]."""
        return self._cube_root_law(self.pressure_coefficient, load)

    @property
    def pressure_coefficient(self) -> float:
        """``p_max / Q^(1/3) = 3 / (2π a_c b_c)`` [Pa N^-1/3]."""
        return 3.0 / (2.0 * math.pi * self.a_coefficient * self.b_coefficient)


def _loads(load):
    q = np.asarray(load, dtype=float)
    if np.any(q < 0.0):
        bad = float(np.min(q))
        raise ValueError(f"normal load must be >= 0 N, got {bad:.6g} N")
    return q


def _finite_number(name: str, value) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {x!r}")
    return x


def _positive(name: str, value, unit: str) -> float:
    x = _finite_number(name, value)
    if x <= 0.0:
        raise ValueError(f"{name} must be > 0 {unit}, got {x:.6g} {unit}")
    return x


def effective_modulus(e1, nu1, e2=None, nu2=None) -> float:
    """Effective modulus ``E'`` of two elastic bodies [Pa].

    Parameters
    ----------
    e1 : float
        Young's modulus of body 1 [Pa].
    nu1 : float
        Poisson ratio of body 1 [-], in (−1, 0.5].
    e2 : float, optional
        Young's modulus of body 2 [Pa]; defaults to ``e1``.
    nu2 : float, optional
        Poisson ratio of body 2 [-]; defaults to ``nu1``.

    Returns
    -------
    float
        ``E' = 2 / [(1 − ν₁²)/E₁ + (1 − ν₂²)/E₂]`` [Pa]; ``E/(1 − ν²)`` for equal bodies.
    """
    e1 = _positive("Young's modulus e1", e1, "Pa")
    nu1 = _finite_number("Poisson ratio nu1", nu1)
    e2 = e1 if e2 is None else _positive("Young's modulus e2", e2, "Pa")
    nu2 = nu1 if nu2 is None else _finite_number("Poisson ratio nu2", nu2)
    for name, nu in (("nu1", nu1), ("nu2", nu2)):
        if not -1.0 < nu <= 0.5:
            raise ValueError(f"Poisson ratio {name} must lie in (-1, 0.5], got {nu:.6g}")
    return 2.0 / ((1.0 - nu1**2) / e1 + (1.0 - nu2**2) / e2)


def _curvature_sums(rho_1x, rho_1y, rho_2x, rho_2y):
    """Validated ``(ρ_x, ρ_y)`` [1/m]."""
    r1x = _finite_number("rho_1x", rho_1x)
    r1y = _finite_number("rho_1y", rho_1y)
    r2x = _finite_number("rho_2x", rho_2x)
    r2y = _finite_number("rho_2y", rho_2y)
    rx, ry = r1x + r2x, r1y + r2y
    total = rx + ry
    if not total > 0.0:
        raise ValueError(
            f"curvature sum Σρ = {r1x:.6g} + {r1y:.6g} + {r2x:.6g} + {r2y:.6g} "
            f"= {total:.6g} 1/m must be > 0")
    for plane, a, b, s in (("x", r1x, r2x, rx), ("y", r1y, r2y, ry)):
        if not s > 0.0:
            raise ValueError(
                f"curvature sum in the {plane} plane rho_1{plane} + rho_2{plane} = "
                f"{a:.6g} + {b:.6g} = {s:.6g} 1/m must be > 0 (the surfaces conform or "
                f"separate there; that is not a Hertz point contact)")
    return rx, ry


def _ratio_of_kappa(t: float) -> float:
    """``ln r`` for ``κ = exp(t)``: ``ln R_D(0,1,1/κ²) − ln R_D(0,1/κ²,1)``."""
    q = math.exp(-2.0 * t)  # 1/κ² = 1 − m
    return math.log(elliprd(0.0, 1.0, q)) - math.log(elliprd(0.0, q, 1.0))


def _solve_ellipticity(ratio: float):
    """``(κ, ℱ, ℰ)`` for the curvature-sum ratio ``r = ρ_max/ρ_min ≥ 1``."""
    if ratio == 1.0:
        return 1.0, math.pi / 2.0, math.pi / 2.0
    target = math.log(ratio)

    def g(t):
        return _ratio_of_kappa(t) - target

    hi = 1.0
    while g(hi) <= 0.0:
        hi *= 2.0
        if hi > 300.0:  # κ > e^300: far beyond any point contact
            raise ValueError(f"curvature-sum ratio {ratio:.6g} is too large for a point contact")
    t = brentq(g, 0.0, hi, xtol=1e-15, rtol=4.0 * np.finfo(float).eps, maxiter=200)
    q = math.exp(-2.0 * t)
    kappa = math.exp(t)
    return kappa, float(ellipkm1(q)), float(ellipe(-math.expm1(-2.0 * t)))


def point_contact(rho_1x, rho_1y, rho_2x, rho_2y, e_eff) -> HertzContact:
    """Hertz constants of a point contact between two bodies with aligned principal planes.

    Parameters
    ----------
    rho_1x, rho_1y : float
        Principal curvatures of body 1 in the rolling (x) and transverse (y) planes [1/m];
        convex positive, concave negative.
    rho_2x, rho_2y : float
        The same for body 2 [1/m].
    e_eff : float
        Effective modulus ``E'`` [Pa] (see :func:`effective_modulus`).

    Returns
    -------
    HertzContact

    Raises
    ------
    ValueError
        A non-finite input, ``E' <= 0``, or a curvature sum ``ρ_x`` or ``ρ_y`` that is not
        positive (which includes ``Σρ <= 0``).

    Notes
    -----
    ``κ`` is solved exactly from the elliptic-integral relation; see the module docstring.
    """
    rx, ry = _curvature_sums(rho_1x, rho_1y, rho_2x, rho_2y)
    e_eff = _positive("effective modulus e_eff", e_eff, "Pa")
    total = rx + ry
    big, small = (rx, ry) if rx >= ry else (ry, rx)
    kappa, fk, ek = _solve_ellipticity(big / small)
    r = 1.0 / total
    stiffness = math.pi * kappa * e_eff * math.sqrt(2.0 * ek * r / 9.0) / fk**1.5
    a_c = (6.0 * kappa**2 * ek * r / (math.pi * e_eff)) ** (1.0 / 3.0)
    b_c = (6.0 * ek * r / (math.pi * kappa * e_eff)) ** (1.0 / 3.0)
    return HertzContact(
        curvature_sum=total,
        curvature_difference=(big - small) / total,
        ellipticity=kappa,
        elliptic_k=fk,
        elliptic_e=ek,
        effective_modulus=e_eff,
        stiffness=stiffness,
        a_coefficient=a_c,
        b_coefficient=b_c,
        major_axis="x" if rx < ry else "y",
    )


def _race_curvatures(ball_diameter, pitch_diameter, curvature_ratio, contact_angle, ring):
    d = _positive("ball_diameter", ball_diameter, "m")
    dm = _positive("pitch_diameter", pitch_diameter, "m")
    f = _finite_number("curvature_ratio", curvature_ratio)
    if f <= 0.5:
        raise ValueError(f"curvature_ratio f must exceed 0.5 (groove radius larger than the "
                         f"ball radius), got {f:.6g}")
    alpha = _finite_number("contact_angle", contact_angle)
    if abs(alpha) > math.pi / 2.0:
        raise ValueError(f"contact_angle must lie in [-pi/2, pi/2] rad, got {alpha:.6g} rad")
    if isinstance(ring, str):
        key = ring.strip().lower()
    elif isinstance(ring, (bool, np.bool_)):
        key = None
    elif isinstance(ring, (int, np.integer)):
        key = {INNER: "inner", OUTER: "outer"}.get(int(ring))
    else:
        key = None
    if key not in ("inner", "outer"):
        raise ValueError(f"ring must be 'inner' or 'outer' (or rvcore.hertz.INNER={INNER} / "
                         f"OUTER={OUTER}), got {ring!r}")
    gamma = d * max(math.cos(alpha), 0.0) / dm
    if gamma >= 1.0:
        raise ValueError(f"D cos(alpha) = {d * math.cos(alpha):.6g} m must be smaller than the "
                         f"pitch diameter {dm:.6g} m")
    ball = 2.0 / d
    if key == "inner":
        race_x = ball * gamma / (1.0 - gamma)
    else:
        race_x = -ball * gamma / (1.0 + gamma)
    race_y = -1.0 / (f * d)
    return ball, ball, race_x, race_y


def race_contact(ball_diameter, pitch_diameter, curvature_ratio, contact_angle, ring,
                 e_eff) -> HertzContact:
    """Hertz constants of a ball on an inner or outer raceway groove.

    Parameters
    ----------
    ball_diameter : float
        ``D`` [m], > 0.
    pitch_diameter : float
        ``d_m`` [m], > 0.
    curvature_ratio : float
        Groove radius over ball diameter ``f`` [-], > 0.5.
    contact_angle : float
        ``α`` [rad], in [−π/2, π/2].
    ring : {"inner", "outer"} or int
        Which raceway; ``rvcore.hertz.INNER`` / ``OUTER`` are accepted too.
    e_eff : float
        Effective modulus ``E'`` [Pa].

    Returns
    -------
    HertzContact
        ``x`` is the rolling direction and ``y`` the transverse direction; the major axis
        is along ``y``.

    Notes
    -----
    The curvatures are in the module docstring (``γ = D cos α / d_m``).
    """
    return point_contact(*_race_curvatures(ball_diameter, pitch_diameter, curvature_ratio,
                                           contact_angle, ring), e_eff)


def pocket_contact(ball_diameter, pocket_diameter, e_eff) -> HertzContact:
    """Hertz constants of a ball against the wall of a cylindrical cage pocket.

    Parameters
    ----------
    ball_diameter : float
        ``D`` [m], > 0.
    pocket_diameter : float
        ``D_p`` [m], > ``D``.
    e_eff : float
        Effective modulus ``E'`` of ball and cage [Pa].

    Returns
    -------
    HertzContact
        ``x`` is the plane normal to the pocket axis (pocket curvature ``−2/D_p``), ``y``
        the pocket axis (curvature 0); the major axis is along ``x``.
    """
    d = _positive("ball_diameter", ball_diameter, "m")
    dp = _positive("pocket_diameter", pocket_diameter, "m")
    if dp <= d:
        raise ValueError(f"pocket_diameter {dp:.6g} m must exceed ball_diameter {d:.6g} m")
    return point_contact(2.0 / d, 2.0 / d, -2.0 / dp, 0.0, e_eff)


def spherical_pocket_contact(ball_diameter, pocket_diameter, e_eff) -> HertzContact:
    """Hertz constants of a ball in the spherical pocket of a ball-guided cage.

    Parameters and returns as :func:`pocket_contact`; both principal curvatures of the
    pocket are ``−2/D_p`` (concave), so the contact is circular (κ = 1).
    """
    d = _positive("ball_diameter", ball_diameter, "m")
    dp = _positive("pocket_diameter", pocket_diameter, "m")
    if dp <= d:
        raise ValueError(f"pocket_diameter {dp:.6g} m must exceed ball_diameter {d:.6g} m")
    return point_contact(2.0 / d, 2.0 / d, -2.0 / dp, -2.0 / dp, e_eff)


def hamrock_brewe(rho_1x, rho_1y, rho_2x, rho_2y, e_eff) -> dict:
    """Hamrock–Brewe closed-form approximation of the Hertz constants. Cross-check only.

    Parameters
    ----------
    rho_1x, rho_1y, rho_2x, rho_2y : float
        Principal curvatures of bodies 1 and 2 [1/m], as in :func:`point_contact`.
    e_eff : float
        Effective modulus ``E'`` [Pa].

    Returns
    -------
    dict
        ``ellipticity`` [-], ``elliptic_k`` [-], ``elliptic_e`` [-], ``stiffness``
        [N m^-1.5], ``a_coefficient`` and ``b_coefficient`` [m N^-1/3]. These are the same
        quantities as the fields of :class:`HertzContact`, from the approximate ``κ``, ``ℰ``
        and ``ℱ``.

    Notes
    -----
    ``κ ≈ 1.0339 r^0.636``, ``ℰ ≈ 1.0003 + 0.5968/r``, ``ℱ ≈ 1.5277 + 0.6023 ln r``
    with ``r = R_y/R_x ≥ 1``. These go into the same a, b, K formulae as the exact
    solution (module docstring).
    """
    rx, ry = _curvature_sums(rho_1x, rho_1y, rho_2x, rho_2y)
    e_eff = _positive("effective modulus e_eff", e_eff, "Pa")
    ratio = max(rx, ry) / min(rx, ry)
    kappa = 1.0339 * ratio**0.636
    ek = 1.0003 + 0.5968 / ratio
    fk = 1.5277 + 0.6023 * math.log(ratio)
    r = 1.0 / (rx + ry)
    return {
        "ellipticity": kappa,
        "elliptic_k": fk,
        "elliptic_e": ek,
        "stiffness": math.pi * kappa * e_eff * math.sqrt(2.0 * ek * r / 9.0) / fk**1.5,
        "a_coefficient": (6.0 * kappa**2 * ek * r / (math.pi * e_eff)) ** (1.0 / 3.0),
        "b_coefficient": (6.0 * ek * r / (math.pi * kappa * e_eff)) ** (1.0 / 3.0),
    }


def effective_radii(contact: HertzContact):
    """``(R_x, R_y)`` [m] of a Hertz contact, x the rolling direction.

    Parameters
    ----------
    contact : rvcore.hertz.HertzContact

    Notes
    -----
    From the contact's ``Σρ`` and ``F(ρ)``: the curvature sums are ``Σρ·(1 ± F)/2``; the
    larger one lies across the ellipse's minor axis. This module records which
    direction the major axis takes (``major_axis``): for a ball on a raceway it is ``y``,
    so ``ρ_x`` is the larger sum.
    """
    big = 0.5 * contact.curvature_sum * (1.0 + contact.curvature_difference)
    small = 0.5 * contact.curvature_sum * (1.0 - contact.curvature_difference)
    rho_x, rho_y = (big, small) if contact.major_axis == "y" else (small, big)
    return 1.0 / rho_x, 1.0 / rho_y
