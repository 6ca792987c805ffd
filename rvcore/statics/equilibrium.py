"""Quasi-static equilibrium of the inner ring on rigid rings with Hertz contacts (or on
flexible rings in their supports: ``solve_statics(..., rings=...)``, docs/model.md §16).

Unknowns: the inner ring's x, y, z and tilts about x and y. Every ball sits at its pocket
azimuth ψ_j = 2πj/Z and finds its own equilibrium in the meridian plane (radial and
axial position) between the arcs of both rings; the ring is then in equilibrium when
the contact reactions balance the applied load and moment.

Notes
-----
With ``δ_k = |P − C_k| − (f_k − ½)·D`` at every arc k (the same geometry as the
dynamics, :func:`rvcore.contact.laws.arc_penetration`) and ``Q_k = K_k·δ_k^1.5``, a ball's
potential energy ``V_j(P) = Σ_k ⅖·K_k·max(δ_k, 0)^2.5`` is convex in P and in the ring
pose u (δ is a norm minus a constant, C affine in u for small tilts). Hence

    V(u) = Σ_j min_P V_j(P, u) − F·u − M·θ

is convex, its gradient is minus the force balance of the ring (envelope theorem) and
the equilibrium is its unique minimiser whenever the balls carry the load. The solver
minimises V (BFGS) and polishes the force balance with a Newton-type root finder
(MINPACK hybrd). Lift-off, four-point contact (several arcs per ring) and several rows
need no special case: they are just more terms in the sums.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from .._numba import kernel
from scipy import optimize

from ..bearing.geometry import INNER, OUTER, Bearing
from ..rings.flexible import FlexibleRings
from .stiffness import free_stiffness_scalars, stiffness_scalars, tangent_stiffness
from ..contact.laws import LOADED_BALL_LOAD, hertz_energy, hertz_load, race_arc_penetration
from ..contact.pose import ring_rotation, ring_to_global, to_ring_frame
from ..dynamics.raceway import ball_offsets
from ..bearing.layout import (A_K, A_PC3, A_RING, A_RMH, P_GX, P_GY, P_GZ, P_TILT_HELD, R_IMPERFECT,
                    P_RING_M, R_ARC0, R_HALF_D, R_NARC, R_PITCH_R, R_POCKET0, R_Z, R_ZROW,
                    CompiledBearing, compile_bearing)


class NoEquilibriumError(ValueError):
    """The load cannot be carried: every ball is unloaded or the ring runs away."""


@kernel(inline=True)
def _ring_transform(u):
    return ring_rotation(u[3], u[4])


@kernel
def _ball_contacts(px, py, pz, u, rot, r, rows, arcs, pockets, spin, q_out, n_out, j, flex):
    """Forces of every arc on a ball at P; fills q_out[j, k] and n_out[j, k, :] (global normal).
    ``spin`` holds the cosine and sine of the inner ring's turn (an imperfect raceway's
    place, :func:`rvcore.dynamics.raceway.ball_offsets`). ``flex[j]`` holds the flexible
    rings' raceway displacements at ball j (inner radial, inner axial, outer radial, outer
    axial [m], :mod:`rvcore.rings.flexible`); an empty ``flex`` (rigid rings) reads nothing."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = rot
    h = rows[r, R_HALF_D]
    zrow = rows[r, R_ZROW]
    a0, na = int(rows[r, R_ARC0]), int(rows[r, R_NARC])
    plx, ply, plz, rho_l = to_ring_frame(px, py, pz, u[0], u[1], u[2], r00, r01, r02, r10, r11, r12,
                                         r20, r21, r22, zrow)
    rho_b = math.sqrt(px * px + py * py)
    dr_i, dr_o, d_half, sl_i, sl_o, dz_i, dz_o, zs_i, zs_o = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if rows[r, R_IMPERFECT] != 0.0:
        dr_i, dr_o, d_half, sl_i, sl_o, dz_i, dz_o, zs_i, zs_o = ball_offsets(
            rows, r, pockets, j, plx, ply, 1.0 / rho_l, spin[0], spin[1], px / rho_b, py / rho_b)
    pzr = pz - zrow
    if flex.shape[0] > 0:
        # each groove's centre displaced with its ring's raceway at this ball, added to the
        # imperfections' (the inner one in the ring frame, the outer one in the fixed frame)
        dr_i += flex[j, 0]
        dz_i += flex[j, 1]
        dr_o += flex[j, 2]
        dz_o += flex[j, 3]
    energy = 0.0
    for k in range(na):
        a = a0 + k
        inner, d, nx, ny, nz = race_arc_penetration(arcs, a, plx, ply, plz, rho_l, 1.0 / rho_l,
                                                    px, py, pzr, rho_b, 1.0 / rho_b, h, dr_i, dr_o, d_half, sl_i, sl_o,
                                                    dz_i, dz_o, zs_i, zs_o)
        if inner:
            nx, ny, nz = ring_to_global(nx, ny, nz, r00, r01, r02, r10, r11, r12, r20, r21, r22)
        n_out[j, k, 0], n_out[j, k, 1], n_out[j, k, 2] = nx, ny, nz
        n_out[j, k, 3] = d + arcs[a, A_RMH]  # |P − C|
        # the same Hertz law and energy as the dynamics (rvcore.contact.laws)
        q_out[j, k] = hertz_load(arcs[a, A_K], d) if d > 0.0 else 0.0
        energy += hertz_energy(arcs[a, A_K], d)
    return energy


