"""What the integrator keeps at every step: the output table (:mod:`rvcore.output_table`)
turned into index arrays for the numba loop, the loop's per-step signals and reductions,
and the phase metrics read back from the reductions. SI throughout.

:func:`build_plan` lays out, for a bearing's rows and sensors,

- the *series plan*: one line per output column, ``(signal slot, transform)``;
- the *reduction plan*: one line per accumulator, ``(signal slot, kind, first column,
  when)``, with ``when`` 0 for signals of the step's state and 1 for those known only
  after the step (the stage-weighted drive torque);
- the accumulators' initial line, and where each phase metric reads its columns.

The loop (:func:`rvcore.integrate.loop.integrate`) keeps one accumulator line per phase plus
one for the whole cycle, and updates every line whose window holds the step's start
(:func:`reduce_step`); a step's count is column :data:`COUNT`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from .._numba import kernel

from ..contact.pose import ring_rotation
from ..dynamics.rhs import B_QI, B_QO
from ..dynamics.ring_modes import F_INNER_AXIAL, F_INNER_RADIAL, F_OUTER_RADIAL, flexible, order_amplitude, surface
from ..bearing.layout import (P_LUB_C, P_LUB_DM, P_LUB_EC, P_LUB_ECCU, P_LUB_EP, P_LUB_NU, P_LUB_QCE, P_LUB_QCI,
                              R_CAGE0, R_HALF_D, R_PITCH_R, R_POCKET0, R_Z)
from ..output_table import (ARCSINE_LOADED, CUBE_ROOT, ISO76_LOAD_RATIO, N_ROW_SIGNALS, N_SIGNALS, OUTPUTS, PHASE,
                      ROOT_OF_POSITIVE, ROW_SLOT, SERIES, SIGNALS, SIXTH_ROOT, SLOT, STEP)
from ..profile import CH_AXIAL, CH_DIRECTION, CH_MOMENT, CH_RADIAL, CH_SPEED, channel_value
from ..standards.iso76 import ISO76_BALL_PRESSURE
from ..standards.iso281 import WEIBULL_E
from ..standards.iso281_modified import KAPPA_MIN, a_iso_of, reference_viscosity_of

# ---- reduction kinds and their columns
SUM, MAX, MIN, MAX_AND_TIME, STATISTICS, INTEGRAL, ABS_MAX, FINITE_MEAN = range(8)
#: Columns each kind takes: STATISTICS keeps count, min, max, their times, Welford's mean
#: and sum of squared deviations (no cancellation); MAX_AND_TIME the extreme and its time;
#: FINITE_MEAN the sum and the count of the finite values (a NaN, "none", is left out; MIN
#: leaves it out too, since no comparison with NaN holds).
WIDTH = {SUM: 1, MAX: 1, MIN: 1, MAX_AND_TIME: 2, STATISTICS: 7, INTEGRAL: 1, ABS_MAX: 1, FINITE_MEAN: 2}
S_N, S_MIN, S_MAX, S_TMIN, S_TMAX, S_MEAN, S_M2 = range(7)
#: Plan columns.
PL_SLOT, PL_KIND, PL_COL, PL_WHEN = range(4)
#: Column 0 of every accumulator line counts the steps.
COUNT = 0

_KIND_OF = {"mean": SUM, "slip": SUM, "max": MAX, "min": MIN, "max_time": MAX_AND_TIME, "abs_max": ABS_MAX,
            "integral": INTEGRAL, "range": STATISTICS, "stats_mean": STATISTICS, "std": STATISTICS,
            "min_time": STATISTICS, "max_time_of": STATISTICS, "range_at_edge": STATISTICS,
            "finite_mean": FINITE_MEAN}

#: Reductions the driver reads besides the outputs': the energies of the balance of
#: tests/core/test_energy_balance.py and the life sums of :mod:`rvcore.standards.iso16281`.
#: The drive's work comes from the step's stage-weighted power (the work its impulse did):
#: the instantaneous ``drive_power`` carries the contact oscillation's chatter, which a
#: trapezoid of samples at the steps' starts aliases (docs/performance.md). The loads' and
#: gravity's work from the fall of their potential across each step: the power ``F·v``
#: aliases the ring's vibration alike, by up to 1 % of the dissipation on the study
#: bearing (docs/validation.md, §9.4).
ENERGIES = {"friction": "friction_power", "damping": "damping_power", "drive": "drive_power_step",
            "load": "load_power_step", "tilt": "tilt_power"}

_S = SLOT
_R = ROW_SLOT
# the fixed slots the loop writes (rvcore.output_table.SIGNALS)
(SL_X, SL_Y, SL_Z, SL_TX, SL_TY, SL_DR, SL_DA, SL_FR, SL_FA, SL_W, SL_M, SL_PSI, SL_HOLD, SL_REV, SL_TORQUE_STEP,
 SL_TORQUE_BAND, SL_POWER_STEP, SL_LOAD_POWER_STEP) = (_S[n] for n in (
     "inner_ring_x", "inner_ring_y", "inner_ring_z", "inner_ring_tilt_x", "inner_ring_tilt_y", "radial_displacement",
     "axial_displacement", "applied_radial_load", "applied_axial_load", "inner_ring_speed", "applied_moment",
     "load_direction", "tilt_reaction_moment", "revolutions", "drive_torque_step", "drive_torque_band_limited",
     "drive_power_step", "load_power_step"))
SL_KAPPA, SL_A_ISO, SL_REV_LOW = _S["kappa"], _S["a_iso"], _S["revolutions_kappa_below_scope"]
SL_HOLD_X, SL_HOLD_Y = _S["tilt_reaction_moment_x"], _S["tilt_reaction_moment_y"]
SL_OVAL_I, SL_OVAL_O = _S["inner_ring_ovalisation"], _S["outer_ring_ovalisation"]
(RS_COS, RS_CAGE, RS_EPI, RS_EPI_NOMINAL, RS_LIFE_I, RS_LIFE_O, RS_LIFE_I_MOD, RS_LIFE_O_MOD) = (_R[n] for n in (
    "cos_contact_angle", "cage_speed", "epicyclic_cage_speed", "epicyclic_cage_speed_nominal", "life_sum_inner",
    "life_sum_outer", "life_sum_inner_modified", "life_sum_outer_modified"))


def row_slot(name: str, r: int) -> int:
    """Slot of row ``r``'s signal ``name`` (rvcore.output_table.ROW_SIGNALS)."""
    return N_SIGNALS + N_ROW_SIGNALS * r + ROW_SLOT[name]


