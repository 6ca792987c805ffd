"""A preloaded pair and the tangent stiffness of the statics.

Reduced bearings (12 balls of the study's ring section) keep every solve to milliseconds.
Every expected value is derived here from the geometry and Hertz's law, independently of
rvcore's quasi-static solver.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import optimize

from rvcore import hertz
from rvcore.statics.preload import apply_preload, mirrored_rows
from rvcore.statics.equilibrium import solve_statics
from rvcore.statics.stiffness import load_frame

from .physics_cases import section_bearing


def _row(angle_deg: float = 15.0):
    b = section_bearing(12, alpha=math.radians(angle_deg))
    return b, b.rows[0]


def _pair(angle_deg=25.0, preload=2000.0, arrangement="back-to-back", spacing=0.03):
    b, row = _row(angle_deg)
    rows = mirrored_rows(row, arrangement, spacing)
    return apply_preload(dataclasses.replace(b, rows=rows, arrangement=arrangement, preload=preload))


def test_mirrored_rows_back_to_back_meet_the_axis_outside():
    """Back-to-back: each row's line of contact meets the axis beyond the rows' span."""
    pair = _pair(arrangement="back-to-back")
    crossings = [r.axial_position - r.pitch_diameter / 2 * math.tan(r.nominal_contact_angle) for r in pair.rows]
    assert crossings[0] < pair.rows[0].axial_position < pair.rows[1].axial_position < crossings[1]
    x = _pair(arrangement="face-to-face")
    crossings = [r.axial_position - r.pitch_diameter / 2 * math.tan(r.nominal_contact_angle) for r in x.rows]
    assert x.rows[0].axial_position < crossings[0] and crossings[1] < x.rows[1].axial_position


def test_preload_offset_gives_the_preload_by_hand():
    """The offset the statics found, put through the curvature-centre geometry and Hertz
    by hand, carries the preload asked for.

    Each row's inner raceway moves axially by δ₀/2; with zero clearance the groove centres
    start ``A₀ = (f_i + f_o − 1)·D`` apart along the nominal contact line, so they end
    ``A = |(A₀ cos α, A₀ sin α + δ₀/2)|`` apart at the loaded angle
    ``α' = atan2(A₀ sin α + δ₀/2, A₀ cos α)``. Each ball is two Hertz contacts in series,
    ``Q = K_e·(A − A₀)^1.5`` with ``K_e = (K_i^(−2/3) + K_o^(−2/3))^(−3/2)`` at α', and the
    row carries ``Z·Q·sin α'`` axially. The root-finder's target (the statics' mean row
    load) is not used.
    """
    pair = _pair(preload=2000.0)
    assert pair.preload_offset > 0
    row = pair.rows[0]
    d, z = row.ball_diameter, row.ball_count
    fi, fo, a = row.inner_arcs[0].curvature_ratio, row.outer_arcs[0].curvature_ratio, row.nominal_contact_angle
    assert row.radial_clearance == 0.0
    a0 = (fi + fo - 1.0) * d
    axial, radial = a0 * math.sin(a) + pair.preload_offset / 2.0, a0 * math.cos(a)
    loaded_angle = math.atan2(axial, radial)
    e = hertz.effective_modulus(pair.ring_material.youngs_modulus, pair.ring_material.poisson_ratio,
                                pair.ball_material.youngs_modulus, pair.ball_material.poisson_ratio)
    ki = hertz.race_contact(d, row.pitch_diameter, fi, loaded_angle, "inner", e).stiffness
    ko = hertz.race_contact(d, row.pitch_diameter, fo, loaded_angle, "outer", e).stiffness
    ke = (ki ** (-2 / 3) + ko ** (-2 / 3)) ** -1.5
    q = ke * (math.hypot(axial, radial) - a0) ** 1.5
    assert z * q * math.sin(loaded_angle) == pytest.approx(2000.0, rel=1e-4)
    # the rows push the ring opposite ways: no net force, and the ring stays centred
    st = solve_statics(pair, gravity=False, stiffness=False)
    assert abs(st.row_forces[:, 2].sum()) < 1e-6 * 2000.0
    assert np.abs(st.displacement).max() < 1e-12


def test_tandem_pair_cannot_be_preloaded():
    with pytest.raises(ValueError, match="tandem"):
        _pair(arrangement="tandem", preload=1000.0)


def test_symmetric_pair_under_pure_radial_load_neither_tilts_nor_moves_axially():
    """Mirror symmetry about the mid-plane z = 0 (the weight acts in that plane too)."""
    pair = _pair()
    st = solve_statics(pair, radial_load=10e3, load_angle=0.3, gravity=True)
    assert abs(st.displacement[2]) < 1e-9
    assert np.abs(st.displacement[3:]).max() < 1e-9
    np.testing.assert_allclose(st.row_radial_loads[0], st.row_radial_loads[1], rtol=1e-9)
    np.testing.assert_allclose(st.row_axial_loads[0], st.row_axial_loads[1], rtol=1e-9)
    # and the rows carry the radial load between them
    total = st.row_forces[:, :2].sum(axis=0)
    np.testing.assert_allclose(-total, st.applied[:2], rtol=1e-6)


def _unloading_load(pair, preload):
    """External axial load at which the opposite row's axial load reaches zero [N]."""
    def opposite(fa):
        return solve_statics(pair, axial_load=fa, gravity=False, stiffness=False).row_axial_loads[1] - 1e-9 * preload
    return optimize.brentq(opposite, 1.5 * preload, 6.0 * preload, xtol=1e-6 * preload)


