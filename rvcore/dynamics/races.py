"""The ball contacts of one row, every ball at once: the loops the compiler turns into
vector code. SI throughout.

Why passes of their own
-----------------------
The right-hand side (:func:`rvcore.dynamics.rhs.rhs`) visits a ball at a time: its race
contacts, its pocket, and the sums over the balls into the rings and the cage. Written
that way, numba's LLVM compiles the contacts to scalar code, one ball after another.
Here they are taken out of that loop into loops over the row's balls with nothing that
depends on another ball: every ball's centre in the fixed and the ring's frame
(:func:`ball_geometry`), then for each raceway arc every ball's penetration, normal,
slip, normal load and contact force (:func:`arc_contacts`), and the same for the pockets
(:func:`pocket_contacts`). LLVM vectorises these (with AVX-512, eight balls an
instruction), and the ball loop of the right-hand side reads the results back and does
the rest (the sums, the diagnostics, the IMEX tangents) as before. What it gained:
docs/performance.md, "The ball contacts in vector passes".

The values are those of the scalar code, bit for bit: each is computed by the same
functions of :mod:`rvcore.contact.laws` in the same order of operations, for every ball, and
the ball loop takes them where that code took them (a contact it skipped, it still skips;
the values of an open contact are never read). What made the loops vectorisable:

- the ball states are gathered into the scratch a quantity a row (:func:`gather_balls`):
  LLVM does not vectorise the ball's nine states at a stride of nine;
- one scratch array with constant distances between its quantities (below);
- the contact laws return one value through selects, not through several ``return``
  statements (which LLVM lowers to a switch it cannot vectorise), load the law's
  parameters outside any branch, and take the Hertz root of ``|δ|``
  (:func:`rvcore.contact.laws.hertz_load`);
- the friction law's kind is a constant in each loop: the loop is written once and copied
  a law (:func:`arc_contacts`, :data:`rvcore.contact.laws.FRICTION_KINDS`), so the
  dispatch's branches fold away and a copy holds one law's code. A loop that computed
  every law's friction and selected (the lubricated law's exponentials and logarithms
  beside the study law's cubic) was not vectorised at all.
"""
from __future__ import annotations

import math

from .._numba import kernel

from ..contact.laws import (FRICTION_KINDS, NO_FILM, NO_FILM_CONSTANTS, ball_contact_force, boundary_film_exponent,
                            cage_pocket_penetration, contact_film_of_logs, film_coefficients, friction_film_constants_of, friction_kind,
                            friction_uses_film, hertz_load, normal_force, race_arc_penetration)
from ..bearing.layout import A_EEFF, A_ELL, A_K, A_LOG_HC1, A_LOG_LAM1, A_PC3, A_RING, A_RX, BALL_STATES, MAX_ROW_ARCS, MAX_ROW_BALLS, R_BALL0, R_IMPERFECT, R_POCKET0, R_Z
from ..contact.film import HC_EXP_U, HC_EXP_W, HM_EXP_U, HM_EXP_W, log_films
from .raceway import ball_offsets
from .ring_modes import F_INNER_RADIAL, F_OUTER_RADIAL, family_record, flexible
from ..contact.pose import ring_to_global, to_ring_frame

# The scratch: quantity ``f`` of the row's ball ``j`` (its index in the row, from 0) at
# ``buf[f·W + j]``, W a constant. One array with constant distances between its
# quantities, so that LLVM sees that a loop's stores do not overlap its loads: between
# arrays of their own it must check that at run time, and with the thirty-odd streams of
# a contact it gave up and ran the scalar loop. The index from 0 is known not to be
# negative (a negative index's wrap-around is a select LLVM does not vectorise). W is a
# multiple of 8 balls (one AVX-512 vector) but not a power of two: quantities 2 KiB apart
# fall into two of the 64 sets of a 32 KiB 8-way L1 cache and evict each other. The
# quantities: the balls' states (S_*, :func:`gather_balls`); their centres' distance from
# the axis (fixed frame) and its inverse, their centres in the inner ring's frame with
# that distance and its inverse, the offsets of an imperfect row's raceways at them, and
# their pockets' angles; each groove's radial and axial displacement and their slopes along
# the ring are an imperfection's plus a flexible ring's modal sum (rvcore.dynamics.ring_modes,
# :func:`ring_surfaces`), and each groove's modal velocity in its ring's frame (three values
# from G_VG_I and from G_VG_O; 0 for rigid rings) (G_*); per raceway arc of the row the
# penetration, the normal in
# the arc's ring's frame and in the fixed frame, the slip of the ball against the race,
# its normal rate, the normal load, the force and moment on the ball, and dδ/dt with the
# groove's modal velocity (C_DD; the normal rate C_UN leaves it out: it is the slip's) (C_*, from
# ``arc(slot)``); and the pocket contact's (P_*, from POCKET).
W = MAX_ROW_BALLS + 8
S_PX, S_PY, S_PZ, S_VX, S_VY, S_VZ, S_WX, S_WY, S_WZ = range(9)
(G_RHO_B, G_INV_RHO_B, G_PLX, G_PLY, G_PLZ, G_RHO_L, G_INV_RHO_L, G_DR_I, G_DR_O, G_D_HALF, G_SL_I,
 G_SL_O, G_DZ_I, G_DZ_O, G_ZSL_I, G_ZSL_O, G_CS0, G_SN0) = range(BALL_STATES, BALL_STATES + 18)
