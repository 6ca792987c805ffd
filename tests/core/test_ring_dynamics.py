"""Flexible rings in the dynamics (issue 41; rvcore.dynamics.ring_modes): each flexible
ring's Fourier modes are states, the raceways move with them at every ball, and the
contact forces drive them back.

What must hold, each expectation computed here:

- a lightly supported thin ring's in-plane natural frequencies are Hoppe's,
  ``ω_k² = EI·k²(k² − 1)²/(ρA·R⁴·(k² + 1))``, and its out-of-plane ones Love's with the
  twist condensed, ``ω_k² = EI_out·k²(k² − 1)²/(ρA·R⁴·(k² + EI_out/GJ))``: read from the
  dynamics' own free vibration (zero crossings of the modal state), the section's
  properties from :func:`rvcore.rings.section.ring_section`;
- a very stiff support gives the rigid rings' dynamics within 0.1 %;
- with friction, contact damping and modal damping off the energy, the modes' kinetic and
  strain energy included, is conserved to the integrators' §9.4 bound (docs/model.md:
  1e-4 of the oscillation's energy at the default step);
- the modal states start at the flexible statics' equilibrium;
- the start-up ranges converge with the step (0.8 against 0.4, 2 %); with the number of
  modes (6 against 10, 2 %) on the study's flexible bearing (rv-main-flexible.toml, slow),
  and not on a soft Winkler seat under 12 balls, outside the kept orders' range of
  validity (a strict xfail, slow, its reason measured; the case's ``ring_mode_truncation``
  flags it);
- rigid rings leave a case bit for bit unchanged (a rigid FlexibleRings is the default).

The bearing is the 12-ball section (tests/core/physics_cases.py), its rings on a seat.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from rvcore.bearing.geometry import INNER, OUTER
from rvcore.bearing.layout import compile_bearing
from rvcore.dynamics.energy import kinetic_energy, potential_energy
from rvcore.dynamics.ring_modes import (DYNAMICS_MAX_ORDER, family_states, modal_energy, truncated,
                                        with_ring_modes)
from rvcore.integrate.methods import time_step
from rvcore.profile import OperatingPoint, scaled_study_profile
from rvcore.rings.flexible import RIGID_RINGS, flexible_rings
from rvcore.rings.section import ring_section
from rvcore.rings.support import Foundation
from rvcore.simulation.initial_state import initial_state, peak_contact_load
from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings

from .physics_cases import constant_profile, run_in_chunks, section_bearing

#: The outer ring's bore at its shoulders [m] (its section needs it; as tests/core/test_rings.py).
OUTER_SHOULDER = 0.362


def rings_of(bearing, k_seat, *, damping_ratio=0.0, max_order=DYNAMICS_MAX_ORDER):
    """Both rings flexible on a seat of ``k_seat`` [N m⁻²] radially and axially."""
    seat = Foundation(k_seat, k_seat)
    return flexible_rings(bearing, inner=seat, outer=seat, outer_shoulder_diameter=OUTER_SHOULDER,
                          max_order=max_order, damping_ratio=damping_ratio)


def model_of(bearing, rings, **flags):
    return with_ring_modes(compile_bearing(bearing, **flags), truncated(rings), DYNAMICS_MAX_ORDER)


# --------------------------------------------------------------------------- free vibration

#: A seat this light adds ``π·k·R ≈ 50 N/m`` to the orders' stiffness, against the ring's
#: ``π·EI·(k² − 1)²/R³ ≈ 3e6 N/m`` at k = 2: 2e-5 of ω², below what is asserted.
LIGHT_SEAT = 1e2


def free_frequency(family, order, periods=3.0):
    """ω [rad s⁻¹] of family ``family``'s ``cos kθ`` mode, order ``order``, from the
    dynamics: the balls clear of their races (a 0.2 mm clearance), the mode set to 1 µm,
    RK4 at 1/400 of the expected period, the period from the state's zero crossings."""
    bearing = section_bearing(12, clearance=2e-4)
    rings = rings_of(bearing, LIGHT_SEAT)
    model = model_of(bearing, rings, friction=False, damping=False, gravity=False)
    resolved = constant_profile(0.0, 1.0).resolve(OperatingPoint(0.0, 0.0, 0.0))
    y = initial_state(model, resolved, 0.0, rings=truncated(rings))
    n, s0 = family_states(model, family)
    assert n == DYNAMICS_MAX_ORDER + 1 and np.all(y[s0:s0 + 4 * n] == 0.0)   # nothing loads the rings
    y[s0 + 2 * order] = 1e-6
    modes = getattr(rings, family)
    omega = float(modes.frequencies[order])
    dt = 2 * math.pi / omega / 400
    samples = [y[s0 + 2 * order]]
    for _ in run_in_chunks("rk4", model, y, resolved, dt, 1, int(periods * 400)):
        samples.append(y[s0 + 2 * order])
    x = np.array(samples)
    up = np.nonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))[0]
    crossings = up + x[up] / (x[up] - x[up + 1])     # linear interpolation between the steps
    assert crossings.size >= 2
    return 2 * math.pi / (dt * float(np.mean(np.diff(crossings)))), bearing


