"""Pairs of rows and their axial preload, SI in and SI out.

A pair is two rows of the same design on one inner ring, at ``z = ∓s/2`` for a row
spacing ``s``, with mirrored contact angles:

- back-to-back (O, DB): the lines of contact meet the axis *outside* the rows, which
  spreads the pair's pressure centres and makes it stiff in tilt;
- face-to-face (X, DF): the lines meet the axis between the rows;
- tandem (DT): both rows carry axial load the same way (no preload possible).

With the conventions of :mod:`rvcore.bearing.geometry` (an outer arc at ``α`` touches the ball
along ``(cos α, sin α)`` in (r, z)), the line of contact of a row at ``z_r`` with angle
``α`` meets the axis at ``z_r − (d_m/2)·tan α``. Back-to-back therefore puts ``+|α|`` on
the row at ``−s/2`` and ``−|α|`` on the row at ``+s/2``; face-to-face the opposite.

Preload
-------
A row with ``α > 0`` is loaded when the inner ring moves towards ``+z`` against the outer.
Offsetting each row's inner raceway by ``sign(α)·δ₀/2`` therefore presses both rows of a
back-to-back or face-to-face pair together, the way a ground spacer or a clamped pair of
split inner rings does: ``δ₀`` is the pair's *preload offset* (the axial interference of
the rings). The *preload* ``F_p`` is the axial force each row then carries with no
external load; :func:`offset_for_preload` finds the ``δ₀`` that gives a requested
``F_p`` from the statics (Hertz at every contact, balls in equilibrium).
"""
from __future__ import annotations

import dataclasses
import math

from scipy import optimize

from ..bearing.geometry import Arc, Bearing, Row
from .equilibrium import solve_statics

#: The arrangements of a pair; the sign of the contact angle of the row at −s/2.
ARRANGEMENTS = {"back-to-back": 1.0, "face-to-face": -1.0, "tandem": 1.0}


def _with_angle(arcs: tuple, sign: float) -> tuple:
    return tuple(Arc(a.curvature_ratio, sign * abs(a.contact_angle)) for a in arcs)


def mirrored_rows(row: Row, arrangement: str, row_spacing: float) -> tuple:
    """The two rows of a pair built from one row design.

    Parameters
    ----------
    row : Row
        The row design; its axial position and contact-angle sign are replaced.
    arrangement : str
        A key of :data:`ARRANGEMENTS`.
    row_spacing : float
        Axial distance between the rows' centre planes [m].

    Returns
    -------
    (Row, Row)
        The rows at ``−s/2`` and ``+s/2``.
    """
    if arrangement not in ARRANGEMENTS:
        raise ValueError(f"arrangement {arrangement!r} is not one of {', '.join(ARRANGEMENTS)}")
    if len(row.inner_arcs) != 1 or len(row.outer_arcs) != 1:
        raise ValueError("a pair's rows are angular-contact rows: one arc per ring")
    first = ARRANGEMENTS[arrangement]
    second = first if arrangement == "tandem" else -first
    out = []
    for z, sign in ((-row_spacing / 2.0, first), (row_spacing / 2.0, second)):
        out.append(dataclasses.replace(row, axial_position=z, inner_arcs=_with_angle(row.inner_arcs, sign),
                                       outer_arcs=_with_angle(row.outer_arcs, sign), inner_offset=0.0))
    return tuple(out)


def with_offset(bearing: Bearing, offset: float) -> Bearing:
    """``bearing`` with its rows' inner raceways offset by ``sign(α)·offset/2`` [m]."""
    rows = tuple(dataclasses.replace(r, inner_offset=math.copysign(offset / 2.0, r.nominal_contact_angle))
                 for r in bearing.rows)
    return dataclasses.replace(bearing, rows=rows, preload_offset=offset)


def _check_pair(bearing: Bearing) -> None:
    if len(bearing.rows) != 2:
        raise ValueError(f"only a pair of rows can be preloaded axially; this bearing has "
                         f"{len(bearing.rows)} row(s) (a single row is preloaded by a negative "
                         "radial clearance)")
    a0, a1 = (r.nominal_contact_angle for r in bearing.rows)
    if a0 == 0.0 or a1 == 0.0 or (a0 > 0) == (a1 > 0):
        raise ValueError("an axial preload needs two rows whose contact angles are mirrored "
                         "(back-to-back or face-to-face); a tandem pair's rows would both move "
                         "the same way and carry no preload")


def preload_force(bearing: Bearing) -> float:
    """Axial force each row carries with no external load and no gravity [N].

    The mean over the two rows of a pair (they are equal at equilibrium: the ring is
    free); 0 for any bearing that is not a pair.
    """
    if len(bearing.rows) != 2:
        return 0.0
    st = solve_statics(bearing, gravity=False, stiffness=False)
    return float(st.row_axial_loads.mean())


def offset_for_preload(bearing: Bearing, preload: float) -> float:
    """The pair's preload offset ``δ₀`` [m] that makes each row carry ``preload`` [N].

    Notes
    -----
    ``F_p(δ₀)`` rises monotonically (for equal rows at angle α, close to
    ``Q·sin α·Z`` with ``Q = K·(δ₀/2·sin α)^1.5``); the root is bracketed by doubling from
    1 µm and found by Brent's method to 1e-6 relative in force.
    """
    _check_pair(bearing)
    if preload <= 0.0:
        return 0.0

    def excess(offset):
        return preload_force(with_offset(bearing, offset)) / preload - 1.0

    hi = 1e-6
    while excess(hi) < 0.0:
        hi *= 2.0
        if hi > bearing.rows[0].ball_diameter:
            raise ValueError(f"no offset below a ball diameter gives a preload of {preload:g} N")
    return optimize.brentq(excess, 0.0, hi, rtol=1e-12, xtol=1e-15, maxiter=200)


def apply_preload(bearing: Bearing) -> Bearing:
    """``bearing`` with the inner raceways of its pair offset to give its preload.

    ``bearing.preload`` [N] > 0 asks for a force, whose offset is solved for;
    ``bearing.preload_offset`` [m] ≠ 0 gives the offset directly. A bearing with neither
    is returned unchanged.
    """
    if bearing.preload > 0.0:   # the force rules; an offset already there was solved from it
        return with_offset(bearing, offset_for_preload(bearing, bearing.preload))
    if bearing.preload_offset != 0.0:
        _check_pair(bearing)
        return with_offset(bearing, bearing.preload_offset)
    return bearing
