"""Reduced bearings and constant-load profiles, built in code, for the physics tests.

Nothing here computes an expected value: the tests derive those themselves. This module
only assembles :class:`rvcore.bearing.geometry.Bearing` and :class:`rvcore.profile.Profile`
objects small enough that a dynamic case runs in a few seconds, plus the textbook
relations the tests share (Hertz stiffness of a ball between two races in series).

Everything is SI (m, kg, s, N, rad).
"""
from __future__ import annotations

import math

import numpy as np

from rvcore.bearing.geometry import Arc, Bearing, Cage, ContactLaw, InnerRing, Material, Row
from rvcore.hertz import effective_modulus, race_contact
from rvcore.profile import Channel, Profile

STEEL = Material(7800.0, 208e9, 0.3)
BRASS = Material(8500.0, 100e9, 0.34)

#: The study's ring section (rv-main-bearing-study.md, Table 2) [m].
STUDY_BORE, STUDY_OD, STUDY_WIDTH = 0.320, 0.383, 0.030
STUDY_D, STUDY_DM = 0.023, 0.3515


def section_bearing(z: int = 12, *, alpha: float = math.radians(15.0), fi: float = 0.52,
                    fo: float = 0.53, clearance: float = 0.0, four_point: bool = False,
                    damping: float = 250.0, pocket_damping: float = 150.0,
                    land_damping: float = 150.0, mu_static: float = 0.1,
                    name: str = "section") -> Bearing:
    """The study's ring section with ``z`` balls (not the study's 51: cheap to integrate).

    Parameters
    ----------
    z : int
        Ball count [-].
    alpha : float
        Nominal contact angle of the arcs [rad]; 0 gives a deep-groove raceway.
    fi, fo : float
        Inner and outer groove curvature ratios [-].
    clearance : float
        Radial internal clearance P_d [m].
    four_point : bool
        Two arcs per ring at ±alpha (gothic arch) instead of one at alpha.
    damping, pocket_damping, land_damping : float
        ``c_max`` of the ball–race, ball–pocket and cage–land contacts [N s m^-1].
    mu_static : float
        Static friction coefficient [-] (the study's law otherwise).
    name : str
        Bearing name.

    Returns
    -------
    rvcore.bearing.geometry.Bearing
    """
    if four_point:
        inner = (Arc(fi, alpha), Arc(fi, -alpha))
        outer = (Arc(fo, alpha), Arc(fo, -alpha))
    else:
        inner, outer = (Arc(fi, alpha),), (Arc(fo, alpha),)
    cage = Cage(0.3545, 0.366, 0.028, 0.5e-3, 0.4e-3, "outer-land", BRASS, 1e9)
    row = Row(z, STUDY_D, STUDY_DM, 0.0, inner, outer, cage, clearance)
    return Bearing(name, STUDY_BORE, STUDY_OD, STUDY_WIDTH, (row,), STEEL, STEEL, InnerRing(0.340),
                   ContactLaw(damping, 1e-6, pocket_damping, land_damping, mu_static=mu_static))


def constant_profile(t_ramp: float, t_end: float, *, speed_ramp: float = 0.0,
                     phases=None, name: str = "constant") -> Profile:
    """Loads ramp 0 → 1 over ``[0, t_ramp]`` then hold; speed constant or ramped.

    All channels are fractions of the operating point.

    Parameters
    ----------
    t_ramp : float
        Load ramp time [s]; 0 applies the loads at once (held from t = 0).
    t_end : float
        Cycle end [s].
    speed_ramp : float
        0: the speed is the operating point's from t = 0 (so a run starts rolling);
        otherwise it ramps 0 → 1 over ``[0, speed_ramp]`` [s].
    phases : tuple of (name, start, end), optional
        Default: the three phases start-up ``[0, t_end/3)``, steady ``[t_end/3, 2t_end/3)``,
        deceleration ``[2t_end/3, t_end)`` (the names only label windows here).
    name : str

    Returns
    -------
    rvcore.profile.Profile
    """
    if t_ramp > 0:
        load = Channel((0.0, t_ramp), (0.0, 1.0))
    else:
        load = Channel((0.0,), (1.0,))
    if speed_ramp > 0:
        speed = Channel((0.0, speed_ramp), (0.0, 1.0))
    else:
        speed = Channel((0.0,), (1.0,))
    if phases is None:
        phases = (("startup", 0.0, t_end / 3), ("steady", t_end / 3, 2 * t_end / 3),
                  ("deceleration", 2 * t_end / 3, t_end))
    return Profile(name, load, load, speed, tuple(phases), t_end)


