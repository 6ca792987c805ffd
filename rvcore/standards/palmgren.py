"""Palmgren's estimate of a ball bearing's friction moment: a load term and a viscous
term. SI in and out; the source's formulas are written in its own units (N, mm, rpm,
mm²/s → N mm), converted inside.

What is computed
----------------
``M = M_l + M_v``: the load-dependent moment ``M_l = f_1·F_β·d_m`` (elastic hysteresis
and micro-slip in the loaded contacts, lumped) and the viscous moment ``M_v`` of the
lubricant, which rises with speed and viscosity as ``(ν·n)^(2/3)``.

This is not the moment the project's dynamics compute. The model's drive torque is the
torque of its contact friction law alone (Coulomb–Stribeck sliding in the ball–race,
ball–pocket and cage–land contacts, docs/model.md §4): it has no lubricant drag, no EHL
rolling resistance, no differential slip across the contact ellipse and no seals. This
estimate is an empirical fit over bearings in service, and it leaves out seals too.

Source
------
A. Palmgren, *Ball and Roller Bearing Engineering*, 3rd ed., Burbank, Philadelphia, 1959;
as T. A. Harris and M. N. Kotzalas, *Rolling Bearing Analysis* (5th ed., 2007; in
*Essential Concepts of Bearing Technology*, the chapter on friction in rolling bearings)
give it, with the tables of ``f_0`` (bearing type and lubrication), of ``z`` and ``y`` in
``f_1`` and of ``F_β``. The tables below were typed from that book's tables as we know
them; a public reproduction of them was not found to check against. Check them against
your copy before citing.

Which rows are used (issue 39, item 16)
---------------------------------------
- deep groove (α = 0): ``z`` = 0.0005, the middle of the table's 0.0004 … 0.0006 (light …
  heavy series), ``y`` = 0.55; ``F_β = 3 F_a − 0.1 F_r``; ``f_0`` the top of the grease
  range (2), or the table's oil value.
- angular contact (α > 0): the table's one angular-contact row, which Harris & Kotzalas
  give for contact angles of 30–40° (``z`` = 0.001, ``y`` = 0.33,
  ``F_β = 0.9 F_a cot α − 0.1 F_r``, grease ``f_0`` = 2), applied at whatever α the
  bearing has, the study bearing's 15° included. No published row for 15° was at hand,
  so none is invented; the constants are unchanged, and every output says so
  (:data:`PALMGREN_BASIS`, :func:`palmgren_basis`).

How far other published sets differ (:data:`PUBLISHED_SPREAD`): at 30 kN radial + 10 kN
axial and 660 °/s on the study bearing, issue 39's audit found 5.2 N m (KRW), 6.0 N m
(Timken) and 6.1–10.1 N m (Koyo) where this estimate gives 7.8 N m: −33 % … +29 %
(about ±35 %). Read the moment as that uncertain.

The ``f_1`` takes ISO 76's ``C_0`` (:func:`rvcore.standards.iso76.bearing_static_load_rating`),
so where the grooves are more open than 0.52/0.53·D_w it takes the reduced ``C_0`` of
:func:`rvcore.standards.iso76.f0_osculation_factor`: ``P_0/C_0`` is larger and so is
``f_1`` (by ``k^-y``, ``k`` the reduction).
"""
from __future__ import annotations

import math

from .iso281 import rating_geometry
from .iso76 import bearing_static_load_rating, static_equivalent_load

#: ``f_1 = z·(P_0/C_0)^y`` of the load term: bearing type -> (z smallest, z largest, y).
#: Source: Harris & Kotzalas, table of ``z`` and ``y`` for the load-dependent friction
#: moment (Palmgren 1959). Deep groove: z = 0.0004 … 0.0006 (light … heavy series),
#: y = 0.55; angular contact, single row: z = 0.001, y = 0.33. ``P_0`` and ``C_0`` are
#: ISO 76's static equivalent load and static load rating.
F1_TABLE = {"deep-groove": (0.0004, 0.0006, 0.55), "angular-contact": (0.001, 0.001, 0.33)}

