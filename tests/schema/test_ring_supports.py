"""Flexible rings in the bearing file (issue 41, docs/inputs.md "Flexible rings"): the
[inner_ring.flexible] / [outer_ring.flexible] keys into RingSupport, the FE support file
(its per-order stiffness reproduces a Foundation given the same, computed here from the
Winkler foundation's energy), a rigid bearing's case id untouched, the stored
configuration read back, and every bad input one line naming the file and the key."""
from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from pipeline.errors import ConfigError
from pipeline.schema.bearingfile import bearing_from_dict
from pipeline.schema.ringfile import read_support_file
from pipeline.schema.tomlfile import read_toml
from rvcore.bearing.geometry import INNER, OUTER
from rvcore.rings.flexible import RIGID_RINGS, bearing_rings
from rvcore.rings.section import ring_section

ROOT = Path(__file__).resolve().parents[2]
REDUCED = ROOT / "sweeps" / "bearings" / "reduced-test.toml"
FLEXIBLE = ROOT / "sweeps" / "bearings" / "rv-main-flexible.toml"

K_R, K_A = 2e10, 5e9   # a seat's radial and axial stiffness per unit circumference [N m^-2]


def reduced(**tables) -> dict:
    raw = read_toml(REDUCED)
    raw = copy.deepcopy(raw)
    for ring, table in tables.items():
        raw.setdefault(f"{ring}_ring", {})["flexible"] = table
    return raw


def write(tmp_path, raw, name="b.toml") -> Path:
    path = tmp_path / name
    path.write_text(tomli_w.dumps(raw))
    return path


def foundation_table(n_orders: int, radius: float, unit_scale=1.0, compliance=False) -> str:
    """The per-order stiffness of a Winkler seat, from its energy ½∫k·w²·R dθ: for
    w = a·cos kθ, ½·k·a²·R·π (k ≥ 1) and ½·k·a²·R·2π (k = 0), so K_k = π·k·R, 2π·k·R."""
    lines = ["# a Winkler seat as an FE model would give it", "order,radial_stiffness,axial_stiffness",
             ",N/mm,N/mm"] if not compliance else ["order,radial_compliance,axial_compliance", "1,mm/N,mm/N"]
    for k in range(n_orders + 1):
        factor = 2 * math.pi if k == 0 else math.pi
        kr, ka = factor * K_R * radius, factor * K_A * radius
        if compliance:
            lines.append(f"{k},{1e3 / kr!r},{1e3 / ka!r}")
        else:
            lines.append(f"{k},{kr / 1e3!r},{ka / 1e3!r}")
    return "\n".join(lines) + "\n"


def test_a_rigid_bearing_has_no_ring_support_and_rigid_rings():
    b = bearing_from_dict(read_toml(REDUCED), REDUCED)
    assert b.inner_ring_support is None and b.outer_ring_support is None
    assert bearing_rings(b) is RIGID_RINGS


@pytest.mark.parametrize("compliance", [False, True])
def test_fe_file_reproduces_the_foundation_of_the_same_per_order_stiffness(tmp_path, compliance):
    seat = {"support": "foundation", "seat_radial_stiffness": f"{K_R / 1e6!r} N/mm^2",
            "seat_axial_stiffness": f"{K_A / 1e6!r} N/mm^2", "max_order": 30}
    found = bearing_from_dict(reduced(inner=seat), tmp_path / "f.toml")
    radius = ring_section(found, INNER).centroid_radius
    (tmp_path / "seat.csv").write_text(foundation_table(30, radius, compliance=compliance))
    fe = bearing_from_dict(reduced(inner={"support": "fe_file", "file": "seat.csv"}), tmp_path / "fe.toml")
    assert fe.inner_ring_support.max_order == 30   # the file's highest order by default
    a, b = bearing_rings(found), bearing_rings(fe)
    for d in ("inner_radial", "inner_axial"):
        np.testing.assert_allclose(getattr(b, d).stiffness, getattr(a, d).stiffness, rtol=1e-12)
        np.testing.assert_allclose(getattr(b, d).mass, getattr(a, d).mass, rtol=0)
    from rvcore.statics.equilibrium import solve_statics

    sa = solve_statics(found, 30e3, 10e3, rings=a, stiffness=False)
    sb = solve_statics(fe, 30e3, 10e3, rings=b, stiffness=False)
    # the same modes: the same equilibrium, to the rings' fixed point's tolerance (a change of
    # the raceways' displacements below 1e-12 m + 1e-6 of the largest: ~1e-6 of the loads)
    np.testing.assert_allclose(sb.ball_loads, sa.ball_loads, rtol=1e-5, atol=1e-3)


