"""Sweep files: grid expansion, general axes, explicit cases, case ids, and errors."""
from __future__ import annotations

import itertools
import math
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest

import pipeline.schema.sweepfile as sweepfile
from pipeline.errors import ConfigError, UnitlessNumberWarning
from pipeline.schema import read_sweep_file

REPO = Path(__file__).resolve().parents[2]
SWEEPS = REPO / "sweeps"

HEADER = 'bearing = "bearings/reduced-test.toml"\nprofile = "profiles/short.toml"\n'
GRID = """
[axes]
speed = ["120 deg/s", "660 deg/s"]
radial_load = ["20 kN", "40 kN"]

[fixed]
axial_load = "10 kN"
"""


def make_sweep(folder: Path, body: str, name: str = "s.toml", header: str = HEADER) -> Path:
    """A sweep file in ``folder`` next to copies of the reduced bearing and short profile."""
    (folder / "bearings").mkdir(exist_ok=True)
    (folder / "profiles").mkdir(exist_ok=True)
    shutil.copy(SWEEPS / "bearings" / "reduced-test.toml", folder / "bearings")
    shutil.copy(SWEEPS / "profiles" / "short.toml", folder / "profiles")
    path = folder / name
    path.write_text(header + body)
    return path


def ops(sweep):
    return [(c.operating_point.speed, c.operating_point.radial_load, c.operating_point.axial_load)
            for c in sweep.cases]


# --------------------------------------------------------------------------- the shipped sweeps


def test_study_sweep_is_the_studys_grid():
    s = read_sweep_file(SWEEPS / "study.toml")
    assert s.name == "study"
    speeds_deg = np.arange(120, 661, 60)            # 120, 180, ..., 660 deg/s: 10 values
    loads_kn = np.arange(20, 41, 5)                 # 20, 25, ..., 40 kN: 5 values
    assert len(speeds_deg) == 10 and len(loads_kn) == 5
    n = s.realizations                              # random starts per grid point
    assert n >= 1 and len(s.cases) == 50 * n
    expected = sorted((math.radians(w), f * 1e3) for w, f in itertools.product(speeds_deg, loads_kn))
    got = sorted({(w, f) for w, f, _ in ops(s)})
    np.testing.assert_allclose(np.array(got), np.array(expected), rtol=1e-14)
    assert {a for _, _, a in ops(s)} == {10e3}
    # every grid point has its n realizations, each with its own seed (and case id)
    assert sorted({c.settings.seed for c in s.cases}) == list(range(n)) or n == 1
    assert len({c.case_id for c in s.cases}) == len(s.cases)
    # both of the study's one-dimensional sweeps are in it
    assert sum(math.isclose(f, 30e3) for _, f, _ in ops(s)) == 10 * n
    assert sum(math.isclose(w, math.radians(120), rel_tol=1e-12) for w, _, _ in ops(s)) == 5 * n
    assert s.bearing.name == "rv-main-study"
    assert s.profile.name == "study"
    assert s.settings.output_rate == 1000.0
    assert len({c.case_id for c in s.cases}) == 50 * n


def test_smoke_sweep_is_a_3x3_grid_on_the_reduced_bearing():
    s = read_sweep_file(SWEEPS / "smoke.toml")
    assert s.name == "smoke" and len(s.cases) == 9
    assert s.bearing.name == "reduced-test" and s.profile.name == "short"
    assert s.profile.duration < 1.0
    assert [len(a) for a in s.axes] == [3, 3]
    # three points on each of the study's lines (speed at 30 kN, load at 120 deg/s): fits
    # with a residual
    assert sum(math.isclose(c.point["radial_load"], 30e3) for c in s.cases) == 3
    assert sum(math.isclose(c.point["speed"], math.radians(120), rel_tol=1e-12) for c in s.cases) == 3


# --------------------------------------------------------------------------- axes


def test_range_includes_stop_and_stays_on_the_written_grid(tmp_path):
    p = make_sweep(tmp_path, """
[axes]
speed = {start = "120 deg/s", stop = "300 deg/s", step = "60 deg/s"}
radial_load = {start = "20 kN", stop = "42 kN", step = "5 kN"}
[fixed]
axial_load = "10 kN"
""")
    s = read_sweep_file(p)
    speed, load = s.axes
    np.testing.assert_allclose(np.degrees(speed.coords), [120.0, 180.0, 240.0, 300.0], rtol=1e-14)
    assert list(load.coords) == [20e3, 25e3, 30e3, 35e3, 40e3]      # 42 kN is not on the grid
    assert len(s.cases) == 4 * 5
    # the first axis varies slowest
    assert [c.point["radial_load"] for c in s.cases[:5]] == list(load.coords)


