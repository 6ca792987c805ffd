"""ISO 281 catalogue rating of a radial ball bearing: the basic dynamic load rating
``C_r`` from the geometry, the dynamic equivalent load ``P_r = X·F_r + Y·F_a`` and the
basic rating life ``L10 = (C_r/P_r)^3`` [10^6 rev]. SI in and out, except where the
standard's formula is written in its own units (N, mm), said there.

ISO 281:2007, *Rolling bearings — Dynamic load ratings and rating life*, clause 5
(radial ball bearings): 5.1.1 eq. (1) and (2) (``C_r``), Tables 1 and 2 (``b_m``,
``f_c``), 5.1.2 (bearing combinations), 5.2 eq. (3) and Table 3 (``X``, ``Y``, ``e``),
5.3 eq. (4) (``L10``); what the standards read of a bearing (:func:`rating_geometry`: i, Z,
D_w, D_pw, α and the Table 3 columns, 5.1.2). How the clause numbers were checked:
:mod:`rvcore.standards.iso16281`.
"""
from __future__ import annotations

import math

import numpy as np


#: Exponent of the ball bearing's life equation ``L = (C/P)^p`` (ISO 281 5.3 eq. (4)).
LIFE_EXPONENT = 3.0

#: ``e`` of the Weibull dispersion for ball bearings: ring lives combine as
#: ``L = (Σ L_k^(−e))^(−1/e)`` with ``e = 10/9`` (Lundberg–Palmgren; ISO/TS 16281 eq. (29)
#: written with ring lives, ``(Q_c/Q_e)^(−10/3) = L^(−10/9)`` for ``L = (Q_c/Q_e)^3``).
WEIBULL_E = 10.0 / 9.0

#: ``b_m`` of radial ball bearings with raceway grooves (deep-groove and angular-contact),
#: ISO 281:2007 Table 1.
B_M_RADIAL_BALL = 1.3

#: ``γ = D_w·cos α / D_pw`` rows of ISO 281:2007 Table 2 [-].
FC_GAMMA = np.array([0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09, 0.10, 0.12, 0.14, 0.16,
                     0.18, 0.20, 0.22, 0.24, 0.26, 0.28, 0.30, 0.32, 0.34, 0.36, 0.38, 0.40])
#: ``f_c`` of ISO 281:2007 Table 2, column "single-row radial contact groove ball bearings
#: and single- and double-row angular contact groove ball bearings" [N mm^-1.8].
#: Source: ISO 281:2007 Table 2 (the same values as ISO 281:1990). These values were
#: checked against the theory they come from (ISO/TR 1281-1, Lundberg–Palmgren with
#: f_i = f_e = 0.52): their ratio to ``[1 + (1.04·((1−γ)/(1+γ))^1.72)^(10/3)]^(−0.3)·
#: γ^0.3·(1−γ)^1.39/(1+γ)^(1/3)·(2f_i/(2f_i−1))^0.41`` is 38.2 ± 0.05 over the whole table.
FC_SINGLE = np.array([29.1, 35.8, 40.3, 43.8, 46.7, 49.1, 51.1, 52.8, 54.3, 55.5, 57.5, 58.8, 59.6,
                      59.9, 59.9, 59.6, 59.0, 58.2, 57.1, 56.0, 54.6, 53.2, 51.7, 50.0, 48.4])
#: ``f_c`` of ISO 281:2007 Table 2, column "double-row radial contact groove ball
#: bearings" [N mm^-1.8] (0.947 × :data:`FC_SINGLE` throughout, to the table's rounding).
FC_DOUBLE_DEEP = np.array([27.5, 33.9, 38.2, 41.5, 44.2, 46.5, 48.4, 50.0, 51.4, 52.6, 54.5, 55.7,
                           56.5, 56.8, 56.8, 56.5, 55.9, 55.1, 54.1, 53.0, 51.8, 50.4, 48.9, 47.4, 45.8])

