"""Profile files' optional ``[moment]`` and ``[load_direction]`` tables.

Values are checked against unit conversions done here (1 kN m = 1000 N m,
30 deg = π/6 rad); bad input must name the file, the key and the value.
"""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from pipeline.errors import ConfigError
from pipeline.schema import profile_from_dict, read_toml
from pipeline.schema import fields as schema
from pipeline.schema.parameters import parameter_table
from pipeline.schema.profilefile import CHANNELS
from rvcore import profile as core_profile
from rvcore.profile import CH_DIRECTION, CH_MOMENT, OperatingPoint

PROFILES = Path(__file__).resolve().parents[2] / "sweeps" / "profiles"
FILE = "duty.toml"


@pytest.fixture
def raw():
    return read_toml(PROFILES / "study.toml")


def test_channel_tables_are_in_the_core_channel_order():
    """The file's channel tables and rvcore.profile.CH_* name the same channels in the same order."""
    assert CHANNELS == ("radial_load", "axial_load", "speed", "moment", "load_direction")
    assert [getattr(core_profile, f"CH_{n}") for n in ("RADIAL", "AXIAL", "SPEED", "MOMENT", "DIRECTION")] \
        == list(range(len(CHANNELS)))
    assert len(CHANNELS) == core_profile.N_CHANNELS


def test_left_out_channels_keep_the_study_profile(raw):
    p = profile_from_dict(raw, FILE)
    assert p.moment is None and p.load_direction is None
    res = p.resolve(OperatingPoint(1.0, 30e3, 10e3, moment=500.0, load_angle=0.2))
    # the moment ramps with the load: half the load at half the load ramp (0.15 s of 0.3 s)
    assert res.value(CH_MOMENT, 0.15) == pytest.approx(250.0)
    assert res.value(CH_DIRECTION, 2.0) == 0.2


def test_moment_and_direction_tables(raw):
    raw["moment"] = {"time": ["0 s", "0.3 s", "4.3 s", "4.6 s"], "value": ["0 N m", "2 kN m", "2 kN m", "0 N m"]}
    raw["load_direction"] = {"time": ["0 s", "4.6 s"], "value": ["0 deg", "30 deg"], "interpolation": "smoothstep"}
    p = profile_from_dict(raw, FILE)
    assert not p.moment.relative and p.moment.values[1] == pytest.approx(2000.0)
    assert p.load_direction.values[1] == pytest.approx(math.pi / 6)
    assert p.load_direction.interpolation == "smoothstep"
    res = p.resolve(OperatingPoint(1.0, 30e3, 10e3, moment=99.0, load_angle=0.1))
    assert res.value(CH_MOMENT, 1.0) == pytest.approx(2000.0)            # absolute: not scaled
    assert res.value(CH_DIRECTION, 4.6) == pytest.approx(0.1 + math.pi / 6)
    # the parameter table lists what the file gives, in the display units
    rows = {r.key: r.value for r in parameter_table_rows(p)}
    assert rows["profile.moment.value"].endswith("N m")
    assert rows["profile.load_direction.value"].endswith("deg")


def parameter_table_rows(profile):
    from pipeline.schema import load_bearing
    bearing = load_bearing(Path(__file__).resolve().parents[2] / "sweeps" / "bearings" / "reduced-test.toml")
    return parameter_table(bearing, profile)


def test_moment_as_fractions(raw):
    raw["moment"] = {"time": ["0 s", "1 s"], "fraction": [0.5, 1.0]}
    p = profile_from_dict(raw, FILE)
    res = p.resolve(OperatingPoint(1.0, 30e3, 10e3, moment=400.0))
    assert res.value(CH_MOMENT, 0.0) == pytest.approx(200.0)


def _assert_refused(raw, key, value, words):
    """The loader refuses ``raw`` with an error naming the file, ``key`` and ``value``."""
    with pytest.raises(ConfigError) as info:
        profile_from_dict(raw, FILE)
    err = info.value
    assert err.file == FILE and err.key == key, str(err)
    assert str(err).startswith(f"{FILE}: {key}")
    if value is not None:
        assert err.value == value, str(err)
    for w in words:
        assert w in err.reason, str(err)