@dataclass(frozen=True)
class Plan:
    """The output table laid out for one bearing's rows and sensors (:func:`build_plan`)."""

    series: np.ndarray        # (columns, 2): slot, transform
    series_labels: tuple      # per column: (output name, instance: row or sensor index, or -1)
    reductions: np.ndarray    # (accumulators, 4): slot, kind, column, when
    columns: dict             # (slot, kind) -> first accumulator column
    initial: np.ndarray       # the accumulator line before any step
    n_rows: int
    n_sensors: int

    def column(self, slot: int, kind: int) -> int:
        return self.columns[(slot, kind)]


def _instances(o, n_rows: int, n_sensors: int):
    """``(instance, slot)`` of each copy of output ``o``'s signal: one a row or a sensor."""
    if o.over == "row":
        return [(r, row_slot(o.signal, r)) for r in range(n_rows)]
    if o.over == "sensor":
        return [(s, N_SIGNALS + N_ROW_SIGNALS * n_rows + s) for s in range(n_sensors)]
    return [(-1, SLOT[o.signal])]


def build_plan(n_rows: int, n_sensors: int) -> Plan:
    """The series columns and accumulators of :data:`rvcore.output_table.OUTPUTS` for a bearing
    of ``n_rows`` rows and ``n_sensors`` sensors."""
    series, labels = [], []
    for o in OUTPUTS:
        if o.kind == SERIES:
            for k, slot in _instances(o, n_rows, n_sensors):
                series.append((slot, o.transform))
                labels.append((o.name, k))
    written_after = {SLOT[s.name] for s in SIGNALS if s.written == STEP}
    columns, reductions, col = {}, [], 1      # column 0 is COUNT

    def need(slot, kind):
        nonlocal col
        if (slot, kind) not in columns:
            columns[(slot, kind)] = col
            reductions.append((slot, kind, col, 1 if slot in written_after else 0))
            col += WIDTH[kind]

    for o in OUTPUTS:
        if o.kind != PHASE or o.reduce not in _KIND_OF:
            continue
        for k, slot in _instances(o, n_rows, n_sensors):
            need(slot, _KIND_OF[o.reduce])
            if o.other:
                need(row_slot(o.other, k) if o.over == "row" else SLOT[o.other], SUM)
    for signal in ENERGIES.values():
        need(SLOT[signal], INTEGRAL)
    need(SLOT["revolutions"], SUM)
    need(SLOT["revolutions_kappa_below_scope"], SUM)
    for r in range(n_rows):
        for name in ("life_sum_inner", "life_sum_outer", "life_sum_inner_modified", "life_sum_outer_modified"):
            need(row_slot(name, r), SUM)
    initial = np.zeros(col)
    for (slot, kind), c in columns.items():
        if kind == MIN:
            initial[c] = np.inf
        elif kind in (MAX, MAX_AND_TIME):
            initial[c] = -np.inf
            if kind == MAX_AND_TIME:
                initial[c + 1] = np.nan
        elif kind == STATISTICS:
            initial[c + S_MIN], initial[c + S_MAX] = np.inf, -np.inf
            initial[c + S_TMIN] = initial[c + S_TMAX] = np.nan
    return Plan(np.array(series, dtype=np.int64).reshape(-1, 2), tuple(labels),
                np.array(reductions, dtype=np.int64).reshape(-1, 4), columns, initial, n_rows, n_sensors)


