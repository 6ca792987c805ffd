"""``run_case``: the one entry point for a dynamic case. SI in, SI out.

Takes a bearing, a profile, an operating point and solver settings; returns a
:class:`CaseResult` of plain arrays. ``pipeline.case`` turns it into labelled data.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .contact import arc_penetration, ring_angular_velocity, ring_rotation


@dataclass(frozen=True)
class SolverSettings:
    """Numerical settings of one case.

    Parameters
    ----------
    output_rate : float
        Samples per second of the stored time series [Hz]. Phase metrics do not depend
        on it: they are accumulated at every integrator step.
    method : str
        The integrator: ``"rk4"`` (classical RK4, the reference) or ``"imex"`` (the
        coupled implicit–explicit additive Runge–Kutta scheme of :mod:`rvcore.imex`:
        friction at small slip and contact damping implicit, the rest explicit).
    step_safety : float
        Fraction of the method's explicit stability limit used as the fixed step [-].
    time_step : float
        Explicit fixed step [s]; 0 derives it from the stiffest contact and friction
        rates (see ``rvcore.integrator.stable_time_step``).
    start_time, end_time : float
        Simulated window [s]; ``end_time`` 0 means the profile's duration.
    friction : bool
        Friction on (False switches every friction force off, for conservation checks).
    damping : bool
        Contact damping on.
    gravity : bool
        Gravity on every body, along the bearing's mounting (False only for the
        conservation checks of model.md §9).
    seed : int
        −1: every ball starts at its pocket centre. Otherwise the seed of the random
        start: each ball starts at a uniformly drawn position within its pocket's
        circumferential play (one realization of an ensemble).
    """

    output_rate: float = 1000.0
    method: str = "rk4"
    step_safety: float = 0.8
    time_step: float = 0.0
    start_time: float = 0.0
    end_time: float = 0.0
    friction: bool = True
    damping: bool = True
    gravity: bool = True
    seed: int = -1


@dataclass(frozen=True)
class Sensor:
    """A displacement sensor fixed in space, aimed at the inner ring's bore or face.

    Parameters
    ----------
    name : str
    position : tuple of float
        The point of the (unloaded, centred) ring the sensor reads, in the bearing
        frame [m].
    direction : tuple of float
        Measuring direction [-] (normalised here): the reading is the ring's displacement
        at ``position`` along it (``rvcore.integrator.sensor_reading``).
    """

    name: str
    position: tuple
    direction: tuple

    def as_row(self) -> np.ndarray:
        d = np.asarray(self.direction, dtype=float)
        norm = float(np.linalg.norm(d))
        if not norm > 0.0:
            raise ValueError(f"sensor {self.name!r}: the direction must not be zero")
        return np.concatenate([np.asarray(self.position, dtype=float), d / norm])


@dataclass
class CaseResult:
    """Arrays of one case, SI.

    ``series`` maps a pipeline.md variable name to an array over ``time``; with sensors,
    ``series["sensor_displacement"]`` is over ``(time, sensor)``.
    ``phase_metrics`` maps a metric name to an array over the phases (PHASES order), or
    over ``(phase, sensor)`` for the ``sensor_displacement_*`` metrics.
    ``final_state`` is the integrator state at the end, to continue a run.
    ``steady`` holds scalars at the steady operating point from the statics there
    (:data:`rvcore.operating.STEADY_OUTPUTS`: the stiffnesses).
    ``life_sums`` are the integrator's life sums (the contract of ``rvcore.life``):
    ``"inner"`` and ``"outer"`` over ``(phase + 1, row)`` [N³ rev] and ``"revolutions"``
    over ``phase + 1`` [rev], the last line the whole simulated cycle.
    ``life`` holds the duty-cycle scalars of :data:`DUTY_CYCLE_OUTPUTS` when
    ``rvcore.life.duty_cycle_life`` is available (empty otherwise).
    ``spectra`` holds the steady phase's amplitude spectra and the bearing's kinematic
    frequencies (:func:`rvcore.spectra.steady_spectra`, ``kinematic_frequency`` [Hz]).
    ``energy`` maps ``friction``, ``damping`` (dissipated), ``drive`` (∫T·ω dt),
    ``load`` (work of the applied loads and gravity) and ``tilt`` (the power the
    small-tilt ring equations leave out, see ``rvcore.kernels.rhs``) to arrays over
    ``phase + 1`` [J], the last line the whole cycle, integrated with RK4's weights.
    """

    time: np.ndarray
    series: dict
    phase_metrics: dict
    final_state: np.ndarray
    info: dict = field(default_factory=dict)
    ball_diag: np.ndarray | None = None  # per ball at the end: Q_inner, Q_outer, F_inner_radial, F_outer_radial, Q_pocket
    steady: dict = field(default_factory=dict)  # rvcore.operating.STEADY_OUTPUTS: stiffness at the steady point
    life_sums: dict = field(default_factory=dict)
    life: dict = field(default_factory=dict)
    energy: dict = field(default_factory=dict)
    spectra: dict = field(default_factory=dict)  # rvcore.spectra.steady_spectra and "kinematic_frequency"


#: Duty-cycle life scalars of a case (no dims): name -> (units, long_name), from
#: ``rvcore.life.duty_cycle_life`` over the integrator's life sums.
DUTY_CYCLE_OUTPUTS = {
    "rating_life_L10r": ("1", "ISO/TS 16281 reference rating life L10r of the duty cycle, in revolutions of "
                              "the inner ring (Palmgren-Miner over the integrator steps)"),
    "rating_life_cycles": ("1", "ISO/TS 16281 reference rating life L10r of the duty cycle, in cycles of the profile"),
    "fatigue_damage_cycle": ("1", "Palmgren-Miner fatigue damage of one cycle of the profile (1/rating_life_cycles)"),
}


class SimulationError(RuntimeError):
    """The integration blew up; the message gives the simulated time and the body."""


def _tangent_rows(n, arm):
    """Two rows ``t·[I, −[arm]×]``: the tangential parts of ``v + w × arm`` at normal n."""
    e = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, e)
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    skew = np.array([[0.0, -arm[2], arm[1]], [arm[2], 0.0, -arm[0]], [-arm[1], arm[0], 0.0]])
    return np.array([np.concatenate([t, -t @ skew]) for t in (t1, t2)]), (t1, t2)


def race_contacts(model, y, r, j):
    """The deepest inner and outer arc contacts of ball j of row r at state ``y``.

    Returns ``((n_inner, c_inner), (n_outer, c_outer))``: unit normals (C→P, global) and
    contact points [m], from the same geometry as the right-hand side.
    """
    from .model import A_CR, A_CZ, A_RING, A_RMH, A_SIDE, BALL_STATES, R_ARC0, R_BALL0, R_HALF_D, R_NARC, R_ZROW

    row = model.rows[r]
    h, zrow = row[R_HALF_D], row[R_ZROW]
    b = int(row[R_BALL0]) + BALL_STATES * j
    p = y[b:b + 3]
    rot = np.array(ring_rotation(y[3], y[4])).reshape(3, 3)
    pl = rot.T @ (p - y[0:3])
    pl[2] -= zrow
    rho_l, rho_b = math.hypot(pl[0], pl[1]), math.hypot(p[0], p[1])
    best = {0: (-np.inf, None), 1: (-np.inf, None)}
    for a in range(int(row[R_ARC0]), int(row[R_ARC0] + row[R_NARC])):
        ring = int(model.arcs[a, A_RING])
        geo = (model.arcs[a, A_CR], model.arcs[a, A_CZ], model.arcs[a, A_RMH], model.arcs[a, A_SIDE], h)
        if ring == 0:
            d, nx, ny, nz = arc_penetration(pl[0], pl[1], pl[2], rho_l, 1.0 / rho_l, *geo)
            n = rot @ np.array([nx, ny, nz])
        else:
            d, nx, ny, nz = arc_penetration(p[0], p[1], p[2] - zrow, rho_b, 1.0 / rho_b, *geo)
            n = np.array([nx, ny, nz])
        if d > best[ring][0]:
            best[ring] = (d, n)
    return tuple((best[k][1], p + h * best[k][1]) for k in (0, 1))


def inner_race_velocity(y, omega, point):
    """Velocity of the inner race's material point at ``point`` [m s^-1].

    ``v_ring + Ω × (point − r_ring)`` with the ring's full angular velocity
    (:func:`rvcore.contact.ring_angular_velocity`): spin about its tilted axis plus the
    tilt rates, as in the right-hand side.
    """
    r00, _, r02, _, _, r12, r20, _, r22 = ring_rotation(y[3], y[4])
    om = np.array(ring_angular_velocity(omega, y[8], y[9], r00, r20, r02, r12, r22))
    return y[5:8] + np.cross(om, np.asarray(point) - y[0:3])


def _rolling_velocities(model, y, omega):
    """Set ball and cage velocities for rolling without slip at inner-ring speed ``omega``.

    Each ball's centre velocity v and angular velocity w solve, exactly, the four
    tangential no-slip conditions at its deepest inner and outer contacts
    (:func:`race_contacts`): ``(v + w × (c_i − P))_t = (v_race(c_i))_t`` with the race
    velocity of :func:`inner_race_velocity`, and ``(v + w × (c_o − P))_t = 0``; and a
    fifth, ``v·u = 0`` along the contact line ``u ∝ n_i − n_o``: the ball starts at its
    static position and does not move into its races. Of the rest, the least norm of
    ``(v, r·w)``, both in m/s (r the ball radius). Why both: the tangential conditions
    leave v along the contact line free to first order, and a least norm that mixed m/s
    with rad/s traded it for a smaller spin; with nearly opposite normals (0° contacts)
    that started the balls of a 6010 moving radially at up to 1.3 m/s (issue 28). The
    cage takes the balls' mean orbital speed.
    """
    from .model import BALL_STATES, R_BALL0, R_CAGE0, R_Z

    for r in range(model.rows.shape[0]):
        row = model.rows[r]
        b0, z = int(row[R_BALL0]), int(row[R_Z])
        orbit = []
        for j in range(z):
            b = b0 + BALL_STATES * j
            p = y[b:b + 3].copy()
            (n_i, c_i), (n_o, c_o) = race_contacts(model, y, r, j)
            a_i, t_i = _tangent_rows(n_i, c_i - p)
            a_o, _ = _tangent_rows(n_o, c_o - p)
            v_race = inner_race_velocity(y, omega, c_i)
            rhs_ = np.array([t_i[0] @ v_race, t_i[1] @ v_race, 0.0, 0.0, 0.0])
            line = (n_i - n_o) / np.linalg.norm(n_i - n_o)
            h = float(np.linalg.norm(c_i - p))
            # unknowns (v, h·w): the columns of w scaled by 1/h
            a = np.vstack([a_i, a_o, np.concatenate([line, np.zeros(3)])])
            a[:, 3:] /= h
            sol = np.linalg.lstsq(a, rhs_, rcond=None)[0]
            sol[3:] /= h
            y[b + 3:b + 9] = sol
            orbit.append(np.cross(p, sol[:3])[2] / (p[0] ** 2 + p[1] ** 2))
        y[int(row[R_CAGE0]) + 7] = float(np.mean(orbit))


def _random_start(model, y, seed: int) -> None:
    """Turn every ball about the axis by a uniform draw within its pocket's play.

    The circumferential play of a ball in its pocket is ``±(pocket diameter − D)/2``; the
    ball keeps its quasi-static radial and axial position (the load changes by a
    negligible amount over such an angle).
    """
    from .model import BALL_STATES, R_BALL0, R_HALF_D, R_POCKET_R, R_Z

    rng = np.random.default_rng(seed)
    for r in range(model.rows.shape[0]):
        row = model.rows[r]
        play = row[R_POCKET_R] - row[R_HALF_D]
        for j in range(int(row[R_Z])):
            b = int(row[R_BALL0]) + BALL_STATES * j
            px, py = y[b], y[b + 1]
            turn = rng.uniform(-play, play) / math.hypot(px, py)
            c, s = math.cos(turn), math.sin(turn)
            y[b], y[b + 1] = c * px - s * py, s * px + c * py


def initial_state(model, resolved, t_start, seed: int = -1):
    """Quasi-static equilibrium of the loads (and the ring's weight) at ``t_start``.

    Balls take the equilibrium radial and axial positions at their pocket azimuths, or,
    with ``seed`` ≥ 0, at a random position within their pocket play
    (:func:`_random_start`); when the prescribed speed at ``t_start`` is not zero, every
    ball starts rolling without slip and the cage at the balls' mean orbital speed.
    """
    from .model import nominal_state, BALL_STATES, R_BALL0, R_Z, R_POCKET0
    from .quasistatic import solve_statics

    from .profile import CH_AXIAL, CH_DIRECTION, CH_MOMENT, CH_RADIAL, CH_SPEED

    fr = resolved.value(CH_RADIAL, t_start)
    fa = resolved.value(CH_AXIAL, t_start)
    w = resolved.value(CH_SPEED, t_start)
    moment = resolved.value(CH_MOMENT, t_start)
    psi = resolved.value(CH_DIRECTION, t_start)
    y = nominal_state(model)
    # the statics always run: a preloaded pair or an interference fit loads its balls even
    # with no load and no weight, and centred balls would start squeezed out of equilibrium
    from .profile import channel_integral

    table, meta = resolved.arrays()
    st = solve_statics(model, fr, fa, moment, psi, stiffness=False,
                       ring_angle=channel_integral(table, meta, CH_SPEED, t_start))
    y[0:5] = st.displacement
    for r in range(model.rows.shape[0]):
        b0, z, p0 = int(model.rows[r, R_BALL0]), int(model.rows[r, R_Z]), int(model.rows[r, R_POCKET0])
        for j in range(z):
            b = b0 + BALL_STATES * j
            cs, sn = model.pockets[p0 + j, 0], model.pockets[p0 + j, 1]
            rho, zz = st.ball_positions[p0 + j]
            y[b:b + 3] = rho * cs, rho * sn, zz
    if seed >= 0:
        _random_start(model, y, seed)
    if w != 0.0:
        _rolling_velocities(model, y, w)
    return y


def peak_contact_load(model, resolved) -> float:
    """Largest quasi-static ball–race load over the cycle's extreme loads (and the ring's
    weight) plus the centrifugal force [N].

    The radial load is taken at its largest magnitude, and the axial load and the tilting
    moment at both their largest forward and their largest reverse values: a profile
    whose thrust or moment changes sign loads the opposite arcs, and the step must be
    stable there too. The extremes are combined as if they coincided (an upper bound),
    at every direction of the radial load the profile names at a breakpoint.
    """
    from .quasistatic import solve_statics
    from .model import R_MB, R_PITCH_R

    fr = float(np.max(np.abs(resolved.radial[1])))
    # the reverse extreme only where the thrust does go negative: no extra solve otherwise
    fa_min = float(np.min(resolved.axial[1]))
    axial_extremes = (float(np.max(resolved.axial[1])),) + ((fa_min,) if fa_min < 0.0 else ())
    w = float(np.max(np.abs(resolved.speed[1])))
    # the moment at both its extremes where it changes sign (it tilts the other way)
    m_max, m_min = float(np.max(resolved.moment[1])), float(np.min(resolved.moment[1]))
    moment_extremes = (m_max,) + ((m_min,) if m_min < 0.0 else ())
    # the direction matters only through the ring's weight: every direction the profile
    # names at a breakpoint (one, for a constant direction)
    directions = tuple(dict.fromkeys(float(v) for v in resolved.direction[1]))
    q = 0.0
    for fa in axial_extremes:
        for moment in moment_extremes:
            # always solved: the ring's weight alone loads the balls (solve_statics adds it
            # from the model), and so does a preload or an interference with no load at all
            for psi in directions:
                q = max(q, solve_statics(model, fr, fa, moment, psi, stiffness=False).max_contact_load)
    centrifugal = float(np.max(model.rows[:, R_MB] * model.rows[:, R_PITCH_R] * (0.5 * w) ** 2))
    return q + centrifugal


def run_case(bearing, profile, op, settings: SolverSettings = SolverSettings(), initial_state_vector=None,
             sensors=()) -> CaseResult:
    """Integrate one case through its duty cycle.

    Parameters
    ----------
    bearing : rvcore.geometry.Bearing
    profile : rvcore.profile.Profile
    op : rvcore.profile.OperatingPoint
    settings : SolverSettings
    initial_state_vector : ndarray, optional
        A previous ``CaseResult.final_state`` to continue from; default: quasi-static
        equilibrium at ``settings.start_time`` (random ball positions with
        ``settings.seed`` ≥ 0).
    sensors : sequence of Sensor
        Virtual displacement sensors; each adds a reading over time and its phase metrics.

    Returns
    -------
    CaseResult

    Raises
    ------
    SimulationError
        On blow-up, naming the simulated time and the body.
    """
    import time as _time

    from . import integrator as ig
    from .geometry import epicyclic_cage_ratio
    from .model import body_name, compile_bearing, R_HALF_D, R_MB, R_IB, R_CAGE_M, R_PITCH_R, R_Z
    from .kernels import new_diagnostics

    from .imperfections import realize

    # the imperfections this case runs with: a tolerance class's high-point angles and
    # ball sizes drawn from its seed (rvcore.imperfections)
    bearing = realize(bearing, int(settings.seed))
    model = compile_bearing(bearing, friction=settings.friction, damping=settings.damping,
                            gravity=settings.gravity)
    resolved = profile.resolve(op)
    table, meta = resolved.arrays()
    t_start = settings.start_time
    t_end = settings.end_time if settings.end_time > 0 else profile.duration
    if t_end <= t_start:
        raise ValueError(f"end time {t_end} s is not after start time {t_start} s")
    y = (np.array(initial_state_vector, dtype=float) if initial_state_vector is not None
         else initial_state(model, resolved, t_start, seed=int(settings.seed)))
    if y.shape != (model.n_states,):
        raise ValueError(f"initial state has {y.size} values; this bearing needs {model.n_states}")

    q_peak = peak_contact_load(model, resolved)
    if settings.method not in ig.METHODS:
        raise ValueError(f"solver method {settings.method!r} is not one of {', '.join(ig.METHODS)}")
    dt_max = settings.time_step if settings.time_step > 0 else ig.time_step(
        model, q_peak, settings.method, safety=settings.step_safety)
    # The step divides the output interval exactly, so every case of a sweep samples at
    # the same times t_start + k/output_rate whatever its own stability limit.
    out_every = max(1, int(math.ceil(1.0 / (settings.output_rate * dt_max) - 1e-9)))
    dt = 1.0 / (settings.output_rate * out_every)
    n_steps = int(math.ceil((t_end - t_start) / dt - 1e-6))
    n_out_max = n_steps // out_every + 2
    sensor_rows = (np.array([s.as_row() for s in sensors], dtype=float) if len(sensors)
                   else np.zeros((0, 6)))
    n_sensors = sensor_rows.shape[0]
    n_rows = model.rows.shape[0]
    out = np.zeros((n_out_max, ig.N_OUT + n_sensors + n_rows - 1))
    sig_acc, acc = ig.new_accumulators(resolved.phases.shape[0], n_sensors, n_rows)
    diag, bdiag = new_diagnostics(n_rows, model.n_balls)
    pen_limit = 0.1 * 2 * float(model.rows[:, R_HALF_D].min())
    w_max = max(float(np.max(np.abs(resolved.speed[1]))), 1.0)
    v_ref = w_max * bearing.outer_diameter / 2
    rows = model.rows
    e_ref = 0.5 * v_ref**2 * (model.params[0] + float(np.sum(rows[:, R_CAGE_M]))
                              + float(np.sum(rows[:, R_Z] * (rows[:, R_MB] + rows[:, R_IB] / rows[:, R_HALF_D]**2))))
    # a tilting moment does work like a force pair at the balls (its peak over the pitch radius)
    f_moment = float(np.max(np.abs(resolved.moment[1]))) / float(np.min(rows[:, R_PITCH_R]))
    f_max = float(max(np.max(np.abs(resolved.radial[1])), np.max(np.abs(resolved.axial[1])), f_moment, 1.0))
    ke_limit = 100.0 * e_ref + f_max * 2 * float(rows[:, R_HALF_D].max())

    t0 = _time.perf_counter()
    status, t_fail, where, n_out = ig.advance(
        settings.method, y, t_start, dt, n_steps, out_every, model, table, meta, resolved.phases, sensor_rows,
        out, sig_acc, acc, diag, bdiag, pen_limit, ke_limit,
        np.array([math.cos(row.nominal_contact_angle) for row in bearing.rows]))
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
    series = {name: out[:, k].copy() for k, name in enumerate(ig.OUTPUT_SERIES)}
    if n_sensors:
        series["sensor_displacement"] = out[:, ig.N_OUT:ig.N_OUT + n_sensors].copy()
    if n_rows > 1:   # every row's cage, over a trailing row axis
        series["cage_speed"] = np.column_stack([series["cage_speed"], out[:, ig.N_OUT + n_sensors:]])
    metrics = phase_metrics(sig_acc, acc, resolved.phases, 1.0 / settings.output_rate)
    life_sums = {"inner": acc[:, :, ig.C_LIFE_I].copy(), "outer": acc[:, :, ig.C_LIFE_O].copy(),
                 "revolutions": acc[:, 0, ig.C_REV].copy()}
    life = duty_cycle_outputs(bearing, life_sums, resolved.phases.shape[0])
    if "fatigue_damage" in life:
        metrics["fatigue_damage"] = life.pop("fatigue_damage")
    energy = {name: acc[:, 0, col].copy() for name, col in (
        ("friction", ig.C_E_FRICTION), ("damping", ig.C_E_DAMPING), ("drive", ig.C_W_DRIVE),
        ("load", ig.C_W_LOAD), ("tilt", ig.C_E_TILT))}
    info = {"steps": n_steps, "time_step": dt, "rhs_evaluations": 4 * n_steps + 1, "method": settings.method, "wall_time": wall,
            "ball_count": model.n_balls, "peak_contact_load_estimate": q_peak,
            "ball_mass": float(model.rows[0, R_MB]), "pitch_diameter": 2.0 * float(model.rows[0, R_PITCH_R]),
            "epicyclic_cage_ratio": epicyclic_cage_ratio(bearing.rows[0]),
            "seed": int(settings.seed), "inner_ring_tilt": bearing.inner_ring.tilt}
    from .operating import steady_outputs
    from .spectra import kinematic_frequencies, steady_spectra

    row0 = bearing.rows[0]
    kinematic = kinematic_frequencies(row0.ball_count, row0.ball_diameter, row0.pitch_diameter,
                                      row0.nominal_contact_angle, op.speed)
    spectra = steady_spectra(time, series, tuple(resolved.phases[1]), kinematic)
    if spectra:
        spectra["kinematic_frequency"] = kinematic
    return CaseResult(time=time, series=series, phase_metrics=metrics, final_state=y.copy(), info=info,
                      ball_diag=bdiag.copy(),
                      steady=steady_outputs(bearing, profile, op, gravity=settings.gravity),
                      life_sums=life_sums, life=life, energy=energy, spectra=spectra)


def duty_cycle_outputs(bearing, life_sums: dict, n_phases: int) -> dict:
    """The duty-cycle life of a case from its life sums, or ``{}`` without ``rvcore.life``.

    Returns the scalars of :data:`DUTY_CYCLE_OUTPUTS` that ``rvcore.life.duty_cycle_life``
    gives, plus ``fatigue_damage`` over the phases when it gives that per phase (an array
    of ``n_phases`` values, or ``n_phases + 1`` with the whole cycle last).
    """
    try:
        from .life import duty_cycle_life
    except ImportError:   # rvcore.life is written by another change; the driver runs without it
        return {}
    life = duty_cycle_life(bearing, life_sums)
    # an infinite life (nothing loads the turning bearing, or it does not turn) is stored
    # as NaN, like static_safety_factor with nothing loaded: no inf in a case file
    out = {k: float(life[k]) if math.isfinite(float(life[k])) else math.nan
           for k in DUTY_CYCLE_OUTPUTS if k in life}
    if "fatigue_damage" in life:
        damage = np.atleast_1d(np.asarray(life["fatigue_damage"], dtype=float))
        if damage.size == n_phases + 1:
            out.setdefault("fatigue_damage_cycle", float(damage[-1]))
            damage = damage[:n_phases]
        out["fatigue_damage"] = damage
    return out


def phase_metrics(sig_acc, acc, phases, edge_tolerance: float) -> dict:
    """Phase metrics from the integrator's accumulators (names of ``pipeline.case``).

    For δ_r, δ_a and (over a trailing sensor axis) each sensor: ``_range`` (max − min),
    ``_mean``, ``_std``, ``_min_time`` and ``_max_time`` (when the extremes occur) and
    ``_range_at_edge``: 1 where either extreme lies within ``edge_tolerance`` [s] (one
    output interval) of its phase window's start or end, so the range may be cut off by
    the window. Plus the mean cage and ring speeds, the cage slip against the epicyclic
    speed at the balls' actual contact angles (``cage_slip``) and at the nominal angle
    (``cage_slip_nominal``), the peak Hertz pressure and the windows themselves.
    """
    from . import integrator as ig

    acc = acc[:phases.shape[0]]   # new_accumulators' last line is the whole cycle
    n = acc[:, 0, ig.C_N]
    start, end = phases[:, 0], phases[:, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        nn = np.where(n > 0, n, np.nan)
        out = {}
        groups = (("radial_displacement", sig_acc[:, ig.SIG_DR]), ("axial_displacement", sig_acc[:, ig.SIG_DA]),
                  ("sensor_displacement", sig_acc[:, ig.SIG_SENSOR0:]))
        for name, a in groups:
            if a.ndim == 3 and a.shape[1] == 0:
                continue
            cnt = a[..., ig.S_N]
            ok = cnt > 0
            tmin, tmax = a[..., ig.S_TMIN], a[..., ig.S_TMAX]
            s0 = start if a.ndim == 2 else start[:, None]
            s1 = end if a.ndim == 2 else end[:, None]
            near = lambda t: (np.abs(t - s0) <= edge_tolerance) | (np.abs(s1 - t) <= edge_tolerance)
            out[f"{name}_range"] = np.where(ok, a[..., ig.S_MAX] - a[..., ig.S_MIN], np.nan)
            out[f"{name}_mean"] = np.where(ok, a[..., ig.S_MEAN], np.nan)
            out[f"{name}_std"] = np.where(ok, np.sqrt(np.maximum(a[..., ig.S_M2], 0.0) / np.where(ok, cnt, 1.0)), np.nan)
            out[f"{name}_min_time"] = np.where(ok, tmin, np.nan)
            out[f"{name}_max_time"] = np.where(ok, tmax, np.nan)
            out[f"{name}_range_at_edge"] = np.where(ok, (near(tmin) | near(tmax)).astype(float), np.nan)
        # per row over a trailing row axis, dropped for a single row (the names of pipeline.md)
        per_row = (lambda a: a[:, 0]) if acc.shape[1] == 1 else (lambda a: a)
        nr = nn[:, None]
        out["cage_speed_mean"] = per_row(acc[:, :, ig.C_CAGE_SUM] / nr)
        out["inner_ring_speed_mean"] = acc[:, 0, ig.C_RING_SUM] / nn
        out["cage_slip"] = per_row(1.0 - acc[:, :, ig.C_CAGE_SUM] / acc[:, :, ig.C_EPI_SUM])
        out["cage_slip_nominal"] = per_row(1.0 - acc[:, :, ig.C_CAGE_SUM] / acc[:, :, ig.C_EPI_NOMINAL_SUM])
        out["epicyclic_cage_speed"] = per_row(acc[:, :, ig.C_EPI_SUM] / nr)
        out["peak_contact_pressure"] = np.where(n > 0, np.cbrt(acc[:, 0, ig.C_P3_MAX]), np.nan)
        # issue 10: the designer's outputs (row 0 holds them, over every row)
        a0 = acc[:, 0]
        ok = n > 0
        out["inner_ring_drive_torque_peak"] = np.where(ok, a0[:, ig.C_T_ABS_MAX], np.nan)
        out["inner_ring_drive_torque_mean"] = a0[:, ig.C_T_SUM] / nn
        out["friction_power_mean"] = a0[:, ig.C_PF_SUM] / nn
        out["friction_energy"] = np.where(ok, a0[:, ig.C_E_FRICTION], np.nan)
        out["max_pocket_force_peak"] = np.where(ok, a0[:, ig.C_QP_MAX], np.nan)
        out["cage_land_force_peak"] = np.where(ok, a0[:, ig.C_QLAND_MAX], np.nan)
        out["max_race_sliding_speed_peak"] = np.where(ok, np.sqrt(np.maximum(a0[:, ig.C_SLIDE2_MAX], 0.0)), np.nan)
        out["max_race_pv_peak"] = np.where(ok, a0[:, ig.C_PV6_MAX] ** (1.0 / 6.0), np.nan)
        loaded = ok & np.isfinite(a0[:, ig.C_SIN_MIN])
        out["contact_angle_min"] = np.where(loaded, np.arcsin(np.clip(a0[:, ig.C_SIN_MIN], -1.0, 1.0)), np.nan)
        out["contact_angle_max"] = np.where(loaded, np.arcsin(np.clip(a0[:, ig.C_SIN_MAX], -1.0, 1.0)), np.nan)
        p3 = a0[:, ig.C_RACE_P3_MAX]
        out["static_safety_factor_min"] = np.where(ok & (p3 > 0), ig.ISO76_BALL_STRESS ** 3 / np.where(p3 > 0, p3, 1.0), np.nan)
        out["static_safety_factor_min_time"] = np.where(ok & (p3 > 0), a0[:, ig.C_RACE_P3_TMAX], np.nan)
        # the moment that holds a "held" ring square (0 for a free ring: nothing holds it)
        out["tilt_reaction_moment_mean"] = a0[:, ig.C_HOLD_SUM] / nn
        out["tilt_reaction_moment_peak"] = np.where(ok, a0[:, ig.C_HOLD_MAX], np.nan)
    out["phase_start"] = start.astype(float).copy()
    out["phase_end"] = end.astype(float).copy()
    return out


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
