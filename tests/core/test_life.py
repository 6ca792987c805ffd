"""Rating life: ISO 281 L10, ISO/TS 16281 L10r from the load distribution, the
catalogue load rating, and the duty-cycle life of a profile held at one point.

The standards' formulas are written out again here, from the standards, not imported
from rvcore.standards.iso16281: ISO 281:2007 eq. (1) with Table 1's b_m and the two Table 2 rows that
bracket the γ used, ISO/TS 16281:2008 eq. (19), (20), (25), (26), (29). The zero-clearance
deep-groove load distribution is Stribeck's, Q_j = Q_max·cos^1.5 ψ_j, from Hertz's law
and the ring's rigid radial shift alone.
"""
from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from rvcore.standards import iso281, iso16281 as life
from rvcore.statics.equilibrium import solve_statics

from .physics_cases import STUDY_D, STUDY_DM, constant_profile, section_bearing

ROOT = Path(__file__).resolve().parents[2]

# ISO 281:2007 Table 1 (b_m, radial ball bearings) and Table 2 (f_c, single-row radial
# contact column), the two rows around γ = 23/351.5 = 0.0654.
B_M = 1.3
FC_ROWS = ((0.06, 49.1), (0.07, 51.1))


def iso281_cr(z: int, d_mm: float, dm_mm: float) -> float:
    """ISO 281 eq. (1), α = 0, i = 1, D_w ≤ 25.4 mm [N]."""
    gamma = d_mm / dm_mm
    (g0, f0), (g1, f1) = FC_ROWS
    assert g0 <= gamma <= g1
    fc = f0 + (f1 - f0) * (gamma - g0) / (g1 - g0)
    return B_M * fc * z ** (2 / 3) * d_mm ** 1.8


def iso16281_qc(c: float, z: int, gamma: float, fi: float, fe: float):
    """ISO/TS 16281 eq. (19), (20), α = 0, i = 1 [N]."""
    k = 1.044 * ((1 - gamma) / (1 + gamma)) ** 1.72 * (fi * (2 * fe - 1) / (fe * (2 * fi - 1))) ** 0.41
    return (c / (0.407 * z) * (1 + k ** (10 / 3)) ** 0.3, c / (0.389 * z) * (1 + k ** (-10 / 3)) ** 0.3)


def stribeck_loads(z: int, radial_load: float) -> np.ndarray:
    """Ball loads of a deep-groove row at zero clearance under a pure radial load [N].

    The rigid ring shifts by δ_r along the load; ball j at ψ_j = 2πj/Z is squeezed by
    δ_r·cos ψ_j (α = 0), so Hertz gives Q_j ∝ cos^1.5 ψ_j where cos ψ_j > 0, and the
    radial balance Σ Q_j cos ψ_j = F_r fixes the scale.
    """
    c = np.cos(2 * np.pi * np.arange(z) / z)
    shape = np.where(c > 0, np.clip(c, 0, None) ** 1.5, 0.0)
    return radial_load * shape / np.sum(shape * c)


