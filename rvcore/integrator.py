"""Fixed-step RK4 in numba, with per-step phase accumulators and blow-up detection.

Why a fixed step, and how large
-------------------------------
The bearing is stiff in two ways, and both set a hard explicit stability limit that an
adaptive pair would only rediscover by rejecting steps:

1. *Contact oscillation.* A ball between two Hertz contacts has the linearised stiffness
   ``k = 1.5·K^(2/3)·Q^(1/3)`` per contact. Study bearing at Q = 3.5 kN (40 kN radial):
   K ≈ 4.5e10 N/m^1.5 → k ≈ 2.9e8 N/m, two contacts on m_b = 0.050 kg give
   ω_n = √(2k/m_b) ≈ 1.1e5 rad/s. RK4 is stable on the imaginary axis to
   |λ·dt| ≤ 2√2, so dt ≤ 2.6e-5 s.
2. *Friction at small slip.* The friction law rises from zero with slope
   dμ/ds = 1.5·μ_s/v_s = 1.5 s/m, a viscous damper ``c_f = 1.5·μ_s·Q/v_s`` ≈ 5.3e3 N s/m
   at 3.55 kN (the study's 30 kN + 10 kN). A ball between an inner and an outer contact
   has two tangential modes: translation (rate 2·c_f/m_b) and rolling-direction rotation
   (rate 2·c_f·r²/I_b = 5·c_f/m_b, the faster), so λ_f ≈ 5.4e5 1/s on the negative real
   axis, where RK4 is stable to |λ·dt| ≤ 2.785: dt ≤ 5.2e-6 s.

The friction limit dominates by ~5×, so the step is derived from it at the peak
quasi-static contact load of the cycle (times a dynamic margin), and is the same at
every step: deterministic, reproducible bit for bit, four right-hand-side evaluations
per step and no error norm. ``SolverSettings.step_safety`` scales it; the convergence
check of model.md §9.6 halves it tenfold. Beyond the limit the friction mode does not always
diverge: the saturating friction law can bound it into a slip chatter that spoils the
metrics silently, which is why the step is held below the limit rather than found by
trial. A step that turns out far too large is caught by the blow-up detection (non-finite state, penetration beyond 10 % of the ball diameter,
kinetic energy beyond a physical bound) and reported with the time and the body.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .contact import FAST, friction_slope_at_zero_slip, ring_rotation
from .kernels import (B_QI, B_QO, D_COS_ALPHA, D_DAMPING_POWER, D_DRIVE_TORQUE, D_FRICTION_POWER, D_HOLD_MX, D_HOLD_MY, D_LAND_Q,
                      D_DRIVE_POWER, D_LOAD_POWER, D_LOADED, D_MAX_P3, D_MAX_PEN, D_MAX_PV6, D_MAX_QI, D_MAX_QO, D_MAX_QP,
                      D_MAX_SLIDE2, D_PEN_BALL, D_RACE_P3, D_SIN_MAX, D_SIN_MIN, D_TILT_POWER, rhs, rhs_jac, rhs_stage)
from .imex import B1, B2, B3, B4, GAMMA, JAC_EVERY, imex_step
from .model import (BALL_STATES, P_RING_IP, P_RING_IT, P_RING_M,
                    R_BALL0, R_CAGE0, R_CAGE_I, R_CAGE_M, R_HALF_D, R_IB, R_MB, R_PITCH_R, R_POCKET0, R_Z)
from .static_rating import ISO76_BALL_PRESSURE
from .profile import CH_AXIAL, CH_DIRECTION, CH_MOMENT, CH_RADIAL, CH_SPEED, channel_rate, channel_value

#: Output columns of ``out``, in order, by their pipeline.md names; the sensor readings
#: follow in columns ``N_OUT + s``. The driver labels the columns from this tuple alone.
OUTPUT_SERIES = ("inner_ring_x", "inner_ring_y", "inner_ring_z", "inner_ring_tilt_x",
                 "inner_ring_tilt_y", "radial_displacement", "axial_displacement",
                 "applied_radial_load", "applied_axial_load", "inner_ring_speed", "cage_speed",
                 "max_inner_contact_load", "max_outer_contact_load", "loaded_ball_count",
                 "max_contact_pressure", "applied_moment", "load_direction",
                 "inner_ring_drive_torque", "friction_power", "max_pocket_force", "cage_land_force",
                 "max_race_sliding_speed", "max_race_pv", "min_contact_angle", "max_contact_angle",
                 "static_safety_factor", "tilt_reaction_moment_x", "tilt_reaction_moment_y")
(O_X, O_Y, O_Z, O_TX, O_TY, O_DR, O_DA, O_FR, O_FA, O_W, O_CAGE, O_QI, O_QO, O_LOADED,
 O_PMAX, O_M, O_PSI, O_TORQUE, O_PFRIC, O_QP, O_QLAND, O_SLIDE, O_PV, O_AMIN, O_AMAX,
 O_SSF, O_HOLD_X, O_HOLD_Y) = range(len(OUTPUT_SERIES))

#: ISO 76 (radial ball bearings): the contact pressure at the most heavily loaded
#: ball–race contact under the basic static load rating C_0, 4200 MPa.
ISO76_BALL_STRESS = ISO76_BALL_PRESSURE
N_OUT = len(OUTPUT_SERIES)

#: Tracked signals, one accumulator block each per phase: δ_r, δ_a, then sensor s at
#: ``SIG_SENSOR0 + s``.
SIG_DR, SIG_DA, SIG_SENSOR0 = 0, 1, 2
#: Columns of a signal's accumulator: samples, extremes, the times of the extremes, and
#: the running mean and sum of squared deviations (Welford: no cancellation).
S_N, S_MIN, S_MAX, S_TMIN, S_TMAX, S_MEAN, S_M2 = range(7)
N_SACC = 7
#: Columns of the per-phase scalar accumulators: samples, Σω_cage, Σω_ring, Σ epicyclic
#: cage speed at the balls' actual contact angles, Σ the same at the nominal angle, peak p³.
#: Then (issue 10; in row 0 except the life sums, which are per row): ΣT and max |T| of the
#: drive torque, Σ friction power, the energies integrated over the steps (trapezoid
#: rule on the powers at the steps' states: friction, damping, drive work ∫T·ω, work of the loads and gravity, the tilt
#: term of the rhs Notes) [J], peak pocket and land forces, peak squared race sliding
#: speed, peak (p·s)⁶, extreme sines of the contact angle, peak race p³ and its time, the
#: life sums of rvcore.life (A_i, A_o [N³ rev], revolutions [rev]), and Σ and max of the
#: magnitude of the moment that holds a "held" ring square [N m].
C_N, C_CAGE_SUM, C_RING_SUM, C_EPI_SUM, C_EPI_NOMINAL_SUM, C_P3_MAX = range(6)
(C_T_SUM, C_T_ABS_MAX, C_PF_SUM, C_E_FRICTION, C_E_DAMPING, C_W_DRIVE, C_W_LOAD, C_E_TILT, C_QP_MAX,
 C_QLAND_MAX, C_SLIDE2_MAX, C_PV6_MAX, C_SIN_MIN, C_SIN_MAX, C_RACE_P3_MAX, C_RACE_P3_TMAX, C_LIFE_I,
 C_LIFE_O, C_REV, C_HOLD_SUM, C_HOLD_MAX) = range(6, 27)
N_ACC = 27

OK, NONFINITE, PENETRATION, ENERGY = 0, 1, 2, 3

#: Bandwidth of the drive torque whose peak is reported (``C_T_ABS_MAX``) [Hz]: two
#: cascaded first-order low-passes of this corner (a critically damped second-order
#: filter, as a torque transducer or the drive's current loop would see it) on the
#: contacts' part ``−M_c·e``; the prescribed ``I_p·ω̇`` is added unfiltered. Why: the
#: instantaneous torque carries the contact oscillation (ω_n ≈ 1.1e5 rad/s, 17 kHz on the
#: study bearing) through the friction, a chatter whose sampled peak depends on the step
#: (RK4: 1.46 N m at step_safety 0.8, 1.54 at 0.25 on the study cycle) and is no load a
#: drive train transmits. 1 kHz keeps the bearing's kinematic ripple (the ball pass is
#: 50 Hz at 660 °/s: attenuated by 0.25 %) and takes the 17 kHz chatter down 300×.
TORQUE_BANDWIDTH = 1.0e3

RK4_IMAG_LIMIT = 2.0 * math.sqrt(2.0)
RK4_REAL_LIMIT = 2.785

#: The integrators, by their ``solver.method`` names; the kernel takes the index.
METHODS = ("rk4", "imex")
RK4, IMEX = 0, 1


def new_accumulators(n_phases: int, n_sensors: int = 0, n_rows: int = 1):
    """Empty ``(signal_acc, scalar_acc)`` for ``n_phases`` phases, ``n_sensors`` sensors
    and ``n_rows`` rows of balls (the scalar accumulators are per row).

    ``scalar_acc`` has ``n_phases + 1`` lines: the last accumulates every step of the
    integration, whatever its phase (the whole cycle).
    """
    sig = np.zeros((n_phases, SIG_SENSOR0 + n_sensors, N_SACC))
    sig[:, :, S_MIN] = np.inf
    sig[:, :, S_MAX] = -np.inf
    sig[:, :, S_TMIN] = np.nan
    sig[:, :, S_TMAX] = np.nan
    acc = np.zeros((n_phases + 1, n_rows, N_ACC))
    acc[:, :, C_SIN_MIN] = np.inf
    acc[:, :, C_SIN_MAX] = -np.inf
    acc[:, :, C_RACE_P3_TMAX] = np.nan
    return sig, acc


@njit(cache=True, nogil=True, inline="always", fastmath=FAST)
def sensor_reading(y, sensor):
    """Displacement of the inner ring at a fixed sensor, along its direction [m].

    ``sensor = (px, py, pz, dx, dy, dz)``: the point of the ring's bore or face the
    sensor aims at, in the nominal (unloaded) ring, and the unit measuring direction.
    The reading is ``d·(r_ring + (R − I)·p)``, the displacement of the ring's material
    point at p (its spin about its own axis moves a bore or face within itself, so it is
    left out). To first order in the tilt this is what a laser on a rig reads.
    """
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = ring_rotation(y[3], y[4])
    px, py, pz = sensor[0], sensor[1], sensor[2]
    ux = y[0] + (r00 - 1.0) * px + r01 * py + r02 * pz
    uy = y[1] + r10 * px + (r11 - 1.0) * py + r12 * pz
    uz = y[2] + r20 * px + r21 * py + (r22 - 1.0) * pz
    return sensor[3] * ux + sensor[4] * uy + sensor[5] * uz


@njit(cache=True, nogil=True, inline="always")
def _track(a, x, t):
    """Add sample ``x`` at time ``t`` to one signal's accumulator line ``a``."""
    a[S_N] += 1.0
    if x < a[S_MIN]:
        a[S_MIN] = x
        a[S_TMIN] = t
    if x > a[S_MAX]:
        a[S_MAX] = x
        a[S_TMAX] = t
    d = x - a[S_MEAN]
    a[S_MEAN] += d / a[S_N]
    a[S_M2] += d * (x - a[S_MEAN])


