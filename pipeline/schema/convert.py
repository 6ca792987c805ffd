"""The loader's one converter: a file's tables into the ``rvcore`` dataclasses, driven by the
field table (:mod:`pipeline.schema.fields`, read through :class:`pipeline.schema.reader.Table`).

Each key's value lands at its field's ``source``; what no one key holds is read by a reader
the file's module gives (``bearingfile.SET_ELSEWHERE``, ``profilefile.SET_ELSEWHERE``), and
the rules keys obey together (``bearingfile.RULES``, the profile's channel and phase rules)
run on each instance once it is built. The read-back of a stored configuration, the other
direction's one converter, is :func:`pipeline.schema.stored.rebuild`.
"""
from __future__ import annotations

import dataclasses
import functools
import typing

from . import fields
from .fields import OPTIONAL_TABLES, fields_of

__all__ = ["from_fields"]


def from_fields(cls, t, source: str, readers: dict | None = None, overrides: dict | None = None,
                rules: dict | None = None):
    """An instance of dataclass ``cls`` read from table ``t`` by the schema's field table: the
    loader's one converter.

    Each field ``name`` of ``cls``, at ``at = f"{source}.{name}"`` in the built dataclasses
    (``rows[].cage.width``), is

    - ``readers[at](t)`` where a reader is given (a value no one key holds: the file module's
      ``SET_ELSEWHERE``);
    - a value: from the schema field whose ``source`` is ``at``, its key path relative to ``t``
      saying where it is written (``friction.mu_static`` holds ``contact.mu_static``), validated
      and defaulted by :meth:`Table.get` (``overrides[at]``: its ``default``/``bounds`` there). A
      key left out whose default is a rule (:attr:`Field.text_default`) keeps the dataclass's
      default, and a list is held as a tuple;
    - a dataclass (``Row.cage``): read the same way from the table that holds its keys;
    - a tuple of dataclasses (``tuple[Row, ...]``: ``Bearing.rows``, ``Row.inner_arcs``): one
      from each entry of the array of tables that holds its keys; left out, the dataclass's
      default where it has one;
    - otherwise (derived, ``SET_ELSEWHERE``): the dataclass's default.

    A sub-table is required when any key read from it is, unless the schema lists it in
    :data:`pipeline.schema.fields.OPTIONAL_TABLES` (then, left out, its fields keep their
    defaults). The rules that tie keys together run as soon as what they tie is read, and return
    it checked (or completed: a rule may build what its keys decide together):
    ``rules[cls](instance, t)`` on each instance once it is built, with the table it was read
    from; ``rules[at](value, t)`` on one attribute's value as soon as it is read (a channel's
    times against the cycle, before its values are read).
    """
    readers, overrides, rules = readers or {}, overrides or {}, rules or {}
    hints = _hints(cls)
    sourced = _sourced(t.schema_file, t.pattern)
    kwargs = {}
    for d in dataclasses.fields(cls):
        at = f"{source}.{d.name}" if source else d.name
        if at in readers:
            kwargs[d.name] = readers[at](t)
            if at in rules:
                kwargs[d.name] = rules[at](kwargs[d.name], t)
            continue
        f = sourced.get(at)
        item = fields.item_class(hints[d.name])
        below = [g for p, g in sourced.items() if p.startswith(f"{at}[]." if item else f"{at}.")
                 and not any(p.startswith(f"{r}.") for r in readers)]
        if f is not None:   # a value
            parts = _relative(f.path, t.pattern)
            here = _descend(t, parts[:-1])
            if here is None or (f.text_default and not here.has(parts[-1]) and "default" not in overrides.get(at, {})):
                continue   # the dataclass's default
            value = here.get(parts[-1], **overrides.get(at, {}))
            kwargs[d.name] = tuple(value) if isinstance(value, list) else value
            if at in rules:
                kwargs[d.name] = rules[at](kwargs[d.name], here)
        elif below and item is not None:   # an array of tables
            *tables, array = _common_table(below, t.pattern)
            here, array = _descend(t, tables), array.removesuffix("[]")
            has_default = d.default is not dataclasses.MISSING or d.default_factory is not dataclasses.MISSING
            if here is not None and not (has_default and not here.has(array)):
                kwargs[d.name] = tuple(from_fields(item, x, f"{at}[]", readers, overrides, rules)
                                       for x in here.tables(array))
        elif below:   # a dataclass, from the table holding its keys
            here = _descend(t, _common_table(below, t.pattern))
            if here is not None:
                kwargs[d.name] = from_fields(hints[d.name], here, at, readers, overrides, rules)
        # else derived (SET_ELSEWHERE): the dataclass's default
    obj = cls(**kwargs)
    rule = rules.get(cls)
    return obj if rule is None else rule(obj, t)


@functools.cache
def _hints(cls) -> dict:
    return typing.get_type_hints(cls)


@functools.cache
def _sourced(schema_file: str, pattern: str) -> dict:
    """``{source: schema Field}`` of the fields under table ``pattern`` that hold a dataclass value."""
    return {f.source: f for f in fields_of(schema_file)
            if f.source and (not pattern or f.path.startswith(f"{pattern}."))}


def _relative(path: str, pattern: str) -> list:
    """The parts of key path ``path`` below table ``pattern``."""
    return path[len(pattern) + 1 if pattern else 0:].split(".")


def _common_table(below: list, pattern: str) -> list:
    """The deepest table holding every field of ``below``, as parts below ``pattern``
    (``["inner_groove", "arcs[]"]``, ``["inner_ring"]``, ``[]`` for ``pattern`` itself)."""
    common = []
    for parts in zip(*(_relative(f.path, pattern)[:-1] for f in below)):
        if len(set(parts)) != 1:
            break
        common.append(parts[0])
        if parts[0].endswith("[]"):   # an array of tables: its entries are the instances
            break
    return common


def _descend(t, tables: list):
    """The sub-table ``tables`` of ``t``; each is required when a key read from it is, and
    None where an optional table (:data:`OPTIONAL_TABLES`) on the way is left out."""
    here = t
    for sub in tables:
        below = f"{here.pattern}.{sub}" if here.pattern else sub
        if below in OPTIONAL_TABLES.get(t.schema_file, ()) and not here.has(sub):
            return None
        here = here.table(sub, required=_any_required(t.schema_file, below))
    return here


@functools.cache
def _any_required(schema_file: str, pattern: str) -> bool:
    return any(f.required for f in fields_of(schema_file) if f.path.startswith(f"{pattern}."))
