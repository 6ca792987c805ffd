"""The quasi-static solver (rvcore.statics.equilibrium) against hand cases (docs/model.md §9.2).

Every expected value is derived here from textbook relations, independently of the
solver:

- pure axial load: the Jones/Harris relation for the operating contact angle of a ball
  between two rigid grooves whose curvature centres are ``A = (f_i + f_o − 1)·D`` apart;
- pure radial load on a zero-clearance deep-groove bearing: Stribeck's rigid-ring sum;
- radial load at any angle on that bearing: a 2-D rigid-ring Newton solve written here;
- force and moment balance: recomputed from the returned ball positions and loads with
  the groove geometry of ``rvcore.bearing.geometry`` (arc centres, normals) written out again;
- four-point grooves: which arcs must carry load, from symmetry and the clearance.

The only inputs shared with the code are the Hertz constants ``K`` of each contact
(``rvcore.hertz``, checked against an independent integral form in test_hertz.py); the
model evaluates them once at the nominal contact angle, and so do these tests.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from rvcore import hertz
from rvcore.bearing.geometry import Arc
from rvcore.statics.equilibrium import NoEquilibriumError, solve_statics
from tests.core.physics_cases import STEEL, section_bearing, series_stiffness

REPO = Path(__file__).resolve().parents[2]
FOUR_POINT_FILE = REPO / "sweeps" / "bearings" / "four-point-example.toml"
E_STEEL = hertz.effective_modulus(STEEL.youngs_modulus, STEEL.poisson_ratio)


def race_stiffnesses(row, inner_arc=0, outer_arc=0):
    """Hertz ``K_i``, ``K_o`` [N m^-1.5] of a row's arcs at their nominal angles."""
    ai, ao = row.inner_arcs[inner_arc], row.outer_arcs[outer_arc]
    ki = hertz.race_contact(row.ball_diameter, row.pitch_diameter, ai.curvature_ratio,
                            ai.contact_angle, "inner", E_STEEL).stiffness
    ko = hertz.race_contact(row.ball_diameter, row.pitch_diameter, ao.curvature_ratio,
                            ao.contact_angle, "outer", E_STEEL).stiffness
    return ki, ko


def rotation(tilt_x, tilt_y):
    """Inner-ring attitude ``R = Ry(θy)·Rx(θx)`` (the convention of rvcore.dynamics.rhs)."""
    ca, sa, cb, sb = math.cos(tilt_x), math.sin(tilt_x), math.cos(tilt_y), math.sin(tilt_y)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, ca, -sa], [0.0, sa, ca]])
    ry = np.array([[cb, 0.0, sb], [0.0, 1.0, 0.0], [-sb, 0.0, cb]])
    return ry @ rx


def rot_z(phi):
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# --------------------------------------------------------------------------- pure axial


def jones_axial(z, d, f_i, f_o, alpha0, clearance, k_n, f_a):
    """Operating angle [rad], ball load [N] and axial displacement [m] under pure thrust.

    Notes
    -----
    Rigid rings, every ball loaded alike. The inner and outer curvature centres of a ball
    lie on its nominal contact line ``u = (cos α0, sin α0)`` (radial, axial), each arc
    ``g = P_d/4`` short of touching the centred ball, so they start ``L0 = A − P_d/2``
    apart, ``A = (f_i + f_o − 1)·D``. An axial shift ``δ_a`` of the inner ring moves its
    centre along ``z``; the ball sits on the line between the two centres, so::

        cos α = L0·cos α0 / A',   A' = |L0·u + δ_a·ẑ| ,   δ_n = A' − A ,
        Q = K_n·δ_n^1.5 ,   Z·Q·sin α = F_a
        ⇔  F_a / (Z·K_n) = sin α · (L0·cos α0/cos α − A)^1.5
        δ_a = A'·sin α − L0·sin α0

    which with ``P_d = 0`` is the classical ``F_a/(Z·K_n·A^1.5) = sin α·(cos α0/cos α − 1)^1.5``.
    """
    a_dist = (f_i + f_o - 1.0) * d
    l0 = a_dist - clearance / 2.0

    def excess(alpha):
        stretch = max(l0 * math.cos(alpha0) / math.cos(alpha) - a_dist, 0.0)
        return z * k_n * stretch**1.5 * math.sin(alpha) - f_a

    touch = math.acos(min(1.0, l0 * math.cos(alpha0) / a_dist))  # angle at first contact
    alpha = brentq(excess, max(touch, alpha0) + 1e-14, math.radians(89.0), xtol=1e-15, rtol=1e-15)
    a_op = l0 * math.cos(alpha0) / math.cos(alpha)
    return alpha, f_a / (z * math.sin(alpha)), a_op * math.sin(alpha) - l0 * math.sin(alpha0)