#: ISO 281:2007 Table 3, radial contact groove ball bearings (α = 0): columns
#: ``f_0·F_a/C_0r``, ``e``, ``Y`` (for F_a/F_r > e; X = 0.56 there, X = 1, Y = 0 below e).
_XY_DEEP = np.array([
    [0.172, 0.19, 2.30], [0.345, 0.22, 1.99], [0.689, 0.26, 1.71], [1.03, 0.28, 1.55],
    [1.38, 0.30, 1.45], [2.07, 0.34, 1.31], [3.45, 0.38, 1.15], [5.17, 0.42, 1.04], [6.89, 0.44, 1.00]])
_X_DEEP = 0.56
#: ISO 281:2007 Table 3, angular contact groove ball bearings α = 15°: columns
#: ``i·f_0·F_a/C_0r``, ``e``, single-row ``Y`` (F_a/F_r > e, X = 0.44), double-row ``Y``
#: for F_a/F_r ≤ e (X = 1) and for F_a/F_r > e (X = 0.72).
_XY_15 = np.array([
    [0.178, 0.38, 1.47, 1.65, 2.39], [0.357, 0.40, 1.40, 1.57, 2.28], [0.714, 0.43, 1.30, 1.46, 2.11],
    [1.07, 0.46, 1.23, 1.38, 2.00], [1.43, 0.47, 1.19, 1.34, 1.93], [2.14, 0.50, 1.12, 1.26, 1.82],
    [3.57, 0.55, 1.02, 1.14, 1.66], [5.35, 0.56, 1.00, 1.12, 1.63], [7.14, 0.56, 1.00, 1.12, 1.63]])
_X_15_SINGLE, _X_15_DOUBLE = 0.44, 0.72
#: ISO 281:2007 Table 3, angular contact groove ball bearings α = 20° … 45°: α [deg], e,
#: single row X, Y (F_a/F_r > e), double row Y (F_a/F_r ≤ e, X = 1), X, Y (F_a/F_r > e).
_XY_ANGULAR = np.array([
    [20.0, 0.57, 0.43, 1.00, 1.09, 0.70, 1.63],
    [25.0, 0.68, 0.41, 0.87, 0.92, 0.67, 1.41],
    [30.0, 0.80, 0.39, 0.76, 0.78, 0.63, 1.24],
    [35.0, 0.95, 0.37, 0.66, 0.66, 0.60, 1.07],
    [40.0, 1.14, 0.35, 0.57, 0.55, 0.57, 0.93],
    [45.0, 1.34, 0.33, 0.50, 0.47, 0.54, 0.81]])


#: Largest groove radii, over the ball diameter, for which ISO 281 Table 2's ``f_c`` holds
#: (inner ring, outer ring) [-]: radial and angular contact groove ball bearings.
FC_TABLE_F_INNER, FC_TABLE_F_OUTER = 0.52, 0.53


def fc_osculation_problem(f_inner: float, f_outer: float) -> str:
    """Why ISO 281 Table 2's ``f_c`` does not hold at these groove radii ('' where it does).

    Parameters
    ----------
    f_inner, f_outer : float
        ``r_i/D_w``, ``r_e/D_w`` [-].

    Returns
    -------
    str
        One line, empty within ``r_i ≤ 0.52·D_w`` and ``r_e ≤ 0.53·D_w``.

    Notes
    -----
    ISO 281 (5.1.1) gives Table 2 for those radii; above them it asks for a reduced
    ``f_c``, to be calculated as ISO/TR 1281-1 explains. That calculation (Lundberg and
    Palmgren's dependence of ``f_c`` on both osculations) could not be checked against the
    standard's text here, so the project refuses the rating rather than guess it: ``C_r``,
    ``L10`` and ``L10r`` (which ISO/TS 16281 splits from the same ``C_r``) are NaN with
    this reason, unless the bearing file gives the maker's ``dynamic_load_rating``.
    """
    if f_inner <= FC_TABLE_F_INNER and f_outer <= FC_TABLE_F_OUTER:
        return ""
    return (f"ISO 281 C_r, L10 and L10r not rated: groove radii {f_inner:.4g}/{f_outer:.4g} Dw exceed "
            f"Table 2's {FC_TABLE_F_INNER:g}/{FC_TABLE_F_OUTER:g} Dw, where ISO 281 5.1.1 requires a reduced f_c "
            "(ISO/TR 1281-1) that is not implemented; give the maker's dynamic_load_rating in the bearing file")