@kernel
def ring_balance(u, rows, arcs, pockets, ball_rz, q_out, n_out, tol, spin, flex):
    """Equilibrate every ball for ring pose ``u``; return the balls' force/moment on the ring.

    ``ball_rz[j]`` (radial, axial position of ball j) is the warm start and the result.
    ``spin``: cosine and sine of the angle the ring has turned through (imperfections).
    ``flex``: the flexible rings' raceway displacements per ball, ``(n_balls, 4)`` [m], or
    ``(0, 4)`` for rigid rings (:func:`_ball_contacts`).
    Returns ``(fx, fy, fz, mx, my, potential_energy)``.
    """
    rot = _ring_transform(u)
    fx = fy = fz = mx = my = 0.0
    energy = 0.0
    for r in range(rows.shape[0]):
        p0 = int(rows[r, R_POCKET0])
        na = int(rows[r, R_NARC])
        a0 = int(rows[r, R_ARC0])
        for jj in range(int(rows[r, R_Z])):
            j = p0 + jj
            ex, ey = pockets[j, 0], pockets[j, 1]
            rho, z = ball_rz[j, 0], ball_rz[j, 1]
            # damped Newton on the convex ball energy in the meridian plane (e, ẑ)
            for it in range(200):
                e0 = _ball_contacts(rho * ex, rho * ey, z, u, rot, r, rows, arcs, pockets, spin, q_out, n_out, j, flex)
                g0 = g1 = 0.0
                h00 = h01 = h11 = 0.0
                for k in range(na):
                    q = q_out[j, k]
                    if q <= 0.0:
                        continue
                    ne = n_out[j, k, 0] * ex + n_out[j, k, 1] * ey
                    nz = n_out[j, k, 2]
                    d = n_out[j, k, 3] - arcs[a0 + k, A_RMH]
                    kn = 1.5 * arcs[a0 + k, A_K] * math.sqrt(d)
                    kt = q / n_out[j, k, 3]
                    g0 += q * ne           # gradient of the energy = −force on the ball
                    g1 += q * nz
                    h00 += kn * ne * ne + kt * (1.0 - ne * ne)
                    h01 += (kn - kt) * ne * nz
                    h11 += kn * nz * nz + kt * (1.0 - nz * nz)
                if g0 == 0.0 and g1 == 0.0:
                    break
                lam = 1e-12 * (h00 + h11) + 1e-300
                det = (h00 + lam) * (h11 + lam) - h01 * h01
                s0 = -((h11 + lam) * g0 - h01 * g1) / det
                s1 = -((h00 + lam) * g1 - h01 * g0) / det
                # backtrack until the energy decreases (convex: a full step usually does)
                step_len = 1.0
                for _ in range(60):
                    e1 = _ball_contacts((rho + step_len * s0) * ex, (rho + step_len * s0) * ey,
                                        z + step_len * s1, u, rot, r, rows, arcs, pockets, spin, q_out,
                                        n_out, j, flex)
                    if e1 <= e0:
                        break
                    step_len *= 0.5
                rho += step_len * s0
                z += step_len * s1
                if abs(step_len * s0) + abs(step_len * s1) < tol:
                    break
            ball_rz[j, 0], ball_rz[j, 1] = rho, z
            energy += _ball_contacts(rho * ex, rho * ey, z, u, rot, r, rows, arcs, pockets, spin, q_out, n_out, j, flex)
            # reactions on the inner ring at its contact points
            h = rows[r, R_HALF_D]
            for k in range(na):
                q = q_out[j, k]
                if q <= 0.0 or arcs[a0 + k, A_RING] != 0.0:
                    continue
                nx, ny, nzz = n_out[j, k, 0], n_out[j, k, 1], n_out[j, k, 2]
                cx, cy, cz = rho * ex + h * nx - u[0], rho * ey + h * ny - u[1], z + h * nzz - u[2]
                fx += q * nx
                fy += q * ny
                fz += q * nzz
                mx += cy * q * nzz - cz * q * ny
                my += cz * q * nx - cx * q * nzz
    return fx, fy, fz, mx, my, energy


