"""Static load rating and static safety factor of radial ball bearings (ISO 76). SI in and
out, except where the standard's formula is written in its own units (N, mm), said there.

What is computed
----------------
- the static safety factor from the peak Hertz contact pressure of the load
  distribution, ``s_0 = (4200 MPa / p_max)^3`` (:func:`static_safety_factor_from_pressure`);
- the catalogue form: the basic static radial load rating ``C_0r = f_0·i·Z·D_w²·cos α``
  with ``f_0`` from ISO 76's table, the static equivalent radial load
  ``P_0r = max(X_0·F_r + Y_0·F_a, F_r)`` and ``s_0 = C_0r/P_0r``
  (:func:`static_safety_factor`).

The two routes answer the same question, ISO 76's: how far is the most heavily loaded
contact from the pressure at which the permanent deformation of ball and raceway
reaches 10^-4 of the ball diameter. The pressure route takes the peak pressure of the
actual load distribution (the contact angles under load, the tilt, the bearing's own
groove radii); the catalogue route takes ISO 76's idealised distribution (Stribeck's
``Q_max = 5·F_r/(Z·cos α)``) and ISO 76's osculations, ``f_i = 0.52``, ``f_e = 0.53``.

Standards and their numbering
-----------------------------
ISO 76:2006, *Rolling bearings — Static load ratings*: 3.2 (basic static radial load
rating: the load at which the contact pressure at the centre of the most heavily
loaded contact is 4200 MPa for radial ball bearings other than self-aligning), 3.6
(static safety factor ``s_0 = C_0/P_0``), 6.1.1 eq. (1) and Table 1 (``C_0r``, ``f_0``),
6.2 eq. (2) and (3) and Table 2 (``P_0r``, ``X_0``, ``Y_0``). The clause and table
numbers were written from the standard's structure as we know it; the standard's text
was not at hand. Check them against your copy before citing.

Groove radii above the table's
------------------------------
Table 1's ``f_0`` holds for raceway groove radii ``r_i ≤ 0.52·D_w`` (inner ring) and
``r_e ≤ 0.53·D_w`` (outer ring). A more open groove carries less at the same peak
pressure, and ISO 76 asks for a correspondingly reduced ``f_0`` (ISO/TR 10657 explains the
derivation; its text was not at hand). The reduction here follows from the rating's own
definition (3.2: the load at which the peak pressure of the most heavily loaded contact
is 4200 MPa): ``f_0`` is scaled by the ratio of the ball load that reaches 4200 MPa at the
bearing's own groove radii to the one at 0.52/0.53 (Hertz, the smaller of the two
raceways), the same derivation the table itself reproduces within 0.5 %
(tests/core/test_static_rating.py). A smaller radius is not credited (taken at the
limit). Every output says which basis it used (:func:`static_rating_basis`).
"""
from __future__ import annotations

import math

import numpy as np

from ..hertz import effective_modulus, race_contact
from .iso281 import LifeError, rating_geometry

#: Contact pressure at the centre of the most heavily loaded ball–raceway contact under
#: the basic static load rating, radial ball bearings other than self-aligning [Pa]
#: (ISO 76:2006 3.2).
ISO76_BALL_PRESSURE = 4200e6

#: Exponent of the load–pressure relation of a Hertz point contact, ``p_max ∝ Q^(1/3)``:
#: a load ratio is the cube of the pressure ratio.
PRESSURE_LOAD_EXPONENT = 3.0

