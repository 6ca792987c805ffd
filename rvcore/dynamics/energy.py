"""Energies of the bearing's state, for the conservation and balance checks of
docs/model.md §9.4. SI throughout."""
from __future__ import annotations

import math

import numpy as np

from .._numba import kernel

from ..contact.laws import cage_pocket_penetration, hertz_energy, land_penetration, race_arc_penetration
from ..contact.pose import ring_rotation, to_ring_frame
from ..bearing.layout import (A_K, BALL_STATES, GUIDE_OUTER_LAND, P_GX, P_GY, P_GZ, P_RING_IT, P_RING_M, R_ARC0, R_BALL0,
                    R_CAGE0, R_CAGE_I, R_CAGE_M, R_CAGE_RI, R_CAGE_RO, R_GUIDE, R_HALF_D, R_IB, R_IMPERFECT,
                    R_LAND_CLEAR, R_LAND_K, R_MB, R_NARC, R_PITCH_R, R_POCKET0, R_POCKET_K, R_POCKET_R, R_Z,
                    R_ZROW)
from ..profile import CH_AXIAL, CH_DIRECTION, CH_MOMENT, CH_RADIAL, channel_value
from .raceway import ball_offsets, spin_of
from .ring_modes import F_INNER_AXIAL, F_INNER_RADIAL, F_OUTER_AXIAL, F_OUTER_RADIAL, flexible, groove, modal_energy


def kinetic_energy_limit(model, resolved, outer_diameter: float) -> float:
    """The kinetic energy a case may not exceed: beyond it the integration has blown up [J].

    Parameters
    ----------
    model : rvcore.bearing.layout.CompiledBearing
        The compiled bearing (its masses and inertias).
    resolved : rvcore.profile.Profile
        The case's profile resolved at its operating point (its peak speed and loads).
    outer_diameter : float
        The bearing's outer diameter [m].

    Notes
    -----
    A hundred times the energy of every body moving at the outer rim's peak speed
    ``v = max(|ω|, 1 rad/s)·D/2``, the balls rolling::

        E_ref = ½·v²·(m_ring + Σ m_cage + Σ Z·(m_b + I_b/(D_w/2)²))
        E_max = 100·E_ref + F_max·D_w,max

    plus the work of the peak load ``F_max`` (radial, axial, or the moment as a force
    pair at the smallest pitch radius; at least 1 N) over a ball diameter.
    """
    rows = model.rows
    w_max = max(float(np.max(np.abs(resolved.speed[1]))), 1.0)
    v_ref = w_max * outer_diameter / 2
    e_ref = 0.5 * v_ref**2 * (model.params[P_RING_M] + float(np.sum(rows[:, R_CAGE_M]))
                              + float(np.sum(rows[:, R_Z] * (rows[:, R_MB] + rows[:, R_IB] / rows[:, R_HALF_D]**2))))
    # a tilting moment does work like a force pair at the balls (its peak over the pitch radius)
    f_moment = float(np.max(np.abs(resolved.moment[1]))) / float(np.min(rows[:, R_PITCH_R]))
    f_max = float(max(np.max(np.abs(resolved.radial[1])), np.max(np.abs(resolved.axial[1])), f_moment, 1.0))
    return 100.0 * e_ref + f_max * 2 * float(rows[:, R_HALF_D].max())


@kernel(inline=True)
def pocket_energy(y, rows, pockets, r, j, cphi, sphi):
    """Elastic energy ``⅖·K_p·δ^2.5`` [J] of ball ``j`` of row ``r`` against its cage pocket
    at the state ``y``; ``cphi``, ``sphi`` the cosine and sine of the row's cage angle."""
    b = int(rows[r, R_BALL0]) + BALL_STATES * j
    c0, k = int(rows[r, R_CAGE0]), int(rows[r, R_POCKET0]) + j
    cs0, sn0 = pockets[k, 0], pockets[k, 1]
    d, _, _, _, _ = cage_pocket_penetration(rows[r, R_GUIDE], y[b] - y[c0], y[b + 1] - y[c0 + 1],
                                            y[b + 2] - y[c0 + 2] - rows[r, R_ZROW],
                                            cphi * cs0 - sphi * sn0, sphi * cs0 + cphi * sn0,
                                            rows[r, R_PITCH_R], rows[r, R_POCKET_R], rows[r, R_HALF_D],
                                            rows[r, R_CAGE_RI], rows[r, R_CAGE_RO])
    return hertz_energy(rows[r, R_POCKET_K], d)


