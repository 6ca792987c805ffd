"""Numba kernels: contact laws, friction law and the equations of motion. SI throughout.

Every function here is ``@njit`` on flat arrays (layouts in :mod:`rvcore.model`); none
allocates. The right-hand side :func:`rhs` is the whole model; the energy
:func:`total_energy` and the quasi-static solver reuse the same contact geometry
(:func:`arc_penetration`) so the equations live in one place each.

Notes
-----
Cubic step (model.md §3)::

    STEP(x, x0, h0, x1, h1) = h0                          x ≤ x0
                            = h0 + (h1−h0)·Δ²·(3 − 2Δ)    Δ = (x−x0)/(x1−x0)
                            = h1                          x ≥ x1

Ball–race normal force (Hertz with the IMPACT damper)::

    δ = |P − C| − (f − ½)·D        (penetration, normal n along C→P)
    Q = K·δ^1.5 + STEP(δ, 0, 0, d_max, c_max)·dδ/dt,   then Q ← max(Q, 0)

Friction (model.md §4) with slip speed ``s = |v_t|`` of the ball's material point
relative to the other body's, tangential part only::

    μ(s) = STEP(s, −v_s, −μ_s, v_s, μ_s)      s < v_s
         = STEP(s, v_s, μ_s, v_d, μ_d)        v_s ≤ s ≤ v_d
         = μ_d                                 s > v_d
    F_t = −μ(s)·Q·v_t/s on the ball, −F_t on the other body, moment r_c × F_t.

Inner-ring kinematics (model.md §1). The ring's pose is ``R = Ry(θy)·Rx(θx)`` and it
spins at the prescribed ω about its own (tilted) axis ``R·ẑ``, so its angular velocity
in the inertial frame is (:func:`ring_angular_velocity`)::

    Ω = θ̇y·ŷ + θ̇x·Ry(θy)·x̂ + ω·R·ẑ = (θ̇x·cos θy + ω·R₀₂,  θ̇y + ω·R₁₂,  −θ̇x·sin θy + ω·R₂₂)

≈ (θ̇x + ω·θy, θ̇y − ω·θx, ω) for small tilts — the angular velocity whose momentum the
small-tilt Euler equations below differentiate. Every inner-race contact velocity is
``v_ring + Ω × (c − r_ring)``, here and in the initial rolling state.

Equations of motion (inertial frame; no centrifugal or gyroscopic term is added — they
come out of these; ``g`` is the gravity vector of the bearing's mounting)::

    ball:   m_b·dv/dt = ΣF + m_b·g,     I_b·dω/dt = ΣM           (sphere: I isotropic)
    ring:   m·dv/dt = F_ext + ΣF + m·g
            I_t·θ̈x + I_p·(ω̇·θy + ω·θ̇y) = M_x            (small-tilt Euler equations of a
            I_t·θ̈y − I_p·(ω̇·θx + ω·θ̇x) = M_y             ring spinning at the prescribed ω)
    cage:   m_c·dv/dt = ΣF + m_c·g,     I_c·dφ̇/dt = ΣT_z
"""
from __future__ import annotations

import math

from numba import njit

from .model import (A_CR, A_CZ, A_K, A_PC3, A_RING, A_RMH, A_SIDE, BALL_STATES,
                    GUIDE_OUTER_LAND, P_DAMP_C, P_DAMP_D, P_DAMPING, P_FRICTION, P_GX, P_GY,
                    P_GZ, P_LAND_C,
                    P_LOAD_COS, P_LOAD_SIN, P_MOMENT, P_MU_D, P_MU_S, P_POCKET_C, P_RING_IP,
                    P_RING_IT, P_RING_M, P_V_D, P_V_S, R_ARC0, R_BALL0, R_CAGE0, R_CAGE_I,
                    R_CAGE_M, R_CAGE_RI, R_CAGE_RO, R_GUIDE, R_HALF_D, R_IB, R_LAND_CLEAR,
                    R_LAND_K, R_MB, R_NARC, R_PITCH_R, R_POCKET0, R_POCKET_K, R_POCKET_PC,
                    R_POCKET_R, R_Z, R_ZROW)
from .profile import channel_rate, channel_value