#: ``f_0`` of the viscous term: bearing type -> lubrication -> f_0 (a range as (lo, hi)).
#: Source: Harris & Kotzalas, table of ``f_0`` versus bearing type and method of
#: lubrication (Palmgren 1959). "oil-jet" stands for the book's "oil bath, vertical shaft,
#: or oil jet".
F0_TABLE = {
    "deep-groove": {"grease": (0.7, 2.0), "oil-mist": (1.0, 1.0), "oil-bath": (2.0, 2.0), "oil-jet": (4.0, 4.0)},
    "angular-contact": {"grease": (2.0, 2.0), "oil-mist": (1.7, 1.7), "oil-bath": (3.3, 3.3),
                        "oil-jet": (6.6, 6.6)},
}

#: Which source and rows the estimate takes, in one line for every output to repeat.
PALMGREN_BASIS = {
    "deep-groove": ("Palmgren (1959) as Harris & Kotzalas tabulate it, deep-groove row: z = 0.0005 (middle of "
                    "0.0004-0.0006), y = 0.55, F_beta = 3 F_a - 0.1 F_r, f0 grease 2 (top of 0.7-2)"),
    "angular-contact": ("Palmgren (1959) as Harris & Kotzalas tabulate it, angular-contact row for 30-40 deg "
                        "applied at this bearing's angle (no published row for smaller angles used): z = 0.001, "
                        "y = 0.33, F_beta = 0.9 F_a cot(alpha) - 0.1 F_r, f0 grease 2"),
}

#: The spread of other published friction-moment estimates, as issue 39's audit found it
#: for the study bearing at 30 kN radial + 10 kN axial and 660 °/s [N m]: source -> (lo, hi),
#: and this estimate's value there.
PUBLISHED_SPREAD = {"KRW": (5.2, 5.2), "Timken": (6.0, 6.0), "Koyo": (6.1, 10.1)}
PUBLISHED_SPREAD_OURS = 7.8

#: Methods of lubrication the ``f_0`` table carries.
LUBRICATIONS = ("grease", "oil-mist", "oil-bath", "oil-jet")

#: ``ν·n`` [mm²/s · rpm] below which the viscous moment no longer falls with speed
#: (Palmgren: ``M_v = 160·10^-7·f_0·d_m³`` there).
VISCOUS_THRESHOLD = 2000.0


def palmgren_basis(contact_angle: float) -> str:
    """One line: the source and row of Palmgren's constants for a bearing of nominal
    contact angle ``contact_angle`` [rad] (:data:`PALMGREN_BASIS`)."""
    return PALMGREN_BASIS["deep-groove" if abs(contact_angle) < 1e-9 else "angular-contact"]


def published_spread_text() -> str:
    """One line: the spread of other published sets (:data:`PUBLISHED_SPREAD`)."""
    lo = min(v[0] for v in PUBLISHED_SPREAD.values())
    hi = max(v[1] for v in PUBLISHED_SPREAD.values())
    ours = PUBLISHED_SPREAD_OURS
    sets = ", ".join(f"{k} {a:g} N m" if a == b else f"{k} {a:g}-{b:g} N m" for k, (a, b) in PUBLISHED_SPREAD.items())
    return (f"other published sets give {sets} where this estimate gives {ours:g} N m (study bearing, 30 kN + "
            f"10 kN, 660 °/s; issue 39's audit): {100 * (lo / ours - 1):+.0f} % to {100 * (hi / ours - 1):+.0f} %")


class FrictionMomentError(ValueError):
    """The estimate has no factor for this bearing, or an input is out of range (said why)."""


def _type(contact_angle: float) -> str:
    return "deep-groove" if abs(contact_angle) < 1e-9 else "angular-contact"


def _nonnegative(name, value, unit):
    v = float(value)
    if not (math.isfinite(v) and v >= 0.0):
        raise FrictionMomentError(f"{name} = {value!r} {unit} must be a finite number >= 0")
    return v


def load_friction_force(radial_load: float, axial_load: float, contact_angle: float) -> float:
    """Palmgren's load ``F_β`` of the load term [N].

    Parameters
    ----------
    radial_load, axial_load : float
        ``F_r``, ``F_a`` [N] (signs do not matter).
    contact_angle : float
        Nominal contact angle ``α`` [rad]; 0 is a deep-groove bearing.

    Returns
    -------
    float
        ``F_β`` [N].

    Notes
    -----
    Harris & Kotzalas's table of ``F_β`` (Palmgren 1959), never less than ``F_r``:

    - deep groove: :math:`F_β = 3 F_a − 0.1 F_r`;
    - angular contact, single row: :math:`F_β = 0.9 F_a \\cot α − 0.1 F_r`.
    """
    fr, fa = abs(float(radial_load)), abs(float(axial_load))
    if _type(contact_angle) == "deep-groove":
        f_beta = 3.0 * fa - 0.1 * fr
    else:
        f_beta = 0.9 * fa / math.tan(abs(contact_angle)) - 0.1 * fr
    return max(f_beta, fr)