G_VG_I, G_VG_O = BALL_STATES + 18, BALL_STATES + 21    # three values each
# a flexible ring's modal sums over the orders, ball by ball (ring_surfaces, ring_forces):
# cos kθ and sin kθ, the largest |w| and |u| of the modes alone, and the ball's normal
# forces on the four families (inner radial, inner axial, outer radial, outer axial)
G_CK, G_SK, G_MW, G_MU, G_FM = BALL_STATES + 24, BALL_STATES + 25, BALL_STATES + 26, BALL_STATES + 27, BALL_STATES + 28
N_BALL_FIELDS = BALL_STATES + 32
# (and the contact's film for the friction law: mean Hertz pressure, central film, λ;
# rvcore.contact.laws.contact_film, NO_FILM when the law needs none; and for a law that needs
# it, the logarithms of h_c and λ that the film along the cycle takes, arc_film; for one that
# does not, C_LOG_HC holds the entrainment speed smallest_film took)
(C_DELTA, C_NLX, C_NLY, C_NLZ, C_NX, C_NY, C_NZ, C_UX, C_UY, C_UZ, C_UN, C_Q, C_FX, C_FY, C_FZ, C_MX, C_MY,
 C_MZ, C_P, C_H, C_LAM, C_DD, C_LOG_HC, C_LOG_LAM) = range(24)
N_ARC_FIELDS = 24
# the pocket contact: penetration, arm, gradient, slip, its normal rate, normal load, its
# Hertz part, force and moment on the ball
(P_DELTA, P_AX, P_AY, P_AZ, P_DGX, P_DGY, P_DGZ, P_UX, P_UY, P_UZ, P_UN, P_Q, P_QH, P_FX, P_FY, P_FZ, P_MX, P_MY,
 P_MZ) = range(19)
N_POCKET_FIELDS = 19
POCKET = (N_BALL_FIELDS + MAX_ROW_ARCS * N_ARC_FIELDS) * W
#: Scratch values (:func:`rvcore.dynamics.rhs.new_diagnostics` keeps them at the end of ``diag``).
SCRATCH_SIZE = POCKET + N_POCKET_FIELDS * W


@kernel(inline=True)
def scratch(diag):
    """The scratch at the end of ``diag`` (:func:`rvcore.dynamics.rhs.new_diagnostics`)."""
    return diag[diag.size - SCRATCH_SIZE:]


@kernel(inline=True)
def arc(slot):
    """Where arc number ``slot`` of the row starts in the scratch (add ``C_*·W + j``)."""
    return (N_BALL_FIELDS + slot * N_ARC_FIELDS) * W


@kernel(inline=True)
def entrainment_speed(px, py, vx, vy, wx, wy, wz, ax, ay, az, inv_rho_b, ux, uy, uz, un, nx, ny, nz):
    """Entrainment speed ``|u_e|`` of a ball–race contact [m s⁻¹]: the mean of the two
    surfaces' speeds past the contact point, which moves with the ball centre and turns with
    its orbit (``ω_c ẑ``, ``ω_c = (p × v)_z/ρ²`` the ball's orbital speed): ``(ω − ω_c ẑ) × a``
    for the ball's, the same less the slip ``u`` for the race's, tangential (the arm ``a`` is
    along ``n``).

    Parameters
    ----------
    px, py, vx, vy : float
        The ball centre's position [m] and velocity [m s⁻¹] in the bearing's plane.
    wx, wy, wz : float
        The ball's angular velocity [rad s⁻¹].
    ax, ay, az : float
        The arm from the ball centre to the contact point [m].
    inv_rho_b : float
        1/(the ball centre's distance from the axis) [m⁻¹].
    ux, uy, uz, un : float
        The slip of the ball's material point against the race's, and its normal part [m s⁻¹].
    nx, ny, nz : float
        The contact normal (unit).
    """
    w_orb = (px * vy - py * vx) * inv_rho_b * inv_rho_b
    ex = (wy * az - wz * ay + w_orb * ay) - 0.5 * (ux - un * nx)
    ey = (wz * ax - wx * az - w_orb * ax) - 0.5 * (uy - un * ny)
    ez = (wx * ay - wy * ax) - 0.5 * (uz - un * nz)
    return math.sqrt(ex * ex + ey * ey + ez * ez)


@kernel
def gather_balls(y, buf, rows, r, pockets):
    """Copy row ``r``'s ball states from ``y``, and its pockets' angles (cosine and sine)
    from ``pockets``, into the scratch, a quantity a row."""
    b0, k0 = int(rows[r, R_BALL0]), int(rows[r, R_POCKET0])
    for j in range(int(rows[r, R_Z])):
        b = b0 + BALL_STATES * j
        for f in range(BALL_STATES):
            buf[f * W + j] = y[b + f]
        buf[G_CS0 * W + j] = pockets[k0 + j, 0]
        buf[G_SN0 * W + j] = pockets[k0 + j, 1]


@kernel
def ball_geometry(buf, nz, xi, yi, zi, r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow):
    """Every ball's distance from the axis and its centre in the inner ring's frame
    (:func:`rvcore.contact.pose.to_ring_frame`), with the inverses of both distances."""
    for j in range(nz):
        px, py, pz = buf[S_PX * W + j], buf[S_PY * W + j], buf[S_PZ * W + j]
        rho_b = math.sqrt(px * px + py * py)
        plx, ply, plz, rho_l = to_ring_frame(px, py, pz, xi, yi, zi, r00, r01, r02, r10, r11, r12,
                                             r20, r21, r22, zrow)
        buf[G_RHO_B * W + j] = rho_b
        buf[G_INV_RHO_B * W + j] = 1.0 / rho_b
        buf[G_PLX * W + j] = plx
        buf[G_PLY * W + j] = ply
        buf[G_PLZ * W + j] = plz
        buf[G_RHO_L * W + j] = rho_l
        buf[G_INV_RHO_L * W + j] = 1.0 / rho_l


