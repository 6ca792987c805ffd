"""Bearing files: TOML in, a validated :class:`rvcore.bearing.geometry.Bearing` (SI) out.

Which keys each table allows, every value's kind, bounds and default, and the dataclass
attribute each key holds come from the schema (:mod:`pipeline.schema.fields`, read through
:class:`pipeline.schema.reader.Table`): the loader's one converter
(:func:`pipeline.schema.convert.from_fields`) builds the Bearing, its rows, arcs, cages,
imperfections and the pair's keys from that table. This module adds what one field cannot say: the readers of the values no one key holds
(:data:`SET_ELSEWHERE`: the material's two forms, gravity by mounting or vector, the
assumptions list, the contamination level, a row's imperfections from three tables), the
rules keys obey together (:data:`RULES`: the cage's land values, two arcs at ±α, the friction
speeds' order, the base oil), a ``[pair]``'s two mirrored rows and their preload
(:mod:`rvcore.statics.preload`), and the one-line error of the first problem the geometry
checks find (:func:`rvcore.bearing.checks.bearing_problems`). The file format is described
in :mod:`pipeline.schema.config`.
"""
from __future__ import annotations

import dataclasses

from rvcore.bearing.checks import BALL_OVERLAP, bearing_problems
from rvcore.bearing.geometry import MOUNTINGS, Bearing, Cage, ContactLaw, Lubricant, Material, Row
from rvcore.bearing.imperfections import MAX_WAVINESS_TERMS, Imperfections

from ..errors import ConfigError
from .convert import from_fields
from .reader import Table, short, top_table
from .ringfile import check_ring_supports, ring_supports
from .tomlfile import MISSING, lookup, parse_key_path, read_toml
from .units import unit_warnings_on_success

__all__ = ["bearing_from_dict", "load_bearing"]


#: The bearing's dataclass fields that no one key holds, and what sets them: a reader given to
#: the converter (:func:`pipeline.schema.convert.from_fields`, by :func:`bearing_from_dict`) for those read from the
#: file in some other way; the derived ones keep the dataclass's default for the step that
#: sets them. Every other field is read by the field table (``Field.source``); a test holds
#: that each field is one or the other.
SET_ELSEWHERE = {
    "name": "the file's name key, else its stem (pipeline.schema.reader.top_table)",
    "ring_material": "[material] (rings and balls) or [ring_material] (_materials)",
    "ball_material": "[material] (rings and balls) or [ball_material] (_materials)",
    "gravity": "mounting by name or gravity as a vector, not both (_gravity)",
    "assumptions": "the assumptions list, each naming a key of this file (_assumptions)",
    "lubricant.contamination": "a number e_C or an ISO 281 level at the pitch diameter (_contamination)",
    "rows[].imperfections": "the row's [rows.imperfections] over the bearing's [imperfections], a "
                            "pair's [[pair.imperfections]] entry over both (layered_imperfections)",
    "rows[].imperfections.tolerance_class": "tolerance_class, \"none\" held as \"\" (layered_imperfections)",
    "warnings": "derived: the accepted ball overlap of the geometry checks (bearing_from_dict)",
    "nominal_radial_clearances": "derived: the clearances as given, where the temperatures move them "
                                 "(rvcore.bearing.thermal.operating_bearing)",
    "inner_ring_support": "[inner_ring.flexible]: rigid, or flexible in a support of one of three kinds "
                          "(pipeline.schema.ringfile.ring_supports)",
    "outer_ring_support": "[outer_ring.flexible], as the inner ring's (pipeline.schema.ringfile.ring_supports)",
    "rows[].inner_offset": "derived: a pair's preload offset (rvcore.statics.preload.apply_preload)",
    "rows[].cage.material.thermal_expansion": "not an input: the cage's expansion enters no clearance "
                                              "(the dataclass's default)",
}

# ----------------------------------------------------------------- readers: values no one key holds