@pytest.mark.filterwarnings("ignore::pipeline.errors.UnitlessNumberWarning")   # speeds in rad/s
def test_range_with_a_float_step_does_not_lose_its_last_value(tmp_path):
    # (1.3 - 1.0) / 0.1 is 2.9999999999999996 in binary floating point
    p = make_sweep(tmp_path, """
[axes]
speed = {start = 1.0, stop = 1.3, step = 0.1}
[fixed]
radial_load = "20 kN"
axial_load = "10 kN"
""")
    np.testing.assert_allclose(read_sweep_file(p).axes[0].coords, [1.0, 1.1, 1.2, 1.3], rtol=1e-12)


def test_general_axes_reach_the_bearing_and_the_solver(tmp_path):
    p = make_sweep(tmp_path, """
[axes]
"friction.mu_static" = [0.05, 0.15]
"rows[0].cage.pocket_clearance" = ["0.3 mm", "0.6 mm"]
"solver.time_step" = ["2 us", "1 us"]
[fixed]
speed = "120 deg/s"
radial_load = "20 kN"
axial_load = "10 kN"
""")
    s = read_sweep_file(p)
    assert [a.key for a in s.axes] == ["friction.mu_static", "rows[0].cage.pocket_clearance",
                                       "solver.time_step"]
    assert [a.units for a in s.axes] == ["1", "m", "s"]
    assert [a.name for a in s.axes] == ["friction_mu_static", "rows_0_cage_pocket_clearance",
                                        "solver_time_step"]
    assert len(s.cases) == 8
    for c in s.cases:
        assert c.bearing.contact.mu_static == c.point["friction.mu_static"]
        assert math.isclose(c.bearing.rows[0].cage.pocket_clearance,
                            c.point["rows[0].cage.pocket_clearance"], rel_tol=1e-12)
        assert c.settings.time_step == c.point["solver.time_step"]
        # the other bearing values are the file's
        assert c.bearing.contact.mu_dynamic == 0.02
    assert {c.bearing.contact.mu_static for c in s.cases} == {0.05, 0.15}
    np.testing.assert_allclose(sorted({c.bearing.rows[0].cage.pocket_clearance for c in s.cases}),
                               [0.3e-3, 0.6e-3], rtol=1e-12)
    assert sorted({c.settings.time_step for c in s.cases}) == pytest.approx([1e-6, 2e-6], rel=1e-12)
    assert len({c.case_id for c in s.cases}) == 8


def test_unquoted_dotted_keys_mean_the_same(tmp_path):
    quoted = read_sweep_file(make_sweep(tmp_path, GRID + '"contact.damping" = "300 N s/m"\n', "a.toml"))
    dotted = read_sweep_file(make_sweep(tmp_path, GRID + 'contact.damping = "300 N s/m"\n', "b.toml"))
    assert [c.case_id for c in quoted.cases] == [c.case_id for c in dotted.cases]
    assert quoted.cases[0].bearing.contact.damping == 300.0


def test_a_value_the_bearing_file_leaves_at_its_default_can_be_swept(tmp_path):
    p = make_sweep(tmp_path, GRID.replace("[fixed]", '"friction.mu_static" = [0.08, 0.12]\n[fixed]'))
    text = (tmp_path / "bearings" / "reduced-test.toml").read_text()
    start = text.index("[friction]")
    end = text.index("[[rows]]")
    (tmp_path / "bearings" / "reduced-test.toml").write_text(text[:start] + text[end:])
    s = read_sweep_file(p)
    assert {c.bearing.contact.mu_static for c in s.cases} == {0.08, 0.12}
    assert {c.bearing.contact.mu_dynamic for c in s.cases} == {0.02}   # the loader's default


