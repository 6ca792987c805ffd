"""Reading one TOML table against the schema (:mod:`pipeline.schema.fields`).

A :class:`Table` knows its key path (``rows[0].cage``) and so its schema pattern
(``rows[].cage``): the keys it allows, and each value's kind, bounds and default, come
from the field table. Every problem is a one-line :class:`pipeline.errors.ConfigError`
naming file, key path, value as written and reason.
"""
from __future__ import annotations

import math
from pathlib import Path

from ..errors import ConfigError
from . import fields as schema
from .tomlfile import MISSING, format_key_path
from .units import parse_quantity

_SAME = object()   # "use the field's own bounds / default"


def short(v):
    """A value for an error message: tables and long lists are not spelled out."""
    if isinstance(v, dict):
        return None
    if isinstance(v, list) and (len(v) > 8 or any(isinstance(x, dict) for x in v)):
        return None
    return v


def join(names, quote=False):
    return ", ".join(f'"{n}"' if quote else str(n) for n in names)


def check_quantity(v, kind, file, key, bounds=None, why=""):
    """``v`` in SI, finite and within ``bounds`` (see :class:`~pipeline.schema.fields.Field`)."""
    if isinstance(v, (dict, list)):
        raise ConfigError(file, key, short(v), "expected a single quantity")
    x = parse_quantity(v, kind, file=file, key=key)
    if not math.isfinite(x):
        raise ConfigError(file, key, v, "must be finite")
    if bounds == "positive" and not x > 0:
        raise ConfigError(file, key, v, why or f"must be positive (got {x:g} in SI)")
    if bounds == "nonnegative" and x < 0:
        raise ConfigError(file, key, v, why or f"must not be negative (got {x:g} in SI)")
    if bounds == "fraction" and not 0 < x <= 1:
        raise ConfigError(file, key, v, why or f"must lie in (0, 1] (got {x:g})")
    if isinstance(bounds, tuple) and not bounds[0] < x < bounds[1]:
        raise ConfigError(file, key, v, why or f"must lie strictly between {bounds[0]:g} and "
                                               f"{bounds[1]:g} (got {x:g} in SI)")
    return x


def check_value(f: schema.Field, v, file, key, bounds=_SAME):
    """One value of field ``f`` as written, validated: SI float, int, bool, str or list."""
    if f.kind == "quantity":
        return check_quantity(v, f.unit_kind, file, key, f.bounds if bounds is _SAME else bounds, f.why)
    if f.kind == "integer":
        if isinstance(v, bool) or not isinstance(v, int):
            raise ConfigError(file, key, short(v), "must be an integer")
        if f.minimum is not None and v < f.minimum:
            raise ConfigError(file, key, v, f"must be at least {f.minimum}")
        if f.maximum is not None and v > f.maximum:
            raise ConfigError(file, key, v, f"must be at most {f.maximum}" + (f" ({f.why})" if f.why else ""))
        return v
    if f.kind == "boolean":
        if not isinstance(v, bool):
            raise ConfigError(file, key, short(v), "must be true or false")
        return v
    if f.kind in ("string", "choice"):
        if f.choices and isinstance(v, int) and not isinstance(v, bool) and str(v) in f.choices:
            return str(v)       # tolerance_class = 4: the class "4", typed without its quotes
        if f.choices and not isinstance(v, str):
            raise ConfigError(file, key, short(v), f"must be one of the strings {join(f.choices, quote=True)}")
        if not isinstance(v, str):
            raise ConfigError(file, key, short(v), "must be a string")
        if f.choices and v not in f.choices:
            raise ConfigError(file, key, v, f"must be one of {join(f.choices, quote=True)}")
        return v
    if not isinstance(v, list):
        raise ConfigError(file, key, short(v), "expected a list")
    if not v:
        raise ConfigError(file, key, v, "must not be empty")
    if f.unit_kind is None:
        return list(v)
    b = f.bounds if bounds is _SAME else bounds
    return [check_quantity(x, f.unit_kind, file, f"{key}[{i}]", b, f.why) for i, x in enumerate(v)]


