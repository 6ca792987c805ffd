"""Ground truths for gravity, the inner ring's full kinematics, virtual sensors and ensembles.

Every expected value is derived here, from statics, rigid-body kinematics or sampling
theory, and not read from the code's output:

- gravity at rest: force balance of every body of a bearing whose balls, cage and ring
  have come to rest under their own weights (the Hertz and land forces recomputed here
  from the settled positions and the bearing's geometry);
- a gravity-only case gets a stable step from the driver;
- rolling without slip of a tilted, tilting, translating and spinning ring: the ring's
  material-point velocity by finite differences of its pose, not from Ω;
- sensors: the centre sensor is the radial displacement; an axial face sensor reads the
  small-angle expansion of the ring's rotation;
- ensembles: random starts give independent draws whose standard error falls as 1/√N,
  and seed −1 is the centred start;
- (slow) the study's start-up ranges converge with the step.

The only inputs shared with the code are the masses of ``rvcore.bearing.geometry``, the Hertz
constants ``K`` of ``rvcore.hertz`` (checked in test_hertz.py) and, at rest, the pocket
loads of the kernel's per-ball diagnostics.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from rvcore import hertz
from rvcore.simulation.run import run_case
from rvcore.simulation.initial_state import initial_state, set_rolling_velocities
from rvcore.simulation.settings import Sensor, SolverSettings
from rvcore.bearing.geometry import ball_mass, cage_mass_properties, inner_ring_mass_properties
from rvcore.integrate.methods import NAMES as METHODS
from rvcore.dynamics.rhs import new_diagnostics, rhs
from rvcore.bearing.layout import compile_bearing
from rvcore.profile import OperatingPoint, scaled_study_profile, study_profile
from tests.core.physics_cases import ball_states, cage_state, constant_profile, section_bearing

REPO = Path(__file__).resolve().parents[2]
STUDY_SPEED = math.radians(660.0)  # the study's top speed [rad/s]
EZ = np.array([0.0, 0.0, 1.0])
B_QP = 4  # per-ball diagnostic column: pocket load [N] (rvcore.dynamics.rhs.B_QP)


# --------------------------------------------------------------------------- helpers


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def ring_pose(y):
    """Centre and rotation ``Ry(θy)·Rx(θx)`` of the inner ring in state ``y``."""
    return y[0:3].copy(), rot_y(y[4]) @ rot_x(y[3])


def groove_arcs(bearing):
    """Every arc of row 0 as ``(ring, centre_radial, centre_axial, (f − ½)·D, K)``.

    Notes
    -----
    The groove convention of rvcore.bearing.geometry, written out again: an outer arc at α
    touches the centred ball along ``u = (cos α, sin α)`` (radial, axial), an inner arc
    along ``−u``; its centre lies on that line at ``(f − ½)·D − P_d/4`` from the centred
    ball, away from the contact. ``K`` is the Hertz constant at the nominal angle.
    """
    row = bearing.rows[0]
    d, dm = row.ball_diameter, row.pitch_diameter
    e = hertz.effective_modulus(bearing.ring_material.youngs_modulus, bearing.ring_material.poisson_ratio,
                                bearing.ball_material.youngs_modulus, bearing.ball_material.poisson_ratio)
    out = []
    for ring, arcs in (("inner", row.inner_arcs), ("outer", row.outer_arcs)):
        for arc in arcs:
            sign = -1.0 if ring == "inner" else 1.0
            ur, uz = sign * math.cos(arc.contact_angle), sign * math.sin(arc.contact_angle)
            reach = (arc.curvature_ratio - 0.5) * d - row.radial_clearance / 4
            k = hertz.race_contact(d, dm, arc.curvature_ratio, arc.contact_angle, ring, e).stiffness
            out.append((ring, dm / 2 - reach * ur, -reach * uz, (arc.curvature_ratio - 0.5) * d, k))
    return out


def race_contact_geometry(bearing, y, j):
    """Per arc of ball j (row 0): ``(ring, penetration δ, normal n (C→P), contact point, K)``.

    The inner arcs are fixed in the ring: their centre is placed at the ball's azimuth in
    the ring's own frame and carried into the bearing frame by the ring's pose. The
    contact point is on the ball, ``P + (D/2)·n``.
    """
    row = bearing.rows[0]
    h = row.ball_diameter / 2
    b = ball_states(compile_bearing(bearing), y)[j]
    p = b[0:3]
    r_ring, rot = ring_pose(y)
    out = []
    for ring, cr, cz, rmh, k in groove_arcs(bearing):
        if ring == "inner":
            pl = rot.T @ (p - r_ring)
            psi = math.atan2(pl[1], pl[0])
            c = r_ring + rot @ np.array([cr * math.cos(psi), cr * math.sin(psi), row.axial_position + cz])
        else:
            psi = math.atan2(p[1], p[0])
            c = np.array([cr * math.cos(psi), cr * math.sin(psi), row.axial_position + cz])
        dist = float(np.linalg.norm(p - c))
        n = (p - c) / dist
        out.append((ring, dist - rmh, n, p + h * n, k))
    return out


def hertz_race_forces(bearing, y):
    """Elastic race forces on every ball of row 0 at rest: ``(F_inner, F_outer)``, (Z, 3) each [N].

    ``Q = K·δ^1.5`` along ``−n`` (towards the arc centre) for δ > 0; no damping or
    friction (the bodies are at rest, the slips zero).
    """
    z = bearing.rows[0].ball_count
    f_in, f_out = np.zeros((z, 3)), np.zeros((z, 3))
    for j in range(z):
        for ring, delta, n, _, k in race_contact_geometry(bearing, y, j):
            if delta > 0:
                (f_in if ring == "inner" else f_out)[j] += -k * delta**1.5 * n
    return f_in, f_out


def rhs_at(model, y, t, resolved):
    """dy/dt and the per-ball diagnostics of the model at state ``y``."""
    table, meta = resolved.arrays()
    dy = np.zeros_like(y)
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    rhs(t, y, dy, model.params, model.rows, model.arcs, model.pockets, table, meta, diag, bdiag)
    return dy, bdiag


# --------------------------------------------------------------------------- gravity


def _deep_groove(z):
    """The study's section with ``z`` balls on α = 0 grooves (deep groove).

    With one angular-contact arc per ring and no axial load, the ring's weight alone has
    no equilibrium near the centred ring: each loaded ball pushes it axially the same way
    and it walks off by ~0.3 mm until the contact lines turn radial. A deep groove
    carries a pure radial load with the ring in place.
    """
    return section_bearing(z, alpha=0.0)


@pytest.mark.parametrize("method", METHODS)
def test_gravity_at_rest_cage_on_land_balls_carry_ring(method):
    """Horizontal axis, no load, no speed: 10 balls, the ring and the cage settle under gravity.

    Notes
    -----
    Started from the quasi-static sag of the ring under its weight (the cage centred,
    every ball at its pocket centre), the cage drops 0.4 mm onto its outer land and the
    balls settle. At the ~10 N ball loads of the ring's weight a ball between two
    contacts rings at ω_n ≈ 4e4 rad/s (period 1.6e-4 s): a fixed step of 10 µs resolves
    it (the derived step is checked on its own below); 0.8 s brings the kinetic energy from ~5 mJ to ~1e-13 J. (Ten balls, not twelve:
    with Z = 12 a ball sits on top of the inner race at ψ = 90°, where nothing holds it
    circumferentially, and it rolls off like a ball on top of a cylinder, growing as
    exp(√(5g/7(R+r))·t) ≈ exp(6.3 t), until its pocket catches it.)

    At rest every force is static (the slips are zero, so is friction: μ(0) = 0):

    - a ball at azimuth ψ on a deep groove (normals in its meridian plane) cannot take
      the circumferential part of its weight, ``m_b·g·cos ψ`` (gravity along −y), from
      the races: it rolls until its pocket wall carries it, so its pocket load is
      ``m_b·g·|cos ψ|``. Summed over Z evenly spaced balls the reactions on the cage are
      ``Σ m_b·g·cos²ψ_j = (Z/2)·m_b·g`` downwards (their horizontal parts and the radial
      parts of the pocket forces cancel in pairs ψ, ψ+π);
    - so the cage's outer land carries the cage's weight *plus* half the balls' weight,
      ``Q_land = (m_c + Z·m_b/2)·g`` (Z = 10: 15.5 N, 19 % above the cage's 13.1 N);
    - the ring is at rest: the balls' inner-race forces on it sum to ``−m_ring·g``;
    - the whole bearing is at rest: the outer races and the land carry every weight,
      ``Σ F_outer + F_land = −(m_ring + m_c + Z·m_b)·g``.

    The race and land forces are recomputed here from the settled positions (Hertz
    ``K·δ^1.5`` on the bearing's groove geometry; ``K_land·(e − c_land)^1.5`` from the
    cage's eccentricity e); the pocket loads are the kernel's per-ball diagnostics.
    Measured: land 0.25 %, pocket loads 0.06 % of m_b·g, ring 7e-5, total 8e-6.
    Every integrator settles there, at the same fixed step.
    """
    z = 10
    bearing = _deep_groove(z)
    row = bearing.rows[0]
    g_vec = np.array(bearing.gravity, dtype=float)
    g = float(np.linalg.norm(g_vec))
    m_ring = inner_ring_mass_properties(bearing)[0]
    m_c = cage_mass_properties(row)[0]
    m_b = ball_mass(row, bearing.ball_material)
    assert m_b == pytest.approx(bearing.ball_material.density * math.pi * row.ball_diameter**3 / 6, rel=1e-12)

    op = OperatingPoint(0.0, 0.0, 0.0)
    t_end = 0.8
    prof = constant_profile(0.0, t_end)
    res = run_case(bearing, prof, op, SolverSettings(output_rate=1e3, time_step=1e-5, method=method))
    assert res.info["method"] == method
    model = compile_bearing(bearing)
    y = res.final_state
    assert res.series["inner_ring_y"].min() < 0.0  # the ring did sag under its weight

    # at rest: the bodies hardly move, their accelerations are tiny fractions of g
    balls = ball_states(model, y)
    assert np.abs(balls[:, 3:6]).max() < 1e-5  # m/s
    dy, bdiag = rhs_at(model, y, t_end, prof.resolve(op))
    assert np.abs(ball_states(model, dy)[:, 3:6]).max() < 0.02 * g  # µm-scale contact ringing
    assert np.abs(dy[5:8]).max() < 1e-3 * g
    assert np.abs(cage_state(model, dy)[4:7]).max() < 1e-3 * g

    # (a) the cage rests on its land, straight below the axis
    cage = cage_state(model, y)
    ecc = math.hypot(cage[0], cage[1])
    assert ecc > row.cage.land_clearance
    assert abs(math.atan2(cage[0], -cage[1])) < math.radians(1.0)
    q_land = row.cage.land_stiffness * (ecc - row.cage.land_clearance) ** 1.5
    assert q_land == pytest.approx((m_c + z * m_b / 2) * g, rel=0.01)
    f_land = -q_land * np.array([cage[0], cage[1], 0.0]) / ecc  # on the cage

    # ... and each ball hangs in its pocket by the circumferential part of its weight
    psi = np.arctan2(balls[:, 1], balls[:, 0])
    expected_qp = m_b * g * np.abs(np.cos(psi))
    assert np.abs(bdiag[:, B_QP] - expected_qp).max() < 0.02 * m_b * g

    # (b) the balls carry the ring's weight
    f_in, f_out = hertz_race_forces(bearing, y)
    on_ring = -f_in.sum(axis=0)
    assert np.linalg.norm(on_ring + m_ring * g_vec) < 0.01 * m_ring * g
    # (c) the outer races and the land carry everything
    total_weight = (m_ring + m_c + z * m_b) * g_vec
    assert np.linalg.norm(f_out.sum(axis=0) + f_land + total_weight) < 0.01 * np.linalg.norm(total_weight)


@pytest.mark.parametrize("method", METHODS)
def test_gravity_only_case_gets_a_stable_step(method):
    """No load and no speed: the derived step must still be stable under the ring's weight.

    The ring's 23.8 N weight loads the bottom ball by 9.6 N (quasi-static, zero-clearance
    deep groove, 10 balls), and the balls rattle on the races as the cage drops onto its
    land. The driver derives the step from its estimate of the peak contact load, which
    must include the weight: at 9.6 N the contact-oscillation limit is
    ``2√2/ω_n = 7.0e-5 s`` (``ω_n = √(2·1.5·K^(2/3)·Q^(1/3)/m_b) = 4.0e4 rad/s``,
    K = 4.45e10 N/m^1.5); a step sized for the 1 N floor (8.2e-5 s, 7.7e-5 s once
    fitted to the output interval) is beyond it, and the run blows up within a few ms.
    Every integrator's derived step.
    """
    bearing = _deep_groove(10)
    row = bearing.rows[0]
    m_ring = inner_ring_mass_properties(bearing)[0]
    g = float(np.linalg.norm(bearing.gravity))
    res = run_case(bearing, constant_profile(0.0, 0.03), OperatingPoint(0.0, 0.0, 0.0), SolverSettings(method=method))
    assert res.info["method"] == method
    # the estimate covers at least the ring's weight shared among the balls
    assert res.info["peak_contact_load_estimate"] > m_ring * g / row.ball_count
    assert np.all(np.isfinite(res.series["inner_ring_y"]))


# --------------------------------------------------------------------------- kinematics


def finite_difference_race_velocity(y, omega, point, h=1e-5):
    """Velocity of the inner race's material point now at ``point``, by differentiating its path.

    The point is fixed in the ring: at t = 0 its body coordinates are ``X₀ = R₀ᵀ·(c − r₀)``;
    the ring's centre moves at ``v``, its tilts at their rates and it spins at ω about
    its own axis, so the point is at ``X(t) = r₀ + v·t + Ry(θy + θ̇y·t)·Rx(θx + θ̇x·t)·Rz(ω·t)·X₀``.
    Five-point central difference: truncation ~ (ω·h)⁴/30 ≈ 6e-18 of the surface speed at
    h = 10 µs, round-off ~ 1e-16·|X|/h ≈ 2e-12 m/s.
    """
    r0, rot0 = ring_pose(y)
    x0 = rot0.T @ (np.asarray(point) - r0)

    def x(t):
        return r0 + y[5:8] * t + rot_y(y[4] + y[9] * t) @ rot_x(y[3] + y[8] * t) @ rot_z(omega * t) @ x0

    return (-x(2 * h) + 8 * x(h) - 8 * x(-h) + x(-2 * h)) / (12 * h)


@pytest.mark.parametrize("tilt_rates", [False, True])
def test_tilted_spinning_ring_rolls_without_slip(tilt_rates):
    """Balls set rolling on a tilted ring have zero slip at every race contact.

    The ring is at the statics of F_r = 10 kN, F_a = 5 kN and M = 500 N m at ψ = 0.6 rad
    (it tilts by ~1.7 mrad) and spins at 660°/s about its own, tilted axis. First as
    ``initial_state`` leaves it (tilt rates zero), then with the ring also translating
    (1–2 mm/s) and tilting (0.05, −0.03 rad/s) and the balls re-set by
    ``_rolling_velocities``.

    The slip is computed here: the race's material-point velocity by differentiating
    the path of a point fixed in the ring (:func:`finite_difference_race_velocity`), the
    ball's as ``v + w × (c − P)``, the contact point ``c = P + (D/2)·n`` from the groove
    geometry, and its tangential part (normal n removed) must vanish to round-off:
    < 1e-9·ω·d_m/2 (measured ≲ 1e-12). The outer race is at rest.

    The check can fail: the incomplete race velocity ``v_ring + ω·ẑ × (c − r_ring)``
    (spin about the bearing's axis, no tilt rates) leaves a slip of 1e-4–5e-3·ω·d_m/2
    at every inner contact; and the kernel's friction moments on the balls, which an
    inconsistent race velocity in ``rhs`` makes 1e4–1e5 rad/s², vanish (< 1 rad/s²).
    """
    omega = STUDY_SPEED
    bearing = section_bearing(12)
    row = bearing.rows[0]
    op = OperatingPoint(omega, 10e3, 5e3, moment=500.0, load_angle=0.6)
    model = compile_bearing(bearing)   # the moment and the direction come from the profile
    resolved = constant_profile(0.0, 1.0).resolve(op)
    y = initial_state(model, resolved, 0.0)
    assert math.hypot(y[3], y[4]) > 1e-3  # a real tilt
    assert np.all(y[5:10] == 0.0)
    if tilt_rates:
        y[5:8] = (1e-3, -2e-3, 5e-4)
        y[8:10] = (0.05, -0.03)
        set_rolling_velocities(model, y, omega)

    surface = omega * row.pitch_diameter / 2
    balls = ball_states(model, y)
    n_inner = 0
    for j in range(row.ball_count):
        p, v, w = balls[j, 0:3], balls[j, 3:6], balls[j, 6:9]
        for ring, delta, n, c, _ in race_contact_geometry(bearing, y, j):
            assert delta > 0  # every ball is loaded at both races here
            ball_point = v + np.cross(w, c - p)
            race_point = finite_difference_race_velocity(y, omega, c) if ring == "inner" else np.zeros(3)
            u = ball_point - race_point
            assert np.linalg.norm(u - (u @ n) * n) < 1e-9 * surface, (j, ring)
            if ring == "inner":
                n_inner += 1
                old = y[5:8] + np.cross(omega * EZ, c - y[0:3])
                u_old = ball_point - old
                assert np.linalg.norm(u_old - (u_old @ n) * n) > 1e-5 * surface, j
    assert n_inner == row.ball_count

    # the kernel sees the same race velocity: no friction moment on any ball
    dy, _ = rhs_at(model, y, 0.0, resolved)
    assert np.abs(ball_states(model, dy)[:, 6:9]).max() < 1.0


# --------------------------------------------------------------------------- sensors

SENSOR_OP = OperatingPoint(STUDY_SPEED, 20e3, 8e3, moment=800.0, load_angle=0.7)


def _sensor_run(sensors):
    return run_case(section_bearing(12), constant_profile(0.005, 0.03), SENSOR_OP,
                    SolverSettings(output_rate=1e4), sensors=sensors)


def test_sensor_at_centre_reproduces_radial_displacement():
    """A sensor at the ring's centre aimed along the radial load reads δ_r exactly.

    At p = 0 the rotation term ``(R − I)·p`` vanishes and the reading is
    ``(cos ψ, sin ψ, 0)·r_ring = x·cos ψ + y·sin ψ``, the definition of δ_r; the series
    and the phase metrics (accumulated at every step) agree to round-off. A sensor at the
    centre aimed along z reads δ_a.
    """
    psi = SENSOR_OP.load_angle
    res = _sensor_run((Sensor("centre", (0.0, 0.0, 0.0), (math.cos(psi), math.sin(psi), 0.0)),
                       Sensor("centre-axial", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))))
    s = res.series["sensor_displacement"]
    assert s.shape == (len(res.time), 2)
    dr = res.series["radial_displacement"]
    assert np.abs(dr).max() > 1e-6  # a real signal
    assert np.abs(s[:, 0] - dr).max() < 1e-15
    assert np.abs(s[:, 1] - res.series["axial_displacement"]).max() < 1e-15
    by_hand = res.series["inner_ring_x"] * math.cos(psi) + res.series["inner_ring_y"] * math.sin(psi)
    assert np.abs(s[:, 0] - by_hand).max() < 1e-15
    pm = res.phase_metrics
    for stat in ("range", "mean", "std", "min_time", "max_time"):
        assert pm[f"sensor_displacement_{stat}"].shape == (3, 2)
        np.testing.assert_allclose(pm[f"sensor_displacement_{stat}"][:, 0], pm[f"radial_displacement_{stat}"],
                                   rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(pm[f"sensor_displacement_{stat}"][:, 1], pm[f"axial_displacement_{stat}"],
                                   rtol=1e-9, atol=1e-15)


def test_axial_sensor_reads_tilt_to_first_order():
    """An axial sensor on the ring's face at radius r and azimuth φ reads δ_a + r·(θx·sin φ − θy·cos φ).

    Notes
    -----
    The face point ``p = (r cos φ, r sin φ, z_f)`` moves to ``r_ring + R·p`` with
    ``R = Ry(θy)·Rx(θx)``; its axial displacement is
    ``z + R₂₀·p_x + R₂₁·p_y + (R₂₂ − 1)·z_f`` with ``R₂₀ = −sin θy``,
    ``R₂₁ = cos θy·sin θx``, ``R₂₂ = cos θy·cos θx``. Expanding,
    ``−sin θy ≈ −θy``, ``cos θy·sin θx ≈ θx``, ``cos θy·cos θx − 1 ≈ −(θx² + θy²)/2``::

        reading = δ_a + r·(θx·sin φ − θy·cos φ) + e

    and, since ``1 − cos θx·cos θy ≤ (θx² + θy²)/2``, ``|θy − sin θy| ≤ |θ|³/6`` and
    ``|cos θy·sin θx − θx| ≤ |θ|³/2``, the remainder is bounded by
    ``|e| ≤ |θ|²·(|z_f|/2 + r·|θ|)``: second order, from the face's offset z_f alone.
    The moment (800 N m about the axis normal to the load) tilts the ring by up to
    2.6 mrad, a tilt term r·|θ| up to 0.44 mm at r = 165 mm, against a remainder of
    5e-8 m (the bound: 5.4e-8 m). Checked at four azimuths on the face z_f = B/2, then
    once more exactly with R written out here.
    """
    bearing = section_bearing(12)
    r, z_face = 0.165, bearing.width / 2
    phis = (SENSOR_OP.load_angle, SENSOR_OP.load_angle + math.pi / 2, SENSOR_OP.load_angle + math.pi, 2.0)
    sensors = tuple(Sensor(f"face-{k}", (r * math.cos(f), r * math.sin(f), z_face), (0.0, 0.0, 1.0))
                    for k, f in enumerate(phis))
    res = _sensor_run(sensors)
    s = res.series["sensor_displacement"]
    tx, ty = res.series["inner_ring_tilt_x"], res.series["inner_ring_tilt_y"]
    da = res.series["axial_displacement"]
    tilt2 = tx**2 + ty**2
    assert np.sqrt(tilt2).max() > 5e-4  # the ring does tilt
    bound = tilt2 * (abs(z_face) / 2 + r * np.sqrt(tilt2)) + 1e-18
    for k, f in enumerate(phis):
        tilt_term = r * (tx * math.sin(f) - ty * math.cos(f))
        assert np.all(np.abs(s[:, k] - (da + tilt_term)) <= bound), k
        if k == 0:  # along the load the tilt term dominates the remainder
            assert np.abs(tilt_term).max() > 1000 * bound.max()
        # exactly, with R = Ry(θy)·Rx(θx) written out here
        p = np.array([r * math.cos(f), r * math.sin(f), z_face])
        exact = np.array([res.series["inner_ring_z"][i] + (rot_y(ty[i]) @ rot_x(tx[i]) @ p - p)[2]
                          for i in range(len(res.time))])
        assert np.abs(s[:, k] - exact).max() < 1e-17
    # with the moment about (−sin ψ, cos ψ, 0) the face dips along the load and rises
    # opposite it (or the reverse): readings at φ = ψ and ψ + π straddle δ_a
    late = res.time > 0.02
    assert np.all((s[late, 0] - da[late]) * (s[late, 2] - da[late]) < 0)


# --------------------------------------------------------------------------- ensembles


def test_seed_minus_one_is_the_centred_start_and_seeds_draw_within_the_play():
    """seed −1 puts every ball at its pocket azimuth 2πj/Z; seed k ≥ 0 turns each ball by a
    draw within its pocket's circumferential play ±(pocket diameter − D)/2, keeping its
    quasi-static radius and axial position; the same seed gives the same start."""
    bearing = section_bearing(8)
    row = bearing.rows[0]
    op = OperatingPoint(STUDY_SPEED, 30e3, 10e3)
    model = compile_bearing(bearing)
    resolved = scaled_study_profile(0.05).resolve(op)
    centred = ball_states(model, initial_state(model, resolved, 0.0, seed=-1))
    z = row.ball_count
    psi0 = 2 * np.pi * np.arange(z) / z
    psi_c = np.arctan2(centred[:, 1], centred[:, 0])
    assert np.abs(np.angle(np.exp(1j * (psi_c - psi0)))).max() < 1e-14
    rho_c = np.hypot(centred[:, 0], centred[:, 1])
    play = row.cage.pocket_clearance / 2
    draws = []
    for seed in (0, 1, 2):
        b = ball_states(model, initial_state(model, resolved, 0.0, seed=seed))
        assert np.array_equal(b, ball_states(model, initial_state(model, resolved, 0.0, seed=seed)))
        rho = np.hypot(b[:, 0], b[:, 1])
        np.testing.assert_allclose(rho, rho_c, rtol=1e-13)
        np.testing.assert_array_equal(b[:, 2], centred[:, 2])
        arc = np.angle(np.exp(1j * (np.arctan2(b[:, 1], b[:, 0]) - psi0))) * rho
        assert np.all(np.abs(arc) <= play * (1 + 1e-9))
        assert np.abs(arc).max() > 0.2 * play  # a real draw, not the centre
        draws.append(arc)
    assert not np.allclose(draws[0], draws[1]) and not np.allclose(draws[1], draws[2])


def test_ensemble_standard_error_falls_as_inverse_sqrt_n():
    """16 random starts (seeds 0–15) of 8 balls through the study's start-up at 1/20 of its time.

    Study loads (30 kN + 10 kN) at the top speed; the run ends with the start-up phase
    (0.015–0.04 s). Each realization's start-up δ_r range is one draw (the balls' start
    positions within the 0.25 mm pocket play shift when they pass the load line).

    Notes
    -----
    For independent draws the standard error of the ensemble mean is ``s/√N``: from 4 to
    16 realizations it halves, ``SE₄/SE₁₆ = 2·s₄/s₁₆``. With so few draws the sample
    standard deviations scatter a lot: for normal draws ``s₄/σ ~ √(χ²₃/3)``, so
    ``SE₄/SE₁₆`` from the first four lies in [1.2, 3.5] (s₄/s₁₆ in [0.6, 1.75]) only
    about three times in four. The seeds are fixed, so the outcome is deterministic, but
    any change of the dynamics redraws it: when written it was 1.7–2.6 depending on the
    core's version, while the other groups of four gave 0.5–2.8 (the draws are not
    normal: single realizations fall 2–2.6 σ low). The mean of SE₄ over the four
    disjoint groups, divided by SE₁₆, is the steadier estimate (≈ 2·c₄ ≈ 1.84 for normal
    draws; 1.65–1.74 measured); both must lie in the band. If a legitimate change of the
    draws moves the first-four ratio out of it, look at the group mean first.
    """
    bearing = section_bearing(8)
    prof = scaled_study_profile(0.05)
    _, start, end = prof.phases[0]
    op = OperatingPoint(STUDY_SPEED, 30e3, 10e3)
    ranges = np.array([run_case(bearing, prof, op, SolverSettings(end_time=end, seed=k))
                       .phase_metrics["radial_displacement_range"][0] for k in range(16)])
    assert np.all(np.isfinite(ranges)) and ranges.min() > 0
    assert len(np.unique(ranges)) == 16  # every seed is its own realization
    s16 = ranges.std(ddof=1)
    assert s16 > 1e-3 * ranges.mean()

    def se(x):
        return x.std(ddof=1) / math.sqrt(len(x))

    ratio_first = se(ranges[:4]) / se(ranges)
    ratio_groups = np.mean([se(ranges[k:k + 4]) for k in range(0, 16, 4)]) / se(ranges)
    assert 1.2 < ratio_first < 3.5, ratio_first
    assert 1.2 < ratio_groups < 3.5, ratio_groups


# --------------------------------------------------------------------------- convergence


@pytest.mark.slow
@pytest.mark.parametrize("law", ["coulomb_step", "ehl_bair_winer"])
def test_study_startup_ranges_converge_with_step(law):
    """The study bearing (51 balls) through the study's start-up (0–0.8 s), at step_safety 0.8 and 0.4.

    Study operating point (660°/s, 30 kN, 10 kN). Halving the step must leave the
    start-up phase's δ_r and δ_a ranges within 2 %: they are what the sweeps report,
    and the fixed step is sized from a stability limit, not from an error estimate.
    With the study's dry law and with the lubricated one (docs/model.md §4.1; the bearing
    file's lubricant, issue 40).
    """
    import dataclasses

    from pipeline.schema import load_bearing

    bearing = load_bearing(REPO / "sweeps" / "bearings" / "rv-main-study.toml")
    bearing = dataclasses.replace(bearing, contact=dataclasses.replace(bearing.contact, law=law))
    prof = study_profile()
    op = OperatingPoint(STUDY_SPEED, 30e3, 10e3)
    runs = [run_case(bearing, prof, op, SolverSettings(end_time=0.8, step_safety=safety)) for safety in (0.8, 0.4)]
    assert runs[1].info["time_step"] < 0.6 * runs[0].info["time_step"]
    pairs = {name: (runs[0].phase_metrics[name][0], runs[1].phase_metrics[name][0])
             for name in ("radial_displacement_range", "axial_displacement_range")}
    print(f"{law}: start-up ranges at step_safety 0.8 / 0.4 [nm]: "
          + ", ".join(f"{n} {c * 1e9:.2f} / {f * 1e9:.2f} ({c / f - 1:+.2%})" for n, (c, f) in pairs.items()))
    for name, (coarse, fine) in pairs.items():
        assert fine > 0, pairs
        assert abs(coarse / fine - 1) < 0.02, pairs