@kernel
def raceway_offsets(buf, rows, r, pockets, cos_spin, sin_spin):
    """Every ball's offsets of an imperfect row's raceways (:func:`rvcore.dynamics.raceway.ball_offsets`),
    0 for a perfect row."""
    k0, nz = int(rows[r, R_POCKET0]), int(rows[r, R_Z])
    imperfect = rows[r, R_IMPERFECT] != 0.0
    for j in range(nz):
        dr_i, dr_o, d_half, sl_i, sl_o, dz_i, dz_o, zs_i, zs_o = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        if imperfect:
            inv_rho_b = buf[G_INV_RHO_B * W + j]
            dr_i, dr_o, d_half, sl_i, sl_o, dz_i, dz_o, zs_i, zs_o = ball_offsets(
                rows, r, pockets, k0 + j, buf[G_PLX * W + j], buf[G_PLY * W + j], buf[G_INV_RHO_L * W + j],
                cos_spin, sin_spin, buf[S_PX * W + j] * inv_rho_b, buf[S_PY * W + j] * inv_rho_b)
        buf[G_DR_I * W + j] = dr_i
        buf[G_DR_O * W + j] = dr_o
        buf[G_D_HALF * W + j] = d_half
        buf[G_SL_I * W + j] = sl_i
        buf[G_SL_O * W + j] = sl_o
        buf[G_DZ_I * W + j] = dz_i
        buf[G_DZ_O * W + j] = dz_o
        buf[G_ZSL_I * W + j] = zs_i
        buf[G_ZSL_O * W + j] = zs_o


@kernel(inline=True)
def _angle(buf, j, inner):
    """The ball's direction ``(cos θ, sin θ)`` in the inner ring's frame or the fixed frame."""
    if inner:
        return buf[G_PLX * W + j] * buf[G_INV_RHO_L * W + j], buf[G_PLY * W + j] * buf[G_INV_RHO_L * W + j]
    return buf[S_PX * W + j] * buf[G_INV_RHO_B * W + j], buf[S_PY * W + j] * buf[G_INV_RHO_B * W + j]


@kernel(inline=True)
def _order_coefficients(y, ar, nr, aa, na, k):
    """Order ``k``'s amplitudes and their rates of a ring's radial (``ar``, ``nr`` orders) and
    axial (``aa``, ``na``) families in ``y`` (0 past a family's last order)."""
    wc, ws = (y[ar + 2 * k], y[ar + 2 * k + 1]) if k < nr else (0.0, 0.0)
    wdc, wds = (y[ar + 2 * nr + 2 * k], y[ar + 2 * nr + 2 * k + 1]) if k < nr else (0.0, 0.0)
    uc, us = (y[aa + 2 * k], y[aa + 2 * k + 1]) if k < na else (0.0, 0.0)
    udc, uds = (y[aa + 2 * na + 2 * k], y[aa + 2 * na + 2 * k + 1]) if k < na else (0.0, 0.0)
    return wc, ws, wdc, wds, uc, us, udc, uds


@kernel(inline=True)
def _ring_surface(buf, params, y, nz, inner, fr, dr, sl, dz, zsl, vg):
    """One ring's modal sums at every ball of the row (:func:`ring_surfaces`): the orders
    in the outer loop, two at a time, the balls in the inner (vectorised), ``cos kθ``,
    ``sin kθ`` by the rotation recurrence in ``G_CK``, ``G_SK``; each sum a ball's, over the
    orders in turn."""
    nr, ar, _ = family_record(params, fr)
    na, aa, _ = family_record(params, fr + 1)
    for j in range(nz):
        buf[G_CK * W + j], buf[G_SK * W + j] = 1.0, 0.0
        buf[G_MW * W + j], buf[G_MU * W + j] = 0.0, 0.0
        buf[vg * W + j], buf[(vg + 2) * W + j] = 0.0, 0.0
    nk = max(nr, na)
    for k in range(0, nk - 1, 2):      # orders k and k + 1: the sums read and written once
        wc, ws, wdc, wds, uc, us, udc, uds = _order_coefficients(y, ar, nr, aa, na, k)
        wc2, ws2, wdc2, wds2, uc2, us2, udc2, uds2 = _order_coefficients(y, ar, nr, aa, na, k + 1)
        k2 = k + 1
        for j in range(nz):
            ck, sk = buf[G_CK * W + j], buf[G_SK * W + j]
            c1, s1 = _angle(buf, j, inner)
            ck2, sk2 = ck * c1 - sk * s1, sk * c1 + ck * s1
            buf[G_MW * W + j] = buf[G_MW * W + j] + (wc * ck + ws * sk) + (wc2 * ck2 + ws2 * sk2)
            buf[sl * W + j] = buf[sl * W + j] + k * (ws * ck - wc * sk) + k2 * (ws2 * ck2 - wc2 * sk2)
            buf[vg * W + j] = buf[vg * W + j] + (wdc * ck + wds * sk) + (wdc2 * ck2 + wds2 * sk2)
            buf[G_MU * W + j] = buf[G_MU * W + j] + (uc * ck + us * sk) + (uc2 * ck2 + us2 * sk2)
            buf[zsl * W + j] = buf[zsl * W + j] + k * (us * ck - uc * sk) + k2 * (us2 * ck2 - uc2 * sk2)
            buf[(vg + 2) * W + j] = buf[(vg + 2) * W + j] + (udc * ck + uds * sk) + (udc2 * ck2 + uds2 * sk2)
            buf[G_CK * W + j], buf[G_SK * W + j] = ck2 * c1 - sk2 * s1, sk2 * c1 + ck2 * s1
    if nk % 2 == 1:     # the last order alone
        k = nk - 1
        wc, ws, wdc, wds, uc, us, udc, uds = _order_coefficients(y, ar, nr, aa, na, k)
        for j in range(nz):
            ck, sk = buf[G_CK * W + j], buf[G_SK * W + j]
            buf[G_MW * W + j] += wc * ck + ws * sk
            buf[sl * W + j] += k * (ws * ck - wc * sk)
            buf[vg * W + j] += wdc * ck + wds * sk
            buf[G_MU * W + j] += uc * ck + us * sk
            buf[zsl * W + j] += k * (us * ck - uc * sk)
            buf[(vg + 2) * W + j] += udc * ck + uds * sk
    max_w, max_u = 0.0, 0.0
    for j in range(nz):
        w, u = buf[G_MW * W + j], buf[G_MU * W + j]
        buf[dr * W + j] += w
        buf[dz * W + j] += u
        max_w = max(max_w, abs(w))
        max_u = max(max_u, abs(u))
        c1, s1 = _angle(buf, j, inner)
        wd = buf[vg * W + j]
        buf[vg * W + j], buf[(vg + 1) * W + j] = wd * c1, wd * s1
    return max_w, max_u