def new_accumulators(plan: Plan, n_phases: int) -> np.ndarray:
    """``(n_phases + 1, columns)`` accumulators: a line a phase, the last the whole cycle."""
    return np.tile(plan.initial, (n_phases + 1, 1))


# ---- the numba side ---------------------------------------------------------------

@kernel(inline=True)
def transform(code, x):
    """An output's value from its signal (or from the signal's phase extreme)."""
    if code == CUBE_ROOT:
        return x ** (1.0 / 3.0)
    if code == ROOT_OF_POSITIVE:
        return math.sqrt(max(x, 0.0))
    if code == SIXTH_ROOT:
        return x ** (1.0 / 6.0)
    if code == ARCSINE_LOADED:
        # the kernel writes 2 (smallest) or −1 (largest) when no race contact is loaded
        return math.asin(min(x, 1.0)) if 0.0 <= x <= 1.5 else math.nan
    if code == ISO76_LOAD_RATIO:
        # ISO 76 s0 = C0/P0 is a load ratio; the Hertz pressure goes as the load^(1/3), so
        # it is the cube of the pressure ratio (rvcore.standards.iso76)
        return ISO76_BALL_PRESSURE ** 3 / x if x > 0.0 else math.nan
    return x


@kernel(inline=True)
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


@kernel(inline=True)
def sensor_surface_reading(params, y, sensor):
    """What a flexible inner ring's deformation adds to :func:`sensor_reading` [m]: the
    surface at the sensor's point moved by ``w(θ)·ê_r + u(θ)·ẑ`` in the ring's frame
    (:func:`rvcore.dynamics.ring_modes.surface`, ``θ`` the point's angle there; a thin
    ring's radial displacement is the same through its thickness, and its axial one is
    the centroid's, the section's twist neglected), turned by the ring's tilt, along the
    sensor's direction. 0 at a point on the axis."""
    px, py = sensor[0], sensor[1]
    rho = math.sqrt(px * px + py * py)
    if rho == 0.0:
        return 0.0
    c, s = px / rho, py / rho
    w, _, _ = surface(params, y, F_INNER_RADIAL, c, s)
    u, _, _ = surface(params, y, F_INNER_AXIAL, c, s)
    lx, ly, lz = w * c, w * s, u
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = ring_rotation(y[3], y[4])
    return (sensor[3] * (r00 * lx + r01 * ly + r02 * lz) + sensor[4] * (r10 * lx + r11 * ly + r12 * lz)
            + sensor[5] * (r20 * lx + r21 * ly + r22 * lz))


