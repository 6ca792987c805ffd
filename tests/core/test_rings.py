"""Flexible rings, the physics foundation (issue 41): a ring's section, its thin-ring
Fourier modes, its support and its static deflection under point loads.

Every expectation is computed here from theory: direct integration of the section,
Saint-Venant's series for a rectangle's torsion, the pinched ring's closed form
(Timoshenko), closed-form sums for Z equal loads (the partial fractions of π·cot), a ring
on an elastic foundation by its Fourier series and, stiff, by Hetényi's infinite beam,
the thin ring's natural frequencies (Hoppe, Love) and the out-of-plane stiffness by
minimising the strain energy over the twist numerically. No number is copied from the
code's output.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate, optimize

from pipeline.schema import load_bearing
from rvcore.bearing.geometry import INNER, OUTER, Material
from rvcore.rings import deflection as rd
from rvcore.rings import modes as rm
from rvcore.rings import section as rs
from rvcore.rings import support as rsup

STEEL = Material(7800.0, 208e9, 0.3)
E, NU, RHO = STEEL.youngs_modulus, STEEL.poisson_ratio, STEEL.density
G = E / (2 * (1 + NU))
# the study's inner ring without its groove: bore 320 mm, shoulder 340 mm, 30 mm wide
RI, RO, B = 0.160, 0.170, 0.030
N_MODES = 2000
REPO = Path(__file__).resolve().parents[2]


def rectangle():
    return rs.section_from_envelope(RI, RO, B)


def bending(section):
    return E * section.i_in_plane


# --------------------------------------------------------------------------- section


def test_ungrooved_section_is_the_rectangle():
    t = RO - RI
    sec = rectangle()
    assert sec.area == pytest.approx(B * t, rel=1e-12)
    assert sec.centroid_radius == pytest.approx((RI + RO) / 2, rel=1e-12)
    assert sec.i_in_plane == pytest.approx(B * t ** 3 / 12, rel=1e-9)
    assert sec.i_out_of_plane == pytest.approx(t * B ** 3 / 12, rel=1e-9)
    assert sec.i_product == pytest.approx(0.0, abs=1e-20)


def _strip_integrals(ri, ro, b, rc, zc, a, n=2):
    """A, ∫r dA, ∫z dA, ∫r² dA, ∫z² dA, ∫rz dA of the rectangle less the disc
    |(r, z) − (rc, zc)| < a, by quadrature over r of each strip's exact z-integrals."""
    def strip(r, p, q):
        # ∫ r^p z^q dz over [−b/2, b/2] less the disc's chord at r
        full = r ** p * ((b / 2) ** (q + 1) - (-b / 2) ** (q + 1)) / (q + 1)
        if abs(r - rc) < a:
            h = math.sqrt(a * a - (r - rc) ** 2)
            full -= r ** p * ((zc + h) ** (q + 1) - (zc - h) ** (q + 1)) / (q + 1)
        return full
    kinks = [max(ri, min(ro, rc - a)), max(ri, min(ro, rc + a))]
    return {pq: integrate.quad(strip, ri, ro, args=pq, points=kinks, epsabs=0, epsrel=1e-12, limit=200)[0]
            for pq in [(0, 0), (1, 0), (0, 1), (2, 0), (0, 2), (1, 1)]}


@pytest.mark.parametrize("raceway", ["outer", "inner"])
def test_grooved_section_matches_direct_integration(raceway):
    """A groove of radius 11.96 mm (f = 0.52, D = 23 mm), its centre 1.5 mm off the
    mid-plane (an angular-contact groove), cut 4 mm deep into the raceway side."""
    a, zc = 0.52 * 0.023, 0.0015
    rc = RO + a - 0.004 if raceway == "outer" else RI - a + 0.004
    sec = rs.section_from_envelope(RI, RO, B, [rs.Groove(rc, zc, a)], raceway)
    m = _strip_integrals(RI, RO, B, rc, zc, a)
    area = m[0, 0]
    r_bar, z_bar = m[1, 0] / area, m[0, 1] / area
    assert sec.area == pytest.approx(area, rel=1e-9)
    assert sec.centroid_radius == pytest.approx(r_bar, rel=1e-11)
    assert sec.centroid_axial == pytest.approx(z_bar, rel=1e-6, abs=1e-12)
    assert sec.i_in_plane == pytest.approx(m[2, 0] - area * r_bar ** 2, rel=1e-6)
    assert sec.i_out_of_plane == pytest.approx(m[0, 2] - area * z_bar ** 2, rel=1e-9)
    assert sec.i_product == pytest.approx(m[1, 1] - area * r_bar * z_bar, rel=1e-4)
    assert sec.area < B * (RO - RI) and sec.i_in_plane < B * (RO - RI) ** 3 / 12


