"""Bearing files: TOML in, a validated :class:`rvcore.bearing.geometry.Bearing` (SI) out.

Which keys each table allows, every value's kind, bounds and default come from the
schema (:mod:`pipeline.schema.fields`, read through :class:`pipeline.schema.reader.Table`).
This module adds what one field cannot say: the material's two forms, the cage's land
values required when it is outer-land guided, two arcs at ±α, the friction speeds'
order, gravity by mounting or vector, the assumptions list, a ``[pair]``'s two mirrored
rows and their preload (:mod:`rvcore.statics.preload`), and the one-line error of the first
problem the geometry checks find (:func:`rvcore.bearing.checks.bearing_problems`). The file
format is described in :mod:`pipeline.schema.config`.
"""
from __future__ import annotations

import dataclasses

from rvcore.bearing.checks import BALL_OVERLAP, bearing_problems
from rvcore.bearing.geometry import MOUNTINGS, Arc, Bearing, Cage, ContactLaw, InnerRing, Lubricant, Material, Row

from rvcore.bearing.imperfections import MAX_WAVINESS_TERMS, Imperfections, Waviness

from ..errors import ConfigError
from .fields import fields_of
from .reader import Table, short, top_table
from .ringfile import check_ring_supports, ring_supports
from .tomlfile import MISSING, lookup, parse_key_path, read_toml

__all__ = ["bearing_from_dict", "load_bearing"]


def from_fields(cls, t: Table, source: str, given: dict | None = None, overrides: dict | None = None):
    """An instance of dataclass ``cls`` read from table ``t`` by the schema's field table.

    Each field ``name`` of ``cls`` not in ``given`` is read from the schema field under
    ``t`` whose ``source`` is ``f"{source}.{name}"`` (:class:`pipeline.schema.fields.Field`):
    its key path relative to ``t`` says where it is written (``friction.mu_static`` holds
    ``contact.mu_static``), and :meth:`Table.get` validates it and supplies its default. A
    sub-table is required when any field read from it is. ``overrides`` maps a name to
    :meth:`Table.get`'s ``default``/``bounds`` where another key decides them. A field of
    ``cls`` that no schema field holds keeps the dataclass's default.
    """
    given, overrides = dict(given or {}), overrides or {}
    kwargs = {}
    for name, f in _sourced(t.schema_file, t.pattern, source, cls).items():
        if name in given:
            kwargs[name] = given.pop(name)
            continue
        *tables, key = f.path[len(t.pattern) + 1 if t.pattern else 0:].split(".")
        here = t
        for sub in tables:
            below = f"{here.pattern}.{sub}" if here.pattern else sub
            here = here.table(sub, required=_any_required(t.schema_file, below))
        kwargs[name] = here.get(key, **overrides.get(name, {}))
    return cls(**kwargs, **given)


def _sourced(schema_file: str, pattern: str, source: str, cls) -> dict:
    """``{dataclass field name: schema Field}`` of the fields under ``pattern`` that hold
    ``cls``'s fields at ``source``, in the dataclass's order."""
    under = [f for f in fields_of(schema_file) if not pattern or f.path.startswith(f"{pattern}.")]
    by_source = {f.source: f for f in under if f.source}
    return {d.name: by_source[f"{source}.{d.name}"] for d in dataclasses.fields(cls)
            if f"{source}.{d.name}" in by_source}


def _any_required(schema_file: str, pattern: str) -> bool:
    return any(f.required for f in fields_of(schema_file) if f.path.startswith(f"{pattern}."))


def _material(t: Table, source: str) -> Material:
    return from_fields(Material, t, source)


def _arcs(row: Table, groove: str, ball_diameter: float) -> tuple:
    g = row.table(groove)
    arcs = g.tables("arcs")
    if len(arcs) > 2:
        raise ConfigError(row.file, g.key("arcs"), None,
                          f"{len(arcs)} arcs: a groove has one arc (deep groove or angular "
                          "contact) or two at ±α (four-point)")
    out = []
    for a in arcs:
        f = a.get("curvature_ratio", bounds=None)   # the schema's bound, said with the numbers
        lower = a.field("curvature_ratio").bounds[0]
        if f <= lower:
            rel = "smaller than" if f < lower else "equal to"
            raise ConfigError(row.file, a.key("curvature_ratio"), a.raw("curvature_ratio"),
                              f"groove radius {rel} the ball's: f·D = {f * ball_diameter * 1e3:.4g} mm "
                              f"against a ball radius of {ball_diameter / 2 * 1e3:.4g} mm "
                              f"(f must exceed {lower:g})")
        out.append(Arc(curvature_ratio=f, contact_angle=a.get("contact_angle")))
    if len(out) == 2:
        a0, a1 = out[0].contact_angle, out[1].contact_angle
        if a0 == 0.0 or a1 == 0.0 or (a0 > 0) == (a1 > 0):
            raise ConfigError(row.file, arcs[1].key("contact_angle"), arcs[1].raw("contact_angle"),
                              "the two arcs of a four-point groove must sit on opposite sides "
                              "of the groove (contact angles of opposite sign, ±α, neither 0)")
    return tuple(out)