def test_housing_by_rectangle_and_by_properties_are_the_same(tmp_path):
    """A 280-320 x 40 mm rectangle: A = b·t, I_in = b·t³/12, I_out = t·b³/12 about its centre."""
    b_, t = 0.040, 0.020
    rect = {"support": "housing", "housing": {"inner_diameter": "280 mm", "outer_diameter": "320 mm",
                                              "width": "40 mm", "ground_radial_stiffness": "5e3 N/mm^2",
                                              "ground_axial_stiffness": "1e3 N/mm^2"}}
    spec = bearing_from_dict(reduced(inner=rect), tmp_path / "r.toml").inner_ring_support
    area, radius, i_in, i_out, j = spec.housing_section
    assert area == pytest.approx(b_ * t, rel=1e-12)
    assert radius == pytest.approx(0.150, rel=1e-12)
    assert i_in == pytest.approx(b_ * t ** 3 / 12, rel=1e-12)
    assert i_out == pytest.approx(t * b_ ** 3 / 12, rel=1e-12)
    given = copy.deepcopy(rect)
    given["housing"] = {"area": f"{area!r} m^2", "centroid_diameter": f"{2 * radius!r} m",
                        "i_in_plane": f"{i_in!r} m^4", "i_out_of_plane": f"{i_out!r} m^4",
                        "torsion_constant": f"{j!r} m^4", "ground_radial_stiffness": "5e3 N/mm^2",
                        "ground_axial_stiffness": "1e3 N/mm^2"}
    other = bearing_from_dict(reduced(inner=given), tmp_path / "g.toml").inner_ring_support
    np.testing.assert_allclose(other.housing_section, spec.housing_section, rtol=1e-12)
    assert spec.seat_radial == math.inf and spec.housing_material is None


def test_the_shipped_flexible_bearing_loads_with_both_rings_on_housings():
    b = bearing_from_dict(read_toml(FLEXIBLE), FLEXIBLE)
    assert b.inner_ring_support.kind == b.outer_ring_support.kind == "housing"
    rings = bearing_rings(b)
    assert not rings.rigid and rings.outer_radial is not None
    # the outer ring's own section from its envelope: 366.8-383 mm x 30 mm less the groove
    assert ring_section(b, OUTER, other_diameter=0.3668).area == pytest.approx(
        rings.outer_radial.mass[1] / (math.pi * b.ring_material.density * rings.outer_radial.radius) / 2, rel=1e-12)


def test_the_rigid_case_id_is_unchanged_by_the_new_fields():
    """A rigid bearing's plain form (what is hashed) has no ring-support key: None is dropped."""
    from pipeline.schema.caseids import plain

    b = bearing_from_dict(read_toml(REDUCED), REDUCED)
    assert not {"inner_ring_support", "outer_ring_support"} & set(plain(b))


def test_the_stored_configuration_reads_a_flexible_bearing_back():
    from pipeline.schema.caseids import plain
    from pipeline.schema.stored import rebuild
    import tomllib

    b = bearing_from_dict(read_toml(FLEXIBLE), FLEXIBLE)
    text = tomli_w.dumps({"bearing": {k: v for k, v in plain(b).items() if k != "extra"}})
    back = rebuild(type(b), tomllib.loads(text)["bearing"], "bearing")
    assert back.inner_ring_support == b.inner_ring_support
    assert back.outer_ring_support == b.outer_ring_support


def _refused(tmp_path, raw, key, reason, file=None):
    with pytest.raises(ConfigError) as err:
        bearing_from_dict(raw, file or (tmp_path / "bad.toml"))
    msg = str(err.value)
    assert "\n" not in msg and key in msg and reason in msg, msg
    return msg


@pytest.mark.parametrize("table, key, reason", [
    ({"max_order": 10}, "inner_ring.flexible.support", "missing required key"),
    ({"support": "seat"}, "inner_ring.flexible.support", "must be one of"),
    ({"support": "foundation", "seat_radial_stiffness": "1e4 N/mm^2"}, "inner_ring.flexible.seat_axial_stiffness",
     "missing"),
    ({"support": "foundation", "seat_radial_stiffness": "1e4 N/mm", "seat_axial_stiffness": "1e4 N/mm^2"},
     "inner_ring.flexible.seat_radial_stiffness", "wrong units"),
    ({"support": "foundation", "seat_radial_stiffness": "1e4 N/mm^2", "seat_axial_stiffness": "1e4 N/mm^2",
      "file": "x.csv"}, "inner_ring.flexible.file", "does not apply"),
    ({"support": "foundation", "seat_radial_stiffness": "1e4 N/mm^2", "seat_axial_stiffness": "1e4 N/mm^2",
      "section": {"area": "300 mm^2"}}, "inner_ring.flexible.section.centroid_diameter", "all of"),
    ({"support": "foundation", "seat_radial_stiffness": "1e4 N/mm^2", "seat_axial_stiffness": "1e4 N/mm^2",
      "max_order": 1}, "inner_ring.flexible.max_order", "at least 2"),
    ({"support": "foundation", "seat_radial_stiffness": "1e4 N/mm^2", "seat_axial_stiffness": "1e4 N/mm^2",
      "damping_ratio": 1.5}, "inner_ring.flexible.damping_ratio", "between 0 and 1"),
    ({"support": "housing"}, "inner_ring.flexible.housing", "missing required table"),
    ({"support": "housing", "housing": {"inner_diameter": "280 mm", "outer_diameter": "320 mm"}},
     "inner_ring.flexible.housing.width", "rectangular"),
    ({"support": "housing", "housing": {"inner_diameter": "280 mm", "outer_diameter": "320 mm", "width": "40 mm"}},
     "inner_ring.flexible", "no stiffness"),   # a free housing does not hold the ring's rigid-body orders
    ({"support": "fe_file"}, "inner_ring.flexible.file", "missing"),
    ({"support": "fe_file", "file": "absent.csv"}, "inner_ring.flexible.file", "cannot read"),
])
def test_bad_flexible_ring_keys_are_one_line(tmp_path, table, key, reason):
    _refused(tmp_path, reduced(inner=table), key, reason)


