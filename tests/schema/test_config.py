"""Bearing and profile files: validation errors, overrides, and the shipped files' contents.

Every expected number is computed here from the geometry (not copied from the loader's
output), and every error is checked for naming the file, the key, the value and the reason.
"""
from __future__ import annotations

import copy
import math
import re
from pathlib import Path

import pytest

from pipeline.schema import (apply_override, bearing_from_dict, load_bearing, load_profile,
                             lookup, profile_from_dict, read_toml, resolve_path)
from pipeline.errors import ConfigError
from rvcore.profile import scaled_study_profile, study_profile

ROOT = Path(__file__).resolve().parents[2]
BEARINGS = ROOT / "sweeps" / "bearings"
PROFILES = ROOT / "sweeps" / "profiles"
FILE = "some/bearing.toml"


@pytest.fixture
def study_raw():
    return read_toml(BEARINGS / "rv-main-study.toml")


@pytest.fixture
def buildable_raw():
    return read_toml(BEARINGS / "rv-main-buildable.toml")


@pytest.fixture
def profile_raw():
    return read_toml(PROFILES / "study.toml")


def expect_error(fn, raw, key, value=None, reason_words=(), file=FILE):
    """Call ``fn(raw, file)`` and check the ConfigError names file, key, value and reason."""
    with pytest.raises(ConfigError) as info:
        fn(raw, file=file)
    err = info.value
    msg = str(err)
    assert err.file == file and msg.startswith(file), msg
    assert err.key == key, msg
    assert key in msg
    if value is not None:
        assert err.value == value, msg
        assert repr(value) in msg
    for word in reason_words:
        assert word in err.reason, msg
    assert "\n" not in msg
    return err


def overlap_need_mm(count, ball_mm):
    """Smallest pitch diameter for ``count`` balls, from the chord between neighbours."""
    return ball_mm / math.sin(math.pi / count)


# --------------------------------------------------------------------------- unknown / missing keys


def test_unknown_top_level_key(buildable_raw):
    buildable_raw["colour"] = "red"
    expect_error(bearing_from_dict, buildable_raw, "colour", "red", ["unknown key"])


def test_unknown_nested_key_in_cage(buildable_raw):
    buildable_raw["rows"][0]["cage"]["colour"] = "red"
    err = expect_error(bearing_from_dict, buildable_raw, "rows[0].cage.colour", "red", ["unknown key"])
    assert "pocket_clearance" in err.reason  # lists what is allowed there


def test_unknown_key_in_groove_arc(buildable_raw):
    buildable_raw["rows"][0]["outer_groove"]["arcs"][0]["radius"] = "12 mm"
    expect_error(bearing_from_dict, buildable_raw, "rows[0].outer_groove.arcs[0].radius", "12 mm",
                 ["unknown key"])


def test_unknown_key_in_friction(buildable_raw):
    buildable_raw["friction"]["mu_kinetic"] = 0.05
    expect_error(bearing_from_dict, buildable_raw, "friction.mu_kinetic", 0.05, ["unknown key"])


def test_missing_required_key(buildable_raw):
    del buildable_raw["rows"][0]["balls"]["diameter"]
    expect_error(bearing_from_dict, buildable_raw, "rows[0].balls.diameter", None, ["missing"])


def test_missing_required_table(buildable_raw):
    del buildable_raw["envelope"]
    expect_error(bearing_from_dict, buildable_raw, "envelope", None, ["missing"])


# --------------------------------------------------------------------------- units and values


def test_wrong_unit_mass_for_a_length(buildable_raw):
    buildable_raw["rows"][0]["balls"]["diameter"] = "30 kg"
    err = expect_error(bearing_from_dict, buildable_raw, "rows[0].balls.diameter", "30 kg",
                       ["wrong units"])
    assert "kg" in err.reason and "m" in err.reason