def _materials(top: Table) -> tuple:
    """(ring material, ball material): ``[material]`` for both, or ``[ring_material]`` and
    ``[ball_material]``."""
    file = top.file
    if top.has("material"):
        for other in ("ring_material", "ball_material"):
            if top.has(other):
                raise ConfigError(file, other, None,
                                  "give either [material] (rings and balls) or both "
                                  "[ring_material] and [ball_material], not both forms")
        mat = from_fields(Material, top.table("material"), "ring_material")
        return mat, mat
    if top.has("ring_material") or top.has("ball_material"):
        return (from_fields(Material, top.table("ring_material"), "ring_material"),
                from_fields(Material, top.table("ball_material"), "ball_material"))
    raise ConfigError(file, "material", None,
                      "missing required table (or [ring_material] and [ball_material])")


def _contamination(lub: Table, pitch_diameter) -> float | None:
    """The ISO 281 contamination factor e_C: a number in [0, 1], or a Table 13 level taken at
    the lower bound of its column at the row's pitch diameter; None when left out."""
    from rvcore.standards.iso281_modified import CONTAMINATION_GUIDE, contamination_factor

    ec = lub.raw("contamination", None)
    if ec is None:
        return None
    if isinstance(ec, str) and ec.strip().lower() in CONTAMINATION_GUIDE:
        return contamination_factor(ec, pitch_diameter(), "low")
    if isinstance(ec, (int, float)) and not isinstance(ec, bool) and 0.0 <= ec <= 1.0:
        return float(ec)
    raise ConfigError(lub.file, lub.key("contamination"), ec,
                      "must be a number e_C in [0, 1] or one of ISO 281 Table 13's levels: "
                      + ", ".join(f'"{k}"' for k in CONTAMINATION_GUIDE))


class _Layers:
    """A row's imperfection tables read as one: each key from the first table that gives it
    (a pair's entry, the row's, the bearing's), a key none gives from the last (its default).
    Offers what :func:`from_fields` reads of a :class:`Table`."""

    def __init__(self, tables: list):
        self.layers = tables
        self.file, self.schema_file, self.pattern = tables[-1].file, tables[-1].schema_file, tables[0].pattern

    def _of(self, name):
        return next((x for x in self.layers if x.has(name)), self.layers[-1])

    def has(self, name):
        return any(x.has(name) for x in self.layers)

    def get(self, name, **kw):
        return self._of(name).get(name, **kw)

    def raw(self, name, *default):
        return self._of(name).raw(name, *default)

    def key(self, name):
        return self._of(name).key(name)

    def tables(self, name):
        return self._of(name).tables(name)


def layered_imperfections(top: Table, row: Table, ball_count: int, first: Table | None = None) -> Imperfections:
    """The row's ``[rows.imperfections]`` over the bearing's ``[imperfections]`` (docs/model.md §12);
    ``first`` (a pair's ``[[pair.imperfections]]`` entry of this row) over both. Read by the field
    table (:func:`from_fields`), with its checks: the waviness terms a raceway holds (before),
    one diameter deviation per ball (after)."""
    tables = [x for x in (first, row.table("imperfections", required=False)) if x is not None]
    t = _Layers(tables + [top.table("imperfections", required=False)])
    for name in ("inner_waviness", "outer_waviness", "inner_axial_waviness", "outer_axial_waviness"):
        n = len(t.tables(name)) if t.has(name) else 0   # said before Imperfections itself refuses them
        if n > MAX_WAVINESS_TERMS:
            raise ConfigError(t.file, t.key(name), None,
                              f"{n} terms: at most {MAX_WAVINESS_TERMS} a raceway")
    cls = t.get("tolerance_class")
    imp = from_fields(Imperfections, t, "rows[].imperfections",
                      readers={"rows[].imperfections.tolerance_class": lambda _: "" if cls == "none" else cls})
    balls = imp.ball_diameter_deviation
    if len(balls) not in (0, ball_count):
        raise ConfigError(t.file, t.key("ball_diameter_deviation"), short(t.raw("ball_diameter_deviation")),
                          f"{len(balls)} values for {ball_count} balls: give one per ball")
    return imp


