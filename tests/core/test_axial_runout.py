"""A raceway's axial runout (docs/model.md §12): a groove whose plane is tilted to its ring's
axis. Each expectation is derived here from kinematics, equilibrium or ISO 492's tables,
never from the code's own output.

The reduced 12-ball section of the study bearing, weightless, turning at 2 rev/s.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rvcore import hertz
from rvcore.bearing.geometry import epicyclic_cage_ratio
from rvcore.bearing.imperfections import Imperfections, Waviness, realize
from rvcore.profile import CH_SPEED, OperatingPoint, channel_integral
from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings
from rvcore.statics.equilibrium import solve_statics
from rvcore.statics.runout import runout_path

from .physics_cases import STUDY_D, STUDY_DM, constant_profile, minus_gradient, section_bearing, series_stiffness

Z = 12
FI, FO = 0.52, 0.53              # section_bearing's groove curvature ratios
ALPHA = math.radians(15.0)       # and its contact angle
#: Start-up 0–0.1 s (the loads ramp over 10 ms), steady 0.1–0.6 s: one revolution at 2 rev/s.
PROFILE = constant_profile(0.01, 0.61, phases=(("startup", 0.0, 0.1), ("steady", 0.1, 0.6),
                                               ("deceleration", 0.6, 0.61)))


def bearing(tilt: str = "free", **imperfections):
    b = section_bearing(Z)
    b = dataclasses.replace(b, inner_ring=dataclasses.replace(b.inner_ring, tilt=tilt))
    if imperfections:
        b = dataclasses.replace(b, rows=(dataclasses.replace(b.rows[0], imperfections=Imperfections(
            **imperfections)),))
    return b


def chain_constant() -> float:
    """``K_n`` of a ball between the section's two races in series, ``Q = K_n·δ^1.5``
    [N m^-1.5] (Hertz's point contact, :mod:`rvcore.hertz`)."""
    e = hertz.effective_modulus(208e9, 0.3, 208e9, 0.3)
    k_i = hertz.race_contact(STUDY_D, STUDY_DM, FI, ALPHA, "inner", e).stiffness
    k_o = hertz.race_contact(STUDY_D, STUDY_DM, FO, ALPHA, "outer", e).stiffness
    return series_stiffness(k_i, k_o)


def linear_axial_response(perfect, f_r, f_a, ring_angle, ball_angle, dz_of_angle):
    """The held ring's translation (x, y, z) [m] that a small axial shift of the inner
    groove, ``dz_of_angle(φ)`` at the ring angle φ, adds to the perfect bearing's pose at
    the same ring and ball angles: quasi-static, linear in the shift.

    Each loaded ball j joins the centres of curvature of its two grooves, ``L = A + δ``
    apart (``A = (f_i + f_o − 1)·D``), along its line of contact ``m`` (from the inner
    race through the ball, at the contact angle α): a Hertz chain ``Q = K_n·δ^1.5`` of
    stiffness ``k = 1.5·Q/δ`` along m, and, the ball sitting on the line of centres, a
    turn of that line by a shift ``ε`` of the inner centre across it in the meridian
    plane (along ``t``) turns its force Q by ε/L: a stiffness ``Q/L`` along t. The
    groove shifted by Δz at a ball moves its centre of curvature as the ring moved by
    Δz·ẑ would, so equilibrium of the increments is ``Σ K_j (u + Δz_j ẑ) = 0``,
    ``K_j = k m mᵀ + (Q/L) t tᵀ``.
    """
    st = solve_statics(perfect, f_r, f_a, gravity=False, stiffness=False, tilt="held", ball_angle=ball_angle)
    on = st.ball_loads[:, 0] > 0.0
    q, alpha, theta = st.ball_loads[on, 0], np.abs(st.contact_angles[on, 0]), st.azimuths[on]
    m = np.stack([np.cos(alpha) * np.cos(theta), np.cos(alpha) * np.sin(theta), np.sin(alpha)], axis=1)
    t = np.stack([-np.sin(alpha) * np.cos(theta), -np.sin(alpha) * np.sin(theta), np.cos(alpha)], axis=1)
    # the base state's equilibrium, read with these lines of contact: Σ Q m = F
    np.testing.assert_allclose((q[:, None] * m).sum(axis=0), (f_r, 0.0, f_a), atol=0.01 * f_r)
    delta = (q / chain_constant()) ** (2.0 / 3.0)
    k, g = 1.5 * q / delta, q / ((FI + FO - 1.0) * STUDY_D + delta)
    per_ball = k[:, None, None] * m[:, :, None] * m[:, None, :] + g[:, None, None] * t[:, :, None] * t[:, None, :]
    dz = dz_of_angle(theta - ring_angle)
    return -np.linalg.solve(per_ball.sum(axis=0), (per_ball[:, :, 2] * dz[:, None]).sum(axis=0))


def test_a_class_sets_half_iso492_s_ia_and_s_ea_and_normal_has_none():
    """ISO 492 class 5, bore and outside diameter 315–400 mm (the study's 320/383 mm):
    S_ia 20 µm, S_ea 20 µm (NodesHK's reproduction of the class 5 tables). A tilted plane's
    total indicator reading is 2a, so a = S/2. The Normal class has no axial runout in ISO
    492: 0 unless given; a given amplitude overrides the class."""
    from rvcore.standards.iso492 import axial_runout_limits

    assert axial_runout_limits(0.320, 0.383, "5") == pytest.approx((10e-6, 10e-6))
    assert axial_runout_limits(0.320, 0.383, "normal") == (None, None)
    r5 = realize(bearing(tolerance_class="5"), seed=3).rows[0].imperfections
    assert (r5.inner_axial_amplitude, r5.outer_axial_amplitude) == pytest.approx((10e-6, 10e-6))
    rn = realize(bearing(tolerance_class="normal"), seed=3).rows[0].imperfections
    assert (rn.inner_axial_amplitude, rn.outer_axial_amplitude) == (0.0, 0.0)
    given = realize(bearing(tolerance_class="normal", inner_axial_amplitude=12e-6), seed=3).rows[0].imperfections
    assert given.inner_axial_amplitude == 12e-6
    # the seed draws the axial high points after the eccentricities': theirs stay as they were
    old = realize(bearing(tolerance_class="5", inner_axial_amplitude=0.0, outer_axial_amplitude=0.0),
                  seed=3).rows[0].imperfections
    assert (old.inner_eccentricity_angle, old.outer_eccentricity_angle) == (
        r5.inner_eccentricity_angle, r5.outer_eccentricity_angle)
    assert r5.inner_axial_angle != realize(bearing(tolerance_class="5"), seed=4).rows[0].imperfections.inner_axial_angle


def test_class_4_axial_runout_is_iso492s_and_refused_above_its_table():
    """ISO 492 class 4 as NSK's Table 8.2 (and NTN's Table 6.4) reproduces it: S_ia 4 µm and
    S_d 4 µm at a bore of 30–50 mm, S_ea 5 µm at an outside diameter of 50–80 mm; S_ia 8 µm
    at 180–250 mm, S_ea 13 µm at 315–400 mm; a = S/2. ISO 492 gives class 4 no S_ia above a
    250 mm bore: the study's section (320 mm) is refused in one line naming the class, S_ia
    and the table's end, unless the amplitudes are given."""
    from rvcore.standards.iso492 import ToleranceError, axial_runout_limits, face_runout_with_bore, tolerance_problems

    assert axial_runout_limits(0.050, 0.080, "4") == pytest.approx((2e-6, 2.5e-6))
    assert face_runout_with_bore(0.050, "4") == pytest.approx(4e-6)
    assert axial_runout_limits(0.200, 0.383, "4") == pytest.approx((4e-6, 6.5e-6))
    with pytest.raises(ToleranceError) as err:
        realize(bearing(tolerance_class="4", inner_eccentricity=1e-6, outer_eccentricity=1e-6), seed=1)
    text = str(err.value)
    assert "\n" not in text and "class 4" in text and "S_ia" in text and "250 mm" in text
    given = dict(inner_given=True, outer_given=True, grade_given=True)
    assert not tolerance_problems("4", 0.050, 0.080, 0.008, **given)
    assert [p for p in tolerance_problems("4", 0.320, 0.383, 0.008, **given) if "S_ia" in p[2]]
    assert not tolerance_problems("4", 0.320, 0.383, 0.008, inner_axial_given=True, outer_axial_given=True, **given)


def test_free_ring_tilts_with_its_tilted_groove_and_its_centre_stays():
    """A ring free to tilt follows its groove's plane: a rigid tilt θ moves the groove's
    centres of curvature, on the circle of radius c_r = d_m/2 + (f_i − ½)·D·cos α, along the
    axis by c_r·θ·cos(φ − φ_t); θ = a/c_r about the axis normal to the high point undoes
    the runout a·cos(φ − φ_a) at every ball, and no ball's load changes. Over a
    revolution of the ring: the ring's tilt turns with it at amplitude a/c_r, its centre
    stays (quasi-statically)."""
    a, phase = 5e-6, 0.4
    c_r = STUDY_DM / 2 + (FI - 0.5) * STUDY_D * math.cos(ALPHA)
    path = runout_path(bearing(inner_axial_amplitude=a, inner_axial_angle=phase), 10e3, 5e3, gravity=False, points=12)
    perfect = runout_path(bearing(), 10e3, 5e3, gravity=False, points=12)
    tilt = path["displacement"][:, 3:5] - perfect["displacement"][:, 3:5]
    np.testing.assert_allclose(np.hypot(tilt[:, 0], tilt[:, 1]), a / c_r, rtol=0.02)
    dz = path["axial_displacement"] - perfect["axial_displacement"]
    assert np.abs(dz).max() < 0.02 * a
    # the tilt's direction turns with the ring: a full turn of its angle over a revolution
    turn = np.unwrap(np.arctan2(tilt[:, 1], tilt[:, 0]))
    assert abs(turn[-1] - turn[0]) == pytest.approx(2 * math.pi * 11 / 12, abs=0.05)


def test_held_ring_axial_range_from_a_tilted_inner_groove_follows_kinematics():
    """A ring held square (inner_ring.tilt = "held"), radial + axial load, 2 rev/s: the
    inner groove's plane tilted by s/D_pw (its axial runout a = s/2 at the pitch circle)
    moves the ring's centre along the axis once a revolution. Over the steady phase's
    revolution the axial displacement it adds to the perfect bearing's (their difference:
    the perfect bearing's own ball-pass ripple and friction offset cancel) follows the
    quasi-static response of the loaded balls to the groove's shift at them
    (:func:`linear_axial_response`), at the same ring and cage angles, within 2 % of a
    (0.7 % here), and its range within 5 % (1.8 %).

    The range is about 0.27·a: to the balls' Hertz chains alone a tilted groove of a
    single row is a radial shift by a·tan α (``Δz·sin α = (a·tan α)·cos α`` at every
    ball), which moves the ring radially and not at all along the axis; the axial motion
    comes from the lines of contact turning (the ``Q/L`` term), which a check without it
    would miss."""
    s, phase, w, f_r, f_a = 6e-6, 0.4, 2 * math.pi * 2.0, 10e3, 5e3
    a = s / 2
    tilted = bearing("held", inner_axial_amplitude=a, inner_axial_angle=phase)
    perfect = bearing("held")
    settings = SolverSettings(output_rate=2000.0, gravity=False)
    res = run_case(tilted, PROFILE, OperatingPoint(w, f_r, f_a), settings)
    res0 = run_case(perfect, PROFILE, OperatingPoint(w, f_r, f_a), settings)
    t = res.time
    steady = np.flatnonzero((t >= 0.1) & (t < 0.6))
    dyn = res.series["axial_displacement"] - res0.series["axial_displacement"]
    table, meta = PROFILE.resolve(OperatingPoint(w, f_r, f_a)).arrays()
    ratio = epicyclic_cage_ratio(perfect.rows[0])
    samples = steady[::25]
    predicted = []
    for k in samples:
        psi = channel_integral(table, meta, CH_SPEED, t[k])
        u = linear_axial_response(perfect, f_r, f_a, psi, ratio * psi, lambda phi: a * np.cos(phi - phase))
        predicted.append(u[2])
    predicted = np.array(predicted)
    assert np.abs(dyn[samples] - predicted).max() < 0.02 * a
    assert np.ptp(dyn[steady]) == pytest.approx(np.ptp(predicted), rel=0.05)
    assert np.ptp(predicted) > 0.2 * a          # the check has something to see


def test_axial_harmonic_shift_and_zero_runout_change_nothing_else():
    """A higher axial harmonic of order k moves the groove by B·cos(k·φ + ψ): at the
    ring angle 0, a held ring under pure axial load (every ball alike) sees the mean of
    the shift over its balls, 0 for k not a multiple of Z, and B·cos ψ for k = Z: then every
    ball's groove is shifted alike and the ring moves by −B·cos ψ along the axis."""
    b_amp, psi = 2e-6, 0.3
    st0 = solve_statics(bearing("held"), 0.0, 5e3, gravity=False, stiffness=False)
    for order, expected in ((3, 0.0), (Z, -b_amp * math.cos(psi))):
        b = bearing("held", inner_axial_waviness=(Waviness(order, b_amp, psi),))
        st = solve_statics(b, 0.0, 5e3, gravity=False, stiffness=False)
        assert st.axial_displacement - st0.axial_displacement == pytest.approx(expected, abs=0.01 * b_amp)


def test_rhs_forces_are_minus_the_energy_gradient_with_axial_runout():
    """Without friction and damping, at rest, each ball's contact force in the right-hand
    side is −∂V/∂P of the potential energy with both grooves tilted and an axial harmonic
    on the outer one: the groove's axial shift and the normal's lean with its slope (a
    tangential force of up to Q·n_z·Δz′/c_r, a few hundredths of a newton here, tens of
    times the 1e-3 N tolerance) are the energy's."""
    from rvcore.bearing.layout import BALL_STATES, R_BALL0, R_MB, compile_bearing
    from rvcore.dynamics.energy import potential_energy
    from rvcore.dynamics.rhs import new_diagnostics, rhs
    from rvcore.simulation.initial_state import initial_state

    b = bearing(inner_axial_amplitude=20e-6, inner_axial_angle=0.7, outer_axial_amplitude=8e-6,
                outer_axial_angle=2.0, outer_axial_waviness=(Waviness(5, 2e-6, 0.3),))
    model = compile_bearing(b, friction=False, damping=False, gravity=False)
    prof = constant_profile(0.0, 1.0).resolve(OperatingPoint(0.0, 10e3, 4e3))
    table, meta = prof.arrays()
    y = initial_state(model, prof, 0.0)
    dy = np.zeros_like(y)
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    rhs(0.0, y, dy, model.params, model.rows, model.arcs, model.pockets, table, meta, diag, bdiag)
    m_b = model.rows[0, R_MB]

    def energy(yy):
        return potential_energy(0.0, yy, model.params, model.rows, model.arcs, model.pockets, table, meta)

    loaded = [j for j in range(Z) if bdiag[j, 0] > 100.0 and bdiag[j, 4] == 0.0]
    assert len(loaded) >= 4
    for j in loaded:
        p = int(model.rows[0, R_BALL0]) + BALL_STATES * j
        for k in range(3):
            assert m_b * dy[p + 3 + k] == pytest.approx(minus_gradient(energy, y, p + k), rel=1e-4, abs=1e-3), (j, k)


def test_an_axially_shifted_gothic_arch_is_the_unshifted_one_translated():
    """A groove shifted axially by Δz (an axial runout's, or a flexible ring's modes') moves its
    arcs and the mid-plane between a gothic arch's two arcs with it: a ball at height z + Δz
    in the shifted groove sees what a ball at z sees in the unshifted one, on every arc of
    either ring, near the crown too, where the mid-plane decides which arc exists (a
    translation: the expectation is the unshifted groove's own contact)."""
    from rvcore.bearing.layout import A_RING, R_HALF_D, R_PITCH_R, compile_bearing
    from rvcore.contact.laws import race_arc_penetration

    model = compile_bearing(section_bearing(Z, four_point=True))
    arcs, h, rho = model.arcs, model.rows[0, R_HALF_D], model.rows[0, R_PITCH_R]
    shift = 3e-5
    excluded = 0
    for a in range(arcs.shape[0]):
        inner = arcs[a, A_RING] == 0.0
        for z in np.linspace(-2e-4, 2e-4, 81):
            def contact(z_ball, dz):
                zi, zo = (z_ball, 0.0) if inner else (0.0, z_ball)
                return race_arc_penetration(arcs, a, rho, 0.0, zi, rho, 1.0 / rho, rho, 0.0, zo, rho, 1.0 / rho, h,
                                            0.0, 0.0, 0.0, 0.0, 0.0, dz if inner else 0.0, 0.0 if inner else dz,
                                            0.0, 0.0)
            got, want = contact(z + shift, shift), contact(z, 0.0)
            assert got[0] == want[0]
            assert (got[1] == -1.0) == (want[1] == -1.0), (a, z)
            assert got[1] == pytest.approx(want[1], abs=1e-15)
            assert np.allclose(got[2:], want[2:], rtol=0.0, atol=1e-12)
            excluded += want[1] == -1.0
    assert 0 < excluded < arcs.shape[0] * 81    # the mid-plane's rule was exercised both ways