@kernel
def ring_surfaces(buf, params, y, nz):
    """Every ball's raceway displacements and modal velocities of flexible rings
    (:mod:`rvcore.dynamics.ring_modes`), after :func:`ball_geometry` and
    :func:`raceway_offsets`: each groove's radial shift ``w`` and axial shift ``u`` added to
    the imperfections' ``G_DR_*`` and ``G_DZ_*``, their slopes ``∂w/∂θ``, ``∂u/∂θ`` to
    ``G_SL_*`` and ``G_ZSL_*`` (one raceway displacement, imperfections plus modes), and each
    groove's velocity ``ẇ·ê_r + u̇·ẑ`` in its ring's frame in ``G_VG_I``/``G_VG_O``; the
    same shifts as the flexible statics' (:func:`rvcore.statics.equilibrium._ball_contacts`)
    and as :func:`rvcore.dynamics.ring_modes.groove`'s.
    The angles: the ball's direction in the inner ring's frame and in the fixed frame.
    With rigid rings the velocities are set to 0 and nothing else is touched.
    Returns the largest ``|w|`` and ``|u|`` of either ring at the balls [m]."""
    if not flexible(params):
        for j in range(nz):
            for c in range(3):
                buf[(G_VG_I + c) * W + j] = 0.0
                buf[(G_VG_O + c) * W + j] = 0.0
        return 0.0, 0.0
    wi, ui = _ring_surface(buf, params, y, nz, True, F_INNER_RADIAL, G_DR_I, G_SL_I, G_DZ_I, G_ZSL_I, G_VG_I)
    wo, uo = _ring_surface(buf, params, y, nz, False, F_OUTER_RADIAL, G_DR_O, G_SL_O, G_DZ_O, G_ZSL_O, G_VG_O)
    return max(wi, wo), max(ui, uo)


@kernel(inline=True)
def _ring_force(buf, params, dy, nz, inner, fr):
    """One ring's generalized forces from the balls' normal forces on it in ``G_FM``
    (:func:`ring_forces`): per order, ``Σ_j F_j·cos kθ_j`` and ``Σ_j F_j·sin kθ_j`` of its
    radial and axial families (four sums over the balls an order; two orders a pass over
    the balls, each sum over the balls in turn)."""
    nr, ar, _ = family_record(params, fr)
    na, aa, _ = family_record(params, fr + 1)
    f0 = G_FM if inner else G_FM + 2
    for j in range(nz):
        buf[G_CK * W + j], buf[G_SK * W + j] = 1.0, 0.0
    nk = max(nr, na)
    for k in range(0, nk, 2):
        two = k + 1 < nk
        rc, rs, ac, as_ = 0.0, 0.0, 0.0, 0.0
        rc2, rs2, ac2, as2 = 0.0, 0.0, 0.0, 0.0
        if two:
            for j in range(nz):
                ck, sk = buf[G_CK * W + j], buf[G_SK * W + j]
                fw, fu = buf[f0 * W + j], buf[(f0 + 1) * W + j]
                c1, s1 = _angle(buf, j, inner)
                ck2, sk2 = ck * c1 - sk * s1, sk * c1 + ck * s1
                rc += fw * ck
                rs += fw * sk
                ac += fu * ck
                as_ += fu * sk
                rc2 += fw * ck2
                rs2 += fw * sk2
                ac2 += fu * ck2
                as2 += fu * sk2
                buf[G_CK * W + j], buf[G_SK * W + j] = ck2 * c1 - sk2 * s1, sk2 * c1 + ck2 * s1
        else:
            for j in range(nz):
                ck, sk = buf[G_CK * W + j], buf[G_SK * W + j]
                fw, fu = buf[f0 * W + j], buf[(f0 + 1) * W + j]
                rc += fw * ck
                rs += fw * sk
                ac += fu * ck
                as_ += fu * sk
        for o in range(2 if two else 1):
            kk = k + o
            if kk < nr:
                dy[ar + 2 * nr + 2 * kk] += rc if o == 0 else rc2
                dy[ar + 2 * nr + 2 * kk + 1] += rs if o == 0 else rs2
            if kk < na:
                dy[aa + 2 * na + 2 * kk] += ac if o == 0 else ac2
                dy[aa + 2 * na + 2 * kk + 1] += as_ if o == 0 else as2