@dataclass
class StaticResult:
    """Quasi-static equilibrium, SI.

    ``ball_loads[j, k]`` and ``contact_angles[j, k]`` are per ball j (all rows, in order)
    and per arc k of its row (inner arcs first, then outer, as in the bearing file).
    """

    displacement: np.ndarray      # x, y, z [m], tilt_x, tilt_y [rad]
    radial_displacement: float    # along the radial load direction [m]
    axial_displacement: float     # [m]
    ball_positions: np.ndarray    # (n_balls, 2): radial, axial [m]
    azimuths: np.ndarray          # [rad]
    ball_loads: np.ndarray        # [N]
    contact_angles: np.ndarray    # [rad], NaN where unloaded
    arc_rings: np.ndarray         # 0 inner / 1 outer, per arc column
    loaded_ball_count: int        # balls carrying more than LOADED_BALL_LOAD on both races
    max_contact_load: float       # [N]
    max_contact_pressure: float   # [Pa]
    residual: np.ndarray          # force/moment imbalance on the ring [N, N m]
    applied: np.ndarray           # applied fx, fy, fz [N], mx, my [N m], the ring's weight included
    row_of_ball: np.ndarray       # row index of each ball
    row_forces: np.ndarray        # (n_rows, 3): each row's force on the inner ring [N]
    stiffness_matrix: np.ndarray | None  # (5, 5) tangent stiffness over x, y, z, tilt_x, tilt_y [SI]
    stiffness_change: float       # relative change of K when the difference step is halved [-]
    load_angle: float = 0.0       # ψ of the radial load [rad]
    tilt: str = "free"            # how the ring's tilts were held: "free" or "held"
    reaction_moment: np.ndarray = field(default_factory=lambda: np.zeros(2))
    # the moment about x and y [N m] that the support of a "held" ring applies to keep it
    # square (0 when free)
    ring_displacements: np.ndarray | None = None
    # flexible rings (rvcore.rings.flexible): (n_balls, 4) displacement of the inner ring's
    # raceway (radial outward, axial) and of the outer ring's at each ball [m]; None when rigid
    ring_iterations: int = 0      # iterations of the rings' fixed point (0 when rigid)
    ring_forces: np.ndarray | None = None
    # flexible rings: (n_balls, 4) the balls' radial (outward) and axial forces on the inner
    # ring and on the outer ring at the equilibrium [N]; None when rigid

    @property
    def row_axial_loads(self) -> np.ndarray:
        """Axial force each row carries [N] (magnitude of its force on the ring along z)."""
        return np.abs(self.row_forces[:, 2])

    @property
    def row_radial_loads(self) -> np.ndarray:
        """Radial force each row carries [N] (magnitude of its force on the ring in x–y)."""
        return np.hypot(self.row_forces[:, 0], self.row_forces[:, 1])

    def stiffness_scalars(self):
        """Radial [N/m], axial [N/m] and tilting [N m/rad] stiffness in the load frame:
        the direct terms, every other coordinate held (:func:`rvcore.statics.stiffness.stiffness_scalars`)."""
        return stiffness_scalars(self.stiffness_matrix, self.load_angle)

    def free_stiffness_scalars(self):
        """Radial [N/m], axial [N/m] and tilting [N m/rad] stiffness in the load frame with
        the other coordinates free (:func:`rvcore.statics.stiffness.free_stiffness_scalars`); a
        held ring's tilts stay held (its tilting stiffness is then NaN)."""
        return free_stiffness_scalars(self.stiffness_matrix, self.load_angle, tilt_held=self.tilt == "held")