# ----------------------------------------------------------------- rules: keys that constrain each other


def _cage_land(cage: Cage, c: Table) -> Cage:
    """The land values matter only for an outer-land guided cage: there they are required and
    positive, else not negative (the schema's bound)."""
    outer = cage.guidance == "outer-land"
    for name in ("land_clearance", "land_stiffness"):
        c.get(name, default=MISSING, bounds="positive") if outer else c.get(name)
    return cage


def _row_arcs(row: Row, t: Table) -> Row:
    """Each groove has one arc or two at ±α, and each groove radius exceeds the ball's."""
    for groove, arcs in (("inner_groove", row.inner_arcs), ("outer_groove", row.outer_arcs)):
        g = t.table(groove)
        if len(arcs) > 2:
            raise ConfigError(t.file, g.key("arcs"), None,
                              f"{len(arcs)} arcs: a groove has one arc (deep groove or angular "
                              "contact) or two at ±α (four-point)")
        tables = g.tables("arcs")
        for a, arc in zip(tables, arcs):
            f, lower = arc.curvature_ratio, a.field("curvature_ratio").bounds[0]
            if f <= lower:
                rel = "smaller than" if f < lower else "equal to"
                raise ConfigError(t.file, a.key("curvature_ratio"), a.raw("curvature_ratio"),
                                  f"groove radius {rel} the ball's: f·D = {f * row.ball_diameter * 1e3:.4g} mm "
                                  f"against a ball radius of {row.ball_diameter / 2 * 1e3:.4g} mm "
                                  f"(f must exceed {lower:g})")
        if len(arcs) == 2:
            a0, a1 = arcs[0].contact_angle, arcs[1].contact_angle
            if a0 == 0.0 or a1 == 0.0 or (a0 > 0) == (a1 > 0):
                raise ConfigError(t.file, tables[1].key("contact_angle"), tables[1].raw("contact_angle"),
                                  "the two arcs of a four-point groove must sit on opposite sides "
                                  "of the groove (contact angles of opposite sign, ±α, neither 0)")
    return row


def _friction_speeds(contact: ContactLaw, top: Table) -> ContactLaw:
    """Friction is dynamic only beyond the static peak: v_dynamic > v_static."""
    if not contact.v_dynamic > contact.v_static:
        raise ConfigError(top.file, "friction.v_dynamic",
                          top.table("friction", required=False).raw("v_dynamic", contact.v_dynamic),
                          f"must exceed friction.v_static ({contact.v_static:g} m/s)")
    return contact


def _base_oil(lubricant: Lubricant, lub: Table) -> Lubricant:
    """The base oil by ``grade`` or by ``viscosity_40`` and ``viscosity_100`` (not both):
    ν40 from the grade (ISO 3448), ν100 built in for ISO VG 68 only, and the two must make a
    Walther line (:mod:`rvcore.bearing.lubricant`)."""
    from rvcore.bearing.lubricant import (ISO_VG_GRADES, LubricantError, VG68_VISCOSITY_100,
                                          iso_vg_viscosity, walther_coefficients)

    file = lub.file
    if lub.has("grade") and lub.has("viscosity_40"):
        raise ConfigError(file, lub.key("viscosity_40"), lub.raw("viscosity_40"),
                          "give either grade (ISO VG: nu40 is its number in mm^2/s) or viscosity_40, not both")
    if lub.has("viscosity_40") and not lub.has("viscosity_100"):
        raise ConfigError(file, lub.key("viscosity_40"), lub.raw("viscosity_40"),
                          "needs viscosity_100 too: the two fix the oil's ASTM D341 (Walther) line")
    grade = lubricant.grade
    if grade not in ISO_VG_GRADES:
        raise ConfigError(file, lub.key("grade"), lub.raw("grade", grade), lub.field("grade").why)
    if lub.has("viscosity_40"):
        grade, nu40 = None, lubricant.viscosity_40
    else:
        nu40 = iso_vg_viscosity(grade)
    if lub.has("viscosity_100"):
        nu100 = lubricant.viscosity_100
    elif grade == 68:
        nu100 = VG68_VISCOSITY_100
    else:
        raise ConfigError(file, lub.key("grade"), lub.raw("grade"),
                          "needs viscosity_100 (the oil's, from its data sheet): only ISO VG 68's "
                          "(8.5 mm^2/s, VI 94) is built in")
    try:
        walther_coefficients(nu40, nu100)
    except LubricantError as exc:
        raise ConfigError(file, lub.key("viscosity_100"), lub.raw("viscosity_100", None), str(exc)) from None
    return dataclasses.replace(lubricant, grade=grade, viscosity_40=nu40, viscosity_100=nu100)