@pytest.mark.parametrize("z, alpha0_deg, clearance, f_a", [
    (12, 15.0, 0.0, 10e3),
    (12, 15.0, 40e-6, 10e3),
    (16, 25.0, 0.0, 50e3),
    (12, 15.0, 0.0, 100.0),
])
def test_pure_axial_matches_jones(z, alpha0_deg, clearance, f_a):
    alpha0 = math.radians(alpha0_deg)
    bearing = section_bearing(z, alpha=alpha0, clearance=clearance)
    row = bearing.rows[0]
    res = solve_statics(bearing, 0.0, f_a, gravity=False)

    # symmetry: no radial displacement, equal loads on every ball and both races
    assert abs(res.radial_displacement) < 1e-12
    assert np.hypot(res.displacement[0], res.displacement[1]) < 1e-12
    q = res.ball_loads
    assert res.loaded_ball_count == z
    # 1e-6 (the balance tolerance), not 1e-9: the solver stops at a force residual of
    # ~3e-8 of the load, which leaves tilts of ~1e-12 rad and a ball-load spread of
    # 1.3e-8 at 10 kN, 1.7e-7 at 100 N (see the report)
    assert np.ptp(q) / q.mean() < 1e-6
    # the returned angle carries the load: Z·Q·sin α = F_a
    alpha = res.contact_angles
    assert np.ptp(alpha) < 1e-8
    assert abs(z * q[:, 0].mean() * math.sin(alpha[:, 0].mean()) - f_a) / f_a < 1e-6
    assert abs(z * q[:, 1].mean() * math.sin(alpha[:, 1].mean()) - f_a) / f_a < 1e-6

    # the operating angle, load and axial shift from the Jones relation
    k_n = series_stiffness(*race_stiffnesses(row))
    a_exp, q_exp, da_exp = jones_axial(z, row.ball_diameter, row.inner_arcs[0].curvature_ratio,
                                       row.outer_arcs[0].curvature_ratio, alpha0, clearance, k_n, f_a)
    assert alpha.mean() == pytest.approx(a_exp, rel=1e-6)
    assert alpha.mean() > alpha0  # the thrust opens the angle
    assert q.mean() == pytest.approx(q_exp, rel=1e-6)
    assert res.axial_displacement == pytest.approx(da_exp, rel=1e-6)


# --------------------------------------------------------------------------- Stribeck


def rigid_ring_radial(k_n, psi, load, load_angle):
    """Displacement (x, y) [m] of a rigid inner ring on a zero-clearance deep-groove set.

    Notes
    -----
    Ball j at azimuth ψ_j is squeezed by ``δ_j = max(u·e_j, 0)`` and pushes back with
    ``Q_j = K_n·δ_j^1.5`` along ``e_j``; Newton on ``Σ Q_j e_j = F`` with the Jacobian
    ``Σ 1.5·K_n·δ_j^0.5·e_j e_jᵀ`` (the potential is convex).
    """
    e = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    f = load * np.array([math.cos(load_angle), math.sin(load_angle)])
    u = (load / (k_n * len(psi) / 4)) ** (2 / 3) * f / load
    for _ in range(100):
        d = np.maximum(e @ u, 0.0)
        res = (k_n * d**1.5) @ e - f
        jac = (1.5 * k_n * np.sqrt(d))[:, None, None] * (e[:, :, None] * e[:, None, :])
        step = np.linalg.solve(jac.sum(axis=0), -res)
        u = u + step
        if np.linalg.norm(step) < 1e-16:
            break
    return u