_SCALE = np.array([1e-5, 1e-5, 1e-5, 1e-4, 1e-4])


def solve_statics(bearing_or_model, radial_load: float = 0.0, axial_load: float = 0.0,
                  moment: float = 0.0, load_angle: float = 0.0, *, moment_x: float = 0.0,
                  moment_y: float = 0.0, x0=None, gravity: bool = True,
                  stiffness: bool = True, tilt: str | None = None, ring_angle: float = 0.0,
                  ball_angle: float = 0.0, rings: FlexibleRings | None = None) -> StaticResult:
    """Equilibrium of the inner ring under the given loads and its own weight.

    The applied load vector is ``(F_r·cos ψ, F_r·sin ψ, F_a, M_x, M_y)`` with
    ``M_x = −M·sin ψ + moment_x`` and ``M_y = M·cos ψ + moment_y``: ``moment`` turns about
    the axis normal to the radial load (an overhung load's moment), ``moment_x`` and
    ``moment_y`` add any other moment, such as one about the radial load's own axis.

    Parameters
    ----------
    bearing_or_model : Bearing or CompiledBearing
    radial_load : float
        [N], applied along ``load_angle`` in the x–y plane.
    axial_load : float
        [N], positive towards +z.
    moment : float
        Tilting moment about the axis normal to the radial load, (−sin ψ, cos ψ, 0) [N m].
    load_angle : float
        ψ [rad].
    moment_x, moment_y : float
        Further moment about x and y [N m].
    x0 : array_like, optional
        Initial guess of the pose (x, y, z, tilt_x, tilt_y).
    gravity : bool
        Include the inner ring's weight ``m·g`` (the mounting's gravity vector; a
        ``CompiledBearing`` carries its own, zero when compiled without gravity). The
        balls' weights (a fraction of a newton each) are left out of the statics.
    stiffness : bool
        Also form the 5×5 tangent stiffness at the equilibrium (:mod:`rvcore.statics.stiffness`).
    tilt : {"free", "held"}, optional
        How the ring's tilts are held (docs/model.md §11); by default the bearing's
        ``inner_ring.tilt`` (a ``CompiledBearing``'s ``P_TILT_HELD``). ``"held"`` fixes
        both tilts at 0, solves the three translations and reports the moment the
        support takes (``reaction_moment``); the moment balance is then the support's.
    ring_angle : float
        Angle the inner ring has turned through from its position at t = 0 [rad]: where
        an imperfect inner raceway's eccentricity and waviness stand (docs/model.md §12); no
        effect on a perfect bearing.
    ball_angle : float
        Angle the balls (the cage) have turned through from their pockets' places at
        2πj/Z [rad]: where the balls stand against the load, which a few balls' varying
        compliance depends on (the quasi-static reference of a turning bearing).
    rings : rvcore.rings.flexible.FlexibleRings, optional
        Flexible rings in their supports (docs/model.md §16); rigid by default. Each ball's
        contact then meets its rings' raceways displaced by the rings' deformation at its
        azimuth, and the load distribution and the deformation are solved together (a
        fixed point with Anderson's mixing: the contact forces give the rings' modal
        amplitudes, which move the raceways, which give the forces). The pose is then the supports' (a
        flexible ring's rigid-body orders are its support's), the stiffness the
        assembly's (the deformation settles at every pose of the difference quotient).

    Raises
    ------
    NoEquilibriumError
        When no ball carries the load or the ring moves away without finding support.
    """
    model = (bearing_or_model if isinstance(bearing_or_model, CompiledBearing)
             else compile_bearing(bearing_or_model, gravity=gravity))
    if tilt is None:
        tilt = "held" if model.params[P_TILT_HELD] != 0.0 else "free"
    if tilt not in ("free", "held"):
        raise ValueError(f"tilt {tilt!r} is not 'free' or 'held'")
    spin = np.array([math.cos(ring_angle), math.sin(ring_angle)])
    # the unknowns: all five pose coordinates, or the three translations of a held ring
    n_free = 3 if tilt == "held" else 5
    rows, arcs, pockets = model.rows, model.arcs, model.pockets
    if ball_angle != 0.0:   # every ball turned about the axis with the cage
        pockets = pockets.copy()
        c0, s0 = math.cos(ball_angle), math.sin(ball_angle)
        pockets[:, 0], pockets[:, 1] = (c0 * model.pockets[:, 0] - s0 * model.pockets[:, 1],
                                        s0 * model.pockets[:, 0] + c0 * model.pockets[:, 1])
    n_arcs = int(rows[:, R_NARC].max())
    nb = model.n_balls
    q_out = np.zeros((nb, n_arcs))
    n_out = np.zeros((nb, n_arcs, 4))
    ball_rz = np.zeros((nb, 2))
    for r in range(rows.shape[0]):
        p0, z = int(rows[r, R_POCKET0]), int(rows[r, R_Z])
        ball_rz[p0:p0 + z, 0] = rows[r, R_PITCH_R]
        ball_rz[p0:p0 + z, 1] = rows[r, R_ZROW]
    c, s = math.cos(load_angle), math.sin(load_angle)
    applied = np.array([radial_load * c, radial_load * s, axial_load,
                        -moment * s + moment_x, moment * c + moment_y])
    if gravity:
        applied[:3] += model.params[P_RING_M] * model.params[[P_GX, P_GY, P_GZ]]
    d_max = float(rows[:, R_HALF_D].max()) * 2

    def pose(v):
        """The five pose coordinates of the unknowns ``v`` (scaled), held tilts 0."""
        u = np.zeros(5)
        u[:n_free] = v[:n_free] * _SCALE[:n_free]
        return u

    # flexible rings: each ring's raceway displacement at every ball, (0, 4) when all are rigid
    ring_model = rings   # (the name ``rings`` is the arcs' rings below)
    flexing = ring_model is not None and not ring_model.rigid
    flex = np.zeros((nb if flexing else 0, 4))
    azim_now = np.arctan2(pockets[:, 1], pockets[:, 0])

    def balance(v):
        fx, fy, fz, mx, my, e = ring_balance(pose(v), rows, arcs, pockets, ball_rz, q_out, n_out, 1e-15, spin,
                                             flex)
        return np.array([fx, fy, fz, mx, my])[:n_free] + applied[:n_free], e

    def ring_offsets():
        """The raceways' displacements at every ball under the contact forces now in
        ``q_out``/``n_out`` (:meth:`rvcore.rings.flexible.FlexibleRings.raceway_displacements`)."""
        radial, axial = _ring_forces(rows, arcs, pockets, q_out, n_out)
        out = np.zeros((nb, 4))
        out[:, 0], out[:, 1] = ring_model.raceway_displacements(INNER, radial[:, 0], axial[:, 0], azim_now)
        out[:, 2], out[:, 3] = ring_model.raceway_displacements(OUTER, radial[:, 1], axial[:, 1], azim_now)
        return out

    def settle(solve):
        """Fixed point of the rings' deformation and the load distribution: ``G(x)``, the
        offsets the contact forces give when the raceways stand at ``x`` (``solve()``
        refreshes the forces after ``flex`` is set), iterated with Anderson's mixing (the
        last :data:`_FLEX_MEMORY` steps; Walker & Ni 2011) until ``G(x) = x``. Returns the
        iteration count."""
        xs, gs, fs = [], [], []
        last = math.inf
        for it in range(1, _FLEX_ITERATIONS + 1):
            x = flex.ravel().copy()
            g = ring_offsets().ravel()
            f = g - x
            last = float(np.abs(f).max(initial=0.0))
            if last <= _FLEX_TOL + _FLEX_RTOL * float(np.abs(g).max(initial=0.0)):
                return it
            xs.append(x), gs.append(g), fs.append(f)
            del xs[:-_FLEX_MEMORY - 1], gs[:-_FLEX_MEMORY - 1], fs[:-_FLEX_MEMORY - 1]
            if len(fs) > 1:
                d_f = np.array([fs[i + 1] - fs[i] for i in range(len(fs) - 1)]).T
                d_g = np.array([gs[i + 1] - gs[i] for i in range(len(gs) - 1)]).T
                gamma = np.linalg.lstsq(d_f, f, rcond=None)[0]
                g = g - d_g @ gamma
            flex[:] = g.reshape(flex.shape)
            solve()
        raise NoEquilibriumError(
            f"no equilibrium: the flexible rings' deformation and the load distribution did not settle in "
            f"{_FLEX_ITERATIONS} iterations (last change {last:.3g} m): the rings are too soft for their support")

    # a preloaded bearing carries internal loads at rest: they set the scale too
    v_start = np.zeros(n_free) if x0 is None else np.asarray(x0, float)[:n_free] / _SCALE[:n_free]
    balance(v_start)
    internal = float(q_out.max(initial=0.0))
    load_scale = max(np.abs(applied[:3]).sum(), np.abs(applied[3:]).sum() / 0.1, internal, 1.0)

    def objective(v):
        res, e = balance(v)
        u = pose(v)
        return (e - applied @ u) / load_scale / 1e-5, -res * _SCALE[:n_free] / load_scale / 1e-5

    # Below a micronewton a contact load is the round-off of a closed groove's geometry
    # (δ ~ 1e-11 m at K ~ 4e10 N/m^1.5), not a preload, and does not move the ring.
    flex_iterations = 0
    if not np.any(applied) and internal < 1e-6:
        v = v_start   # nothing loads the ring: it stays where it is
    else:
        v0 = v_start.copy()
        if x0 is None and np.any(applied[:3]):
            # start a few microns along the load so that some contacts are engaged
            f = applied[:3] / max(np.linalg.norm(applied[:3]), 1e-300)
            v0[:3] = f * 1.0
        # a ring that finds no support runs away: overflow there is expected, and reported below
        with np.errstate(over="ignore", invalid="ignore"):
            v = _solve_pose(objective, balance, pose, v0, d_max, load_scale)
            if flexing and np.all(np.isfinite(v)) and np.linalg.norm(pose(v)[:3]) <= d_max:
                state = {"v": v}

                def resolve():
                    state["v"] = _solve_pose(objective, balance, pose, state["v"], d_max, load_scale)
                    balance(state["v"])

                balance(v)
                flex_iterations = settle(resolve)
                v = state["v"]
    u = pose(v) if np.all(np.isfinite(v)) else np.full(5, np.nan)
    if not np.all(np.isfinite(u)) or np.linalg.norm(u[:3]) > d_max:
        raise NoEquilibriumError(
            f"no equilibrium: under F_r = {radial_load:.6g} N, F_a = {axial_load:.6g} N, M = {moment:.6g} N m "
            f"the inner ring runs away (more than a ball diameter, {d_max * 1e3:.4g} mm) without the "
            f"balls carrying the load")
    res, _ = balance(v)
    # a held ring's moment balance is its support's: the reaction is what the contacts
    # and the applied moment leave
    full = np.array(ring_balance(u, rows, arcs, pockets, ball_rz, q_out, n_out, 1e-15, spin, flex)[:5]) + applied
    reaction = -full[3:5] if tilt == "held" else np.zeros(2)
    res = np.concatenate([res, full[3:5] + reaction]) if tilt == "held" else res
    loaded = (q_out > 0).any(axis=1)
    if np.any(applied) and not loaded.any():
        raise NoEquilibriumError(
            f"no equilibrium: every ball is unloaded under F_r = {radial_load:.6g} N, "
            f"F_a = {axial_load:.6g} N, M = {moment:.6g} N m")
    row_forces = np.zeros((rows.shape[0], 3))
    row_of_ball = np.zeros(nb, dtype=int)
    rings = np.full(n_arcs, -1)
    angles = np.full_like(q_out, np.nan)
    pc3 = np.zeros(n_arcs)
    azim = np.zeros(nb)
    for r in range(rows.shape[0]):
        p0, z, a0, na = (int(rows[r, R_POCKET0]), int(rows[r, R_Z]), int(rows[r, R_ARC0]),
                         int(rows[r, R_NARC]))
        rings[:na] = arcs[a0:a0 + na, A_RING]
        pc3[:na] = np.maximum(pc3[:na], arcs[a0:a0 + na, A_PC3])
        row_of_ball[p0:p0 + z] = r
        for j in range(p0, p0 + z):
            ex, ey = pockets[j, 0], pockets[j, 1]
            azim[j] = math.atan2(ey, ex)
            for k in range(na):
                if arcs[a0 + k, A_RING] == 0:   # the row's force on the inner ring, as ring_balance sums it
                    row_forces[r] += q_out[j, k] * n_out[j, k, :3]
                if q_out[j, k] > 0:
                    ne = n_out[j, k, 0] * ex + n_out[j, k, 1] * ey
                    nz = n_out[j, k, 2]
                    sign = -1.0 if arcs[a0 + k, A_RING] == 0 else 1.0
                    angles[j, k] = math.atan2(sign * nz, sign * ne)
    p_max = float(np.max(np.cbrt(pc3[None, :] * q_out))) if q_out.size else 0.0
    result = dict(ball_positions=ball_rz.copy(), ball_loads=q_out.copy(),
                  max_contact_load=float(q_out.max(initial=0.0)))
    if flexing:   # the balls' forces on each ring at the equilibrium: the rings' deformation
        radial, axial = _ring_forces(rows, arcs, pockets, q_out, n_out)
        result["ring_forces"] = np.stack([radial[:, 0], axial[:, 0], radial[:, 1], axial[:, 1]], axis=1)
    k_matrix, k_change = None, float("nan")
    if stiffness:
        base = ball_rz.copy()
        flex_base = flex.copy()

        def ball_forces(uu):
            ball_rz[:] = base   # every pose starts from the equilibrium's balls
            flex[:] = flex_base

            def at_pose():
                return np.array(ring_balance(np.asarray(uu, dtype=float), rows, arcs, pockets, ball_rz, q_out,
                                             n_out, 1e-15, spin, flex)[:5])

            forces = at_pose()
            if flexing:   # the rings' deformation settles at this pose too: the stiffness is the assembly's
                settle(at_pose)
                forces = at_pose()
            return forces

        k_matrix, k_change = tangent_stiffness(ball_forces, u, float(rows[:, R_PITCH_R].max()))
        ball_rz[:] = base
        flex[:] = flex_base
    return StaticResult(
        displacement=u, radial_displacement=float(u[0] * c + u[1] * s), axial_displacement=float(u[2]),
        azimuths=azim, contact_angles=angles, arc_rings=rings, loaded_ball_count=_loaded_balls(q_out, rings),
        max_contact_pressure=p_max, residual=res,
        applied=applied, row_of_ball=row_of_ball, row_forces=row_forces,
        stiffness_matrix=k_matrix, stiffness_change=k_change, load_angle=float(load_angle), tilt=tilt,
        reaction_moment=reaction, ring_displacements=flex.copy() if flexing else None,
        ring_iterations=flex_iterations, **result,
    )


