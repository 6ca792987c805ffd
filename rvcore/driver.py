"""``run_case``: the one entry point for a dynamic case. SI in, SI out.

Takes a bearing, a profile, an operating point and solver settings; returns a
:class:`CaseResult` of plain arrays. ``pipeline.case`` turns it into labelled data.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class SolverSettings:
    """Numerical settings of one case.

    Parameters
    ----------
    output_rate : float
        Samples per second of the stored time series [Hz]. Phase metrics do not depend
        on it: they are accumulated at every integrator step.
    step_safety : float
        Fraction of the explicit RK4 stability limit used as the fixed step [-].
    time_step : float
        Explicit fixed step [s]; 0 derives it from the stiffest contact and friction
        rates (see ``rvcore.integrator.stable_time_step``).
    start_time, end_time : float
        Simulated window [s]; ``end_time`` 0 means the profile's duration.
    friction : bool
        Friction on (False switches every friction force off, for conservation checks).
    damping : bool
        Contact damping on.
    """

    output_rate: float = 1000.0
    step_safety: float = 0.8
    time_step: float = 0.0
    start_time: float = 0.0
    end_time: float = 0.0
    friction: bool = True
    damping: bool = True


@dataclass
class CaseResult:
    """Arrays of one case, SI.

    ``series`` maps a pipeline.md variable name to an array over ``time``.
    ``phase_metrics`` maps a metric name to an array over the phases (PHASES order).
    ``final_state`` is the integrator state at the end, to continue a run.
    """

    time: np.ndarray
    series: dict
    phase_metrics: dict
    final_state: np.ndarray
    info: dict = field(default_factory=dict)
    ball_diag: np.ndarray | None = None  # per ball at the end: Q_inner, Q_outer, F_inner_radial, F_outer_radial, Q_pocket


class SimulationError(RuntimeError):
    """The integration blew up; the message gives the simulated time and the body."""


def _rolling_velocities(model, y, omega):
    """Set ball and cage velocities for rolling without slip at inner-ring speed ``omega``.

    Each ball's centre velocity v and angular velocity w solve, in least squares (the
    spin about the contact line is left at its minimum norm), the no-slip conditions
    ``v + w×(c_i − P) = ω ẑ×c_i`` at the inner contact and ``v + w×(c_o − P) = 0`` at the
    outer one, with the contacts at the row's nominal angle.
    """
    from .model import BALL_STATES, R_BALL0, R_CAGE0, R_HALF_D, R_Z, R_ARC0, R_NARC, R_ZROW, A_RING, A_CR, A_CZ

    def skew(a):
        return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])

    for r in range(model.rows.shape[0]):
        row = model.rows[r]
        h = row[R_HALF_D]
        b0, z = int(row[R_BALL0]), int(row[R_Z])
        a0 = int(row[R_ARC0])
        orbit = []
        for j in range(z):
            b = b0 + BALL_STATES * j
            p = y[b:b + 3]
            rho = np.hypot(p[0], p[1])
            er = np.array([p[0] / rho, p[1] / rho, 0.0])
            normals = []
            for ring in (0, 1):
                arc = next(k for k in range(a0, a0 + int(row[R_NARC])) if model.arcs[k, A_RING] == ring)
                c = model.arcs[arc, A_CR] * er + np.array([0, 0, model.arcs[arc, A_CZ] + row[R_ZROW]])
                n = p - c
                normals.append(n / np.linalg.norm(n))
            ci, co = p + h * normals[0], p + h * normals[1]
            a = np.zeros((6, 6))
            rhs_ = np.zeros(6)
            a[:3, :3] = np.eye(3)
            a[:3, 3:] = -skew(ci - p)
            rhs_[:3] = np.cross([0.0, 0.0, omega], ci)
            a[3:, :3] = np.eye(3)
            a[3:, 3:] = -skew(co - p)
            sol = np.linalg.lstsq(a, rhs_, rcond=None)[0]
            y[b + 3:b + 9] = sol
            orbit.append(np.cross(p, sol[:3])[2] / rho**2)
        y[int(row[R_CAGE0]) + 7] = float(np.mean(orbit))


def initial_state(model, resolved, t_start):
    """Quasi-static equilibrium of the loads at ``t_start``, balls at their pocket centres.

    Balls take the equilibrium radial and axial positions at their pocket azimuths; when
    the prescribed speed at ``t_start`` is not zero, every ball starts rolling without
    slip and the cage at the balls' mean orbital speed.
    """
    from .model import nominal_state, BALL_STATES, R_BALL0, R_Z, R_POCKET0
    from .quasistatic import solve_statics

    table, meta = resolved.arrays()
    from .profile import channel_value

    fr = channel_value(table, meta, 0, t_start)
    fa = channel_value(table, meta, 1, t_start)
    w = channel_value(table, meta, 2, t_start)
    y = nominal_state(model)
    lc, ls = model.params[3], model.params[4]
    moment = model.params[5]
    if fr != 0.0 or fa != 0.0 or moment != 0.0:
        st = solve_statics(model, fr, fa, moment, float(np.arctan2(ls, lc)))
        y[0:5] = st.displacement
        for r in range(model.rows.shape[0]):
            b0, z, p0 = int(model.rows[r, R_BALL0]), int(model.rows[r, R_Z]), int(model.rows[r, R_POCKET0])
            for j in range(z):
                b = b0 + BALL_STATES * j
                cs, sn = model.pockets[p0 + j]
                rho, zz = st.ball_positions[p0 + j]
                y[b:b + 3] = rho * cs, rho * sn, zz
    if w != 0.0:
        _rolling_velocities(model, y, w)
    return y


def peak_contact_load(model, resolved) -> float:
    """Largest quasi-static ball–race load at the cycle's peak loads plus the centrifugal force [N]."""
    from .quasistatic import solve_statics
    from .model import R_MB, R_PITCH_R

    fr = float(np.max(np.abs(resolved.radial[1])))
    fa = float(np.max(np.abs(resolved.axial[1])))
    w = float(np.max(np.abs(resolved.speed[1])))
    lc, ls = model.params[3], model.params[4]
    q = 0.0
    if fr or fa or model.params[5]:
        q = solve_statics(model, fr, float(np.max(resolved.axial[1]) if fa else 0.0), model.params[5],
                          float(np.arctan2(ls, lc))).max_contact_load
    centrifugal = float(np.max(model.rows[:, R_MB] * model.rows[:, R_PITCH_R] * (0.5 * w) ** 2))
    return q + centrifugal