def test_stribeck_deep_groove_zero_clearance():
    z, f_r = 18, 20e3
    bearing = section_bearing(z, alpha=0.0)
    res = solve_statics(bearing, f_r, 0.0, gravity=False)
    psi = 2 * np.pi * np.arange(z) / z
    # Rigid rings, zero clearance: δ_j = δ_r·cos ψ_j, so Q_j = Q_max·cos^1.5 ψ_j in the
    # ±90° zone and F_r = Σ Q_j cos ψ_j = Q_max·Σ cos^2.5 ψ_j.
    c = np.cos(psi)
    zone = c > 1e-12
    q_max_exact = f_r / np.sum(c[zone] ** 2.5)
    q_ball = res.ball_loads.max(axis=1)
    assert res.max_contact_load == pytest.approx(q_max_exact, rel=1e-3)
    assert q_ball[0] == pytest.approx(q_max_exact, rel=1e-3)
    assert q_ball[zone] == pytest.approx(q_max_exact * c[zone] ** 1.5, rel=1e-3)
    assert np.all(q_ball[~zone] == 0.0)
    assert res.loaded_ball_count == int(zone.sum())
    # Stribeck's large-Z constant: 1/(1/2π ∫_{−π/2}^{π/2} cos^2.5) = 4.37
    j_int = quad(lambda x: math.cos(x) ** 2.5, -math.pi / 2, math.pi / 2)[0] / (2 * math.pi)
    assert 1 / j_int == pytest.approx(4.37, abs=0.005)
    assert res.max_contact_load == pytest.approx(4.37 * f_r / z, rel=0.02)
    # the displacement, from the same rigid-ring picture
    k_n = series_stiffness(*race_stiffnesses(bearing.rows[0]))
    assert res.radial_displacement == pytest.approx((q_max_exact / k_n) ** (2 / 3), rel=1e-3)


# --------------------------------------------------------------------------- load direction


@pytest.mark.parametrize("load_angle", [0.0, math.pi / 12, 0.37, 3 * 2 * math.pi / 12 + 0.37, 2.0])
def test_radial_direction_deep_groove_against_rigid_ring(load_angle):
    """Any load angle (on a ball, between balls, or neither) against a 2-D solve here."""
    z, f_r = 12, 20e3
    bearing = section_bearing(z, alpha=0.0)
    res = solve_statics(bearing, f_r, 0.0, 0.0, load_angle, gravity=False)
    k_n = series_stiffness(*race_stiffnesses(bearing.rows[0]))
    u = rigid_ring_radial(k_n, 2 * np.pi * np.arange(z) / z, f_r, load_angle)
    # the model keeps the exact geometry (the ring's sideways shift moves each ball by
    # ~|u|²/(2·r) more): ~1.5e-4 relative at these 62 µm, well inside 1e-3
    assert np.linalg.norm(res.displacement[:2] - u) < 1e-3 * np.linalg.norm(u)
    assert abs(res.displacement[2]) < 1e-12


def test_radial_compliance_depends_on_ball_position():
    """|δ| is not rotation invariant: the ring is stiffer with a ball on the load line.

    Z = 12 balls, load on a ball (0) and midway between two (π/12). The rigid-ring model
    gives the ratio; the solver must reproduce it, so a rotation by a non-multiple of
    the ball spacing does *not* give the same |δ| (variable compliance).
    """
    z, f_r = 12, 20e3
    bearing = section_bearing(z, alpha=0.0)
    k_n = series_stiffness(*race_stiffnesses(bearing.rows[0]))
    psi = 2 * np.pi * np.arange(z) / z
    on = solve_statics(bearing, f_r, 0.0, 0.0, 0.0, gravity=False)
    mid = solve_statics(bearing, f_r, 0.0, 0.0, math.pi / z, gravity=False)
    ratio_exp = (np.linalg.norm(rigid_ring_radial(k_n, psi, f_r, math.pi / z))
                 / np.linalg.norm(rigid_ring_radial(k_n, psi, f_r, 0.0)))
    ratio = np.linalg.norm(mid.displacement[:2]) / np.linalg.norm(on.displacement[:2])
    assert abs(ratio_exp - 1.0) > 1e-3  # the effect exists at this Z
    assert ratio == pytest.approx(ratio_exp, abs=2e-5)
    # on the mirror planes (a ball, or midway) the displacement is along the load
    for res, ang in ((on, 0.0), (mid, math.pi / z)):
        transverse = -res.displacement[0] * math.sin(ang) + res.displacement[1] * math.cos(ang)
        assert abs(transverse) < 1e-9 * np.linalg.norm(res.displacement[:2])