class LifeError(ValueError):
    """The standards give no rating for this bearing or load (said why)."""


# --------------------------------------------------------------------------- ISO 281


def fc_factor(gamma: float, double_row_deep_groove: bool = False) -> float:
    """``f_c`` of ISO 281:2007 Table 2, linearly interpolated as the standard allows.

    Parameters
    ----------
    gamma : float
        ``D_w·cos α / D_pw`` [-], within the table's 0.01 … 0.40.
    double_row_deep_groove : bool
        Use the double-row radial contact column.

    Returns
    -------
    float
        ``f_c`` [N mm^-1.8 in the standard's units].
    """
    if not FC_GAMMA[0] <= gamma <= FC_GAMMA[-1]:
        raise LifeError(f"D_w cos(alpha)/D_pw = {gamma:.4g} lies outside ISO 281 Table 2 "
                        f"({FC_GAMMA[0]:g} to {FC_GAMMA[-1]:g})")
    return float(np.interp(gamma, FC_GAMMA, FC_DOUBLE_DEEP if double_row_deep_groove else FC_SINGLE))


def basic_dynamic_load_rating(ball_diameter: float, pitch_diameter: float, contact_angle: float,
                              ball_count: int, rows: int = 1, double_row_deep_groove: bool = False) -> float:
    """ISO 281 basic dynamic radial load rating ``C_r`` of a radial ball bearing [N].

    Parameters
    ----------
    ball_diameter : float
        ``D_w`` [m].
    pitch_diameter : float
        ``D_pw`` [m].
    contact_angle : float
        Nominal contact angle ``α`` [rad].
    ball_count : int
        ``Z``, balls per row.
    rows : int
        ``i``, rows of balls (a back-to-back or face-to-face pair, or a tandem pair, is
        rated as ``i = 2``; ISO 281 5.1.2).
    double_row_deep_groove : bool
        ``f_c`` from the double-row radial contact column.

    Returns
    -------
    float
        ``C_r`` [N].

    Notes
    -----
    ISO 281:2007 5.1.1, eq. (1) for ``D_w ≤ 25.4 mm`` and eq. (2) above, ``D_w`` in mm:

    .. math:: C_r = b_m f_c (i \\cos α)^{0.7} Z^{2/3} D_w^{1.8}
    .. math:: C_r = 3.647\\, b_m f_c (i \\cos α)^{0.7} Z^{2/3} D_w^{1.4}

    with ``b_m = 1.3`` (Table 1) and ``f_c(γ)`` from Table 2, ``γ = D_w cos α / D_pw``.
    5.1.2: a pair mounted back-to-back or face-to-face is rated as one double-row
    bearing (``i = 2``); a tandem pair of identical bearings gets ``2^0.7`` times the
    single rating, which is the same formula with ``i = 2``.
    """
    if not (ball_diameter > 0 and pitch_diameter > ball_diameter and ball_count >= 1 and rows >= 1):
        raise LifeError(f"no load rating for D_w = {ball_diameter!r} m, D_pw = {pitch_diameter!r} m, "
                        f"Z = {ball_count!r}, i = {rows!r}: need 0 < D_w < D_pw, Z >= 1, i >= 1")
    cos_a = math.cos(contact_angle)
    gamma = ball_diameter * cos_a / pitch_diameter
    fc = fc_factor(gamma, double_row_deep_groove)
    d_mm = ball_diameter * 1e3
    if d_mm <= 25.4:
        size = d_mm ** 1.8
    else:
        size = 3.647 * d_mm ** 1.4
    return B_M_RADIAL_BALL * fc * (rows * cos_a) ** 0.7 * ball_count ** (2.0 / 3.0) * size


