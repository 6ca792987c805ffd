"""The bearing file's ``[lubricant]`` table: its default, its errors, and case ids.

The lubricant enters only the friction-moment estimate; the default lubricant is left out
of the hashed configuration (the ids pinned in tests/pipeline/test_regression.py), and a
lubricant other than the default gives new ids.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from pipeline.schema import bearing_from_dict, read_sweep_file, read_toml
from pipeline.schema.fields import field
from pipeline.schema.stored import stored_configuration

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


def test_default_is_iso_vg_68_and_grease(buildable_raw):
    b = bearing_from_dict(buildable_raw, file=FILE)
    assert b.lubricant.kinematic_viscosity == pytest.approx(68e-6, rel=1e-12)     # 68 mm²/s
    assert b.lubricant.method == "grease"
    assert "assumption" in field("bearing", "lubricant.kinematic_viscosity").doc


def test_viscosity_in_mm2_per_s(buildable_raw):
    raw = with_lubricant(buildable_raw, kinematic_viscosity="150 mm^2/s")
    assert bearing_from_dict(raw, file=FILE).lubricant.kinematic_viscosity == pytest.approx(150e-6, rel=1e-12)


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


def test_the_default_lubricant_keeps_case_ids_and_another_changes_them(tmp_path):
    """Written out at its default the table gives the same ids as leaving it out; another
    viscosity gives other ids; the stored configuration reads the lubricant back."""
    plain = read_sweep_file(make_sweep(tmp_path, GRID, "a.toml"))
    same = read_sweep_file(make_sweep(tmp_path, GRID + '"lubricant.kinematic_viscosity" = "68 mm^2/s"\n', "b.toml"))
    other = read_sweep_file(make_sweep(tmp_path, GRID + '"lubricant.kinematic_viscosity" = "100 mm^2/s"\n', "c.toml"))
    ids = [c.case_id for c in plain.cases]
    assert [c.case_id for c in same.cases] == ids
    assert not set(c.case_id for c in other.cases) & set(ids)
    assert stored_configuration(other.configuration).bearing.lubricant.kinematic_viscosity == pytest.approx(1e-4)
    assert stored_configuration(plain.configuration).bearing.lubricant.kinematic_viscosity == pytest.approx(68e-6)


def test_unknown_lubricant_key_is_one_line(buildable_raw):
    assert "lubricant" not in buildable_raw      # the table is optional: the default loads
    expect_error(bearing_from_dict, with_lubricant(buildable_raw, viscosity="68 mm^2/s"), "lubricant.viscosity",
                 None, ["unknown key"])
