"""The contact laws of rvcore.contact.laws, the profile tables, step sizing and run continuation.

Every expected value is derived here from docs/model.md, never copied from the code's output:
the cubic STEP is written out below (``spec_step``), the friction law of §4 is built from
it (``spec_mu``), and rates are checked against finite differences.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from rvcore.contact import laws as contact
from rvcore.contact import pose as ring_pose
from rvcore.bearing.laws import pack_friction_law
from rvcore.integrate.rk4 import rk4_time_step
from rvcore.simulation.run import run_case
from rvcore.simulation.initial_state import peak_contact_load
from rvcore.simulation.settings import SolverSettings
from rvcore.bearing.layout import compile_bearing
from rvcore.profile import Channel, OperatingPoint, Profile, channel_rate
from rvcore.statics.equilibrium import solve_statics
from tests.core.physics_cases import constant_profile, minus_gradient, section_bearing

MU_S, V_S, MU_D, V_D = 0.1, 0.1, 0.02, 1.0   # the study's friction law (docs/model.md §4)
LAW = pack_friction_law(MU_S, V_S, MU_D, V_D)


def spec_step(x, x0, h0, x1, h1):
    """docs/model.md §3, written independently of the code."""
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    d = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d)


def spec_mu(s, mu_s=MU_S, v_s=V_S, mu_d=MU_D, v_d=V_D):
    """docs/model.md §4."""
    if s < v_s:
        return spec_step(s, -v_s, -mu_s, v_s, mu_s)
    if s <= v_d:
        return spec_step(s, v_s, mu_s, v_d, mu_d)
    return mu_d


# ------------------------------------------------------------------------- the STEP


@pytest.mark.parametrize("x0, h0, x1, h1", [(0.0, 0.0, 1.0, 1.0), (-0.1, -0.1, 0.1, 0.1),
                                            (0.1, 0.1, 1.0, 0.02), (2.0, 5.0, 3.5, -1.0)])
def test_step_matches_the_cubic_and_its_slope(x0, h0, x1, h1):
    xs = np.linspace(x0 - 0.3 * (x1 - x0), x1 + 0.3 * (x1 - x0), 241)
    for x in xs:
        assert contact.step(x, x0, h0, x1, h1) == pytest.approx(spec_step(x, x0, h0, x1, h1),
                                                                rel=1e-13, abs=1e-15)
    # the slope against a central difference of the spec cubic (smooth inside the interval)
    e = 1e-6 * (x1 - x0)
    for x in np.linspace(x0 + 0.01 * (x1 - x0), x1 - 0.01 * (x1 - x0), 37):
        fd = (spec_step(x + e, x0, h0, x1, h1) - spec_step(x - e, x0, h0, x1, h1)) / (2 * e)
        assert contact.step_slope(x, x0, h0, x1, h1) == pytest.approx(fd, rel=1e-6, abs=1e-9)
    assert contact.step_slope(x0 - 1.0, x0, h0, x1, h1) == 0.0
    assert contact.step_slope(x1 + 1.0, x0, h0, x1, h1) == 0.0


def test_damper_ramps_in_as_the_step():
    """STEP(δ, 0, 0, d_max, c_max): 0 at first touch, c_max at d_max and beyond."""
    c_max, d_max = 250.0, 1e-6
    assert contact.damping_coefficient(0.0, c_max, 1.0 / d_max) == 0.0
    for delta in np.linspace(0.0, 3 * d_max, 301):
        expected = c_max if delta >= d_max else c_max * (delta / d_max) ** 2 * (3 - 2 * delta / d_max)
        assert contact.damping_coefficient(delta, c_max, 1.0 / d_max) == pytest.approx(
            expected, rel=1e-12, abs=1e-12)
    # monotone rise, and the force it gives: Hertz plus that damping, never adhesive
    c = [contact.damping_coefficient(d, c_max, 1.0 / d_max) for d in np.linspace(0, d_max, 50)]
    assert np.all(np.diff(c) > 0)
    k, delta, rate = 4.5e10, 0.4e-6, 1e-3
    ramp = c_max * (delta / d_max) ** 2 * (3 - 2 * delta / d_max)
    assert contact.normal_force(delta, rate, k, c_max, 1.0 / d_max) == pytest.approx(
        k * delta ** 1.5 + ramp * rate, rel=1e-12)
    assert contact.normal_force(delta, -1e3, k, c_max, 1.0 / d_max) == 0.0


# ----------------------------------------------------------------------- friction


def test_friction_coefficient_is_the_law():
    for s in np.concatenate([np.linspace(0.0, 1.5, 1501), [V_S, V_D, 1e-12, 10.0]]):
        assert contact.friction_coefficient(s, *contact.NO_FILM, LAW) == pytest.approx(
            spec_mu(s), rel=1e-12, abs=1e-15)


def test_fast_friction_form_agrees_with_the_law_everywhere():
    """friction_per_slip (μ(s)/s from s², the form the right-hand side runs) against the
    law itself, on a dense grid over every branch and on both sides of each breakpoint."""
    grid = np.concatenate([np.geomspace(1e-9, 3.0, 4000),
                           [V_S * (1 - 1e-12), V_S, V_S * (1 + 1e-12), V_D * (1 - 1e-12), V_D,
                            V_D * (1 + 1e-12)]])
    for s in grid:
        fast = contact.friction_per_slip(s * s, *contact.NO_FILM, LAW) * s
        assert fast == pytest.approx(spec_mu(s), rel=1e-9, abs=1e-15)
    # zero slip: a finite μ/s (the slope), so the force vanishes without a division by 0
    assert contact.friction_per_slip(0.0, *contact.NO_FILM, LAW) == pytest.approx(1.5 * MU_S / V_S)


def test_friction_force_is_tangential_and_opposes_slip():
    n = np.array([0.3, -0.4, math.sqrt(1 - 0.25)])
    u = np.array([0.05, 0.2, -0.1])
    q = 1234.0
    ft = np.array(contact.friction_force(*u, *n, q, *contact.NO_FILM, LAW, contact.friction_kind(LAW)))
    vt = u - (u @ n) * n
    s = np.linalg.norm(vt)
    np.testing.assert_allclose(ft, -spec_mu(s) * q * vt / s, rtol=1e-12)


def test_friction_slope_at_zero_slip_is_the_laws_own():
    """docs/model.md §4: the law rises from zero with slope 1.5·μ_s/v_s; a one-sided finite
    difference of the spec law agrees, and so does the function the step size uses."""
    for mu_s, v_s in [(0.1, 0.1), (0.25, 0.02), (0.05, 0.5)]:
        e = 1e-7 * v_s
        fd = spec_mu(e, mu_s, v_s, 0.01, 1.0) / e
        law = pack_friction_law(mu_s, v_s, 0.01, 1.0)
        assert contact.friction_slope_at_zero_slip(law) == pytest.approx(fd, rel=1e-6)
        assert contact.friction_slope_at_zero_slip(law) == pytest.approx(1.5 * mu_s / v_s, rel=1e-14)


def test_friction_slope_and_fall_are_the_laws_own():
    """dμ/ds against central differences of the spec law on every branch; the steepest
    fall is the STEP's from μ_s to μ_d at its middle, 1.5·(μ_s − μ_d)/(v_d − v_s)."""
    for s in np.concatenate([np.linspace(1e-3, 0.999 * V_S, 7), np.linspace(1.001 * V_S, 0.999 * V_D, 9),
                             [1.5 * V_D]]):
        e = 1e-7 * s
        fd = (spec_mu(s + e) - spec_mu(s - e)) / (2 * e)
        assert contact.friction_slope(s, *contact.NO_FILM, LAW) == pytest.approx(fd, rel=1e-6, abs=1e-9)
    assert contact.friction_falling_slope(LAW) == pytest.approx(1.5 * (MU_S - MU_D) / (V_D - V_S), rel=1e-14)
    assert contact.friction_falling_slope(pack_friction_law(0.1, 0.1, 0.2, 1.0)) == 0.0   # a law that rises