def test_a_groove_that_cuts_the_side_face_is_refused():
    with pytest.raises(ValueError, match="side face"):
        rs.section_from_envelope(RI, RO, B, [rs.Groove(RO + 0.01, 0.012, 0.0125)], "outer")


def saint_venant_j(b, t, terms=200):
    """Timoshenko & Goodier §109: J = b t³/3 · (1 − (192/π⁵)(t/b) Σ_{n odd} tanh(nπb/2t)/n⁵)."""
    b, t = max(b, t), min(b, t)
    n = np.arange(1, 2 * terms, 2, dtype=float)
    return b * t ** 3 / 3 * (1 - 192 / math.pi ** 5 * (t / b) * np.sum(np.tanh(n * math.pi * b / (2 * t)) / n ** 5))


@pytest.mark.parametrize("aspect", [1.0, 1.5, 3.0, 10.0])
def test_torsion_constant_within_roark_accuracy_of_saint_venant(aspect):
    t = 0.01
    assert rs.rectangle_torsion_constant(aspect * t, t) == pytest.approx(saint_venant_j(aspect * t, t), rel=3e-3)


@pytest.mark.parametrize("ring", [INNER, OUTER])
def test_a_bearings_ring_section_is_its_envelope_less_its_groove(ring):
    """The 6010 deep-groove bearing (α = 0, zero clearance, one row on the mid-plane): the
    groove's circle, radius f·D, is centred on the contact line at (f − ½)·D beyond the
    ball centre on the pitch circle; the section is the rectangle less that disc, and
    symmetric about the mid-plane."""
    bearing = load_bearing(REPO / "sweeps" / "bearings" / "deep-groove-6010.toml")
    row = bearing.rows[0]
    d, pitch_r = row.ball_diameter, row.pitch_diameter / 2
    if ring == INNER:
        f = row.inner_arcs[0].curvature_ratio
        ri, ro, rc = bearing.bore / 2, bearing.inner_ring.shoulder_diameter / 2, pitch_r + (f - 0.5) * d
        sec = rs.ring_section(bearing, INNER)
    else:
        f = row.outer_arcs[0].curvature_ratio
        ri, ro, rc = 0.035125, bearing.outer_diameter / 2, pitch_r - (f - 0.5) * d
        sec = rs.ring_section(bearing, OUTER, other_diameter=2 * ri)
    m = _strip_integrals(ri, ro, bearing.width, rc, 0.0, f * d)
    assert sec.area == pytest.approx(m[0, 0], rel=1e-9)
    assert sec.centroid_radius == pytest.approx(m[1, 0] / m[0, 0], rel=1e-11)
    assert sec.centroid_axial == pytest.approx(0.0, abs=1e-15) and sec.i_product == pytest.approx(0.0, abs=1e-20)
    assert sec.i_in_plane == pytest.approx(m[2, 0] - m[1, 0] ** 2 / m[0, 0], rel=1e-6)
    with pytest.raises(ValueError, match="other_diameter"):
        rs.ring_section(bearing, OUTER)


# --------------------------------------------------------------------------- in-plane statics


def pinched(extension, n=N_MODES):
    sec = rectangle()
    modes = rm.free_ring_modes(sec, STEEL, n, "radial", extension=extension)
    return sec, modes