# diag slots written by rhs()
D_MAX_QI, D_MAX_QO, D_LOADED, D_MAX_P3, D_MAX_PEN, D_PEN_BALL = 0, 1, 2, 3, 4, 5
# mean over row 0's loaded balls of cos α (each ball's race contacts averaged): the
# epicyclic cage speed at the balls' actual contact angles uses it
D_COS_ALPHA = 6
N_DIAG = 7
# per-ball diag columns: total inner / outer race load, radial components of the inner /
# outer race forces on the ball (outward positive), pocket load
B_QI, B_QO, B_FIR, B_FOR, B_QP = 0, 1, 2, 3, 4
N_BDIAG = 5

CH_RADIAL, CH_AXIAL, CH_SPEED = 0, 1, 2

# Fast-math without the no-NaN/no-Inf assumptions, so a blow-up still shows as NaN.
FAST = {"nsz", "arcp", "contract", "afn", "reassoc"}


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def step(x, x0, h0, x1, h1):
    """The cubic STEP of model.md §3."""
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    d = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d)


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def friction_coefficient(s, mu_s, v_s, mu_d, v_d):
    """μ(s) of model.md §4 for slip speed ``s`` ≥ 0 [m s^-1]."""
    if s < v_s:
        return step(s, -v_s, -mu_s, v_s, mu_s)
    if s <= v_d:
        return step(s, v_s, mu_s, v_d, mu_d)
    return mu_d


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def friction_slope_at_zero_slip(mu_s, v_s):
    """dμ/ds at s = 0 of :func:`friction_coefficient` [s m^-1]: ``1.5·μ_s/v_s``.

    The friction law acts as a viscous damper of ``c_f = Q·dμ/ds`` at small slip; the
    explicit step is sized from it (:func:`rvcore.integrator.stable_time_step`).
    """
    return 1.5 * mu_s / v_s


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def ring_rotation(tilt_x, tilt_y):
    """Rotation matrix ``R = Ry(θy)·Rx(θx)`` of the inner ring, row by row [-].

    Returns ``(r00, r01, r02, r10, r11, r12, r20, r21, r22)``; a point fixed in the ring
    at ``p`` (ring frame) is at ``r_ring + R·p``.
    """
    ca, sa, cb, sb = math.cos(tilt_x), math.sin(tilt_x), math.cos(tilt_y), math.sin(tilt_y)
    return cb, sb * sa, sb * ca, 0.0, ca, -sa, -sb, cb * sa, cb * ca


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def ring_angular_velocity(w_ring, tilt_rate_x, tilt_rate_y, r00, r20, r02, r12, r22):
    """Inertial angular velocity Ω of the inner ring [rad s^-1] (module notes).

    ``w_ring`` is the prescribed spin about the ring's own axis ``R·ẑ = (r02, r12, r22)``;
    ``r00 = cos θy`` and ``r20 = −sin θy`` turn the tilt rate about x into Ry(θy)·x̂.
    """
    return (tilt_rate_x * r00 + w_ring * r02, tilt_rate_y + w_ring * r12,
            tilt_rate_x * r20 + w_ring * r22)


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def arc_penetration(plx, ply, plz, rho, inv_rho, cr, cz, rmh, side, half_d):
    """Penetration of a ball into one groove arc, in the ring's own frame.

    Parameters
    ----------
    plx, ply, plz : float
        Ball centre in the ring frame, axial coordinate relative to the row plane [m].
    rho, inv_rho : float
        ``√(plx² + ply²)`` and its inverse (computed once per ring, not per arc).
    cr, cz : float
        Arc centre: distance from the axis and axial offset [m].
    rmh : float
        ``(f − ½)·D`` [m].
    side : float
        0, or ±1 for an arc that exists only on that side of the groove mid-plane.
    half_d : float
        Ball radius [m].

    Returns
    -------
    delta : float
        Penetration [m] (≤ 0: no contact; −1 when the arc does not exist there).
    nx, ny, nz : float
        Unit normal C→P in the ring frame.
    """
    dr = rho - cr
    dz = plz - cz
    dist = math.sqrt(dr * dr + dz * dz)
    delta = dist - rmh
    inv = 1.0 / dist
    nr = dr * inv
    nz = dz * inv
    nx = nr * plx * inv_rho
    ny = nr * ply * inv_rho
    if side != 0.0 and side * (plz + half_d * nz) < 0.0:
        delta = -1.0
    return delta, nx, ny, nz


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def normal_force(delta, delta_rate, k, c_max, inv_dmax):
    """Hertz force with the IMPACT damper, clipped at zero [N] (δ > 0).

    ``STEP(δ, 0, 0, d_max, c_max)`` written with ``inv_dmax = 1/d_max`` so that no
    division is left in the contact loop.
    """
    d = delta * inv_dmax
    c = c_max if d >= 1.0 else c_max * d * d * (3.0 - 2.0 * d)
    q = k * delta * math.sqrt(delta) + c * delta_rate
    return q if q > 0.0 else 0.0