def test_friction_tangent_curvature_is_the_forces_derivative():
    """The friction force's tangent along the slip, ``∂(μ(s)/s·s)/∂s = μ'``, is
    ``μ/s + s²·curvature`` wherever μ does not fall (where it falls, the curvature leaves
    the negative slope out: ``μ/s + s²·curvature = 0``)."""
    for s in np.concatenate([np.geomspace(1e-6, 0.999 * V_S, 9), np.linspace(1.001 * V_S, 0.999 * V_D, 5),
                             [2.0 * V_D]]):
        along = spec_mu(s) / s + s * s * contact.friction_tangent_curvature(s * s, *contact.NO_FILM, LAW)
        e = 1e-5 * s
        slope = (spec_mu(s + e) - spec_mu(s - e)) / (2 * e)
        assert along == pytest.approx(max(slope, 0.0), rel=1e-6, abs=1e-8)


def test_stable_time_step_follows_the_friction_law():
    """The friction-limited step scales as 1/(dμ/ds at 0): doubling μ_s with v_s fixed,
    or halving v_s, halves it (when friction, not contact oscillation, sets the limit)."""
    def dt_for(mu_s, v_s):
        b = section_bearing(12)
        b = replace(b, contact=replace(b.contact, mu_static=mu_s, v_static=v_s))
        return rk4_time_step(compile_bearing(b, damping=False), 3.5e3)

    base = dt_for(0.1, 0.1)
    assert dt_for(0.2, 0.1) == pytest.approx(base / 2, rel=1e-12)
    assert dt_for(0.1, 0.05) == pytest.approx(base / 2, rel=1e-12)


