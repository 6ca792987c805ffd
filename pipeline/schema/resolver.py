"""Bearing and profile values of a sweep: the files it names, and each case's overrides
applied and validated by the bearing and profile loaders (with caches)."""
from __future__ import annotations

import copy
from pathlib import Path

from rvcore.bearing.geometry import Bearing
from rvcore.profile import Profile

from ..errors import ConfigError
from .bearingfile import bearing_from_dict
from .profilefile import profile_from_dict
from .tomlfile import apply_override, parse_key_path, resolve_path


def resolve_file(sweep_file: Path, raw: dict, key: str) -> Path:
    if key not in raw:
        raise ConfigError(sweep_file, key, None, f"missing required key: the {key} file")
    v = raw[key]
    if not isinstance(v, str) or not v.strip():
        raise ConfigError(sweep_file, key, v, "must be a file path (a string)")
    p = resolve_path(sweep_file, v)
    if p.is_file():
        return p
    shipped = _shipped(v)
    if shipped is not None:
        return shipped
    raise ConfigError(sweep_file, key, v, f"no such {key} file ({p}), nor a shipped one of that name")


def _shipped(written: str):
    """The shipped file a relative path names (``bearings/reduced-test.toml``, or
    ``sweeps/bearings/...``), or None: the README's "shipped files can be named from
    anywhere" holds inside a copied sweep file too."""
    from .shipped import shipped_root

    rel = Path(written).expanduser()
    if rel.is_absolute() or not rel.parts:
        return None
    if rel.parts[0] == "sweeps":
        rel = Path(*rel.parts[1:])
    root = shipped_root().resolve()
    candidate = (root / rel).resolve()
    if root in candidate.parents and candidate.is_file():
        return candidate
    return None

def read_named_file(sweep_file: Path, raw: dict, key: str) -> tuple:
    """(path, TOML) of the ``bearing`` or ``profile`` file a sweep names; a file of another
    kind there is said about the sweep file's key ("this is a bearing file, not a profile
    file"), which is what to change."""
    from .reader import refuse_other_kind
    from .tomlfile import read_toml

    path = resolve_file(sweep_file, raw, key)
    named = read_toml(path)
    try:
        refuse_other_kind(named, path, key)
    except ConfigError as exc:
        raise ConfigError(sweep_file, key, raw[key], f"{exc.reason} ({path})") from None
    return path, named


class Resolver:
    """Builds bearing/profile/solver/operating point for a set of values, with caches."""

    def __init__(self, sweep_file, bearing_file, bearing_raw, profile_file, profile_raw):
        self.sweep_file = sweep_file
        self.bearing_file = bearing_file
        self.profile_file = profile_file
        self.bearing_raw = bearing_raw
        self.profile_raw = profile_raw
        self._bearings = {}
        self._profiles = {}

    def _override(self, raw, target_file, key, value, where):
        try:
            return apply_override(raw, key, value, file=self.sweep_file)
        except ConfigError as exc:
            if not exc.reason.startswith("unknown key"):
                raise ConfigError(self.sweep_file, where, value, exc.reason) from None
            # The file leaves the key at its default (e.g. friction.mu_static without a
            # [friction] table): create it; the loader rejects keys it does not know.
            created = _set_creating(raw, parse_key_path(key, self.sweep_file, value), value)
            if created is None:
                raise ConfigError(self.sweep_file, where, value, exc.reason) from None
            return created

    def _build(self, kind, overrides: tuple):
        cache = self._bearings if kind == "bearing" else self._profiles
        cache_key = repr(overrides)
        if cache_key in cache:
            return cache[cache_key]
        raw = self.bearing_raw if kind == "bearing" else self.profile_raw
        file = self.bearing_file if kind == "bearing" else self.profile_file
        for key, value, where in overrides:
            raw = self._override(raw, file, key, value, where)
        loader = bearing_from_dict if kind == "bearing" else profile_from_dict
        try:
            obj = loader(raw, file=str(file))
        except ConfigError as exc:
            for key, value, where in overrides:
                if exc.key == key or (exc.key or "").startswith(key + "."):
                    raise ConfigError(self.sweep_file, where, value,
                                      f"{exc.reason} (in {kind} {file.name})") from None
            if overrides:
                shown = ", ".join(f"{w} = {v!r}" for _, v, w in overrides)
                raise ConfigError(exc.file, exc.key, exc.value,
                                  f"{exc.reason} (with {shown} from {self.sweep_file})") from None
            raise
        cache[cache_key] = obj
        return obj

    def bearing(self, overrides: tuple) -> Bearing:
        return self._build("bearing", overrides)

    def profile(self, overrides: tuple) -> Profile:
        return self._build("profile", overrides)


def _set_creating(raw: dict, parts: list, value):
    """A deep copy of ``raw`` with ``parts`` set, creating missing tables; None if a
    missing part is a list index (lists are never created)."""
    new = copy.deepcopy(raw)
    node = new
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(part, int):
            if not isinstance(node, list) or part >= len(node):
                return None
            if last:
                node[part] = value
            else:
                node = node[part]
            continue
        if not isinstance(node, dict):
            return None
        if last:
            node[part] = value
        else:
            node = node.setdefault(part, {})
    return new
