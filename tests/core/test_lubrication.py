"""The lubrication physics of issue 40 as pure functions: Hamrock–Dowson's film, ISO 281
clause 9 (ν1, κ, a_ISO, C_u, e_C, a_1, L_nm and its duty-cycle accumulation), the Walther
viscosity–temperature line and the lubricated traction law.

Every expectation is computed here from the published formula (written out again, not
imported), from Hertz theory or from the law's own definition (finite differences); no
number is copied from the code's output.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rvcore import hertz
from rvcore.bearing import lubricant as lub
from rvcore.contact import film, traction_ehl as tr
from rvcore.standards import iso281_modified as iso

STEEL_E, STEEL_NU = 208e9, 0.3
E_EFF = STEEL_E / (1.0 - STEEL_NU ** 2)          # two equal solids, E' = E/(1 − ν²)
STUDY_D, STUDY_DM = 0.023, 0.3515


def hd_central(w, u, eta, alpha, e, rx, k):
    """Hamrock & Dowson (1977): H_c = 2.69 U^0.67 G^0.53 W^-0.067 (1 − 0.61 e^-0.73k)."""
    big_u, big_g, big_w = eta * u / (e * rx), alpha * e, w / (e * rx * rx)
    return rx * 2.69 * big_u ** 0.67 * big_g ** 0.53 * big_w ** -0.067 * (1 - 0.61 * math.exp(-0.73 * k))


def hd_minimum(w, u, eta, alpha, e, rx, k):
    """Hamrock & Dowson (1977): H_min = 3.63 U^0.68 G^0.49 W^-0.073 (1 − e^-0.68k)."""
    big_u, big_g, big_w = eta * u / (e * rx), alpha * e, w / (e * rx * rx)
    return rx * 3.63 * big_u ** 0.68 * big_g ** 0.49 * big_w ** -0.073 * (1 - math.exp(-0.68 * k))


# --------------------------------------------------------------------------- Hamrock–Dowson


def test_reference_contact_ball_on_flat():
    """Issue 40's reference contact: a 12.7 mm steel ball on a steel flat, 100 N, 1 m/s,
    η0 = 0.04 Pa s, α = 2e-8 1/Pa. Hertz theory: a sphere on a flat is a circular contact
    (k = 1) with R_x = R_y = D/2."""
    d = 12.7e-3
    contact = hertz.point_contact(2 / d, 2 / d, 0.0, 0.0, E_EFF)
    assert contact.ellipticity == pytest.approx(1.0, abs=1e-12)
    r_x, r_y = film.effective_radii(contact)
    assert r_x == pytest.approx(d / 2, rel=1e-12) and r_y == pytest.approx(d / 2, rel=1e-12)
    got = film.hamrock_dowson_contact(contact, 100.0, 1.0, 0.04, 2e-8)
    assert got.central == pytest.approx(hd_central(100, 1, 0.04, 2e-8, E_EFF, d / 2, 1.0), rel=1e-12)
    assert got.minimum == pytest.approx(hd_minimum(100, 1, 0.04, 2e-8, E_EFF, d / 2, 1.0), rel=1e-12)
    assert not got.extrapolated
    # the film of such a contact is a fraction of a micrometre, thinner at its exit lobes
    assert 0.0 < got.minimum < got.central < 1e-6


def test_race_contact_radii_from_the_groove_geometry():
    """Inner raceway, α = 0: 1/R_x = 2/D + (2/D)γ/(1 − γ) ⇒ R_x = D(1 − γ)/2, and
    1/R_y = 2/D − 1/(fD) ⇒ R_y = fD/(2f − 1) (Harris & Kotzalas)."""
    f = 0.52
    gamma = STUDY_D / STUDY_DM
    contact = hertz.race_contact(STUDY_D, STUDY_DM, f, 0.0, "inner", E_EFF)
    r_x, r_y = film.effective_radii(contact)
    assert r_x == pytest.approx(STUDY_D * (1 - gamma) / 2, rel=1e-12)
    assert r_y == pytest.approx(f * STUDY_D / (2 * f - 1), rel=1e-12)


@pytest.mark.parametrize("ring, f", [("inner", 0.52), ("outer", 0.53)])
def test_film_scales_with_speed_and_load_as_the_law_says(ring, f):
    """h_c ∝ u^0.67 and h_min ∝ u^0.68; h_c ∝ w^−0.067, h_min ∝ w^−0.073 (k, R_x fixed by
    the geometry)."""
    contact = hertz.race_contact(STUDY_D, STUDY_DM, f, 0.0, ring, E_EFF)
    base = film.hamrock_dowson_contact(contact, 3000.0, 0.2, 0.088, 2e-8)
    fast = film.hamrock_dowson_contact(contact, 3000.0, 0.6, 0.088, 2e-8)
    heavy = film.hamrock_dowson_contact(contact, 12000.0, 0.2, 0.088, 2e-8)
    assert fast.central / base.central == pytest.approx(3.0 ** 0.67, rel=1e-12)
    assert fast.minimum / base.minimum == pytest.approx(3.0 ** 0.68, rel=1e-12)
    assert heavy.central / base.central == pytest.approx(4.0 ** -0.067, rel=1e-12)
    assert heavy.minimum / base.minimum == pytest.approx(4.0 ** -0.073, rel=1e-12)


def test_study_inner_contact_matches_the_issue_table():
    """Issue 40's table, computed there from the same published formulas: the inner
    contact of the study bearing at 3 kN, base oil 100 mm²/s (η0 = 0.088 Pa s at 880 kg/m³),
    α = 2e-8 1/Pa, pure rolling: h_c about 0.15 µm at 120 °/s and 0.46 µm at 660 °/s."""
    alpha = math.radians(15.0)
    contact = hertz.race_contact(STUDY_D, STUDY_DM, 0.52, alpha, "inner", E_EFF)
    for deg_s, expected in ((120.0, 0.15e-6), (660.0, 0.46e-6)):
        u = film.entrainment_speed_pure_rolling(math.radians(deg_s), STUDY_DM, STUDY_D, alpha)
        got = film.hamrock_dowson_contact(contact, 3000.0, u, 0.088, 2e-8)
        assert got.central == pytest.approx(expected, rel=0.03)
        assert got.extrapolated                     # k = 8.5, beyond the fit's 1..8


def test_ellipticity_outside_the_fit_is_flagged_and_k_below_one_refused():
    inside = film.hamrock_dowson(100.0, 1.0, 0.04, 2e-8, E_EFF, 0.005, 8.0)
    outside = film.hamrock_dowson(100.0, 1.0, 0.04, 2e-8, E_EFF, 0.005, 8.5)
    assert not inside.extrapolated and outside.extrapolated
    with pytest.raises(ValueError, match="k >= 1"):
        film.hamrock_dowson(100.0, 1.0, 0.04, 2e-8, E_EFF, 0.005, 0.9)
    with pytest.raises(ValueError, match="load"):
        film.hamrock_dowson(0.0, 1.0, 0.04, 2e-8, E_EFF, 0.005, 2.0)


def test_entrainment_speed_is_the_same_at_both_races_in_pure_rolling():
    """Cage at ω_c = ω_i(1 − γ)/2 (outer ring fixed, pure rolling): the inner race passes
    its contact at (ω_i − ω_c)(d_m − D cos α)/2, the outer at ω_c(d_m + D cos α)/2."""
    w_i, alpha = 2.0, math.radians(15.0)
    gamma = STUDY_D * math.cos(alpha) / STUDY_DM
    w_c = w_i * (1 - gamma) / 2
    u_inner = (w_i - w_c) * STUDY_DM * (1 - gamma) / 2
    u_outer = w_c * STUDY_DM * (1 + gamma) / 2
    got = film.entrainment_speed_pure_rolling(w_i, STUDY_DM, STUDY_D, alpha)
    assert got == pytest.approx(u_inner, rel=1e-12) and got == pytest.approx(u_outer, rel=1e-12)


def test_film_parameter_and_composite_roughness():
    sigma = lub.composite_roughness(0.0625e-6, 0.175e-6)
    assert sigma == pytest.approx(math.sqrt(0.0625e-6 ** 2 + 0.175e-6 ** 2), rel=1e-15)
    assert lub.composite_roughness() == pytest.approx(sigma, rel=1e-15)     # the defaults
    assert film.film_parameter(0.372e-6, sigma) == pytest.approx(0.372e-6 / sigma, rel=1e-15)
    with pytest.raises(ValueError):
        lub.composite_roughness(-1e-9, 1e-7)


# --------------------------------------------------------------------------- ISO 281 clause 9


def a_iso_formula(kappa, x):
    """ISO 281:2007, radial ball bearings, the three κ branches written out again."""
    if kappa < 0.4:
        c, e = 2.2649, 0.054381
    elif kappa < 1.0:
        c, e = 1.9987, 0.190870
    else:
        c, e = 1.9987, 0.071739
    return 0.1 * (1 - (2.5671 - c / kappa ** e) ** 0.83 * x ** (1 / 3)) ** -9.3


@pytest.mark.parametrize("x", [0.01, 0.05, 0.1, 0.2, 0.4])
def test_a_iso_branches_meet_at_kappa_0_4_and_1(x):
    """Left and right of each branch point, within 0.1 % (the constants' rounding)."""
    for k0, left in ((0.4, (2.2649, 0.054381)), (1.0, (1.9987, 0.190870))):
        c, e = left
        from_left = 0.1 * (1 - (2.5671 - c / k0 ** e) ** 0.83 * x ** (1 / 3)) ** -9.3
        from_right = a_iso_formula(k0, x)
        assert from_left == pytest.approx(from_right, rel=1e-3)
        got_left = iso.a_iso_ball(k0 * (1 - 1e-12), x)["a_iso"]
        got_right = iso.a_iso_ball(k0, x)["a_iso"]
        assert got_left == pytest.approx(from_left, rel=1e-9)
        assert got_right == pytest.approx(from_right, rel=1e-9)
        assert got_left == pytest.approx(got_right, rel=1e-3)


def test_a_iso_is_capped_at_50_and_kappa_at_4():
    assert iso.a_iso_ball(2.0, 5.0)["a_iso"] == 50.0              # the bracket reaches 0
    x = 0.1
    assert a_iso_formula(4.0, x) < 50.0
    assert iso.a_iso_ball(9.0, x)["a_iso"] == pytest.approx(a_iso_formula(4.0, x), rel=1e-12)
    assert iso.a_iso_ball(9.0, x)["kappa_used"] == 4.0
    # a_ISO grows with κ and with e_C·C_u/P, and never passes 50
    grid = [iso.a_iso_ball(k, xx)["a_iso"] for k in np.linspace(0.1, 4, 40) for xx in (0.05, 0.5, 2.0)]
    assert max(grid) <= 50.0


def test_kappa_below_0_1_is_flagged_and_held_at_the_floor():
    """At κ = 0.1 the formula's first branch gives a_ISO ≈ 0.1 whatever the load
    (2.2649·0.1^−0.054381 = 2.5671 to the constants' rounding, so the bracket is ≈ 1)."""
    assert 2.2649 * 0.1 ** -0.054381 == pytest.approx(2.5671, abs=1e-4)
    for x in (0.01, 0.5, 3.0):
        floor = a_iso_formula(0.1, x)
        assert floor == pytest.approx(0.1, rel=1e-2)
        assert iso.a_iso_ball(0.1, x)["a_iso"] == pytest.approx(floor, rel=1e-12)
        low = iso.a_iso_ball(0.05, x)
        assert low["outside_scope"] and low["a_iso"] == pytest.approx(floor, rel=1e-12)
    assert not iso.a_iso_ball(0.1, 0.5)["outside_scope"]


def test_ep_rule():
    """κ < 1, e_C ≥ 0.2, EP additives: κ = 1 may be used, a_ISO then limited to 3; the
    rule never lowers a_ISO below the value at the actual κ."""
    x = 0.1
    plain = iso.a_iso_ball(0.5, x, ep_additives=False)["a_iso"]
    ep = iso.a_iso_ball(0.5, x, ep_additives=True, contamination=0.5)
    assert plain == pytest.approx(a_iso_formula(0.5, x), rel=1e-12)
    assert ep["ep_rule"] and ep["a_iso"] == pytest.approx(min(a_iso_formula(1.0, x), 3.0), rel=1e-12)
    assert ep["a_iso"] > plain
    # e_C below 0.2: no rule
    dirty = iso.a_iso_ball(0.5, x, ep_additives=True, contamination=0.1)
    assert not dirty["ep_rule"] and dirty["a_iso"] == pytest.approx(plain, rel=1e-12)
    # where a_ISO(κ = 1) exceeds 3, the rule gives 3 (unless the actual κ gives more)
    x_big = 1.0
    assert a_iso_formula(1.0, x_big) > 3.0
    capped = iso.a_iso_ball(0.5, x_big, ep_additives=True, contamination=0.8)
    assert capped["a_iso"] == pytest.approx(max(3.0, a_iso_formula(0.5, x_big)), rel=1e-12)
    # κ ≥ 1: nothing to do
    assert not iso.a_iso_ball(1.5, x, ep_additives=True, contamination=0.8)["ep_rule"]
    with pytest.raises(ValueError, match="e_C"):
        iso.a_iso_ball(0.5, x, ep_additives=True)


def test_reference_viscosity_branches_and_the_issue_figures():
    """ν1 = 45000 n^−0.83 d_m^−0.5 (n < 1000 r/min), 4500 n^−0.5 d_m^−0.5 above (n in r/min,
    d_m in mm, ν1 in mm²/s): the branches meet within 3 % at 1000 r/min."""
    rpm = 2 * math.pi / 60
    dm_mm = 351.5
    below = iso.reference_viscosity(999.999 * rpm, dm_mm / 1e3)
    at = iso.reference_viscosity(1000.0 * (1 + 1e-12) * rpm, dm_mm / 1e3)
    assert below == pytest.approx(45000 * 999.999 ** -0.83 * dm_mm ** -0.5 * 1e-6, rel=1e-9)
    assert at == pytest.approx(4500 * 1000 ** -0.5 * dm_mm ** -0.5 * 1e-6, rel=1e-9)
    assert below == pytest.approx(at, rel=0.03)
    # issue 40: 120 deg/s (20 r/min) about 200 mm²/s, 660 deg/s (110 r/min) about 49 mm²/s
    assert iso.reference_viscosity(math.radians(120), 0.3515) * 1e6 == pytest.approx(200, rel=0.01)
    assert iso.reference_viscosity(math.radians(660), 0.3515) * 1e6 == pytest.approx(49, rel=0.02)
    assert iso.viscosity_ratio(100e-6, math.radians(120), 0.3515) == pytest.approx(0.5, rel=0.01)


def test_fatigue_load_limit_simplified():
    """C_u = C_0/22 up to d_m = 100 mm, times (100/d_m)^0.5 above: continuous at 100 mm."""
    c0 = 100e3
    assert iso.fatigue_load_limit_ball(c0, 0.08) == pytest.approx(c0 / 22, rel=1e-15)
    assert iso.fatigue_load_limit_ball(c0, 0.1) == pytest.approx(c0 / 22, rel=1e-15)
    assert iso.fatigue_load_limit_ball(c0, 0.3515) == pytest.approx(c0 / 22 * (100 / 351.5) ** 0.5, rel=1e-12)
    assert iso.fatigue_load_limit_ball(c0, 0.1 * (1 + 1e-9)) == pytest.approx(c0 / 22, rel=1e-8)


def test_reliability_factors_follow_their_weibull_relation():
    """ISO/TR 1281-2: a_1 = 0.95·(ln(100/R)/ln(100/90))^(2/3) + 0.05 (Weibull slope 1.5,
    a_1 ≥ 0.05); the table holds it to its printed digits."""
    for r, a1 in iso.RELIABILITY_FACTORS.items():
        theory = 0.95 * (math.log(100 / r) / math.log(100 / 90)) ** (2 / 3) + 0.05
        decimals = len(repr(a1).split(".")[1])
        assert abs(a1 - theory) <= 0.5 * 10 ** -decimals + 1e-12, (r, a1, theory)
        assert iso.reliability_factor(r) == a1
    with pytest.raises(ValueError, match="Table 12"):
        iso.reliability_factor(93.0)


def test_contamination_guide_values():
    assert iso.contamination_factor() == 0.6                            # normal, d_m ≥ 100 mm, low end
    assert iso.contamination_factor("normal cleanliness", 0.05, "high") == 0.6
    assert iso.contamination_factor("high cleanliness", 0.3515, "high") == 0.9
    for small, large in iso.CONTAMINATION_GUIDE.values():                # each range is (high, low)
        assert small[0] >= small[1] and large[0] >= large[1]
    with pytest.raises(ValueError, match="contamination level"):
        iso.contamination_factor("clean-ish")


def test_duty_cycle_of_one_step_is_the_static_modified_life():
    """One step: L_nm = a_1·a_ISO·(C/P)^3·10^6 rev, whatever the step's length."""
    c, cu, p, kappa, ec, a1 = 250e3, 9e3, 20e3, 0.6, 0.6, 0.25
    a = a_iso_formula(kappa, ec * cu / p)
    expected = a1 * a * (c / p) ** 3 * 1e6
    for n in (1.0, 3.7e4):
        got = iso.duty_cycle_modified_life([p], [kappa], [n], c, cu, ec, a1)
        assert got["modified_life"] == pytest.approx(expected, rel=1e-12)
    assert iso.modified_rating_life((c / p) ** 3 * 1e6, a, a1) == pytest.approx(expected, rel=1e-12)


def test_duty_cycle_accumulates_damage_palmgren_miner():
    """Three steps, one unloaded: D = Σ N_k/(a_k·L10_k), L_nm = a_1·ΣN/D; the step below
    κ = 0.1 is flagged and counted."""
    c, cu, ec = 250e3, 9e3, 0.5
    p = np.array([30e3, 10e3, 0.0, 15e3])
    k = np.array([0.05, 2.0, 1.0, 0.7])
    n = np.array([100.0, 2000.0, 50.0, 400.0])
    damage = 0.0
    for pk, kk, nk in zip(p, k, n):
        if pk > 0:
            a = min(a_iso_formula(max(kk, 0.1), ec * cu / pk), 50.0)     # the cap of 50
            damage += nk / (a * (c / pk) ** 3 * 1e6)
    got = iso.duty_cycle_modified_life(p, k, n, c, cu, ec)
    assert got["damage_cycle"] == pytest.approx(damage, rel=1e-12)
    assert got["modified_life"] == pytest.approx(n.sum() / damage, rel=1e-12)
    assert got["damage"][2] == 0.0
    assert list(got["outside_scope"]) == [True, False, False, False]
    assert got["outside_scope_revolutions"] == 100.0
    assert iso.duty_cycle_modified_life([0.0], [1.0], [10.0], c, cu, ec)["modified_life"] == math.inf


# --------------------------------------------------------------------------- lubricant


def loglog(nu_mm2s):
    return math.log10(math.log10(nu_mm2s + 0.7))


def test_walther_reproduces_its_two_points():
    for nu40, nu100 in ((100e-6, 11.1e-6), (68e-6, 8.5e-6), (320e-6, 24e-6)):
        assert lub.kinematic_viscosity(313.15, nu40, nu100) == pytest.approx(nu40, rel=1e-12)
        assert lub.kinematic_viscosity(373.15, nu40, nu100) == pytest.approx(nu100, rel=1e-12)


def test_walther_is_a_straight_line_in_loglog_against_log_t():
    """ASTM D341: any third point lies on the line through the first two."""
    nu40, nu100 = 100e-6, 11.1e-6
    t3 = 333.15
    nu3 = lub.kinematic_viscosity(t3, nu40, nu100) * 1e6
    slope_13 = (loglog(nu3) - loglog(100.0)) / (math.log10(t3) - math.log10(313.15))
    slope_12 = (loglog(11.1) - loglog(100.0)) / (math.log10(373.15) - math.log10(313.15))
    assert slope_13 == pytest.approx(slope_12, rel=1e-10)


def test_viscosity_index_behaviour_of_a_vg_grade():
    """Two ISO VG 100 oils (ν40 = 100 mm²/s by ISO 3448), the second of higher viscosity
    index (thicker at 100 °C): it is thicker above 40 °C and thinner below, and both thin
    monotonically as they warm."""
    nu40 = lub.iso_vg_viscosity("VG 100")
    assert nu40 == pytest.approx(100e-6, rel=1e-15)
    low_vi, high_vi = 10.0e-6, 14.0e-6
    temps = np.linspace(283.15, 393.15, 23)
    a = np.array([lub.kinematic_viscosity(t, nu40, low_vi) for t in temps])
    b = np.array([lub.kinematic_viscosity(t, nu40, high_vi) for t in temps])
    assert np.all(np.diff(a) < 0) and np.all(np.diff(b) < 0)
    assert np.all(b[temps > 313.2] > a[temps > 313.2])
    assert np.all(b[temps < 313.1] < a[temps < 313.1])


def test_lubricant_inputs_out_of_range_are_refused():
    with pytest.raises(ValueError, match="ISO VG grade"):
        lub.iso_vg_viscosity(90)
    with pytest.raises(ValueError, match="2.0 mm"):
        lub.kinematic_viscosity(373.15, 5e-6, 1.5e-6)
    with pytest.raises(ValueError, match="2.0 mm"):
        lub.kinematic_viscosity(600.0, 10e-6, 2.5e-6)       # too hot for the simple form
    with pytest.raises(ValueError, match="must exceed"):
        lub.kinematic_viscosity(330.0, 10e-6, 12e-6)
    assert lub.dynamic_viscosity(100e-6, 880.0) == pytest.approx(0.088, rel=1e-15)


# --------------------------------------------------------------------------- traction law

LAW = tr.pack_ehl_traction_law(0.088, 2e-8)


def barus(eta0, alpha, p):
    return eta0 * math.exp(alpha * p)


def test_small_slip_is_newtonian_with_barus_viscosity():
    """Full film (λ ≥ 3): μ(s) → η0·e^(αp)·s/(h·p) as s → 0."""
    p, h = 0.3e9, 0.3e-6
    eta = barus(0.088, 2e-8, p)
    s = 1e-6 * h * 0.07 * p / eta            # η·s/(h·τ_L) = 1e-6: deep in the Newtonian part
    mu = tr.ehl_traction_coefficient(s, p, h, 4.0, LAW)
    assert mu == pytest.approx(eta * s / (h * p), rel=1e-5)
    assert tr.ehl_slope_at_zero_slip(p, h, 4.0, LAW) == pytest.approx(eta / (h * p), rel=1e-12)


def test_large_slip_saturates_at_the_limiting_shear_stress():
    """μ → τ_L/p = (τ_L0 + γ_L·p)/p at large slip."""
    law = tr.pack_ehl_traction_law(0.088, 2e-8, tau_l0=2e6, gamma_l=0.06)
    for p in (0.5e9, 1.5e9):
        mu = tr.ehl_traction_coefficient(5.0, p, 0.2e-6, 3.5, law)
        assert mu == pytest.approx((2e6 + 0.06 * p) / p, rel=1e-12)


def test_blend_toward_boundary_friction():
    """λ ≤ λ_b: the boundary law alone, the study's cubic rise μ_b(1.5x − 0.5x³), x = s/v_b;
    λ ≥ λ_f: the film alone; between, a weighted mean."""
    p, h, s = 1e9, 0.2e-6, 0.04
    x = s / 0.1
    boundary = 0.1 * (1.5 * x - 0.5 * x ** 3)
    assert tr.ehl_traction_coefficient(s, p, h, 0.5, LAW) == pytest.approx(boundary, rel=1e-12)
    full = tr.ehl_traction_coefficient(s, p, h, 3.0, LAW)
    assert full == pytest.approx(0.07 * -math.expm1(-barus(0.088, 2e-8, p) * s / (h * 0.07 * p)), rel=1e-12)
    mid = tr.ehl_traction_coefficient(s, p, h, 2.0, LAW)       # STEP at its middle: weight 1/2
    assert mid == pytest.approx(0.5 * boundary + 0.5 * full, rel=1e-12)


@settings(max_examples=300, deadline=None)
@given(s=st.floats(0.0, 10.0), p=st.floats(1e7, 3e9), h=st.floats(1e-9, 1e-5), lam=st.floats(0.0, 6.0))
def test_dissipation_is_never_negative(s, p, h, lam):
    mu = tr.ehl_traction_coefficient(s, p, h, lam, LAW)
    assert math.isfinite(mu) and mu >= 0.0 and mu * s >= 0.0
    assert tr.ehl_traction_slope(s, p, h, lam, LAW) >= 0.0


@settings(max_examples=200, deadline=None)
@given(s=st.floats(0.0, 1e3), p=st.floats(1e3, 1e11), h=st.floats(1e-12, 1e-3), lam=st.floats(0.0, 10.0))
def test_law_stays_finite_far_outside_its_range(s, p, h, lam):
    """The Barus exponent's guard keeps every term a finite number, even for pressures
    and films no bearing sees (a NaN would reach the integrator's blow-up check)."""
    for value in (tr.ehl_traction_coefficient(s, p, h, lam, LAW), tr.ehl_traction_slope(s, p, h, lam, LAW),
                  tr.ehl_traction_per_slip(s * s, p, h, lam, LAW),
                  tr.ehl_tangent_curvature(s * s, p, h, lam, LAW)):
        assert math.isfinite(value)


@settings(max_examples=200, deadline=None)
@given(s=st.floats(0.0, 1e-100), p=st.floats(1e8, 1e11), h=st.floats(1e-12, 1e-6), lam=st.floats(0.0, 5.0))
def test_tangent_term_stays_finite_at_vanishing_slip(s, p, h, lam):
    """The film's curvature coefficient grows as 1/s; its tangent term, coefficient·s²,
    goes to 0 with s and never overflows."""
    c = tr.ehl_tangent_curvature(s * s, p, h, lam, LAW)
    assert math.isfinite(c) and math.isfinite(c * s * s)
    assert abs(c * s * s) <= tr.ehl_slope_at_zero_slip(p, h, lam, LAW) * (1 + 1e-9) + 1e-300


@pytest.mark.parametrize("lam", [0.5, 1.7, 4.0])
@pytest.mark.parametrize("s", [2e-4, 1e-3, 0.03, 0.3])
def test_slope_and_tangent_terms_against_finite_differences(s, lam):
    """dμ/ds by a central difference; μ/s and (μ' − μ/s)/s² from μ and μ' (the forms the
    IMEX tangent takes). Parameters put the film's shear in its bend (η s/(h τ_L) ≈ 1)."""
    law = tr.pack_ehl_traction_law(1e-3, 1e-9, gamma_l=0.07)
    p, h = 0.2e9, 1e-6
    step = 1e-6 * s
    fd = (tr.ehl_traction_coefficient(s + step, p, h, lam, law)
          - tr.ehl_traction_coefficient(s - step, p, h, lam, law)) / (2 * step)
    slope = tr.ehl_traction_slope(s, p, h, lam, law)
    assert slope == pytest.approx(fd, rel=1e-6, abs=1e-9)
    mu = tr.ehl_traction_coefficient(s, p, h, lam, law)
    assert tr.ehl_traction_per_slip(s * s, p, h, lam, law) == pytest.approx(mu / s, rel=1e-12)
    assert tr.ehl_tangent_curvature(s * s, p, h, lam, law) == pytest.approx((slope - mu / s) / s ** 2, rel=1e-8)


def test_per_slip_has_no_division_at_zero_slip():
    p, h = 0.3e9, 0.3e-6
    eta = barus(0.088, 2e-8, p)
    assert tr.ehl_traction_per_slip(0.0, p, h, 4.0, LAW) == pytest.approx(eta / (h * p), rel=1e-12)
    assert tr.ehl_traction_per_slip(0.0, p, h, 0.0, LAW) == pytest.approx(1.5 * 0.1 / 0.1, rel=1e-12)
    assert math.isfinite(tr.ehl_tangent_curvature(0.0, p, h, 2.0, LAW))


def test_pack_refuses_bad_parameters():
    with pytest.raises(ValueError, match="eta0"):
        tr.pack_ehl_traction_law(0.0, 2e-8)
    with pytest.raises(ValueError, match="lambda_b < lambda_f"):
        tr.pack_ehl_traction_law(0.1, 2e-8, lambda_b=3.0, lambda_f=1.0)