#: ``γ = D_w·cos α / D_pw`` rows of ISO 76:2006 Table 1 [-].
F0_GAMMA = np.round(np.arange(0.0, 0.405, 0.01), 2)
#: ``f_0`` of ISO 76:2006 Table 1, column "radial and angular contact groove ball
#: bearings" [N mm^-2 in the standard's units].
#: Source: ISO 76:2006 Table 1, as an open implementation of ISO 76 reproduces it (a
#: JavaScript ``sfereRadiali`` function in a public GitHub repository, found by content;
#: it has 15.7 at γ = 0.06, a typing slip for the 15.9 kept here). Every value was checked
#: against the theory the table comes from (ISO/TR 10657): the ball load at which the Hertz
#: peak pressure reaches 4200 MPa (E = 207 GPa, ν = 0.3, f_i = 0.52, f_e = 0.53, the
#: smaller of the two raceways) divided by ``5·D_w²`` (Stribeck's ``Q_max = 5·F_r/(Z cos α)``)
#: matches the table within 0.5 % at every row (tests/core/test_static_rating.py).
F0_RADIAL = np.array([14.7, 14.9, 15.1, 15.3, 15.5, 15.7, 15.9, 16.1, 16.3, 16.5, 16.4,
                      16.1, 15.9, 15.6, 15.4, 15.2, 14.9, 14.7, 14.4, 14.2, 14.0,
                      13.7, 13.5, 13.2, 13.0, 12.8, 12.5, 12.3, 12.1, 11.8, 11.6,
                      11.4, 11.2, 10.9, 10.7, 10.5, 10.3, 10.0, 9.8, 9.6, 9.4])

#: ISO 76:2006 Table 2, radial contact groove ball bearings (α = 0), single and double row:
#: ``X_0 = 0.6``, ``Y_0 = 0.5``. Source: the standard's values as Koyo's technical data
#: reproduce them (koyousa.com, "Calculation of equivalent radial / axial load":
#: deep groove ball bearings ``P_0r = 0.6 F_r + 0.5 F_a``, ``P_0r = F_r`` when smaller) and
#: SKF's deep groove ball bearing pages (``P_0 = 0.6 F_r + 0.5 F_a``, ``P_0 < F_r → P_0 = F_r``).
X0_DEEP, Y0_DEEP = 0.6, 0.5
#: ISO 76:2006 Table 2, angular contact groove ball bearings: α [deg] and single-row
#: ``Y_0`` (``X_0 = 0.5``); double row (back-to-back, face-to-face) ``X_0 = 1`` and twice
#: the single row's ``Y_0``. Sources: 15°, 30°, 40° (0.46, 0.33, 0.26; double row 0.92,
#: 0.66, 0.52) as Koyo's technical data reproduce them (koyousa.com, same page);
#: 15°, 25°, 40° (0.46, 0.38, 0.26; pairs 0.92, 0.76, 0.52) as LYC's technical pages do
#: (lycbearing.com, "Equivalent static load — angular contact ball bearings"; NTN-SNR's
#: e-shop gives the same 30° and 40° rows). 20°, 35°, 45° (0.42, 0.29, 0.22) are the
#: standard's table as we know it; no public reproduction of those rows was at hand.
Y0_ANGULAR = np.array([[15.0, 0.46], [20.0, 0.42], [25.0, 0.38], [30.0, 0.33],
                       [35.0, 0.29], [40.0, 0.26], [45.0, 0.22]])
X0_ANGULAR_SINGLE, X0_ANGULAR_DOUBLE = 0.5, 1.0

#: Largest groove radii, over the ball diameter, for which ISO 76 Table 1 holds
#: (inner ring, outer ring) [-].
F0_TABLE_F_INNER, F0_TABLE_F_OUTER = 0.52, 0.53

#: Young's modulus and Poisson's ratio of the steel ISO 76's table was derived with
#: (ISO/TR 10657) [Pa], [-]; they cancel in the reduction's ratio.
_ISO76_E, _ISO76_NU = 207e9, 0.3


class StaticRatingError(ValueError):
    """ISO 76 gives no rating or factor for this bearing or load (said why)."""