#: Bounds the rules (:data:`RULES`) check instead of the schema, to say more: the groove radius
#: against the ball's, the land values against the cage's guidance.
_OVERRIDES = {"rows[].inner_arcs[].curvature_ratio": {"bounds": None},
              "rows[].outer_arcs[].curvature_ratio": {"bounds": None},
              "rows[].cage.land_clearance": {"bounds": None},
              "rows[].cage.land_stiffness": {"bounds": None}}

#: The rules each dataclass's keys obey together, run by :func:`~pipeline.schema.convert.from_fields` on the instance it
#: has read (with the table it read it from). The pair's rule (:func:`_pair`) also builds.
RULES = {Cage: _cage_land, Row: _row_arcs, ContactLaw: _friction_speeds, Lubricant: _base_oil}


def _pair(bearing: Bearing, top: Table) -> Bearing:
    """A ``[pair]``'s two mirrored rows.

    The file gives one ``[[rows]]`` entry, the design of both rows; the rows are built by
    :func:`rvcore.statics.preload.mirrored_rows` at ∓row_spacing/2, their contact angles mirrored
    as the arrangement says. The preload is applied later (:func:`_preload`), once the
    bearing has passed the geometry checks.
    """
    from rvcore.statics.preload import mirrored_rows

    file, rows = top.file, bearing.rows
    pair = top.table("pair")
    arrangement, preload, offset = bearing.arrangement, bearing.preload, bearing.preload_offset
    spacing = pair.get("row_spacing")
    if pair.has("preload") and pair.has("preload_offset"):
        raise ConfigError(file, "pair.preload_offset", pair.raw("preload_offset"),
                          "give either preload (a force; the statics find the offset that gives it) "
                          "or preload_offset (the offset itself), not both")
    if arrangement == "tandem" and (preload > 0.0 or offset != 0.0):
        key = "pair.preload" if pair.has("preload") else "pair.preload_offset"
        raise ConfigError(file, key, pair.raw(key.split(".")[1]),
                          "a tandem pair cannot be preloaded: both rows carry axial load in the "
                          "same direction, so neither row holds the other against a preload")
    if len(rows) != 1:
        raise ConfigError(file, "rows", None,
                          f"{len(rows)} [[rows]] entries with [pair]: give exactly one, the design of "
                          "both rows (the pair builds the second, mirrored), or leave [pair] out and "
                          "give every row with its axial_position")
    row, t = rows[0], top.tables("rows")[0]
    if t.has("axial_position"):
        raise ConfigError(file, t.key("axial_position"), t.raw("axial_position"),
                          "a pair's rows sit at -row_spacing/2 and +row_spacing/2 (pair.row_spacing); "
                          "leave axial_position out")
    if len(row.inner_arcs) != 1 or len(row.outer_arcs) != 1 or row.nominal_contact_angle == 0.0:
        kind = "a four-point" if len(row.inner_arcs) > 1 or len(row.outer_arcs) > 1 else "a deep-groove (0 deg)"
        raise ConfigError(file, f"{t.key('outer_groove')}.arcs[0].contact_angle",
                          t.table("outer_groove").tables("arcs")[0].raw("contact_angle"),
                          f"{kind} row cannot be mirrored into a pair: give an angular-contact row "
                          "(one arc per ring, at a contact angle other than 0)")
    pair_rows = mirrored_rows(row, arrangement, spacing)
    if pair.has("imperfections"):   # the two rows' own imperfections, row at -row_spacing/2 first
        entries = pair.tables("imperfections")
        if len(entries) != 2:
            raise ConfigError(file, "pair.imperfections", None,
                              f"{len(entries)} entries: give two [[pair.imperfections]], one per row "
                              "(the row at -row_spacing/2 first)")
        pair_rows = tuple(dataclasses.replace(r, imperfections=layered_imperfections(top, t, r.ball_count, e))
                          for r, e in zip(pair_rows, entries))
    return dataclasses.replace(bearing, rows=pair_rows)