def test_deep_groove_zero_clearance_l10r_matches_iso281_l10():
    """ISO/TS 16281 L10r within 5 % of ISO 281's (C_r/P)^3, both from the
    standards' formulas here; and the code gives the same C_r, Q_c and L10r."""
    z, fr = 42, 30e3
    b = section_bearing(z, alpha=0.0)
    fi, fe = b.rows[0].inner_arcs[0].curvature_ratio, b.rows[0].outer_arcs[0].curvature_ratio
    # the standards, here
    c = iso281_cr(z, STUDY_D * 1e3, STUDY_DM * 1e3)
    l10 = (c / fr) ** 3                       # ISO 281 eq. (4): P_r = F_r under pure radial load
    q_ci, q_ce = iso16281_qc(c, z, STUDY_D / STUDY_DM, fi, fe)
    q = stribeck_loads(z, fr)
    q_ei = np.mean(q ** 3) ** (1 / 3)
    q_ee = np.mean(q ** (10 / 3)) ** 0.3
    l10r = ((q_ci / q_ei) ** (-10 / 3) + (q_ce / q_ee) ** (-10 / 3)) ** (-0.9)
    assert l10r == pytest.approx(l10, rel=0.05)

    # the code
    st = solve_statics(b, fr, 0.0, gravity=False, stiffness=False)
    out = life.static_life(b, st, fr, 0.0)
    assert out["dynamic_load_rating_N"] == pytest.approx(c, rel=1e-9)
    assert out["equivalent_load_N"] == pytest.approx(fr, rel=1e-12)
    assert out["basic_rating_life_L10_Mrev"] == pytest.approx(l10, rel=1e-9)
    assert (out["contact_load_rating_inner_N"], out["contact_load_rating_outer_N"]) == \
        pytest.approx((q_ci, q_ce), rel=1e-9)
    # the statics' load distribution is Stribeck's to within the ball's small lateral shift
    inner, outer = life.ring_ball_loads(b, st)
    np.testing.assert_allclose(inner[0], q, rtol=0.01, atol=0.01 * q.max())
    assert out["reference_rating_life_L10r_Mrev"] == pytest.approx(l10r, rel=0.01)
    assert out["reference_rating_life_L10r_Mrev"] == pytest.approx(l10, rel=0.05)


def test_catalogue_rating_scales_the_contact_ratings():
    """C_catalogue = 1.5 C_r(geometry) scales Q_ci, Q_ce by 1.5 and both lives by 1.5^3."""
    b = section_bearing(12, alpha=math.radians(30.0))
    st = solve_statics(b, 8e3, 6e3, gravity=False, stiffness=False)
    geo = life.static_life(b, st, 8e3, 6e3)
    cat = dataclasses.replace(b, dynamic_load_rating=1.5 * geo["dynamic_load_rating_N"])
    out = life.static_life(cat, st, 8e3, 6e3)
    assert out["dynamic_load_rating_N"] == pytest.approx(1.5 * geo["dynamic_load_rating_N"], rel=1e-12)
    assert out["contact_load_rating_inner_N"] == pytest.approx(1.5 * geo["contact_load_rating_inner_N"], rel=1e-12)
    assert out["contact_load_rating_outer_N"] == pytest.approx(1.5 * geo["contact_load_rating_outer_N"], rel=1e-12)
    for k in ("reference_rating_life_L10r_Mrev", "basic_rating_life_L10_Mrev"):
        assert out[k] == pytest.approx(1.5 ** 3 * geo[k], rel=1e-9)


def test_angular_contact_equivalent_load_uses_table3():
    """ISO 281 Table 3, α = 30°: single row X = 0.39, Y = 0.76 above e = 0.80; a
    back-to-back pair (double row) X = 1, Y = 0.78 below e and X = 0.63, Y = 1.24 above."""
    a, z, d = math.radians(30.0), 12, STUDY_D
    assert iso281.equivalent_dynamic_load(10e3, 10e3, a, z, d) == pytest.approx(0.39 * 10e3 + 0.76 * 10e3)
    assert iso281.equivalent_dynamic_load(10e3, 5e3, a, z, d) == pytest.approx(10e3)
    assert iso281.equivalent_dynamic_load(10e3, 5e3, a, z, d, double_row=True, rows=2) == \
        pytest.approx(10e3 + 0.78 * 5e3)
    assert iso281.equivalent_dynamic_load(10e3, 10e3, a, z, d, double_row=True, rows=2) == \
        pytest.approx(0.63 * 10e3 + 1.24 * 10e3)


def test_pair_is_rated_as_double_row():
    """ISO 281 5.1.2: a back-to-back pair is a double-row bearing, C_r = 2^0.7 × a row's."""
    from pipeline.schema.bearingfile import load_bearing

    pair = load_bearing(ROOT / "sweeps" / "bearings" / "rv-main-pair.toml")
    row = dataclasses.replace(pair, rows=pair.rows[:1], arrangement="", preload=0.0, preload_offset=0.0)
    assert life.geometry_load_rating(pair) == pytest.approx(2 ** 0.7 * life.geometry_load_rating(row), rel=1e-12)
    assert iso281.rating_geometry(pair)["double_row"]