@kernel
def ring_forces(buf, params, dy, nz):
    """The row's balls' normal forces on flexible rings (``G_FM``: inner radial, inner
    axial, outer radial, outer axial, at each ball's angle in its ring's frame, as
    :func:`ring_surfaces` reads them) added to the modes' generalized forces in ``dy``'s
    rate slots (:func:`rvcore.dynamics.ring_modes.modal_rhs` turns them into accelerations)."""
    _ring_force(buf, params, dy, nz, True, F_INNER_RADIAL)
    _ring_force(buf, params, dy, nz, False, F_OUTER_RADIAL)


@kernel
def arc_contacts(buf, out, nz, arcs, a, h, xi, yi, zi, vxi, vyi, vzi, omx, omy, omz,
                 r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow, c_race, inv_dmax, law):
    """Every ball's contact with arc ``a`` into ``out``, the arc's part of the scratch
    (``C_*·W + j``; an array of its own, so that the distances LLVM compares are constants
    within each of the two): the values the ball loop of :func:`rvcore.dynamics.rhs.rhs` reads
    (module docstring), for every ball whether it touches or not.

    The loop (:func:`_arc_loop`) is written once and copied a friction law
    (:data:`rvcore.contact.laws.FRICTION_KINDS`), the law's kind a constant in each copy,
    so that a copy holds its law's code alone (the study law's copy is vectorised; a copy
    that also computed the other law's friction and selected was not).
    """
    kind = friction_kind(law)
    k0, k1 = FRICTION_KINDS
    if kind == k0:
        _arc_loop(buf, out, nz, arcs, a, h, xi, yi, zi, vxi, vyi, vzi, omx, omy, omz,
                  r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow, c_race, inv_dmax, law, k0)
    elif kind == k1:
        _arc_loop(buf, out, nz, arcs, a, h, xi, yi, zi, vxi, vyi, vzi, omx, omy, omz,
                  r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow, c_race, inv_dmax, law, k1)
    else:
        _arc_loop(buf, out, nz, arcs, a, h, xi, yi, zi, vxi, vyi, vzi, omx, omy, omz,
                  r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow, c_race, inv_dmax, law, kind)


@kernel(inline=True)
def _arc_loop(buf, out, nz, arcs, a, h, xi, yi, zi, vxi, vyi, vzi, omx, omy, omz,
              r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow, c_race, inv_dmax, law, kind):
    """:func:`arc_contacts`' loop for the friction law of kind ``kind``."""
    inner = arcs[a, A_RING] == 0.0
    k_hertz = arcs[a, A_K]
    uses_film = friction_uses_film(kind)
    p_none, h_none, lam_none = NO_FILM
    f0, f1, f2 = NO_FILM_CONSTANTS
    vg = G_VG_I if inner else G_VG_O    # the groove's modal velocity (ring_surfaces)
    for j in range(nz):
        px, py, pz = buf[S_PX * W + j], buf[S_PY * W + j], buf[S_PZ * W + j]
        vx, vy, vz = buf[S_VX * W + j], buf[S_VY * W + j], buf[S_VZ * W + j]
        wx, wy, wz = buf[S_WX * W + j], buf[S_WY * W + j], buf[S_WZ * W + j]
        _, delta, nlx, nly, nlz = race_arc_penetration(
            arcs, a, buf[G_PLX * W + j], buf[G_PLY * W + j], buf[G_PLZ * W + j], buf[G_RHO_L * W + j],
            buf[G_INV_RHO_L * W + j], px, py, pz - zrow, buf[G_RHO_B * W + j], buf[G_INV_RHO_B * W + j], h,
            buf[G_DR_I * W + j], buf[G_DR_O * W + j], buf[G_D_HALF * W + j], buf[G_SL_I * W + j],
            buf[G_SL_O * W + j], buf[G_DZ_I * W + j], buf[G_DZ_O * W + j], buf[G_ZSL_I * W + j],
            buf[G_ZSL_O * W + j])
        gx, gy, gz = ring_to_global(nlx, nly, nlz, r00, r01, r02, r10, r11, r12, r20, r21, r22)
        nx = gx if inner else nlx
        ny = gy if inner else nly
        nz_ = gz if inner else nlz
        # contact point on the ball, and the arm from the ball centre
        ax, ay, az = h * nx, h * ny, h * nz_
        cx, cy, cz = px + ax, py + ay, pz + az
        # slip of the ball's material point against the race's: v_ring + Ω × (c − r_ring)
        # for the inner ring's
        ux = vx + wy * az - wz * ay
        uy = vy + wz * ax - wx * az
        uz = vz + wx * ay - wy * ax
        qx, qy, qz = cx - xi, cy - yi, cz - zi
        ux = ux - (vxi + omy * qz - omz * qy) if inner else ux
        uy = uy - (vyi + omz * qx - omx * qz) if inner else uy
        uz = uz - (vzi + omx * qy - omy * qx) if inner else uz
        un = ux * nx + uy * ny + uz * nz_    # dδ/dt of rigid rings
        # less the groove's modal velocity along the normal (∂δ/∂(groove) = −n; 0 when rigid)
        dd = un - (nlx * buf[vg * W + j] + nly * buf[(vg + 1) * W + j] + nlz * buf[(vg + 2) * W + j])
        q = normal_force(delta, dd, k_hertz, c_race, inv_dmax)
        p_f, h_f, lam_f = p_none, h_none, lam_none
        if uses_film:
            # the entrainment speed only, kept in C_P for the film's own pass (arc_film), so
            # that this loop stays free of exp and log (and vectorised)
            p_f = entrainment_speed(px, py, vx, vy, wx, wy, wz, ax, ay, az, buf[G_INV_RHO_B * W + j], ux, uy, uz,
                                    un, nx, ny, nz_)
            fx, fy, fz, dmx, dmy, dmz = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        else:
            fx, fy, fz, dmx, dmy, dmz = ball_contact_force(q, nx, ny, nz_, ux, uy, uz, nx, ny, nz_, ax, ay, az,
                                                           f0, f1, f2, law, kind)
        out[C_DELTA * W + j] = delta
        out[C_NLX * W + j] = nlx
        out[C_NLY * W + j] = nly
        out[C_NLZ * W + j] = nlz
        out[C_NX * W + j] = nx
        out[C_NY * W + j] = ny
        out[C_NZ * W + j] = nz_
        out[C_UX * W + j] = ux
        out[C_UY * W + j] = uy
        out[C_UZ * W + j] = uz
        out[C_UN * W + j] = un
        out[C_Q * W + j] = q
        out[C_FX * W + j] = fx
        out[C_FY * W + j] = fy
        out[C_FZ * W + j] = fz
        out[C_MX * W + j] = dmx
        out[C_MY * W + j] = dmy
        out[C_MZ * W + j] = dmz
        out[C_P * W + j] = p_f
        out[C_H * W + j] = h_f
        out[C_LAM * W + j] = lam_f
        out[C_DD * W + j] = dd