@njit(cache=True, nogil=True)
def kinetic_energy(y, params, rows):
    """Kinetic energy of the free motion [J] (the prescribed spin of the ring excluded)."""
    e = 0.5 * params[P_RING_M] * (y[5] ** 2 + y[6] ** 2 + y[7] ** 2)
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


@njit(cache=True, nogil=True, inline="always")
def static_safety_factor(race_p3):
    """ISO 76 static safety factor ``s_0 = C_0/P_0 = (4200 MPa / p_max)³`` [1] from the
    largest ball–race ``p_max³`` [Pa³]; NaN when no ball–race contact is loaded.

    ISO 76 defines ``s_0 = C_0/P_0``, a load ratio; 4200 MPa is the pressure at C_0 and
    the Hertz pressure goes as the load^(1/3), so the load ratio is the pressure ratio
    cubed (:func:`rvcore.static_rating.static_safety_factor_from_pressure`)."""
    if race_p3 > 0.0:
        return ISO76_BALL_STRESS ** 3 / race_p3
    return math.nan


@njit(cache=True, nogil=True, inline="always")
def _add_energies(a, diag, w):
    """Add the powers of ``diag`` times the weight ``w`` [s] to the energies of ``a`` [J]."""
    a[C_E_FRICTION] += diag[D_FRICTION_POWER] * w
    a[C_E_DAMPING] += diag[D_DAMPING_POWER] * w
    a[C_W_DRIVE] += diag[D_DRIVE_POWER] * w
    a[C_W_LOAD] += diag[D_LOAD_POWER] * w
    a[C_E_TILT] += diag[D_TILT_POWER] * w