def _preload(bearing: Bearing, top: Table) -> Bearing:
    """The pair with its preload applied (:func:`rvcore.statics.preload.apply_preload`)."""
    from rvcore.statics.preload import apply_preload

    if not (bearing.preload > 0.0 or bearing.preload_offset != 0.0):
        return bearing
    pair = top.table("pair")
    key = "preload" if pair.has("preload") else "preload_offset"
    try:
        return apply_preload(bearing)
    except ValueError as exc:
        raise ConfigError(top.file, f"pair.{key}", pair.raw(key, None), str(exc)) from None


def _assumptions(top: Table, raw: dict) -> tuple:
    v = top.raw("assumptions", [])
    if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
        raise ConfigError(top.file, "assumptions", short(v), "must be a list of key paths (strings)")
    for i, k in enumerate(v):
        parse_key_path(k, top.file, k)
        absent = object()
        if k == "assumptions" or lookup(raw, k, absent) is absent:
            raise ConfigError(top.file, f"assumptions[{i}]", k, "names a key that is not in this file")
    return tuple(dict.fromkeys(v))


def _gravity(top: Table) -> tuple:
    """Gravity in the bearing frame [m s^-2]: ``mounting`` by name, or ``gravity`` as a vector.

    ``mounting = "horizontal"`` (the default: axis horizontal, gravity along −y) or
    ``"vertical"`` (gravity along −z); ``gravity = ["0 m/s^2", "-9.81 m/s^2", "0 m/s^2"]``
    gives any other direction. Switching gravity off is a solver setting
    (``solver.gravity = false``), not a mounting.
    """
    if top.has("gravity"):
        if top.has("mounting"):
            raise ConfigError(top.file, "gravity", None, "give either mounting or a gravity vector, not both")
        vec = top.raw("gravity")
        n = top.field("gravity").length
        if not isinstance(vec, list) or len(vec) != n:
            raise ConfigError(top.file, "gravity", short(vec),
                              'must be a list of three accelerations, e.g. ["0 m/s^2", "-9.81 m/s^2", "0 m/s^2"]')
        return tuple(top.get("gravity"))
    return MOUNTINGS[top.get("mounting")]