@pytest.mark.parametrize("base", [0.0, 0.37])
@pytest.mark.parametrize("k", [1, 5])
def test_radial_direction_rotates_response(base, k):
    """Rotating the load by k ball spacings rotates the whole pose (15° bearing, F_r + F_a)."""
    z = 12
    bearing = section_bearing(z)
    f_r, f_a = 20e3, 8e3
    phi = 2 * math.pi * k / z
    a = solve_statics(bearing, f_r, f_a, 0.0, base, gravity=False)
    b = solve_statics(bearing, f_r, f_a, 0.0, base + phi, gravity=False)
    scale = np.linalg.norm(a.displacement[:3])
    # (1e-7: the solver's own precision is ~4e-8 of the displacement)
    assert np.linalg.norm(rot_z(phi)[:2, :2] @ a.displacement[:2] - b.displacement[:2]) < 1e-7 * scale
    assert np.linalg.norm(b.displacement[:2]) == pytest.approx(np.linalg.norm(a.displacement[:2]), rel=1e-7)
    assert b.displacement[2] == pytest.approx(a.displacement[2], rel=1e-7)
    assert b.radial_displacement == pytest.approx(a.radial_displacement, rel=1e-7)
    # the ring's axis turns with it: Rz(φ)·(R_a·ẑ) = R_b·ẑ. (Not the whole matrix: the
    # Ry(θy)·Rx(θx) parametrisation carries a spurious spin θx·θy/2 about z, which is
    # irrelevant for an axisymmetric ring but differs between the two poses.)
    axis_a = rotation(*a.displacement[3:])[:, 2]
    axis_b = rotation(*b.displacement[3:])[:, 2]
    tilt = np.linalg.norm(a.displacement[3:])
    assert tilt > 1e-4  # a single-row angular bearing tilts under radial load
    assert np.linalg.norm(rot_z(phi) @ axis_a - axis_b) < 1e-7 * tilt
    # and the ball loads are the same set, shifted by k balls
    assert np.allclose(np.roll(a.ball_loads, k, axis=0), b.ball_loads, rtol=1e-6, atol=1e-6 * a.max_contact_load)


def test_radial_direction_mirror_symmetry():
    """Loads mirrored about a ball's plane give mirrored poses (any angle, not a multiple)."""
    z, theta = 12, 0.2
    bearing = section_bearing(z)
    plus = solve_statics(bearing, 20e3, 8e3, 0.0, theta, gravity=False)
    minus = solve_statics(bearing, 20e3, 8e3, 0.0, -theta, gravity=False)
    x, y = plus.displacement[:2]
    scale = np.linalg.norm(plus.displacement[:2])
    assert abs(y) > 1e-3 * scale  # off a mirror plane the response leaves the load line
    assert minus.displacement[0] == pytest.approx(x, abs=1e-7 * scale)
    assert minus.displacement[1] == pytest.approx(-y, abs=1e-7 * scale)
    assert minus.displacement[2] == pytest.approx(plus.displacement[2], rel=1e-7)
    assert minus.radial_displacement == pytest.approx(plus.radial_displacement, rel=1e-7)


# --------------------------------------------------------------------------- force balance


