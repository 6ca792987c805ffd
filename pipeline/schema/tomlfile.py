"""TOML files and key paths: reading, ``rows[0].cage.width`` paths, and ``--set`` values.

The one ``--set`` parser lives here: :func:`parse_set` splits ``KEY=VALUE`` and
:func:`parse_value` reads the value (a TOML literal when it is one, else the string as
written, e.g. ``"0.5 mm"``). Every command and :func:`apply_override` use them.
"""
from __future__ import annotations

import copy
import os
import re
import stat
import tomllib
from pathlib import Path

from ..errors import ConfigError

__all__ = ["read_toml", "loads_toml", "MAX_INPUT_BYTES", "resolve_path", "parse_key_path", "format_key_path", "lookup",
           "apply_override", "parse_value", "parse_set", "parse_sets", "MISSING"]

#: Marks "no value" (a required key, a missing default) where None is a value.
MISSING = object()
_MISSING = MISSING


# --------------------------------------------------------------------------- files


#: Largest input file read [bytes]. The shipped files are a few kB; a sweep's ``[[cases]]``
#: list of :data:`pipeline.schema.sweepaxes.MAX_CASES` cases of about 100 bytes each is
#: 10 MB. 16 MiB holds that and stops ``/dev/zero``-like input before it fills the memory.
MAX_INPUT_BYTES = 16 * 1024 * 1024

#: The UTF-8 byte order mark some Windows editors write first. TOML says nothing of it and
#: tomllib refuses it ("invalid TOML at line 1"); it carries no meaning, so it is dropped.
_BOM = b"\xef\xbb\xbf"


def read_toml(path) -> dict:
    """Read a TOML file into a dict.

    Only a regular file of at most :data:`MAX_INPUT_BYTES` is read (a device, a FIFO or
    a larger file is refused before a byte is read); a leading UTF-8 byte order mark is
    dropped.

    Parameters
    ----------
    path : str or Path
        The file [-].

    Raises
    ------
    ConfigError
        ``ConfigError(path, None, None, reason)`` when the file is missing, unreadable,
        not a regular file, too large, nested too deep or not valid TOML (the reason
        carries tomllib's line and column).
    """
    p = Path(path)
    try:
        if stat.S_ISDIR(p.stat().st_mode):
            raise IsADirectoryError(path)
        if not stat.S_ISREG(p.stat().st_mode):   # before open(): opening a FIFO waits for a writer
            raise ConfigError(path, None, None, "not a regular file (a device, a pipe or a socket); "
                                                "give a TOML file")
        with p.open("rb") as fh:
            st = os.fstat(fh.fileno())
            if st.st_size > MAX_INPUT_BYTES:
                raise ConfigError(path, None, None, f"{st.st_size} bytes: larger than the "
                                                    f"{MAX_INPUT_BYTES // 2**20} MiB an input file may be")
            data = fh.read(MAX_INPUT_BYTES + 1)
        if len(data) > MAX_INPUT_BYTES:   # grew while being read
            raise ConfigError(path, None, None, f"larger than the {MAX_INPUT_BYTES // 2**20} MiB an "
                                                "input file may be")
        return loads_toml(data.removeprefix(_BOM).decode("utf-8"), path)
    except FileNotFoundError:
        raise ConfigError(path, None, None, "no such file") from None
    except IsADirectoryError:
        raise ConfigError(path, None, None, "is a directory, not a TOML file") from None
    except PermissionError:
        raise ConfigError(path, None, None, "permission denied") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(path, None, None, f"not UTF-8 text: {exc.reason} at byte {exc.start}") from None


def loads_toml(text: str, file="<input>") -> dict:
    """TOML text into a dict; every failure one :class:`ConfigError` naming ``file``.

    tomllib recurses once a level of nesting: a file nested a few thousand levels deep
    (``a = [[[[...]]]]``) exhausts Python's stack, which is said here in one line.
    """
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(file, None, None, f"invalid TOML: {exc}") from None
    except RecursionError:
        raise ConfigError(file, None, None, "nested too deep: tables or arrays inside each other "
                                            "more levels than a TOML reader can follow") from None


def resolve_path(base_file, relative) -> Path:
    """A path written in ``base_file``, taken relative to that file's folder.

    Absolute paths (and ``~``) are returned as they are.

    Parameters
    ----------
    base_file : str or Path
        The file the path was written in [-].
    relative : str or Path
        The path as written [-].
    """
    rel = Path(relative).expanduser()
    if rel.is_absolute():
        return rel
    return Path(base_file).parent / rel


# --------------------------------------------------------------------------- key paths

_KEY_PATH = re.compile(r"^[A-Za-z_][\w-]*(\[\d+\])*(\.[A-Za-z_][\w-]*(\[\d+\])*)*$")
_TOKEN = re.compile(r"([^.\[\]]+)|\[(\d+)\]")