def test_wrong_unit_length_for_an_angle(buildable_raw):
    buildable_raw["rows"][0]["inner_groove"]["arcs"][0]["contact_angle"] = "15 mm"
    expect_error(bearing_from_dict, buildable_raw, "rows[0].inner_groove.arcs[0].contact_angle",
                 "15 mm", ["wrong units"])


@pytest.mark.parametrize("key, value", [
    ("rows[0].balls.diameter", "-3 mm"),
    ("envelope.width", "0 mm"),
    ("rows[0].cage.width", "-28 mm"),
    ("material.youngs_modulus", "0 GPa"),
    ("contact.damping_depth", "0 um"),
])
def test_non_positive_size(buildable_raw, key, value):
    raw = apply_override(buildable_raw, key, value)
    expect_error(bearing_from_dict, raw, key, value, ["must be positive"])


def test_negative_clearance_is_accepted_as_an_interference(buildable_raw):
    # a negative radial clearance is a radial preload (tests/schema/test_pair_file.py
    # checks the interference it gives); a clearance must still be a length
    raw = apply_override(buildable_raw, "rows[0].radial_clearance", "-0.01 mm")
    b = bearing_from_dict(raw, file=FILE)
    # the file's value at 20 degC; one steel at the default 40 degC scales it by 1 + alpha*20 K
    assert b.nominal_radial_clearances[0] == pytest.approx(-1e-5)
    assert b.rows[0].radial_clearance == pytest.approx(-1e-5 * (1 + 11.5e-6 * 20.0), rel=1e-9)
    raw = apply_override(buildable_raw, "rows[0].radial_clearance", "-0.01 kg")
    expect_error(bearing_from_dict, raw, "rows[0].radial_clearance", "-0.01 kg")


def test_ball_count_must_be_an_integer(buildable_raw):
    raw = apply_override(buildable_raw, "rows[0].balls.count", 42.5)
    expect_error(bearing_from_dict, raw, "rows[0].balls.count", 42.5, ["integer"])


def test_overlap_flag_must_be_boolean(buildable_raw):
    buildable_raw["allow_ball_overlap"] = "yes"
    expect_error(bearing_from_dict, buildable_raw, "allow_ball_overlap", "yes", ["true or false"])


def test_poisson_ratio_range(buildable_raw):
    raw = apply_override(buildable_raw, "material.poisson_ratio", 0.7)
    expect_error(bearing_from_dict, raw, "material.poisson_ratio", 0.7, ["0.5"])


def test_friction_speeds_in_order(buildable_raw):
    raw = apply_override(buildable_raw, "friction.v_dynamic", "50 mm/s")
    expect_error(bearing_from_dict, raw, "friction.v_dynamic", "50 mm/s", ["v_static"])


def test_friction_law_is_one_of_the_registered_laws(buildable_raw):
    """``friction.law`` names a law of rvcore.bearing.laws.FRICTION_LAWS; the study's by default."""
    assert bearing_from_dict(buildable_raw, file=FILE).contact.law == "coulomb_step"
    buildable_raw["friction"]["law"] = "ehl_bair_winer"
    assert bearing_from_dict(buildable_raw, file=FILE).contact.law == "ehl_bair_winer"
    buildable_raw["friction"]["law"] = "wet"
    expect_error(bearing_from_dict, buildable_raw, "friction.law", "wet", ["coulomb_step", "ehl_bair_winer"])


def test_cage_guidance_choice(buildable_raw):
    raw = apply_override(buildable_raw, "rows[0].cage.guidance", "inner-land")
    expect_error(bearing_from_dict, raw, "rows[0].cage.guidance", "inner-land", ["outer-land"])


# --------------------------------------------------------------------------- geometry