def test_outer_ring_needs_its_shoulder_diameter_or_a_section(tmp_path):
    table = {"support": "foundation", "seat_radial_stiffness": "1e4 N/mm^2", "seat_axial_stiffness": "1e4 N/mm^2"}
    _refused(tmp_path, reduced(outer=table), "outer_ring.flexible.shoulder_diameter", "missing")
    ok = bearing_from_dict(reduced(outer={**table, "shoulder_diameter": "366.8 mm"}), tmp_path / "ok.toml")
    assert ok.outer_ring_support.shoulder_diameter == pytest.approx(0.3668)


def _csv(tmp_path, text) -> Path:
    path = tmp_path / "fe.csv"
    path.write_text(text)
    return path


@pytest.mark.parametrize("text, where, reason", [
    ("order,radial,axial\n,N/m,N/m\n0,1,1\n", "line 1", "the columns must be"),
    ("order,radial_stiffness,axial_stiffness\n,N/m,N\n0,1,1\n1,1,1\n2,1,1\n", "line 2, axial_stiffness",
     "wrong units"),
    ("order,radial_stiffness,axial_stiffness\n,N/m,N/m\n0,1,1\n2,1,1\n", "line 4, order", "in order"),
    ("order,radial_stiffness,axial_stiffness\n,N/m,N/m\n0,1,1\n1,-1,1\n2,1,1\n", "line 4, radial_stiffness",
     ">= 0"),
    ("order,radial_stiffness,axial_stiffness\n,N/m,N/m\n0,1,1\n1,1,x\n2,1,1\n", "line 4, axial_stiffness", ">= 0"),
    ("order,radial_stiffness,axial_stiffness\n,N/m,N/m\n0,1,1\n1,1\n", "line 4", "one value per column"),
    ("order,radial_stiffness,axial_stiffness\n,N/m,N/m\n0,1,1\n1,1,1\n", None, "at least"),
    ("order,radial_stiffness,axial_stiffness\n,N/m,N/m\n0,1,1\n1,0,1\n2,1,1\n", "order 1, radial_stiffness",
     "must hold it"),
    ("order,radial_stiffness,axial_stiffness\nm,N/m,N/m\n0,1,1\n1,1,1\n2,1,1\n", "line 2, order", "no unit"),
])
def test_bad_fe_files_are_one_line_naming_the_line_and_column(tmp_path, text, where, reason):
    path = _csv(tmp_path, text)
    with pytest.raises(ConfigError) as err:
        read_support_file(path)
    msg = str(err.value)
    assert "\n" not in msg and str(path) in msg and reason in msg, msg
    if where:
        assert where in msg, msg


def test_max_order_beyond_the_fe_file_is_refused(tmp_path):
    _csv(tmp_path, "order,radial_stiffness,axial_stiffness\n,N/m,N/m\n0,1e9,1e9\n1,1e9,1e9\n2,1e9,1e9\n")
    _refused(tmp_path, reduced(inner={"support": "fe_file", "file": "fe.csv", "max_order": 5}),
             "inner_ring.flexible.max_order", "orders up to 2")


def test_a_quoted_csv_and_comments_are_read(tmp_path):
    path = _csv(tmp_path, '# from the FE model\n"order","radial_compliance","axial_compliance"\n'
                          '"","um/kN","um/kN"\n0,0.5,2\n1,1,4\n# midway comment\n2,2,0\n')
    orders, radial, axial = read_support_file(path)
    assert orders == (0, 1, 2)
    assert radial == pytest.approx((2e9, 1e9, 0.5e9), rel=1e-12)   # 1 / (c um/kN) in N/m
    assert axial[:2] == pytest.approx((0.5e9, 0.25e9), rel=1e-12) and axial[2] == math.inf
