"""The bearing file's ``[lubricant]`` and ``[temperature]`` tables: the defaults, the
operating viscosity (ASTM D341 / Walther, computed here), the one-line errors, and case ids.

The expectations are computed here from the published relations (ISO 3448's grade
midpoint, ASTM D341's line through two points, ASTM D2270's viscosity index, ISO 281
Table 13), not read from the code's output.
"""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from pipeline.schema import bearing_from_dict, read_sweep_file, read_toml
from pipeline.schema.fields import field
from pipeline.schema.stored import stored_configuration
from rvcore.bearing.lubricant import contact_lubricant, contamination_of, operating_viscosity

from .test_config import expect_error
from .test_sweepfile import GRID, make_sweep

ROOT = Path(__file__).resolve().parents[2]
FILE = "some/bearing.toml"


@pytest.fixture
def buildable_raw():
    return read_toml(ROOT / "sweeps" / "bearings" / "rv-main-buildable.toml")


def with_lubricant(raw: dict, **table) -> dict:
    """``raw`` with a ``[lubricant]`` table (the shipped files leave it out)."""
    return {**raw, "lubricant": dict(table)}


def with_temperature(raw: dict, **table) -> dict:
    return {**raw, "temperature": dict(table)}


def walther(t_kelvin, nu40_mm2s, nu100_mm2s):
    """ASTM D341's simple form through (313.15 K, ν40) and (373.15 K, ν100), in mm²/s."""
    def ll(nu):
        return math.log10(math.log10(nu + 0.7))
    b = (ll(nu40_mm2s) - ll(nu100_mm2s)) / (math.log10(373.15) - math.log10(313.15))
    a = ll(nu40_mm2s) + b * math.log10(313.15)
    return 10 ** (10 ** (a - b * math.log10(t_kelvin))) - 0.7


def test_default_is_iso_vg_68_grease_at_40_degC(buildable_raw):
    """ISO VG 68 (ν40 = 68 mm²/s by ISO 3448's definition of the grade), both rings at
    40 °C: the operating viscosity is the grade's own 68 mm²/s, exactly."""
    b = bearing_from_dict(buildable_raw, file=FILE)
    assert b.lubricant.grade == 68 and b.lubricant.method == "grease"
    assert b.lubricant.kinematic_viscosity is None          # no override
    assert b.inner_ring_temperature == b.outer_ring_temperature == 313.15
    assert operating_viscosity(b) == 68e-6
    assert "assumption" in field("bearing", "lubricant.grade").doc


def test_the_default_vg68_nu100_is_viscosity_index_94():
    """ASTM D2270: VI = (L − U)/(L − H)·100 with the standard's L = 111.5 and H = 65.32
    mm²/s at ν100 = 8.5 mm²/s (its table) and U = ν40 = 68 mm²/s."""
    from rvcore.bearing.lubricant import VG68_VISCOSITY_100

    assert VG68_VISCOSITY_100 == pytest.approx(8.5e-6, rel=1e-12)
    vi = (111.5 - 68.0) / (111.5 - 65.32) * 100.0
    assert 93.5 < vi < 95.0


@pytest.mark.parametrize("t_c", [20.0, 60.0, 80.0])
def test_operating_viscosity_follows_walther_at_the_mean_ring_temperature(buildable_raw, t_c):
    raw = with_lubricant(buildable_raw, viscosity_40="100 mm^2/s", viscosity_100="11 mm^2/s")
    raw = with_temperature(raw, inner_ring=f"{t_c + 4} degC", outer_ring=f"{t_c - 4} degC")
    b = bearing_from_dict(raw, file=FILE)
    assert operating_viscosity(b) == pytest.approx(walther(t_c + 273.15, 100.0, 11.0) * 1e-6, rel=1e-9)


def test_the_operating_viscosity_falls_as_the_oil_warms(buildable_raw):
    nus = [operating_viscosity(bearing_from_dict(with_temperature(buildable_raw, inner_ring=f"{t} degC",
                                                                  outer_ring=f"{t} degC"), file=FILE))
           for t in (20, 40, 60, 80)]
    assert all(a > b for a, b in zip(nus, nus[1:]))
    assert nus[1] == 68e-6


