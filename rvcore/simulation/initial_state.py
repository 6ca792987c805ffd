"""The state a case starts from: the statics of the loads at the start, every ball in
its pocket (or at a random place in its play), rolling without slip where the ring
turns; and the peak contact load the step is sized for. SI throughout."""
from __future__ import annotations

import math

import numpy as np

from ..bearing.geometry import centrifugal_ball_load
from ..contact.laws import arc_penetration
from ..contact.pose import ring_angular_velocity, ring_rotation
from ..bearing.layout import (A_CR, A_CZ, A_RING, A_RMH, A_SIDE, BALL_STATES, R_ARC0, R_BALL0, R_CAGE0, R_HALF_D, R_MB,
                    R_NARC, R_PITCH_R, R_POCKET0, R_POCKET_R, R_Z, R_ZROW, nominal_state)
from ..profile import CH_AXIAL, CH_DIRECTION, CH_MOMENT, CH_RADIAL, CH_SPEED, channel_integral
from ..statics.equilibrium import solve_statics
from ..dynamics.ring_modes import set_static_modes


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
        geo = (model.arcs[a, A_CR], model.arcs[a, A_CZ], model.arcs[a, A_RMH], model.arcs[a, A_SIDE], h, 0.0)
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
    (:func:`rvcore.contact.pose.ring_angular_velocity`): spin about its tilted axis plus the
    tilt rates, as in the right-hand side.
    """
    r00, _, r02, _, _, r12, r20, _, r22 = ring_rotation(y[3], y[4])
    om = np.array(ring_angular_velocity(omega, y[8], y[9], r00, r20, r02, r12, r22))
    return y[5:8] + np.cross(om, np.asarray(point) - y[0:3])


def set_rolling_velocities(model, y, omega):
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
    that started the balls of a 6010 moving radially at up to 1.3 m/s. The
    cage takes the balls' mean orbital speed.
    """

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


def random_start(model, y, seed: int) -> None:
    """Turn every ball about the axis by a uniform draw within its pocket's play.

    The circumferential play of a ball in its pocket is ``±(pocket diameter − D)/2``; the
    ball keeps its quasi-static radial and axial position (the load changes by a
    negligible amount over such an angle).
    """

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


def initial_state(model, resolved, t_start, seed: int = -1, rings=None):
    """Quasi-static equilibrium of the loads (and the ring's weight) at ``t_start``.

    Flexible rings (``rings``, the modes ``model`` keeps: :func:`rvcore.dynamics.ring_modes.truncated`)
    start in the flexible statics' equilibrium, their modes at its static amplitudes
    (:func:`rvcore.dynamics.ring_modes.set_static_modes`).

    Balls take the equilibrium radial and axial positions at their pocket azimuths, or,
    with ``seed`` ≥ 0, at a random position within their pocket play
    (:func:`random_start`); when the prescribed speed at ``t_start`` is not zero, every
    ball starts rolling without slip and the cage at the balls' mean orbital speed.
    """

    fr = resolved.value(CH_RADIAL, t_start)
    fa = resolved.value(CH_AXIAL, t_start)
    w = resolved.value(CH_SPEED, t_start)
    moment = resolved.value(CH_MOMENT, t_start)
    psi = resolved.value(CH_DIRECTION, t_start)
    y = nominal_state(model)
    # the statics always run: a preloaded pair or an interference fit loads its balls even
    # with no load and no weight, and centred balls would start squeezed out of equilibrium

    table, meta = resolved.arrays()
    st = solve_statics(model, fr, fa, moment, psi, stiffness=False,
                       ring_angle=channel_integral(table, meta, CH_SPEED, t_start), rings=rings)
    y[0:5] = st.displacement
    if st.ring_forces is not None:
        set_static_modes(model, rings, st.ring_forces, st.azimuths, y)
    for r in range(model.rows.shape[0]):
        b0, z, p0 = int(model.rows[r, R_BALL0]), int(model.rows[r, R_Z]), int(model.rows[r, R_POCKET0])
        for j in range(z):
            b = b0 + BALL_STATES * j
            cs, sn = model.pockets[p0 + j, 0], model.pockets[p0 + j, 1]
            rho, zz = st.ball_positions[p0 + j]
            y[b:b + 3] = rho * cs, rho * sn, zz
    if seed >= 0:
        random_start(model, y, seed)
    if w != 0.0:
        set_rolling_velocities(model, y, w)
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
    # the cage at half the ring's speed: a bound on the epicyclic ratio, which is below ½
    # for an inner ring that turns (epicyclic_cage_ratio)
    centrifugal = float(np.max(centrifugal_ball_load(model.rows[:, R_MB], model.rows[:, R_PITCH_R], 0.5 * w)))
    return q + centrifugal