@njit(cache=True, nogil=True, inline="always", fastmath=FAST, error_model="numpy")
def friction_force(ux, uy, uz, nx, ny, nz, un, q, mu_s, v_s, mu_d, v_d, inv_vs, inv_dv):
    """Coulomb friction on the ball for slip velocity ``u`` at a contact of normal ``n``.

    ``un = u·n``; the slip is ``v_t = u − un·n`` and the force ``−μ(|v_t|)·q·v_t/|v_t|``
    (zero at zero slip) [N]. ``inv_vs = 1/v_s`` and ``inv_dv = 1/(v_d − v_s)``.

    Notes
    -----
    Below ``v_s`` the law of :func:`friction_coefficient` is, with ``x = s/v_s``,
    ``STEP(s, −v_s, −μ_s, v_s, μ_s) = μ_s·(1.5·x − 0.5·x³)``, so
    ``μ/s = μ_s·(1.5 − 0.5·x²)/v_s`` needs neither ``s`` nor a division: the rolling
    contacts, whose slip is small, cost no square root here.
    """
    tx = ux - un * nx
    ty = uy - un * ny
    tz = uz - un * nz
    s2 = tx * tx + ty * ty + tz * tz
    x2 = s2 * inv_vs * inv_vs
    if x2 < 1.0:
        g = -q * mu_s * (1.5 - 0.5 * x2) * inv_vs
    else:
        s = math.sqrt(s2)
        if s <= v_d:
            d = (s - v_s) * inv_dv
            mu = mu_s + (mu_d - mu_s) * d * d * (3.0 - 2.0 * d)
        else:
            mu = mu_d
        g = -mu * q / s
    return g * tx, g * ty, g * tz