def test_free_ring_in_plane_frequency_from_the_dynamics():
    """Ovalisation (k = 2) and triangularity (k = 3) of the inner ring in plane: Hoppe's
    frequency from its section within 1e-3."""
    for k in (2, 3):
        omega, bearing = free_frequency("inner_radial", k)
        sec, mat = ring_section(bearing, INNER), bearing.ring_material
        ei, rho_a, r = mat.youngs_modulus * sec.i_in_plane, mat.density * sec.area, sec.centroid_radius
        expected = math.sqrt(ei * k**2 * (k**2 - 1) ** 2 / (rho_a * r**4 * (k**2 + 1)))
        assert omega == pytest.approx(expected, rel=1e-3), k


def test_free_ring_out_of_plane_frequency_from_the_dynamics():
    """The outer ring's out-of-plane k = 2 mode, bending with its twist condensed out:
    Love's frequency from the section's I_out and J within 1e-3."""
    omega, bearing = free_frequency("outer_axial", 2)
    sec, mat = ring_section(bearing, OUTER, other_diameter=OUTER_SHOULDER), bearing.ring_material
    k, e = 2, mat.youngs_modulus
    g = e / (2 * (1 + mat.poisson_ratio))
    ei, gj = e * sec.i_out_of_plane, g * sec.torsion_constant
    rho_a, r = mat.density * sec.area, sec.centroid_radius
    expected = math.sqrt(ei * k**2 * (k**2 - 1) ** 2 / (rho_a * r**4 * (k**2 + ei / gj)))
    assert omega == pytest.approx(expected, rel=1e-3)


# --------------------------------------------------------------------------- the stiff limit

def test_a_very_stiff_support_gives_the_rigid_rings_dynamics():
    """Both rings on a seat of 1e15 N/m²: a Winkler seat's own compliance under a ball,
    ``w = Q·β/(2k)`` with ``β = (k/4EI)^¼`` (Hetényi), is ~4e-11 m at 500 N, 1e-5 of the
    contacts' approach and 2e-4 of the ring's axial travel here. A rolling start under a
    combined load gives the ring's displacements and the contact loads of rigid rings
    within 0.1 % of their scale, both at the flexible case's IMEX step (the seat's own
    stiffness, ~2.5e7 rad/s on the modes, is in its implicit part)."""
    bearing = section_bearing(12)
    rings = rings_of(bearing, 1e15, damping_ratio=0.02)
    profile = constant_profile(0.0, 0.001)
    op = OperatingPoint(20.0, 3e3, 1e3)
    model = model_of(bearing, rings)
    dt = time_step(model, peak_contact_load(model, profile.resolve(op)), "imex")
    settings = SolverSettings(output_rate=1e4, time_step=dt)
    rigid = run_case(bearing, profile, op, settings)
    flexible = run_case(bearing, profile, op, settings, rings=rings)
    assert flexible.final_state.size == rigid.final_state.size + 4 * 4 * (DYNAMICS_MAX_ORDER + 1)
    for name in ("radial_displacement", "axial_displacement", "max_inner_contact_load", "max_outer_contact_load"):
        a, b = rigid.series[name], flexible.series[name]
        assert np.abs(b - a).max() <= 1e-3 * np.abs(a).max(), name
    # the rings did deform, by little
    amplitudes = []
    for name in ("inner_radial", "inner_axial", "outer_radial", "outer_axial"):
        n, s0 = family_states(model, name)
        amplitudes.extend(flexible.final_state[s0:s0 + 2 * n])
    assert 0.0 < np.abs(amplitudes).max() < 1e-10