def test_the_friction_law_is_set_from_the_command_line_when_the_bearing_file_has_no_friction_table(tmp_path):
    """``--set friction.law=...`` (the one-case sweep of ``statics``/``simulate``) on a bearing
    file without ``[friction]``: the table is made, its other keys at their defaults."""
    import argparse

    from pipeline.commands.common import one_case_sweep
    from rvcore.bearing.geometry import ContactLaw

    make_sweep(tmp_path, GRID)
    bearing = tmp_path / "bearings" / "reduced-test.toml"
    text = bearing.read_text()
    bearing.write_text(text[:text.index("[friction]")] + text[text.index("[[rows]]"):])
    args = argparse.Namespace(bearing=str(bearing), radial_load="20 kN", axial_load="10 kN", moment="0 N m",
                              load_angle="0 deg", speed="120 deg/s", set=["friction.law=ehl_bair_winer"])
    contact = one_case_sweep(args, profile=str(tmp_path / "profiles" / "short.toml")).cases[0].bearing.contact
    assert contact.law == "ehl_bair_winer"
    defaults = ContactLaw(damping=0.0, damping_depth=1.0, pocket_damping=0.0, land_damping=0.0)
    assert (contact.mu_static, contact.mu_dynamic) == (defaults.mu_static, defaults.mu_dynamic)


def test_explicit_cases(tmp_path):
    p = make_sweep(tmp_path, """
[fixed]
axial_load = "10 kN"

[[cases]]
speed = "120 deg/s"
radial_load = "30 kN"

[[cases]]
speed = "660 deg/s"
radial_load = "30 kN"

[[cases]]
speed = "120 deg/s"
radial_load = "20 kN"
""")
    s = read_sweep_file(p)
    assert s.explicit
    assert len(s.cases) == 3
    expected = [(math.radians(120), 30e3), (math.radians(660), 30e3), (math.radians(120), 20e3)]
    np.testing.assert_allclose([(w, f) for w, f, _ in ops(s)], expected, rtol=1e-12)
    assert [a.key for a in s.axes] == ["speed", "radial_load"]
    assert list(s.axis("radial_load").coords) == [20e3, 30e3]


# --------------------------------------------------------------------------- case ids