def static_safety_factor_from_pressure(p_max, pressure_limit: float = ISO76_BALL_PRESSURE):
    """ISO 76 static safety factor from the peak Hertz contact pressure.

    Parameters
    ----------
    p_max : float or array_like
        Peak contact pressure of the most heavily loaded ball–raceway contact [Pa]; an
        array gives the factor at each of its values (along a cycle).
    pressure_limit : float
        Contact pressure at the basic static load rating [Pa];
        :data:`ISO76_BALL_PRESSURE` (4200 MPa) for radial ball bearings other than
        self-aligning.

    Returns
    -------
    float or ndarray
        ``s_0`` [1]: inf where ``p_max`` is 0 (no contact carries load), NaN where
        ``p_max`` is NaN.

    Raises
    ------
    StaticRatingError
        A negative pressure.

    Notes
    -----
    ISO 76:2006 3.6 defines ``s_0 = C_0/P_0``; 3.2 sets ``C_0`` as the load at which the
    peak pressure is ``p_0 = 4200 MPa``; 3.4 sets ``P_0`` as the load that gives the same
    peak pressure as the actual loads. A Hertz point contact of fixed geometry has
    ``p_max ∝ Q^(1/3)``, so the load ratio is the cube of the pressure ratio:

    .. math:: s_0 = \\frac{C_0}{P_0} = \\left(\\frac{p_0}{p_{max}}\\right)^3

    This holds exactly where the most heavily loaded contact's geometry (contact angle,
    osculation) does not change between ``P_0`` and ``C_0``; the load distribution of a
    bearing under combined load does change a little with the load's size.
    """
    p = np.asarray(p_max, dtype=float)
    if np.any(p < 0.0):
        raise StaticRatingError(f"p_max = {np.min(p):.6g} Pa is negative: a contact pressure is >= 0")
    if not pressure_limit > 0.0:
        raise StaticRatingError(f"pressure_limit = {pressure_limit!r} Pa must be positive")
    with np.errstate(divide="ignore"):
        s0 = (pressure_limit / p) ** PRESSURE_LOAD_EXPONENT
    return float(s0) if s0.ndim == 0 else s0


def _load_at_pressure(ball_diameter, pitch_diameter, contact_angle, f_inner, f_outer,
                      pressure=ISO76_BALL_PRESSURE) -> float:
    """Ball load [N] at which the more heavily stressed raceway reaches ``pressure``
    (Hertz: ``p_max = 3Q/(2πab)``, ``a, b ∝ Q^(1/3)``, so ``Q = (2π a* b* p/3)^3``)."""
    e_eff = effective_modulus(_ISO76_E, _ISO76_NU)
    loads = []
    for ring, f in (("inner", f_inner), ("outer", f_outer)):
        c = race_contact(ball_diameter, pitch_diameter, f, contact_angle, ring, e_eff)
        loads.append((2.0 * math.pi * c.a_coefficient * c.b_coefficient * pressure / 3.0) ** 3)
    return min(loads)


def f0_osculation_factor(ball_diameter: float, pitch_diameter: float, contact_angle: float,
                         f_inner: float, f_outer: float) -> float:
    """Reduction of ISO 76 Table 1's ``f_0`` for groove radii above 0.52/0.53·D_w [-].

    Parameters
    ----------
    ball_diameter, pitch_diameter : float
        ``D_w``, ``D_pw`` [m].
    contact_angle : float
        Nominal ``α`` [rad].
    f_inner, f_outer : float
        Groove radius over ball diameter, ``r_i/D_w`` and ``r_e/D_w`` [-].

    Returns
    -------
    float
        1 within the table's limits, less than 1 above them.

    Notes
    -----
    From the definition of ``C_0`` (ISO 76 3.2, 4200 MPa at the centre of the most heavily
    loaded contact), with each ring's ``f`` taken no smaller than its limit (a closer
    groove is not credited):

    .. math:: k = \\frac{Q_{4200}(γ, \\max(f_i, 0.52), \\max(f_e, 0.53))}{Q_{4200}(γ, 0.52, 0.53)}

    ``Q_4200`` the smaller of the inner- and outer-raceway ball loads at 4200 MPa (Hertz).
    """
    fi, fe = max(float(f_inner), F0_TABLE_F_INNER), max(float(f_outer), F0_TABLE_F_OUTER)
    if fi == F0_TABLE_F_INNER and fe == F0_TABLE_F_OUTER:
        return 1.0
    actual = _load_at_pressure(ball_diameter, pitch_diameter, contact_angle, fi, fe)
    table = _load_at_pressure(ball_diameter, pitch_diameter, contact_angle, F0_TABLE_F_INNER, F0_TABLE_F_OUTER)
    return actual / table