def test_ball_overlap_is_an_error_with_the_numbers(study_raw):
    del study_raw["allow_ball_overlap"]
    err = expect_error(bearing_from_dict, study_raw, "rows[0].balls.count", 51,
                       ["need a pitch diameter"])
    need = overlap_need_mm(51, 23.0)
    assert 373.5 < need < 373.7  # docs/model.md §10 quotes 373.6 mm
    pitch = (320.0 + 383.0) / 2.0
    assert f"51 balls of 23 mm need a pitch diameter of at least {need:.1f} mm; " \
           f"this bearing's is {pitch:.1f} mm" in err.reason


def test_ball_overlap_with_flag_false_is_an_error(study_raw):
    study_raw["allow_ball_overlap"] = False
    expect_error(bearing_from_dict, study_raw, "rows[0].balls.count", 51, ["need a pitch diameter"])


def test_overlap_flag_turns_the_error_into_a_warning(study_raw):
    b = bearing_from_dict(study_raw, file=FILE)
    assert b.allow_ball_overlap
    need = overlap_need_mm(51, 23.0)
    assert b.warnings == (f"51 balls of 23 mm need a pitch diameter of at least {need:.1f} mm; "
                          f"this bearing's is {351.5:.1f} mm",)


def test_overlap_flag_does_not_hide_other_problems(study_raw):
    raw = apply_override(study_raw, "rows[0].outer_groove.arcs[0].curvature_ratio", 0.45)
    expect_error(bearing_from_dict, raw, "rows[0].outer_groove.arcs[0].curvature_ratio", 0.45,
                 ["groove radius smaller than the ball's"])


def test_fewer_balls_remove_the_overlap(study_raw):
    # The largest count whose neighbouring centres are at least one ball diameter apart.
    z = max(n for n in range(3, 200) if 351.5 * math.sin(math.pi / n) >= 23.0)
    raw = apply_override(study_raw, "rows[0].balls.count", str(z))
    assert bearing_from_dict(raw, file=FILE).warnings == ()
    raw = apply_override(study_raw, "rows[0].balls.count", str(z + 1))
    assert len(bearing_from_dict(raw, file=FILE).warnings) == 1


def test_groove_radius_smaller_than_the_ball(buildable_raw):
    raw = apply_override(buildable_raw, "rows[0].inner_groove.arcs[0].curvature_ratio", 0.48)
    err = expect_error(bearing_from_dict, raw, "rows[0].inner_groove.arcs[0].curvature_ratio", 0.48,
                       ["groove radius smaller than the ball's"])
    assert f"{0.48 * 23:.4g} mm" in err.reason and "11.5 mm" in err.reason


def test_groove_radius_equal_to_the_ball(buildable_raw):
    raw = apply_override(buildable_raw, "rows[0].outer_groove.arcs[0].curvature_ratio", 0.5)
    expect_error(bearing_from_dict, raw, "rows[0].outer_groove.arcs[0].curvature_ratio", 0.5,
                 ["f must exceed 0.5"])


def test_cage_bore_inside_the_inner_ring_shoulder(buildable_raw):
    # The shoulder is 340 mm: a 336 mm cage bore does not clear it.
    raw = apply_override(buildable_raw, "rows[0].cage.inner_diameter", "336 mm")
    expect_error(bearing_from_dict, raw, "rows[0].cage.inner_diameter", "336 mm",
                 ["does not clear the inner-ring shoulder"])


def test_cage_beyond_the_outer_ring_land(buildable_raw):
    # The outer groove's bottom is at d_m + D = 374.5 mm; a 380 mm cage cannot ride on a land.
    raw = apply_override(buildable_raw, "rows[0].cage.outer_diameter", "380 mm")
    err = expect_error(bearing_from_dict, raw, "rows[0].cage.outer_diameter", "380 mm",
                       ["does not fit inside the outer ring"])
    assert f"{351.5 + 23:.4g} mm" in err.reason


def test_cage_beyond_the_outer_diameter(buildable_raw):
    raw = apply_override(buildable_raw, "rows[0].cage.outer_diameter", "390 mm")
    expect_error(bearing_from_dict, raw, "rows[0].cage.outer_diameter", "390 mm", ["does not fit"])