def test_rigid_rings_are_the_default_bit_for_bit():
    """``rings=RIGID_RINGS`` is the default and adds no state: the same result bit for bit."""
    bearing = section_bearing(12)
    profile, op = constant_profile(0.0, 0.001), OperatingPoint(20.0, 3e3, 1e3)
    a = run_case(bearing, profile, op, SolverSettings(output_rate=1e4))
    b = run_case(bearing, profile, op, SolverSettings(output_rate=1e4), rings=RIGID_RINGS)
    assert np.array_equal(a.final_state, b.final_state)
    for name in a.series:
        assert np.array_equal(a.series[name], b.series[name], equal_nan=True), name


# --------------------------------------------------------------------------- statics and energy

#: A seat on which the rings take a visible share of the deflection: ``π·k·R ≈ 5e9 N/m``
#: an order, against the 12 balls' ~4e9 N/m of Hertz tangent.
SOFT_SEAT = 1e10


def test_modes_start_at_the_flexible_statics():
    """At the start the modes hold the statics' amplitudes: the rings' displacement at each
    ball is the flexible statics' (``ring_displacements``, the same truncated modes) to
    twice the statics' fixed-point tolerance (1e-12 m + 1e-8 of the largest,
    rvcore.statics.equilibrium), and the right-hand side's modal accelerations nearly
    vanish (the generalized forces balance the stiffness). Not exactly: the statics read
    both rings' modes at the balls' azimuths about the bearing's axis, the dynamics read
    the inner ring's about its own centre, which the load has moved by ``|r_i|``; the
    angles differ by up to ``ε = |r_i|/ρ`` (ρ the balls' distance from the axis), and
    ``Q_k = Σ F_j·cos kθ_j`` by at most ``k·ε·Σ|F_j|``; and the statics resolve the forces
    on the inner ring radially and axially in the fixed frame, the dynamics in the ring's,
    tilted by ``|θ|``: at most ``|θ|·Σ(|F_r| + |F_z|)`` more. The outer ring's, read at the
    same azimuths in the same frame, balance to 1e-5 of the stiffness term (what the
    statics' tolerance leaves)."""
    from rvcore.dynamics.rhs import new_diagnostics, rhs
    from rvcore.rings.deflection import modal_displacement
    from rvcore.statics.equilibrium import solve_statics

    bearing = section_bearing(12)
    rings = truncated(rings_of(bearing, SOFT_SEAT))
    model = model_of(bearing, rings, gravity=False)
    resolved = constant_profile(0.0, 1.0).resolve(OperatingPoint(0.0, 3e3, 1e3))
    y = initial_state(model, resolved, 0.0, rings=rings)
    st = solve_statics(model, 3e3, 1e3, stiffness=False, rings=rings)
    for f, name in enumerate(("inner_radial", "inner_axial", "outer_radial", "outer_axial")):
        n, s0 = family_states(model, name)
        w = modal_displacement(getattr(rings, name), y[s0:s0 + 2 * n:2], y[s0 + 1:s0 + 2 * n:2], st.azimuths)
        tol = 2 * (1e-12 + 1e-8 * np.abs(st.ring_displacements).max())
        np.testing.assert_allclose(w, st.ring_displacements[:, f], rtol=0, atol=tol)
        assert np.abs(w).max() > 1e-8, name    # a visible deformation
    dy = np.zeros_like(y)
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    table, meta = resolved.arrays()
    rhs(0.0, y, dy, model.params, model.rows, model.arcs, model.pockets, table, meta, diag, bdiag)
    eps = math.hypot(y[0], y[1]) / (bearing.rows[0].pitch_diameter / 2 - bearing.rows[0].ball_diameter)
    for f, name in enumerate(("inner_radial", "inner_axial", "outer_radial", "outer_axial")):
        n, s0 = family_states(model, name)
        modes = getattr(rings, name)
        scale = np.abs(modes.stiffness[:n, None] * np.column_stack([y[s0:s0 + 2 * n:2], y[s0 + 1:s0 + 2 * n:2]])).max()
        acc = dy[s0 + 2 * n:s0 + 4 * n] * np.repeat(modes.mass[:n], 2)
        if name.startswith("inner"):
            bound = ((n - 1) * eps + math.hypot(y[3], y[4])) * np.abs(st.ring_forces[:, :2]).sum()
            assert bound < 0.05 * scale      # the frames differ by little
        else:
            bound = 1e-5 * scale
        assert np.abs(acc).max() < bound, name