@kernel
def fill_state_signals(diag, y, t, dt, table, meta, rows, bdiag, sensors, cos_nominal, params):
    """Write the signals of the state ``y`` at ``t`` that the right-hand side does not
    (rvcore.output_table: ``written = "state"``), for a step of ``dt`` from it; ``params``
    the compiled bearing's (its lubrication, and a flexible ring's modes,
    :mod:`rvcore.dynamics.ring_modes`).

    Notes
    -----
    The step's modified life (docs/model.md, "The film along the cycle"): κ = ν/ν1 at the
    step's speed (ISO 281 9.3.3, :func:`rvcore.standards.iso281_modified.reference_viscosity_of`);
    the step's ring damage rates ``Q_e³/Q_c³`` per 10^6 rev (ISO/TS 16281, the life sums' own
    ``Q_e``), combined ``D = (Σ_k D_k^(10/9))^(9/10)`` as its eq. (29) combines lives, give its
    reference life ``1/D`` and its equivalent reference load ``P = C_r·D^(1/3)`` (the load of
    that basic life by ISO 281 eq. (4)); a_ISO at κ and ``e_C·C_u/P``
    (:func:`rvcore.standards.iso281_modified.a_iso_of`) divides the step's life sums: the
    modified sums, whose Palmgren–Miner sum over the cycle is the modified life."""
    psi = channel_value(table, meta, CH_DIRECTION, t)
    w_ring = channel_value(table, meta, CH_SPEED, t)
    diag[SL_X], diag[SL_Y], diag[SL_Z], diag[SL_TX], diag[SL_TY] = y[0], y[1], y[2], y[3], y[4]
    # δ_r along the radial load's direction at t (the profile may turn it)
    diag[SL_DR] = y[0] * math.cos(psi) + y[1] * math.sin(psi)
    diag[SL_DA] = y[2]
    diag[SL_FR] = channel_value(table, meta, CH_RADIAL, t)
    diag[SL_FA] = channel_value(table, meta, CH_AXIAL, t)
    diag[SL_W] = w_ring
    diag[SL_M] = channel_value(table, meta, CH_MOMENT, t)
    diag[SL_PSI] = psi
    diag[SL_HOLD] = math.sqrt(diag[SL_HOLD_X] * diag[SL_HOLD_X] + diag[SL_HOLD_Y] * diag[SL_HOLD_Y])
    # the inner ring's revolutions against the fixed outer ring over the step
    d_rev = abs(w_ring) * dt / (2.0 * math.pi)
    diag[SL_REV] = d_rev
    q_ci3, q_ce3 = params[P_LUB_QCI] ** 3, params[P_LUB_QCE] ** 3
    rate = 0.0      # Σ over the rows' rings of (Q_e³/Q_c³)^(10/9) (Notes)
    for r in range(rows.shape[0]):
        base = N_SIGNALS + N_ROW_SIGNALS * r
        gamma = rows[r, R_HALF_D] / rows[r, R_PITCH_R]     # D/d_m of the row
        cos_a = diag[base + RS_COS] if diag[base + RS_COS] > 0.0 else cos_nominal[r]
        diag[base + RS_CAGE] = y[int(rows[r, R_CAGE0]) + 7]
        diag[base + RS_EPI] = 0.5 * (1.0 - gamma * cos_a) * w_ring
        diag[base + RS_EPI_NOMINAL] = 0.5 * (1.0 - gamma * cos_nominal[r]) * w_ring
        # life sums (the accumulation contract of rvcore.standards.iso16281): per row of Z balls,
        # A_i += d_rev·(1/Z)·Σ Q_i³ (rotating inner ring) and A_o += d_rev·((1/Z)·Σ
        # Q_o^(10/3))^(9/10) (stationary outer ring) [N³ rev]
        z = int(rows[r, R_Z])
        p0 = int(rows[r, R_POCKET0])
        si, so = 0.0, 0.0
        for j in range(p0, p0 + z):
            qi, qo = bdiag[j, B_QI], bdiag[j, B_QO]
            si += qi * qi * qi
            if qo > 0.0:
                so += qo ** (10.0 / 3.0)
        diag[base + RS_LIFE_I] = d_rev * si / z
        diag[base + RS_LIFE_O] = d_rev * (so / z) ** 0.9 if so > 0.0 else 0.0
        rate += (si / z / q_ci3) ** WEIBULL_E
        if so > 0.0:
            rate += ((so / z) ** 0.9 / q_ce3) ** WEIBULL_E
    # the step's κ and a_ISO (Notes), and its modified life sums
    kappa = params[P_LUB_NU] / reference_viscosity_of(abs(w_ring), params[P_LUB_DM])
    diag[SL_KAPPA] = kappa
    diag[SL_REV_LOW] = d_rev if kappa < KAPPA_MIN else 0.0
    a_iso = math.nan
    if rate > 0.0:
        load = params[P_LUB_C] * rate ** (1.0 / (3.0 * WEIBULL_E))
        a_iso = a_iso_of(kappa, params[P_LUB_ECCU] / load, params[P_LUB_EP] != 0.0, params[P_LUB_EC])[0]
    diag[SL_A_ISO] = a_iso
    for r in range(rows.shape[0]):
        base = N_SIGNALS + N_ROW_SIGNALS * r
        li, lo = diag[base + RS_LIFE_I], diag[base + RS_LIFE_O]
        diag[base + RS_LIFE_I_MOD] = li / a_iso if li > 0.0 else 0.0
        diag[base + RS_LIFE_O_MOD] = lo / a_iso if lo > 0.0 else 0.0
    flex = flexible(params)
    diag[SL_OVAL_I] = order_amplitude(params, y, F_INNER_RADIAL, 2)
    diag[SL_OVAL_O] = order_amplitude(params, y, F_OUTER_RADIAL, 2)
    s0 = N_SIGNALS + N_ROW_SIGNALS * rows.shape[0]
    for s in range(sensors.shape[0]):
        diag[s0 + s] = sensor_reading(y, sensors[s])
        if flex:
            diag[s0 + s] += sensor_surface_reading(params, y, sensors[s])