def test_cage_narrower_than_its_pockets(buildable_raw):
    raw = apply_override(buildable_raw, "rows[0].cage.width", "23 mm")  # pockets are 23.5 mm
    expect_error(bearing_from_dict, raw, "rows[0].cage.width", "23 mm", ["pockets"])


def test_balls_reaching_the_bore(buildable_raw):
    raw = apply_override(buildable_raw, "rows[0].pitch_diameter", "340 mm")  # 340 - 23 < 320
    expect_error(bearing_from_dict, raw, "rows[0].pitch_diameter", "340 mm", ["reach the bore"])


def test_four_point_arcs_on_the_same_side(buildable_raw):
    raw = read_toml(BEARINGS / "four-point-example.toml")
    raw = apply_override(raw, "rows[0].outer_groove.arcs[1].contact_angle", "20 deg")
    expect_error(bearing_from_dict, raw, "rows[0].outer_groove.arcs[1].contact_angle", "20 deg",
                 ["opposite"])


def test_three_arcs_are_rejected(buildable_raw):
    arcs = buildable_raw["rows"][0]["inner_groove"]["arcs"]
    arcs += [dict(arcs[0]), dict(arcs[0])]
    expect_error(bearing_from_dict, buildable_raw, "rows[0].inner_groove.arcs", None, ["3 arcs"])


def test_rows_must_be_an_array_of_tables(buildable_raw):
    buildable_raw["rows"] = buildable_raw["rows"][0]
    expect_error(bearing_from_dict, buildable_raw, "rows", None, ["array of tables"])


def test_separate_ring_and_ball_materials(buildable_raw):
    mat = buildable_raw.pop("material")
    buildable_raw["ring_material"] = dict(mat)
    buildable_raw["ball_material"] = dict(mat, youngs_modulus="310 GPa")  # ceramic-ish balls
    b = bearing_from_dict(buildable_raw, file=FILE)
    assert b.ring_material.youngs_modulus == pytest.approx(208e9)
    assert b.ball_material.youngs_modulus == pytest.approx(310e9)
    buildable_raw["material"] = mat
    expect_error(bearing_from_dict, buildable_raw, "ring_material", None, ["either"])


# --------------------------------------------------------------------------- assumptions


def test_assumption_that_names_no_key(buildable_raw):
    buildable_raw["assumptions"] = ["rows[0].cage.width", "rows[0].cage.colour"]
    expect_error(bearing_from_dict, buildable_raw, "assumptions[1]", "rows[0].cage.colour",
                 ["not in this file"])


def test_assumption_that_is_not_a_key_path(buildable_raw):
    buildable_raw["assumptions"] = ["rows[0]..width"]
    with pytest.raises(ConfigError, match="key path"):
        bearing_from_dict(buildable_raw, file=FILE)


def _assumption_comments(path: Path) -> dict:
    """Map 'table.key' (list indices dropped) -> whether an ASSUMPTION comment goes with it.

    The comment counts when it is on the key's own line or in the block of comment lines
    directly above the key (or above the [[table]] header, for a whole array of tables).
    """
    marks, table, block = {}, "", []
    for line in path.read_text().splitlines():
        s = line.strip()
        if s.startswith("#"):
            block.append(s)
            continue
        assumed = any("ASSUMPTION" in c for c in block) or "ASSUMPTION" in line
        header = re.match(r"^\[\[?([\w.]+)\]\]?", s)
        if header:
            table = header.group(1)
            marks[table] = marks.get(table, False) or assumed
        elif "=" in s:
            key = s.split("=", 1)[0].strip()
            full = f"{table}.{key}" if table else key
            marks[full] = marks.get(full, False) or assumed
        block = []
    return marks


@pytest.mark.parametrize("name", ["rv-main-study", "rv-main-buildable", "reduced-test",
                                  "four-point-example", "deep-groove-example"])