def test_pinched_ring_inextensional_closed_form():
    """Two equal inward loads P at 0 and π (Timoshenko & Goodier; Roark Table 9.2):
    ΔD along the loads −(π/4 − 2/π)·PR³/EI, across them +(2/π − 1/2)·PR³/EI."""
    p = 3000.0
    sec, modes = pinched(extension=False)
    scale = p * sec.centroid_radius ** 3 / bending(sec)
    w = rd.static_deflection(modes, [-p, -p], [0.0, math.pi], [0.0, math.pi, math.pi / 2, 3 * math.pi / 2])
    assert w[0] + w[1] == pytest.approx(-(math.pi / 4 - 2 / math.pi) * scale, rel=1e-9)
    assert w[2] + w[3] == pytest.approx((2 / math.pi - 0.5) * scale, rel=1e-9)
    # the figure: a free ring of the study's size pinched by 3 kN, about 4 mm
    assert 3e-3 < -(w[0] + w[1]) < 5e-3


def test_pinched_ring_with_extension_adds_the_uniform_shrink():
    """With the centre line extensible, k = 0 takes Q_0 = −2P on K_0 = 2π(EA/R + EI/R³):
    both diameters shrink by 2·2P/K_0 more (k = 1 carries no force: the loads balance)."""
    p = 3000.0
    sec, modes = pinched(extension=True)
    r = sec.centroid_radius
    scale = p * r ** 3 / bending(sec)
    shrink = 2 * 2 * p / (2 * math.pi * (E * sec.area / r + bending(sec) / r ** 3))
    w = rd.static_deflection(modes, [-p, -p], [0.0, math.pi], [0.0, math.pi, math.pi / 2, 3 * math.pi / 2])
    assert w[0] + w[1] == pytest.approx(-(math.pi / 4 - 2 / math.pi) * scale - shrink, rel=1e-9)
    assert w[2] + w[3] == pytest.approx((2 / math.pi - 0.5) * scale - shrink, rel=1e-9)


def _sum_inv_sq(a, alternating):
    """Σ_{m≥1} (±1)^m / (m² − a²)² in closed form, from Σ_ℤ 1/(m² − a²) = −π·cot(πa)/a and
    Σ_ℤ (−1)^m/(m² − a²) = −π/(a·sin πa), differentiated in a (d/da gives 2a·Σ 1/(m² − a²)²)."""
    s, c = math.sin(math.pi * a), math.cos(math.pi * a)
    if alternating:
        d = math.pi / (a * a * s) + math.pi ** 2 * c / (a * s * s)
    else:
        d = math.pi ** 2 / (a * s * s) + math.pi * c / (s * a * a)
    return (d / (2 * a) - 1 / a ** 4) / 2


@pytest.mark.parametrize("z", [3, 8, 51])
def test_equally_spaced_loads_at_a_load_and_midway(z):
    """Z equal inward loads P at 2πj/Z excite only k = mZ, each with Q = −Z·P:
    w(θ) = −(Z·P·R³/(π·EI))·Σ_{m≥1} cos(mZθ)/((mZ)² − 1)², summed in closed form at θ = 0
    and θ = π/Z (inextensible ring)."""
    p = 3000.0
    sec = rectangle()
    modes = rm.free_ring_modes(sec, STEEL, N_MODES, "radial", extension=False)
    psi = 2 * math.pi * np.arange(z) / z
    w = rd.static_deflection(modes, np.full(z, -p), psi, [0.0, math.pi / z])
    pre = -z * p * sec.centroid_radius ** 3 / (math.pi * bending(sec)) / z ** 4
    assert w[0] == pytest.approx(pre * _sum_inv_sq(1 / z, False), rel=1e-8)
    assert w[1] == pytest.approx(pre * _sum_inv_sq(1 / z, True), rel=1e-8)
    assert w[0] < 0 < w[1] or z > 3   # three loads push the ring into a triangle


def test_unbalanced_load_on_a_free_ring_is_refused_and_a_seat_carries_it():
    sec = rectangle()
    free = rm.free_ring_modes(sec, STEEL, 20, "radial")
    with pytest.raises(ValueError, match="k = 1 is rigid"):
        rd.static_deflection(free, [-1000.0], [0.0], [0.0])
    seated = rsup.supported_ring_modes(sec, STEEL, 20, "radial", rsup.Foundation(radial=1e9))
    assert rd.static_deflection(seated, [-1000.0], [0.0], [0.0])[0] < 0


# --------------------------------------------------------------------------- elastic foundation