def load_friction_factor(static_equivalent_load: float, static_load_rating: float,
                         contact_angle: float, z: float | None = None) -> float:
    """``f_1 = z·(P_0/C_0)^y`` [-] of the load term.

    Parameters
    ----------
    static_equivalent_load, static_load_rating : float
        ISO 76 ``P_0`` and ``C_0`` [N] (:mod:`rvcore.standards.iso76`).
    contact_angle : float
        Nominal contact angle ``α`` [rad]; 0 is a deep-groove bearing.
    z : float, optional
        ``z`` of the table; by default the middle of its range (deep groove: 0.0005).

    Returns
    -------
    float
        ``f_1`` [-].

    Notes
    -----
    Harris & Kotzalas's table of ``z`` and ``y`` (:data:`F1_TABLE`).
    """
    lo, hi, y = F1_TABLE[_type(contact_angle)]
    z = 0.5 * (lo + hi) if z is None else float(z)
    p0 = _nonnegative("P_0", static_equivalent_load, "N")
    if not static_load_rating > 0.0:
        raise FrictionMomentError(f"C_0 = {static_load_rating!r} N must be positive")
    return z * (p0 / static_load_rating) ** y


def load_friction_moment(radial_load: float, axial_load: float, contact_angle: float, pitch_diameter: float,
                         static_equivalent_load: float, static_load_rating: float,
                         z: float | None = None) -> float:
    """Palmgren's load-dependent friction moment ``M_l = f_1·F_β·d_m`` [N m].

    Parameters
    ----------
    radial_load, axial_load : float
        ``F_r``, ``F_a`` [N].
    contact_angle : float
        Nominal contact angle ``α`` [rad].
    pitch_diameter : float
        ``d_m`` [m].
    static_equivalent_load, static_load_rating : float
        ISO 76 ``P_0``, ``C_0`` [N].
    z : float, optional
        See :func:`load_friction_factor`.

    Returns
    -------
    float
        ``M_l`` [N m].

    Notes
    -----
    .. math:: M_l = f_1 F_β d_m, \\qquad f_1 = z (P_0/C_0)^y

    (:func:`load_friction_factor`, :func:`load_friction_force`). Independent of speed.
    """
    dm = _nonnegative("d_m", pitch_diameter, "m")
    f1 = load_friction_factor(static_equivalent_load, static_load_rating, contact_angle, z)
    return f1 * load_friction_force(radial_load, axial_load, contact_angle) * dm


def viscous_friction_factor(contact_angle: float, lubrication: str = "grease", f0: float | None = None) -> float:
    """``f_0`` of the viscous term [-] from the table (:data:`F0_TABLE`), or ``f0`` itself.

    A range in the table (deep groove, grease: 0.7 … 2) gives its upper end: the estimate
    then does not understate the moment.
    """
    if f0 is not None:
        return _nonnegative("f_0", f0, "")
    if lubrication not in LUBRICATIONS:
        raise FrictionMomentError(f"lubrication = {lubrication!r} must be one of {', '.join(LUBRICATIONS)}")
    return F0_TABLE[_type(contact_angle)][lubrication][1]


