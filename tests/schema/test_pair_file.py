"""Bearing files with a ``[pair]``: two mirrored rows from one row design, their preload,
the errors of an impossible pair, negative clearance, and the preload on a sweep axis."""
from __future__ import annotations

import copy
import math
from pathlib import Path

import pytest

from pipeline.errors import ConfigError
from pipeline.schema import apply_override, bearing_from_dict, read_sweep_file, read_toml
from pipeline.schema.tomlfile import lookup

ROOT = Path(__file__).resolve().parents[2]
PAIR = ROOT / "sweeps" / "bearings" / "rv-main-pair.toml"
BUILDABLE = ROOT / "sweeps" / "bearings" / "rv-main-buildable.toml"
FILE = "some/pair.toml"


@pytest.fixture(scope="module")
def pair_file_raw():
    return read_toml(PAIR)


@pytest.fixture
def raw(pair_file_raw):
    """The shipped pair without its preload (fast to load: no offset to solve for)."""
    r = copy.deepcopy(pair_file_raw)
    del r["pair"]["preload"]
    return r


def pressure_centre(row) -> float:
    """Where the row's line of contact meets the bearing axis [m].

    The line runs through the centred ball (r = d_m/2, z = z_row) along the contact
    direction (cos α, sin α) of rvcore.bearing.geometry's convention; it reaches r = 0 after
    travelling d_m/2 / cos α back along it, i.e. at z_row − (d_m/2)·tan α.
    """
    alpha = row.outer_arcs[0].contact_angle
    assert row.inner_arcs[0].contact_angle == alpha   # one load line
    return row.axial_position - row.pitch_diameter / 2 * math.tan(alpha)


def with_pair(raw, **values):
    r = copy.deepcopy(raw)
    r["pair"].update(values)
    return r


def expect_error(raw, key, words=()):
    with pytest.raises(ConfigError) as info:
        bearing_from_dict(raw, file=FILE)
    err = info.value
    assert err.file == FILE and err.key == key, str(err)
    for w in words:
        assert w in err.reason, str(err)
    assert "\n" not in str(err)
    return err


# --------------------------------------------------------------------------- the rows


def test_pair_gives_two_rows_at_plus_minus_half_spacing(raw):
    b = bearing_from_dict(raw, file=FILE)
    spacing = 30e-3   # the file's pair.row_spacing
    assert len(b.rows) == 2
    assert sorted(r.axial_position for r in b.rows) == pytest.approx([-spacing / 2, spacing / 2], abs=1e-15)
    assert b.arrangement == "back-to-back"
    # both rows are the file's one design, contact angles mirrored
    a = [r.nominal_contact_angle for r in b.rows]
    assert abs(a[0]) == pytest.approx(math.radians(30)) and a[1] == pytest.approx(-a[0])
    for r in b.rows:
        assert r.ball_count == 42 and r.ball_diameter == pytest.approx(23e-3)
        assert r.inner_offset == 0.0   # no preload asked for in this copy


def test_back_to_back_lines_of_contact_meet_the_axis_outside_the_rows(raw):
    b = bearing_from_dict(raw, file=FILE)
    lo, hi = sorted(b.rows, key=lambda r: r.axial_position)
    # O arrangement: each row's pressure centre lies beyond the row, away from the other
    assert pressure_centre(lo) < lo.axial_position
    assert pressure_centre(hi) > hi.axial_position
    spread = pressure_centre(hi) - pressure_centre(lo)
    dm, s, alpha = 351.5e-3, 30e-3, math.radians(30)
    assert spread == pytest.approx(s + dm * math.tan(alpha), rel=1e-12)


def test_face_to_face_lines_of_contact_meet_the_axis_between_the_rows(raw):
    b = bearing_from_dict(with_pair(raw, arrangement="face-to-face"), file=FILE)
    lo, hi = sorted(b.rows, key=lambda r: r.axial_position)
    assert pressure_centre(lo) > lo.axial_position
    assert pressure_centre(hi) < hi.axial_position
    assert pressure_centre(hi) - pressure_centre(lo) < hi.axial_position - lo.axial_position