@kernel
def arc_film(out, nz, arcs, a, h, law, held, fresh):
    """The film and the friction of every loaded contact of arc ``a`` (:func:`_film_pass`),
    after :func:`arc_contacts` for a law that needs the film
    (:func:`rvcore.contact.laws.friction_uses_film`); nothing for one that does not.

    ``held[j]`` keeps the row's ball j's film at this arc through a step's stages
    (:func:`_film_pass`), ``fresh`` the step's first evaluation, which computes and keeps it.
    """
    kind = friction_kind(law)
    k0, k1 = FRICTION_KINDS
    if kind == k0 and friction_uses_film(k0):
        _film_pass(out, nz, arcs, a, h, law, k0, held, fresh)
    elif kind == k1 and friction_uses_film(k1):
        _film_pass(out, nz, arcs, a, h, law, k1, held, fresh)


@kernel(inline=True)
def _film_pass(out, nz, arcs, a, h, law, kind, held, fresh):
    """:func:`arc_film` for the law of kind ``kind``: the film
    (:func:`rvcore.contact.laws.contact_film_or_boundary`: none where the contact is certainly
    boundary lubricated, λ's exponent below the arc's ``x_b``) and the law's force of every
    loaded contact, after :func:`_arc_loop`'s geometry pass, which left each contact's
    entrainment speed in ``C_P``. A loop of its own, scalar (its exp, log and expm1; no
    vector maths library here), so that the geometry's loop stays vectorised; an open
    contact (q = 0) gets :data:`rvcore.contact.laws.NO_FILM` and no force, its values read by
    nobody (:func:`rvcore.dynamics.rhs.rhs` skips q ≤ 0).

    The film is held through a step's stages (docs/model.md §4.1, "The film through a
    step"): the step's first evaluation (``fresh``) computes each loaded contact's film
    ``(p, h_c, λ)`` into ``C_P``, ``C_H``, ``C_LAM`` and the law's film constants from it
    (:func:`rvcore.contact.laws.friction_film_constants`), which it keeps in ``held[j]``
    (``held[j, 3]`` 1 where kept, 0 where the contact was open); a stage takes the kept
    constants, or computes its own where none were kept (a contact that closed within the
    step), and leaves ``C_P`` … ``C_LAM`` as they were (read by the tangents of a first
    evaluation only). A first evaluation also leaves the logarithms of the contact's h_c and
    λ in ``C_LOG_HC`` and ``C_LOG_LAM``, as :func:`rvcore.dynamics.rhs.rhs` would compute
    them for the film along the cycle (docs/model.md §15.2), from this pass's logarithms."""
    p1, hc1, lam1 = film_coefficients(arcs[a, A_PC3], arcs[a, A_RX], arcs[a, A_EEFF], arcs[a, A_ELL], law)
    x_b = boundary_film_exponent(lam1, law)
    p_none, h_none, lam_none = NO_FILM
    n0, n1, n2 = NO_FILM_CONSTANTS
    for j in range(nz):
        q = out[C_Q * W + j]
        p_f, h_f, lam_f = p_none, h_none, lam_none
        f0, f1, f2 = n0, n1, n2
        fx, fy, fz, dmx, dmy, dmz = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        if q > 0.0:
            nx, ny, nz_ = out[C_NX * W + j], out[C_NY * W + j], out[C_NZ * W + j]
            if fresh or held[j, 3] == 0.0:
                ue = out[C_P * W + j]
                lw, lu = math.log(max(q, 1e-6)), math.log(max(ue, 1e-30))
                p_f, h_f, lam_f = contact_film_of_logs(lw, lu, p1, hc1, lam1, x_b)
                f0, f1, f2 = friction_film_constants_of(kind, p_f, h_f, lam_f, law)
                if fresh:    # the film along the cycle's logarithms, as rvcore.dynamics.rhs writes them
                    lq = lw if q >= 1e-6 else math.log(q)
                    lu = lu if ue >= 1e-30 else (math.log(ue) if ue > 0.0 else -math.inf)
                    out[C_LOG_HC * W + j], out[C_LOG_LAM * W + j] = log_films(arcs[a, A_LOG_HC1],
                                                                             arcs[a, A_LOG_LAM1], lu, lq)
            else:
                f0, f1, f2 = held[j, 0], held[j, 1], held[j, 2]
            fx, fy, fz, dmx, dmy, dmz = ball_contact_force(q, nx, ny, nz_, out[C_UX * W + j], out[C_UY * W + j],
                                                           out[C_UZ * W + j], nx, ny, nz_, h * nx, h * ny, h * nz_,
                                                           f0, f1, f2, law, kind)
        if fresh:
            held[j, 0] = f0
            held[j, 1] = f1
            held[j, 2] = f2
            held[j, 3] = 1.0 if q > 0.0 else 0.0
            out[C_P * W + j] = p_f
            out[C_H * W + j] = h_f
            out[C_LAM * W + j] = lam_f
        out[C_FX * W + j] = fx
        out[C_FY * W + j] = fy
        out[C_FZ * W + j] = fz
        out[C_MX * W + j] = dmx
        out[C_MY * W + j] = dmy
        out[C_MZ * W + j] = dmz


