"""The schema (pipeline.schema.fields): it covers every key the loaders accept and only
those; the one --set parser; the report's parameter table; one-line errors."""
from __future__ import annotations

import argparse
import copy
import math
import re
from pathlib import Path

import pytest

from pipeline.errors import ConfigError
from pipeline.schema import (FIELDS, REQUIRED, ParameterRow, apply_override, bearing_from_dict,
                             check_set_key, load_bearing, load_profile, parameter_table, parse_quantity,
                             parse_set, parse_sets, profile_from_dict, read_toml, sweep_from_dict)
from pipeline.schema import fields as schema
from pipeline.schema.shipped import DEFAULT_BEARING, DEFAULT_PROFILE, shipped_file
from pipeline.schema.tomlfile import lookup

ROOT = Path(__file__).resolve().parents[2]
SWEEPS = ROOT / "sweeps"
BEARING_FILES = sorted((SWEEPS / "bearings").glob("*.toml"))
PROFILE_FILES = sorted((SWEEPS / "profiles").glob("*.toml"))
SWEEP_FILES = sorted(SWEEPS.glob("*.toml"))


def leaf_paths(node, prefix=""):
    """Every value's key path in a TOML document (arrays of tables get indices)."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from leaf_paths(v, f"{prefix}.{k}" if prefix else k)
    elif isinstance(node, list) and node and all(isinstance(x, dict) for x in node):
        for i, x in enumerate(node):
            yield from leaf_paths(x, f"{prefix}[{i}]")
    else:
        yield prefix


# --------------------------------------------------------------------------- coverage


def test_the_shipped_files_exist():
    assert BEARING_FILES and PROFILE_FILES and SWEEP_FILES


@pytest.mark.parametrize("path", BEARING_FILES, ids=lambda p: p.name)
def test_every_key_of_every_shipped_bearing_is_in_the_schema(path):
    for key in leaf_paths(read_toml(path)):
        assert schema.field("bearing", key) is not None, key


@pytest.mark.parametrize("path", PROFILE_FILES, ids=lambda p: p.name)
def test_every_key_of_every_shipped_profile_is_in_the_schema(path):
    for key in leaf_paths(read_toml(path)):
        assert schema.field("profile", key) is not None, key


@pytest.mark.parametrize("path", SWEEP_FILES, ids=lambda p: p.name)
def test_every_solver_and_operating_point_key_of_every_shipped_sweep_is_in_the_schema(path):
    raw = read_toml(path)
    for key in raw.get("solver", {}):
        assert schema.field("solver", f"solver.{key}") is not None, key
    for key in raw.get("fixed", {}):
        assert schema.check_set_key(key) is not None, key
    for key in raw.get("axes", {}):
        assert schema.check_set_key(key) is not None, key


def _sample(f):
    """A valid value for field ``f`` as a file would write it (SI numbers)."""
    if f.default is not REQUIRED and not (isinstance(f.default, str) and f.default.startswith(("<", "(", "from"))):
        return list(f.default) if isinstance(f.default, tuple) else f.default
    leaf = f.path.rsplit(".", 1)[-1]
    imperfection = {"tolerance_class": "5", "ball_grade": "G10", "inner_eccentricity": "10 um",
                    "outer_eccentricity": "5 um", "inner_eccentricity_angle": "30 deg",
                    "outer_eccentricity_angle": "-30 deg", "inner_axial_amplitude": "8 um",
                    "outer_axial_amplitude": "4 um", "inner_axial_angle": "10 deg", "outer_axial_angle": "-10 deg"}
    if "imperfections" in f.path and leaf in imperfection:
        return imperfection[leaf]
    return {"gravity": [0.0, -9.81, 0.0], "dynamic_load_rating": "23.4 kN", "name": "x", "description": "d", "source": "s",
            "lubricant.kinematic_viscosity": "68 mm^2/s", "lubricant.viscosity_40": "100 mm^2/s",
            "lubricant.viscosity_100": "8.5 mm^2/s"}.get(f.path)


#: A valid [<ring>_ring.flexible] table for each of its keys (pipeline.schema.ringfile):
#: the support that takes the key, the key given.
_SEAT = {"seat_radial_stiffness": "1e4 N/mm^2", "seat_axial_stiffness": "1e4 N/mm^2"}
_SECTION = {"area": "250 mm^2", "centroid_diameter": "334 mm", "i_in_plane": "5000 mm^4",
            "i_out_of_plane": "30000 mm^4", "torsion_constant": "15000 mm^4"}
_GROUND = {"ground_radial_stiffness": "5e3 N/mm^2", "ground_axial_stiffness": "1e3 N/mm^2"}


def _flexible_table(ring: str, leaf: str) -> dict:
    shoulder = {"shoulder_diameter": "366.8 mm"} if ring == "outer" else {}
    if leaf == "file":
        return {"support": "fe_file", "file": str(SWEEPS / "bearings" / "supports" / "carrier-fe.csv"), **shoulder}
    if leaf.startswith("housing."):
        given = leaf.split(".")[1] in _SECTION
        housing = {**(_SECTION if given else {"inner_diameter": "280 mm", "outer_diameter": "320 mm",
                                              "width": "40 mm"}), **_GROUND,
                   "material": {"density": "7850 kg/m^3", "youngs_modulus": "206 GPa", "poisson_ratio": 0.3}}
        return {"support": "housing", "housing": housing, **shoulder}
    if leaf.startswith("section."):
        return {"support": "foundation", **_SEAT, "section": dict(_SECTION)}
    return {"support": "foundation", **_SEAT, **shoulder, "max_order": 12, "damping_ratio": 0.05}


def _with_bearing_field(raw, f):
    raw = copy.deepcopy(raw)
    if f.path.startswith(("inner_ring.flexible.", "outer_ring.flexible.")):
        ring, _, leaf = f.path.partition("_ring.flexible.")
        raw.setdefault(f"{ring}_ring", {})["flexible"] = _flexible_table(ring, leaf)
        return raw, f.path
    head = f.path.split(".")[0]
    if head in ("ring_material", "ball_material"):
        mat = raw.pop("material")
        raw["ring_material"], raw["ball_material"] = dict(mat), dict(mat)
    if f.path == "lubricant.viscosity_40":   # the base oil's two points go together
        raw["lubricant"] = {"viscosity_100": "11 mm^2/s"}
    if f.path == "gravity":
        raw.pop("mounting", None)
        raw["assumptions"] = [a for a in raw.get("assumptions", []) if a != "mounting"]
    key = f.path.replace("[]", "[0]")
    if f.path.startswith("pair.imperfections[]"):   # two entries, one per row of the pair
        leaf = f.path.split("].", 1)[1]
        if "_waviness[]" in leaf:
            value = {leaf.split("[]")[0]: [{"order": 13, "amplitude": "0.5 um", "phase": "20 deg"}]}
        elif leaf == "ball_diameter_deviation":
            value = {leaf: ["0.1 um"] * raw["rows"][0]["balls"]["count"]}
        else:
            value = {leaf: _sample(f)}
        raw["pair"]["imperfections"] = [dict(value), dict(value)]
        return raw, f.path.replace("[]", "[0]")
    if "_waviness[]" in f.path:   # one harmonic, every key of it
        table = f.path.split("_waviness[]")[0] + "_waviness"
        node = raw
        parts = table.replace("rows[].", "rows[0].").split(".")
        for part in parts[:-1]:
            node = node["rows"][0] if part == "rows[0]" else node.setdefault(part, {})
        node[parts[-1]] = [{"order": 13, "amplitude": "0.5 um", "phase": "20 deg"}]
    if f.path.endswith("ball_diameter_deviation"):   # one per ball of the row
        count = raw["rows"][0]["balls"]["count"]
        node = raw["rows"][0] if f.path.startswith("rows") else raw
        node.setdefault("imperfections", {})["ball_diameter_deviation"] = ["0.1 um"] * count
    if lookup(raw, key, None) is None:
        parts = key.split(".")
        node = raw
        for part in parts[:-1]:
            node = node["rows"][0] if part == "rows[0]" else node.setdefault(part, {})
        node[parts[-1]] = _sample(f)
    return raw, key


@pytest.mark.filterwarnings("ignore::pipeline.errors.UnitlessNumberWarning")   # the samples are SI numbers
@pytest.mark.parametrize("f", schema.fields_of("bearing"), ids=lambda f: f.path)
def test_every_bearing_field_is_accepted_by_the_loader(f):
    base = read_toml(shipped_file(DEFAULT_BEARING))
    if f.path.startswith("pair."):   # a pair's keys, in the shipped pair
        base = read_toml(shipped_file("bearings/rv-main-pair.toml"))
        if f.path == "pair.preload_offset":   # one of preload / preload_offset
            del base["pair"]["preload"]
    raw, key = _with_bearing_field(base, f)
    assert lookup(raw, key, None) is not None
    bearing_from_dict(raw, "x.toml")


@pytest.mark.filterwarnings("ignore::pipeline.errors.UnitlessNumberWarning")   # the samples are SI numbers
@pytest.mark.parametrize("f", schema.fields_of("profile"), ids=lambda f: f.path)
def test_every_profile_field_is_accepted_by_the_loader(f):
    raw = read_toml(shipped_file(DEFAULT_PROFILE))
    channel, _, leaf = f.path.partition(".")
    if channel in schema.profile_channels() and channel not in raw:   # an optional channel table
        raw[channel] = {"time": ["0 s"], "fraction" if leaf == "fraction" else "value": [0.0]}
    if leaf == "value" and "fraction" in raw[channel]:
        raw[channel]["value"] = raw[channel].pop("fraction")
    elif f.path not in ("name", "description") and lookup(raw, f.path, None) is None:
        raw[channel][leaf] = _sample(f)
    if f.path == "description":
        raw["description"] = "d"
    assert lookup(raw, f.path, None) is not None
    profile_from_dict(raw, "p.toml")


@pytest.mark.filterwarnings("ignore::pipeline.errors.UnitlessNumberWarning")   # the samples are SI numbers
def test_every_solver_field_is_accepted_in_a_sweep(tmp_path):
    solver = {f.path.split(".", 1)[1]: f.default for f in schema.fields_of("solver")}
    raw = {"bearing": str(shipped_file(DEFAULT_BEARING)), "profile": str(shipped_file(DEFAULT_PROFILE)),
           "solver": solver, "cases": [{"speed": "120 deg/s", "radial_load": "30 kN", "axial_load": "10 kN"}]}
    sweep = sweep_from_dict(raw, tmp_path / "s.toml")
    assert set(solver) == {f for f in sweep.settings.__dataclass_fields__}


@pytest.mark.parametrize("key", ["rows[0].balls.colour", "friction.mu_kinetic", "envelope.depth", "extra"])
def test_a_key_not_in_the_schema_is_rejected_by_the_loader(key):
    raw = read_toml(shipped_file(DEFAULT_BEARING))
    assert schema.field("bearing", key) is None
    parts = key.replace("[0]", ".0").split(".")
    node = raw
    for part in parts[:-1]:
        node = node[int(part)] if part.isdigit() else node[part]
    node[parts[-1]] = 1
    with pytest.raises(ConfigError, match="unknown key") as e:
        bearing_from_dict(raw, "x.toml")
    assert e.value.key == key


def test_every_field_has_a_kind_a_doc_and_a_unit_kind_when_it_is_a_quantity():
    from pipeline.schema.units import SI_UNITS, format_quantity

    assert len({(f.file, f.path) for f in FIELDS}) == len(FIELDS)
    for f in FIELDS:
        assert f.kind in schema.KINDS and f.doc, f.path
        if f.kind == "quantity":
            assert f.unit_kind in SI_UNITS, f.path
            if f.unit:   # the display unit converts from the SI unit
                format_quantity(1.0, f.unit, f.unit_kind)
        if f.kind == "choice":
            assert f.choices


def test_solver_fields_are_exactly_those_of_solver_settings():
    from rvcore.simulation.settings import SolverSettings

    assert set(schema.solver_fields()) == set(SolverSettings.__dataclass_fields__)


def test_the_sweep_module_keeps_no_kind_table_of_its_own():
    import pipeline.schema.sweepaxes as sweepaxes
    import pipeline.schema.sweepfile as sweepfile

    for mod in (sweepfile, sweepaxes):
        assert not hasattr(mod, "_KEY_KINDS") and not hasattr(mod, "SOLVER_KINDS")


# --------------------------------------------------------------------------- --set


@pytest.mark.parametrize("item, expected", [
    ("friction.mu_static=0.05", ("friction.mu_static", 0.05)),
    ("rows[0].balls.count=40", ("rows[0].balls.count", 40)),
    ("rows[0].cage.pocket_clearance = 0.3 mm", ("rows[0].cage.pocket_clearance", "0.3 mm")),
    ("solver.gravity=false", ("solver.gravity", False)),
    ("solver.friction=True", ("solver.friction", True)),
    ('rows[0].cage.guidance="ball"', ("rows[0].cage.guidance", "ball")),
    ("rows[0].cage.guidance='ball'", ("rows[0].cage.guidance", "ball")),
])
def test_parse_set(item, expected):
    assert parse_set(item) == expected


@pytest.mark.parametrize("item, reason", [
    ("friction.mu_static", "expected KEY=VALUE"),
    ("=3", "expected KEY=VALUE"),
    ("friction..mu=3", "not a key path"),
    ("friction.mu_static=", "no value"),
])
def test_bad_set_items_are_one_line_errors(item, reason):
    with pytest.raises(ConfigError, match=reason) as e:
        parse_set(item)
    assert str(e.value).startswith("--set") and "\n" not in str(e.value)


def test_a_key_given_twice_is_an_error():
    with pytest.raises(ConfigError, match="given twice"):
        parse_sets(["solver.step_safety=0.5", "solver.step_safety=0.4"])


def test_apply_override_reads_values_with_the_same_parser():
    raw = read_toml(shipped_file(DEFAULT_BEARING))
    for text in ("40", "0.05", "true", '"ball"', "0.3 mm"):
        key, value = parse_set(f"x={text}")
        new = apply_override(raw, "rows[0].cage.width", text)
        assert new["rows"][0]["cage"]["width"] == value


def test_unknown_set_keys_name_the_known_ones():
    with pytest.raises(ConfigError) as e:
        check_set_key("friction.mu_kinetic", 0.1)
    assert "friction.mu_static" in str(e.value) and "--fields" in str(e.value)
    assert check_set_key("profile.duration").unit_kind == "time"
    assert check_set_key("speed").file == "operating_point"


def test_the_one_case_commands_take_set_through_the_one_parser():
    from pipeline.commands.common import one_case_sweep

    args = argparse.Namespace(
        bearing="bearings/rv-main-buildable.toml", speed="120 deg/s", radial_load="30 kN",
        axial_load="10 kN", moment="0 N*m", load_angle="0 deg",
        set=["friction.mu_static=0.05", "solver.output_rate=2 kHz", "rows[0].cage.pocket_clearance=0.3 mm",
             "profile.duration=4.8 s"])
    case = one_case_sweep(args, profile=None).cases[0]
    assert case.bearing.contact.mu_static == 0.05
    assert case.settings.output_rate == pytest.approx(2000.0)
    assert case.bearing.rows[0].cage.pocket_clearance == pytest.approx(0.3e-3)
    assert case.profile.duration == pytest.approx(4.8)
    args.set = ["friction.mu_kinetic=0.05"]
    with pytest.raises(ConfigError, match="unknown bearing key"):
        one_case_sweep(args, profile=None)


# --------------------------------------------------------------------------- parameter table


@pytest.fixture(scope="module")
def study():
    return load_bearing(shipped_file(DEFAULT_BEARING)), load_profile(shipped_file(DEFAULT_PROFILE))


def test_parameter_rows_round_trip_to_the_loaded_values(study):
    bearing, profile = study
    rows = {r.key: r for r in parameter_table(bearing, profile)}
    assert all(isinstance(r, ParameterRow) for r in rows.values())
    assert len(rows) == len(parameter_table(bearing, profile))            # keys are unique
    checks = {
        "rows[0].balls.diameter": bearing.rows[0].ball_diameter,
        "envelope.bore": bearing.bore,
        "material.youngs_modulus": bearing.ring_material.youngs_modulus,
        "rows[0].inner_groove.arcs[0].contact_angle": bearing.rows[0].inner_arcs[0].contact_angle,
        "contact.damping": bearing.contact.damping,
        "profile.duration": profile.duration,
    }
    for key, si in checks.items():
        f = schema.field("profile", key.removeprefix("profile.")) if key.startswith("profile.") \
            else schema.field("bearing", key)
        assert rows[key].value.endswith(f" {f.unit}")                        # display unit
        assert parse_quantity(rows[key].value, f.unit_kind) == pytest.approx(si)
        assert rows[key].doc == f.doc
    assert rows["rows[0].balls.count"].value == str(bearing.rows[0].ball_count)


def test_parameter_rows_mark_the_assumptions(study):
    bearing, profile = study
    rows = parameter_table(bearing, profile)
    for r in rows:
        listed = any(r.key == a or r.key.startswith((a + ".", a + "[")) for a in bearing.assumptions)
        assert r.assumed == listed, r.key
    by_key = {r.key: r for r in rows}
    # A table in the list marks the values in it; a key outside it is not assumed.
    assert "rows[0].inner_groove.arcs" in bearing.assumptions
    assert by_key["rows[0].inner_groove.arcs[0].curvature_ratio"].assumed
    assert "rows[0].balls.diameter" not in bearing.assumptions
    assert not by_key["rows[0].balls.diameter"].assumed


def test_parameter_table_covers_every_value_the_file_gives(study):
    bearing, _ = study
    keys = {r.key for r in parameter_table(bearing)}
    raw = read_toml(shipped_file(DEFAULT_BEARING))
    metadata = {"description", "source", "assumptions"}
    for key in leaf_paths(raw):
        if key in metadata:
            continue
        item = key.rsplit("[", 1)[0] if key.endswith("]") else key
        assert key in keys or item in keys, key


def test_parameter_table_shows_two_materials_when_the_file_gives_two():
    raw = read_toml(shipped_file("bearings/rv-main-buildable.toml"))
    ring = raw.pop("material")
    raw["ring_material"] = dict(ring)
    raw["ball_material"] = dict(ring, youngs_modulus="310 GPa")     # ceramic balls
    keys = {r.key: r.value for r in parameter_table(bearing_from_dict(raw, "x.toml"))}
    assert "material.density" not in keys
    assert parse_quantity(keys["ball_material.youngs_modulus"], "pressure") == pytest.approx(310e9)
    assert parse_quantity(keys["ring_material.youngs_modulus"], "pressure") == \
        pytest.approx(parse_quantity(ring["youngs_modulus"], "pressure"))


# --------------------------------------------------------------------------- errors


@pytest.mark.parametrize("key, value, reason", [
    ("rows[0].balls.diameter", "-3 mm", "must be positive"),
    ("friction.mu_static", "3 kN", "wrong units"),
    ("rows[0].inner_groove.arcs[0].contact_angle", "95 deg", "between -90 and 90 deg"),
    ("material.poisson_ratio", 0.6, "between -1 and 0.5"),
    ("rows[0].cage.guidance", "floating", "must be one of"),
    ("rows[0].balls.count", 2.5, "must be an integer"),
    ("contact.damping", "-1 N s/m", "must not be negative"),
    ("allow_ball_overlap", "yes", "must be true or false"),
])
def test_bad_values_give_one_line_errors_naming_file_key_value_reason(key, value, reason):
    raw = apply_override(read_toml(shipped_file(DEFAULT_BEARING)), key, value)
    raw = _set(raw, key, value)
    with pytest.raises(ConfigError) as e:
        bearing_from_dict(raw, "some/bearing.toml")
    msg = str(e.value)
    assert "\n" not in msg
    assert msg.startswith(f"some/bearing.toml: {key} = {value!r}: ")
    assert reason in msg


def _set(raw, key, value):
    """Set the value exactly as given (apply_override reads strings as TOML literals)."""
    parts = key.replace("]", "").replace("[", ".").split(".")
    node = raw
    for part in parts[:-1]:
        node = node[int(part)] if part.isdigit() else node[part]
    node[parts[-1]] = value
    return raw


@pytest.mark.parametrize("where", ["imperfections", "rows[0].imperfections"])
def test_more_waviness_terms_than_the_kernels_hold_is_one_line_naming_the_table(where):
    from rvcore.bearing.imperfections import MAX_WAVINESS_TERMS

    raw = read_toml(shipped_file("bearings/reduced-test.toml"))
    terms = [{"order": k + 2, "amplitude": "0.01 um"} for k in range(MAX_WAVINESS_TERMS + 1)]
    table = raw if where == "imperfections" else raw["rows"][0]
    table["imperfections"] = {"outer_waviness": terms}
    with pytest.raises(ConfigError) as e:
        bearing_from_dict(raw, "b.toml")
    assert e.value.key == f"{where}.outer_waviness"
    assert f"{MAX_WAVINESS_TERMS + 1} terms: at most {MAX_WAVINESS_TERMS}" in str(e.value)
    table["imperfections"] = {"outer_waviness": terms[:MAX_WAVINESS_TERMS]}
    assert len(bearing_from_dict(raw, "b.toml").rows[0].imperfections.outer_waviness) == MAX_WAVINESS_TERMS


def test_the_land_values_are_required_for_an_outer_land_guided_cage_only():
    raw = read_toml(shipped_file(DEFAULT_BEARING))
    assert raw["rows"][0]["cage"]["guidance"] == "outer-land"
    del raw["rows"][0]["cage"]["land_clearance"]
    raw["assumptions"] = [a for a in raw["assumptions"] if a != "rows[0].cage.land_clearance"]
    with pytest.raises(ConfigError, match="missing required key") as e:
        bearing_from_dict(raw, "b.toml")
    assert e.value.key == "rows[0].cage.land_clearance"
    raw["rows"][0]["cage"]["guidance"] = "ball"
    assert bearing_from_dict(raw, "b.toml").rows[0].cage.land_clearance == schema.field(
        "bearing", "rows[].cage.land_clearance").default
    assert math.isfinite(bearing_from_dict(raw, "b.toml").rows[0].cage.land_stiffness)


def _attribute(obj, source: str, indices: list):
    """The value at a field's ``source`` (``rows[].inner_arcs[].contact_angle``), each ``[]``
    taken as the next of ``indices``."""
    indices = list(indices)
    for part in source.split("."):
        name, listed = part.removesuffix("[]"), part.endswith("[]")
        obj = getattr(obj, name)
        if listed:
            obj = obj[indices.pop(0)]
    return obj


def _with_every_table(path):
    """A shipped bearing file and, beside it, the reduced test bearing with imperfections
    written at the bearing's level and at its row's, a lubricant and temperatures: every
    table a (non-pair) file may hold."""
    raw = read_toml(path)
    if path.name == "reduced-test.toml":
        raw["imperfections"] = {"tolerance_class": "5", "outer_eccentricity": "1 um",
                                "outer_waviness": [{"order": 5, "amplitude": "0.1 um", "phase": "10 deg"}]}
        raw["rows"][0]["imperfections"] = {"inner_eccentricity": "2 um", "inner_eccentricity_angle": "30 deg",
                                           "inner_waviness": [{"order": 3, "amplitude": "0.2 um"},
                                                              {"order": 7, "amplitude": "0.05 um"}],
                                           "ball_grade": "G10"}
        raw["lubricant"] = {"method": "oil-bath", "grade": 100, "viscosity_100": "11 mm^2/s",
                            "density": "870 kg/m^3", "ep_additives": True}
        raw["temperature"] = {"reference": "20 degC"}
    return raw


@pytest.mark.parametrize("path", [p for p in BEARING_FILES if "pair" not in p.name], ids=lambda p: p.name)
def test_every_value_written_in_a_shipped_bearing_lands_where_its_field_says(path):
    """The loader reads the dataclasses by the field table (``Field.source``): each quantity,
    integer, boolean and choice written in the file, converted on its own here, is the value
    at the field's ``source`` in the built Bearing (arcs, waviness terms and imperfections
    included: a key's indices are the source's, a bearing-wide imperfection lands in row 0);
    and that source is the attribute of the key's own name (or its one documented rename),
    so the table cannot map a key elsewhere."""
    from pipeline.schema.bearingfile import SET_ELSEWHERE

    renamed = {"balls.count": "ball_count", "balls.diameter": "ball_diameter", "envelope.bore": "bore",
               "envelope.outer_diameter": "outer_diameter", "envelope.width": "width",
               "temperature.reference": "reference_temperature"}
    raw = _with_every_table(path)
    bearing = bearing_from_dict(raw, path)
    checked = 0
    for key in leaf_paths(raw):
        f = schema.field("bearing", key)
        if f is None or f.source is None or f.source in SET_ELSEWHERE or f.kind == "list":
            continue
        if f.path.startswith("material."):   # [material]: rings and balls alike
            sources = [f.source, f.source.replace("ring_material", "ball_material")]
        else:
            sources = [f.source]
        indices = [int(i) for i in re.findall(r"\[(\d+)\]", key)]
        indices = [0] * (f.source.count("[]") - len(indices)) + indices   # bearing-wide: row 0
        tail = ".".join(f.path.split(".")[-2:])
        assert f.source.split(".")[-1] == renamed.get(tail, f.path.split(".")[-1]), (f.path, f.source)
        written = lookup(raw, key)
        expected = parse_quantity(written, f.unit_kind) if f.kind == "quantity" else written
        for source in sources:
            if source == "rows[].radial_clearance" and bearing.nominal_radial_clearances:
                # given at the reference temperature; the row's is the operating one
                got = bearing.nominal_radial_clearances[indices[0]]
            else:
                got = _attribute(bearing, source, indices)
            assert got == expected, (key, source)
            checked += 1
    assert checked >= 20


def _dataclass_paths(cls, prefix=""):
    """Every attribute path of dataclass ``cls``, through nested dataclasses and
    ``tuple[X, ...]`` items (``rows[].cage.material.density``)."""
    import dataclasses
    import typing

    for d in dataclasses.fields(cls):
        at = f"{prefix}.{d.name}" if prefix else d.name
        hint = typing.get_type_hints(cls)[d.name]
        item = schema.item_class(hint)
        if item is not None:
            yield from _dataclass_paths(item, f"{at}[]")
        elif schema.dataclass_of(hint) is not None:   # Cage, or Channel | None
            yield from _dataclass_paths(schema.dataclass_of(hint), at)
        else:
            yield at


@pytest.mark.parametrize("file", ["bearing", "profile"])
def test_every_attribute_is_read_by_the_field_table_or_set_elsewhere_once(file):
    """The converter's one map: each attribute of the Bearing (rows, arcs, cage, materials,
    imperfections, lubricant, ...) and of the Profile (each channel's times, values,
    interpolation, the duration, ...) is the ``source`` of a key of its file, or named in its
    module's SET_ELSEWHERE (read by a reader, or derived; a derived one is no key's source);
    every source and every SET_ELSEWHERE entry is a real attribute."""
    from rvcore.bearing.geometry import Bearing
    from rvcore.profile import Profile
    from pipeline.schema import bearingfile, profilefile

    cls, SET_ELSEWHERE = {"bearing": (Bearing, bearingfile.SET_ELSEWHERE),
                          "profile": (Profile, profilefile.SET_ELSEWHERE)}[file]
    paths = set(_dataclass_paths(cls))
    assert len(paths) > (40 if file == "bearing" else 20)
    sources = {f.source for f in schema.fields_of(file) if f.source}
    sources |= {s.replace("ring_material", "ball_material") for s in sources if s.startswith("ring_material.")}

    def elsewhere(p):
        return any(p == e or p.startswith(e + ".") for e in SET_ELSEWHERE)

    for p in paths:
        assert (p in sources) or elsewhere(p), f"{p}: no key holds it and SET_ELSEWHERE does not say what sets it"
    for e in SET_ELSEWHERE:
        assert e in paths or any(p.startswith(e + ".") for p in paths), e
        if SET_ELSEWHERE[e].startswith(("derived", "not an input")):
            assert e not in sources, f"{e}: a key's source, and derived"
    assert sources <= paths, sources - paths


def test_a_tolerance_class_typed_as_a_number_is_that_class():
    """`tolerance_class = 5`, the class written without its quotes (a TOML integer, as
    `--set imperfections.tolerance_class=5` gives it too), is the class "5"; a number that is
    no class is refused in one line naming the classes."""
    from pipeline.schema.tomlfile import read_toml

    raw = read_toml(ROOT / "sweeps" / "bearings" / "reduced-test.toml")
    raw["imperfections"] = {"tolerance_class": 5}
    assert bearing_from_dict(copy.deepcopy(raw), file="b.toml").rows[0].imperfections.tolerance_class == "5"
    raw["imperfections"] = {"tolerance_class": 3}
    with pytest.raises(ConfigError) as err:
        bearing_from_dict(raw, file="b.toml")
    text = str(err.value)
    assert "\n" not in text and "tolerance_class" in text and '"normal"' in text and '"4"' in text
