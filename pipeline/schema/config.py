"""Bearing and profile files: TOML in, validated ``rvcore`` dataclasses out (SI).

Every quantity goes through :func:`pipeline.units.parse_quantity`, so a file may write
``"23 mm"``, ``"15 deg"``, ``"250 N s/m"`` or a plain SI number. Every problem is a
:class:`pipeline.errors.ConfigError` naming the file, the dotted key, the value as
written and the reason: unknown keys (anywhere, nested too), missing required keys,
wrong units, non-positive sizes, impossible geometry (``rvcore.geometry.geometry_problems``
plus the checks of :func:`extra_geometry_problems`).

Key paths
---------
Keys are written as dotted paths with list indices, exactly as the TOML nests them:
``friction.mu_static``, ``rows[0].balls.count``,
``rows[0].inner_groove.arcs[1].contact_angle``. The same paths are used in error
messages, in the ``assumptions`` list and by :func:`apply_override`.

Bearing file
------------
::

    name = "rv-main-study"            # optional, defaults to the file's stem
    description = "..."               # optional
    source = "..."                    # optional: where the numbers come from
    allow_ball_overlap = false        # optional; true turns a ball overlap into a warning
    assumptions = ["rows[0].radial_clearance", ...]   # keys whose values are assumed

    [envelope]     bore, outer_diameter, width
    [material]     density, youngs_modulus, poisson_ratio        (rings and balls)
                   -- or [ring_material] and [ball_material], each with the same keys
    [inner_ring]   shoulder_diameter; attached_mass = 0, attached_inertia = 0
    [contact]      damping, damping_depth, pocket_damping, land_damping
    [friction]     mu_static = 0.1, v_static = 0.1 m/s, mu_dynamic = 0.02,
                   v_dynamic = 1 m/s  (the study's values are the defaults)
    [[rows]]       pitch_diameter; axial_position = 0, radial_clearance = 0
    [rows.balls]   count, diameter
    [[rows.inner_groove.arcs]]   curvature_ratio, contact_angle   (1 or 2 per ring)
    [[rows.outer_groove.arcs]]   curvature_ratio, contact_angle
    [rows.cage]    inner_diameter, outer_diameter, width, pocket_clearance, guidance
                   ("outer-land" | "ball"), density, youngs_modulus, poisson_ratio,
                   land_clearance and land_stiffness (required when outer-land guided)

Assumptions: TOML comments are not readable by ``tomllib``, so each assumed value
carries a ``# ASSUMPTION: why`` comment for the reader *and* its key path in the
top-level ``assumptions`` list for the program. Each listed path must exist in the file
(a path to a table marks everything in it). They end up in ``Bearing.assumptions``.

Ball overlap: ``geometry_problems`` reports balls that do not fit on their pitch circle
with the numbers (model.md §10). With ``allow_ball_overlap = true`` that message goes
into ``Bearing.warnings`` (which every output must repeat) instead of being an error.

Profile file
------------
::

    name = "study"
    description = "..."
    duration = "4.6 s"
    [radial_load]  time = ["0 s", ...], fraction = [0, 1, 1, 0], interpolation = "linear"
    [axial_load]   (the same; ``value = ["10 kN", ...]`` instead of ``fraction`` gives
                   absolute values)
    [speed]        (the same; absolute values in angular speed, e.g. "660 deg/s")
    [phases]       startup = ["0.3 s", "0.8 s"], steady = [...], deceleration = [...]
"""
from __future__ import annotations

import copy
import dataclasses
import math
import re
import tomllib
from pathlib import Path

from rvcore.geometry import (MOUNTINGS, Arc, Bearing, Cage, ContactLaw, InnerRing, Material, Row,
                             geometry_problems)
from rvcore.profile import INTERPOLATIONS, PHASES, Channel, Profile

from ..errors import ConfigError
from .units import parse_quantity