def test_back_to_back_pair_unloads_its_opposite_row_at_2_to_the_3_halves_preload():
    """Hertz's 3/2 law at equal, fixed contact angles.

    Each row's axial load follows ``F = c·δ^1.5`` in its own axial approach δ. Preloaded,
    both rows sit at δ_p with ``F_p = c·δ_p^1.5``. An external load moves the ring by x:
    ``F_a = c·((δ_p + x)^1.5 − (δ_p − x)^1.5)``. The opposite row unloads at x = δ_p:
    ``F_a = c·(2·δ_p)^1.5 = 2^(3/2)·F_p``. Under load the contact angle of the loaded row
    grows and that of the unloading row shrinks, which moves the point; the steeper the
    nominal angle and the lighter the preload, the smaller that change. At 40° and 1 kN on
    12 balls it is within 2 %; the test also checks the departure grows with the preload,
    as an angle change would make it.
    """
    ratio = 2.0 ** 1.5
    light = _unloading_load(_pair(angle_deg=40.0, preload=1000.0), 1000.0) / 1000.0
    assert light == pytest.approx(ratio, rel=0.02)
    heavy = _unloading_load(_pair(angle_deg=40.0, preload=3000.0), 3000.0) / 3000.0
    assert abs(heavy / ratio - 1) > abs(light / ratio - 1)


def _load_vector_statics(bearing, load, x0=None, **kw):
    """Statics under the applied vector (Fx, Fy, Fz, Mx, My) [N, N m]."""
    fr, psi = math.hypot(load[0], load[1]), math.atan2(load[1], load[0])
    return solve_statics(bearing, radial_load=fr, load_angle=psi, axial_load=load[2],
                         moment_x=load[3], moment_y=load[4], x0=x0, **kw)


def test_stiffness_is_symmetric_positive_definite_and_inverts_to_the_compliance():
    pair = _pair()
    load = np.array([8e3, 1e3, 2e3, 150.0, -400.0])
    st = _load_vector_statics(pair, load, gravity=False)
    k = st.stiffness_matrix
    assert k.shape == (5, 5)
    assert np.abs(k - k.T).max() < 1e-4 * np.abs(k).max()
    assert np.linalg.eigvalsh(0.5 * (k + k.T)).min() > 0.0
    assert st.stiffness_change < 1e-3
    # compliance by central differences of the statics under small load changes
    steps = np.array([50.0, 50.0, 50.0, 2.0, 2.0])
    c = np.empty((5, 5))
    for j in range(5):
        d = np.zeros(5)
        d[j] = steps[j]
        up = _load_vector_statics(pair, load + d, x0=st.displacement, gravity=False, stiffness=False)
        down = _load_vector_statics(pair, load - d, x0=st.displacement, gravity=False, stiffness=False)
        c[:, j] = (up.displacement - down.displacement) / (2 * steps[j])
    inv = np.linalg.inv(k)
    for j in range(5):
        assert np.linalg.norm(c[:, j] - inv[:, j]) < 0.01 * np.linalg.norm(inv[:, j]), j


def test_rotating_the_load_rotates_the_stiffness():
    """A load turned by ψ = 3 ball pitches meets the same ball pattern turned by ψ.

    Only turns by whole ball pitches (2π/Z) are exact symmetries of a bearing of Z balls;
    the weight is switched off because it does not turn with the load.
    """
    pair = _pair()
    z = pair.rows[0].ball_count
    psi = 3 * 2 * math.pi / z
    k0 = solve_statics(pair, 8e3, 2e3, 300.0, 0.0, gravity=False).stiffness_matrix
    k1 = solve_statics(pair, 8e3, 2e3, 300.0, psi, gravity=False).stiffness_matrix
    t = load_frame(psi)
    np.testing.assert_allclose(k1, t.T @ k0 @ t, atol=1e-5 * np.abs(k0).max())