def ring_reactions(bearing, res):
    """Force and moment of the balls on the inner ring [N, N m], recomputed here.

    Notes
    -----
    From ``rvcore.bearing.geometry`` (module doc): an inner arc at contact angle α sits at
    ``C = (d_m/2 + r·cos α, r·sin α)`` in the ring's meridian plane through the ball,
    ``r = (f − ½)·D − P_d/4``. The ball centre ``P`` (returned) is taken into the ring
    frame ``p = Rᵀ·(P − c)``; the contact normal is ``n = R·(p − C)/|p − C|`` and the
    contact load ``Q = K·(|p − C| − (f − ½)·D)^1.5``. The ball pushes the ring with
    ``Q·n`` at the contact point ``P + (D/2)·n``.
    """
    row = bearing.rows[0]
    d, g = row.ball_diameter, row.radial_clearance / 4.0
    c = res.displacement[:3]
    rot = rotation(*res.displacement[3:])
    force, moment = np.zeros(3), np.zeros(3)
    max_load_error = 0.0
    for j in range(row.ball_count):
        e = np.array([math.cos(res.azimuths[j]), math.sin(res.azimuths[j]), 0.0])
        p_glob = res.ball_positions[j, 0] * e + np.array([0.0, 0.0, res.ball_positions[j, 1]])
        p = rot.T @ (p_glob - c)
        e_l = np.array([p[0], p[1], 0.0]) / math.hypot(p[0], p[1])
        for k, arc in enumerate(row.inner_arcs):
            q = res.ball_loads[j, k]
            reach = (arc.curvature_ratio - 0.5) * d - g
            centre = (row.pitch_diameter / 2 + reach * math.cos(arc.contact_angle)) * e_l
            centre[2] = reach * math.sin(arc.contact_angle)
            dist = np.linalg.norm(p - centre)
            pen = dist - (arc.curvature_ratio - 0.5) * d
            k_h = hertz.race_contact(d, row.pitch_diameter, arc.curvature_ratio, arc.contact_angle,
                                     "inner", E_STEEL).stiffness
            q_geom = k_h * max(pen, 0.0) ** 1.5
            if pen > 0 and q_geom > 1e-9 * res.max_contact_load:
                max_load_error = max(max_load_error, abs(q - q_geom) / q_geom)
            if q <= 0.0:
                continue
            n = rot @ ((p - centre) / dist)
            force += q * n
            moment += np.cross(p_glob + d / 2 * n - c, q * n)
    return force, moment, max_load_error


@pytest.mark.parametrize("f_r, f_a, m, psi, four_point", [
    (30e3, 10e3, 500.0, 0.3, False),
    (30e3, 10e3, 0.0, 1.1, False),
    (20e3, 5e3, 300.0, 1.0, True),
    (5e3, 20e3, -800.0, 2.5, False),
])
def test_force_balance_combined_loads(f_r, f_a, m, psi, four_point):
    z = 16 if four_point else 12
    bearing = (section_bearing(z, alpha=math.radians(30), fi=0.53, clearance=40e-6, four_point=True)
               if four_point else section_bearing(z))
    res = solve_statics(bearing, f_r, f_a, m, psi, gravity=False)
    f_app = np.array([f_r * math.cos(psi), f_r * math.sin(psi), f_a])
    m_app = m * np.array([-math.sin(psi), math.cos(psi)])
    f_scale = np.linalg.norm(f_app)
    m_scale = abs(m) + f_scale * bearing.rows[0].ball_diameter  # moment of F over a ball diameter
    # the solver's own residual
    assert np.all(np.isfinite(res.residual))
    assert np.linalg.norm(res.residual[:3]) <= 1e-6 * f_scale
    assert np.linalg.norm(res.residual[3:]) <= 1e-6 * m_scale
    # recomputed here from the returned ball positions and loads
    force, moment, load_err = ring_reactions(bearing, res)
    assert load_err < 1e-9  # the returned loads are Hertz loads of the returned geometry
    assert np.linalg.norm(force + f_app) <= 1e-6 * f_scale
    assert np.linalg.norm(moment[:2] + m_app) <= 1e-6 * m_scale
    # each ball's race loads balance in its meridian plane (no speed: no inertia force)
    row = bearing.rows[0]
    rings = res.arc_rings
    for j in range(z):
        fe = fz = 0.0
        for k in range(len(rings)):
            q, a = res.ball_loads[j, k], res.contact_angles[j, k]
            if q > 0:
                sign = 1.0 if rings[k] == 0 else -1.0  # inner pushes out along +(cos α, sin α)
                fe += sign * q * math.cos(a)
                fz += sign * q * math.sin(a)
        # (1e-5: the angles are meridian-plane angles; a tilted ring gives the inner
        # normals a small out-of-plane part, whose cosine error is ~θ²/2 ≈ 1e-6)
        assert math.hypot(fe, fz) <= 1e-5 * res.max_contact_load
    assert len(row.inner_arcs) + len(row.outer_arcs) == len(rings)