__all__ = [
    "read_toml", "bearing_from_dict", "load_bearing", "profile_from_dict", "load_profile",
    "apply_override", "resolve_path", "parse_key_path", "format_key_path", "lookup",
    "extra_geometry_problems", "is_overlap_problem",
]

_MISSING = object()


# --------------------------------------------------------------------------- files


def read_toml(path) -> dict:
    """Read a TOML file into a dict.

    Parameters
    ----------
    path : str or Path
        The file [-].

    Raises
    ------
    ConfigError
        ``ConfigError(path, None, None, reason)`` when the file is missing, unreadable or
        not valid TOML (the reason carries tomllib's line and column).
    """
    p = Path(path)
    try:
        with p.open("rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise ConfigError(path, None, None, "no such file") from None
    except IsADirectoryError:
        raise ConfigError(path, None, None, "is a directory, not a TOML file") from None
    except PermissionError:
        raise ConfigError(path, None, None, "permission denied") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(path, None, None, f"invalid TOML: {exc}") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(path, None, None, f"not UTF-8 text: {exc.reason}") from None


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


def _parse_cli_value(value):
    """A ``--set`` value: a TOML literal if it parses as one, else the string itself."""
    if not isinstance(value, str):
        return value
    try:
        return tomllib.loads(f"v = {value}")["v"]
    except tomllib.TOMLDecodeError:
        return value


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
            node[part] = _parse_cli_value(value)
        else:
            node = node[part]
    return new


# --------------------------------------------------------------------------- table reader


class _Table:
    """One TOML table being read: checks unknown keys up front, reads typed values."""

    def __init__(self, data, path: list, file, allowed):
        self.path = list(path)
        self.file = file
        if not isinstance(data, dict):
            raise ConfigError(file, self.key(None), _short(data),
                              "expected a table" + (f" with keys {_join(allowed)}" if allowed else ""))
        self.data = data
        for k, v in data.items():
            if k not in allowed:
                raise ConfigError(file, self.key(k), _short(v),
                                  f"unknown key (allowed here: {_join(allowed)})")

    def key(self, name) -> str:
        parts = self.path + ([] if name is None else [name])
        return format_key_path(parts) or "<top level>"

    def has(self, name) -> bool:
        return name in self.data

    def raw(self, name, default=_MISSING):
        if name in self.data:
            return self.data[name]
        if default is _MISSING:
            raise ConfigError(self.file, self.key(name), None, "missing required key")
        return default

    def quantity(self, name, kind, *, default=_MISSING, sign="positive", upper=None):
        """A quantity in SI; ``sign`` is "positive", "nonnegative" or None."""
        if name not in self.data:
            if default is _MISSING:
                raise ConfigError(self.file, self.key(name), None, "missing required key")
            return float(default)
        v = self.data[name]
        return _check_quantity(v, kind, self.file, self.key(name), sign, upper)

    def quantities(self, name, kind, *, sign=None):
        v = self.raw(name)
        if not isinstance(v, list):
            raise ConfigError(self.file, self.key(name), _short(v), "expected a list")
        if not v:
            raise ConfigError(self.file, self.key(name), v, "must not be empty")
        return [_check_quantity(x, kind, self.file, f"{self.key(name)}[{i}]", sign, None)
                for i, x in enumerate(v)]

    def integer(self, name, *, minimum=None):
        v = self.raw(name)
        if isinstance(v, bool) or not isinstance(v, int):
            raise ConfigError(self.file, self.key(name), v, "must be an integer")
        if minimum is not None and v < minimum:
            raise ConfigError(self.file, self.key(name), v, f"must be at least {minimum}")
        return v

    def boolean(self, name, default=_MISSING):
        v = self.raw(name, default)
        if not isinstance(v, bool):
            raise ConfigError(self.file, self.key(name), v, "must be true or false")
        return v

    def string(self, name, default=_MISSING, choices=None):
        v = self.raw(name, default)
        if not isinstance(v, str):
            raise ConfigError(self.file, self.key(name), _short(v), "must be a string")
        if choices is not None and v not in choices:
            raise ConfigError(self.file, self.key(name), v, f"must be one of {_join(choices, quote=True)}")
        return v

    def table(self, name, allowed, *, required=True):
        if name not in self.data:
            if required:
                raise ConfigError(self.file, self.key(name), None, "missing required table")
            return _Table({}, self.path + [name], self.file, allowed)
        return _Table(self.data[name], self.path + [name], self.file, allowed)

    def tables(self, name, allowed, *, minimum=1):
        """An array of tables (``[[name]]``)."""
        v = self.raw(name)
        if isinstance(v, dict) or not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
            raise ConfigError(self.file, self.key(name), _short(v),
                              f"expected an array of tables (write [[{self.key(name)}]] sections)")
        if len(v) < minimum:
            raise ConfigError(self.file, self.key(name), v, f"needs at least {minimum} entr{'y' if minimum == 1 else 'ies'}")
        return [_Table(x, self.path + [name, i], self.file, allowed) for i, x in enumerate(v)]


def _check_quantity(v, kind, file, key, sign, upper):
    if isinstance(v, (dict, list)):
        raise ConfigError(file, key, _short(v), "expected a single quantity")
    x = parse_quantity(v, kind, file=file, key=key)
    if not math.isfinite(x):
        raise ConfigError(file, key, v, "must be finite")
    if sign == "positive" and not x > 0:
        raise ConfigError(file, key, v, f"must be positive (got {x:g} in SI)")
    if sign == "nonnegative" and x < 0:
        raise ConfigError(file, key, v, f"must not be negative (got {x:g} in SI)")
    if upper is not None and not x < upper:
        raise ConfigError(file, key, v, f"must be below {upper:g} (got {x:g})")
    return x


def _short(v):
    """A value for an error message: tables and long lists are not spelled out."""
    if isinstance(v, dict):
        return None
    if isinstance(v, list) and (len(v) > 8 or any(isinstance(x, dict) for x in v)):
        return None
    return v


def _join(names, quote=False):
    names = list(names)
    return ", ".join(f'"{n}"' if quote else str(n) for n in names)


# --------------------------------------------------------------------------- bearing

_TOP_KEYS = ("name", "description", "source", "allow_ball_overlap", "assumptions",
             "mounting", "gravity", "envelope", "material", "ring_material", "ball_material", "inner_ring",
             "contact", "friction", "rows")
_MATERIAL_KEYS = ("density", "youngs_modulus", "poisson_ratio")
_ROW_KEYS = ("pitch_diameter", "axial_position", "radial_clearance", "balls",
             "inner_groove", "outer_groove", "cage")
_CAGE_KEYS = ("inner_diameter", "outer_diameter", "width", "pocket_clearance",
              "land_clearance", "guidance", "land_stiffness") + _MATERIAL_KEYS
_GUIDANCE = ("outer-land", "ball")


def _material(t: _Table) -> Material:
    return Material(
        density=t.quantity("density", "density"),
        youngs_modulus=t.quantity("youngs_modulus", "pressure"),
        poisson_ratio=_poisson(t),
    )


def _poisson(t: _Table) -> float:
    nu = t.quantity("poisson_ratio", "dimensionless", sign=None)
    if not -1.0 < nu < 0.5:
        raise ConfigError(t.file, t.key("poisson_ratio"), t.raw("poisson_ratio"),
                          "must lie between -1 and 0.5 for an isotropic solid")
    return nu


def _arcs(row: _Table, groove: str, ball_diameter: float) -> tuple:
    g = row.table(groove, ("arcs",))
    arcs = g.tables("arcs", ("curvature_ratio", "contact_angle"))
    if len(arcs) > 2:
        raise ConfigError(row.file, g.key("arcs"), None,
                          f"{len(arcs)} arcs: a groove has one arc (deep groove or angular "
                          "contact) or two at ±α (four-point)")
    out = []
    for a in arcs:
        f = a.quantity("curvature_ratio", "dimensionless", sign=None)
        if f <= 0.5:
            rel = "smaller than" if f < 0.5 else "equal to"
            raise ConfigError(row.file, a.key("curvature_ratio"), a.raw("curvature_ratio"),
                              f"groove radius {rel} the ball's: f·D = {f * ball_diameter * 1e3:.4g} mm "
                              f"against a ball radius of {ball_diameter / 2 * 1e3:.4g} mm "
                              "(f must exceed 0.5)")
        alpha = a.quantity("contact_angle", "angle", sign=None)
        if not abs(alpha) < math.pi / 2:
            raise ConfigError(row.file, a.key("contact_angle"), a.raw("contact_angle"),
                              "a contact angle must lie strictly between -90 and 90 deg")
        out.append(Arc(curvature_ratio=f, contact_angle=alpha))
    if len(out) == 2:
        a0, a1 = out[0].contact_angle, out[1].contact_angle
        if a0 == 0.0 or a1 == 0.0 or (a0 > 0) == (a1 > 0):
            raise ConfigError(row.file, arcs[1].key("contact_angle"), arcs[1].raw("contact_angle"),
                              "the two arcs of a four-point groove must sit on opposite sides "
                              "of the groove (contact angles of opposite sign, ±α, neither 0)")
    return tuple(out)


def _row(t: _Table) -> Row:
    balls = t.table("balls", ("count", "diameter"))
    count = balls.integer("count", minimum=3)
    d = balls.quantity("diameter", "length")
    dm = t.quantity("pitch_diameter", "length")
    z = t.quantity("axial_position", "length", default=0.0, sign=None)
    pd = t.quantity("radial_clearance", "length", default=0.0, sign="nonnegative")
    inner = _arcs(t, "inner_groove", d)
    outer = _arcs(t, "outer_groove", d)
    c = t.table("cage", _CAGE_KEYS)
    guidance = c.string("guidance", choices=_GUIDANCE)
    land_required = _MISSING if guidance == "outer-land" else 0.0
    cage = Cage(
        inner_diameter=c.quantity("inner_diameter", "length"),
        outer_diameter=c.quantity("outer_diameter", "length"),
        width=c.quantity("width", "length"),
        pocket_clearance=c.quantity("pocket_clearance", "length", sign="nonnegative"),
        land_clearance=c.quantity("land_clearance", "length", default=land_required,
                                  sign="positive" if guidance == "outer-land" else "nonnegative"),
        guidance=guidance,
        material=_material(c),
        land_stiffness=c.quantity("land_stiffness", "stiffness_hertz", default=land_required,
                                  sign="positive" if guidance == "outer-land" else "nonnegative"),
    )
    return Row(ball_count=count, ball_diameter=d, pitch_diameter=dm, axial_position=z,
               inner_arcs=inner, outer_arcs=outer, cage=cage, radial_clearance=pd)


def extra_geometry_problems(bearing: Bearing):
    """Checks beyond ``rvcore.geometry.geometry_problems``, as ``(key, value, reason)``.

    - the cage is no wider than the bearing, and wider than its pockets (``D + c_p``),
      or the pockets would cut the cage ring in two;
    - an outer-land guided cage's land (bore ``d_cage,o + 2·c_land``) lies inside the
      outer ring's envelope and above the outer groove's bottom (``d_m + D``), so that
      the outer ring has a land there at all.
    """
    out = []
    for i, row in enumerate(bearing.rows):
        c = row.cage
        if c.width > bearing.width:
            out.append((f"rows[{i}].cage.width", c.width,
                        f"the cage ({c.width * 1e3:.4g} mm) is wider than the bearing "
                        f"({bearing.width * 1e3:.4g} mm)"))
        pocket = row.ball_diameter + c.pocket_clearance
        if c.width <= pocket:
            out.append((f"rows[{i}].cage.width", c.width,
                        f"the cage ({c.width * 1e3:.4g} mm) is not wider than its pockets "
                        f"({pocket * 1e3:.4g} mm = ball diameter + pocket clearance), so they "
                        "would cut the ring in two"))
        if c.guidance == "outer-land":
            land = c.outer_diameter + 2.0 * c.land_clearance
            groove_bottom = row.pitch_diameter + row.ball_diameter
            if land >= groove_bottom:
                out.append((f"rows[{i}].cage.outer_diameter", c.outer_diameter,
                            f"the cage does not fit inside the outer ring: its guiding land's bore "
                            f"({land * 1e3:.4g} mm = cage OD + 2 × land clearance "
                            f"{c.land_clearance * 1e3:.4g} mm) is not below the outer groove's "
                            f"bottom ({groove_bottom * 1e3:.4g} mm = d_m + D), so the outer ring "
                            "has no land there"))
    return out


def is_overlap_problem(key: str, reason: str) -> bool:
    """Whether a ``geometry_problems`` entry is the ball overlap of model.md §10."""
    return key.endswith(".balls.count") and "need a pitch diameter" in reason


def _assumptions(top: _Table, raw: dict) -> tuple:
    v = top.raw("assumptions", [])
    if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
        raise ConfigError(top.file, "assumptions", _short(v), "must be a list of key paths (strings)")
    for i, k in enumerate(v):
        parse_key_path(k, top.file, k)
        absent = object()
        if k == "assumptions" or lookup(raw, k, absent) is absent:
            raise ConfigError(top.file, f"assumptions[{i}]", k,
                              "names a key that is not in this file")
    return tuple(dict.fromkeys(v))


def _gravity(top: _Table, file) -> tuple:
    """Gravity in the bearing frame [m s^-2]: ``mounting`` by name, or ``gravity`` as a vector.

    ``mounting = "horizontal"`` (the default: axis horizontal, gravity along −y) or
    ``"vertical"`` (gravity along −z); ``gravity = ["0 m/s^2", "-9.81 m/s^2", "0 m/s^2"]``
    gives any other direction. Switching gravity off is a solver setting
    (``solver.gravity = false``), not a mounting.
    """
    if top.has("gravity"):
        if top.has("mounting"):
            raise ConfigError(file, "gravity", None, "give either mounting or a gravity vector, not both")
        vec = top.raw("gravity")
        if not isinstance(vec, list) or len(vec) != 3:
            raise ConfigError(file, "gravity", _short(vec),
                              'must be a list of three accelerations, e.g. ["0 m/s^2", "-9.81 m/s^2", "0 m/s^2"]')
        return tuple(parse_quantity(v, "acceleration", file=file, key=f"gravity[{i}]") for i, v in enumerate(vec))
    mounting = top.string("mounting", "horizontal", choices=tuple(MOUNTINGS))
    return MOUNTINGS[mounting]


def bearing_from_dict(raw: dict, file="<input>") -> Bearing:
    """Validate a bearing file's contents and build the :class:`rvcore.geometry.Bearing`.

    Parameters
    ----------
    raw : dict
        The file as read by :func:`read_toml` [-].
    file : str or Path
        The file's name, for error messages; its stem is the default ``name``.

    Returns
    -------
    rvcore.geometry.Bearing
        In SI, with ``warnings`` (accepted ball overlap) and ``assumptions``.

    Raises
    ------
    ConfigError
        The first problem found, naming file, key, value and reason.
    """
    top = _Table(raw, [], file, _TOP_KEYS)
    name = top.string("name", Path(str(file)).stem if file != "<input>" else "bearing")
    description = top.string("description", "")
    source = top.string("source", "")
    allow_overlap = top.boolean("allow_ball_overlap", False)

    env = top.table("envelope", ("bore", "outer_diameter", "width"))
    bore = env.quantity("bore", "length")
    od = env.quantity("outer_diameter", "length")
    width = env.quantity("width", "length")

    if top.has("material"):
        for other in ("ring_material", "ball_material"):
            if top.has(other):
                raise ConfigError(file, other, None,
                                  "give either [material] (rings and balls) or both "
                                  "[ring_material] and [ball_material], not both forms")
        ring_mat = ball_mat = _material(top.table("material", _MATERIAL_KEYS))
    elif top.has("ring_material") or top.has("ball_material"):
        ring_mat = _material(top.table("ring_material", _MATERIAL_KEYS))
        ball_mat = _material(top.table("ball_material", _MATERIAL_KEYS))
    else:
        raise ConfigError(file, "material", None,
                          "missing required table (or [ring_material] and [ball_material])")

    ir = top.table("inner_ring", ("shoulder_diameter", "attached_mass", "attached_inertia"))
    inner_ring = InnerRing(
        shoulder_diameter=ir.quantity("shoulder_diameter", "length"),
        attached_mass=ir.quantity("attached_mass", "mass", default=0.0, sign="nonnegative"),
        attached_inertia=ir.quantity("attached_inertia", "inertia", default=0.0, sign="nonnegative"),
    )

    ct = top.table("contact", ("damping", "damping_depth", "pocket_damping", "land_damping"))
    fr = top.table("friction", ("mu_static", "v_static", "mu_dynamic", "v_dynamic"), required=False)
    defaults = ContactLaw(0.0, 1.0, 0.0, 0.0)
    contact = ContactLaw(
        damping=ct.quantity("damping", "damping", sign="nonnegative"),
        damping_depth=ct.quantity("damping_depth", "length"),
        pocket_damping=ct.quantity("pocket_damping", "damping", sign="nonnegative"),
        land_damping=ct.quantity("land_damping", "damping", sign="nonnegative"),
        mu_static=fr.quantity("mu_static", "dimensionless", default=defaults.mu_static, sign="nonnegative"),
        v_static=fr.quantity("v_static", "speed", default=defaults.v_static),
        mu_dynamic=fr.quantity("mu_dynamic", "dimensionless", default=defaults.mu_dynamic, sign="nonnegative"),
        v_dynamic=fr.quantity("v_dynamic", "speed", default=defaults.v_dynamic),
    )
    if not contact.v_dynamic > contact.v_static:
        raise ConfigError(file, "friction.v_dynamic", fr.raw("v_dynamic", contact.v_dynamic),
                          f"must exceed friction.v_static ({contact.v_static:g} m/s)")

    rows = tuple(_row(t) for t in top.tables("rows", _ROW_KEYS))
    assumptions = _assumptions(top, raw)
    gravity = _gravity(top, file)

    bearing = Bearing(name=name, bore=bore, outer_diameter=od, width=width, rows=rows,
                      ring_material=ring_mat, ball_material=ball_mat, inner_ring=inner_ring,
                      contact=contact, allow_ball_overlap=allow_overlap, gravity=gravity,
                      assumptions=assumptions, source=source, description=description)

    warnings = []
    for key, value, reason in list(geometry_problems(bearing)) + extra_geometry_problems(bearing):
        if allow_overlap and is_overlap_problem(key, reason):
            warnings.append(reason)
            continue
        shown = lookup(raw, key, value)
        if isinstance(shown, (dict, list)):
            shown = value
        if is_overlap_problem(key, reason):
            reason += ("; set allow_ball_overlap = true to reproduce it anyway, with this "
                       "as a warning (model.md §10)")
        raise ConfigError(file, key, shown, reason)
    return dataclasses.replace(bearing, warnings=tuple(warnings))


def load_bearing(path) -> Bearing:
    """Read and validate a bearing file (:func:`read_toml` + :func:`bearing_from_dict`)."""
    return bearing_from_dict(read_toml(path), file=str(path))


# --------------------------------------------------------------------------- profile

_CHANNELS = {"radial_load": "force", "axial_load": "force", "speed": "angular_speed"}


def _channel(top: _Table, name: str, duration: float) -> Channel:
    t = top.table(name, ("time", "fraction", "value", "interpolation"))
    times = t.quantities("time", "time", sign="nonnegative")
    for i in range(1, len(times)):
        if not times[i] > times[i - 1]:
            raise ConfigError(t.file, f"{t.key('time')}[{i}]", t.raw("time")[i],
                              f"times must increase strictly (the previous one is "
                              f"{t.raw('time')[i - 1]!r})")
    if times[-1] > duration * (1 + 1e-12):
        raise ConfigError(t.file, f"{t.key('time')}[{len(times) - 1}]", t.raw("time")[-1],
                          f"breakpoint after the end of the cycle (duration = {duration:g} s)")
    has_f, has_v = t.has("fraction"), t.has("value")
    if has_f == has_v:
        raise ConfigError(t.file, t.key(None), None,
                          "give exactly one of 'fraction' (of the operating point) or 'value' "
                          "(absolute)" + (", not both" if has_f else ""))
    if has_f:
        values = t.quantities("fraction", "dimensionless")
        vkey = "fraction"
    else:
        values = t.quantities("value", _CHANNELS[name])
        vkey = "value"
    if len(values) != len(times):
        raise ConfigError(t.file, t.key(vkey), _short(t.raw(vkey)),
                          f"has {len(values)} entries but '{t.key('time')}' has {len(times)}")
    interp = t.string("interpolation", "linear", choices=tuple(INTERPOLATIONS))
    return Channel(times=tuple(times), values=tuple(values), relative=has_f, interpolation=interp)


def profile_from_dict(raw: dict, file="<input>") -> Profile:
    """Validate a profile file's contents and build the :class:`rvcore.profile.Profile`.

    Parameters
    ----------
    raw : dict
        The file as read by :func:`read_toml` [-].
    file : str or Path
        The file's name, for error messages; its stem is the default ``name``.

    Raises
    ------
    ConfigError
        Unknown keys, missing tables, times not strictly increasing, lists of unequal
        length, neither or both of ``fraction``/``value``, an unknown interpolation,
        phases outside the cycle or out of order.
    """
    top = _Table(raw, [], file, ("name", "description", "duration", "phases") + tuple(_CHANNELS))
    name = top.string("name", Path(str(file)).stem if file != "<input>" else "profile")
    description = top.string("description", "")
    duration = top.quantity("duration", "time")
    channels = {c: _channel(top, c, duration) for c in _CHANNELS}

    ph = top.table("phases", PHASES)
    phases = []
    previous_end, previous_name = 0.0, None
    for p in PHASES:
        se = ph.raw(p)
        if not isinstance(se, list) or len(se) != 2:
            raise ConfigError(file, ph.key(p), _short(se), "must be a list [start, end] of two times")
        s, e = (_check_quantity(x, "time", file, f"{ph.key(p)}[{i}]", "nonnegative", None)
                for i, x in enumerate(se))
        if not e > s:
            raise ConfigError(file, ph.key(p), se, "the end must come after the start")
        if e > duration * (1 + 1e-12):
            raise ConfigError(file, ph.key(p), se, f"ends after the cycle (duration = {duration:g} s)")
        if s < previous_end * (1 - 1e-12):
            raise ConfigError(file, ph.key(p), se,
                              f"starts before phase '{previous_name}' ends ({previous_end:g} s); "
                              f"phases must follow in the order {', '.join(PHASES)}")
        phases.append((p, s, e))
        previous_end, previous_name = e, p
    return Profile(name=name, radial_load=channels["radial_load"], axial_load=channels["axial_load"],
                   speed=channels["speed"], phases=tuple(phases), duration=duration,
                   description=description)


def load_profile(path) -> Profile:
    """Read and validate a profile file (:func:`read_toml` + :func:`profile_from_dict`)."""
    return profile_from_dict(read_toml(path), file=str(path))
