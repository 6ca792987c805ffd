"""Palmgren's friction moment (rvcore.standards.palmgren) against a worked example computed
here from the source's formulas, and the regimes the formulas set.

Source (Harris & Kotzalas, *Rolling Bearing Analysis*, the chapter on friction; Palmgren
1959): ``M_l = f_1·F_β·d_m`` with ``f_1 = z·(P_0/C_0)^y`` and ``F_β``, ``M_v`` in N mm from
ν [mm²/s], n [rpm], d_m [mm].
"""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from rvcore.standards import palmgren as fm

ROOT = Path(__file__).resolve().parents[2]


def _study():
    from pipeline.schema.bearingfile import load_bearing

    return load_bearing(ROOT / "sweeps" / "bearings" / "rv-main-study.toml")


def test_study_bearing_worked_example():
    """The study bearing at 30 kN radial + 10 kN axial, 120 deg/s, ISO VG 68, grease.

    By hand, in the source's units: ISO 76 C_0 = f_0·Z·D_w²·cos α with f_0 interpolated
    between the 0.06 (15.9) and 0.07 (16.1) rows at γ = 23·cos 15°/351.5; P_0 = max(0.5·30 +
    0.46·10, 30) = 30 kN; f_1 = 0.001·(P_0/C_0)^0.33; F_β = 0.9·10 kN·cot 15° − 0.1·30 kN =
    30.59 kN (above F_r); M_l = f_1·F_β·d_m with d_m = 351.5 mm. 120 deg/s is 20 rpm, ν·n =
    68·20 = 1360 < 2000: M_v = 160·10⁻⁷·f_0·d_m³ with f_0 = 2 (angular contact, grease).
    The issue's estimate of M_l, about 4.5 N m, is reproduced.
    """
    cos15 = math.cos(math.radians(15.0))
    gamma = 23.0 * cos15 / 351.5
    c0 = (15.9 + (gamma - 0.06) / 0.01 * 0.2) * 51 * 23.0 ** 2 * cos15
    f1 = 0.001 * (30e3 / c0) ** 0.33
    f_beta = 0.9 * 10e3 / math.tan(math.radians(15.0)) - 0.1 * 30e3
    m_l = f1 * f_beta * 351.5 * 1e-3                    # N mm -> N m
    m_v = 160e-7 * 2.0 * 351.5 ** 3 * 1e-3
    assert f_beta > 30e3
    assert m_l == pytest.approx(4.5, abs=0.05)
    out = fm.friction_moment(_study(), 30e3, 10e3, math.radians(120.0))
    assert out["F_beta_N"] == pytest.approx(f_beta, rel=1e-12)
    assert out["load_moment_N_m"] == pytest.approx(m_l, rel=1e-9)
    assert out["viscous_moment_N_m"] == pytest.approx(m_v, rel=1e-9)
    assert out["friction_moment_N_m"] == pytest.approx(m_l + m_v, rel=1e-9)


def test_f_beta_is_never_less_than_the_radial_load():
    """Under a small axial load Palmgren's F_β is F_r; deep groove: 3F_a − 0.1F_r."""
    a15 = math.radians(15.0)
    assert fm.load_friction_force(30e3, 1e3, a15) == 30e3
    assert fm.load_friction_force(1e3, 10e3, 0.0) == pytest.approx(3 * 10e3 - 0.1 * 1e3)
    assert fm.load_friction_force(10e3, 1e3, 0.0) == 10e3


def test_viscous_term_rises_as_the_two_thirds_power_of_speed_and_the_load_term_does_not_move():
    """Above ν·n = 2000 the viscous moment goes as n^(2/3): eight times the speed, four
    times the moment; below it, constant. The load term does not depend on speed."""
    b = _study()
    nu = 68e-6
    rpm = lambda n: n * 2 * math.pi / 60  # noqa: E731
    fast = fm.friction_moment(b, 30e3, 10e3, rpm(400.0), kinematic_viscosity=nu)
    faster = fm.friction_moment(b, 30e3, 10e3, rpm(3200.0), kinematic_viscosity=nu)
    assert 68 * 400 > 2000
    assert faster["viscous_moment_N_m"] == pytest.approx(4 * fast["viscous_moment_N_m"], rel=1e-12)
    assert faster["load_moment_N_m"] == fast["load_moment_N_m"]
    slow = fm.friction_moment(b, 30e3, 10e3, rpm(5.0), kinematic_viscosity=nu)
    slower = fm.friction_moment(b, 30e3, 10e3, rpm(1.0), kinematic_viscosity=nu)
    assert slow["viscous_moment_N_m"] == slower["viscous_moment_N_m"]
    # the two branches nearly meet at ν·n = 2000: 2000^(2/3) = 158.7 against 160
    below = fm.viscous_friction_moment(nu, rpm(2000 / 68 * 0.999999), 0.35, 2.0)
    above = fm.viscous_friction_moment(nu, rpm(2000 / 68), 0.35, 2.0)
    assert above / below == pytest.approx(2000 ** (2 / 3) / 160, rel=1e-5)