@kernel
def kinetic_energy(y, params, rows):
    """Kinetic energy of the free motion [J] (the prescribed spin of the ring excluded),
    a flexible ring's modes' included (:func:`rvcore.dynamics.ring_modes.modal_energy`)."""
    e = 0.5 * params[P_RING_M] * (y[5] ** 2 + y[6] ** 2 + y[7] ** 2)
    if flexible(params):
        e += modal_energy(params, y)[0]
    e += 0.5 * params[P_RING_IT] * (y[8] ** 2 + y[9] ** 2)
    for r in range(rows.shape[0]):
        c0 = int(rows[r, R_CAGE0])
        e += 0.5 * rows[r, R_CAGE_M] * (y[c0 + 4] ** 2 + y[c0 + 5] ** 2 + y[c0 + 6] ** 2)
        e += 0.5 * rows[r, R_CAGE_I] * y[c0 + 7] ** 2
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            e += 0.5 * rows[r, R_MB] * (y[b + 3] ** 2 + y[b + 4] ** 2 + y[b + 5] ** 2)
            e += 0.5 * rows[r, R_IB] * (y[b + 6] ** 2 + y[b + 7] ** 2 + y[b + 8] ** 2)
    return e


@kernel
def gravity_potential(y, params, rows):
    """``−Σ m·g·r`` over the inner ring, the cages and the balls [J]: gravity's potential."""
    gx, gy, gz = params[P_GX], params[P_GY], params[P_GZ]
    e = -params[P_RING_M] * (gx * y[0] + gy * y[1] + gz * y[2])
    for r in range(rows.shape[0]):
        b0, c0 = int(rows[r, R_BALL0]), int(rows[r, R_CAGE0])
        e -= rows[r, R_CAGE_M] * (gx * y[c0] + gy * y[c0 + 1] + gz * y[c0 + 2])
        m_b = rows[r, R_MB]
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            e -= m_b * (gx * y[b] + gy * y[b + 1] + gz * y[b + 2])
    return e


@kernel(inline=True)
def ring_load_coefficients(t, table, meta):
    """The applied loads at ``t`` [s] as the coefficients ``a`` of the ring's pose
    ``(x, y, z, θx, θy)`` [m, rad] in their work potential ``−a·q`` [N, N m]: the radial
    load along the load direction ψ, the axial along z, the moment about the axis at
    ψ + 90°."""
    fr = channel_value(table, meta, CH_RADIAL, t)
    fa = channel_value(table, meta, CH_AXIAL, t)
    moment = channel_value(table, meta, CH_MOMENT, t)
    psi = channel_value(table, meta, CH_DIRECTION, t)
    lc, ls = math.cos(psi), math.sin(psi)
    return fr * lc, fr * ls, fa, -moment * ls, moment * lc


@kernel(inline=True)
def ring_load_potential(t, xi, yi, zi, tx, ty, table, meta):
    """``−(F·r_ring + M·θ)`` [J]: the applied loads' potential at the ring's pose
    ``(xi, yi, zi, tx, ty)`` [m, rad], the loads those of the profile at ``t`` [s] held
    constant (:func:`ring_load_coefficients`)."""
    a0, a1, a2, a3, a4 = ring_load_coefficients(t, table, meta)
    return -(a0 * xi + a1 * yi + a2 * zi) - (a3 * tx + a4 * ty)