def _hand_life_sums(b, st, revolutions):
    """The integrator's accumulation contract done by hand: per phase and
    row, dN·(1/Z)Σ Q_i^3 and dN·((1/Z)Σ Q_o^(10/3))^(9/10), from the statics' loads."""
    q = st.ball_loads
    inner_cols = st.arc_rings == 0
    q_in = (q * inner_cols).sum(axis=1)
    q_out = (q * ~inner_cols).sum(axis=1)
    n_rows = len(b.rows)
    a_i = np.array([np.mean(q_in[st.row_of_ball == r] ** 3) for r in range(n_rows)])
    a_o = np.array([np.mean(q_out[st.row_of_ball == r] ** (10 / 3)) ** 0.9 for r in range(n_rows)])
    revs = np.append(revolutions, np.sum(revolutions))
    return {"inner": revs[:, None] * a_i, "outer": revs[:, None] * a_o, "revolutions": revs}


@pytest.mark.parametrize("alpha_deg, fr, fa", [(0.0, 20e3, 0.0), (15.0, 15e3, 8e3)])
def test_duty_cycle_at_one_point_equals_static_l10r(alpha_deg, fr, fa):
    """A profile held at one constant operating point has the static L10r
    (here exactly, within 1 % asked); the damage splits over the phases as their revolutions."""
    b = section_bearing(12, alpha=math.radians(alpha_deg))
    st = solve_statics(b, fr, fa, gravity=False, stiffness=False)
    static = life.static_life(b, st, fr, fa)["reference_rating_life_L10r_Mrev"]
    revs = np.array([2.0, 30.0, 3.0])
    dc = life.duty_cycle_life(b, _hand_life_sums(b, st, revs))
    assert dc["rating_life_L10r_Mrev"] == pytest.approx(static, rel=0.01)
    assert dc["rating_life_L10r"] == pytest.approx(static * 1e6, rel=0.01)
    assert dc["rating_life_cycles"] == pytest.approx(static * 1e6 / revs.sum(), rel=0.01)
    # the cycle's damage is its revolutions over the static L10r, written here from the
    # contact ratings and the ball loads (ISO/TS 16281 eq. (25), (26), (29))
    q_ci, q_ce = life.bearing_contact_ratings(b)
    inner = (st.ball_loads * (st.arc_rings == 0)).sum(axis=1)
    outer = (st.ball_loads * (st.arc_rings != 0)).sum(axis=1)
    l_i = (q_ci / np.mean(inner ** 3) ** (1 / 3)) ** 3
    l_e = (q_ce / np.mean(outer ** (10 / 3)) ** 0.3) ** 3
    l10r_by_hand = (l_i ** (-10 / 9) + l_e ** (-10 / 9)) ** -0.9 * 1e6           # [rev]
    assert dc["fatigue_damage_cycle"] == pytest.approx(revs.sum() / l10r_by_hand, rel=1e-9)
    # Palmgren–Miner: twice the revolutions at the same loads, twice the damage
    twice = life.duty_cycle_life(b, _hand_life_sums(b, st, 2 * revs))
    assert twice["fatigue_damage_cycle"] == pytest.approx(2 * dc["fatigue_damage_cycle"], rel=1e-12)
    np.testing.assert_allclose(dc["fatigue_damage"], dc["fatigue_damage_cycle"] * revs / revs.sum(), rtol=1e-9)
    # the helper that builds the same sums agrees with the hand-built ones
    assert life.duty_cycle_life(b, life.life_sums_at(b, st, revs))["rating_life_L10r"] == \
        pytest.approx(dc["rating_life_L10r"], rel=1e-12)


def test_two_equal_rows_live_2_to_the_minus_0_9_times_one():
    """Rows in series (Weibull, e = 10/9): two equally loaded rows last 2^(-9/10) of one."""
    b = section_bearing(12, alpha=math.radians(15.0))
    two = dataclasses.replace(b, rows=b.rows * 2)
    one = {"inner": np.array([[4e12], [4e12]]), "outer": np.array([[3e12], [3e12]]),
           "revolutions": np.array([10.0, 10.0])}
    both = {k: (np.repeat(v, 2, axis=1) if v.ndim == 2 else v) for k, v in one.items()}
    l1 = life.duty_cycle_life(b, one)["rating_life_L10r"]
    l2 = life.duty_cycle_life(two, both)["rating_life_L10r"]
    assert l2 == pytest.approx(l1 * 2 ** (-0.9), rel=1e-12)