# --------------------------------------------------------------------------- four-point


def four_point_bearing():
    if FOUR_POINT_FILE.exists():
        from pipeline.schema import load_bearing
        return load_bearing(FOUR_POINT_FILE)
    return section_bearing(42, alpha=math.radians(30), fi=0.53, fo=0.53, clearance=40e-6,
                           four_point=True)


def test_four_point_radial_load_uses_all_four_arcs():
    bearing = four_point_bearing()
    row = bearing.rows[0]
    assert len(row.inner_arcs) == 2 and len(row.outer_arcs) == 2
    alpha = abs(row.inner_arcs[0].contact_angle)
    f_r = 30e3
    res = solve_statics(bearing, f_r, 0.0, gravity=False)
    q = res.ball_loads  # columns: inner +α, inner −α, outer +α, outer −α (file order)
    signs = [np.sign(a.contact_angle) for a in row.inner_arcs + row.outer_arcs]
    # by mirror symmetry about the groove mid-plane the ring does not move axially
    assert abs(res.axial_displacement) < 1e-12
    # Which balls carry load: the ring's radial approach at ball j is s_j = δ_r·cos ψ_j.
    # Both diagonals start L0 = A − P_d/2 long (A = (f_i + f_o − 1)·D) on the lines at
    # ±α; moving the inner centres radially by s stretches them to
    # √(L0² + 2·L0·s·cos α + s²), which touches (= A) at s_crit.
    d, pd = row.ball_diameter, row.radial_clearance
    a_dist = (row.inner_arcs[0].curvature_ratio + row.outer_arcs[0].curvature_ratio - 1) * d
    l0 = a_dist - pd / 2
    s_crit = -l0 * math.cos(alpha) + math.sqrt((l0 * math.cos(alpha)) ** 2 + a_dist**2 - l0**2)
    s = res.radial_displacement * np.cos(res.azimuths)
    loaded = q.max(axis=1) > 0
    clear = np.abs(s - s_crit) > 1e-3 * s_crit  # leave out a ball right at first touch
    assert np.array_equal(loaded[clear], (s > s_crit)[clear])
    assert 0 < loaded.sum() < row.ball_count
    # every loaded ball touches all four arcs, mirror pairs equally
    for j in np.flatnonzero(loaded):
        assert np.all(q[j] > 0)
        assert q[j, 0] == pytest.approx(q[j, 1], rel=1e-6)
        assert q[j, 2] == pytest.approx(q[j, 3], rel=1e-6)
        ang = res.contact_angles[j]
        assert np.sign(ang) == pytest.approx(signs)
        assert abs(ang[0]) == pytest.approx(abs(ang[1]), rel=1e-6)
    # the radial load is carried: Σ over inner contacts of Q·cos α·cos ψ = F_r
    inner = res.arc_rings == 0
    carried = np.nansum(q[:, inner] * np.cos(res.contact_angles[:, inner]) * np.cos(res.azimuths)[:, None])
    assert carried == pytest.approx(f_r, rel=1e-4)  # meridian-plane sum: ~|δ|/r off


@pytest.mark.parametrize("f_a", [20e3, -20e3])
def test_four_point_axial_load_uses_one_diagonal(f_a):
    bearing = four_point_bearing()
    row = bearing.rows[0]
    z = row.ball_count
    res = solve_statics(bearing, 0.0, f_a, gravity=False)
    arcs = row.inner_arcs + row.outer_arcs
    # a thrust towards +z is carried by the arcs at +α on both rings (the diagonal whose
    # reaction on the inner ring points to −z), a thrust towards −z by those at −α
    carrying = np.array([np.sign(a.contact_angle) == np.sign(f_a) for a in arcs])
    q = res.ball_loads
    assert np.all(q[:, ~carrying] == 0.0)
    assert np.all(q[:, carrying] > 0.0)
    assert res.loaded_ball_count == z
    # equal by symmetry, to the pose solver's convergence (BFGS, gtol 1e-10): the spread
    # is 1e-8 to 1.3e-6 of the mean (1 mN in 887 N), by the clearance (40 µm nominal or its
    # 40 °C operating value); an unequal share would be percent
    assert np.ptp(q[:, carrying]) / q[:, carrying].mean() < 1e-5
    alpha = np.abs(res.contact_angles[:, carrying])
    assert z * q[:, carrying][:, 0].mean() * math.sin(alpha.mean()) == pytest.approx(abs(f_a), rel=1e-6)
    assert abs(res.radial_displacement) < 1e-12
    assert np.sign(res.axial_displacement) == np.sign(f_a)