def test_listed_assumptions_exist_and_are_commented(name):
    path = BEARINGS / f"{name}.toml"
    raw = read_toml(path)
    b = load_bearing(path)
    assert b.name == name
    assert b.assumptions and len(b.assumptions) == len(raw["assumptions"])
    marks = _assumption_comments(path)
    for key in b.assumptions:
        lookup(raw, key)  # raises KeyError if the key does not exist
        plain = re.sub(r"\[\d+\]", "", key)
        assert marks.get(plain), f"{name}: {key} has no '# ASSUMPTION' comment"


def test_study_unknowns_are_all_assumptions():
    """Everything the study does not give (docs/model.md §10) is listed as an assumption."""
    b = load_bearing(BEARINGS / "rv-main-study.toml")
    needed = {"rows[0].radial_clearance", "rows[0].inner_groove.arcs", "rows[0].outer_groove.arcs",
              "rows[0].cage.pocket_clearance", "rows[0].cage.land_clearance",
              "rows[0].cage.land_stiffness", "inner_ring.shoulder_diameter", "contact.damping",
              "contact.damping_depth"}
    assert needed <= set(b.assumptions)
    # ...and nothing that Table 2 does give.
    table2 = {"envelope.bore", "envelope.outer_diameter", "envelope.width", "rows[0].balls.count",
              "rows[0].balls.diameter", "rows[0].cage.inner_diameter", "rows[0].cage.outer_diameter",
              "material.density", "material.youngs_modulus", "material.poisson_ratio"}
    assert not table2 & set(b.assumptions)


# --------------------------------------------------------------------------- shipped bearing files


def test_study_file_holds_table_2_exactly():
    b = load_bearing(BEARINGS / "rv-main-study.toml")
    row = b.rows[0]
    rel = dict(rel=1e-12)
    assert b.bore == pytest.approx(0.320, **rel)
    assert b.outer_diameter == pytest.approx(0.383, **rel)
    assert b.width == pytest.approx(0.030, **rel)
    assert len(b.rows) == 1 and row.ball_count == 51
    assert row.ball_diameter == pytest.approx(0.023, **rel)
    assert row.cage.inner_diameter == pytest.approx(0.3545, **rel)
    assert row.cage.outer_diameter == pytest.approx(0.366, **rel)
    for m in (b.ring_material, b.ball_material):
        assert m.density == pytest.approx(7800.0, **rel)
        assert m.youngs_modulus == pytest.approx(208e9, **rel)
        assert m.poisson_ratio == pytest.approx(0.3, **rel)
    assert row.pitch_diameter == pytest.approx((0.320 + 0.383) / 2, **rel)
    # The study's friction law.
    c = b.contact
    assert (c.mu_static, c.v_static, c.mu_dynamic, c.v_dynamic) == pytest.approx((0.1, 0.1, 0.02, 1.0))
    # The documented assumptions of the brief: angular contact at 15 deg, f_i 0.52, f_o 0.53.
    assert len(row.inner_arcs) == len(row.outer_arcs) == 1
    assert row.inner_arcs[0].contact_angle == pytest.approx(math.radians(15))
    assert row.outer_arcs[0].contact_angle == pytest.approx(math.radians(15))
    assert (row.inner_arcs[0].curvature_ratio, row.outer_arcs[0].curvature_ratio) == (0.52, 0.53)
    assert row.radial_clearance == 0.0
    assert b.allow_ball_overlap and len(b.warnings) == 1