def test_no_rotation_no_load_no_damage():
    b = section_bearing(12)
    zero = {"inner": np.zeros((3, 1)), "outer": np.zeros((3, 1)), "revolutions": np.zeros(3)}
    dc = life.duty_cycle_life(b, zero)
    assert dc["rating_life_cycles"] == math.inf and dc["fatigue_damage_cycle"] == 0.0
    np.testing.assert_array_equal(dc["fatigue_damage"], 0.0)


def test_steady_outputs_carry_the_lives_in_revolutions():
    from rvcore.statics.operating import steady_outputs, steady_statics
    from rvcore.output_table import OUTPUT
    from rvcore.profile import OperatingPoint

    b = section_bearing(12)
    profile = constant_profile(0.01, 0.03)
    op = OperatingPoint(speed=1.0, radial_load=10e3, axial_load=4e3)
    out = steady_outputs(b, profile, op, gravity=False)
    st = steady_statics(b, profile, op, gravity=False)
    ref = life.static_life(b, st)
    assert out["reference_rating_life_L10r"] == pytest.approx(ref["reference_rating_life_L10r_Mrev"] * 1e6)
    assert out["basic_rating_life_L10"] == pytest.approx(ref["basic_rating_life_L10_Mrev"] * 1e6)
    for k in ("basic_rating_life_L10", "reference_rating_life_L10r"):
        units, long_name = OUTPUT[k].units, OUTPUT[k].long_name
        assert units == "1" and "revolutions" in long_name


def test_bad_input():
    from pipeline.errors import ConfigError
    from pipeline.schema.bearingfile import bearing_from_dict
    from pipeline.schema.tomlfile import read_toml

    raw = read_toml(ROOT / "sweeps" / "bearings" / "deep-groove-example.toml")
    raw["dynamic_load_rating"] = "-23.4 kN"
    with pytest.raises(ConfigError, match=r"x\.toml: dynamic_load_rating = '-23.4 kN': must be positive"):
        bearing_from_dict(raw, file="x.toml")
    raw["dynamic_load_rating"] = "23.4 kN"
    assert bearing_from_dict(raw, file="x.toml").dynamic_load_rating == pytest.approx(23.4e3)
    b = section_bearing(12)
    with pytest.raises(ValueError, match="life_sums has 2 rows, the bearing 1"):
        life.duty_cycle_life(b, {"inner": np.ones((3, 2)), "outer": np.ones((3, 2)), "revolutions": np.ones(3)})
    with pytest.raises(ValueError, match="n_phases"):
        life.duty_cycle_life(b, {"inner": np.ones((3, 1)), "outer": np.ones((2, 1)), "revolutions": np.ones(3)})
    with pytest.raises(ValueError, match="negative"):
        life.duty_cycle_life(b, {"inner": -np.ones((2, 1)), "outer": np.ones((2, 1)), "revolutions": np.ones(2)})
    with pytest.raises(life.LifeError, match="Table 2"):
        iso281.fc_factor(0.5)
    # Table 3 rows for 5 and 10 deg are not carried: L10 is not rated, L10r still is
    b10 = section_bearing(12, alpha=math.radians(10.0))
    st = solve_statics(b10, 10e3, 3e3, gravity=False, stiffness=False)
    out = life.static_life(b10, st)
    assert math.isnan(out["basic_rating_life_L10_Mrev"]) and math.isfinite(out["reference_rating_life_L10r_Mrev"])