def _cage(c: Table) -> Cage:
    land = {}
    if c.get("guidance") == "outer-land":   # the land values matter only then: required and positive
        land = {"default": MISSING, "bounds": "positive"}
    return from_fields(Cage, c, "rows[].cage", given={"material": _material(c, "rows[].cage.material")},
                       overrides={"land_clearance": land, "land_stiffness": land})


def _row(t: Table, top: Table) -> Row:
    balls = t.table("balls")
    d = balls.get("diameter")
    count = balls.get("count")
    return Row(ball_count=count, ball_diameter=d, pitch_diameter=t.get("pitch_diameter"),
               axial_position=t.get("axial_position"), inner_arcs=_arcs(t, "inner_groove", d),
               outer_arcs=_arcs(t, "outer_groove", d), cage=_cage(t.table("cage")),
               radial_clearance=t.get("radial_clearance"), imperfections=_imperfections(top, t, count))


def _imperfections(top: Table, row: Table, ball_count: int, first: Table | None = None) -> Imperfections:
    """The row's ``[rows.imperfections]`` over the bearing's ``[imperfections]`` (docs/model.md §12);
    ``first`` (a pair's ``[[pair.imperfections]]`` entry of this row) over both."""
    tables = [x for x in (first, row.table("imperfections", required=False),
                          top.table("imperfections", required=False)) if x is not None and x.data]
    if not tables:
        return Imperfections()

    def value(name, absent):
        for x in tables:
            if x.has(name):
                return x, x.get(name)
        return None, absent

    kw = {}
    for ring in ("inner", "outer"):
        kw[f"{ring}_eccentricity"] = value(f"{ring}_eccentricity", None)[1]
        kw[f"{ring}_eccentricity_angle"] = value(f"{ring}_eccentricity_angle", None)[1]
        where = next((x for x in tables if x.has(f"{ring}_waviness")), None)
        kw[f"{ring}_waviness"] = () if where is None else tuple(
            Waviness(int(w.get("order")), w.get("amplitude"), w.get("phase"))
            for w in where.tables(f"{ring}_waviness"))
        if len(kw[f"{ring}_waviness"]) > MAX_WAVINESS_TERMS:
            raise ConfigError(where.file, where.key(f"{ring}_waviness"), None,
                              f"{len(kw[f'{ring}_waviness'])} terms: at most {MAX_WAVINESS_TERMS} a raceway")
    x, balls = value("ball_diameter_deviation", ())
    if len(balls) not in (0, ball_count):
        raise ConfigError(x.file, x.key("ball_diameter_deviation"), short(x.raw("ball_diameter_deviation")),
                          f"{len(balls)} values for {ball_count} balls: give one per ball")
    kw["ball_diameter_deviation"] = tuple(balls)
    kw["ball_grade"] = value("ball_grade", "")[1]
    cls = value("tolerance_class", "none")[1]
    kw["tolerance_class"] = "" if cls == "none" else cls
    return Imperfections(**kw)


def _pair(top: Table, row_tables: list, rows: tuple) -> tuple:
    """The two mirrored rows of a ``[pair]`` and its preload: (rows, arrangement, preload
    [N], preload_offset [m]).

    The file gives one ``[[rows]]`` entry, the design of both rows; the rows are built by
    :func:`rvcore.statics.preload.mirrored_rows` at ∓row_spacing/2, their contact angles mirrored
    as the arrangement says. The preload is applied later (:func:`_preload`), once the
    bearing has passed the geometry checks.
    """
    from rvcore.statics.preload import mirrored_rows

    file = top.file
    pair = top.table("pair")
    arrangement = pair.get("arrangement")
    spacing = pair.get("row_spacing")
    preload, offset = pair.get("preload"), pair.get("preload_offset")
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
    row, t = rows[0], row_tables[0]
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
        pair_rows = tuple(dataclasses.replace(r, imperfections=_imperfections(top, t, r.ball_count, e))
                          for r, e in zip(pair_rows, entries))
    return pair_rows, arrangement, preload, offset


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


def _materials(top: Table):
    file = top.file
    if top.has("material"):
        for other in ("ring_material", "ball_material"):
            if top.has(other):
                raise ConfigError(file, other, None,
                                  "give either [material] (rings and balls) or both "
                                  "[ring_material] and [ball_material], not both forms")
        mat = _material(top.table("material"), "ring_material")
        return mat, mat
    if top.has("ring_material") or top.has("ball_material"):
        return (_material(top.table("ring_material"), "ring_material"),
                _material(top.table("ball_material"), "ball_material"))
    raise ConfigError(file, "material", None,
                      "missing required table (or [ring_material] and [ball_material])")


def _contact(top: Table) -> ContactLaw:
    contact = from_fields(ContactLaw, top, "contact")
    if not contact.v_dynamic > contact.v_static:
        raise ConfigError(top.file, "friction.v_dynamic",
                          top.table("friction", required=False).raw("v_dynamic", contact.v_dynamic),
                          f"must exceed friction.v_static ({contact.v_static:g} m/s)")
    return contact