@njit(cache=True, nogil=True, inline="always")
def _step_stats(a, diag, t, dt):
    """Add the step from ``t`` (``diag`` of the rhs at its start) to one phase's (or the
    cycle's) scalar accumulators of row 0 ``a``: the designer's outputs, but the drive
    torque's (:func:`_torque_stats`, after the step).

    The energies get the half ``dt/2`` of the trapezoid rule from the step's start;
    :func:`_add_energies` adds the other half from its end. (The powers are evaluated at
    each step's state, not at the RK4 stages, to keep the stages' cost unchanged.)
    """
    a[C_PF_SUM] += diag[D_FRICTION_POWER]
    _add_energies(a, diag, 0.5 * dt)
    a[C_QP_MAX] = max(a[C_QP_MAX], diag[D_MAX_QP])
    a[C_QLAND_MAX] = max(a[C_QLAND_MAX], diag[D_LAND_Q])
    a[C_SLIDE2_MAX] = max(a[C_SLIDE2_MAX], diag[D_MAX_SLIDE2])
    a[C_PV6_MAX] = max(a[C_PV6_MAX], diag[D_MAX_PV6])
    if diag[D_SIN_MAX] >= 0.0:
        a[C_SIN_MIN] = min(a[C_SIN_MIN], diag[D_SIN_MIN])
        a[C_SIN_MAX] = max(a[C_SIN_MAX], diag[D_SIN_MAX])
    if diag[D_RACE_P3] > a[C_RACE_P3_MAX]:
        a[C_RACE_P3_MAX] = diag[D_RACE_P3]
        a[C_RACE_P3_TMAX] = t
    hold = math.sqrt(diag[D_HOLD_MX] * diag[D_HOLD_MX] + diag[D_HOLD_MY] * diag[D_HOLD_MY])
    a[C_HOLD_SUM] += hold
    a[C_HOLD_MAX] = max(a[C_HOLD_MAX], hold)


