"""Where an imperfect raceway is: the radial and axial shift of a groove at a contact's angle, and
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
from ..bearing.layout import (R_AX_I_X, R_AX_I_Y, R_AX_O_X, R_AX_O_Y, R_AXWAVE0, R_ECC_I_X, R_ECC_I_Y, R_ECC_O_X,
                              R_ECC_O_Y, R_IMPERFECT, R_NAXWAVE_I, R_NAXWAVE_O, R_NWAVE_I, R_NWAVE_O, R_WAVE0)
from ..profile import CH_SPEED, channel_integral


@kernel(inline=True)
def _harmonic_shift(rows, r, cx, cy, cn, c0, ux, uy):
    """``s(φ) = v⃗·u + Σ_k A_k·cos(k·φ + φ_k)`` of row ``r`` at the unit direction ``(ux, uy)``
    and its slope ``ds/dφ`` [m]: the first-order term as the vector ``v⃗`` in columns
    ``cx, cy`` (its slope ``u × v⃗``), ``rows[r, cn]`` harmonics (order, amplitude, phase) from
    column ``c0``."""
    vx, vy, n = rows[r, cx], rows[r, cy], int(rows[r, cn])
    shift = ux * vx + uy * vy
    slope = ux * vy - uy * vx
    if n > 0:
        phi = math.atan2(uy, ux)
        for k in range(n):
            c = c0 + 3 * k
            order, amplitude, arg = rows[r, c], rows[r, c + 1], rows[r, c] * phi + rows[r, c + 2]
            shift += amplitude * math.cos(arg)
            slope -= order * amplitude * math.sin(arg)
    return shift, slope


@kernel(inline=True)
def raceway_offset(rows, r, outer, ux, uy):
    """Radial and axial shift of row ``r``'s inner (``outer`` False) or outer raceway [m] at
    the unit direction ``(ux, uy)`` given in that ring's own frame, with their slopes along
    the ring: ``(Δr, dΔr/dφ, Δz, dΔz/dφ)`` [m].

    Notes
    -----
    ``Δr(φ) = e·cos(φ − φ_e) + Σ_k A_k·cos(k·φ + φ_k)`` with ``φ`` the direction's angle:
    the eccentricity as ``u·e⃗`` (its vector stored, no angle needed), its slope as
    ``u × e⃗``; the waviness terms from ``φ``. The axial runout likewise,
    ``Δz(φ) = a·cos(φ − φ_a) + Σ_k B_k·cos(k·φ + ψ_k)`` (:mod:`rvcore.bearing.imperfections`).
    The slopes turn the contact normal out of the meridian plane
    (:func:`rvcore.contact.laws.race_arc_penetration`).
    """
    m = MAX_WAVINESS_TERMS if outer else 0
    if outer:
        dr, slope = _harmonic_shift(rows, r, R_ECC_O_X, R_ECC_O_Y, R_NWAVE_O, R_WAVE0 + 3 * m, ux, uy)
        dz, zslope = _harmonic_shift(rows, r, R_AX_O_X, R_AX_O_Y, R_NAXWAVE_O, R_AXWAVE0 + 3 * m, ux, uy)
    else:
        dr, slope = _harmonic_shift(rows, r, R_ECC_I_X, R_ECC_I_Y, R_NWAVE_I, R_WAVE0, ux, uy)
        dz, zslope = _harmonic_shift(rows, r, R_AX_I_X, R_AX_I_Y, R_NAXWAVE_I, R_AXWAVE0, ux, uy)
    return dr, slope, dz, zslope


@kernel(inline=True)
def ball_offsets(rows, r, pockets, j, plx, ply, inv_rho_l, cos_spin, sin_spin, erx, ery):
    """``(Δr_inner, Δr_outer, ΔD/2, dΔr_inner/dφ, dΔr_outer/dφ, Δz_inner, Δz_outer,
    dΔz_inner/dφ, dΔz_outer/dφ)`` of ball ``j`` (global index) of row ``r`` [m].

    ``(plx, ply)·inv_rho_l`` is the ball's direction in the inner ring's (tilted) frame,
    which the prescribed spin has turned by ``spin`` (its cosine and sine given);
    ``(erx, ery)`` its direction in the fixed frame, the outer ring's.
    """
    exl, eyl = plx * inv_rho_l, ply * inv_rho_l
    ux = cos_spin * exl + sin_spin * eyl
    uy = cos_spin * eyl - sin_spin * exl
    dr_i, slope_i, dz_i, zslope_i = raceway_offset(rows, r, False, ux, uy)
    dr_o, slope_o, dz_o, zslope_o = raceway_offset(rows, r, True, erx, ery)
    return dr_i, dr_o, 0.5 * pockets[j, 2], slope_i, slope_o, dz_i, dz_o, zslope_i, zslope_o


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