def test_fifteen_degrees_carries_the_nominal_load_without_lift_off():
    """The 15 deg choice: the largest standard angle with F_a >= 1.22 F_r tan(alpha), and
    the quasi-static solution at the study's 30 kN + 10 kN keeps every ball loaded, while
    the next standard angle lets balls lift off."""
    from rvcore.statics.equilibrium import solve_statics

    fr, fa = 30e3, 10e3
    alpha_max = math.degrees(math.atan(fa / (1.22 * fr)))
    standard = [a for a in (15, 25, 30, 40) if a <= alpha_max]
    raw = read_toml(BEARINGS / "rv-main-study.toml")
    b = bearing_from_dict(raw, FILE)
    assert math.degrees(b.rows[0].nominal_contact_angle) == pytest.approx(max(standard))
    st = solve_statics(b, fr, fa, 0.0, 0.0, gravity=False)
    assert st.loaded_ball_count == b.rows[0].ball_count
    assert (st.ball_loads.sum(axis=1) > 0).all()
    steeper = min(a for a in (15, 25, 30, 40) if a > alpha_max)
    for groove in ("inner_groove", "outer_groove"):
        raw = apply_override(raw, f"rows[0].{groove}.arcs[0].contact_angle", f"{steeper} deg")
    st = solve_statics(bearing_from_dict(raw, FILE), fr, fa, 0.0, 0.0, gravity=False)
    assert st.loaded_ball_count < b.rows[0].ball_count


def test_buildable_file_has_the_largest_count_with_a_3_mm_web():
    b = load_bearing(BEARINGS / "rv-main-buildable.toml")
    s = load_bearing(BEARINGS / "rv-main-study.toml")
    row = b.rows[0]
    dm, d, web = 351.5, 23.0, 3.0
    gap = lambda z: dm * math.sin(math.pi / z) - d  # noqa: E731 - ball-to-ball gap on the pitch circle
    z = max(n for n in range(3, 200) if gap(n) >= web)
    assert row.ball_count == z and gap(z + 1) < web
    assert not b.allow_ball_overlap and b.warnings == ()
    # Everything else as in the study file.
    assert (b.bore, b.outer_diameter, b.width) == (s.bore, s.outer_diameter, s.width)
    assert row.ball_diameter == s.rows[0].ball_diameter
    assert row.cage == s.rows[0].cage and b.contact == s.contact
    assert b.assumptions == s.assumptions


def test_four_point_file_has_two_arcs_per_ring_at_plus_minus_alpha():
    b = load_bearing(BEARINGS / "four-point-example.toml")
    row = b.rows[0]
    assert b.warnings == ()
    assert row.radial_clearance > 0
    for arcs in (row.inner_arcs, row.outer_arcs):
        assert len(arcs) == 2
        a0, a1 = (a.contact_angle for a in arcs)
        assert a0 == pytest.approx(-a1) and a0 != 0
        assert all(a.curvature_ratio > 0.5 for a in arcs)


def test_deep_groove_file_has_one_arc_per_ring_at_zero():
    row = load_bearing(BEARINGS / "deep-groove-example.toml").rows[0]
    assert len(row.inner_arcs) == len(row.outer_arcs) == 1
    assert row.inner_arcs[0].contact_angle == 0.0 == row.outer_arcs[0].contact_angle
    assert row.radial_clearance == 0.0


def test_reduced_test_bearing_is_small_and_buildable():
    b = load_bearing(BEARINGS / "reduced-test.toml")
    s = load_bearing(BEARINGS / "rv-main-study.toml")
    assert b.name == "reduced-test" and b.warnings == ()
    assert 8 <= b.rows[0].ball_count <= 16
    assert (b.bore, b.outer_diameter, b.width) == (s.bore, s.outer_diameter, s.width)
    assert b.rows[0].ball_diameter == s.rows[0].ball_diameter


# --------------------------------------------------------------------------- overrides