@njit(cache=True, nogil=True, inline="always")
def _torque_stats(a, torque, torque_band_limited):
    """Add a step's drive torque to a phase's accumulators of row 0 ``a``: ``torque`` the
    step's mean (the stage-weighted torque ``Σ b_i·T(Y_i)``: the moment whose impulse the
    step gave the balls, for both integrators, since their velocity updates weigh the
    stages' forces by the same b), ``torque_band_limited`` that at :data:`TORQUE_BANDWIDTH`
    for the peak."""
    a[C_T_SUM] += torque
    a[C_T_ABS_MAX] = max(a[C_T_ABS_MAX], abs(torque_band_limited))


# FAST (rvcore.contact: no fast-math flags) keeps IEEE semantics, so the non-finite check
# below works and the state sums are rounded in the same order on every CPU.
@njit(cache=True, nogil=True, fastmath=FAST)
def integrate(y, t_start, dt, n_steps, out_every, params, rows, arcs, pockets, table, meta,
              phases, sensors, out, sig_acc, acc, diag, bdiag, work, pen_limit, ke_limit,
              cos_nominal, method, jwork, schur):
    """Advance ``y`` in place by ``n_steps`` steps of ``dt`` of ``method`` (``RK4`` or
    ``IMEX``; :func:`advance` allocates ``work``, ``jwork`` and ``schur`` for it).

    Every ``out_every`` steps (and at the first and last step) a line of ``out`` is
    written (columns :data:`OUTPUT_SERIES`, then one per sensor). At every step the
    state at the step's start is added to the accumulators of the phase it falls in
    (``phases[k] = (start, end)``): ``sig_acc[k, signal]`` for δ_r, δ_a and each sensor
    of ``sensors`` (rows ``(px, py, pz, dx, dy, dz)``), ``acc[k]`` for the speeds and the
    peak pressure, per row (``acc[k, r]``), plus the designer's outputs (issue 10: drive
    torque, friction, forces, sliding, contact angles, safety factor, energies) and the
    life sums of rvcore.life; the line ``acc[len(phases)]`` of :func:`new_accumulators`
    takes the life sums and energies of every step. ``cos_nominal[r]`` is cos α of row r's nominal
    contact angle. Columns ``N_OUT + n_sensors + r - 1`` of ``out`` hold row r's cage speed
    (r ≥ 1; row 0's is ``cage_speed``).

    Returns
    -------
    status : int
        ``OK`` or the blow-up kind.
    t_fail : float
        Simulated time of the failure [s].
    where : int
        State index (non-finite) or ball state offset (penetration) of the culprit.
    n_out : int
        Lines written to ``out``.
    """
    n = y.size
    n_sensors = sensors.shape[0]
    k1, k2, k3, k4, tmp = work[0], work[1], work[2], work[3], work[4]
    n_rows = rows.shape[0]
    n_out = 0
    half = 0.5 * dt
    n_ph = phases.shape[0]
    has_cycle = acc.shape[0] > n_ph     # the whole-cycle line of new_accumulators
    # the band-limited drive torque (TORQUE_BANDWIDTH): two first-order stages, exact for
    # a torque held over each step, started at the first step's torque
    decay = 1.0 - math.exp(-2.0 * math.pi * TORQUE_BANDWIDTH * dt)
    torque_f1, torque_f2, torque = 0.0, 0.0, 0.0
    for i in range(n_steps + 1):
        t = t_start + i * dt
        # the designer's diagnostics at the step's state only (rhs_stage skips them); the
        # IMEX scheme's stiff damping blocks from the same evaluation
        # (the frozen tangents serve JAC_EVERY steps: rvcore.imex, "Step")
        refresh = i % JAC_EVERY == 0
        if method == IMEX and refresh:
            rhs_jac(t, y, k1, params, rows, arcs, pockets, table, meta, diag, bdiag, dt * GAMMA, jwork, schur)
        else:
            rhs(t, y, k1, params, rows, arcs, pockets, table, meta, diag, bdiag)
        # blow-up checks on the state at t
        total = 0.0
        for m in range(n):
            total += y[m] + k1[m]
        if not math.isfinite(total):
            for m in range(n):
                if not (math.isfinite(y[m]) and math.isfinite(k1[m])):
                    return NONFINITE, t, m, n_out
        if diag[D_MAX_PEN] > pen_limit:
            return PENETRATION, t, int(diag[D_PEN_BALL]), n_out

        # δ_r along the radial load's direction at t (the profile may turn it)
        psi = channel_value(table, meta, CH_DIRECTION, t)
        dr = y[0] * math.cos(psi) + y[1] * math.sin(psi)
        da = y[2]
        w_ring = channel_value(table, meta, CH_SPEED, t)
        if i > 0:
            # the end half of the previous step's trapezoid, to that step's phases
            tp = t_start + (i - 1) * dt
            for k in range(n_ph + 1):
                if (k < n_ph and phases[k, 0] <= tp < phases[k, 1]) or (k == n_ph and has_cycle):
                    _add_energies(acc[k, 0], diag, half)
        if i < n_steps:
            # the inner ring's revolutions against the fixed outer ring over this step
            # Life sums (the accumulation contract of rvcore.life): over the step's d_rev
            # revolutions, per row of Z balls, A_i += d_rev·(1/Z)·Σ Q_i³ (rotating inner
            # ring) and A_o += d_rev·((1/Z)·Σ Q_o^(10/3))^(9/10) (stationary outer ring),
            # with the ball-race loads of the step's state (bdiag) [N³ rev]
            d_rev = abs(w_ring) * dt / (2.0 * math.pi)
            for r in range(n_rows):
                z = int(rows[r, R_Z])
                p0 = int(rows[r, R_POCKET0])
                si, so = 0.0, 0.0
                for j in range(p0, p0 + z):
                    qi, qo = bdiag[j, B_QI], bdiag[j, B_QO]
                    si += qi * qi * qi
                    if qo > 0.0:
                        so += qo ** (10.0 / 3.0)
                life_i = d_rev * si / z
                life_o = d_rev * (so / z) ** 0.9 if so > 0.0 else 0.0
                for k in range(n_ph + 1):
                    if (k < n_ph and phases[k, 0] <= t < phases[k, 1]) or (k == n_ph and has_cycle):
                        a = acc[k, r]
                        a[C_REV] += d_rev
                        a[C_LIFE_I] += life_i
                        a[C_LIFE_O] += life_o
            torque = B1 * diag[D_DRIVE_TORQUE]     # the stages' weighted sum, after the step
            for k in range(n_ph + 1):
                if (k < n_ph and phases[k, 0] <= t < phases[k, 1]) or (k == n_ph and has_cycle):
                    _step_stats(acc[k, 0], diag, t, dt)
            for k in range(n_ph):
                if phases[k, 0] <= t < phases[k, 1]:
                    _track(sig_acc[k, SIG_DR], dr, t)
                    _track(sig_acc[k, SIG_DA], da, t)
                    for s in range(n_sensors):
                        _track(sig_acc[k, SIG_SENSOR0 + s], sensor_reading(y, sensors[s]), t)
                    for r in range(n_rows):
                        a = acc[k, r]
                        gamma = rows[r, R_HALF_D] / rows[r, R_PITCH_R]     # D/d_m of the row
                        cos_a = diag[D_COS_ALPHA + r] if diag[D_COS_ALPHA + r] > 0.0 else cos_nominal[r]
                        a[C_N] += 1.0
                        a[C_CAGE_SUM] += y[int(rows[r, R_CAGE0]) + 7]
                        a[C_RING_SUM] += w_ring
                        a[C_EPI_SUM] += 0.5 * (1.0 - gamma * cos_a) * w_ring
                        a[C_EPI_NOMINAL_SUM] += 0.5 * (1.0 - gamma * cos_nominal[r]) * w_ring
                        a[C_P3_MAX] = max(a[C_P3_MAX], diag[D_MAX_P3])
        if i % out_every == 0 or i == n_steps:
            if kinetic_energy(y, params, rows) > ke_limit:
                return ENERGY, t, -1, n_out
            o = out[n_out]
            o[O_X], o[O_Y], o[O_Z], o[O_TX], o[O_TY] = y[0], y[1], y[2], y[3], y[4]
            o[O_DR], o[O_DA] = dr, da
            o[O_FR] = channel_value(table, meta, CH_RADIAL, t)
            o[O_FA] = channel_value(table, meta, CH_AXIAL, t)
            o[O_W] = w_ring
            o[O_M] = channel_value(table, meta, CH_MOMENT, t)
            o[O_PSI] = psi
            o[O_CAGE] = y[int(rows[0, R_CAGE0]) + 7]
            for r in range(1, n_rows):   # the other rows' cage speeds follow the sensors
                o[N_OUT + n_sensors + r - 1] = y[int(rows[r, R_CAGE0]) + 7]
            o[O_QI], o[O_QO], o[O_LOADED] = diag[D_MAX_QI], diag[D_MAX_QO], diag[D_LOADED]
            o[O_PMAX] = diag[D_MAX_P3] ** (1.0 / 3.0)
            o[O_TORQUE] = diag[D_DRIVE_TORQUE]
            o[O_PFRIC] = diag[D_FRICTION_POWER]
            o[O_QP] = diag[D_MAX_QP]
            o[O_QLAND] = diag[D_LAND_Q]
            o[O_SLIDE] = math.sqrt(max(diag[D_MAX_SLIDE2], 0.0))
            o[O_PV] = diag[D_MAX_PV6] ** (1.0 / 6.0)
            o[O_AMIN] = math.asin(min(diag[D_SIN_MIN], 1.0)) if diag[D_SIN_MAX] >= 0.0 else math.nan
            o[O_AMAX] = math.asin(min(diag[D_SIN_MAX], 1.0)) if diag[D_SIN_MAX] >= 0.0 else math.nan
            o[O_SSF] = static_safety_factor(diag[D_RACE_P3])
            o[O_HOLD_X], o[O_HOLD_Y] = diag[D_HOLD_MX], diag[D_HOLD_MY]
            for s in range(n_sensors):
                o[N_OUT + s] = sensor_reading(y, sensors[s])
            n_out += 1
        if i == n_steps:
            break
        if method == IMEX:
            torque += imex_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur,
                                refresh)
        else:
            # classical RK4
            for m in range(n):
                tmp[m] = y[m] + half * k1[m]
            rhs_stage(t + half, tmp, k2, params, rows, arcs, pockets, table, meta, diag, bdiag)
            torque += B2 * diag[D_DRIVE_TORQUE]
            for m in range(n):
                tmp[m] = y[m] + half * k2[m]
            rhs_stage(t + half, tmp, k3, params, rows, arcs, pockets, table, meta, diag, bdiag)
            torque += B3 * diag[D_DRIVE_TORQUE]
            for m in range(n):
                tmp[m] = y[m] + dt * k3[m]
            rhs_stage(t + dt, tmp, k4, params, rows, arcs, pockets, table, meta, diag, bdiag)
            torque += B4 * diag[D_DRIVE_TORQUE]
            sixth = dt / 6.0
            for m in range(n):
                y[m] += sixth * (k1[m] + 2.0 * (k2[m] + k3[m]) + k4[m])
        # the step's drive torque to the phases of its start; the peak band-limited
        # (TORQUE_BANDWIDTH) in its contacts' part only: the prescribed spin's I_p·ω̇ is
        # known exactly, and its jumps at the profile's corners would only lag. It is
        # weighed over the stages as the step's torque is (both methods' nodes are
        # 0, ½, ½, 1), so that the filter sees the contacts' part alone: ω̇ at the step's
        # start put a step's worth of the jump of ω̇ at a corner into the filter, an error
        # of the peak proportional to the step (0.05 % per µs on the study cycle)
        inertial = params[P_RING_IP] * (B1 * channel_rate(table, meta, CH_SPEED, t)
                                        + (B2 + B3) * channel_rate(table, meta, CH_SPEED, t + half)
                                        + B4 * channel_rate(table, meta, CH_SPEED, t + dt))
        if i == 0:
            torque_f1 = torque_f2 = torque - inertial
        # the band-limited torque at t, the time whose phase it goes to: the filter's
        # output before this step's torque enters it (after, it is the output at t + dt,
        # which put the filter's decay over one step after a profile's corner into the
        # next phase's peak: an error growing as the step squared)
        band = inertial + torque_f2
        if i > 0:
            torque_f1 += decay * (torque - inertial - torque_f1)
            torque_f2 += decay * (torque_f1 - torque_f2)
        for k in range(n_ph + 1):
            if (k < n_ph and phases[k, 0] <= t < phases[k, 1]) or (k == n_ph and has_cycle):
                _torque_stats(acc[k, 0], torque, band)
    return OK, t_start + n_steps * dt, -1, n_out