# ------------------------------------------------------------------ contact geometry


def test_pocket_penetration_guards():
    h, pocket_r, ri, ro = 0.0115, 0.0115 + 0.25e-3, 0.17725, 0.183
    # ball centred in the pocket: no contact
    assert contact.pocket_penetration(0.18, 0.0, 0.0, 1.0, 0.0, pocket_r, h, ri, ro)[0] == -1.0
    # ball pushed 0.3 mm circumferentially at the cage's mid radius: δ = 0.3 − 0.25 mm
    d, ax, ay, az, a_sec = contact.pocket_penetration(0.18, 0.3e-3, 0.0, 1.0, 0.0, pocket_r, h, ri, ro)
    assert d == pytest.approx(0.05e-3, rel=1e-9)
    assert (ax, ay, az) == pytest.approx((0.0, h, 0.0), abs=1e-15)
    assert a_sec == pytest.approx(h)
    # ball radially past the cage ring's outer edge by more than its radius: no contact
    assert contact.pocket_penetration(ro + 1.01 * h, 0.3e-3, 0.0, 1.0, 0.0, pocket_r, h, ri, ro)[0] == -1.0


def test_land_penetration():
    d, nx, ny = contact.land_penetration(3e-4, 4e-4, 0.4e-3)
    assert d == pytest.approx(0.1e-3) and (nx, ny) == pytest.approx((0.6, 0.8))
    assert contact.land_penetration(1e-4, 0.0, 0.4e-3)[0] < 0.0