def test_the_implicit_tangent_couples_the_modes_as_the_right_hand_side_does():
    """The IMEX tangent's contact stiffness on the modes (rvcore.dynamics.tangent.modal_blocks):
    its coupling of a mode with every ball's centre, with the ring's translation and with the
    mode itself is the derivative of the right-hand side's forces, by central differences of
    a mode's amplitude (friction and damping off: the tangent leaves the friction's
    dependence on the load explicit). The tangent reads every mode at the ball's azimuth
    about the bearing's axis, the right-hand side the inner ring's about its centre: they
    differ by ``k·|r_i|/ρ`` ≈ 1e-3 here, within the 3e-3 asserted."""
    from rvcore.dynamics.rhs import new_diagnostics, rhs, rhs_jac
    from rvcore.dynamics.tangent import FX_CK, FX_PK, FX_VK, J_FX
    from rvcore.integrate.imex import new_work
    from rvcore.bearing.layout import BALL_STATES, R_BALL0, R_MB, R_POCKET0, P_RING_M

    bearing = section_bearing(12)
    rings = truncated(rings_of(bearing, SOFT_SEAT))
    model = model_of(bearing, rings, friction=False, damping=False, gravity=False)
    resolved = constant_profile(0.0, 1.0).resolve(OperatingPoint(0.0, 3e3, 1e3))
    table, meta = resolved.arrays()
    y = initial_state(model, resolved, 0.0, rings=rings)
    args = (model.params, model.rows, model.arcs, model.pockets, table, meta)
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    _, jwork, schur = new_work(model, 1e-9, 1.0)
    hg = 1e-6
    rhs_jac(0.0, y, np.zeros_like(y), *args, diag, bdiag, hg, jwork, schur)
    row = model.rows[0]
    b0, p0, z = int(row[R_BALL0]), int(row[R_POCKET0]), 12
    balls = [b0 + BALL_STATES * j for j in range(z)]
    theta = np.arctan2([y[b + 1] for b in balls], [y[b] for b in balls])

    def forces(yy):
        dy = np.zeros_like(yy)
        rhs(0.0, yy, dy, *args, diag, bdiag)
        return dy

    for f, (name, k) in enumerate((("inner_radial", 2), ("inner_axial", 3), ("outer_radial", 2), ("outer_axial", 1))):
        n, s0 = family_states(model, name)
        eps = 1e-9
        up, down = y.copy(), y.copy()
        up[s0 + 2 * k] += eps
        down[s0 + 2 * k] -= eps
        d = (forces(up) - forces(down)) / (2 * eps)
        shape = np.cos(k * theta)
        # the balls' centres: ∂F_b/∂a = −K_ba
        fd = np.array([d[b + 3:b + 6] * row[R_MB] for b in balls])
        tangent = -np.array([jwork[p0 + j, J_FX + FX_VK + 3 * f:J_FX + FX_VK + 3 * f + 3] for j in range(z)]) / hg
        tangent *= shape[:, None]
        assert np.abs(tangent).max() > 1e6, name          # a real coupling, N/m
        assert np.abs(fd - tangent).max() < 3e-3 * np.abs(tangent).max(), name
        # the mode itself: ∂Q/∂a = −K_k − K_contacts
        modes = getattr(rings, name)
        own = d[s0 + 2 * n + 2 * k] * modes.mass[k] + modes.stiffness[k]
        block = 3 * (f // 2) + (0 if f % 2 == 0 else 2)
        contacts = sum(jwork[p0 + j, J_FX + FX_CK + block] * shape[j] ** 2 for j in range(z)) / hg
        assert contacts > 1e7 and own == pytest.approx(-contacts, rel=3e-3), name
        if f < 2:    # the inner ring's translation
            ring = d[5:8] * model.params[P_RING_M]
            pose = -sum(jwork[p0 + j, J_FX + FX_PK + 5 * f:J_FX + FX_PK + 5 * f + 3] * shape[j]
                        for j in range(z)) / hg
            assert np.abs(ring - pose).max() < 3e-3 * np.abs(pose).max(), name


def modal_energy_drift(method, step_fraction=1.0, loads=(10e3, 5e3), horizon=0.005):
    """(largest |E − E₀| / the oscillation's energy, the modes' largest share of it), friction,
    contact and modal damping off, no gravity: started at the flexible statics of 95 % of the
    loads and held at the full loads, the method at ``step_fraction`` of its default step (as
    tests/core/test_imex_conservation.py's, the modal rates included)."""
    bearing = section_bearing(12)
    rings = truncated(rings_of(bearing, SOFT_SEAT, damping_ratio=0.0))
    model = model_of(bearing, rings, friction=False, damping=False, gravity=False)
    sized = model_of(bearing, rings, gravity=False)
    fr, fa = loads
    resolved = constant_profile(0.0, horizon).resolve(OperatingPoint(0.0, fr, fa))
    start = constant_profile(0.0, horizon).resolve(OperatingPoint(0.0, 0.95 * fr, 0.95 * fa))
    dt = step_fraction * time_step(sized, peak_contact_load(sized, resolved), method)
    table, meta = resolved.arrays()

    def energy(y):
        return kinetic_energy(y, model.params, model.rows) + potential_energy(
            0.0, y, model.params, model.rows, model.arcs, model.pockets, table, meta)

    at_rest = energy(initial_state(model, resolved, 0.0, rings=rings))
    y = initial_state(model, start, 0.0, rings=rings)
    chunks = 50
    per = int(round(horizon / dt)) // chunks
    total, share = [energy(y)], 0.0
    for _ in run_in_chunks(method, model, y, resolved, dt, per, chunks):
        total.append(energy(y))
        kin, strain = modal_energy(model.params, y)
        share = max(share, kin)
    oscillation = total[0] - at_rest
    assert oscillation > 1e-5
    return np.abs(np.array(total) - total[0]).max() / oscillation, share / oscillation


@pytest.mark.parametrize("method", ["imex", "rk4"])
def test_energy_with_the_modes_is_conserved(method):
    """docs/model.md §9.4(a): the drift of kinetic plus potential energy, the modes' included,
    below 1e-4 of the oscillation's energy at the method's default step; the modes carry a
    share of the motion that would break that bound were their energy left out."""
    drift, share = modal_energy_drift(method)
    assert drift < 1e-4, drift
    assert share > 1e-3, share


# --------------------------------------------------------------------------- convergence

def startup_ranges(safety=0.8, max_order=DYNAMICS_MAX_ORDER):
    """The start-up phase's ranges of δ_r and δ_a and its peak contact pressure on the
    12-ball section with flexible rings (seat 1e10 N/m², ζ 2 %) over the 1/20 study cycle's
    load ramp and start-up, in gravity."""
    bearing = section_bearing(12)
    rings = rings_of(bearing, SOFT_SEAT, damping_ratio=0.02, max_order=max(max_order, DYNAMICS_MAX_ORDER))
    prof = scaled_study_profile(0.05)
    op = OperatingPoint(math.radians(660.0), 30e3, 10e3)
    res = run_case(bearing, prof, op, SolverSettings(output_rate=1e4, step_safety=safety, end_time=prof.phases[1][1]),
                   rings=rings, ring_max_order=max_order)
    return startup_of(res)


def startup_of(res):
    """The start-up phase's δ_r and δ_a ranges [m] and peak contact pressure [Pa] of a case."""
    return {name: float(np.asarray(res.phase_metrics[name])[0])
            for name in ("radial_displacement_range", "axial_displacement_range", "peak_contact_pressure")}


def test_startup_ranges_converge_with_the_step():
    """step_safety 0.8 against 0.4: the start-up ranges and peak pressure within 2 % (a few
    seconds since the modes are implicit in IMEX: the rigid rings' step)."""
    coarse, fine = startup_ranges(0.8), startup_ranges(0.4)
    for name in coarse:
        assert coarse[name] == pytest.approx(fine[name], rel=0.02), (name, coarse[name], fine[name])


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="outside the kept orders' range of validity (docs/model.md §16.1): on a soft "
                   "1e10 N/m² Winkler seat the orders up to the ring's crossover with its seat (k⁴ ≈ k_r·R⁴/EI, k ≈ 12) "
                   "and k = Z = 12 carry the seat's compliance under each ball (orders 7–60 hold 30 % of a contact's "
                   "compliance); measured δ_r range 13.5 µm (orders 0–6) against 12.1 µm (0–10), 11 %; δ_a 22.7 "
                   "against 17.7 µm. The case's ring_mode_truncation flags it (0.18 at 30 kN + 10 kN, above 2 %)")