def viscous_friction_moment(kinematic_viscosity: float, speed: float, pitch_diameter: float, f0: float) -> float:
    """Palmgren's viscous friction moment ``M_v`` [N m].

    Parameters
    ----------
    kinematic_viscosity : float
        ``ν`` of the oil (of a grease: its base oil) at the operating temperature [m² s^-1].
    speed : float
        Speed of the rotating ring relative to the other [rad s^-1] (sign ignored).
    pitch_diameter : float
        ``d_m`` [m].
    f0 : float
        ``f_0`` of the bearing type and lubrication (:func:`viscous_friction_factor`).

    Returns
    -------
    float
        ``M_v`` [N m].

    Notes
    -----
    Palmgren, in the source's units (ν in mm²/s, n in rpm, d_m in mm, M in N mm):

    .. math:: M_v = 10^{-7} f_0 (ν n)^{2/3} d_m^3 \\quad (ν n \\ge 2000), \\qquad
              M_v = 160 \\cdot 10^{-7} f_0 d_m^3 \\quad (ν n < 2000)

    The two branches meet at ``ν n = 2000`` (``2000^(2/3) = 158.7 ≈ 160``).
    """
    nu = _nonnegative("kinematic_viscosity", kinematic_viscosity, "m^2/s") * 1e6     # mm²/s
    n = abs(float(speed)) * 60.0 / (2.0 * math.pi)                                    # rpm
    dm = _nonnegative("d_m", pitch_diameter, "m") * 1e3                               # mm
    f0 = _nonnegative("f_0", f0, "")
    if nu * n >= VISCOUS_THRESHOLD:
        m_nmm = 1e-7 * f0 * (nu * n) ** (2.0 / 3.0) * dm ** 3
    else:
        m_nmm = 160e-7 * f0 * dm ** 3
    return m_nmm * 1e-3


def friction_moment(bearing, radial_load: float, axial_load: float, speed: float,
                    kinematic_viscosity: float | None = None, lubrication: str | None = None) -> dict:
    """Palmgren's friction moment of a single-row ball bearing, ``M = M_l + M_v``.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
        One row, deep groove (α = 0) or angular contact.
    radial_load, axial_load : float
        ``F_r``, ``F_a`` [N].
    speed : float
        Inner-ring speed relative to the outer ring [rad s^-1].
    kinematic_viscosity : float, optional
        [m² s^-1]; by default the bearing's ``operating_viscosity``
        (:func:`rvcore.bearing.lubricant.operating_viscosity`: the base oil at the rings'
        operating temperature, or ``lubricant.kinematic_viscosity`` where given).
    lubrication : str, optional
        One of :data:`LUBRICATIONS`; by default the bearing's ``lubricant.method``.

    Returns
    -------
    dict
        ``load_moment_N_m`` (``M_l``), ``viscous_moment_N_m`` (``M_v``),
        ``friction_moment_N_m`` (their sum), ``f1``, ``F_beta_N``, ``f0`` and ``basis``
        (:func:`palmgren_basis`).

    Notes
    -----
    :func:`load_friction_moment` with ISO 76's ``P_0``, ``C_0``
    (:mod:`rvcore.standards.iso76`) and :func:`viscous_friction_moment`, at ``d_m`` the
    pitch diameter. Range of validity (Palmgren's, as Harris & Kotzalas state it and as
    the fit's data were taken): steady running at moderate load and speed, the bearing
    run in, fully flooded lubrication at the operating temperature's viscosity, no
    seals. It does not resolve the contributions the dynamics could (spin, differential
    slip across the contact ellipse, EHL rolling resistance, cage drag); the SKF
    four-component model does, and is not implemented here. A pair or a four-point row
    is not covered: Palmgren's tables are per bearing type, and a pair's two rows carry
    different loads (sum the rows' moments, each with its own loads, with the
    functions above).
    """
    g = rating_geometry(bearing)
    if g["rows"] != 1 or g["four_point"]:
        raise FrictionMomentError(f"Palmgren's estimate here covers single-row deep-groove and angular-contact "
                                  f"bearings; this one has {g['rows']} rows"
                                  f"{' of four-point contact' if g['four_point'] else ''}")
    lub = bearing.lubricant
    nu = kinematic_viscosity if kinematic_viscosity is not None else bearing.operating_viscosity
    method = lubrication if lubrication is not None else lub.method
    alpha, dm = g["contact_angle"], g["pitch_diameter"]
    c0 = bearing_static_load_rating(bearing)
    p0 = static_equivalent_load(radial_load, axial_load, alpha)
    f0 = viscous_friction_factor(alpha, method)
    m_l = load_friction_moment(radial_load, axial_load, alpha, dm, p0, c0)
    m_v = viscous_friction_moment(nu, speed, dm, f0)
    return {"load_moment_N_m": m_l, "viscous_moment_N_m": m_v, "friction_moment_N_m": m_l + m_v,
            "f1": load_friction_factor(p0, c0, alpha), "F_beta_N": load_friction_force(radial_load, axial_load, alpha),
            "f0": f0, "basis": palmgren_basis(alpha)}