class Table:
    """One TOML table being read: rejects unknown keys up front, reads fields by name."""

    def __init__(self, data, path: list, file, schema_file: str):
        self.path = list(path)
        self.file = file
        self.schema_file = schema_file
        self.pattern = schema.pattern(format_key_path(self.path))
        allowed = schema.keys_under(schema_file, self.pattern)
        if not isinstance(data, dict):
            raise ConfigError(file, self.key(None), short(data),
                              "expected a table" + (f" with keys {join(allowed)}" if allowed else ""))
        self.data = data
        for k, reason in schema.refused_keys(schema_file, self.pattern).items():
            if k in data:
                raise ConfigError(file, self.key(k), short(data[k]), reason)
        for k, v in data.items():
            if k not in allowed:
                raise ConfigError(file, self.key(k), short(v), f"unknown key (allowed here: {join(allowed)})")

    def key(self, name) -> str:
        parts = self.path + ([] if name is None else [name])
        return format_key_path(parts) or "<top level>"

    def field(self, name) -> schema.Field:
        return schema.field(self.schema_file, f"{self.pattern}.{name}" if self.pattern else name)

    def has(self, name) -> bool:
        return name in self.data

    def raw(self, name, default=MISSING):
        if name in self.data:
            return self.data[name]
        if default is MISSING:
            raise ConfigError(self.file, self.key(name), None, "missing required key")
        return default

    def get(self, name, *, default=_SAME, bounds=_SAME):
        """The field ``name``, validated by the schema; its default when absent.

        ``default`` and ``bounds`` override the schema's where another key decides them
        (a cage's land clearance is required when the cage is outer-land guided).
        """
        f = self.field(name)
        if name not in self.data:
            d = f.default if default is _SAME else default
            if d is schema.REQUIRED or d is MISSING:
                raise ConfigError(self.file, self.key(name), None, "missing required key")
            return d
        return check_value(f, self.data[name], self.file, self.key(name), bounds)

    def table(self, name, *, required=True):
        if name not in self.data:
            if required:
                raise ConfigError(self.file, self.key(name), None, "missing required table")
            return Table({}, self.path + [name], self.file, self.schema_file)
        return Table(self.data[name], self.path + [name], self.file, self.schema_file)

    def tables(self, name, *, minimum=1):
        """An array of tables (``[[name]]``)."""
        v = self.raw(name)
        if isinstance(v, dict) or not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
            raise ConfigError(self.file, self.key(name), short(v),
                              f"expected an array of tables (write [[{self.key(name)}]] sections)")
        if len(v) < minimum:
            raise ConfigError(self.file, self.key(name), v,
                              f"needs at least {minimum} entr{'y' if minimum == 1 else 'ies'}")
        return [Table(x, self.path + [name, i], self.file, self.schema_file) for i, x in enumerate(v)]


#: Top-level keys that tell a kind of file apart (``rvsweep check`` reads them too): a
#: bearing has ``[[rows]]``/``[envelope]``, a profile ``duration``/``[phases]``, a sweep
#: names a ``bearing`` and a ``profile`` file.
KIND_MARKERS = {"bearing": ("rows", "envelope"), "profile": ("duration", "phases"),
                "sweep": ("bearing", "profile")}


def refuse_other_kind(raw, file, expected: str) -> None:
    """A file of another kind where ``expected`` ("bearing", "profile") belongs: say which
    it is, rather than "unknown key" about its first key."""
    if not isinstance(raw, dict) or any(k in raw for k in KIND_MARKERS[expected]):
        return
    for kind, markers in KIND_MARKERS.items():
        if kind != expected and any(k in raw for k in markers) and (
                kind != "sweep" or any(isinstance(raw.get(k), str) for k in markers)):
            raise ConfigError(file, None, None, f"this is a {kind} file, not a {expected} file")


def top_table(raw, file, schema_file: str) -> tuple:
    """(the file's top-level :class:`Table`, its ``name``): the name defaults to the
    file's stem, or to ``schema_file`` ("bearing", "profile") for in-memory input."""
    refuse_other_kind(raw, file, schema_file)
    top = Table(raw, [], file, schema_file)
    stem = Path(str(file)).stem if file != "<input>" else schema_file
    return top, top.get("name", default=stem)