#: Where :func:`smallest_film` takes a contact's logarithms: where the lower bound of how far
#: its ``log h_c`` (and its ``log λ``) lies above the largest-loaded contact's is at most
#: this [-]. The logarithms themselves err by about 1e-14 (|log h_c| ≈ 16).
FILM_MARGIN = 1e-9


@kernel
def smallest_film(buf, out, nz, arcs, a, h):
    """The smallest ``log h_c`` and ``log λ`` [log m, -] over arc ``a``'s loaded contacts
    (docs/model.md, "The film along the cycle"), for a friction law without a film of its
    own (:func:`arc_film` leaves a film law's logarithms in ``C_LOG_HC``, ``C_LOG_LAM``);
    ``(inf, inf)`` where none is loaded. After :func:`arc_contacts` and before the next row.

    Notes
    -----
    Hamrock–Dowson at each contact, ``log h = log h1 + e_u·log u_e + e_w·log Q``
    (:func:`rvcore.contact.film.with_film_columns`; ``u_e = 0``: no film, −inf), exactly as
    each contact's own would be, but only where it can be the smallest: ``e_u > 0`` and
    ``e_w < 0``, so with ``k`` the contact of the largest load ``Q*`` (entrainment speed
    ``u*``) and ``ln x ≥ 1 − 1/x``::

        log h_j − log h_k ≥ e_u·(1 − u*/u_j) − e_w·(1 − Q_j/Q*)

    and where that bound passes :data:`FILM_MARGIN` for both films, contact j is not the
    smallest and no logarithm is taken (the study bearing at steady running, 660 °/s: an
    arc's 51 loaded contacts share one entrainment speed to 1.4e-3, and one of them takes
    the logarithms). The result is the same, bit for bit, as the minimum over every contact.
    A kernel of its own, not inlined into :func:`rvcore.dynamics.rhs.rhs`: with the scratch
    and the arc's part of it as two arrays, LLVM vectorises the entrainment speeds' pass.
    """
    for j in range(nz):     # every contact's u_e, in a vector pass (C_LOG_HC: a dry law's slot is free)
        out[C_LOG_HC * W + j] = entrainment_speed(
            buf[S_PX * W + j], buf[S_PY * W + j], buf[S_VX * W + j], buf[S_VY * W + j], buf[S_WX * W + j],
            buf[S_WY * W + j], buf[S_WZ * W + j], h * out[C_NX * W + j], h * out[C_NY * W + j],
            h * out[C_NZ * W + j], buf[G_INV_RHO_B * W + j], out[C_UX * W + j], out[C_UY * W + j],
            out[C_UZ * W + j], out[C_UN * W + j], out[C_NX * W + j], out[C_NY * W + j], out[C_NZ * W + j])
    best_q, best_u = -1.0, 0.0
    for j in range(nz):     # the most loaded contact
        delta, q = out[C_DELTA * W + j], out[C_Q * W + j]
        if delta <= 0.0 or q <= 0.0 or q != q:     # a NaN load's film is NaN: no minimum
            continue
        ue = out[C_LOG_HC * W + j]
        if not ue > 0.0:
            return -math.inf, -math.inf     # no film: log h = −inf whatever the load
        if q > best_q:
            best_q, best_u = q, ue
    log_hc, log_lam = math.inf, math.inf
    if best_q < 0.0:
        return log_hc, log_lam
    for j in range(nz):
        delta, q = out[C_DELTA * W + j], out[C_Q * W + j]
        if delta <= 0.0 or q <= 0.0 or q != q:
            continue
        ue = out[C_LOG_HC * W + j]
        gu, gq = 1.0 - best_u / ue, 1.0 - q / best_q
        if HC_EXP_U * gu - HC_EXP_W * gq > FILM_MARGIN and HM_EXP_U * gu - HM_EXP_W * gq > FILM_MARGIN:
            continue
        lu = math.log(ue)
        lq = math.log(q)
        lh, ll = log_films(arcs[a, A_LOG_HC1], arcs[a, A_LOG_LAM1], lu, lq)
        if lh < log_hc:
            log_hc = lh
        if ll < log_lam:
            log_lam = ll
    return log_hc, log_lam