def run_case(bearing, profile, op, settings: SolverSettings = SolverSettings(), initial_state_vector=None) -> CaseResult:
    """Integrate one case through its duty cycle.

    Parameters
    ----------
    bearing : rvcore.geometry.Bearing
    profile : rvcore.profile.Profile
    op : rvcore.profile.OperatingPoint
    settings : SolverSettings
    initial_state_vector : ndarray, optional
        A previous ``CaseResult.final_state`` to continue from; default: quasi-static
        equilibrium at ``settings.start_time``.

    Returns
    -------
    CaseResult

    Raises
    ------
    SimulationError
        On blow-up, naming the simulated time and the body.
    """
    import math
    import time as _time

    from . import integrator as ig
    from .geometry import epicyclic_cage_ratio
    from .model import body_name, compile_bearing, R_HALF_D, R_MB, R_IB, R_CAGE_M, R_PITCH_R, R_Z
    from .kernels import N_BDIAG, N_DIAG

    model = compile_bearing(bearing, friction=settings.friction, damping=settings.damping,
                            moment=op.moment, load_angle=op.load_angle)
    resolved = profile.resolve(op)
    table, meta = resolved.arrays()
    t_start = settings.start_time
    t_end = settings.end_time if settings.end_time > 0 else profile.duration
    if t_end <= t_start:
        raise ValueError(f"end time {t_end} s is not after start time {t_start} s")
    y = (np.array(initial_state_vector, dtype=float) if initial_state_vector is not None
         else initial_state(model, resolved, t_start))
    if y.shape != (model.n_states,):
        raise ValueError(f"initial state has {y.size} values; this bearing needs {model.n_states}")

    q_peak = peak_contact_load(model, resolved)
    dt_max = settings.time_step if settings.time_step > 0 else ig.stable_time_step(
        model, q_peak, safety=settings.step_safety)
    # The step divides the output interval exactly, so every case of a sweep samples at
    # the same times t_start + k/output_rate whatever its own stability limit.
    out_every = max(1, int(math.ceil(1.0 / (settings.output_rate * dt_max) - 1e-9)))
    dt = 1.0 / (settings.output_rate * out_every)
    n_steps = int(math.ceil((t_end - t_start) / dt - 1e-6))
    n_out_max = n_steps // out_every + 2
    out = np.zeros((n_out_max, ig.N_OUT))
    acc = ig.new_accumulators(resolved.phases.shape[0])
    diag = np.zeros(N_DIAG)
    bdiag = np.zeros((model.n_balls, N_BDIAG))
    work = np.zeros((5, model.n_states))
    pen_limit = 0.1 * 2 * float(model.rows[:, R_HALF_D].min())
    w_max = max(float(np.max(np.abs(resolved.speed[1]))), 1.0)
    v_ref = w_max * bearing.outer_diameter / 2
    rows = model.rows
    e_ref = 0.5 * v_ref**2 * (model.params[0] + float(np.sum(rows[:, R_CAGE_M]))
                              + float(np.sum(rows[:, R_Z] * (rows[:, R_MB] + rows[:, R_IB] / rows[:, R_HALF_D]**2))))
    f_max = float(max(np.max(np.abs(resolved.radial[1])), np.max(np.abs(resolved.axial[1])), 1.0))
    ke_limit = 100.0 * e_ref + f_max * 2 * float(rows[:, R_HALF_D].max())

    t0 = _time.perf_counter()
    status, t_fail, where, n_out = ig.integrate(
        y, t_start, dt, n_steps, out_every, model.params, model.rows, model.arcs, model.pockets,
        table, meta, resolved.phases, out, acc, diag, bdiag, work, pen_limit, ke_limit)
    wall = _time.perf_counter() - t0
    if status != ig.OK:
        what = {ig.NONFINITE: "a non-finite state value",
                ig.PENETRATION: f"a penetration beyond {pen_limit * 1e3:.3g} mm (10 % of the ball diameter)",
                ig.ENERGY: f"kinetic energy beyond the physical bound {ke_limit:.3g} J"}[status]
        if where < 0:  # energy bound: name the body holding the most kinetic energy
            where = _most_energetic_state(model, y)
        body = body_name(model, where)
        hint = ("try a smaller solver.time_step" if settings.time_step > 0
                else "try a smaller solver.step_safety")
        raise SimulationError(f"simulation blew up at t = {t_fail:.6g} s: {what} in {body} "
                              f"(time step {dt:.3g} s; {hint})")
    out = out[:n_out]
    k = np.minimum(np.arange(n_out) * out_every, n_steps)
    time = t_start + np.where(k % out_every == 0, k // out_every / settings.output_rate, k * dt)
    names = ("inner_ring_x", "inner_ring_y", "inner_ring_z", "inner_ring_tilt_x", "inner_ring_tilt_y",
             "radial_displacement", "axial_displacement", "applied_radial_load", "applied_axial_load",
             "inner_ring_speed", "cage_speed", "max_inner_contact_load", "max_outer_contact_load",
             "loaded_ball_count", "max_contact_pressure")
    series = {name: out[:, k].copy() for k, name in enumerate(names)}

    w = acc[:, ig.C_W]
    with np.errstate(invalid="ignore", divide="ignore"):
        wn = np.where(w > 0, w, np.nan)
        metrics = {}
        for name, c_min, c_max, c_sum, c_sq in (("radial_displacement", ig.C_DR_MIN, ig.C_DR_MAX, ig.C_DR_SUM, ig.C_DR_SQ),
                                                ("axial_displacement", ig.C_DA_MIN, ig.C_DA_MAX, ig.C_DA_SUM, ig.C_DA_SQ)):
            mean = acc[:, c_sum] / wn
            metrics[f"{name}_range"] = np.where(w > 0, acc[:, c_max] - acc[:, c_min], np.nan)
            metrics[f"{name}_mean"] = mean
            metrics[f"{name}_std"] = np.sqrt(np.maximum(acc[:, c_sq] / wn - mean**2, 0.0))
        metrics["cage_speed_mean"] = acc[:, ig.C_CAGE_SUM] / wn
        metrics["inner_ring_speed_mean"] = acc[:, ig.C_RING_SUM] / wn
        ratio = epicyclic_cage_ratio(bearing.rows[0])
        metrics["cage_slip"] = 1.0 - metrics["cage_speed_mean"] / (ratio * metrics["inner_ring_speed_mean"])
        metrics["peak_contact_pressure"] = np.where(w > 0, np.cbrt(acc[:, ig.C_P3_MAX]), np.nan)
    info = {"steps": n_steps, "time_step": dt, "rhs_evaluations": 4 * n_steps + 1, "wall_time": wall,
            "ball_count": model.n_balls, "peak_contact_load_estimate": q_peak,
            "ball_mass": float(model.rows[0, R_MB]), "pitch_diameter": 2.0 * float(model.rows[0, R_PITCH_R]),
            "epicyclic_cage_ratio": epicyclic_cage_ratio(bearing.rows[0])}
    return CaseResult(time=time, series=series, phase_metrics=metrics, final_state=y.copy(), info=info,
                      ball_diag=bdiag.copy())


def _most_energetic_state(model, y) -> int:
    """First state index of the body with the largest kinetic energy in ``y``."""
    from .model import BALL_STATES, R_BALL0, R_CAGE0, R_CAGE_I, R_CAGE_M, R_IB, R_MB, R_Z

    p = model.params
    best = (0.5 * p[0] * float(y[5:8] @ y[5:8]) + 0.5 * p[2] * float(y[8:10] @ y[8:10]), 0)
    for row in model.rows:
        c0 = int(row[R_CAGE0])
        e = 0.5 * row[R_CAGE_M] * float(y[c0 + 4:c0 + 7] @ y[c0 + 4:c0 + 7]) + 0.5 * row[R_CAGE_I] * y[c0 + 7] ** 2
        best = max(best, (e, c0))
        for j in range(int(row[R_Z])):
            b = int(row[R_BALL0]) + BALL_STATES * j
            e = 0.5 * row[R_MB] * float(y[b + 3:b + 6] @ y[b + 3:b + 6]) + 0.5 * row[R_IB] * float(y[b + 6:b + 9] @ y[b + 6:b + 9])
            best = max(best, (e, b))
    return best[1]


def warm_up() -> None:
    """Compile (or load from the numba cache) every kernel by running a tiny case."""
    from .geometry import Arc, Bearing, Cage, ContactLaw, InnerRing, Material, Row
    from .profile import OperatingPoint, scaled_study_profile
    import math

    steel = Material(7800.0, 208e9, 0.3)
    cage = Cage(0.0545, 0.0575, 0.008, 0.3e-3, 0.3e-3, "outer-land", Material(8500.0, 100e9, 0.34), 1e9)
    row = Row(6, 0.008, 0.056, 0.0, (Arc(0.52, math.radians(15)),), (Arc(0.53, math.radians(15)),), cage)
    b = Bearing("warm-up", 0.045, 0.068, 0.012, (row,), steel, steel, InnerRing(0.050),
                ContactLaw(50.0, 1e-6, 10.0, 10.0))
    run_case(b, scaled_study_profile(0.002), OperatingPoint(1.0, 100.0, 50.0),
             SolverSettings(output_rate=1e4, time_step=2e-6))