def test_apply_override_sets_values_on_a_copy(buildable_raw):
    before = copy.deepcopy(buildable_raw)
    raw = apply_override(buildable_raw, "friction.mu_static", "0.2")
    raw = apply_override(raw, "rows[0].cage.pocket_clearance", "0.3 mm")
    raw = apply_override(raw, "rows[0].balls.count", "40")
    assert buildable_raw == before  # the input is untouched
    assert raw["rows"][0]["balls"]["count"] == 40  # a TOML literal: an integer
    assert raw["rows"][0]["cage"]["pocket_clearance"] == "0.3 mm"  # not a literal: a string
    b = bearing_from_dict(raw, file=FILE)
    assert b.contact.mu_static == 0.2
    assert b.rows[0].cage.pocket_clearance == pytest.approx(0.3e-3)
    assert b.rows[0].ball_count == 40


def test_apply_override_reaches_arcs(buildable_raw):
    raw = apply_override(buildable_raw, "rows[0].outer_groove.arcs[0].contact_angle", "25 deg")
    b = bearing_from_dict(raw, file=FILE)
    assert b.rows[0].outer_arcs[0].contact_angle == pytest.approx(math.radians(25))


@pytest.mark.parametrize("key, words", [
    ("friction.mu_kinetic", ["unknown key", "mu_static"]),
    ("rows[0].cage.colour", ["unknown key"]),
    ("rows[3].balls.count", ["out of range"]),
    ("shipping.weight", ["unknown key"]),
    ("rows[0].cage", ["table"]),
    ("rows[0]..cage", ["key path"]),
])
def test_apply_override_rejects_bad_keys(buildable_raw, key, words):
    with pytest.raises(ConfigError) as info:
        apply_override(buildable_raw, key, "1", file="--set")
    err = info.value
    assert err.file == "--set" and err.key == key
    assert str(err).startswith(f"--set: {key}")
    for w in words:
        assert w in err.reason
    assert lookup(buildable_raw, "rows[0].balls.count") == 42  # nothing was created or changed
    assert "colour" not in buildable_raw["rows"][0]["cage"]


# --------------------------------------------------------------------------- files and paths