@kernel
def pocket_contacts(buf, out, nz, guide, pitch_r, pocket_r, h, cage_ri, cage_ro, k_pocket, c_pocket, inv_dmax,
                    xc, yc, zc, cphi, sphi, vxc, vyc, vzc, wc, zrow, law):
    """Every ball's contact with its pocket (:func:`rvcore.contact.laws.cage_pocket_penetration`)
    into ``out``, the pocket's part of the scratch (``P_*·W + j``), as :func:`arc_contacts`:
    the cage at ``(xc, yc, zc)`` turned by the angle of cosine ``cphi`` and sine ``sphi``,
    moving at ``(vxc, vyc, vzc)`` and turning at ``wc``; the loop (:func:`_pocket_loop`)
    copied a friction law as :func:`arc_contacts`'."""
    kind = friction_kind(law)
    k0, k1 = FRICTION_KINDS
    if kind == k0:
        _pocket_loop(buf, out, nz, guide, pitch_r, pocket_r, h, cage_ri, cage_ro, k_pocket, c_pocket, inv_dmax,
                     xc, yc, zc, cphi, sphi, vxc, vyc, vzc, wc, zrow, law, k0)
    elif kind == k1:
        _pocket_loop(buf, out, nz, guide, pitch_r, pocket_r, h, cage_ri, cage_ro, k_pocket, c_pocket, inv_dmax,
                     xc, yc, zc, cphi, sphi, vxc, vyc, vzc, wc, zrow, law, k1)
    else:
        _pocket_loop(buf, out, nz, guide, pitch_r, pocket_r, h, cage_ri, cage_ro, k_pocket, c_pocket, inv_dmax,
                     xc, yc, zc, cphi, sphi, vxc, vyc, vzc, wc, zrow, law, kind)


@kernel(inline=True)
def _pocket_loop(buf, out, nz, guide, pitch_r, pocket_r, h, cage_ri, cage_ro, k_pocket, c_pocket, inv_dmax,
                 xc, yc, zc, cphi, sphi, vxc, vyc, vzc, wc, zrow, law, kind):
    """:func:`pocket_contacts`' loop for the friction law of kind ``kind``."""
    inv_h = 1.0 / h
    f_none = NO_FILM_CONSTANTS     # no film at a pocket: the law's boundary friction
    for j in range(nz):
        px, py, pz = buf[S_PX * W + j], buf[S_PY * W + j], buf[S_PZ * W + j]
        vx, vy, vz = buf[S_VX * W + j], buf[S_VY * W + j], buf[S_VZ * W + j]
        wx, wy, wz = buf[S_WX * W + j], buf[S_WY * W + j], buf[S_WZ * W + j]
        cs0, sn0 = buf[G_CS0 * W + j], buf[G_SN0 * W + j]
        cth = cphi * cs0 - sphi * sn0
        sth = sphi * cs0 + cphi * sn0
        delta, ax, ay, az, a_sec = cage_pocket_penetration(guide, px - xc, py - yc, pz - zc - zrow, cth, sth,
                                                           pitch_r, pocket_r, h, cage_ri, cage_ro)
        # ∇δ along the arm
        dgx, dgy, dgz = ax / a_sec, ay / a_sec, az / a_sec
        cx, cy = px + ax, py + ay
        ux = vx + wy * az - wz * ay - (vxc - wc * (cy - yc))
        uy = vy + wz * ax - wx * az - (vyc + wc * (cx - xc))
        uz = vz + wx * ay - wy * ax - vzc
        un = ux * dgx + uy * dgy + uz * dgz   # dδ/dt
        qp = normal_force(delta, un, k_pocket, c_pocket, inv_dmax)
        # friction tangential to the ball's surface there, normal a/h
        fpx, fpy, fpz, mpx, mpy, mpz = ball_contact_force(qp, dgx, dgy, dgz, ux, uy, uz, ax * inv_h, ay * inv_h,
                                                          az * inv_h, ax, ay, az, f_none[0], f_none[1], f_none[2], law,
                                                          kind)
        out[P_DELTA * W + j] = delta
        out[P_AX * W + j] = ax
        out[P_AY * W + j] = ay
        out[P_AZ * W + j] = az
        out[P_DGX * W + j] = dgx
        out[P_DGY * W + j] = dgy
        out[P_DGZ * W + j] = dgz
        out[P_UX * W + j] = ux
        out[P_UY * W + j] = uy
        out[P_UZ * W + j] = uz
        out[P_UN * W + j] = un
        out[P_Q * W + j] = qp
        out[P_QH * W + j] = hertz_load(k_pocket, delta)
        out[P_FX * W + j] = fpx
        out[P_FY * W + j] = fpy
        out[P_FZ * W + j] = fpz
        out[P_MX * W + j] = mpx
        out[P_MY * W + j] = mpy
        out[P_MZ * W + j] = mpz