def _lubricant(top: Table, pitch_diameter: float) -> Lubricant:
    """The ``[lubricant]`` table: the base oil by ``grade`` or by ``viscosity_40`` and
    ``viscosity_100`` (not both), the contamination factor by number or by ISO 281 level,
    and the rest by the schema (:mod:`rvcore.bearing.lubricant`)."""
    from rvcore.bearing.lubricant import (ISO_VG_GRADES, LubricantError, VG68_VISCOSITY_100,
                                          iso_vg_viscosity, walther_coefficients)
    from rvcore.standards.iso281_modified import CONTAMINATION_GUIDE, contamination_factor

    lub = top.table("lubricant", required=False)
    file = top.file
    if lub.has("grade") and lub.has("viscosity_40"):
        raise ConfigError(file, "lubricant.viscosity_40", lub.raw("viscosity_40"),
                          "give either grade (ISO VG: nu40 is its number in mm^2/s) or viscosity_40, not both")
    if lub.has("viscosity_40") and not lub.has("viscosity_100"):
        raise ConfigError(file, "lubricant.viscosity_40", lub.raw("viscosity_40"),
                          "needs viscosity_100 too: the two fix the oil's ASTM D341 (Walther) line")
    grade = lub.get("grade")
    if grade not in ISO_VG_GRADES:
        raise ConfigError(file, "lubricant.grade", lub.raw("grade", grade), lub.field("grade").why)
    if lub.has("viscosity_40"):
        grade, nu40 = None, lub.get("viscosity_40")
    else:
        nu40 = iso_vg_viscosity(grade)
    if lub.has("viscosity_100"):
        nu100 = lub.get("viscosity_100")
    elif grade == 68:
        nu100 = VG68_VISCOSITY_100
    else:
        raise ConfigError(file, "lubricant.grade", lub.raw("grade"),
                          "needs viscosity_100 (the oil's, from its data sheet): only ISO VG 68's "
                          "(8.5 mm^2/s, VI 94) is built in")
    try:
        walther_coefficients(nu40, nu100)
    except LubricantError as exc:
        raise ConfigError(file, "lubricant.viscosity_100", lub.raw("viscosity_100", None), str(exc)) from None
    ec = lub.raw("contamination", None)
    if ec is None:
        contamination = None
    elif isinstance(ec, str) and ec.strip().lower() in CONTAMINATION_GUIDE:
        contamination = contamination_factor(ec, pitch_diameter, "low")
    elif isinstance(ec, (int, float)) and not isinstance(ec, bool) and 0.0 <= ec <= 1.0:
        contamination = float(ec)
    else:
        raise ConfigError(file, "lubricant.contamination", ec,
                          "must be a number e_C in [0, 1] or one of ISO 281 Table 13's levels: "
                          + ", ".join(f'"{k}"' for k in CONTAMINATION_GUIDE))
    return Lubricant(kinematic_viscosity=lub.get("kinematic_viscosity", default=None), method=lub.get("method"),
                     grade=grade, viscosity_40=nu40, viscosity_100=nu100, density=lub.get("density"),
                     pressure_viscosity=lub.get("pressure_viscosity"), ep_additives=lub.get("ep_additives"),
                     contamination=contamination, ball_roughness=lub.get("ball_roughness"),
                     raceway_roughness=lub.get("raceway_roughness"))


def _temperatures(top: Table) -> dict:
    """The ``[temperature]`` table: the rings' operating temperatures and the clearance's
    reference [K]."""
    t = top.table("temperature", required=False)
    return {"inner_ring_temperature": t.get("inner_ring"), "outer_ring_temperature": t.get("outer_ring"),
            "reference_temperature": t.get("reference")}


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
    allow_overlap = top.get("allow_ball_overlap")
    env = top.table("envelope")
    bore, od, width = env.get("bore"), env.get("outer_diameter"), env.get("width")
    ring_mat, ball_mat = _materials(top)
    inner_ring = from_fields(InnerRing, top, "inner_ring")
    contact = _contact(top)
    row_tables = top.tables("rows")
    rows = tuple(_row(t, top) for t in row_tables)
    arrangement, preload, offset = "", 0.0, 0.0
    if top.has("pair"):
        rows, arrangement, preload, offset = _pair(top, row_tables, rows)
    bearing = Bearing(name=name, bore=bore, outer_diameter=od, width=width, rows=rows, ring_material=ring_mat, ball_material=ball_mat,
                      inner_ring=inner_ring, contact=contact, allow_ball_overlap=allow_overlap,
                      assumptions=_assumptions(top, raw), gravity=_gravity(top),
                      arrangement=arrangement, preload=preload, preload_offset=offset,
                      source=top.get("source"), description=top.get("description"),
                      # left out: 0, "from the geometry" (rvcore.standards.iso16281)
                      dynamic_load_rating=top.get("dynamic_load_rating", default=0.0),
                      lubricant=_lubricant(top, rows[0].pitch_diameter), **_temperatures(top),
                      **ring_supports(top))

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