def static_rating_basis(f_inner: float, f_outer: float) -> str:
    """One line: which ``f_0`` the catalogue ``C_0r`` took, for every output to repeat."""
    if f_inner <= F0_TABLE_F_INNER and f_outer <= F0_TABLE_F_OUTER:
        return "ISO 76 Table 1 f0 (groove radii within 0.52/0.53 Dw)"
    return (f"ISO 76 Table 1 f0 reduced for groove radii {f_inner:.4g}/{f_outer:.4g} Dw above 0.52/0.53 Dw: "
            "scaled by the ball load that reaches 4200 MPa at these radii over that at 0.52/0.53 (Hertz, "
            "the rating's definition, ISO 76 3.2)")


def f0_factor(gamma: float) -> float:
    """``f_0`` of ISO 76:2006 Table 1, linearly interpolated as the standard allows.

    Parameters
    ----------
    gamma : float
        ``D_w·cos α / D_pw`` [-], within the table's 0 … 0.40.

    Returns
    -------
    float
        ``f_0`` [N mm^-2 in the standard's units], radial and angular contact groove ball
        bearings.

    Notes
    -----
    The table holds for raceway groove radii of at most 0.52·D_w (inner ring) and
    0.53·D_w (outer ring); ISO 76 asks for a correspondingly smaller ``f_0`` where the
    grooves are more open: :func:`static_load_rating` applies
    :func:`f0_osculation_factor`.
    """
    if not F0_GAMMA[0] <= gamma <= F0_GAMMA[-1]:
        raise StaticRatingError(f"D_w cos(alpha)/D_pw = {gamma:.4g} lies outside ISO 76 Table 1 "
                                f"({F0_GAMMA[0]:g} to {F0_GAMMA[-1]:g})")
    return float(np.interp(gamma, F0_GAMMA, F0_RADIAL))


def static_load_factors(contact_angle: float, double_row: bool = False):
    """ISO 76 static radial and axial load factors ``X_0``, ``Y_0``.

    Parameters
    ----------
    contact_angle : float
        Nominal contact angle ``α`` [rad]: 0 (radial contact) or 15° … 45°.
    double_row : bool
        The double-row columns (a back-to-back or face-to-face pair, a four-point row).

    Returns
    -------
    X0, Y0 : float

    Notes
    -----
    ISO 76:2006 Table 2. Between the tabulated angles the values are interpolated
    linearly, as the standard allows. A tandem pair takes the single-row factors.
    """
    a = abs(math.degrees(contact_angle))
    if a < 1e-9:
        return X0_DEEP, Y0_DEEP
    if not Y0_ANGULAR[0, 0] - 1e-9 <= a <= Y0_ANGULAR[-1, 0] + 1e-9:
        raise StaticRatingError(f"ISO 76 Table 2 factors for a nominal contact angle of {a:.4g} deg are not "
                                "carried here (0 and 15 to 45 deg are)")
    y0 = float(np.interp(a, Y0_ANGULAR[:, 0], Y0_ANGULAR[:, 1]))
    if double_row:
        return X0_ANGULAR_DOUBLE, 2.0 * y0
    return X0_ANGULAR_SINGLE, y0


def static_load_rating(ball_diameter: float, pitch_diameter: float, contact_angle: float,
                       ball_count: int, rows: int = 1, f_inner: float = F0_TABLE_F_INNER,
                       f_outer: float = F0_TABLE_F_OUTER) -> float:
    """ISO 76 basic static radial load rating ``C_0r`` of a radial ball bearing [N].

    Parameters
    ----------
    ball_diameter, pitch_diameter, contact_angle, ball_count, rows
        ``D_w`` [m], ``D_pw`` [m], the nominal ``α`` [rad], ``Z`` balls per row and ``i``
        rows (a pair of single-row bearings is ``i = 2``), as
        :func:`rvcore.standards.iso281.basic_dynamic_load_rating` takes them.

    Returns
    -------
    float
        ``C_0r`` [N].

    Notes
    -----
    ISO 76:2006 6.1.1, eq. (1), ``D_w`` in mm:

    .. math:: C_{0r} = f_0\\, i\\, Z\\, D_w^2 \\cos α

    with ``f_0(γ)`` from Table 1 (:func:`f0_factor`), ``γ = D_w cos α / D_pw``, times
    :func:`f0_osculation_factor` where the grooves are more open than 0.52/0.53·D_w.
    """
    if not (ball_diameter > 0 and pitch_diameter > ball_diameter and ball_count >= 1 and rows >= 1):
        raise StaticRatingError(f"no static load rating for D_w = {ball_diameter!r} m, D_pw = {pitch_diameter!r} m, "
                                f"Z = {ball_count!r}, i = {rows!r}: need 0 < D_w < D_pw, Z >= 1, i >= 1")
    cos_a = math.cos(contact_angle)
    f0 = f0_factor(ball_diameter * cos_a / pitch_diameter)
    f0 *= f0_osculation_factor(ball_diameter, pitch_diameter, contact_angle, f_inner, f_outer)
    return f0 * rows * ball_count * (ball_diameter * 1e3) ** 2 * cos_a