def test_tandem_rows_share_one_contact_angle(raw):
    b = bearing_from_dict(with_pair(raw, arrangement="tandem"), file=FILE)
    assert b.rows[0].nominal_contact_angle == b.rows[1].nominal_contact_angle


def test_shipped_pair_is_preloaded_by_an_offset_that_presses_the_rows_together(pair_file_raw):
    b = bearing_from_dict(pair_file_raw, file=str(PAIR))
    assert b.preload == pytest.approx(3.5e3)
    assert b.preload_offset > 0
    # each row's inner raceway moves towards the side its contact angle loads it from:
    # an outer arc at α touches along (cos α, sin α), so the inner raceway of a row at α
    # must move along +sign(α)·z to close the contact; the offsets are equal and opposite
    for r in b.rows:
        assert r.inner_offset * r.nominal_contact_angle > 0
    assert b.rows[0].inner_offset == pytest.approx(-b.rows[1].inner_offset)
    assert abs(b.rows[0].inner_offset - b.rows[1].inner_offset) == pytest.approx(b.preload_offset)


def test_preload_offset_given_directly(raw):
    b = bearing_from_dict(with_pair(raw, preload_offset="10 um"), file=FILE)
    assert b.preload_offset == pytest.approx(10e-6)
    assert b.preload == 0.0
    assert abs(b.rows[0].inner_offset - b.rows[1].inner_offset) == pytest.approx(10e-6)


# --------------------------------------------------------------------------- errors


def test_both_preload_and_offset(raw):
    expect_error(with_pair(raw, preload="3 kN", preload_offset="10 um"), "pair.preload_offset",
                 ["either preload", "not both"])


def test_tandem_cannot_be_preloaded(raw):
    expect_error(with_pair(raw, arrangement="tandem", preload="3 kN"), "pair.preload", ["tandem"])
    expect_error(with_pair(raw, arrangement="tandem", preload_offset="5 um"), "pair.preload_offset",
                 ["tandem"])


def test_negative_preload(raw):
    expect_error(with_pair(raw, preload="-1 kN"), "pair.preload", ["negative"])


def test_unknown_arrangement(raw):
    expect_error(with_pair(raw, arrangement="sideways"), "pair.arrangement", ["back-to-back"])


def test_pair_with_two_rows(raw):
    r = copy.deepcopy(raw)
    r["rows"].append(copy.deepcopy(r["rows"][0]))
    expect_error(r, "rows", ["exactly one"])


def test_pair_row_with_an_axial_position(raw):
    r = copy.deepcopy(raw)
    r["rows"][0]["axial_position"] = "5 mm"
    expect_error(r, "rows[0].axial_position", ["row_spacing"])


def test_deep_groove_row_in_a_pair(raw):
    r = apply_override(raw, "rows[0].inner_groove.arcs[0].contact_angle", "0 deg")
    r = apply_override(r, "rows[0].outer_groove.arcs[0].contact_angle", "0 deg")
    expect_error(r, "rows[0].outer_groove.arcs[0].contact_angle", ["deep-groove", "angular-contact"])


def test_rows_closer_than_a_ball_overlap(raw):
    expect_error(with_pair(raw, row_spacing="20 mm"), "pair.row_spacing", ["ball diameter"])


def test_rows_closer_than_a_cage_width(raw):
    expect_error(with_pair(raw, row_spacing="25 mm"), "pair.row_spacing", ["cage"])


def test_rows_wider_than_the_envelope(raw):
    # 40 mm spacing + the 28 mm cage = 68 mm > the 60 mm width
    err = expect_error(with_pair(raw, row_spacing="40 mm"), "pair.row_spacing", ["envelope width"])
    assert "68 mm" in err.reason and "60 mm" in err.reason