def new_work(model, method: str):
    """The scratch arrays ``(work, jwork, schur)`` that :func:`integrate` needs for ``method``."""
    if method == "rk4":
        return np.zeros((5, model.n_states)), np.zeros((1, 1)), np.zeros((1, 1))
    from . import imex
    return imex.new_work(model)


def time_step(model, peak_contact_load: float, method: str, *, safety: float = 0.8) -> float:
    """The fixed step [s] of ``method`` (:func:`stable_time_step` for RK4,
    :func:`rvcore.imex.stable_time_step` for the IMEX scheme)."""
    if method == "rk4":
        return stable_time_step(model, peak_contact_load, safety=safety)
    from . import imex
    return imex.stable_time_step(model, peak_contact_load, safety=safety)


def advance(method: str, y, t_start, dt, n_steps, out_every, model, table, meta, phases, sensors, out,
            sig_acc, acc, diag, bdiag, pen_limit, ke_limit, cos_nominal):
    """:func:`integrate` with ``method`` by name (:data:`METHODS`) and its scratch allocated.

    Returns ``(status, t_fail, where, n_out)`` as :func:`integrate`.
    """
    if method not in METHODS:
        raise ValueError(f"unknown integrator {method!r}: use one of {', '.join(METHODS)}")
    work, jwork, schur = new_work(model, method)
    return integrate(y, t_start, dt, n_steps, out_every, model.params, model.rows, model.arcs, model.pockets,
                     table, meta, phases, sensors, out, sig_acc, acc, diag, bdiag, work, pen_limit, ke_limit,
                     cos_nominal, METHODS.index(method), jwork, schur)