def test_startup_ranges_converge_with_the_modes():
    """Orders 0–6 (the default) against 0–10: the start-up ranges and peak pressure within 2 %.

    Known to fail (strict xfail: it documents the limit, docs/model.md §16.1): this seat is
    outside the range where the orders kept converge, a seat whose local compliance under a
    ball is small against the contact's (the study's flexible bearing is inside it,
    :func:`test_startup_ranges_converge_with_the_modes_on_the_study_bearing`). The flexible
    statics of the same section show why, δ_r at 30 kN + 10 kN is 153.0 µm with orders 0–4,
    0–6 and 0–8 alike, 155.1 µm with 0–10, 174.4 µm with 0–12 and 186.2 µm with 0–60: the
    low orders converge among themselves, the seat's local compliance under each ball needs
    the orders to the crossover and the multiples of Z. Each case says so in its steady
    outputs, ``ring_mode_truncation`` above 2 % (:func:`test_a_flexible_case_records_its_modes_truncation`),
    and the report warns. A static correction for the orders left out (the mode-acceleration
    method) is what would fix it at a few modes."""
    few, more = startup_ranges(max_order=DYNAMICS_MAX_ORDER), startup_ranges(max_order=10)
    for name in few:
        assert few[name] == pytest.approx(more[name], rel=0.02), (name, few[name], more[name])