def test_spacing_must_be_positive(raw):
    expect_error(with_pair(raw, row_spacing="0 mm"), "pair.row_spacing", ["positive"])


def test_problem_of_the_mirrored_row_names_the_files_row(raw):
    # the second row is built, not written: its problems are reported at rows[0]
    r = apply_override(raw, "rows[0].cage.inner_diameter", "330 mm")
    expect_error(r, "rows[0].cage.inner_diameter", ["shoulder"])


# --------------------------------------------------------------------------- negative clearance


def test_negative_radial_clearance_is_an_interference():
    """A single row with P_d < 0 is accepted and its arcs reach into the centred ball:
    each arc centre is (f − ½)·D − P_d/4 from the ball centre, so the penetration of the
    centred ball is −P_d/4 at every arc."""
    from rvcore.bearing.geometry import INNER, OUTER, arc_geometry

    raw = apply_override(read_toml(BUILDABLE), "rows[0].radial_clearance", "-0.01 mm")
    raw["temperature"] = {"inner_ring": "20 degC", "outer_ring": "20 degC"}   # the file's clearance itself
    b = bearing_from_dict(raw, file=FILE)
    row = b.rows[0]
    assert row.radial_clearance == pytest.approx(-10e-6)
    for ring, arc in ((INNER, row.inner_arcs[0]), (OUTER, row.outer_arcs[0])):
        cr, cz, rmh, _ = arc_geometry(row, arc, ring)
        dist = math.hypot(row.pitch_diameter / 2 - cr, row.axial_position - cz)
        assert dist - rmh == pytest.approx(10e-6 / 4, rel=1e-9)


# --------------------------------------------------------------------------- sweep axis


def test_preload_on_a_sweep_axis_reloads_the_bearing(tmp_path):
    sweep = tmp_path / "preload.toml"
    sweep.write_text(f"""
name = "preload-axis"
bearing = "{PAIR.as_posix()}"
profile = "{(ROOT / 'sweeps' / 'profiles' / 'short.toml').as_posix()}"
[axes]
"pair.preload" = ["0 kN", "3.5 kN"]
[fixed]
speed = "120 deg/s"
radial_load = "20 kN"
axial_load = "10 kN"
""")
    s = read_sweep_file(sweep)
    assert len(s.cases) == 2
    by_preload = {c.bearing.preload: c.bearing for c in s.cases}
    assert set(by_preload) == {0.0, 3.5e3}
    assert by_preload[0.0].preload_offset == 0.0
    assert all(r.inner_offset == 0.0 for r in by_preload[0.0].rows)
    assert by_preload[3.5e3].preload_offset > 0.0
    assert lookup(read_toml(PAIR), "pair.preload") == "3.5 kN"   # the file itself untouched



def test_a_pairs_rows_take_their_own_imperfections(raw):
    """``[[pair.imperfections]]``: one entry per row (the row at -row_spacing/2 first) over
    the bearing's ``[imperfections]``; any other number of entries is one line."""
    raw = copy.deepcopy(raw)
    raw["imperfections"] = {"outer_eccentricity": "10 um"}
    raw["pair"]["imperfections"] = [{"inner_eccentricity": "20 um"},
                                    {"inner_eccentricity": "5 um", "inner_eccentricity_angle": "90 deg"}]
    b = bearing_from_dict(raw, "pair.toml")
    low, high = sorted(b.rows, key=lambda r: r.axial_position)
    assert low.imperfections.inner_eccentricity == pytest.approx(20e-6)
    assert high.imperfections.inner_eccentricity == pytest.approx(5e-6)
    assert high.imperfections.inner_eccentricity_angle == pytest.approx(math.pi / 2)
    assert low.imperfections.outer_eccentricity == high.imperfections.outer_eccentricity == pytest.approx(10e-6)
    raw["pair"]["imperfections"] = raw["pair"]["imperfections"][:1]
    with pytest.raises(ConfigError, match="give two"):
        bearing_from_dict(raw, "pair.toml")
