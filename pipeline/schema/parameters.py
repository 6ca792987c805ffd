"""The report's parameter table: every input value of a bearing (and a profile) with its
file key path, its value in the schema's display unit, its doc, and whether it is assumed.

Built from the schema (:mod:`pipeline.schema.fields`: which keys, their units and docs,
and where each value sits in the ``rvcore`` dataclasses) and the loaded ``Bearing`` /
``Profile``, so it shows defaults too (a key the file leaves out) and never re-reads TOML.
"""
from __future__ import annotations

from dataclasses import dataclass

from rvcore.bearing.geometry import MOUNTINGS

from . import fields as schema
from .units import format_quantity

__all__ = ["ParameterRow", "parameter_table", "format_value", "display_unit", "readable_number"]

#: How a reader is shown the schema's file units (which stay ASCII so that a value can be
#: pasted back into a TOML file): symbols in place of the ASCII spellings.
_DISPLAY_UNITS = {"deg/s": "°/s", "deg": "°", "um": "µm", "us": "µs", "kg/m^3": "kg/m³", "kg m^2": "kg m²",
                  "m/s^2": "m/s²", "N/m^1.5": "N/m¹·⁵", "mm^2/s": "mm²/s"}

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def readable_number(text: str) -> str:
    """``"1e+09"`` -> ``"1×10⁹"``; a number without an exponent unchanged."""
    mantissa, e, exponent = text.partition("e")
    if not e:
        return text
    return f"{mantissa}×10" + str(int(exponent)).translate(_SUPERSCRIPT)


def display_unit(unit: str) -> str:
    """The reader's spelling of a schema unit: ``"deg/s"`` -> ``"°/s"``, ``"um"`` -> ``"µm"``."""
    return _DISPLAY_UNITS.get(unit, unit)


@dataclass(frozen=True)
class ParameterRow:
    """One row of the parameter table.

    Parameters
    ----------
    key : str
        The file key path, e.g. ``"rows[0].balls.diameter"``; profile values are written
        ``"profile.<key path>"`` as a sweep file addresses them.
    value : str
        The value in the field's display unit, e.g. ``"23 mm"``.
    doc : str
        The field's one-line doc.
    assumed : bool
        Whether the key, or a table holding it, is in ``bearing.assumptions``.
    """

    key: str
    value: str
    doc: str
    assumed: bool


def format_value(f: schema.Field, value, symbols: bool = False) -> str:
    """``value`` (SI, as in the ``rvcore`` dataclasses) in ``f``'s display unit.

    With ``symbols``, the unit as a reader writes it (:func:`display_unit`: ``120 °/s``);
    without, as the files spell it (``120 deg/s``, which reads back).
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)):
        items = [format_value(f, v).removesuffix(f" {f.unit}") if f.unit else format_value(f, v)
                 for v in value]
        unit = display_unit(f.unit) if symbols else f.unit
        return "[" + ", ".join(items) + "]" + (f" {unit}" if unit else "")
    if f.kind == "integer":
        return str(int(value))
    if f.unit and f.unit_kind:
        text = format_quantity(value, f.unit, f.unit_kind)
        if not symbols:
            return text
        return f"{readable_number(text.removesuffix(f' {f.unit}'))} {display_unit(f.unit)}"
    return f"{value:.6g}"


def _walk(obj, parts: list, indices: tuple):
    """(indices, value) of every value at the attribute path ``parts`` ("rows[]" expands)."""
    if obj is None:   # an optional part left out (a profile's moment channel): no rows
        return
    if not parts:
        yield indices, obj
        return
    head, rest = parts[0], parts[1:]
    if head.endswith("[]"):
        for i, item in enumerate(getattr(obj, head[:-2])):
            yield from _walk(item, rest, indices + (i,))
    else:
        yield from _walk(getattr(obj, head), rest, indices)


def _key(path: str, indices: tuple) -> str:
    for i in indices:
        path = path.replace("[]", f"[{i}]", 1)
    return path


def _is_assumed(key: str, assumptions) -> bool:
    return any(key == a or key.startswith(a + ".") or key.startswith(a + "[") for a in assumptions)


def _skip(f: schema.Field, bearing) -> bool:
    """Fields that do not describe this bearing: the material form it does not use, and
    the gravity vector when a mounting names it (and the other way round)."""
    one_material = bearing.ring_material == bearing.ball_material
    head = f.path.split(".")[0]
    if head == "material":
        return not one_material
    if head in ("ring_material", "ball_material"):
        return one_material
    return f.path == "gravity" and _mounting(bearing) is not None


def _mounting(bearing):
    return next((m for m, g in MOUNTINGS.items() if tuple(g) == tuple(bearing.gravity)), None)


def _rows(obj, file_fields, prefix: str, assumptions, skip=lambda f: False, symbols: bool = False) -> list:
    out = []
    for f in file_fields:
        # free text (not hashed) is no parameter; a row's imperfections are what its table,
        # the bearing's and a pair's entry give together, not one key's value
        if f.source is None or not f.hashed or f.source.startswith("rows[].imperfections.") or skip(f):
            continue
        for indices, value in _walk(obj, f.source.split("."), ()):
            key = prefix + _key(f.path, indices)
            # a key left out whose default is a rule, not a number ("from the geometry":
            # the catalogue C_r), shows the rule, not the 0 that stands for it
            shown = (f.default if isinstance(f.default, str) and f.default.startswith("from")
                     and not isinstance(value, (bool, str, list, tuple)) and value == 0
                     else format_value(f, value, symbols))
            out.append(ParameterRow(key, shown, f.doc, _is_assumed(key, assumptions)))
    return out


def _profile_rows(profile, symbols: bool = False) -> list:
    out = _rows(profile, schema.fields_of("profile"), "profile.", (), symbols=symbols)
    by_path = schema.field_map("profile")
    for c in schema.profile_channels():
        ch = getattr(profile, c)
        if ch is None:   # an optional channel the profile leaves out (its default applies)
            continue
        f = by_path[f"{c}.fraction" if ch.relative else f"{c}.value"]
        out.append(ParameterRow(f"profile.{f.path}", format_value(f, ch.values, symbols), f.doc, False))
    for name, start, end in profile.phases:
        f = by_path[f"phases.{name}"]
        out.append(ParameterRow(f"profile.{f.path}", format_value(f, (start, end), symbols), f.doc, False))
    return out


def parameter_table(bearing, profile=None, settings=None, symbols: bool = False) -> list:
    """The parameters of ``bearing`` (and ``profile``, and the solver ``settings``) as
    :class:`ParameterRow` s, in schema order (``mounting``, when it names the gravity,
    after the bearing's fields).

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    profile : rvcore.profile.Profile, optional
    settings : rvcore.simulation.run.SolverSettings, optional
    symbols : bool
        Units as a reader writes them (``°/s``, ``µm``; :func:`display_unit`) rather than as
        the files spell them (``deg/s``, ``um``).
    """
    rows = _rows(bearing, schema.fields_of("bearing"), "", bearing.assumptions,
                 skip=lambda f: _skip(f, bearing), symbols=symbols)
    mounting = _mounting(bearing)
    if mounting is not None:
        f = schema.field_map("bearing")["mounting"]
        rows.append(ParameterRow("mounting", mounting, f.doc, _is_assumed("mounting", bearing.assumptions)))
    if profile is not None:
        rows += _profile_rows(profile, symbols)
    if settings is not None:
        rows += _rows(settings, schema.fields_of("solver"), "", (), symbols=symbols)
    return rows