def test_ring_on_elastic_foundation_fourier_solution():
    """One inward load P at θ = 0 on a ring in a seat k_r [N/m²]: the ring equation
    EI/R⁴·(w'''' + 2w'' + w) + k_r·w = q expanded in cos kθ gives
    w(θ) = −P·[1/K_0 + Σ_{k≥1} cos kθ / (π·EI·(k² − 1)²/R³ + π·k_r·R)],
    K_0 = 2π(EA/R + EI/R³ + k_r·R), written out here."""
    p, k_r = 3000.0, 2e9
    sec = rectangle()
    r, ei = sec.centroid_radius, bending(sec)
    modes = rsup.supported_ring_modes(sec, STEEL, N_MODES, "radial", rsup.Foundation(radial=k_r))
    theta = np.array([0.0, 0.3, math.pi / 2, math.pi])
    k = np.arange(1, N_MODES + 1)[:, None]
    expected = -p * (1 / (2 * math.pi * (E * sec.area / r + ei / r ** 3 + k_r * r))
                     + (np.cos(k * theta) / (math.pi * ei * (k * k - 1.0) ** 2 / r ** 3 + math.pi * k_r * r)).sum(0))
    got = rd.static_deflection(modes, [-p], [0.0], theta)
    np.testing.assert_allclose(got, expected, rtol=1e-10)


def test_stiff_foundation_tends_to_hetenyis_infinite_beam():
    """A seat so stiff that the load's reach 1/λ, λ = (k_r/(4EI))^¼, is small against R:
    the ring is a beam on an elastic foundation (Hetényi): w(0) = P·λ/(2k_r) and
    w(x) = w(0)·e^(−λx)(cos λx + sin λx), x = R·θ (the ring's curvature adds ~1/(λR)²)."""
    p, k_r = 3000.0, 1e12
    sec = rectangle()
    r, ei = sec.centroid_radius, bending(sec)
    lam = (k_r / (4 * ei)) ** 0.25
    assert lam * r > 20
    modes = rsup.supported_ring_modes(sec, STEEL, N_MODES, "radial", rsup.Foundation(radial=k_r))
    x = np.array([0.0, 0.5, 1.0, 2.0]) / lam
    got = rd.static_deflection(modes, [-p], [0.0], x / r)
    w0 = p * lam / (2 * k_r)
    expected = -w0 * np.exp(-lam * x) * (np.cos(lam * x) + np.sin(lam * x))
    np.testing.assert_allclose(got, expected, rtol=5e-3)


# --------------------------------------------------------------------------- frequencies


def test_free_ring_in_plane_frequencies():
    """Hoppe's ring: ω_k² = EI·k²(k² − 1)²/(ρA·R⁴·(k² + 1)); k = 1 is the rigid
    translation (ω = 0, the modal mass the ring's 2πρAR); k = 0 breathes at ω² ≈ E/(ρR²)."""
    sec = rectangle()
    r, a, ei = sec.centroid_radius, sec.area, bending(sec)
    modes = rm.free_ring_modes(sec, STEEL, 8, "radial")
    k = np.arange(2, 9)
    np.testing.assert_allclose(modes.frequencies[2:] ** 2,
                               ei * k ** 2 * (k ** 2 - 1.0) ** 2 / (RHO * a * r ** 4 * (k ** 2 + 1.0)), rtol=1e-12)
    assert modes.frequencies[1] == 0.0 and modes.mass[1] == pytest.approx(2 * math.pi * RHO * a * r, rel=1e-12)
    assert modes.frequencies[0] ** 2 == pytest.approx(E / (RHO * r * r), rel=1e-3)


def test_free_ring_out_of_plane_frequency_of_a_circular_wire():
    """Love §291: a ring of circular section (E·I/(G·J) = 1 + ν, J = 2I) vibrates out of
    its plane at ω_k² = EI·k²(k² − 1)²/(ρA·R⁴·(k² + 1 + ν)); k = 0, 1 are rigid."""
    d, r = 0.01, 0.2
    i = math.pi * d ** 4 / 64
    a = math.pi * d * d / 4
    wire = rs.given_section(a, r, i, i, 2 * i)
    modes = rm.free_ring_modes(wire, STEEL, 4, "axial")
    for k in (2, 3, 4):
        expected = E * i * k * k * (k * k - 1) ** 2 / (RHO * a * r ** 4 * (k * k + 1 + NU))
        assert modes.frequencies[k] ** 2 == pytest.approx(expected, rel=1e-12)
    assert modes.stiffness[0] == 0.0 and modes.stiffness[1] == 0.0