def minus_gradient(energy, y: np.ndarray, index: int, step: float = 1e-10) -> float:
    """``−∂V/∂y[index]`` of ``energy(y)`` by the central difference over ``±step`` [the
    energy's unit over y's]: the force a potential exerts along one coordinate."""
    yp, ym = y.copy(), y.copy()
    yp[index] += step
    ym[index] -= step
    return -(energy(yp) - energy(ym)) / (2 * step)


def series_stiffness(k_inner: float, k_outer: float) -> float:
    """Load–approach constant of a ball between two Hertz contacts in series [N m^-1.5].

    Notes
    -----
    ``Q = K_i δ_i^1.5 = K_o δ_o^1.5`` and ``δ = δ_i + δ_o`` give ``Q = K_n δ^1.5`` with
    ``K_n = (K_i^(-2/3) + K_o^(-2/3))^(-3/2)``.
    """
    return (k_inner ** (-2.0 / 3.0) + k_outer ** (-2.0 / 3.0)) ** (-1.5)


def ramp_profile(t_load: float, t_speed0: float, t_speed1: float, t_end: float, phases,
                 name: str = "ramp") -> Profile:
    """Loads ramp 0 → 1 over ``[0, t_load]``; speed ramps 0 → 1 over ``[t_speed0, t_speed1]``.

    Parameters
    ----------
    t_load : float
        End of the load ramp [s].
    t_speed0, t_speed1 : float
        Start and end of the speed ramp [s].
    t_end : float
        Cycle end [s].
    phases : tuple of (name, start, end)
        The three named windows [s].
    name : str

    Returns
    -------
    rvcore.profile.Profile
    """
    load = Channel((0.0, t_load), (0.0, 1.0))
    speed = Channel((t_speed0, t_speed1), (0.0, 1.0))
    return Profile(name, load, load, speed, tuple(phases), t_end)


def ball_states(model, y):
    """Per-ball state rows of row 0, shape (Z, 9): x, y, z, vx, vy, vz, wx, wy, wz (SI).

    The layout is rvcore.bearing.layout's: ball j of row r starts at ``rows[r, R_BALL0] + 9·j``.
    """
    from rvcore.bearing.layout import BALL_STATES, R_BALL0, R_Z

    b0, z = int(model.rows[0, R_BALL0]), int(model.rows[0, R_Z])
    return y[b0:b0 + BALL_STATES * z].reshape(z, BALL_STATES)


def cage_state(model, y):
    """Cage state of row 0: x, y, z, angle, vx, vy, vz, angular speed (SI)."""
    from rvcore.bearing.layout import CAGE_STATES, R_CAGE0

    c0 = int(model.rows[0, R_CAGE0])
    return y[c0:c0 + CAGE_STATES]


def run_in_chunks(method, model, y, resolved, dt, per, chunks, retakes=None):
    """Advance ``y`` in place by ``chunks`` × ``per`` steps of ``dt`` [s] with
    :func:`rvcore.integrate.loop.advance` (no sensors, no output kept), yielding the time [s]
    and the per-ball diagnostics after each chunk. A status other than OK raises. The IMEX
    pocket check and tangents have the case's own tolerances
    (:func:`rvcore.integrate.imex.pocket_energy_tolerance` at the loads' peak contact load and
    the step, :func:`rvcore.integrate.imex.tangent_load_tolerance`). ``retakes``, a list,
    receives each chunk's (steps taken again, substeps they computed)."""

    from rvcore.integrate import loop as ig
    from rvcore.recording.plan import build_plan, new_accumulators
    from rvcore.simulation.initial_state import peak_contact_load
    from rvcore.dynamics.rhs import new_diagnostics
    from rvcore.integrate.imex import pocket_energy_tolerance, tangent_load_tolerance
    from rvcore.integrate.schedule import uniform_schedule

    table, meta = resolved.arrays()
    plan = build_plan(model.rows.shape[0], 0)
    out = np.zeros((per + 2, plan.series.shape[0]))
    acc = new_accumulators(plan, resolved.phases.shape[0])
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    q_peak = peak_contact_load(model, resolved)
    pocket_tolerance = pocket_energy_tolerance(model, q_peak, dt)
    t = 0.0
    for _ in range(chunks):
        status, _, _, _, again, _, computed = ig.advance(
            method, y, t, uniform_schedule(per, dt, per, pocket_tolerance, tangent_load_tolerance(q_peak)), model,
            table, meta, resolved.phases, np.zeros((0, 6)), out, acc, plan, diag, bdiag, 1e-3, 1e9,
            np.ones(model.rows.shape[0]))
        if retakes is not None:
            retakes.append((again, computed))
        if status != ig.OK:
            raise RuntimeError(f"{method} stopped with status {status} at t = {t} s")
        t += per * dt
        yield t, bdiag