@pytest.mark.parametrize("table, key, value, words", [
    ({"time": ["0 s"], "fraction": [0.5]}, "load_direction.fraction", [0.5], ["only 'value'", "angle"]),
    ({"time": ["0 s"], "fraction": [0.5], "value": ["1 deg"]}, "load_direction.fraction", [0.5], ["only 'value'"]),
    ({"time": ["0 s"]}, "load_direction.value", None, ["missing"]),
    ({"time": ["0 s"], "value": ["3 N"]}, "load_direction.value[0]", "3 N", ["wrong units"]),
    ({"time": ["0 s", "1 s"], "value": ["3 deg"]}, "load_direction.value", ["3 deg"], ["1 entries", "2"]),
    ({"time": ["0 s"], "value": ["1 deg"], "offset": 1}, "load_direction.offset", 1, ["unknown key"]),
])
def test_bad_direction_tables(raw, table, key, value, words):
    raw["load_direction"] = table
    _assert_refused(raw, key, value, words)


@pytest.mark.parametrize("table, key, value, words", [
    ({"time": ["0 s"], "value": ["2 kN"]}, "moment.value[0]", "2 kN", ["wrong units"]),
    ({"time": ["0 s"], "value": ["2 kN m"], "fraction": [1]}, "moment", None, ["exactly one", "not both"]),
    ({"time": ["0 s", "9 s"], "fraction": [0, 1]}, "moment.time[1]", "9 s", ["after the end of the cycle"]),
    ({"value": ["2 kN m"]}, "moment.time", None, ["missing"]),
    ("2 kN m", "moment", "2 kN m", ["expected a table"]),
])
def test_bad_moment_tables(raw, table, key, value, words):
    raw["moment"] = table
    _assert_refused(raw, key, value, words)


def test_the_schema_lists_no_fraction_for_the_direction():
    assert schema.field("profile", "load_direction.fraction") is None
    assert schema.field("profile", "load_direction.value").unit == "deg"
    assert schema.field("profile", "moment.fraction") is not None
    assert schema.field("profile", "moment.value").unit_kind == "moment"


def test_a_stored_profile_reads_back_its_optional_channels(raw):
    """The read-back (pipeline.schema.stored.rebuild) of a profile with a moment and a
    load_direction channel gives the same Profile, each channel a Channel (an annotation
    ``Channel | None`` is a nested dataclass, not a plain value)."""
    from pipeline.schema.caseids import plain
    from pipeline.schema.stored import rebuild
    from rvcore.profile import Channel, Profile

    raw["moment"] = {"time": ["0 s", "1 s"], "value": ["0 kN m", "1 kN m"]}
    raw["load_direction"] = {"time": ["0 s"], "value": ["30 deg"]}
    p = profile_from_dict(raw, FILE)
    back = rebuild(Profile, plain(p), "profile")
    assert isinstance(back.moment, Channel) and isinstance(back.load_direction, Channel)
    assert back.moment.values == (0.0, 1000.0)
    assert back.load_direction.values == (math.pi / 6,)
    assert back == p
    assert rebuild(Profile, plain(profile_from_dict(read_toml(PROFILES / "study.toml"), FILE)),
                   "profile").moment is None


def test_a_fraction_in_load_direction_is_refused_with_its_own_reason(raw):
    """load_direction is an angle offset: a ``fraction`` there is refused with the reason, one
    line naming the key and the value, before any other unknown key of the table."""
    raw["load_direction"] = {"bogus": 1, "time": ["0 s"], "fraction": [0.5]}
    with pytest.raises(ConfigError) as e:
        profile_from_dict(raw, FILE)
    msg = str(e.value)
    assert msg.startswith(f"{FILE}: load_direction.fraction = [0.5]: ") and "\n" not in msg
    assert "a fraction of an angle means nothing" in msg
