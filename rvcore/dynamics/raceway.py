"""Where an imperfect raceway is: the radial shift of a groove at a contact's angle, and
the angle the inner ring's raceway has turned through (:func:`spin_of`).

The one place an imperfection enters the contact geometry (docs/model.md §12,
:mod:`rvcore.bearing.imperfections`): the right-hand side, the potential energy and the statics
all take the shift from :func:`raceway_offset` and hand it to
:func:`rvcore.contact.laws.race_arc_penetration`.
"""
from __future__ import annotations

import math

from .._numba import kernel

from ..bearing.imperfections import MAX_WAVINESS_TERMS
from ..bearing.layout import R_ECC_I_X, R_ECC_I_Y, R_ECC_O_X, R_ECC_O_Y, R_IMPERFECT, R_NWAVE_I, R_NWAVE_O, R_WAVE0
from ..profile import CH_SPEED, channel_integral


@kernel(inline=True)
def raceway_offset(rows, r, outer, ux, uy):
    """Radial shift of row ``r``'s inner (``outer`` False) or outer raceway [m] at the unit
    direction ``(ux, uy)`` given in that ring's own frame, and its slope ``dΔr/dφ`` [m].

    Notes
    -----
    ``Δr(φ) = e·cos(φ − φ_e) + Σ_k A_k·cos(k·φ + φ_k)`` with ``φ`` the direction's angle:
    the eccentricity as ``u·e⃗`` (its vector stored, no angle needed), its slope as
    ``u × e⃗``; the waviness terms from ``φ``. The slope turns the contact normal out of
    the meridian plane (:func:`rvcore.contact.laws.race_arc_penetration`).
    """
    if outer:
        ex, ey, n, c0 = rows[r, R_ECC_O_X], rows[r, R_ECC_O_Y], int(rows[r, R_NWAVE_O]), R_WAVE0 + 3 * MAX_WAVINESS_TERMS
    else:
        ex, ey, n, c0 = rows[r, R_ECC_I_X], rows[r, R_ECC_I_Y], int(rows[r, R_NWAVE_I]), R_WAVE0
    dr = ux * ex + uy * ey
    slope = ux * ey - uy * ex
    if n > 0:
        phi = math.atan2(uy, ux)
        for k in range(n):
            c = c0 + 3 * k
            order, amplitude, arg = rows[r, c], rows[r, c + 1], rows[r, c] * phi + rows[r, c + 2]
            dr += amplitude * math.cos(arg)
            slope -= order * amplitude * math.sin(arg)
    return dr, slope


@kernel(inline=True)
def ball_offsets(rows, r, pockets, j, plx, ply, inv_rho_l, cos_spin, sin_spin, erx, ery):
    """``(Δr_inner, Δr_outer, ΔD/2, dΔr_inner/dφ, dΔr_outer/dφ)`` of ball ``j`` (global
    index) of row ``r`` [m].

    ``(plx, ply)·inv_rho_l`` is the ball's direction in the inner ring's (tilted) frame,
    which the prescribed spin has turned by ``spin`` (its cosine and sine given);
    ``(erx, ery)`` its direction in the fixed frame, the outer ring's.
    """
    exl, eyl = plx * inv_rho_l, ply * inv_rho_l
    ux = cos_spin * exl + sin_spin * eyl
    uy = cos_spin * eyl - sin_spin * exl
    dr_i, slope_i = raceway_offset(rows, r, False, ux, uy)
    dr_o, slope_o = raceway_offset(rows, r, True, erx, ery)
    return dr_i, dr_o, 0.5 * pockets[j, 2], slope_i, slope_o


@kernel(inline=True)
def spin_of(rows, table, meta, t):
    """Cosine and sine of the angle the inner ring has turned through by ``t`` (the
    integral of the prescribed speed), which an imperfect inner raceway turns with;
    (1, 0) when every row is perfect, which needs no angle."""
    for r in range(rows.shape[0]):
        if rows[r, R_IMPERFECT] != 0.0:
            spin = channel_integral(table, meta, CH_SPEED, t)
            return math.cos(spin), math.sin(spin)
    return 1.0, 0.0