@kernel(inline=True)
def in_window(phases, k, n_ph, t):
    """Whether accumulator line ``k`` takes a step from ``t``: its phase's window holds
    ``t``, or it is the whole cycle's line (``k == n_ph``)."""
    return k == n_ph or phases[k, 0] <= t < phases[k, 1]


@kernel
def reduce_step(line, plan, diag, t, when, half):
    """Add the step from ``t`` to one accumulator line: every reduction of ``plan`` whose
    signal is known at ``when`` (0 the step's state, 1 after the step). ``half`` is half
    the step [s]: an integral of a state's signal gets the trapezoid's half from the
    step's start here and the other half from its end (:func:`add_integral_end`); one of
    a step's signal (its own average over the step) gets the whole step here."""
    if when == 0:
        line[COUNT] += 1.0
    for m in range(plan.shape[0]):
        if plan[m, PL_WHEN] != when:
            continue
        x = diag[plan[m, PL_SLOT]]
        c = plan[m, PL_COL]
        kind = plan[m, PL_KIND]
        if kind == SUM:
            line[c] += x
        elif kind == MAX:
            if x > line[c]:
                line[c] = x
        elif kind == MIN:
            if x < line[c]:
                line[c] = x
        elif kind == MAX_AND_TIME:
            if x > line[c]:
                line[c] = x
                line[c + 1] = t
        elif kind == INTEGRAL:
            line[c] += x * (half if when == 0 else 2.0 * half)
        elif kind == ABS_MAX:
            if abs(x) > line[c]:
                line[c] = abs(x)
        elif kind == FINITE_MEAN:
            if math.isfinite(x):
                line[c] += x
                line[c + 1] += 1.0
        else:   # STATISTICS
            line[c + S_N] += 1.0
            if x < line[c + S_MIN]:
                line[c + S_MIN] = x
                line[c + S_TMIN] = t
            if x > line[c + S_MAX]:
                line[c + S_MAX] = x
                line[c + S_TMAX] = t
            d = x - line[c + S_MEAN]
            line[c + S_MEAN] += d / line[c + S_N]
            line[c + S_M2] += d * (x - line[c + S_MEAN])


@kernel
def add_integral_end(line, plan, diag, half):
    """Add the end half of the previous step's trapezoid (``diag`` at its end state) to
    the integrals of states' signals."""
    for m in range(plan.shape[0]):
        if plan[m, PL_KIND] == INTEGRAL and plan[m, PL_WHEN] == 0:
            line[plan[m, PL_COL]] += diag[plan[m, PL_SLOT]] * half


@kernel
def add_substep_integrals(line, plan, inner, h):
    """A step taken again in substeps of ``h`` [s] (rvcore.integrate.imex): turn its trapezoid into
    the substeps' own. ``inner`` holds ``Σ_{s≥1} x_s − (S − 1)/2·x_0`` of each signal at the
    substeps' starts; with the step's start half here already (``S·h/2·x_0``) and its end
    half added at ``h/2`` (:func:`add_integral_end` with ``half/S``), an integral then
    gets ``h·(x_0/2 + Σ_{s≥1} x_s + x_S/2)``: the integrals of the right-hand side's
    signals (``when`` 0), which every substep evaluates; a step's signal is the substeps'
    own average already."""
    for m in range(plan.shape[0]):
        if plan[m, PL_KIND] == INTEGRAL and plan[m, PL_WHEN] == 0:
            line[plan[m, PL_COL]] += inner[plan[m, PL_SLOT]] * h


@kernel
def write_series(o, series, diag):
    """One line of the output series: every column's signal through its transform."""
    for c in range(series.shape[0]):
        o[c] = transform(series[c, 1], diag[series[c, 0]])