def test_oil_bath_and_lubricant_from_the_bearing():
    """The bearing's lubricant is the default: grease, ISO VG 68 at the default 40 °C, so
    68 mm²/s; an oil bath's f_0 (3.3 for angular contact) raises the viscous term by 3.3/2."""
    b = _study()
    assert b.operating_viscosity == pytest.approx(68e-6) and b.lubricant.method == "grease"
    w = math.radians(660.0)
    grease = fm.friction_moment(b, 30e3, 10e3, w)
    bath = fm.friction_moment(b, 30e3, 10e3, w, lubrication="oil-bath")
    assert bath["viscous_moment_N_m"] == pytest.approx(3.3 / 2.0 * grease["viscous_moment_N_m"], rel=1e-12)


def test_the_viscous_term_takes_the_operating_viscosity():
    """Issue 40: M_v ∝ (ν·n)^(2/3), ν at the rings' operating temperature (both at 60 °C here:
    VG 68 thins), so the warm bearing's viscous term is the cold one's × (ν_60/ν_40)^(2/3)."""
    import dataclasses

    b = _study()
    warm = dataclasses.replace(b, inner_ring_temperature=333.15, outer_ring_temperature=333.15)
    assert warm.operating_viscosity < 0.6 * b.operating_viscosity     # VG 68: about 30 mm²/s at 60 °C
    w = math.radians(660.0)
    cold_mv = fm.friction_moment(b, 30e3, 10e3, w)["viscous_moment_N_m"]
    warm_mv = fm.friction_moment(warm, 30e3, 10e3, w)["viscous_moment_N_m"]
    ratio = (warm.operating_viscosity / b.operating_viscosity) ** (2.0 / 3.0)
    assert warm_mv == pytest.approx(ratio * cold_mv, rel=1e-12)


def test_bad_input_is_one_clear_error():
    with pytest.raises(fm.FrictionMomentError) as err:
        fm.viscous_friction_moment(-1e-6, 1.0, 0.35, 2.0)
    assert "\n" not in str(err.value) and "kinematic_viscosity" in str(err.value)
    with pytest.raises(fm.FrictionMomentError) as err:
        fm.viscous_friction_factor(0.2, "oil-splash")
    assert "\n" not in str(err.value) and "oil-splash" in str(err.value)


def test_palmgren_f1_takes_the_reduced_c0_of_open_grooves_and_says_which_row():
    """f1 = z (P0/C0)^y with ISO 76's C0: on the 6010 (grooves 0.625 D_w) that C0 is the
    reduced one, so f1 = z (P0/C0_reduced)^y, the deep-groove row z = 0.0005, y = 0.55
    (Harris & Kotzalas, the middle of 0.0004-0.0006), P0 = F_r under pure radial load."""
    from pipeline.schema.bearingfile import load_bearing
    from rvcore.standards.iso76 import static_safety_factor

    b = load_bearing(ROOT / "sweeps" / "bearings" / "deep-groove-6010.toml")
    c0 = static_safety_factor(b, 500.0, 0.0)["static_load_rating_N"]
    m = fm.friction_moment(b, 500.0, 0.0, 0.0)
    assert m["f1"] == pytest.approx(0.0005 * (500.0 / c0) ** 0.55, rel=1e-12)
    assert "deep-groove row" in m["basis"]
    study = fm.friction_moment(_study(), 30e3, 10e3, math.radians(660))
    assert "30-40 deg" in study["basis"]
    # the spread quoted beside the moment: KRW 5.2 and Koyo's top 10.1 N m against 7.8 N m
    assert study["friction_moment_N_m"] == pytest.approx(fm.PUBLISHED_SPREAD_OURS, abs=0.05)
    text = fm.published_spread_text()
    assert f"{round(100 * (5.2 / 7.8 - 1)):+d} %" in text and f"{round(100 * (10.1 / 7.8 - 1)):+d} %" in text