#: Phase minima that start-up and deceleration take at standstill: the film and κ go to 0 with
#: the speed (h ∝ u^0.67, κ ∝ n^0.5), so their minimum there is the value at the first or last
#: loaded step, which the step's size places, not a converging magnitude (the steady phase's is).
AT_STANDSTILL = ("film_thickness_central_min", "film_thickness_minimum_min", "film_parameter_min", "kappa_min")


def phase_metric_changes(coarse, fine):
    """Relative change of every displacement, speed and pressure metric; absolute of the slip.
    The film's and κ's minima of start-up and deceleration (:data:`AT_STANDSTILL`) count as
    converged: they are taken at standstill."""
    out = {}
    for name, v in fine.phase_metrics.items():
        if name.endswith(("_time", "_at_edge")) or name.startswith("phase_"):
            continue   # when an extreme occurs, and whether at an edge, are locators, not magnitudes
        if name.startswith("cage_slip"):
            out[name] = np.abs(coarse.phase_metrics[name] - v)
        elif name != "inner_ring_speed_mean":  # prescribed
            c = coarse.phase_metrics[name]
            # a force that is zero in both (no cage-land contact in a phase) has converged
            out[name] = np.where((c == 0) & (v == 0), 0.0, np.abs(c / np.where(v == 0, np.nan, v) - 1))
            if name in AT_STANDSTILL:
                out[name] = np.where([False, True, False], out[name], 0.0)   # start-up, steady, deceleration
    return out


def axial_point(bearing, p_target):
    """Axial load [N], ball load [N] and contact angle [rad] at which the larger of the
    two race contacts' peak pressures is ``p_target`` [Pa], all balls loaded alike (zero
    clearance)."""
    row = bearing.rows[0]
    (arc_i,), (arc_o,) = row.inner_arcs, row.outer_arcs
    ring, ball = bearing.ring_material, bearing.ball_material
    e_eff = effective_modulus(ring.youngs_modulus, ring.poisson_ratio, ball.youngs_modulus, ball.poisson_ratio)
    hc_i = race_contact(row.ball_diameter, row.pitch_diameter, arc_i.curvature_ratio, arc_i.contact_angle, "inner", e_eff)
    hc_o = race_contact(row.ball_diameter, row.pitch_diameter, arc_o.curvature_ratio, arc_o.contact_angle, "outer", e_eff)
    c_i = 3.0 / (2.0 * math.pi * hc_i.a_coefficient * hc_i.b_coefficient)
    c_o = 3.0 / (2.0 * math.pi * hc_o.a_coefficient * hc_o.b_coefficient)
    # the contact with the larger p_max/Q^(1/3) (here the outer: the inner groove, f_i <
    # f_o, is the more conformal) reaches the target first
    q = (p_target / max(c_i, c_o)) ** 3
    k_n = series_stiffness(hc_i.stiffness, hc_o.stiffness)
    delta = (q / k_n) ** (2.0 / 3.0)
    a = (arc_i.curvature_ratio + arc_o.curvature_ratio - 1.0) * row.ball_diameter
    alpha = math.acos(a * math.cos(arc_i.contact_angle) / (a + delta))
    return row.ball_count * q * math.sin(alpha), q, alpha