def test_statics_json_has_the_lives(capsys):
    from pipeline.cli import main

    bearing = str(ROOT / "sweeps" / "bearings" / "deep-groove-example.toml")
    assert main(["statics", "--json", "--bearing", bearing, "--radial-load", "30kN", "--no-gravity"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["reference_rating_life_L10r_Mrev"] == pytest.approx(out["basic_rating_life_L10_Mrev"], rel=0.05)
    assert out["dynamic_load_rating_N"] == pytest.approx(iso281_cr(42, 23.0, 351.5), rel=1e-9)
    assert main(["statics", "--json", "--bearing", bearing, "--radial-load", "30kN", "--no-gravity",
                 "--set", "bearing.dynamic_load_rating=300 kN"]) == 0
    cat = json.loads(capsys.readouterr().out)
    assert cat["dynamic_load_rating_N"] == 300e3
    ratio = (300e3 / out["dynamic_load_rating_N"]) ** 3
    assert cat["reference_rating_life_L10r_Mrev"] == pytest.approx(ratio * out["reference_rating_life_L10r_Mrev"])


def _has_life_sums() -> bool:
    import dataclasses as dc

    from rvcore.recording.results import CaseResult
    return any(f.name == "life_sums" for f in dc.fields(CaseResult))


@pytest.mark.skipif(not _has_life_sums(), reason="the integrator's life accumulation "
                                                 "is not in rvcore.simulation.run yet")
def test_dynamic_constant_point_life_equals_static_l10r():
    """A reduced case rolling at constant speed under constant loads; the life of
    its steady phase (a profile held there) equals the static L10r there within 1 %.

    The integrator accumulates dN·Q_e^3 with the balls' dynamic loads at every step, while
    they roll through the load zone; the statics see one ball position.
    """
    from rvcore.simulation.run import run_case
    from rvcore.simulation.settings import SolverSettings
    from rvcore.profile import OperatingPoint

    z, fr, fa, omega = 12, 12e3, 6e3, 2.0 * math.pi   # one revolution a second
    b = section_bearing(z, alpha=math.radians(15.0))
    phases = (("startup", 0.0, 0.06), ("steady", 0.06, 0.16), ("deceleration", 0.16, 0.17))
    res = run_case(b, constant_profile(0.01, 0.17, phases=phases), OperatingPoint(omega, fr, fa),
                   SolverSettings(output_rate=2e3, gravity=False))
    sums = res.life_sums
    steady = {k: np.asarray(v)[[1, 1]] for k, v in sums.items()}   # the steady phase as a whole cycle
    assert steady["revolutions"][0] == pytest.approx(omega * 0.10 / (2 * math.pi), rel=1e-6)
    dyn = life.duty_cycle_life(b, steady)["rating_life_L10r_Mrev"]
    static = life.static_life(b, solve_statics(b, fr, fa, gravity=False, stiffness=False))
    static = static["reference_rating_life_L10r_Mrev"]
    assert dyn == pytest.approx(static, rel=0.01)
    # and the case's own cycle scalars are this module's
    assert res.life["rating_life_cycles"] == pytest.approx(
        life.duty_cycle_life(b, sums)["rating_life_cycles"], rel=1e-12)


#: ISO 281:2007 Table 3, angular contact groove ball bearings, α = 15° (the study bearing's
#: row), typed from the standard: i·f_0·F_a/C_0r, e, single row Y (F_a/F_r > e, X = 0.44),
#: double row Y for F_a/F_r ≤ e (X = 1) and for F_a/F_r > e (X = 0.72).
ISO281_TABLE3_15DEG = [
    (0.178, 0.38, 1.47, 1.65, 2.39), (0.357, 0.40, 1.40, 1.57, 2.28), (0.714, 0.43, 1.30, 1.46, 2.11),
    (1.07, 0.46, 1.23, 1.38, 2.00), (1.43, 0.47, 1.19, 1.34, 1.93), (2.14, 0.50, 1.12, 1.26, 1.82),
    (3.57, 0.55, 1.02, 1.14, 1.66), (5.35, 0.56, 1.00, 1.12, 1.63), (7.14, 0.56, 1.00, 1.12, 1.63)]


@pytest.mark.parametrize("rel, e, y1, y2_low, y2_high", ISO281_TABLE3_15DEG)
def test_table3_15_degree_row_of_the_study_bearing(rel, e, y1, y2_low, y2_high):
    """ISO 281 Table 3 at α = 15° for the study bearing (Z = 51, D_w = 23 mm). With ISO 76's
    C_0r = f_0·i·Z·D_w²·cos α the relative axial load i·f_0·F_a/C_0r is F_a/(Z·D_w²·cos α)
    [N, mm], so the axial load of each row of the table is set here from that; F_r puts
    F_a/F_r at twice e (above) and half e (below)."""
    a, z, d = math.radians(15.0), 51, 0.023
    fa = rel * z * 23.0 ** 2 * math.cos(a)
    above, below = fa / (2 * e), fa / (0.5 * e)
    for got, want in ((iso281.xy_factors(above, fa, a, z, d), (0.44, y1, e)),
                      (iso281.xy_factors(below, fa, a, z, d), (1.0, 0.0, e)),
                      (iso281.xy_factors(above, fa, a, z, d, double_row=True, rows=2), (0.72, y2_high, e)),
                      (iso281.xy_factors(below, fa, a, z, d, double_row=True, rows=2), (1.0, y2_low, e))):
        assert got == pytest.approx(want, abs=1e-9)


def test_table3_15_degree_interpolates_between_rows():
    """Halfway between the 1.07 and 1.43 rows: e = 0.465, single-row Y = 1.21 (linear, as
    ISO 281 allows)."""
    a, z = math.radians(15.0), 51
    fa = (1.07 + 1.43) / 2 * z * 23.0 ** 2 * math.cos(a)
    assert iso281.xy_factors(fa, fa, a, z, 0.023) == pytest.approx((0.44, 1.21, 0.465), abs=1e-9)


# --------------------------------------------------------------------------- open grooves (issue 39)


def _bearing_6010():
    from pipeline.schema.bearingfile import load_bearing

    return load_bearing(ROOT / "sweeps" / "bearings" / "deep-groove-6010.toml")


def test_open_grooves_refuse_iso281_cr_l10_and_l10r_with_one_line():
    """ISO 281 Table 2's f_c holds for r_i <= 0.52 D_w, r_e <= 0.53 D_w; the 6010 file has
    0.625 on both rings. The reduced f_c of ISO/TR 1281-1 is not implemented, so C_r, L10
    and L10r (ISO/TS 16281 splits the same C_r) are refused: one line naming the radii."""
    b = _bearing_6010()
    with pytest.raises(iso281.LifeError) as err:
        life.geometry_load_rating(b)
    text = str(err.value)
    assert "\n" not in text and "0.625" in text and "0.52/0.53" in text
    assert life.dynamic_rating_basis(b) == text
    st = solve_statics(b, 500.0, 0.0, gravity=False, tilt="held")
    with pytest.raises(iso281.LifeError):
        life.static_life(b, st)
    # the duty cycle: NaN lives and damages, never a number from a table that does not hold
    sums = life.life_sums_at(b, st, [10.0, 20.0])
    out = life.duty_cycle_life(b, sums)
    assert math.isnan(out["rating_life_L10r"]) and math.isnan(out["fatigue_damage_cycle"])
    assert np.isnan(out["fatigue_damage"]).all() and out["fatigue_damage"].shape == (2,)
    assert len(life.rating_caveats(b)) == 2


def test_a_makers_cr_rates_the_open_groove_bearing():
    """With the maker's C_r in the bearing file the lives use it (ISO 281's table is not
    needed): L10 = (C_r/P_r)^3 with P_r = F_r under pure radial load (ISO 281 Table 3,
    F_a = 0)."""
    b = dataclasses.replace(_bearing_6010(), dynamic_load_rating=16.8e3)
    st = solve_statics(b, 2000.0, 0.0, gravity=False, tilt="held")
    out = life.static_life(b, st, 2000.0, 0.0)
    assert out["basic_rating_life_L10_Mrev"] == pytest.approx((16.8e3 / 2000.0) ** 3, rel=1e-12)
    assert math.isfinite(out["reference_rating_life_L10r_Mrev"])
    assert "maker" in life.dynamic_rating_basis(b)
    assert len(life.rating_caveats(b)) == 1          # only ISO 76's reduced f0 remains to say