def test_case_id_is_a_sha256_prefix_of_the_canonical_configuration(tmp_path):
    import hashlib
    import json

    s = read_sweep_file(make_sweep(tmp_path, GRID))
    c = s.cases[0]
    assert len(c.case_id) == 16 and int(c.case_id, 16) >= 0
    conf = tomllib.loads(c.configuration)
    assert conf["model_version"] == sweepfile.MODEL_VERSION
    assert math.isclose(conf["operating_point"]["speed"], math.radians(120), rel_tol=1e-12)
    assert conf["operating_point"]["radial_load"] == 20e3
    assert conf["bearing"]["name"] == "reduced-test"
    # the id is recomputable from the stored configuration alone
    canonical = json.dumps(conf, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    assert hashlib.sha256(canonical.encode()).hexdigest()[:16] == c.case_id


def test_case_ids_ignore_how_values_are_written(tmp_path):
    a = read_sweep_file(make_sweep(tmp_path, GRID, "a.toml"))
    with pytest.warns(UnitlessNumberWarning, match="read in SI: 40000 N"):    # the plain 40000
        b = read_sweep_file(make_sweep(tmp_path, GRID.replace('"20 kN"', '"20000 N"').replace('"40 kN"', "40000")
                                  .replace('"10 kN"', '"0.01 MN"'), "b.toml"))
    c = read_sweep_file(make_sweep(tmp_path, 'description = "other words"\n' + GRID, "c.toml"))
    assert [x.case_id for x in a.cases] == [x.case_id for x in b.cases] == [x.case_id for x in c.cases]


def test_a_changed_value_changes_exactly_the_cases_it_changes(tmp_path):
    a = read_sweep_file(make_sweep(tmp_path, GRID, "a.toml"))
    b = read_sweep_file(make_sweep(tmp_path, GRID.replace('"40 kN"', '"30 kN"'), "b.toml"))
    ida = {(c.point["speed"], c.point["radial_load"]): c.case_id for c in a.cases}
    idb = {(c.point["speed"], c.point["radial_load"]): c.case_id for c in b.cases}
    for (w, f), cid in idb.items():
        if f == 20e3:
            assert ida[(w, f)] == cid
        else:
            assert cid not in ida.values()
    damped = read_sweep_file(make_sweep(tmp_path, GRID + '"contact.damping" = "300 N s/m"\n', "c.toml"))
    assert not {c.case_id for c in damped.cases} & set(ida.values())
    slower = read_sweep_file(make_sweep(tmp_path, GRID + '[solver]\noutput_rate = "500 Hz"\n', "d.toml"))
    assert not {c.case_id for c in slower.cases} & set(ida.values())


def test_model_version_is_part_of_the_id(tmp_path, monkeypatch):
    p = make_sweep(tmp_path, GRID)
    before = [c.case_id for c in read_sweep_file(p).cases]
    monkeypatch.setattr(sweepfile, "MODEL_VERSION", sweepfile.MODEL_VERSION + 1)
    after = [c.case_id for c in read_sweep_file(p).cases]
    assert not set(before) & set(after)


# --------------------------------------------------------------------------- errors

BAD = {
    "unknown top-level key": (GRID + "\n[extra]\nx = 1\n", "extra"),
    "misplaced operating point": ('speed = "120 deg/s"\n' + GRID.replace('speed = ["120 deg/s", "660 deg/s"]\n', ""), "speed"),
    "unknown axis": (GRID.replace("speed =", "sped ="), "axes.sped"),
    "unknown solver setting": (GRID + "[solver]\nstep_size = 1e-6\n", "solver.step_size"),
    "unknown key in a range": (GRID.replace('speed = ["120 deg/s", "660 deg/s"]',
                                            'speed = {start = "120 deg/s", stop = "660 deg/s", step = "60 deg/s", by = 1}'), "axes.speed.by"),
    "bad unit": (GRID.replace('"40 kN"', '"40 kg"'), "axes.radial_load[1]"),
    "unreadable unit": (GRID.replace('"10 kN"', '"10 kNewtons"'), "fixed.axial_load"),
    "bad solver unit": (GRID + '[solver]\noutput_rate = "1000 m"\n', "solver.output_rate"),
    "empty axis": (GRID.replace('["20 kN", "40 kN"]', "[]"), "axes.radial_load"),
    "range going down": (GRID.replace('["20 kN", "40 kN"]', '{start = "40 kN", stop = "20 kN", step = "5 kN"}'), "axes.radial_load"),
    "zero step": (GRID.replace('["20 kN", "40 kN"]', '{start = "20 kN", stop = "40 kN", step = "0 kN"}'), "axes.radial_load.step"),
    "duplicate value": (GRID.replace('["20 kN", "40 kN"]', '["20 kN", "20000 N"]'), "axes.radial_load[1]"),
    "missing axial load": (GRID.replace('axial_load = "10 kN"', ""), "axial_load"),
    "bearing value out of range": (GRID + '"rows[0].cage.pocket_clearance" = "-1 mm"\n', "fixed.rows[0].cage.pocket_clearance"),
    "unknown bearing key": (GRID + '"friction.mu_statik" = 0.1\n', "fixed.friction.mu_statik"),
    "index out of range": (GRID + '"rows[3].cage.width" = "20 mm"\n', "fixed.rows[3].cage.width"),
    "axes and cases": (GRID + '[[cases]]\nspeed = "1 rad/s"\n', "cases"),
    "no axes": ('[fixed]\naxial_load = "10 kN"\n', "axes"),
    "bad name": ('name = "a/b"\n' + GRID, "name"),
}


@pytest.mark.parametrize("what", sorted(BAD))
def test_bad_sweep_file_is_one_config_error_naming_file_and_key(tmp_path, what):
    body, key = BAD[what]
    p = make_sweep(tmp_path, body)
    with pytest.raises(ConfigError) as err:
        read_sweep_file(p)
    msg = str(err.value)
    assert "\n" not in msg
    assert str(p) in msg, msg
    assert err.value.key == key, msg


@pytest.mark.parametrize("which", ["bearing", "profile"])
def test_missing_bearing_or_profile_file(tmp_path, which):
    header = HEADER.replace("reduced-test.toml", "nope.toml").replace("short.toml", "nope.toml")
    p = make_sweep(tmp_path, GRID, header=header if which == "bearing" else HEADER.replace("short.toml", "nope.toml"))
    with pytest.raises(ConfigError) as err:
        read_sweep_file(p)
    assert err.value.key == which
    assert "no such" in str(err.value) and "nope.toml" in str(err.value)


def test_an_explicit_case_lacking_a_key_others_set(tmp_path):
    p = make_sweep(tmp_path, """
[fixed]
axial_load = "10 kN"
[[cases]]
speed = "120 deg/s"
radial_load = "30 kN"
[[cases]]
speed = "660 deg/s"
""")
    with pytest.raises(ConfigError) as err:
        read_sweep_file(p)
    assert err.value.key == "cases[1]" and "radial_load" in str(err.value)