@kernel
def potential_energy(t, y, params, rows, arcs, pockets, table, meta):
    """Elastic energy of every contact minus the work potential of the applied loads [J].

    ``Σ ⅖·K·δ^2.5`` over ball–race, ball–pocket and cage–land contacts, minus
    ``F·r_ring + M·θ`` with the loads at ``t`` held constant, minus ``Σ m·g·r`` of every
    body (gravity), plus a flexible ring's strain energy in its support
    (:func:`rvcore.dynamics.ring_modes.modal_energy`; its raceways displaced at each ball as
    in the right-hand side, :func:`rvcore.dynamics.races.ring_surfaces`). With the kinetic energy
    (:func:`kinetic_energy`) it is conserved when friction and damping
    are off, the loads are constant and the ring does not spin.
    """
    xi, yi, zi, tx, ty = y[0], y[1], y[2], y[3], y[4]
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = ring_rotation(tx, ty)
    cos_spin, sin_spin = spin_of(rows, table, meta, t)
    e = ring_load_potential(t, xi, yi, zi, tx, ty, table, meta) + gravity_potential(y, params, rows)
    flex = flexible(params)
    if flex:
        e += modal_energy(params, y)[1]
    for r in range(rows.shape[0]):
        b0, c0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_CAGE0]), int(rows[r, R_POCKET0])
        a0, na = int(rows[r, R_ARC0]), int(rows[r, R_NARC])
        zrow, h = rows[r, R_ZROW], rows[r, R_HALF_D]
        xc, yc, zc, phi = y[c0], y[c0 + 1], y[c0 + 2], y[c0 + 3]
        cphi, sphi = math.cos(phi), math.sin(phi)
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            px, py, pz = y[b], y[b + 1], y[b + 2]
            plx, ply, plz, rho_l = to_ring_frame(px, py, pz, xi, yi, zi, r00, r01, r02, r10, r11, r12,
                                                 r20, r21, r22, zrow)
            rho_b = math.sqrt(px * px + py * py)
            dr_i, dr_o, d_half, sl_i, sl_o, dz_i, dz_o, zs_i, zs_o = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            if rows[r, R_IMPERFECT] != 0.0:
                dr_i, dr_o, d_half, sl_i, sl_o, dz_i, dz_o, zs_i, zs_o = ball_offsets(
                    rows, r, pockets, p0 + j, plx, ply, 1.0 / rho_l, cos_spin, sin_spin, px / rho_b, py / rho_b)
            if flex:    # the grooves' modal displacements and slopes added to the imperfections'
                w, _, ws, u, _, us = groove(params, y, F_INNER_RADIAL, F_INNER_AXIAL, plx / rho_l, ply / rho_l)
                dr_i, sl_i, dz_i, zs_i = dr_i + w, sl_i + ws, dz_i + u, zs_i + us
                w, _, ws, u, _, us = groove(params, y, F_OUTER_RADIAL, F_OUTER_AXIAL, px / rho_b, py / rho_b)
                dr_o, sl_o, dz_o, zs_o = dr_o + w, sl_o + ws, dz_o + u, zs_o + us
            for a in range(a0, a0 + na):
                _, d, _, _, _ = race_arc_penetration(arcs, a, plx, ply, plz, rho_l, 1.0 / rho_l, px, py, pz - zrow,
                                                     rho_b, 1.0 / rho_b, h, dr_i, dr_o, d_half, sl_i, sl_o,
                                                     dz_i, dz_o, zs_i, zs_o)
                e += hertz_energy(arcs[a, A_K], d)
            e += pocket_energy(y, rows, pockets, r, j, cphi, sphi)
        if rows[r, R_GUIDE] == GUIDE_OUTER_LAND:
            d, _, _ = land_penetration(xc, yc, rows[r, R_LAND_CLEAR])
            e += hertz_energy(rows[r, R_LAND_K], d)
    return e