@pytest.mark.parametrize("k", [2, 3, 5])
def test_out_of_plane_stiffness_minimises_the_energy_over_the_twist(k):
    """u = cos kθ (unit amplitude), β = b·cos kθ: κ = (β − u''/R)/R, τ = (β' + u'/R)/R,
    U(b) = (R/2)∫(EI·κ² + GJ·τ²)dθ integrated numerically and minimised over b; the modal
    stiffness is 2·min U. (A rigid tilt, u = R·sin θ, β = −sin θ, gives κ = τ = 0.)"""
    sec = rectangle()
    r, ei, gj = sec.centroid_radius, E * sec.i_out_of_plane, G * sec.torsion_constant

    def energy(b):
        def density(t):
            u1, u2 = -k * math.sin(k * t), -k * k * math.cos(k * t)
            beta, beta1 = b * math.cos(k * t), -b * k * math.sin(k * t)
            kappa, tau = (beta - u2 / r) / r, (beta1 + u1 / r) / r
            return ei * kappa ** 2 + gj * tau ** 2
        return r / 2 * integrate.quad(density, 0, 2 * math.pi, limit=200, epsrel=1e-13)[0]

    best = optimize.minimize_scalar(energy, bracket=(-100.0, 0.0), tol=1e-12)
    modes = rm.free_ring_modes(sec, STEEL, 6, "axial")
    assert modes.stiffness[k] == pytest.approx(2 * best.fun, rel=1e-7)


# --------------------------------------------------------------------------- convergence


def test_pinched_ring_converges_as_the_cube_of_the_mode_count():
    """The terms fall as k⁻⁴, so the truncation error falls as N⁻³: doubling the modes
    divides it by about 8; with 40 modes it is below 1e-4 of the answer."""
    p = 1000.0
    sec = rectangle()
    exact = -(math.pi / 4 - 2 / math.pi) * p * sec.centroid_radius ** 3 / bending(sec)
    errors = []
    for n in (10, 20, 40, 80):
        modes = rm.free_ring_modes(sec, STEEL, n, "radial", extension=False)
        w = rd.static_deflection(modes, [-p, -p], [0.0, math.pi], [0.0, math.pi])
        errors.append(abs(w.sum() - exact) / abs(exact))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all(ratios > 6.5) and np.all(ratios < 9.5)
    assert errors[2] < 1e-4


# --------------------------------------------------------------------------- support


def test_housing_ring_in_series_with_its_seat_and_in_parallel_with_the_ring():
    """Per order: K = K_ring + 1/(1/K_seat + 1/(K_housing + K_ground)), each term from
    its own formula: K_ring = π·EI(k² − 1)²/R³, K_seat = π·k_s·R, K_ground = π·k_g·R_h."""
    ring = rectangle()
    housing = rs.section_from_envelope(0.170, 0.200, 0.040)
    k_s, k_g = 5e10, 1e9
    support = rsup.HousingRing(housing, STEEL, seat=rsup.Foundation(k_s, k_s), ground=rsup.Foundation(k_g, k_g))
    modes = rsup.supported_ring_modes(ring, STEEL, 6, "radial", support)
    r, rh = ring.centroid_radius, housing.centroid_radius
    for k in range(2, 7):
        k_ring = math.pi * E * ring.i_in_plane * (k * k - 1) ** 2 / r ** 3
        k_house = math.pi * E * housing.i_in_plane * (k * k - 1) ** 2 / rh ** 3 + math.pi * k_g * rh
        expected = k_ring + 1 / (1 / (math.pi * k_s * r) + 1 / k_house)
        assert modes.stiffness[k] == pytest.approx(expected, rel=1e-12)
    bonded = rsup.supported_ring_modes(ring, STEEL, 6, "radial", rsup.HousingRing(housing, STEEL))
    k = 3
    assert bonded.stiffness[k] == pytest.approx(
        math.pi * E * (ring.i_in_plane / r ** 3 + housing.i_in_plane / rh ** 3) * (k * k - 1) ** 2, rel=1e-12)
    # a free housing does not hold the ring's translation: k = 1 stays rigid
    assert bonded.stiffness[1] == 0.0