def _interp_rows(table, x):
    """Rows of ``table`` interpolated at ``x`` in its first column (ends held)."""
    return [float(np.interp(x, table[:, 0], table[:, c])) for c in range(1, table.shape[1])]


def xy_factors(radial_load: float, axial_load: float, contact_angle: float, ball_count: int,
               ball_diameter: float, double_row: bool = False, rows: int = 1):
    """ISO 281 radial and axial load factors ``X``, ``Y`` and the limit ``e``.

    Parameters
    ----------
    radial_load, axial_load : float
        ``F_r``, ``F_a`` [N] (the axial load's sign does not matter).
    contact_angle : float
        Nominal contact angle ``α`` [rad]: 0, 15° or 20° … 45°.
    ball_count : int
        ``Z``, balls per row.
    ball_diameter : float
        ``D_w`` [m].
    double_row : bool
        The double-row columns of Table 3 (a back-to-back or face-to-face pair, a
        four-point contact row).
    rows : int
        ``i`` [-].

    Returns
    -------
    X, Y, e : float

    Notes
    -----
    ISO 281:2007 Table 3. For α = 0 and 15° the factors depend on the relative axial load
    ``f_0·F_a/C_0r`` (α = 0) or ``i·f_0·F_a/C_0r`` (α = 15°); with ISO 76's
    ``C_0r = f_0·i·Z·D_w²·cos α`` the factor ``f_0`` cancels:
    ``f_0·F_a/C_0r = F_a/(i·Z·D_w²·cos α)`` [N, mm]. Between the tabulated relative loads
    and between α = 15° and 20°, … 45° the values are interpolated linearly, as the
    standard allows; outside the tabulated relative loads the end values are held.
    Table 3's rows for α = 5° and 10° are not carried here, so 0 < α < 15° and α > 45°
    raise :class:`LifeError`.
    """
    fr, fa = abs(float(radial_load)), abs(float(axial_load))
    a = abs(math.degrees(contact_angle))
    ratio = math.inf if fr == 0.0 else fa / fr
    d_mm = ball_diameter * 1e3
    if a < 1e-9:
        if double_row:
            raise LifeError("ISO 281 Table 3 gives no double-row radial contact factors here "
                            "(rows given one by one at 0 deg)")
        rel = fa / (rows * ball_count * d_mm ** 2)
        e, y = _interp_rows(_XY_DEEP, rel)
        return (1.0, 0.0, e) if ratio <= e else (_X_DEEP, y, e)

    def at15():
        rel = fa / (ball_count * d_mm ** 2 * math.cos(math.radians(15.0)))   # i·f0·Fa/C0r
        e, y1, y2d, y2 = _interp_rows(_XY_15, rel)
        if double_row:
            return (1.0, y2d, e) if ratio <= e else (_X_15_DOUBLE, y2, e)
        return (1.0, 0.0, e) if ratio <= e else (_X_15_SINGLE, y1, e)

    def at_angle(deg):
        e, x1, y1, y2d, x2, y2 = _interp_rows(_XY_ANGULAR, deg)
        if double_row:
            return (1.0, y2d, e) if ratio <= e else (x2, y2, e)
        return (1.0, 0.0, e) if ratio <= e else (x1, y1, e)

    if abs(a - 15.0) < 1e-9:
        return at15()
    if 15.0 < a < 20.0:
        w = (a - 15.0) / 5.0
        lo, hi = at15(), at_angle(20.0)
        return tuple((1 - w) * p + w * q for p, q in zip(lo, hi))
    if 20.0 <= a <= 45.0 + 1e-9:
        return at_angle(min(a, 45.0))
    raise LifeError(f"ISO 281 Table 3 factors for a nominal contact angle of {a:.4g} deg are not "
                    "carried here (0, 15 and 20 to 45 deg are)")


