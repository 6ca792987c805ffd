"""The inner ring's tilt condition (docs/model.md §11): ``inner_ring.tilt = "free" | "held"``.

A single row under a radial load and zero moment tilts; held square (a shaft on a second
support) it does not, and the support takes a moment. Every expected value here comes
from the load distribution itself (the moment of the contact forces, summed in the test)
or from the standards' own calibration (ISO/TS 16281 reproduces ISO 281 at zero
clearance under a pure radial load), never from the code's earlier output.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings
from rvcore.integrate.methods import NAMES as METHODS
from rvcore.standards.iso16281 import static_life
from rvcore.profile import OperatingPoint
from rvcore.statics.equilibrium import solve_statics

from .physics_cases import constant_profile, section_bearing


def held(bearing):
    return dataclasses.replace(bearing, inner_ring=dataclasses.replace(bearing.inner_ring, tilt="held"))


def contact_moment(bearing, st):
    """Moment of the ball–inner-race forces about the ring centre [N m], summed here.

    Each inner-race normal force acts along the contact normal, whose line runs through
    the ball's centre; it pushes the ring inwards along ``−(cos a·e_r + sin a·ẑ)`` at
    contact angle ``a`` (the angle the statics report for that arc, measured so that the
    outward normal is ``(cos a, sin a)`` in the ball's meridian plane).
    """
    h = bearing.rows[0].ball_diameter / 2
    centre = np.asarray(st.displacement[:3])
    m = np.zeros(3)
    for j in range(st.ball_loads.shape[0]):
        rho, z = st.ball_positions[j]
        e = np.array([math.cos(st.azimuths[j]), math.sin(st.azimuths[j]), 0.0])
        p = rho * e + np.array([0.0, 0.0, z])
        for k in np.flatnonzero(st.arc_rings == 0):
            q, a = st.ball_loads[j, k], st.contact_angles[j, k]
            if q > 0.0:
                outward = math.cos(a) * e + math.sin(a) * np.array([0.0, 0.0, 1.0])
                m += np.cross(p - centre, -q * outward)
        assert h > 0
    return m[:2]


def test_held_statics_keep_the_ring_square_and_report_the_support_moment():
    """30 kN radial + 10 kN axial on a 15° row: free, the ring tilts; held, it does not,
    and the support's moment is minus the moment of the contact forces (no other moment
    acts: zero applied moment, and the ring's weight acts at its centre)."""
    bearing = section_bearing(16)
    free = solve_statics(bearing, 30e3, 10e3, gravity=False)
    hold = solve_statics(held(bearing), 30e3, 10e3, gravity=False)
    assert free.tilt == "free" and hold.tilt == "held"
    assert abs(free.displacement[4]) > 1e-4          # a free single row tilts (rad)
    assert np.abs(hold.displacement[3:]).max() <= 1e-12
    np.testing.assert_array_equal(free.reaction_moment, 0.0)
    m = contact_moment(bearing, hold)
    assert np.linalg.norm(m) > 100.0                  # the support does carry a moment
    np.testing.assert_allclose(hold.reaction_moment, -m, rtol=1e-6, atol=1e-6 * np.linalg.norm(m))
    # tilting, the free ring puts its heaviest ball under more load than the held one
    assert hold.max_contact_load < free.max_contact_load


def test_held_deep_groove_at_zero_clearance_gives_iso281_life():
    """ISO/TS 16281's contact ratings (0.407, 0.389 in eq. (19)/(20)) are calibrated so
    that its L10r reproduces ISO 281's L10 for a radial bearing at zero clearance under a
    pure radial load (Lundberg–Palmgren's load distribution there): within 1 %."""
    bearing = held(section_bearing(16, alpha=0.0))
    st = solve_statics(bearing, 20e3, 0.0, gravity=False)
    life = static_life(bearing, st)
    ratio = life["reference_rating_life_L10r_Mrev"] / life["basic_rating_life_L10_Mrev"]
    assert abs(ratio - 1.0) < 0.01, ratio


@pytest.mark.parametrize("method", METHODS)
def test_held_dynamics_keep_the_tilt_at_zero_and_carry_the_static_moment(method):
    """Radial + axial load at ω = 0, settled: the held ring's tilt stays 0 (1e-12 rad)
    and the support's moment settles to that of the held statics, since the damped
    response settles to the quasi-static equilibrium (docs/model.md §9.2)."""
    bearing = held(section_bearing(12))
    f_r, f_a = 10e3, 5e3
    res = run_case(bearing, constant_profile(0.01, 0.12), OperatingPoint(0.0, f_r, f_a),
                   SolverSettings(output_rate=2e4, gravity=False, method=method))
    assert res.info["inner_ring_tilt"] == "held"
    for name in ("inner_ring_tilt_x", "inner_ring_tilt_y"):
        assert np.abs(res.series[name]).max() <= 1e-12
    st = solve_statics(bearing, f_r, f_a, gravity=False)
    late = res.time >= 0.10
    moment = np.column_stack([res.series["tilt_reaction_moment_x"], res.series["tilt_reaction_moment_y"]])
    scale = np.linalg.norm(st.reaction_moment)
    assert scale > 10.0
    assert np.abs(moment[late] - st.reaction_moment).max() < 0.01 * scale
    # the phase metrics are the magnitude's
    steady = 1   # the second window of constant_profile
    assert res.phase_metrics["tilt_reaction_moment_peak"][steady] == pytest.approx(scale, rel=0.01)


def test_free_ring_has_no_support_moment():
    """Free, nothing holds the ring: its reaction moment is zero at every step."""
    bearing = section_bearing(12)
    res = run_case(bearing, constant_profile(0.005, 0.02), OperatingPoint(0.0, 10e3, 5e3),
                   SolverSettings(output_rate=2e4, gravity=False))
    assert res.info["inner_ring_tilt"] == "free"
    assert np.abs(res.series["tilt_reaction_moment_x"]).max() == 0.0
    assert np.abs(res.series["tilt_reaction_moment_y"]).max() == 0.0
    assert np.abs(res.series["inner_ring_tilt_y"]).max() > 0.0


def test_a_free_deep_groove_row_is_statically_unstable_and_held_it_is_not():
    """At zero clearance and 0° a deep-groove row has no tilt stiffness of its own: with the
    ring free to tilt, the radial load's moment about the loaded ball's contact makes a
    tilt-and-shift direction of negative stiffness (docs/validation.md, the deep-groove
    family), so the 5×5 tangent stiffness is not positive definite. Held square, the three
    translations are stiff. A 15° row under radial and axial load is stable either way."""
    from pipeline.schema.bearingfile import load_bearing
    from pipeline.schema.shipped import shipped_file
    from rvcore.statics.operating import positive_definite

    dg = load_bearing(shipped_file("bearings/deep-groove-6010.toml"))
    assert not positive_definite(solve_statics(dg, 500.0, 0.0).stiffness_matrix)
    assert positive_definite(solve_statics(held(dg), 500.0, 0.0).stiffness_matrix, 3)
    assert positive_definite(solve_statics(section_bearing(16), 30e3, 10e3, gravity=False).stiffness_matrix)