def test_ring_pose_and_angular_velocity():
    """R = Ry(θy)·Rx(θx); Ω = θ̇y·ŷ + θ̇x·Ry(θy)·x̂ + ω·R·ẑ (docs/model.md §1: the spin about the
    ring's own tilted axis plus the tilt rates)."""
    tx, ty = 0.2, -0.35
    r = np.array(ring_pose.ring_rotation(tx, ty)).reshape(3, 3)
    rx = np.array([[1, 0, 0], [0, math.cos(tx), -math.sin(tx)], [0, math.sin(tx), math.cos(tx)]])
    ry = np.array([[math.cos(ty), 0, math.sin(ty)], [0, 1, 0], [-math.sin(ty), 0, math.cos(ty)]])
    np.testing.assert_allclose(r, ry @ rx, atol=1e-15)
    w, wx, wy = 3.0, 0.4, -0.2
    om = ring_pose.ring_angular_velocity(w, wx, wy, r[0, 0], r[2, 0], r[0, 2], r[1, 2], r[2, 2])
    expected = wy * np.array([0, 1, 0]) + wx * ry @ np.array([1, 0, 0]) + w * (ry @ rx) @ np.array([0, 0, 1])
    np.testing.assert_allclose(om, expected, rtol=1e-13, atol=1e-15)


# ------------------------------------------------------------------------ profiles


@pytest.mark.parametrize("interpolation", ["linear", "smoothstep"])
def test_profile_values_and_rate(interpolation):
    times, values = (0.1, 0.4, 0.5, 1.2), (0.0, 2.0, -1.0, 3.0)
    ch = Channel(times, values, relative=False, interpolation=interpolation)
    p = Profile("p", ch, ch, ch, (("startup", 0.1, 0.4), ("steady", 0.4, 0.5),
                                  ("deceleration", 0.5, 1.2)), 1.3)
    r = p.resolve(OperatingPoint(1.0, 1.0, 1.0))
    for t, v in zip(times, values):   # breakpoints
        assert r.value(0, t) == pytest.approx(v, abs=1e-14)
    assert r.value(1, 0.0) == 0.0 and r.value(1, 2.0) == 3.0   # held outside
    for k in range(len(times) - 1):
        t0, t1, v0, v1 = times[k], times[k + 1], values[k], values[k + 1]
        for frac in (0.1, 0.25, 0.5, 0.8):
            t = t0 + frac * (t1 - t0)
            w = frac if interpolation == "linear" else frac * frac * (3 - 2 * frac)
            assert r.value(2, t) == pytest.approx(v0 + (v1 - v0) * w, rel=1e-12, abs=1e-14)
            table, meta = r.arrays()
            e = 1e-7
            fd = (r.value(2, t + e) - r.value(2, t - e)) / (2 * e)
            assert channel_rate(table, meta, 2, t) == pytest.approx(fd, rel=1e-6)
    table, meta = r.arrays()
    assert channel_rate(table, meta, 0, 0.05) == 0.0 and channel_rate(table, meta, 0, 1.25) == 0.0


# ------------------------------------------------------- step sizing: reverse thrust


def test_peak_contact_load_covers_reverse_thrust():
    """A thrust that goes from +1 kN to −10 kN loads the balls at −10 kN: the step must be
    sized there. (Deep groove, so the reverse thrust is carried like a forward one.)"""
    bearing = section_bearing(12, alpha=0.0, clearance=0.0)
    model = compile_bearing(bearing, gravity=False)
    fr = 5e3
    load = Channel((0.0, 0.1), (1.0, 1.0))
    thrust = Channel((0.0, 0.05, 0.1), (1e3, -10e3, -10e3), relative=False)
    speed = Channel((0.0,), (0.0,))
    prof = Profile("reverse", load, thrust, speed, (("startup", 0.0, 0.03), ("steady", 0.03, 0.06),
                                                    ("deceleration", 0.06, 0.1)), 0.1)
    q_peak = peak_contact_load(model, prof.resolve(OperatingPoint(0.0, fr, 1.0)))
    q_reverse = solve_statics(model, fr, -10e3).max_contact_load
    q_forward = solve_statics(model, fr, 1e3).max_contact_load
    assert q_reverse > 1.5 * q_forward        # the case matters
    assert q_peak >= q_reverse * (1 - 1e-9)


# ------------------------------------------------------------------ continuing a run