#: The flexible rings' fixed point: at most this many iterations, until the raceways'
#: displacements change by less than _FLEX_TOL [m] plus _FLEX_RTOL of their largest.
_FLEX_ITERATIONS = 200
_FLEX_MEMORY = 6
_FLEX_TOL = 1e-12
_FLEX_RTOL = 1e-8


def _solve_pose(objective, balance, pose, v0, d_max, load_scale):
    """The ring's pose that minimises ``objective`` from ``v0`` (BFGS), polished by a root
    finder on the force balance (MINPACK hybrd) where that balances better."""
    opt = optimize.minimize(objective, v0, jac=True, method="BFGS", options={"gtol": 1e-10, "maxiter": 2000})
    v = opt.x
    if np.all(np.isfinite(v)) and np.linalg.norm(pose(v)[:3]) <= d_max:
        sol = optimize.root(lambda x: balance(x)[0] / load_scale, v, method="hybr",
                            options={"xtol": 1e-14, "maxfev": 2000})
        if np.all(np.isfinite(sol.x)) and np.abs(balance(sol.x)[0]).max() <= np.abs(balance(v)[0]).max():
            v = sol.x
    return v


def _ring_forces(rows, arcs, pockets, q_out, n_out):
    """The balls' forces on each ring at every ball: ``radial[j, ring]`` (along the ball's
    azimuth, outward positive) and ``axial[j, ring]`` [N], ring 0 inner, 1 outer."""
    nb = pockets.shape[0]
    force = np.zeros((nb, 2, 3))
    for r in range(rows.shape[0]):
        p0, z, a0, na = (int(rows[r, R_POCKET0]), int(rows[r, R_Z]), int(rows[r, R_ARC0]), int(rows[r, R_NARC]))
        for k in range(na):
            ring = int(arcs[a0 + k, A_RING])
            force[p0:p0 + z, ring] += q_out[p0:p0 + z, k, None] * n_out[p0:p0 + z, k, :3]
    radial = force[:, :, 0] * pockets[:, 0, None] + force[:, :, 1] * pockets[:, 1, None]
    return radial, force[:, :, 2]


def _loaded_balls(ball_loads, arc_rings) -> int:
    """Balls carrying more than :data:`rvcore.contact.laws.LOADED_BALL_LOAD` on both races
    (several arcs of a ring summed), as the dynamics count them."""
    inner = np.where((arc_rings == 0)[None, :], ball_loads, 0.0).sum(axis=1)
    outer = np.where((arc_rings == 1)[None, :], ball_loads, 0.0).sum(axis=1)
    return int(np.count_nonzero((inner > LOADED_BALL_LOAD) & (outer > LOADED_BALL_LOAD)))