def test_kinematic_viscosity_is_an_override_at_the_operating_temperature(buildable_raw):
    raw = with_temperature(with_lubricant(buildable_raw, kinematic_viscosity="150 mm^2/s"),
                           inner_ring="70 degC", outer_ring="60 degC")
    assert operating_viscosity(bearing_from_dict(raw, file=FILE)) == pytest.approx(150e-6, rel=1e-12)


def test_contact_lubricant_is_rho_nu_alpha_and_the_composite_roughness(buildable_raw):
    raw = with_lubricant(buildable_raw, grade=68, density="870 kg/m^3", pressure_viscosity="25 GPa^-1",
                         ball_roughness="0.05 um", raceway_roughness="0.12 um")
    eta0, alpha, sigma = contact_lubricant(bearing_from_dict(raw, file=FILE))
    assert eta0 == pytest.approx(870.0 * 68e-6, rel=1e-12)
    assert alpha == pytest.approx(25e-9, rel=1e-12)
    assert sigma == pytest.approx(math.sqrt(0.05 ** 2 + 0.12 ** 2) * 1e-6, rel=1e-12)


@pytest.mark.parametrize("level, expected", [("typical contamination", 0.2), ("high cleanliness", 0.8),
                                             (0.35, 0.35)])
def test_contamination_by_level_or_number(buildable_raw, level, expected):
    """ISO 281:2007 Table 13, d_m ≥ 100 mm column, lower bounds: typical contamination
    0.4–0.2, high cleanliness 0.9–0.8; the default "normal cleanliness" 0.8–0.6."""
    b = bearing_from_dict(with_lubricant(buildable_raw, contamination=level), file=FILE)
    assert contamination_of(b) == pytest.approx(expected)
    assert contamination_of(bearing_from_dict(buildable_raw, file=FILE)) == pytest.approx(0.6)


@pytest.mark.parametrize("value", ["-68 mm^2/s", "0 mm^2/s"])
def test_non_positive_viscosity_is_one_line(buildable_raw, value):
    raw = with_lubricant(buildable_raw, kinematic_viscosity=value)
    expect_error(bearing_from_dict, raw, "lubricant.kinematic_viscosity", value, ["must be positive"])


def test_viscosity_in_wrong_units_is_one_line(buildable_raw):
    raw = with_lubricant(buildable_raw, kinematic_viscosity="68 Pa s")
    expect_error(bearing_from_dict, raw, "lubricant.kinematic_viscosity", "68 Pa s", ["wrong units"])


def test_unknown_method_is_one_line(buildable_raw):
    raw = with_lubricant(buildable_raw, method="oil-splash")
    expect_error(bearing_from_dict, raw, "lubricant.method", "oil-splash", ["must be one of"])


@pytest.mark.parametrize("table, key, value, words", [
    ({"grade": 70}, "lubricant.grade", 70, ["ISO 3448 grade"]),
    ({"grade": 68, "viscosity_40": "68 mm^2/s", "viscosity_100": "8 mm^2/s"}, "lubricant.viscosity_40",
     "68 mm^2/s", ["either grade", "not both"]),
    ({"viscosity_40": "100 mm^2/s"}, "lubricant.viscosity_40", "100 mm^2/s", ["needs viscosity_100"]),
    ({"grade": 220}, "lubricant.grade", 220, ["needs viscosity_100"]),
    ({"viscosity_40": "10 mm^2/s", "viscosity_100": "12 mm^2/s"}, "lubricant.viscosity_100", "12 mm^2/s",
     ["must exceed"]),
    ({"grade": 68, "viscosity_100": "1.5 mm^2/s"}, "lubricant.viscosity_100", "1.5 mm^2/s", ["ASTM D341"]),
    ({"contamination": "dirty"}, "lubricant.contamination", "dirty", ["normal cleanliness"]),
    ({"contamination": 1.5}, "lubricant.contamination", 1.5, ["[0, 1]"]),
    ({"pressure_viscosity": "-20 GPa^-1"}, "lubricant.pressure_viscosity", "-20 GPa^-1", ["must be positive"]),
    ({"ball_roughness": "-0.1 um"}, "lubricant.ball_roughness", "-0.1 um", ["must not be negative"]),
    ({"ep_additives": "yes"}, "lubricant.ep_additives", "yes", ["true or false"]),
])
def test_bad_lubricant_inputs_are_one_line(buildable_raw, table, key, value, words):
    expect_error(bearing_from_dict, with_lubricant(buildable_raw, **table), key, value, words)


