"""Numba kernels: the equations of motion (rhs). SI throughout.

Every function here is a kernel (``rvcore._numba.kernel``) on flat arrays (layouts in :mod:`rvcore.bearing.layout`); none
allocates. The right-hand side :func:`rhs` is the whole model; it, the energy
(:mod:`rvcore.dynamics.energy`) and the quasi-static solver take every contact law (the STEP, the
normal force with its damper, the friction law) and penetration from
:mod:`rvcore.contact.laws`, their one home.

Inner-ring kinematics (docs/model.md §1). The ring's pose is ``R = Ry(θy)·Rx(θx)`` and it
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

A flexible ring's modes (:mod:`rvcore.dynamics.ring_modes`, states after the rows) move its
raceway at every ball (:func:`rvcore.dynamics.races.ring_surfaces`) and take the balls'
normal forces on it as their generalized forces.

The applied loads are the profile's channels at ``t`` (:mod:`rvcore.profile`):
``F_ext = F_r·(cos ψ, sin ψ, 0) + F_a·ẑ`` and the tilting moment ``M·(−sin ψ, cos ψ, 0)``
(about the axis normal to the radial load) added to ``(M_x, M_y)``; ψ is read per call
and its cosine and sine taken there, so a profile may turn the load.
"""
from __future__ import annotations

import math

import numpy as np
from .._numba import kernel

from ..contact.laws import (LOADED_BALL_LOAD, NO_FILM, NO_FILM_CONSTANTS, damping_coefficient, friction_force,
                            friction_kind, friction_uses_film, hertz_load, land_penetration, normal_force)
from ..contact.pose import ring_angular_velocity, ring_rotation, ring_to_global
from ..bearing.laws import FRICTION_LAW_SIZE, LAW_ON
from .tangent import (FX_ANG, J_COUPLED, J_FX, J_KA, J_W, N_FX, N_JWORK, contact_blocks, friction_tangent,
                       groove_blocks, modal_blocks, stiffness_blocks)
from ..bearing.layout import (A_K, A_PC3, A_RING, A_RMH, BALL_STATES, GUIDE_OUTER_LAND, MAX_ROW_ARCS, P_DAMP_C, P_DAMP_D, P_DAMPING, P_GX,
                    P_GY, P_GZ, P_LAND_C, P_LAW, P_LUB_SIGMA, P_POCKET_C, P_RING_IP, P_RING_IT, P_RING_M,
                    P_TILT_HELD, R_ARC0, R_BALL0, R_CAGE0, R_CAGE_I, R_CAGE_M, R_CAGE_RI,
                    R_CAGE_RO, R_GUIDE, R_HALF_D, R_IB, R_LAND_CLEAR, R_LAND_K, R_MB, R_NARC,
                    R_PITCH_R, R_POCKET0, R_POCKET_K, R_POCKET_PC, R_POCKET_R, R_Z, R_ZROW)
from ..output_table import N_ROW_SIGNALS, N_SIGNALS, ROW_SLOT, SLOT, signal_count
from ..profile import CH_AXIAL, CH_DIRECTION, CH_MOMENT, CH_RADIAL, CH_SPEED, channel_rate, channel_value
from .races import (C_DD, C_DELTA, C_H, C_LAM, C_LOG_HC, C_LOG_LAM, C_P, C_FX, C_FY, C_FZ, C_MX, C_MY, C_MZ, C_NLX, C_NLY, C_NLZ, C_NX, C_NY, C_NZ, C_Q,
                    C_UN, C_UX, C_UY, C_UZ, G_D_HALF, G_INV_RHO_B, G_INV_RHO_L, G_PLX, G_PLY, P_AX, P_AY, P_AZ, P_DELTA,
                    P_DGX, P_DGY, P_DGZ, P_FX, P_FY, P_FZ, P_MX, P_MY, P_MZ, P_Q, P_QH, P_UN, P_UX, P_UY, P_UZ,
                    POCKET, SCRATCH_SIZE, W, arc, arc_contacts, arc_film, ball_geometry, gather_balls, smallest_film,
                    pocket_contacts, raceway_offsets, ring_forces, ring_surfaces, scratch, G_FM)
from .raceway import spin_of
from .ring_modes import clear_modal_forces, flexible, modal_rhs