@njit(cache=True, nogil=True, fastmath=FAST, error_model="numpy")
def rhs(t, y, dy, params, rows, arcs, pockets, table, meta, diag, bdiag):
    """dy/dt of the whole bearing at time ``t``; also fills ``diag`` and ``bdiag``."""
    # ---- applied loads and the prescribed speed
    fr = channel_value(table, meta, CH_RADIAL, t)
    fa = channel_value(table, meta, CH_AXIAL, t)
    w_ring = channel_value(table, meta, CH_SPEED, t)
    dw_ring = channel_rate(table, meta, CH_SPEED, t)
    mu_s, v_s, mu_d, v_d = params[P_MU_S], params[P_V_S], params[P_MU_D], params[P_V_D]
    inv_vs, inv_dv = 1.0 / v_s, 1.0 / (v_d - v_s)
    friction_on = params[P_FRICTION] != 0.0
    damp_scale = params[P_DAMPING]
    c_race = params[P_DAMP_C] * damp_scale
    inv_dmax = 1.0 / params[P_DAMP_D]

    gx, gy, gz = params[P_GX], params[P_GY], params[P_GZ]

    # ---- inner ring pose and its full angular velocity (spin about its tilted axis)
    xi, yi, zi, tx, ty = y[0], y[1], y[2], y[3], y[4]
    vxi, vyi, vzi, wxi, wyi = y[5], y[6], y[7], y[8], y[9]
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = ring_rotation(tx, ty)
    omx, omy, omz = ring_angular_velocity(w_ring, wxi, wyi, r00, r20, r02, r12, r22)

    fxi, fyi, fzi, mxi, myi = 0.0, 0.0, 0.0, 0.0, 0.0
    max_qi, max_qo, loaded, max_p3, max_pen, pen_ball = 0.0, 0.0, 0.0, 0.0, 0.0, -1.0
    cos_sum, cos_balls = 0.0, 0.0

    for r in range(rows.shape[0]):
        nz_balls = int(rows[r, R_Z])
        b0 = int(rows[r, R_BALL0])
        c0 = int(rows[r, R_CAGE0])
        p0 = int(rows[r, R_POCKET0])
        a0 = int(rows[r, R_ARC0])
        na = int(rows[r, R_NARC])
        zrow = rows[r, R_ZROW]
        h = rows[r, R_HALF_D]
        inv_mb = 1.0 / rows[r, R_MB]
        inv_ib = 1.0 / rows[r, R_IB]
        pocket_r = rows[r, R_POCKET_R]
        k_pocket = rows[r, R_POCKET_K]
        pc3_pocket = rows[r, R_POCKET_PC]
        c_pocket = params[P_POCKET_C] * damp_scale
        cage_ri, cage_ro = rows[r, R_CAGE_RI], rows[r, R_CAGE_RO]

        xc, yc, zc, phi = y[c0], y[c0 + 1], y[c0 + 2], y[c0 + 3]
        vxc, vyc, vzc, wc = y[c0 + 4], y[c0 + 5], y[c0 + 6], y[c0 + 7]
        cphi, sphi = math.cos(phi), math.sin(phi)
        fxc, fyc, fzc, tzc = 0.0, 0.0, 0.0, 0.0

        for j in range(nz_balls):
            b = b0 + BALL_STATES * j
            px, py, pz = y[b], y[b + 1], y[b + 2]
            vx, vy, vz = y[b + 3], y[b + 4], y[b + 5]
            wx, wy, wz = y[b + 6], y[b + 7], y[b + 8]
            fbx, fby, fbz, mbx, mby, mbz = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            qi_sum, qo_sum, fi_rad, fo_rad = 0.0, 0.0, 0.0, 0.0
            cos_b, n_b = 0.0, 0.0
            rho_b = math.sqrt(px * px + py * py)
            inv_rho_b = 1.0 / rho_b
            erx, ery = px * inv_rho_b, py * inv_rho_b

            # ball centre in the inner ring's frame: Rᵀ·(p − r_i)
            dxg, dyg, dzg = px - xi, py - yi, pz - zi
            plx = r00 * dxg + r10 * dyg + r20 * dzg
            ply = r01 * dxg + r11 * dyg + r21 * dzg
            plz = r02 * dxg + r12 * dyg + r22 * dzg - zrow
            rho_l = math.sqrt(plx * plx + ply * ply)
            inv_rho_l = 1.0 / rho_l

            for a in range(a0, a0 + na):
                inner = arcs[a, A_RING] == 0.0
                if inner:
                    delta, nlx, nly, nlz = arc_penetration(plx, ply, plz, rho_l, inv_rho_l, arcs[a, A_CR],
                                                           arcs[a, A_CZ], arcs[a, A_RMH], arcs[a, A_SIDE], h)
                else:
                    delta, nlx, nly, nlz = arc_penetration(px, py, pz - zrow, rho_b, inv_rho_b, arcs[a, A_CR],
                                                           arcs[a, A_CZ], arcs[a, A_RMH], arcs[a, A_SIDE], h)
                if delta <= 0.0:
                    continue
                if delta > max_pen:
                    max_pen = delta
                    pen_ball = b
                if inner:
                    nx = r00 * nlx + r01 * nly + r02 * nlz
                    ny = r10 * nlx + r11 * nly + r12 * nlz
                    nz = r20 * nlx + r21 * nly + r22 * nlz
                else:
                    nx, ny, nz = nlx, nly, nlz
                # contact point on the ball, and the arm from the ball centre
                ax, ay, az = h * nx, h * ny, h * nz
                cx, cy, cz = px + ax, py + ay, pz + az
                # slip of the ball's material point against the race's
                ux = vx + wy * az - wz * ay
                uy = vy + wz * ax - wx * az
                uz = vz + wx * ay - wy * ax
                if inner:
                    # the race's material point: v_ring + Ω × (c − r_ring)
                    qx, qy, qz = cx - xi, cy - yi, cz - zi
                    ux -= vxi + omy * qz - omz * qy
                    uy -= vyi + omz * qx - omx * qz
                    uz -= vzi + omx * qy - omy * qx
                un = ux * nx + uy * ny + uz * nz
                q = normal_force(delta, un, arcs[a, A_K], c_race, inv_dmax)
                if q <= 0.0:
                    continue
                fx, fy, fz = -q * nx, -q * ny, -q * nz
                if friction_on:
                    ftx, fty, ftz = friction_force(ux, uy, uz, nx, ny, nz, un, q, mu_s, v_s, mu_d, v_d, inv_vs, inv_dv)
                    fx += ftx
                    fy += fty
                    fz += ftz
                    mbx += ay * ftz - az * fty
                    mby += az * ftx - ax * ftz
                    mbz += ax * fty - ay * ftx
                fbx += fx
                fby += fy
                fbz += fz
                cos_b += abs(nx * erx + ny * ery)
                n_b += 1.0
                p3 = arcs[a, A_PC3] * q
                if p3 > max_p3:
                    max_p3 = p3
                if inner:
                    # reaction on the ring, and its moment about the ring centre
                    fxi -= fx
                    fyi -= fy
                    fzi -= fz
                    mxi -= qy * fz - qz * fy
                    myi -= qz * fx - qx * fz
                    qi_sum += q
                    fi_rad += fx * erx + fy * ery
                else:
                    qo_sum += q
                    fo_rad += fx * erx + fy * ery

            if qi_sum > 0.0 or qo_sum > 0.0:
                loaded += 1.0
                if r == 0:
                    cos_sum += cos_b / n_b
                    cos_balls += 1.0
            if qi_sum > max_qi:
                max_qi = qi_sum
            if qo_sum > max_qo:
                max_qo = qo_sum

            # ---- ball–pocket: a cylindrical pocket with its axis radial through the cage centre
            cs0, sn0 = pockets[p0 + j, 0], pockets[p0 + j, 1]
            cth = cphi * cs0 - sphi * sn0
            sth = sphi * cs0 + cphi * sn0
            dxp, dyp, dzp = px - xc, py - yc, pz - zc - zrow
            rad = dxp * cth + dyp * sth            # ball station along the pocket axis
            tan = -dxp * sth + dyp * cth           # offset across it, circumferential
            dperp2 = tan * tan + dzp * dzp
            dperp = 0.0
            qp = 0.0
            # the ball's section is never wider than h: no contact unless dperp + h > pocket_r
            if dperp2 > (pocket_r - h) * (pocket_r - h):
                dperp = math.sqrt(dperp2)
                # the cage ring spans [cage_ri, cage_ro]: the ball meets the pocket wall at
                # the station nearest its centre, where its section radius is a_sec
                station = min(max(rad, cage_ri), cage_ro) - rad
                a_sec = math.sqrt(max(h * h - station * station, 0.0))
                delta = dperp + a_sec - pocket_r
            else:
                station, a_sec, delta = 0.0, h, -1.0
            if delta > 0.0 and dperp > 0.0 and a_sec > 1e-3 * h:
                if delta > max_pen:
                    max_pen = delta
                    pen_ball = b
                inv = 1.0 / dperp
                nx = (-tan * sth) * inv
                ny = (tan * cth) * inv
                nz = dzp * inv
                # arm from the ball centre to the contact; the force is −Q·∇δ, which lies
                # along the arm (a sphere's normal passes through its centre)
                ax = a_sec * nx + station * cth
                ay = a_sec * ny + station * sth
                az = a_sec * nz
                # ∇δ (not named gx…: those hold gravity)
                dgx, dgy, dgz = ax / a_sec, ay / a_sec, az / a_sec
                cx, cy, cz = px + ax, py + ay, pz + az
                ux = vx + wy * az - wz * ay - (vxc - wc * (cy - yc))
                uy = vy + wz * ax - wx * az - (vyc + wc * (cx - xc))
                uz = vz + wx * ay - wy * ax - vzc
                un = ux * dgx + uy * dgy + uz * dgz
                qp = normal_force(delta, un, k_pocket, c_pocket, inv_dmax)
                if qp > 0.0:
                    fx, fy, fz = -qp * dgx, -qp * dgy, -qp * dgz
                    if friction_on:
                        inv_h = 1.0 / h
                        nx, ny, nz = ax * inv_h, ay * inv_h, az * inv_h
                        un = ux * nx + uy * ny + uz * nz
                        ftx, fty, ftz = friction_force(ux, uy, uz, nx, ny, nz, un, qp, mu_s, v_s, mu_d, v_d, inv_vs, inv_dv)
                        fx += ftx
                        fy += fty
                        fz += ftz
                        mbx += ay * ftz - az * fty
                        mby += az * ftx - ax * ftz
                        mbz += ax * fty - ay * ftx
                    fbx += fx
                    fby += fy
                    fbz += fz
                    fxc -= fx
                    fyc -= fy
                    fzc -= fz
                    tzc -= (cx - xc) * fy - (cy - yc) * fx
                    p3 = pc3_pocket * qp
                    if p3 > max_p3:
                        max_p3 = p3

            bdiag[p0 + j, B_QI] = qi_sum
            bdiag[p0 + j, B_QO] = qo_sum
            bdiag[p0 + j, B_FIR] = fi_rad
            bdiag[p0 + j, B_FOR] = fo_rad
            bdiag[p0 + j, B_QP] = qp

            dy[b] = vx
            dy[b + 1] = vy
            dy[b + 2] = vz
            dy[b + 3] = fbx * inv_mb + gx
            dy[b + 4] = fby * inv_mb + gy
            dy[b + 5] = fbz * inv_mb + gz
            dy[b + 6] = mbx * inv_ib
            dy[b + 7] = mby * inv_ib
            dy[b + 8] = mbz * inv_ib

        # ---- cage–land contact (outer-ring land, fixed)
        if rows[r, R_GUIDE] == GUIDE_OUTER_LAND:
            ecc = math.sqrt(xc * xc + yc * yc)
            delta = ecc - rows[r, R_LAND_CLEAR]
            if delta > 0.0:
                nx, ny = xc / ecc, yc / ecc
                # cage surface point at the land and its velocity (the land is at rest)
                ux = vxc - wc * cage_ro * ny
                uy = vyc + wc * cage_ro * nx
                uz = vzc
                un = ux * nx + uy * ny
                ql = normal_force(delta, un, rows[r, R_LAND_K], params[P_LAND_C] * damp_scale, inv_dmax)
                if ql > 0.0:
                    fxc -= ql * nx
                    fyc -= ql * ny
                    if friction_on:
                        ftx, fty, ftz = friction_force(ux, uy, uz, nx, ny, 0.0, un, ql, mu_s, v_s, mu_d, v_d, inv_vs, inv_dv)
                        fxc += ftx
                        fyc += fty
                        fzc += ftz
                        tzc += cage_ro * (nx * fty - ny * ftx)

        mc = rows[r, R_CAGE_M]
        dy[c0] = vxc
        dy[c0 + 1] = vyc
        dy[c0 + 2] = vzc
        dy[c0 + 3] = wc
        dy[c0 + 4] = fxc / mc + gx
        dy[c0 + 5] = fyc / mc + gy
        dy[c0 + 6] = fzc / mc + gz
        dy[c0 + 7] = tzc / rows[r, R_CAGE_I]

    # ---- inner ring: applied loads, contact reactions, small-tilt Euler equations
    lc, ls = params[P_LOAD_COS], params[P_LOAD_SIN]
    m_ring, ip, it = params[P_RING_M], params[P_RING_IP], params[P_RING_IT]
    moment = params[P_MOMENT]  # constant tilting moment about the axis normal to F_r
    dy[0] = vxi
    dy[1] = vyi
    dy[2] = vzi
    dy[3] = wxi
    dy[4] = wyi
    dy[5] = (fxi + fr * lc) / m_ring + gx
    dy[6] = (fyi + fr * ls) / m_ring + gy
    dy[7] = (fzi + fa) / m_ring + gz
    dy[8] = (mxi - moment * ls - ip * (dw_ring * ty + w_ring * wyi)) / it
    dy[9] = (myi + moment * lc + ip * (dw_ring * tx + w_ring * wxi)) / it

    diag[D_MAX_QI] = max_qi
    diag[D_MAX_QO] = max_qo
    diag[D_LOADED] = loaded
    diag[D_MAX_P3] = max_p3
    diag[D_MAX_PEN] = max_pen
    diag[D_PEN_BALL] = pen_ball
    diag[D_COS_ALPHA] = cos_sum / cos_balls if cos_balls > 0.0 else 0.0