@pytest.mark.parametrize("table, key, value, words", [
    ({"inner_ring": 40}, "temperature.inner_ring", 40, ["-50 and 200 degC", "kelvin"]),
    ({"outer_ring": "40 degF"}, "temperature.outer_ring", "40 degF", ["not a temperature"]),
    ({"reference": "20 m"}, "temperature.reference", "20 m", ["not a temperature"]),
    ({"inner_ring": "150 degC", "outer_ring": "150 degC"}, "temperature.inner_ring", "150 degC",
     ["ASTM D341"]),
])
def test_bad_temperatures_are_one_line(buildable_raw, table, key, value, words):
    """A plain number is kelvin (SI) and 40 K is refused; an ISO VG 22 oil (ν100 4.2 mm²/s)
    at 150 °C falls below the 2 mm²/s where ASTM D341's simple form holds (by the line
    through its two points, ≈ 1.96 mm²/s): said at load, before any work."""
    raw = with_lubricant(buildable_raw, viscosity_40="22 mm^2/s", viscosity_100="4.2 mm^2/s")
    assert walther(423.15, 22.0, 4.2) < 2.0
    expect_error(bearing_from_dict, with_temperature(raw, **table), key, value, words)


def test_the_default_lubricant_keeps_case_ids_and_another_changes_them(tmp_path):
    """Written out at its default the table gives the same ids as leaving it out; another
    oil gives other ids; the stored configuration reads the lubricant back."""
    plain = read_sweep_file(make_sweep(tmp_path, GRID, "a.toml"))
    same = read_sweep_file(make_sweep(tmp_path, GRID + '"lubricant.grade" = 68\n', "b.toml"))
    other = read_sweep_file(make_sweep(tmp_path, GRID + '"lubricant.kinematic_viscosity" = "100 mm^2/s"\n',
                                       "c.toml"))
    warm = read_sweep_file(make_sweep(tmp_path, GRID + '"temperature.inner_ring" = "60 degC"\n', "d.toml"))
    ids = [c.case_id for c in plain.cases]
    assert [c.case_id for c in same.cases] == ids
    assert not set(c.case_id for c in other.cases) & set(ids)
    assert not set(c.case_id for c in warm.cases) & set(ids)
    assert stored_configuration(other.configuration).bearing.lubricant.kinematic_viscosity == pytest.approx(1e-4)
    back = stored_configuration(plain.configuration).bearing
    assert back.lubricant.viscosity_40 == pytest.approx(68e-6) and back.lubricant.kinematic_viscosity is None
    assert stored_configuration(warm.configuration).bearing.inner_ring_temperature == pytest.approx(333.15)


def test_unknown_lubricant_key_is_one_line(buildable_raw):
    assert "lubricant" not in buildable_raw      # the table is optional: the default loads
    expect_error(bearing_from_dict, with_lubricant(buildable_raw, viscosity="68 mm^2/s"), "lubricant.viscosity",
                 None, ["unknown key"])


def test_a_ring_temperature_is_a_sweep_axis_in_kelvin(tmp_path):
    """``"temperature.inner_ring" = ["40 degC", "60 degC"]``: a numeric axis in K (40 °C is
    313.15 K by the kelvin's definition), one bearing per value."""
    body = GRID.replace('[fixed]', '"temperature.inner_ring" = ["40 degC", "60 degC"]\n\n[fixed]')
    sweep = read_sweep_file(make_sweep(tmp_path, body))
    axis = next(a for a in sweep.axes if a.key == "temperature.inner_ring")
    assert axis.kind == "temperature" and axis.units == "K"
    assert axis.coords == pytest.approx((313.15, 333.15))
    assert sorted({c.bearing.inner_ring_temperature for c in sweep.cases}) == pytest.approx([313.15, 333.15])