# The slots of the diagnostics vector this kernel writes, by the names of the output
# table (rvcore.output_table.SIGNALS, where each is described with its units). rhs() writes
# them all; rhs_stage() (the intermediate stages, where nobody reads them) writes only
# those marked "stage" there, the drive torque among them.
D_MAX_QI, D_MAX_QO, D_LOADED, D_MAX_P3, D_MAX_PEN, D_PEN_BALL, D_DRIVE_TORQUE = (SLOT[n] for n in (
    "max_inner_contact_load", "max_outer_contact_load", "loaded_ball_count", "max_contact_pressure_cubed",
    "max_penetration", "penetration_ball", "drive_torque"))
(D_FRICTION_POWER, D_DAMPING_POWER, D_TILT_POWER, D_MAX_QP, D_LAND_Q, D_MAX_SLIDE2, D_MAX_PV6,
 D_RACE_P3, D_SIN_MIN, D_SIN_MAX, D_DRIVE_POWER, D_HOLD_MX, D_HOLD_MY) = (SLOT[n] for n in (
    "friction_power", "damping_power", "tilt_power", "max_pocket_force", "cage_land_force",
    "max_race_sliding_speed_squared", "max_race_pv_sixth", "max_race_pressure_cubed", "sin_contact_angle_min",
    "sin_contact_angle_max", "drive_power", "tilt_reaction_moment_x", "tilt_reaction_moment_y"))
D_FILM_C, D_FILM_MIN, D_FILM_LAMBDA = (SLOT[n] for n in (
    "film_central", "film_minimum", "film_parameter"))
D_RING_W, D_RING_U = SLOT["max_ring_radial_deformation"], SLOT["max_ring_axial_deformation"]
#: Row r's mean cos α of its loaded balls (for its epicyclic cage speed) is at
#: ``D_ROW0 + D_ROW_STRIDE·r + D_COS_ALPHA``.
D_ROW0, D_ROW_STRIDE, D_COS_ALPHA = N_SIGNALS, N_ROW_SIGNALS, ROW_SLOT["cos_contact_angle"]
# per-ball diag columns: total inner / outer race load, radial components of the inner /
# outer race forces on the ball (outward positive), pocket load, and the pocket's elastic
# energy and its rate (0.4·Q·δ, Q·δ̇ of the Hertz part: rvcore.integrate.imex's impact check)
B_QI, B_QO, B_FIR, B_FOR, B_QP, B_PV, B_PP = 0, 1, 2, 3, 4, 5, 6
# then the ball's film constants at each of its row's arcs, held through a step's stages,
# and whether they are kept: arc slot s's from B_FILM + FILM_HELD·s (rvcore.dynamics.races.arc_film)
B_FILM, FILM_HELD = 7, 4
N_BDIAG = B_FILM + FILM_HELD * MAX_ROW_ARCS
#: What :func:`_rhs` computes besides dy/dt: the designer's diagnostics (MODE_FULL), only
#: what the integrator needs (MODE_STAGE), or the diagnostics and the IMEX tangents
#: (MODE_JAC). Floats, not booleans: numba compiles a function once per value of a
#: boolean or integer constant argument, and :func:`_rhs` takes half a minute to compile.
MODE_STAGE, MODE_FULL, MODE_JAC = 0.0, 1.0, 2.0


def new_diagnostics(n_rows: int, n_balls: int, n_sensors: int = 0):
    """Empty ``(diag, bdiag)``: the signals of rvcore.output_table for ``n_rows`` rows and
    ``n_sensors`` sensors, then the ball contacts' scratch of :mod:`rvcore.dynamics.races` (at the
    end), and the per-ball loads that :func:`rhs` writes."""
    return np.zeros(signal_count(n_rows, n_sensors) + SCRATCH_SIZE), np.zeros((n_balls, N_BDIAG))


@kernel
def rhs(t, y, dy, params, rows, arcs, pockets, table, meta, diag, bdiag):
    """dy/dt of the whole bearing at time ``t``; also fills ``diag`` and ``bdiag``.

    Notes
    -----
    The designer's diagnostics (``D_DRIVE_TORQUE`` …) come from the forces of
    this same evaluation, no second pass. :func:`rhs_stage` neither computes nor writes
    the slots from ``D_FRICTION_POWER`` on; the drive torque it does.

    - Drive torque ``T = I_p·ω̇ − M_c·e``: ``M_c`` the contact forces' moment on the
      ring about its centre, ``e = R·ẑ`` the spin axis.
    - Friction power ``Σ −F_t·u`` (``u`` the slip of the ball's or cage's material
      point against the other body's; ``F_t·u = F·u + q·u_n`` since ``F = −q·n + F_t``);
      damping power ``Σ (q − K·δ^1.5)·δ̇``, which counts a clipped (zero) force too.
    - The energy balance these give (derived in tests/core/test_energy_balance.py)::

          T·ω + P_load = d/dt(E_kin + ½·I_p·ω² + V_el) + P_fric + P_damp + P_tilt
          P_tilt = θ̇x·(M_x·(cos θy − 1) − M_z·sin θy) − I_p·ω̇·(θx·θ̇y − θy·θ̇x)

      ``P_tilt`` is what the small-tilt ring equations leave out of the rigid ring's
      power (they put ``M_x`` where ``M·(Ry·x̂)`` belongs, and ``I_p·ω̇`` works on the
      tilts); it is second order in the tilt and reported as ``D_TILT_POWER``. ``P_load``,
      the applied loads' and gravity's power, is not sampled here: the loop takes their
      work over each step from the positions' change (:func:`rvcore.integrate.loop.integrate`).
    """
    _rhs(t, y, dy, params, rows, arcs, pockets, table, meta, diag, bdiag, MODE_FULL, 0.0, bdiag, bdiag)