def test_continuing_from_the_final_state_matches_one_run():
    """t0→t2 in one go equals t0→t1 then t1→t2 started from the first run's final state.

    The fixed steps depend only on the bearing, the whole profile and whether the loads
    and speed are held (from 2 ms here: rvcore.integrate.schedule), so both runs take the
    same steps; only the step times ``t_start + i·dt`` are rounded differently, so the
    states agree to round-off amplified over a few thousand steps."""
    bearing = section_bearing(8)
    prof = constant_profile(0.002, 0.006)
    op = OperatingPoint(math.radians(660.0), 10e3, 4e3)
    t1 = 0.003
    one = run_case(bearing, prof, op, SolverSettings(output_rate=1e4))
    a = run_case(bearing, prof, op, SolverSettings(output_rate=1e4, end_time=t1))
    b = run_case(bearing, prof, op, SolverSettings(output_rate=1e4, start_time=t1),
                 initial_state_vector=a.final_state)
    assert a.info["time_step"] == one.info["time_step"]
    assert a.info["held_time_step"] == one.info["held_time_step"] == b.info["time_step"] == b.info["held_time_step"]
    assert b.info["held_steps"] == b.info["steps"]      # held throughout
    assert a.info["steps"] + b.info["steps"] == one.info["steps"]
    assert b.time[0] == pytest.approx(t1) and b.time[-1] == pytest.approx(one.time[-1])
    y1, y2 = one.final_state, b.final_state
    scale = np.maximum(np.abs(y1), 1e-3 * np.abs(y1).max())
    assert np.max(np.abs(y2 - y1) / scale) < 1e-7
    # and the series of the second half lie on the first run's
    np.testing.assert_allclose(b.series["axial_displacement"],
                               np.interp(b.time, one.time, one.series["axial_displacement"]),
                               rtol=1e-7, atol=1e-13)


# ------------------------------------------- one contact law for forces and energy


def test_rhs_forces_are_minus_the_energy_gradient_with_pocket_contact():
    """Without friction and damping, at rest, the contact force on a ball in rhs is
    −∂V/∂P of potential_energy: both take the race and pocket penetrations from one
    place. Ball 0 is pushed into its pocket wall and ball 1 into its races."""
    from rvcore.simulation.initial_state import initial_state
    from rvcore.dynamics.energy import potential_energy
    from rvcore.dynamics.rhs import new_diagnostics, rhs
    from rvcore.bearing.layout import BALL_STATES, R_BALL0, R_MB

    bearing = section_bearing(8)
    model = compile_bearing(bearing, friction=False, damping=False, gravity=False)
    prof = constant_profile(0.0, 1.0).resolve(OperatingPoint(0.0, 10e3, 4e3))
    table, meta = prof.arrays()
    y = initial_state(model, prof, 0.0)
    b0 = int(model.rows[0, R_BALL0])
    b1 = b0 + BALL_STATES
    px, py = y[b0], y[b0 + 1]
    play = bearing.rows[0].cage.pocket_clearance / 2
    turn = 1.4 * play / math.hypot(px, py)        # past the pocket's play: pocket contact
    y[b0], y[b0 + 1] = math.cos(turn) * px - math.sin(turn) * py, math.sin(turn) * px + math.cos(turn) * py
    y[b1 + 2] += 2e-6                              # ball 1 pressed axially into its races

    dy = np.zeros_like(y)
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    rhs(0.0, y, dy, model.params, model.rows, model.arcs, model.pockets, table, meta, diag, bdiag)
    assert bdiag[0, 4] > 0.0 and bdiag[1, 0] > 0.0       # the contacts under test are on
    m_b = model.rows[0, R_MB]

    def energy(yy):
        return potential_energy(0.0, yy, model.params, model.rows, model.arcs, model.pockets, table, meta)

    for b in (b0, b1):
        for k in range(3):
            assert m_b * dy[b + 3 + k] == pytest.approx(minus_gradient(energy, y, b + k), rel=1e-4, abs=1e-3)
