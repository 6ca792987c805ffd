"""Case ids: the canonical JSON of a case's resolved configuration and its hash.

What is hashed (:func:`pipeline.schema.sweepfile.case_configuration`, with
``MODEL_VERSION``) is described in :mod:`pipeline.schema.sweepfile`; changing anything
here changes every case id (``tests/pipeline/test_regression.py`` pins them).
"""
from __future__ import annotations

import dataclasses
import hashlib
import json

import numpy as np


#: Types :func:`plain` returns as they are (exact types: a numpy scalar is converted).
_LEAVES = frozenset({float, int, str, bool, type(None)})
#: Dataclass -> its fields' names (:func:`dataclasses.fields`), looked up once per class.
_FIELD_NAMES = {}


def _field_names(cls) -> tuple:
    names = _FIELD_NAMES.get(cls)
    if names is None:
        names = _FIELD_NAMES[cls] = tuple(f.name for f in dataclasses.fields(cls))
    return names


def plain(obj):
    """Dataclasses, tuples and numpy scalars as plain dicts, lists, floats (None dropped)."""
    cls = type(obj)
    if cls in _LEAVES:
        return obj
    if hasattr(cls, "__dataclass_fields__"):   # an instance (a class's type is no dataclass)
        out = {}
        for name in _field_names(cls):
            value = getattr(obj, name)
            if value is not None:
                out[name] = plain(value)
        return out
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items() if v is not None}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    return obj


class IdentityMemo:
    """Values computed once per object within one expansion of a sweep (a bearing's plain
    form, its load capacity), keyed by the object's identity and what is computed.

    Each entry holds a reference to its object, so that no id is reused by another object
    while the memo lives; objects are never compared by value (two draws of a statistics
    sweep are different objects with their own entries).
    """

    def __init__(self):
        self._values = {}

    def get(self, obj, what, compute):
        """``compute(obj)``, computed on the first call for this object and ``what``."""
        key = (id(obj), what)
        hit = self._values.get(key)
        if hit is None:
            hit = self._values[key] = (obj, compute(obj))
        return hit[1]


def canonical_json(obj) -> str:
    """Sorted keys, no whitespace, shortest round-trip floats: the hashed form."""
    return plain_json(plain(obj))


def plain_json(data) -> str:
    """:func:`canonical_json` of data already in :func:`plain` form (``plain`` is idempotent)."""
    return json.dumps(data, sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def hash_id(obj) -> str:
    """First 16 hex digits of the SHA-256 of :func:`canonical_json`."""
    return hash_plain(plain(obj))


def hash_plain(data) -> str:
    """:func:`hash_id` of data already in :func:`plain` form."""
    return hashlib.sha256(plain_json(data).encode("utf-8")).hexdigest()[:16]