def test_read_toml_errors(tmp_path):
    with pytest.raises(ConfigError, match="no such file") as info:
        read_toml(tmp_path / "missing.toml")
    assert info.value.file.endswith("missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("name = \n")
    with pytest.raises(ConfigError, match=r"invalid TOML.*line 1") as info:
        read_toml(bad)
    assert info.value.file == str(bad)


def test_load_bearing_names_the_file(tmp_path, buildable_raw):
    path = tmp_path / "b.toml"
    text = (BEARINGS / "rv-main-buildable.toml").read_text().replace('diameter = "23 mm"',
                                                                     'diameter = "23 kg"')
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_bearing(path)
    assert info.value.file == str(path) and info.value.key == "rows[0].balls.diameter"


def test_resolve_path(tmp_path):
    base = tmp_path / "sweeps" / "study.toml"
    assert resolve_path(base, "bearings/x.toml") == tmp_path / "sweeps" / "bearings" / "x.toml"
    assert resolve_path(base, "../x.toml") == tmp_path / "sweeps" / ".." / "x.toml"
    assert resolve_path(base, tmp_path / "abs.toml") == tmp_path / "abs.toml"
    assert resolve_path("study.toml", "bearings/x.toml") == Path("bearings/x.toml")


# --------------------------------------------------------------------------- profiles


def _same_profile(a, b):
    for ch in ("radial_load", "axial_load", "speed"):
        ca, cb = getattr(a, ch), getattr(b, ch)
        assert ca.times == pytest.approx(cb.times, rel=1e-12, abs=1e-15)
        assert ca.values == pytest.approx(cb.values)
        assert (ca.relative, ca.interpolation) == (cb.relative, cb.interpolation)
    assert [p[0] for p in a.phases] == [p[0] for p in b.phases]
    assert [p[1:] for p in a.phases] == [pytest.approx(p[1:], rel=1e-12) for p in b.phases]
    assert a.duration == pytest.approx(b.duration, rel=1e-12)


def test_study_profile_file_matches_the_core():
    _same_profile(load_profile(PROFILES / "study.toml"), study_profile())


def test_short_profile_is_the_study_scaled_by_a_tenth():
    _same_profile(load_profile(PROFILES / "short.toml"), scaled_study_profile(0.1))


def test_s_curve_profile_smooths_only_the_speed():
    s, ref = load_profile(PROFILES / "s-curve.toml"), study_profile()
    assert s.speed.interpolation == "smoothstep"
    assert s.speed.times == pytest.approx(ref.speed.times)
    assert s.radial_load == ref.radial_load and s.axial_load == ref.axial_load
    assert s.phases == ref.phases and s.duration == ref.duration


def test_absolute_profile_values(profile_raw):
    ch = profile_raw["speed"]
    del ch["fraction"]
    ch["value"] = ["0 deg/s", "660 deg/s", "660 deg/s", "0 deg/s"]
    p = profile_from_dict(profile_raw, file="p.toml")
    assert not p.speed.relative
    assert p.speed.values[1] == pytest.approx(660 * math.pi / 180)


@pytest.mark.parametrize("edit, key, words", [
    (lambda r: r["speed"].__setitem__("time", ["0.3 s", "0.8 s", "0.8 s", "4.3 s"]),
     "speed.time[2]", ["increase strictly"]),
    (lambda r: r["radial_load"].__setitem__("time", ["0 s", "0.5 s", "0.3 s", "4.6 s"]),
     "radial_load.time[2]", ["increase strictly"]),
    (lambda r: r["axial_load"].__setitem__("fraction", [0, 1, 0]),
     "axial_load.fraction", ["3 entries", "4"]),
    (lambda r: r["speed"].__setitem__("value", [0, 1, 1, 0]),
     "speed", ["exactly one", "not both"]),
    (lambda r: r["speed"].pop("fraction"),
     "speed", ["exactly one"]),
    (lambda r: r["speed"].__setitem__("interpolation", "cubic"),
     "speed.interpolation", ["linear", "smoothstep"]),
    (lambda r: r["speed"].__setitem__("time", ["0.3 s", "0.8 s", "3.8 s", "4.3 kg"]),
     "speed.time[3]", ["wrong units"]),
    (lambda r: r["speed"].__setitem__("ramp", "fast"),
     "speed.ramp", ["unknown key"]),
    (lambda r: r.__setitem__("jerk", 3),
     "jerk", ["unknown key"]),
    (lambda r: r["phases"].__setitem__("deceleration", ["3.8 s", "5 s"]),
     "phases.deceleration", ["ends after the cycle"]),
    (lambda r: r["phases"].__setitem__("steady", ["0.7 s", "3.8 s"]),
     "phases.steady", ["starts before phase 'startup' ends"]),
    (lambda r: r["phases"].__setitem__("startup", ["0.8 s", "0.3 s"]),
     "phases.startup", ["end must come after the start"]),
    (lambda r: r["phases"].pop("steady"),
     "phases.steady", ["missing"]),
    (lambda r: r["phases"].__setitem__("cruise", ["1 s", "2 s"]),
     "phases.cruise", ["unknown key"]),
    (lambda r: r.__setitem__("duration", "-1 s"),
     "duration", ["positive"]),
    (lambda r: r["radial_load"].__setitem__("time", ["0 s", "0.3 s", "4.3 s", "4.7 s"]),
     "radial_load.time[3]", ["after the end of the cycle"]),
    (lambda r: r.pop("axial_load"),
     "axial_load", ["missing"]),
])
def test_bad_profile_tables(profile_raw, edit, key, words):
    edit(profile_raw)
    with pytest.raises(ConfigError) as info:
        profile_from_dict(profile_raw, file="prof.toml")
    err = info.value
    assert err.file == "prof.toml" and err.key == key, str(err)
    assert str(err).startswith(f"prof.toml: {key}")
    for w in words:
        assert w in err.reason, str(err)
