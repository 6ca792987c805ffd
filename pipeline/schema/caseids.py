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


def plain(obj):
    """Dataclasses, tuples and numpy scalars as plain dicts, lists, floats (None dropped)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)
                if getattr(obj, f.name) is not None}
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items() if v is not None}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    return obj


def canonical_json(obj) -> str:
    """Sorted keys, no whitespace, shortest round-trip floats: the hashed form."""
    return json.dumps(plain(obj), sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def hash_id(obj) -> str:
    """First 16 hex digits of the SHA-256 of :func:`canonical_json`."""
    return hashlib.sha256(canonical_json(obj).encode("utf-8")).hexdigest()[:16]