@pytest.mark.slow
def test_startup_ranges_converge_with_the_modes_on_the_study_bearing():
    """The study's flexible bearing (sweeps/bearings/rv-main-flexible.toml, both rings bonded
    in their carrier and housing): orders 0–6 (the dynamics' default) against 0–10, the
    study cycle's load ramp and start-up at 660 °/s, 30 kN + 10 kN, in gravity: the start-up
    ranges and peak pressure within 2 % (measured 0.2 %, docs/validation.md). Its seats
    are stiff against the contacts under a ball, so the low orders carry the deformation
    (docs/model.md §16.1, the range of validity); the 12-ball section's soft Winkler seat
    above is outside it. About 10 s."""
    from pipeline.schema.bearingfile import bearing_from_dict
    from pipeline.schema.tomlfile import read_toml
    from rvcore.profile import study_profile
    from rvcore.rings.flexible import bearing_rings

    path = Path(__file__).resolve().parents[2] / "sweeps" / "bearings" / "rv-main-flexible.toml"
    bearing = bearing_from_dict(read_toml(path), path)
    rings, profile = bearing_rings(bearing), study_profile()
    op = OperatingPoint(math.radians(660.0), 30e3, 10e3)
    settings = SolverSettings(output_rate=1e4, end_time=profile.phases[0][2], gravity=True)
    few, more = (startup_of(run_case(bearing, profile, op, settings, rings=rings, ring_max_order=order))
                 for order in (DYNAMICS_MAX_ORDER, 10))
    assert rings.inner_radial.orders.max() > 10 and DYNAMICS_MAX_ORDER < 10
    for name in few:
        assert few[name] == pytest.approx(more[name], rel=0.02), (name, few[name], more[name])