@unit_warnings_on_success
def bearing_from_dict(raw: dict, file="<input>") -> Bearing:
    """Validate a bearing file's contents and build the :class:`rvcore.bearing.geometry.Bearing`.

    Parameters
    ----------
    raw : dict
        The file as read by :func:`read_toml` [-].
    file : str or Path
        The file's name, for error messages; its stem is the default ``name``.

    Returns
    -------
    rvcore.bearing.geometry.Bearing
        In SI, with ``warnings`` (accepted ball overlap) and ``assumptions``.

    Raises
    ------
    ConfigError
        The first problem found, naming file, key, value and reason.
    """
    top, name = top_table(raw, file, "bearing")
    materials = _materials(top)
    readers = {
        "name": lambda _: name,
        "ring_material": lambda _: materials[0],
        "ball_material": lambda _: materials[1],
        "gravity": _gravity,
        "assumptions": lambda t: _assumptions(t, raw),
        "lubricant.contamination": lambda lub: _contamination(
            lub, lambda: top.tables("rows")[0].get("pitch_diameter")),
        "rows[].imperfections": lambda row: layered_imperfections(top, row, row.table("balls").get("count")),
        "inner_ring_support": lambda _: ring_supports(top)["inner_ring_support"],
        "outer_ring_support": lambda _: ring_supports(top)["outer_ring_support"],
    }
    bearing = from_fields(Bearing, top, "", readers, _OVERRIDES, RULES)
    arrangement, allow_overlap = bearing.arrangement, bearing.allow_ball_overlap
    if arrangement:
        bearing = _pair(bearing, top)

    warnings = []
    for p in bearing_problems(bearing):
        key, reason = p.key, p.reason
        if arrangement:   # the file gives the design of both rows as rows[0]
            key = key.replace("rows[1]", "rows[0]")
        if p.kind == BALL_OVERLAP:
            if allow_overlap:
                warnings.append(reason)
                continue
            reason += ("; set allow_ball_overlap = true to reproduce it anyway, with this "
                       "as a warning (docs/model.md §10)")
        shown = lookup(raw, key, p.value)
        if isinstance(shown, (dict, list)):
            shown = p.value
        raise ConfigError(file, key, shown, reason)
    _refuse_unphysical(bearing, raw, file, arrangement)
    check_ring_supports(bearing, file)
    bearing = dataclasses.replace(bearing, warnings=tuple(dict.fromkeys(warnings)))
    if arrangement:   # the preload is set at the reference temperature, the offset then held
        bearing = _preload(bearing, top)
    return _operating(bearing, top)


def _operating(bearing: Bearing, top: Table) -> Bearing:
    """The rows' clearances at the rings' operating temperatures
    (:func:`rvcore.bearing.thermal.operating_bearing`)."""
    from rvcore.bearing.lubricant import LubricantError, operating_viscosity
    from rvcore.bearing.thermal import operating_bearing

    try:   # the oil's Walther line must hold at the lubricant's temperature: said now, not mid-run
        operating_viscosity(bearing)
    except LubricantError as exc:
        t = top.table("temperature", required=False)
        key = next((k for k in ("inner_ring", "outer_ring") if t.has(k)), None)
        if key is None:
            raise ConfigError(top.file, "lubricant", None, str(exc)) from None
        raise ConfigError(top.file, f"temperature.{key}", t.raw(key), str(exc)) from None
    return operating_bearing(bearing)


def _refuse_unphysical(bearing: Bearing, raw: dict, file, arrangement: str) -> None:
    """The first of :func:`pipeline.schema.physical.physical_problems`, said about the key
    the file wrote it under (a row's, the bearing's ``[imperfections]``, or a pair's entry)."""
    from .physical import physical_problems

    for i, key, value, reason in physical_problems(bearing):
        row = 0 if arrangement else i
        if key.startswith("imperfections."):
            name = key.removeprefix("imperfections.")
            head = name.split("[")[0].split(".")[0]
            places = ([f"pair.imperfections[{i}]"] if arrangement else []) + [f"rows[{row}].imperfections",
                                                                            "imperfections"]
            absent = object()
            where = next((p for p in places if lookup(raw, f"{p}.{head}", absent) is not absent), places[-1])
            key = f"{where}.{name}"
        else:
            key = f"rows[{row}].{key}"
        shown = lookup(raw, key, value)
        raise ConfigError(file, key, shown if not isinstance(shown, (dict, list)) else value, reason)


def load_bearing(path) -> Bearing:
    """Read and validate a bearing file (:func:`read_toml` + :func:`bearing_from_dict`)."""
    return bearing_from_dict(read_toml(path), file=str(path))