def test_modal_damping_from_the_ratio():
    """c_k = 2ζ·√(K_k·M_k), the critical damping times ζ."""
    sec = rectangle()
    modes = rsup.supported_ring_modes(sec, STEEL, 5, "axial", rsup.Foundation(1e9, 1e9), damping_ratio=0.05)
    np.testing.assert_allclose(modes.damping, 2 * 0.05 * np.sqrt(modes.stiffness * modes.mass), rtol=1e-14)
    assert rm.DEFAULT_DAMPING_RATIO == rm.free_ring_modes(sec, STEEL, 2).damping_ratio
    with pytest.raises(ValueError, match="damping ratio"):
        rm.free_ring_modes(sec, STEEL, 2, damping_ratio=-0.1)


# --------------------------------------------------------------------------- statics coupling


BUILDABLE = REPO / "sweeps" / "bearings" / "rv-main-buildable.toml"
#: the outer ring's shoulder (bore) diameter the bearing file does not give: an assumption
#: for these tests, 10.5 mm of wall under the 383 mm outside diameter
OUTER_SHOULDER = 0.362


def _statics(bearing, rings=None, **loads):
    from rvcore.statics.equilibrium import solve_statics

    return solve_statics(bearing, gravity=False, rings=rings, **loads)


def test_a_very_stiff_support_gives_the_rigid_rings_statics():
    """Both rings flexible in a seat of 1e16 N/m² (radially and axially): the raceways move by
    picometres, and the load distribution, the pose and the stiffness are the rigid rings'
    within 0.1 %."""
    from rvcore.rings.flexible import flexible_rings

    bearing = load_bearing(BUILDABLE)
    seat = rsup.Foundation(1e16, 1e16)
    rings = flexible_rings(bearing, inner=seat, outer=seat, outer_shoulder_diameter=OUTER_SHOULDER, max_order=40)
    loads = dict(radial_load=30e3, axial_load=10e3, moment=500.0)
    rigid, flexible = _statics(bearing, **loads), _statics(bearing, rings, **loads)
    assert flexible.ring_iterations >= 1 and np.abs(flexible.ring_displacements).max() < 1e-9
    np.testing.assert_allclose(flexible.displacement[:3], rigid.displacement[:3], rtol=1e-3, atol=1e-9)
    np.testing.assert_allclose(flexible.displacement[3:], rigid.displacement[3:], rtol=1e-3, atol=1e-8)
    assert flexible.max_contact_load == pytest.approx(rigid.max_contact_load, rel=1e-3)
    np.testing.assert_allclose(flexible.ball_loads, rigid.ball_loads, rtol=0, atol=1e-3 * rigid.max_contact_load)
    diag_rigid, diag_flex = np.diag(rigid.stiffness_matrix), np.diag(flexible.stiffness_matrix)
    np.testing.assert_allclose(diag_flex, diag_rigid, rtol=1e-3)
    assert flexible.loaded_ball_count == rigid.loaded_ball_count


def _axial_sum(section, z, k_a, n_max):
    """Σ over the orders a uniform set of Z axial loads excites, k = 0 and mZ, of 1/K_k,
    K_k = π·EI·k²(k² − 1)²/(R³(k² + EI/GJ)) + π·k_a·R, K_0 = 2π·k_a·R (module Notes of
    rvcore.rings.modes and support, written out)."""
    r, ei, gj = section.centroid_radius, E * section.i_out_of_plane, G * section.torsion_constant
    total = 1 / (2 * math.pi * k_a * r)
    for k in range(z, n_max + 1, z):
        total += 1 / (math.pi * ei * k * k * (k * k - 1) ** 2 / (r ** 3 * (k * k + ei / gj)) + math.pi * k_a * r)
    return total


