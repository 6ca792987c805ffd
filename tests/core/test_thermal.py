"""The operating clearance (rvcore.bearing.thermal, issue 40): each part grows by its own
α_T·ΔT; the expectations are written here from the raceway and ball diameters, not read
from the code."""
from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from pipeline.schema import bearing_from_dict, read_toml
from rvcore.bearing.thermal import clearance_change, operating_bearing

ROOT = Path(__file__).resolve().parents[2]
FILE = "some/bearing.toml"
ALPHA = 11.5e-6     # bearing steel [1/K], the default


@pytest.fixture
def raw():
    """The buildable study bearing with a 40 µm radial clearance (at 20 °C)."""
    r = read_toml(ROOT / "sweeps" / "bearings" / "rv-main-buildable.toml")
    r["rows"][0]["radial_clearance"] = "40 um"
    return r


def at(raw, inner, outer, **extra):
    return bearing_from_dict({**raw, "temperature": {"inner_ring": inner, "outer_ring": outer, **extra}},
                             file=FILE)


def free_growth(pd, dm, d, ti, to, tref=20.0, a_ring=ALPHA, a_ball=ALPHA):
    """P_d' − P_d from the raceway diameters d_o = d_m + D + P_d/2 and d_i = d_m − D − P_d/2
    and the ball (at the rings' mean temperature), each grown by α·ΔT."""
    d_o, d_i = dm + d + pd / 2, dm - d - pd / 2
    tb = (ti + to) / 2
    return a_ring * (to - tref) * d_o - a_ring * (ti - tref) * d_i - 2 * a_ball * (tb - tref) * d


@pytest.mark.parametrize("ti, to", [(60.0, 40.0), (40.0, 60.0), (80.0, 55.0), (5.0, 20.0)])
def test_clearance_change_is_the_free_growth_of_rings_and_balls(raw, ti, to):
    b = at(raw, f"{ti} degC", f"{to} degC")
    row = b.rows[0]
    (pd,) = b.nominal_radial_clearances
    assert pd == pytest.approx(40e-6, rel=1e-12)
    want = free_growth(pd, row.pitch_diameter, row.ball_diameter, ti, to)
    assert row.radial_clearance - pd == pytest.approx(want, rel=1e-7, abs=1e-13)


def test_a_warmer_inner_ring_takes_up_clearance_about_alpha_dT_dm(raw):
    """The usual rule: ΔP_d ≈ −α·(T_i − T_o)·d_m for one steel (here within the ball and
    clearance terms' share, D/d_m ≈ 7 %)."""
    b = at(raw, "60 degC", "40 degC")
    dm = b.rows[0].pitch_diameter
    change = b.rows[0].radial_clearance - b.nominal_radial_clearances[0]
    assert change < 0.0
    assert change == pytest.approx(-ALPHA * 20.0 * dm, rel=0.1)


def test_one_material_at_one_temperature_scales_the_clearance(raw):
    """Free expansion of one body: every length, the clearance too, grows by 1 + α·ΔT."""
    b = at(raw, "70 degC", "70 degC")
    assert b.rows[0].radial_clearance == pytest.approx(b.nominal_radial_clearances[0] * (1 + ALPHA * 50.0),
                                                       rel=1e-12)


def test_ceramic_balls_at_one_temperature_open_the_clearance(raw):
    """Balls expanding less than the rings (silicon nitride, α ≈ 3.2e-6 1/K) leave more room:
    ΔP_d = α_r·ΔT·P_d + 2·D·(α_r − α_b)·ΔT."""
    steel = dict(raw.pop("material"))
    raw["ring_material"] = steel
    raw["ball_material"] = {**steel, "thermal_expansion": "3.2e-6 K^-1"}
    b = at(raw, "60 degC", "60 degC")
    d = b.rows[0].ball_diameter
    (pd,) = b.nominal_radial_clearances
    want = ALPHA * 40.0 * pd + 2 * d * (ALPHA - 3.2e-6) * 40.0
    assert b.rows[0].radial_clearance - pd == pytest.approx(want, rel=1e-9)


def test_rings_at_the_reference_leave_the_bearing_bit_for_bit(raw, monkeypatch):
    """Both rings at the reference temperature, rings and balls of different materials
    (so that any temperature would move the clearance): the bearing equals the one built
    with the thermal step taken out, and its statics are the same numbers, bit for bit."""
    from rvcore.bearing import thermal
    from rvcore.statics.equilibrium import solve_statics

    steel = dict(raw.pop("material"))
    raw["ring_material"] = steel
    raw["ball_material"] = {**steel, "thermal_expansion": "3.2e-6 K^-1"}
    ref = at(raw, "20 degC", "20 degC")
    monkeypatch.setattr(thermal, "operating_bearing", lambda bearing: bearing)
    nominal = at(raw, "20 degC", "20 degC")
    assert ref == nominal and ref.nominal_radial_clearances == ()
    assert clearance_change(40e-6, 0.35, 0.023, 293.15, 293.15, 293.15, ALPHA, 3.2e-6) == 0.0
    a = solve_statics(ref, 20e3, 5e3, stiffness=False)
    c = solve_statics(nominal, 20e3, 5e3, stiffness=False)
    assert (a.displacement == c.displacement).all() and (a.ball_loads == c.ball_loads).all()
    monkeypatch.undo()
    warm = at(raw, "20 degC", "21 degC")    # and one kelvin does move it
    assert warm.rows[0].radial_clearance != ref.rows[0].radial_clearance


def test_the_shipped_zero_clearance_steel_bearing_does_not_move_at_40_degC():
    """One steel, zero clearance, both rings at the default 40 °C: ΔP_d = α·ΔT·0 = 0 exactly,
    so the study's results stand (MODEL_VERSION kept)."""
    b = bearing_from_dict(read_toml(ROOT / "sweeps" / "bearings" / "rv-main-study.toml"), file=FILE)
    assert b.inner_ring_temperature == b.outer_ring_temperature == 313.15
    assert b.rows[0].radial_clearance == 0.0 and b.nominal_radial_clearances == ()


def test_operating_bearing_refuses_a_second_application(raw):
    b = at(raw, "60 degC", "40 degC")
    with pytest.raises(ValueError, match="already"):
        operating_bearing(b)


def test_a_pairs_preload_is_set_at_the_reference_and_rises_with_a_warmer_inner_ring():
    """The pair's ring offset is solved for its 3.5 kN at 20 °C and then held: at 20 °C both
    rings the preload is the asked 3.5 kN; an inner ring 10 K warmer than the outer takes up
    radial clearance (≈ α·10 K·d_i ≈ 38 µm here), so the same offset presses harder."""
    from rvcore.statics.preload import preload_force

    raw = read_toml(ROOT / "sweeps" / "bearings" / "rv-main-pair.toml")
    ref = bearing_from_dict({**raw, "temperature": {"inner_ring": "20 degC", "outer_ring": "20 degC"}}, file=FILE)
    warm = bearing_from_dict({**raw, "temperature": {"inner_ring": "50 degC", "outer_ring": "40 degC"}}, file=FILE)
    assert warm.preload_offset == ref.preload_offset
    assert preload_force(ref) == pytest.approx(ref.preload, rel=1e-3)
    assert warm.rows[0].radial_clearance < 0.0
    assert preload_force(warm) > 1.5 * preload_force(ref)