@kernel
def rhs_stage(t, y, dy, params, rows, arcs, pockets, table, meta, diag, bdiag):
    """:func:`rhs` without the designer's diagnostics (the slots from D_FRICTION_POWER
    on): the integrator's intermediate stages, whose diagnostics nobody reads: the same
    code, its branches for them not taken."""
    _rhs(t, y, dy, params, rows, arcs, pockets, table, meta, diag, bdiag, MODE_STAGE, 0.0, bdiag, bdiag)


@kernel
def rhs_jac(t, y, dy, params, rows, arcs, pockets, table, meta, diag, bdiag, hg, jwork, schur):
    """:func:`rhs`, and the stiff damping of every contact for the IMEX integrator.

    Besides everything :func:`rhs` does, accumulates ``hg·GᵀCG`` of every loaded contact
    into ``jwork`` (per ball) and ``schur`` (the ring; layouts and the tangent ``C`` in
    :mod:`rvcore.dynamics.tangent`), from the geometry and slips of this same evaluation.
    ``hg`` is ``h·γ`` [s].
    """
    _rhs(t, y, dy, params, rows, arcs, pockets, table, meta, diag, bdiag, MODE_JAC, hg, jwork, schur)


@kernel
def _rhs(t, y, dy, params, rows, arcs, pockets, table, meta, diag, bdiag, mode, hg, jwork, schur):
    """The body of :func:`rhs` (``mode`` MODE_FULL), :func:`rhs_stage` (MODE_STAGE) and
    :func:`rhs_jac` (MODE_JAC).

    One compiled function for the three, not one inlined into each: each copy cost the
    numba compile half a minute (docs/performance.md, "The numba compile"), and the
    branches on ``mode``, the same at every call of a loop, cost nothing measurable."""
    full = mode != MODE_STAGE
    jac = mode == MODE_JAC
    # ---- applied loads and the prescribed speed
    fr = channel_value(table, meta, CH_RADIAL, t)
    fa = channel_value(table, meta, CH_AXIAL, t)
    moment = channel_value(table, meta, CH_MOMENT, t)   # about (−sin ψ, cos ψ, 0), normal to F_r
    psi = channel_value(table, meta, CH_DIRECTION, t)
    lc, ls = math.cos(psi), math.sin(psi)
    w_ring = channel_value(table, meta, CH_SPEED, t)
    dw_ring = channel_rate(table, meta, CH_SPEED, t)
    cos_spin, sin_spin = spin_of(rows, table, meta, t)
    law = params[P_LAW:P_LAW + FRICTION_LAW_SIZE]     # the friction law (rvcore.bearing.laws)
    friction_on = law[LAW_ON] != 0.0
    film_law = friction_uses_film(friction_kind(law))
    # pockets and lands have no film (rvcore.contact.laws): the film, and the law's constants of it
    p_none, h_none, lam_none = NO_FILM
    f_none0, f_none1, f_none2 = NO_FILM_CONSTANTS
    damp_scale = params[P_DAMPING]
    c_race = params[P_DAMP_C] * damp_scale
    inv_dmax = 1.0 / params[P_DAMP_D]

    gx, gy, gz = params[P_GX], params[P_GY], params[P_GZ]
    buf = scratch(diag)    # rvcore.dynamics.races's (new_diagnostics)
    # flexible rings (rvcore.dynamics.ring_modes): their generalized forces are summed in dy
    flex = flexible(params)
    if flex:
        clear_modal_forces(params, dy)
    if jac:
        for i in range(schur.shape[0]):
            for k in range(schur.shape[1]):
                schur[i, k] = 0.0

    # ---- inner ring pose and its full angular velocity (spin about its tilted axis)
    xi, yi, zi, tx, ty = y[0], y[1], y[2], y[3], y[4]
    vxi, vyi, vzi, wxi, wyi = y[5], y[6], y[7], y[8], y[9]
    held = params[P_TILT_HELD] != 0.0
    if held:    # a held ring is square whatever its tilt states hold (they stay 0)
        tx, ty, wxi, wyi = 0.0, 0.0, 0.0, 0.0
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = ring_rotation(tx, ty)
    omx, omy, omz = ring_angular_velocity(w_ring, wxi, wyi, r00, r20, r02, r12, r22)

    fxi, fyi, fzi, mxi, myi, mzi = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    max_qi, max_qo, loaded, max_p3, max_pen, pen_ball = 0.0, 0.0, 0.0, 0.0, 0.0, -1.0
    # the designer's outputs (D_DRIVE_TORQUE …): sums and extremes over the contacts below
    p_fric, p_damp, max_qp, land_q = 0.0, 0.0, 0.0, 0.0
    max_s2, max_pv6, race_p3, sin_min, sin_max = 0.0, 0.0, 0.0, 2.0, -1.0
    # the smallest film over the loaded race contacts, as logarithms (docs/model.md, "The film
    # along the cycle"): log h_c, log λ; +inf while none is loaded
    log_hc_min, log_lam_min = math.inf, math.inf
    ring_w, ring_u = 0.0, 0.0
    for r in range(rows.shape[0]):
        cos_sum, cos_balls = 0.0, 0.0
        nz_balls = int(rows[r, R_Z])
        b0 = int(rows[r, R_BALL0])
        c0 = int(rows[r, R_CAGE0])
        p0 = int(rows[r, R_POCKET0])
        a0 = int(rows[r, R_ARC0])
        na = int(rows[r, R_NARC])
        zrow = rows[r, R_ZROW]
        h = rows[r, R_HALF_D]
        m_b = rows[r, R_MB]
        inv_mb = 1.0 / m_b
        inv_ib = 1.0 / rows[r, R_IB]
        pocket_r = rows[r, R_POCKET_R]
        k_pocket = rows[r, R_POCKET_K]
        pc3_pocket = rows[r, R_POCKET_PC]
        c_pocket = params[P_POCKET_C] * damp_scale
        cage_ri, cage_ro, guide, pitch_r = rows[r, R_CAGE_RI], rows[r, R_CAGE_RO], rows[r, R_GUIDE], rows[r, R_PITCH_R]

        # every ball's race contacts at once (rvcore.dynamics.races), read back ball by ball below
        gather_balls(y, buf, rows, r, pockets)
        ball_geometry(buf, nz_balls, xi, yi, zi, r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow)
        raceway_offsets(buf, rows, r, pockets, cos_spin, sin_spin)
        row_w, row_u = ring_surfaces(buf, params, y, nz_balls)
        ring_w, ring_u = max(ring_w, row_w), max(ring_u, row_u)
        for a in range(a0, a0 + na):
            arc_contacts(buf, buf[arc(a - a0):arc(a - a0 + 1)], nz_balls, arcs, a, h, xi, yi, zi,
                         vxi, vyi, vzi, omx, omy, omz, r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow, c_race,
                         inv_dmax, law)
            s = B_FILM + FILM_HELD * (a - a0)
            arc_film(buf[arc(a - a0):arc(a - a0 + 1)], nz_balls, arcs, a, h, law, bdiag[p0:p0 + nz_balls, s:s + FILM_HELD],
                     full)

        xc, yc, zc, phi = y[c0], y[c0 + 1], y[c0 + 2], y[c0 + 3]
        vxc, vyc, vzc, wc = y[c0 + 4], y[c0 + 5], y[c0 + 6], y[c0 + 7]
        cphi, sphi = math.cos(phi), math.sin(phi)
        pocket_contacts(buf, buf[POCKET:], nz_balls, guide, pitch_r, pocket_r, h, cage_ri, cage_ro, k_pocket,
                        c_pocket, inv_dmax, xc, yc, zc, cphi, sphi, vxc, vyc, vzc, wc, zrow, law)
        fxc, fyc, fzc, tzc = 0.0, 0.0, 0.0, 0.0

        for j in range(nz_balls):
            b = b0 + BALL_STATES * j
            px, py, pz = y[b], y[b + 1], y[b + 2]
            vx, vy, vz = y[b + 3], y[b + 4], y[b + 5]
            fbx, fby, fbz, mbx, mby, mbz = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            qi_sum, qo_sum, fi_rad, fo_rad = 0.0, 0.0, 0.0, 0.0
            cos_b, n_b = 0.0, 0.0
            f_ir, f_iz, f_or, f_oz = 0.0, 0.0, 0.0, 0.0    # normal forces on flexible rings
            inv_rho_b = buf[G_INV_RHO_B * W + j]
            if jac:
                for i in range(J_W):
                    jwork[p0 + j, i] = 0.0
                jwork[p0 + j, J_COUPLED] = 0.0    # contact_blocks sets it when it writes B
                for i in range(J_KA, N_JWORK):
                    jwork[p0 + j, i] = 0.0
            erx, ery = px * inv_rho_b, py * inv_rho_b
            if jac and flex:    # the modes' columns (rvcore.dynamics.tangent.modal_blocks)
                for i in range(J_FX, J_FX + N_FX):
                    jwork[p0 + j, i] = 0.0
                jwork[p0 + j, J_FX + FX_ANG] = erx
                jwork[p0 + j, J_FX + FX_ANG + 1] = ery

            # the ball centre in the inner ring's frame (Rᵀ·(p − r_i)), and ΔD/2 of an imperfect set
            plx, ply, inv_rho_l = buf[G_PLX * W + j], buf[G_PLY * W + j], buf[G_INV_RHO_L * W + j]
            d_half = buf[G_D_HALF * W + j]

            for a in range(a0, a0 + na):
                o = arc(a - a0) + j      # this contact's values (rvcore.dynamics.races)
                delta = buf[o + C_DELTA * W]
                if delta <= 0.0:
                    continue
                if delta > max_pen:
                    max_pen = delta
                    pen_ball = b
                inner = arcs[a, A_RING] == 0.0
                nx, ny, nz = buf[o + C_NX * W], buf[o + C_NY * W], buf[o + C_NZ * W]
                # contact point on the ball, and the arm from the ball centre
                ax, ay, az = h * nx, h * ny, h * nz
                cx, cy, cz = px + ax, py + ay, pz + az
                qx, qy, qz = cx - xi, cy - yi, cz - zi
                # slip of the ball's material point against the race's, and dδ/dt
                ux, uy, uz, un = buf[o + C_UX * W], buf[o + C_UY * W], buf[o + C_UZ * W], buf[o + C_UN * W]
                q = buf[o + C_Q * W]
                # the damper's dissipation: the normal force's power beyond the elastic one
                # (also when the force is clipped to zero and the spring unloads unresisted)
                if full:    # at dδ/dt with the grooves' modal velocity (rvcore.dynamics.races)
                    p_damp += (q - hertz_load(arcs[a, A_K], delta)) * buf[o + C_DD * W]
                if q <= 0.0:
                    continue
                if flex:
                    # the normal force q·n on the ring, radial and axial in its own frame
                    nlx, nly, nlz = buf[o + C_NLX * W], buf[o + C_NLY * W], buf[o + C_NLZ * W]
                    if inner:
                        f_ir += q * (nlx * plx + nly * ply) * inv_rho_l
                        f_iz += q * nlz
                    else:
                        f_or += q * (nlx * erx + nly * ery)
                        f_oz += q * nlz
                fx, fy, fz = buf[o + C_FX * W], buf[o + C_FY * W], buf[o + C_FZ * W]
                dmx, dmy, dmz = buf[o + C_MX * W], buf[o + C_MY * W], buf[o + C_MZ * W]
                if jac:
                    tvx, tvy, tvz = ux - un * nx, uy - un * ny, uz - un * nz
                    alpha, beta = friction_tangent(q, tvx, tvy, tvz, buf[o + C_P * W], buf[o + C_H * W],
                                                   buf[o + C_LAM * W], law)
                    cd = damping_coefficient(delta, c_race, inv_dmax)
                    # the Hertz stiffness k_n = dq/dδ = 1.5·K·δ^0.5, implicit too: h·γ·k_n
                    # along n, whose h·γ·(h·γ·k_n)·n·nᵀ is the (h·γ)²·K of the stage matrix
                    hk = hg * 1.5 * arcs[a, A_K] * math.sqrt(delta)
                    contact_blocks(jwork, p0 + j, schur, inner, hg, alpha, cd - alpha + hk, nx, ny, nz,
                                   beta, tvx, tvy, tvz, 0.0, 0.0, 0.0, 0.0, ax, ay, az,
                                   cx - xi, cy - yi, cz - zi, r00, r20)
                    stiffness_blocks(jwork, p0 + j, schur, inner, hk, nx, ny, nz, cx - xi, cy - yi, cz - zi,
                                     r00, r20)
                    # t ⊥ n in the groove's meridian plane (ring frame), for groove_blocks
                    nlx, nly, nlz = buf[o + C_NLX * W], buf[o + C_NLY * W], buf[o + C_NLZ * W]
                    mx, my = (plx * inv_rho_l, ply * inv_rho_l) if inner else (erx, ery)
                    tlx, tly, tlz = nlz * mx, nlz * my, -(nlx * mx + nly * my)
                    if inner:
                        tlx, tly, tlz = ring_to_global(tlx, tly, tlz, r00, r01, r02, r10, r11, r12, r20, r21, r22)
                    # |p − c| = δ + (f − ½)·D − d_half (an imperfect set's larger ball)
                    hkg = hg * q / (delta + arcs[a, A_RMH] - d_half)
                    if flex:
                        # the same two terms on the ring's modes, read at the ball's azimuth
                        # (cr, cz: −n·ê_r, −n·ẑ and −t·ê_r, −t·ẑ in the ring's frame)
                        modal_blocks(jwork, p0 + j, inner, hg * (cd + hk), hk, nx, ny, nz,
                                     -(nlx * mx + nly * my), -nlz, cx - xi, cy - yi, cz - zi, r00, r20)
                        modal_blocks(jwork, p0 + j, inner, hg * hkg, hkg, tlx, tly, tlz,
                                     -nlz * (mx * mx + my * my), nlx * mx + nly * my, px - xi, py - yi, pz - zi,
                                     r00, r20)
                    groove_blocks(jwork, p0 + j, schur, inner, hg, hkg,
                                  tlx, tly, tlz, px - xi, py - yi, pz - zi, r00, r20)
                mbx += dmx
                mby += dmy
                mbz += dmz
                fbx += fx
                fby += fy
                fbz += fz
                cos_b += abs(nx * erx + ny * ery)
                n_b += 1.0
                p3 = arcs[a, A_PC3] * q
                if p3 > max_p3:
                    max_p3 = p3
                if full:
                    # friction power −F_t·u = −F·u − q·u_n (F = −q·n + F_t on the ball)
                    p_fric -= fx * ux + fy * uy + fz * uz + q * un
                    # sliding speed |u_t|² and (p_max·s)⁶ = p³²·s²³: no root in the loop
                    s2 = ux * ux + uy * uy + uz * uz - un * un
                    if s2 > max_s2:
                        max_s2 = s2
                    pv6 = p3 * p3 * s2 * s2 * s2
                    if pv6 > max_pv6:
                        max_pv6 = pv6
                    if p3 > race_p3:
                        race_p3 = p3
                    sin_a = abs(nz)     # sine of the contact angle to the bearing's radial plane
                    if sin_a < sin_min:
                        sin_min = sin_a
                    if sin_a > sin_max:
                        sin_max = sin_a
                    # Hamrock–Dowson at this contact, from a film law's own pass
                    # (races.arc_film); without one, races.smallest_film after the row
                    if film_law:
                        lh, ll = buf[o + C_LOG_HC * W], buf[o + C_LOG_LAM * W]
                        if lh < log_hc_min:
                            log_hc_min = lh
                        if ll < log_lam_min:
                            log_lam_min = ll
                if inner:
                    # reaction on the ring, and its moment about the ring centre
                    fxi -= fx
                    fyi -= fy
                    fzi -= fz
                    mxi -= qy * fz - qz * fy
                    myi -= qz * fx - qx * fz
                    mzi -= qx * fy - qy * fx
                    qi_sum += q
                    fi_rad += fx * erx + fy * ery
                else:
                    qo_sum += q
                    fo_rad += fx * erx + fy * ery

            if flex:    # the ball's normal forces drive the rings' modes (ring_forces, below)
                buf[G_FM * W + j], buf[(G_FM + 1) * W + j] = f_ir, f_iz
                buf[(G_FM + 2) * W + j], buf[(G_FM + 3) * W + j] = f_or, f_oz
            if qi_sum > LOADED_BALL_LOAD and qo_sum > LOADED_BALL_LOAD:
                loaded += 1.0
            if qi_sum > 0.0 or qo_sum > 0.0:
                cos_sum += cos_b / n_b
                cos_balls += 1.0
            if qi_sum > max_qi:
                max_qi = qi_sum
            if qo_sum > max_qo:
                max_qo = qo_sum

            # ---- ball–pocket (rvcore.contact.laws.cage_pocket_penetration, rvcore.dynamics.races)
            o = POCKET + j
            delta = buf[o + P_DELTA * W]
            qp, pv, pp = 0.0, 0.0, 0.0
            fpx, fpy, fpz, mpx, mpy, mpz = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            if delta > 0.0:
                if delta > max_pen:
                    max_pen = delta
                    pen_ball = b
                ax, ay, az = buf[o + P_AX * W], buf[o + P_AY * W], buf[o + P_AZ * W]
                # ∇δ along the arm (not named gx…: those hold gravity)
                dgx, dgy, dgz = buf[o + P_DGX * W], buf[o + P_DGY * W], buf[o + P_DGZ * W]
                cx, cy, cz = px + ax, py + ay, pz + az
                ux, uy, uz, un = buf[o + P_UX * W], buf[o + P_UY * W], buf[o + P_UZ * W], buf[o + P_UN * W]
                qp, q_hertz = buf[o + P_Q * W], buf[o + P_QH * W]
                pv, pp = 0.4 * q_hertz * delta, q_hertz * un
                if full:
                    p_damp += (qp - q_hertz) * un
                if qp > 0.0:
                    # friction tangential to the ball's surface there, normal a/h
                    inv_h = 1.0 / h
                    fpx, fpy, fpz = buf[o + P_FX * W], buf[o + P_FY * W], buf[o + P_FZ * W]
                    mpx, mpy, mpz = buf[o + P_MX * W], buf[o + P_MY * W], buf[o + P_MZ * W]
                    if jac:
                        nfx, nfy, nfz = ax * inv_h, ay * inv_h, az * inv_h
                        unf = ux * nfx + uy * nfy + uz * nfz
                        tvx, tvy, tvz = ux - unf * nfx, uy - unf * nfy, uz - unf * nfz
                        alpha, beta = friction_tangent(qp, tvx, tvy, tvz, p_none, h_none, lam_none, law)
                        cd = damping_coefficient(delta, c_pocket, inv_dmax)
                        # the cage's side stays explicit (rvcore.dynamics.tangent)
                        contact_blocks(jwork, p0 + j, schur, False, hg, alpha, -alpha, nfx, nfy, nfz,
                                       beta, tvx, tvy, tvz, cd, dgx, dgy, dgz, ax, ay, az, 0.0, 0.0, 0.0, 0.0, 0.0)
                    fxc -= fpx
                    fyc -= fpy
                    fzc -= fpz
                    tzc -= (cx - xc) * fpy - (cy - yc) * fpx
                    p3 = pc3_pocket * qp
                    if p3 > max_p3:
                        max_p3 = p3
                    if full:
                        p_fric -= fpx * ux + fpy * uy + fpz * uz + qp * un
                        if qp > max_qp:
                            max_qp = qp

            bdiag[p0 + j, B_QI] = qi_sum
            bdiag[p0 + j, B_QO] = qo_sum
            bdiag[p0 + j, B_FIR] = fi_rad
            bdiag[p0 + j, B_FOR] = fo_rad
            bdiag[p0 + j, B_QP] = qp
            bdiag[p0 + j, B_PV] = pv
            bdiag[p0 + j, B_PP] = pp

            dy[b] = vx
            dy[b + 1] = vy
            dy[b + 2] = vz
            # race contacts plus the pocket's (zero without pocket contact)
            dy[b + 3] = (fbx + fpx) * inv_mb + gx
            dy[b + 4] = (fby + fpy) * inv_mb + gy
            dy[b + 5] = (fbz + fpz) * inv_mb + gz
            dy[b + 6] = (mbx + mpx) * inv_ib
            dy[b + 7] = (mby + mpy) * inv_ib
            dy[b + 8] = (mbz + mpz) * inv_ib

        if full and not film_law:    # the smallest film over the row's loaded race contacts
            for a in range(a0, a0 + na):
                lh, ll = smallest_film(buf, buf[arc(a - a0):arc(a - a0 + 1)], nz_balls, arcs, a, h)
                if lh < log_hc_min:
                    log_hc_min = lh
                if ll < log_lam_min:
                    log_lam_min = ll

        if flex:    # at each ball's angle in each ring
            ring_forces(buf, params, dy, nz_balls)

        # ---- cage–land contact (outer-ring land, fixed)
        if rows[r, R_GUIDE] == GUIDE_OUTER_LAND:
            delta, nx, ny = land_penetration(xc, yc, rows[r, R_LAND_CLEAR])
            if delta > 0.0:
                # cage surface point at the land and its velocity (the land is at rest)
                ux = vxc - wc * cage_ro * ny
                uy = vyc + wc * cage_ro * nx
                uz = vzc
                un = ux * nx + uy * ny
                ql = normal_force(delta, un, rows[r, R_LAND_K], params[P_LAND_C] * damp_scale, inv_dmax)
                if full:
                    p_damp += (ql - hertz_load(rows[r, R_LAND_K], delta)) * un
                if ql > 0.0:
                    fxc -= ql * nx
                    fyc -= ql * ny
                    if ql > land_q:
                        land_q = ql
                    if friction_on:
                        ftx, fty, ftz = friction_force(ux, uy, uz, nx, ny, 0.0, ql, f_none0, f_none1, f_none2, law,
                                                        friction_kind(law))
                        fxc += ftx
                        fyc += fty
                        fzc += ftz
                        tzc += cage_ro * (nx * fty - ny * ftx)
                        if full:
                            p_fric -= ftx * ux + fty * uy + ftz * uz

        mc = rows[r, R_CAGE_M]
        dy[c0] = vxc
        dy[c0 + 1] = vyc
        dy[c0 + 2] = vzc
        dy[c0 + 3] = wc
        dy[c0 + 4] = fxc / mc + gx
        dy[c0 + 5] = fyc / mc + gy
        dy[c0 + 6] = fzc / mc + gz
        dy[c0 + 7] = tzc / rows[r, R_CAGE_I]
        diag[D_ROW0 + D_ROW_STRIDE * r + D_COS_ALPHA] = cos_sum / cos_balls if cos_balls > 0.0 else 0.0

    # ---- inner ring: applied loads, contact reactions, small-tilt Euler equations
    m_ring, ip, it = params[P_RING_M], params[P_RING_IP], params[P_RING_IT]
    dy[0] = vxi
    dy[1] = vyi
    dy[2] = vzi
    dy[3] = wxi
    dy[4] = wyi
    dy[5] = (fxi + fr * lc) / m_ring + gx
    dy[6] = (fyi + fr * ls) / m_ring + gy
    dy[7] = (fzi + fa) / m_ring + gz
    if held:
        # the support takes the whole moment: the tilt equations' right-hand sides
        # (at zero tilt and tilt rate) with the opposite sign
        hold_x, hold_y = -(mxi - moment * ls), -(myi + moment * lc)
        dy[3] = dy[4] = dy[8] = dy[9] = 0.0
    else:
        hold_x, hold_y = 0.0, 0.0
        dy[8] = (mxi - moment * ls - ip * (dw_ring * ty + w_ring * wyi)) / it
        dy[9] = (myi + moment * lc + ip * (dw_ring * tx + w_ring * wxi)) / it
    if flex:
        modal_rhs(params, y, dy)

    diag[D_MAX_QI] = max_qi
    diag[D_MAX_QO] = max_qo
    diag[D_LOADED] = loaded
    diag[D_MAX_P3] = max_p3
    diag[D_MAX_PEN] = max_pen
    diag[D_PEN_BALL] = pen_ball
    # the drive: what the prescribed spin needs about its (tilted) axis e = R·ẑ
    torque = ip * dw_ring - (mxi * r02 + myi * r12 + mzi * r22)
    diag[D_DRIVE_TORQUE] = torque
    diag[D_DRIVE_POWER] = torque * w_ring
    if not full:
        return
    diag[D_FRICTION_POWER] = p_fric
    diag[D_DAMPING_POWER] = p_damp
    # the rigid ring's contact power on θ̇x is M·(Ry·x̂) = M_x·cos θy − M_z·sin θy, the
    # small-tilt equation above takes M_x; and I_p·ω̇ does work on the tilts (see Notes)
    diag[D_TILT_POWER] = wxi * (mxi * (r00 - 1.0) + mzi * r20) - ip * dw_ring * (tx * wyi - ty * wxi)
    diag[D_MAX_QP] = max_qp
    diag[D_LAND_Q] = land_q
    diag[D_MAX_SLIDE2] = max_s2
    diag[D_MAX_PV6] = max_pv6
    diag[D_RACE_P3] = race_p3
    diag[D_SIN_MIN] = sin_min
    diag[D_SIN_MAX] = sin_max
    diag[D_HOLD_MX] = hold_x
    diag[D_HOLD_MY] = hold_y
    loaded_film = log_lam_min < math.inf
    diag[D_FILM_C] = math.exp(log_hc_min) if loaded_film else math.nan
    diag[D_FILM_LAMBDA] = math.exp(log_lam_min) if loaded_film else math.nan
    diag[D_FILM_MIN] = diag[D_FILM_LAMBDA] * params[P_LUB_SIGMA] if loaded_film else math.nan
    diag[D_RING_W] = ring_w
    diag[D_RING_U] = ring_u