def equivalent_dynamic_load(radial_load: float, axial_load: float, contact_angle: float, ball_count: int,
                            ball_diameter: float, double_row: bool = False, rows: int = 1) -> float:
    """ISO 281 dynamic equivalent radial load ``P_r = X·F_r + Y·F_a`` [N].

    Parameters are those of :func:`xy_factors`.

    Notes
    -----
    ISO 281:2007 5.2, eq. (3), with ``X``, ``Y`` from Table 3 (:func:`xy_factors`).
    """
    x, y, _ = xy_factors(radial_load, axial_load, contact_angle, ball_count, ball_diameter, double_row, rows)
    return x * abs(radial_load) + y * abs(axial_load)


def basic_rating_life(load_rating: float, equivalent_load: float) -> float:
    """ISO 281 basic rating life ``L10 = (C_r/P_r)^3`` [10^6 rev] (5.3 eq. (4)); inf at no load."""
    if equivalent_load <= 0.0:
        return math.inf
    return (load_rating / equivalent_load) ** LIFE_EXPONENT


# --------------------------------------------------------------------------- ISO/TS 16281


def rating_geometry(bearing) -> dict:
    """What the standards need of a :class:`rvcore.bearing.geometry.Bearing`.

    Returns
    -------
    dict
        ``rows`` (i), ``ball_count`` (Z per row), ``ball_diameter`` [m], ``pitch_diameter``
        [m], ``contact_angle`` (nominal |α|) [rad], ``f_inner``, ``f_outer``, ``gamma``,
        ``double_row`` (Table 3's double-row columns), ``four_point``.

    Notes
    -----
    ISO 281 rates rows of one design. A pair (back-to-back, face-to-face, tandem) is
    ``i = 2`` (5.1.2); back-to-back and face-to-face pairs take Table 3's double-row
    factors, a tandem pair the single-row ones. A four-point contact row (two arcs per
    ring at ±α) is rated as one row at its nominal α, with the double-row factors of
    Table 3 (its two arcs carry axial load either way, as a double-row angular contact
    bearing; the bearing makers' catalogues rate four-point bearings so). Rows given one
    by one must share their design; then ``i`` is their number and Table 3's double-row
    factors apply when their angles have opposite signs.
    """
    rows = bearing.rows
    r0 = rows[0]
    key = lambda r: (r.ball_count, r.ball_diameter, r.pitch_diameter, len(r.inner_arcs), len(r.outer_arcs),  # noqa: E731
                     tuple((a.curvature_ratio, abs(a.contact_angle)) for a in r.inner_arcs + r.outer_arcs))
    for r in rows[1:]:
        if key(r) != key(r0):
            raise LifeError("ISO 281 rates rows of one design only: the bearing's rows differ in "
                            "ball count, ball or pitch diameter, curvature or contact angle")
    alpha = abs(r0.nominal_contact_angle)
    four_point = len(r0.inner_arcs) > 1 or len(r0.outer_arcs) > 1
    signs = {math.copysign(1.0, r.nominal_contact_angle) for r in rows if r.nominal_contact_angle != 0.0}
    if bearing.arrangement:
        double = bearing.arrangement in ("back-to-back", "face-to-face")
    else:
        double = len(signs) > 1
    return dict(rows=len(rows), ball_count=r0.ball_count, ball_diameter=r0.ball_diameter,
                pitch_diameter=r0.pitch_diameter, contact_angle=alpha,
                f_inner=r0.inner_arcs[0].curvature_ratio, f_outer=r0.outer_arcs[0].curvature_ratio,
                gamma=r0.ball_diameter * math.cos(alpha) / r0.pitch_diameter,
                double_row=double or four_point, four_point=four_point)