def parse_key_path(dotted_key: str, file="--set", value=None) -> list:
    """Split ``"rows[0].cage.width"`` into ``["rows", 0, "cage", "width"]``.

    Raises
    ------
    ConfigError
        When the key is not a dotted path of names and ``[index]`` parts.
    """
    if not isinstance(dotted_key, str) or not _KEY_PATH.match(dotted_key):
        raise ConfigError(file, str(dotted_key), value,
                          "not a key path (write names joined by '.', list items as [i], "
                          "e.g. rows[0].cage.pocket_clearance)")
    return [int(i) if i else name for name, i in _TOKEN.findall(dotted_key)]


def format_key_path(parts) -> str:
    """Inverse of :func:`parse_key_path`."""
    out = ""
    for p in parts:
        if isinstance(p, int):
            out += f"[{p}]"
        else:
            out += f".{p}" if out else str(p)
    return out


def lookup(raw: dict, dotted_key: str, default=_MISSING):
    """The value at ``dotted_key`` in a nested dict/list, or ``default`` (KeyError if none)."""
    node = raw
    try:
        for part in parse_key_path(dotted_key):
            if isinstance(part, int):
                if not isinstance(node, list):
                    raise KeyError(dotted_key)
                node = node[part]
            else:
                if not isinstance(node, dict):
                    raise KeyError(dotted_key)
                node = node[part]
    except (KeyError, IndexError, ConfigError):
        if default is _MISSING:
            raise KeyError(dotted_key) from None
        return default
    return node


def apply_override(raw: dict, dotted_key: str, value, file="--set") -> dict:
    """A deep copy of ``raw`` with the existing key ``dotted_key`` set to ``value``.

    Parameters
    ----------
    raw : dict
        A file's contents as read by :func:`read_toml` [-].
    dotted_key : str
        Path of an existing key, e.g. ``"friction.mu_static"``,
        ``"rows[0].cage.pocket_clearance"``, ``"rows[0].balls.count"``.
    value : str, int, float, bool or list
        The new value. A string is read as a TOML literal when it is one (``"40"`` is
        the integer 40, ``"true"`` a boolean, ``'"x"'`` a string), and kept as the
        string otherwise (``"0.5 mm"``); the loader then validates it as usual.
    file : str
        Where the override came from, for error messages.

    Raises
    ------
    ConfigError
        When the key does not exist (no new keys are created), an index is out of range,
        or the key names a table rather than a value.
    """
    parts = parse_key_path(dotted_key, file, value)
    new = copy.deepcopy(raw)
    node = new
    for depth, part in enumerate(parts):
        where = format_key_path(parts[:depth]) or "the top level"
        last = depth == len(parts) - 1
        if isinstance(part, int):
            if not isinstance(node, list):
                raise ConfigError(file, dotted_key, value, f"{where} is not a list")
            if part >= len(node):
                raise ConfigError(file, dotted_key, value,
                                  f"index {part} out of range: {where} has {len(node)} item(s)")
        else:
            if not isinstance(node, dict):
                raise ConfigError(file, dotted_key, value, f"{where} is not a table")
            if part not in node:
                known = ", ".join(sorted(node)) or "none"
                raise ConfigError(file, dotted_key, value,
                                  f"unknown key: {where} has no '{part}' (its keys: {known})")
        if last:
            old = node[part]
            if isinstance(old, dict) or (isinstance(old, list) and old and isinstance(old[0], dict)):
                raise ConfigError(file, dotted_key, value,
                                  "names a table, not a value: set one of its keys")
            node[part] = parse_value(value)
        else:
            node = node[part]
    return new


# --------------------------------------------------------------------------- --set


def parse_value(value):
    """A ``--set`` or override value: a TOML literal if it parses as one, else the string.

    ``"40"`` is the integer 40, ``"0.05"`` a float, ``"true"``/``"True"`` a boolean,
    ``'"x"'`` the string ``x``, ``"[1, 2]"`` a list; ``"0.5 mm"`` stays the string
    ``"0.5 mm"`` (the loader reads its units). Non-strings are returned as they are.
    """
    if not isinstance(value, str):
        return value
    text = value.strip()
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except (tomllib.TOMLDecodeError, RecursionError):
        if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
            return text[1:-1]
        return text


def parse_set(item: str, file="--set") -> tuple:
    """``"friction.mu_static=0.05"`` -> ``("friction.mu_static", 0.05)``.

    The key must be a key path (:func:`parse_key_path`); the value is read by
    :func:`parse_value`.

    Raises
    ------
    ConfigError
        One line naming ``--set``, the item and the reason.
    """
    key, sep, value = str(item).partition("=")
    key = key.strip()
    if not sep or not key:
        raise ConfigError(file, str(item), None, "expected KEY=VALUE, e.g. friction.mu_static=0.05")
    if not value.strip():
        raise ConfigError(file, key, value, "no value after '='")
    parse_key_path(key, file, value.strip())
    return key, parse_value(value)


def parse_sets(items, file="--set") -> dict:
    """Several ``KEY=VALUE`` items (:func:`parse_set`) as a dict; a repeated key is an error."""
    out = {}
    for item in items:
        key, value = parse_set(item, file)
        if key in out:
            raise ConfigError(file, key, value, f"given twice (first as {out[key]!r})")
        out[key] = value
    return out