# --------------------------------------------------------------------------- sensors and outputs

def test_a_flexible_case_records_its_rings_statics_at_the_steady_point():
    """A flexible case's steady outputs (stiffness, lives at the steady point) are those of
    the statics on its own rings (the dynamics' orders), solved here with solve_statics;
    each softer than the rigid rings' (a 1e10 N/m² seat under each ring)."""
    from rvcore.statics.equilibrium import solve_statics

    bearing = section_bearing(12)
    rings = truncated(rings_of(bearing, SOFT_SEAT, damping_ratio=0.02))
    profile, op = constant_profile(0.0, 0.0005), OperatingPoint(20.0, 3e3, 1e3)
    settings = SolverSettings(output_rate=1e4, gravity=False)
    res = run_case(bearing, profile, op, settings, rings=rings)
    rigid = run_case(bearing, profile, op, settings)
    flexible = solve_statics(bearing, 3e3, 1e3, gravity=False, stiffness=True, rings=rings)
    expected = dict(zip(("radial_stiffness", "axial_stiffness", "tilting_stiffness"), flexible.stiffness_scalars()))
    for name, value in expected.items():
        assert res.steady[name] == pytest.approx(value, rel=1e-9), name
        assert res.steady[name] < rigid.steady[name], name


@pytest.mark.parametrize("k_seat", [SOFT_SEAT, 1e15])
def test_a_flexible_case_records_its_modes_truncation(k_seat):
    """``ring_mode_truncation``: the case runs on its rings' first 7 orders (the dynamics'),
    and its steady outputs say how far the statics on them are from the statics on all 61
    orders it was given. Computed here from two solve_statics calls: the largest relative
    change of δ_r, δ_a and Q_max (a displacement's relative to at least a tenth of
    |(δ_r, δ_a)|). On the soft 1e10 N/m² seat it is above the 2 % the report warns at
    (the seat's give under each ball needs the orders the dynamics leave out; the strict
    xfail above); on a 1e15 N/m² seat below 1e-3. Rigid rings: NaN."""
    from rvcore.statics.equilibrium import solve_statics
    from rvcore.statics.flexible import MODE_TRUNCATION_LIMIT

    bearing = section_bearing(12)
    rings = rings_of(bearing, k_seat, damping_ratio=0.02, max_order=60)
    profile, op = constant_profile(0.0, 0.0005), OperatingPoint(20.0, 3e3, 1e3)
    settings = SolverSettings(output_rate=1e4, gravity=False)
    res = run_case(bearing, profile, op, settings, rings=rings)
    kept, every = (solve_statics(bearing, 3e3, 1e3, gravity=False, stiffness=False, rings=r)
                   for r in (truncated(rings), rings))
    floor = 0.1 * math.hypot(every.radial_displacement, every.axial_displacement)
    expected = max(abs(kept.radial_displacement / every.radial_displacement - 1.0),
                   abs(kept.axial_displacement - every.axial_displacement) / max(abs(every.axial_displacement), floor),
                   abs(kept.max_contact_load / every.max_contact_load - 1.0))
    assert abs(every.radial_displacement) > floor     # δ_r is its own scale
    assert res.steady["ring_mode_truncation"] == pytest.approx(expected, rel=1e-9)
    if k_seat == SOFT_SEAT:
        assert expected > MODE_TRUNCATION_LIMIT == 0.02
    else:
        assert expected < 1e-3
    rigid = run_case(bearing, profile, op, settings)
    assert math.isnan(rigid.steady["ring_mode_truncation"])
    assert run_case(bearing, profile, op, settings, rings=truncated(rings)).steady["ring_mode_truncation"] == 0.0