# --------------------------------------------------------------------------- lift-off


def test_lift_off_angular_contact():
    """Large F_r with a small F_a on the 15° bearing: part of the set unloads.

    Harris' rigid-ring rule (no tilt): every ball stays loaded only while
    F_r·tan α/F_a ≲ 0.8 (ε ≥ 1); 30 kN with 2 kN gives 4.0, so the zone is well under
    360°. The ring is free to tilt here (no applied moment), and the tilt that balances
    the contact moments loads the balls opposite the load again, so the unloaded balls
    are those near ±90° from it; only the count and the balance are asserted.
    """
    z = 12
    bearing = section_bearing(z)
    f_r, f_a = 30e3, 2e3
    assert f_r * math.tan(math.radians(15)) / f_a > 3.0
    res = solve_statics(bearing, f_r, f_a, gravity=False)
    q = res.ball_loads.max(axis=1)
    assert 0 < res.loaded_ball_count < z
    assert res.loaded_ball_count == int(np.count_nonzero(q > 0))
    assert q[0] == q.max()  # the ball under the load carries most
    assert np.all(np.isnan(res.contact_angles[q == 0]))
    f_app = np.array([f_r, 0.0, f_a])
    assert np.linalg.norm(res.residual[:3]) <= 1e-6 * np.linalg.norm(f_app)
    force, moment, _ = ring_reactions(bearing, res)
    assert np.linalg.norm(force + f_app) <= 1e-6 * np.linalg.norm(f_app)
    assert np.linalg.norm(moment[:2]) <= 1e-6 * np.linalg.norm(f_app) * bearing.rows[0].ball_diameter


# --------------------------------------------------------------------------- no equilibrium


def test_zero_load_gives_zero_response():
    """Every groove in these tests is closed, so zero load is the only trivial case."""
    for bearing in (section_bearing(12), section_bearing(12, clearance=40e-6),
                    section_bearing(16, alpha=math.radians(30), fi=0.53, clearance=40e-6, four_point=True)):
        res = solve_statics(bearing, 0.0, 0.0, gravity=False)
        assert np.all(res.displacement == 0.0)
        assert np.all(res.ball_loads == 0.0)
        assert res.loaded_ball_count == 0
        assert res.max_contact_load == 0.0


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_open_groove_cannot_carry_reverse_thrust():
    """A genuinely impossible case: grooves with flanks on one side only.

    With two arcs per ring, each exists only on its own side of the groove mid-plane
    (rvcore.bearing.geometry). Putting both arcs on the +z side (at 15° and 40°) leaves the
    grooves open towards −z, like a separable (magneto) bearing: a thrust towards +z is
    carried, a thrust towards −z has nothing to push against.
    (A single arc is a closed torus: an angular-contact bearing under reverse thrust
    finds the opposite flank at −α' after an axial jump of ~2·A·sin α, so it is not an
    impossible case in this model.)
    """
    import dataclasses

    base = section_bearing(12)
    row = base.rows[0]
    row = dataclasses.replace(
        row, inner_arcs=(Arc(0.52, math.radians(15)), Arc(0.52, math.radians(40))),
        outer_arcs=(Arc(0.53, math.radians(15)), Arc(0.53, math.radians(40))))
    bearing = dataclasses.replace(base, rows=(row,))
    ok = solve_statics(bearing, 0.0, 10e3, gravity=False)
    assert ok.loaded_ball_count == 12
    assert np.linalg.norm(ok.residual[:3]) <= 1e-6 * 10e3
    with pytest.raises(NoEquilibriumError, match="no equilibrium"):
        solve_statics(bearing, 0.0, -10e3, gravity=False)