@njit(cache=True, nogil=True)
def potential_energy(t, y, params, rows, arcs, pockets, table, meta):
    """Elastic energy of every contact minus the work potential of the applied loads [J].

    ``Σ ⅖·K·δ^2.5`` over ball–race, ball–pocket and cage–land contacts, minus
    ``F·r_ring + M·θ`` with the loads at ``t`` held constant, minus ``Σ m·g·r`` of every
    body (gravity). With the kinetic energy
    (:func:`rvcore.integrator.kinetic_energy`) it is conserved when friction and damping
    are off, the loads are constant and the ring does not spin.
    """
    fr = channel_value(table, meta, CH_RADIAL, t)
    fa = channel_value(table, meta, CH_AXIAL, t)
    lc, ls, moment = params[P_LOAD_COS], params[P_LOAD_SIN], params[P_MOMENT]
    gx, gy, gz = params[P_GX], params[P_GY], params[P_GZ]
    xi, yi, zi, tx, ty = y[0], y[1], y[2], y[3], y[4]
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = ring_rotation(tx, ty)
    e = -(fr * lc * xi + fr * ls * yi + fa * zi) - moment * (-ls * tx + lc * ty)
    e -= params[P_RING_M] * (gx * xi + gy * yi + gz * zi)
    for r in range(rows.shape[0]):
        b0, c0, p0 = int(rows[r, R_BALL0]), int(rows[r, R_CAGE0]), int(rows[r, R_POCKET0])
        a0, na = int(rows[r, R_ARC0]), int(rows[r, R_NARC])
        zrow, h = rows[r, R_ZROW], rows[r, R_HALF_D]
        xc, yc, zc, phi = y[c0], y[c0 + 1], y[c0 + 2], y[c0 + 3]
        cphi, sphi = math.cos(phi), math.sin(phi)
        e -= rows[r, R_CAGE_M] * (gx * xc + gy * yc + gz * zc)
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            px, py, pz = y[b], y[b + 1], y[b + 2]
            e -= rows[r, R_MB] * (gx * px + gy * py + gz * pz)
            dxg, dyg, dzg = px - xi, py - yi, pz - zi
            plx = r00 * dxg + r10 * dyg + r20 * dzg
            ply = r01 * dxg + r11 * dyg + r21 * dzg
            plz = r02 * dxg + r12 * dyg + r22 * dzg - zrow
            rho_l = math.sqrt(plx * plx + ply * ply)
            rho_b = math.sqrt(px * px + py * py)
            for a in range(a0, a0 + na):
                if arcs[a, A_RING] == 0.0:
                    d, _, _, _ = arc_penetration(plx, ply, plz, rho_l, 1.0 / rho_l, arcs[a, A_CR], arcs[a, A_CZ],
                                                 arcs[a, A_RMH], arcs[a, A_SIDE], h)
                else:
                    d, _, _, _ = arc_penetration(px, py, pz - zrow, rho_b, 1.0 / rho_b, arcs[a, A_CR],
                                                 arcs[a, A_CZ], arcs[a, A_RMH], arcs[a, A_SIDE], h)
                if d > 0.0:
                    e += 0.4 * arcs[a, A_K] * d * d * math.sqrt(d)
            cs0, sn0 = pockets[p0 + j, 0], pockets[p0 + j, 1]
            cth = cphi * cs0 - sphi * sn0
            sth = sphi * cs0 + cphi * sn0
            dxp, dyp, dzp = px - xc, py - yc, pz - zc - zrow
            rad = dxp * cth + dyp * sth
            tan = -dxp * sth + dyp * cth
            station = min(max(rad, rows[r, R_CAGE_RI]), rows[r, R_CAGE_RO]) - rad
            a_sec = math.sqrt(max(h * h - station * station, 0.0))
            d = math.sqrt(tan * tan + dzp * dzp) + a_sec - rows[r, R_POCKET_R]
            # the same guard as rhs(): no pocket contact where the ball's section at the
            # cage ring has shrunk to nothing (the ball is past the ring's edge)
            if d > 0.0 and a_sec > 1e-3 * h:
                e += 0.4 * rows[r, R_POCKET_K] * d * d * math.sqrt(d)
        if rows[r, R_GUIDE] == GUIDE_OUTER_LAND:
            d = math.sqrt(xc * xc + yc * yc) - rows[r, R_LAND_CLEAR]
            if d > 0.0:
                e += 0.4 * rows[r, R_LAND_K] * d * d * math.sqrt(d)
    return e