def test_a_pure_axial_load_adds_the_rings_axial_deflection_in_series():
    """Under a pure axial load F_a every ball carries F_a/Z alike, so a ring held radially
    rigid but axially on a seat k_a moves each raceway by the same u = F_a·Σ_{k=0,mZ} 1/K_k
    (the Z equal loads excite only k = 0 and k = mZ), the contacts meet the same geometry
    and the inner ring's support must move u_inner + u_outer further than on rigid rings."""
    from rvcore.rings.flexible import flexible_rings

    bearing = load_bearing(BUILDABLE)
    z, f_a, k_a, n_max = bearing.rows[0].ball_count, 20e3, 5e9, 80
    rings = flexible_rings(bearing, inner=rsup.Foundation(math.inf, k_a), outer=rsup.Foundation(math.inf, k_a),
                           outer_shoulder_diameter=OUTER_SHOULDER, max_order=n_max)
    rigid = _statics(bearing, axial_load=f_a, stiffness=False)
    flexible = _statics(bearing, rings, axial_load=f_a, stiffness=False)
    inner = rs.ring_section(bearing, INNER)
    outer = rs.ring_section(bearing, OUTER, other_diameter=OUTER_SHOULDER)
    extra = f_a * (_axial_sum(inner, z, k_a, n_max) + _axial_sum(outer, z, k_a, n_max))
    assert extra > 0.05 * rigid.axial_displacement     # a visible share, not round-off
    assert flexible.axial_displacement == pytest.approx(rigid.axial_displacement + extra, rel=1e-6)
    np.testing.assert_allclose(flexible.ball_loads, rigid.ball_loads, rtol=1e-6)
    # the rings' own displacements: the inner raceway pushed back (−z), the outer one along +z
    np.testing.assert_allclose(flexible.ring_displacements[:, 1], -f_a * _axial_sum(inner, z, k_a, n_max), rtol=1e-6)
    np.testing.assert_allclose(flexible.ring_displacements[:, 3], f_a * _axial_sum(outer, z, k_a, n_max), rtol=1e-6)
    assert np.all(flexible.ring_displacements[:, [0, 2]] == 0.0)


def test_a_softer_seat_spreads_the_load_and_keeps_the_ring_in_balance():
    """A flexible inner ring in a seat of 1e10 N/m² under a radial load: the ring still
    balances the load (the residual), it yields more than the rigid one, and the load
    spreads: the most loaded ball carries less (the raceway gives way under it most)."""
    from rvcore.rings.flexible import flexible_rings

    bearing = load_bearing(BUILDABLE)
    rings = flexible_rings(bearing, inner=rsup.Foundation(1e10, 1e10), max_order=40)
    rigid = _statics(bearing, radial_load=30e3, axial_load=10e3, stiffness=False)
    flexible = _statics(bearing, rings, radial_load=30e3, axial_load=10e3, stiffness=False)
    assert np.abs(flexible.residual[:3]).max() < 1e-6 * 30e3
    assert flexible.radial_displacement > rigid.radial_displacement
    assert flexible.max_contact_load < rigid.max_contact_load
    # the inner raceway gives way inward (w < 0) most under the most loaded ball
    j = int(np.argmax(flexible.ball_loads.sum(axis=1)))
    assert flexible.ring_displacements[j, 0] == flexible.ring_displacements[:, 0].min() < 0


def test_rigid_rings_leave_the_statics_bit_for_bit():
    from rvcore.rings.flexible import RIGID_RINGS

    bearing = load_bearing(BUILDABLE)
    a = _statics(bearing, radial_load=30e3, axial_load=10e3)
    b = _statics(bearing, RIGID_RINGS, radial_load=30e3, axial_load=10e3)
    assert np.array_equal(a.displacement, b.displacement) and np.array_equal(a.ball_loads, b.ball_loads)
    assert np.array_equal(a.stiffness_matrix, b.stiffness_matrix) and b.ring_displacements is None


def test_a_flexible_ring_without_a_support_is_refused():
    from rvcore.rings.flexible import FlexibleRings

    free = rm.free_ring_modes(rectangle(), STEEL, 10, "radial")
    with pytest.raises(ValueError, match="k = 1 has no stiffness"):
        FlexibleRings(inner_radial=free)