def test_sensors_read_the_rings_surface_and_the_outputs_its_deformation():
    """A flexible inner ring under a combined load: a radial sensor at the bore and an
    axial one at the face read the rigid-body displacement of the pose plus the surface's
    ``w(θ)·ê_r + u(θ)·ẑ`` at their angle (the modal sum of the final state, computed here
    with rvcore.rings.deflection.modal_displacement); the ovalisation is the k = 2
    amplitude, and the largest raceway deformation at the balls is at least the
    ovalisation's share there and at most the sum of the amplitudes. Rigid rings: all 0."""
    from rvcore.contact.pose import ring_rotation
    from rvcore.rings.deflection import modal_displacement
    from rvcore.simulation.settings import Sensor

    bearing = section_bearing(12)
    rings = truncated(rings_of(bearing, SOFT_SEAT, damping_ratio=0.02))
    theta_r, theta_a = math.radians(30.0), math.radians(200.0)
    sensors = (Sensor("bore", (0.160 * math.cos(theta_r), 0.160 * math.sin(theta_r), 0.0),
                      (math.cos(theta_r), math.sin(theta_r), 0.0)),
               Sensor("face", (0.1675 * math.cos(theta_a), 0.1675 * math.sin(theta_a), 0.015), (0.0, 0.0, 1.0)))
    profile, op = constant_profile(0.0, 0.002), OperatingPoint(20.0, 3e3, 1e3)
    settings = SolverSettings(output_rate=1e4, gravity=False)
    res = run_case(bearing, profile, op, settings, sensors=sensors, rings=rings)
    rigid = run_case(bearing, profile, op, settings, sensors=sensors)
    y = res.final_state
    model = model_of(bearing, rings)
    amplitudes = {}
    for name in ("inner_radial", "inner_axial"):
        n, s0 = family_states(model, name)
        amplitudes[name] = (y[s0:s0 + 2 * n:2], y[s0 + 1:s0 + 2 * n:2])
    rot = np.array(ring_rotation(y[3], y[4])).reshape(3, 3)
    for k, (sensor, theta) in enumerate(zip(sensors, (theta_r, theta_a))):
        p, d = np.array(sensor.position), np.array(sensor.direction) / np.linalg.norm(sensor.direction)
        rigid_body = d @ (y[0:3] + (rot - np.eye(3)) @ p)
        w = float(modal_displacement(rings.inner_radial, *amplitudes["inner_radial"], theta))
        u = float(modal_displacement(rings.inner_axial, *amplitudes["inner_axial"], theta))
        surface = d @ rot @ np.array([w * math.cos(theta), w * math.sin(theta), u])
        assert abs(surface) > 1e-9      # the deformation is visible in the reading
        assert res.series["sensor_displacement"][-1, k] == pytest.approx(rigid_body + surface, rel=1e-9, abs=1e-15)
    a_c, a_s = amplitudes["inner_radial"][0][2], amplitudes["inner_radial"][1][2]
    assert res.series["inner_ring_ovalisation"][-1] == pytest.approx(math.hypot(a_c, a_s), rel=1e-12)
    assert res.series["outer_ring_ovalisation"][-1] > 0.0
    bound = sum(np.abs(a).sum() for a in amplitudes["inner_radial"])
    n_o, s_o = family_states(model, "outer_radial")
    bound = max(bound, np.abs(y[s_o:s_o + 2 * n_o]).sum())
    assert 0.0 < res.series["max_ring_radial_deformation"].max() <= bound * (1 + 1e-9)
    assert res.phase_metrics["max_ring_radial_deformation_peak"][0] > 0.0
    assert res.phase_metrics["max_ring_axial_deformation_peak"][0] > 0.0
    for name in ("max_ring_radial_deformation", "max_ring_axial_deformation", "inner_ring_ovalisation",
                 "outer_ring_ovalisation"):
        assert np.all(rigid.series[name] == 0.0), name