def _jones_single_row(bearing, applied):
    """Independent statics of one angular-contact row: the curvature-centre model.

    With no ball inertia a ball between two arcs sits on the line joining the arcs'
    centres, so each ball is one spring ``Q = K_e·(|C_i − C_o| − A₀)^1.5`` with
    ``A₀ = (f_i + f_o − 1)·D`` and ``K_e = (K_i^(−2/3) + K_o^(−2/3))^(−3/2)`` (two Hertz
    contacts in series). The inner centre moves with the ring (rotation ``Ry·Rx`` about
    its centre), and as in Jones's model only the part of that motion in the
    ball's own meridian plane counts: the groove is a torus, so sliding the ring along a
    ball's rolling direction leaves the nearest groove centre where it was. Returns the
    pose (x, y, z, tilt_x, tilt_y).
    """
    row = bearing.rows[0]
    d, rm, a = row.ball_diameter, row.pitch_diameter / 2, row.nominal_contact_angle
    fi, fo = row.inner_arcs[0].curvature_ratio, row.outer_arcs[0].curvature_ratio
    e = hertz.effective_modulus(bearing.ring_material.youngs_modulus, bearing.ring_material.poisson_ratio,
                                bearing.ball_material.youngs_modulus, bearing.ball_material.poisson_ratio)
    ki = hertz.race_contact(d, row.pitch_diameter, fi, a, "inner", e).stiffness
    ko = hertz.race_contact(d, row.pitch_diameter, fo, a, "outer", e).stiffness
    ke = (ki ** (-2 / 3) + ko ** (-2 / 3)) ** -1.5
    a0 = (fi + fo - 1) * d
    psi = 2 * math.pi * np.arange(row.ball_count) / row.ball_count
    er = np.stack([np.cos(psi), np.sin(psi), np.zeros_like(psi)], axis=1)
    ez = np.array([0.0, 0.0, 1.0])
    ball = rm * er + row.axial_position * ez
    u_c = math.cos(a) * er + math.sin(a) * ez          # the contact line, inner → outer
    ci0 = ball + (fi - 0.5) * d * u_c                   # zero clearance: both centres on it
    co = ball - (fo - 0.5) * d * u_c

    def residual(v):
        t, (tx, ty) = v[:3] * 1e-6, v[3:] * 1e-4
        rx = np.array([[1, 0, 0], [0, math.cos(tx), -math.sin(tx)], [0, math.sin(tx), math.cos(tx)]])
        ry = np.array([[math.cos(ty), 0, math.sin(ty)], [0, 1, 0], [-math.sin(ty), 0, math.cos(ty)]])
        moved = t + ci0 @ (ry @ rx).T - ci0
        ci = ci0 + (moved * er).sum(axis=1)[:, None] * er + moved[:, 2:3] * ez
        gap = ci - co
        dist = np.linalg.norm(gap, axis=1)
        q = ke * np.maximum(dist - a0, 0.0) ** 1.5
        f = -(q / dist)[:, None] * gap                   # on the ring, back along the line
        m = np.cross(ci - t, f)
        total = np.concatenate([f.sum(axis=0), m.sum(axis=0)[:2]])
        return (total + applied) / np.array([1e3, 1e3, 1e3, 1e2, 1e2])

    sol = optimize.root(residual, np.array([5.0, 0.0, 30.0, 0.0, 0.0]), method="hybr", options={"xtol": 1e-13})
    assert sol.success, sol.message
    return np.concatenate([sol.x[:3] * 1e-6, sol.x[3:] * 1e-4])


def test_single_row_tilts_about_x_under_a_moment_about_the_radial_load_axis():
    """Zero clearance, radial load along x, axial load, and M_x about the load's own axis.

    The mirror y → −y leaves F_r (along x) and F_a as they are and reverses M_x. So the
    poses under +M_x and −M_x are mirror images: equal x, z and tilt about y, opposite y
    and tilt about x; the part of the response odd in M_x is a tilt about x (with the y
    shift that goes with it) and nothing else. The pose itself is compared with an
    independent curvature-centre model of the row.
    """
    b, _ = _row()
    assert b.rows[0].radial_clearance == 0.0
    base = np.array([5e3, 0.0, 5e3, 0.0, 0.0])
    m = np.array([0.0, 0.0, 0.0, 100.0, 0.0])
    up = _load_vector_statics(b, base + m, gravity=False, stiffness=False).displacement
    down = _load_vector_statics(b, base - m, gravity=False, stiffness=False).displacement
    # tilts as the displacement they cause at a radius of 0.1 m, to compare like with like;
    # 1e-6 is the solver's tolerance, not a property of the bearing
    scale = np.array([1.0, 1.0, 1.0, 0.1, 0.1])
    mirror = np.array([1.0, -1.0, 1.0, -1.0, 1.0])
    np.testing.assert_allclose(down * scale, mirror * up * scale, rtol=0, atol=1e-6 * np.abs(up * scale).max())
    odd = (up - down) / 2
    assert odd[3] > 0.0   # a positive moment about x turns the ring positively about x
    assert abs(odd[4]) < 1e-6 * abs(odd[3]) and abs(odd[0]) + abs(odd[2]) < 1e-6 * 0.1 * abs(odd[3])
    for load, got in ((base + m, up), (base - m, down)):
        ref = _jones_single_row(b, load)
        # Jones's projection onto the meridian plane drops terms of second order in the
        # ring's motion (≤ 1 mrad, 60 µm here), so the two agree to 0.1 %, not to the
        # solvers' tolerance
        np.testing.assert_allclose(got[:3], ref[:3], rtol=0, atol=1e-3 * np.abs(ref[:3]).max())
        np.testing.assert_allclose(got[3:], ref[3:], rtol=0, atol=1e-3 * np.abs(ref[3:]).max())