def static_equivalent_load(radial_load: float, axial_load: float, contact_angle: float,
                           double_row: bool = False) -> float:
    """ISO 76 static equivalent radial load ``P_0r`` [N].

    Parameters
    ----------
    radial_load, axial_load : float
        ``F_r``, ``F_a`` [N] (signs do not matter).
    contact_angle : float
        Nominal contact angle ``α`` [rad].
    double_row : bool
        The double-row factors of Table 2.

    Returns
    -------
    float
        ``P_0r`` [N].

    Notes
    -----
    ISO 76:2006 6.2, eq. (2) and (3), with ``X_0``, ``Y_0`` of Table 2
    (:func:`static_load_factors`):

    .. math:: P_{0r} = \\max(X_0 F_r + Y_0 F_a,\\; F_r)

    (the standard's "if ``P_0r < F_r``, take ``P_0r = F_r``").
    """
    fr, fa = abs(float(radial_load)), abs(float(axial_load))
    x0, y0 = static_load_factors(contact_angle, double_row)
    return max(x0 * fr + y0 * fa, fr)


def bearing_static_load_rating(bearing) -> float:
    """ISO 76 ``C_0r`` of a :class:`rvcore.bearing.geometry.Bearing` from its geometry [N]
    (:func:`static_load_rating` with :func:`rvcore.standards.iso281.rating_geometry`'s ``i``, ``Z``,
    ``D_w``, ``D_pw``, ``α``)."""

    try:
        g = rating_geometry(bearing)
    except LifeError as exc:
        raise StaticRatingError(str(exc)) from None
    return static_load_rating(g["ball_diameter"], g["pitch_diameter"], g["contact_angle"],
                              g["ball_count"], g["rows"], g["f_inner"], g["f_outer"])


def static_safety_factor(bearing, radial_load: float, axial_load: float) -> dict:
    """ISO 76 static safety factor of the bearing by the catalogue route, ``C_0r/P_0r``.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    radial_load, axial_load : float
        ``F_r``, ``F_a`` [N] on the whole bearing.

    Returns
    -------
    dict
        ``static_load_rating_N`` (``C_0r``), ``static_equivalent_load_N`` (``P_0r``) and
        ``static_safety_factor`` (``s_0``, inf when nothing loads the bearing) and
        ``rating_basis`` (one line: Table 1's ``f_0`` or the reduced one,
        :func:`static_rating_basis`).

    Notes
    -----
    ISO 76:2006 3.6: ``s_0 = C_0r/P_0r`` (:func:`bearing_static_load_rating`,
    :func:`static_equivalent_load`). Table 2's double-row factors apply to back-to-back
    and face-to-face pairs and four-point rows (``rating_geometry``'s ``double_row``).
    ISO 76 has no term for a tilting moment; the pressure route
    (:func:`static_safety_factor_from_pressure`) includes it through the load
    distribution.
    """
    g = rating_geometry(bearing)
    c0 = bearing_static_load_rating(bearing)
    p0 = static_equivalent_load(radial_load, axial_load, g["contact_angle"], g["double_row"])
    return {"static_load_rating_N": c0, "static_equivalent_load_N": p0,
            "static_safety_factor": math.inf if p0 == 0.0 else c0 / p0,
            "rating_basis": static_rating_basis(g["f_inner"], g["f_outer"])}