def stable_time_step(model, peak_contact_load: float, *, safety: float = 0.8,
                     dynamic_margin: float = 1.0) -> float:
    """The fixed RK4 step [s] from the stiffest contact and friction rates.

    Parameters
    ----------
    model : rvcore.model.CompiledBearing
    peak_contact_load : float
        Largest quasi-static ball–race load over the cycle [N].
    safety : float
        Fraction of the stability limit [-].
    dynamic_margin : float
        Factor on the quasi-static load for dynamic overshoot [-].

    Notes
    -----
    Per row, with ``Q = dynamic_margin·peak_contact_load``, ``K`` the stiffest arc,
    ``k = 1.5·K^(2/3)·Q^(1/3)``, ``c_f = Q·dμ/ds`` at zero slip
    (:func:`rvcore.contact.friction_slope_at_zero_slip`, the law's own slope) and the two race contacts of a
    ball::

        ω_n = √(2k/m_b)                        (contact oscillation)
        λ   = 2·(c_f·max(1/m_b, r²/I_b) + c_max/m_b)   (friction and damping, real axis)
        dt  = safety · min(2√2/ω_n, 2.785/λ)
    """
    from .model import P_DAMP_C, P_DAMPING, P_FRICTION, P_MU_S, P_V_S

    q = max(dynamic_margin * peak_contact_load, 1.0)
    p = model.params
    c_f = friction_slope_at_zero_slip(p[P_MU_S], p[P_V_S]) * q * p[P_FRICTION]
    dts = []
    for omega, m, rot in row_rates(model, q):
        lam = 2.0 * (c_f * max(1.0 / m, rot) + p[P_DAMP_C] * p[P_DAMPING] / m)
        dts.append(min(RK4_IMAG_LIMIT / omega, RK4_REAL_LIMIT / lam if lam > 0 else np.inf))
    return safety * min(dts)


def row_rates(model, q: float):
    """Per row: the contact oscillation ``ω_n = √(2k/m_b)`` [rad s^-1] of a ball between
    its two race contacts at the load ``q`` [N] (``k = 1.5·K^(2/3)·q^(1/3)``, K of the
    stiffest arc), the ball mass ``m_b`` [kg] and ``r²/I_b`` [kg^-1]: the rates both
    integrators' steps come from."""
    from .model import A_K, R_ARC0, R_HALF_D, R_NARC

    for r in range(model.rows.shape[0]):
        row = model.rows[r]
        a0, na = int(row[R_ARC0]), int(row[R_NARC])
        k_hertz = model.arcs[a0:a0 + na, A_K].max()
        m, i_b, h = row[R_MB], row[R_IB], row[R_HALF_D]
        yield math.sqrt(2.0 * 1.5 * k_hertz ** (2.0 / 3.0) * q ** (1.0 / 3.0) / m), m, h * h / i_b
