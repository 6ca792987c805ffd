"""Sweep files: a grid (or a list) of cases, expanded and validated before anything runs.

A sweep file is TOML::

    name = "study"                          # optional; the file's stem by default. Names
                                            # the output folder results/<name>/
    description = "..."                     # optional
    bearing = "bearings/rv-main-study.toml" # relative to this file
    profile = "profiles/study.toml"         # relative to this file

    [axes]                                  # the grid: every combination is a case
    speed = {start = "120 deg/s", stop = "660 deg/s", step = "60 deg/s"}   # stop included
    radial_load = ["20 kN", "25 kN", "30 kN", "35 kN", "40 kN"]
    "friction.mu_static" = [0.08, 0.1, 0.12]        # any bearing value, by its key path
    "rows[0].cage.pocket_clearance" = ["0.3 mm", "0.5 mm"]
    "solver.time_step" = ["2 us", "1 us"]           # any solver setting

    [fixed]                                 # one value each, for every case
    axial_load = "10 kN"
    "contact.damping" = "300 N s/m"

    [solver]                                # fields of rvcore.driver.SolverSettings
    output_rate = "1000 Hz"
    time_step = "0 s"                       # 0: derived from the stiffest contact
    step_safety = 0.8
    gravity = true                          # false only for conservation checks

    realizations = 4                        # optional: 4 random starts per grid point,
    seed = 0                                # seeds 0..3 (axis ``realization``); default 1
                                            # and no seed: every ball at its pocket centre

    [[sensors]]                             # optional virtual displacement sensors
    name = "radial"
    position = ["160 mm", "0 mm", "0 mm"]   # the ring point it reads (bearing frame)
    direction = [1, 0, 0]                   # measuring direction

Instead of ``[axes]``, a list of explicit cases may be given, each a table of values
(keys as in ``[axes]``; values missing from a case come from ``[fixed]``)::

    [[cases]]
    speed = "120 deg/s"
    radial_load = "30 kN"

    [[cases]]
    speed = "660 deg/s"
    radial_load = "30 kN"
    "friction.mu_static" = 0.12

Keys
----
- operating point: ``speed``, ``radial_load``, ``axial_load`` (all three required, as
  an axis or a fixed value), ``moment``, ``load_angle`` (default 0);
- ``solver.<field>``: a :class:`rvcore.driver.SolverSettings` field;
- ``profile.<key path>``: a value of the profile file;
- ``bearing.<key path>``, or the key path alone when it has a ``.`` or ``[i]``
  (``friction.mu_static``, ``rows[0].cage.pocket_clearance``): a value of the bearing
  file, applied with :func:`pipeline.config.apply_override` and validated by
  :func:`pipeline.config.bearing_from_dict` like the file itself.

Quantities are unit strings ("120 deg/s", "20 kN") read by
:func:`pipeline.units.parse_quantity`, or plain numbers taken as SI. Written unquoted,
``friction.mu_static = [...]`` is a TOML dotted key and means the same.

Every problem (unknown key, bad unit, empty axis, missing bearing or profile file, a
bearing value out of range in some case) is a :class:`pipeline.errors.ConfigError`
raised by :func:`load_sweep`, before any case runs.

Case ids
--------
A case's id is the first 16 hex digits of the SHA-256 of the canonical JSON (sorted
keys, no spaces, ``repr`` floats) of everything that determines its result: the
resolved bearing, profile, solver settings and operating point, all in SI, and
:data:`MODEL_VERSION`. The same values written in other units give the same id; a
changed value gives new ids to exactly the cases it changes.
"""
from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import tomli_w

from rvcore.driver import SolverSettings
from rvcore.geometry import Bearing
from rvcore.profile import OperatingPoint, Profile

from . import config
from ..errors import ConfigError
from ..io import UDUNITS, cf_name
from .units import SI_UNITS, parse_quantity, registry

#: Version of the model's equations and numerics. Part of every case id: bump it when a
#: change to ``rvcore`` changes results, so that resumed sweeps recompute every case.
MODEL_VERSION = 3

#: Operating-point keys and their kinds (pipeline.units.SI_UNITS).
OPERATING_POINT = {
    "speed": "angular_speed",
    "radial_load": "force",
    "axial_load": "force",
    "moment": "moment",
    "load_angle": "angle",
}
REQUIRED_OPERATING_POINT = ("speed", "radial_load", "axial_load")

#: Kinds of the SolverSettings fields (booleans are recognised by their default).
SOLVER_KINDS = {
    "output_rate": "frequency",
    "step_safety": "dimensionless",
    "time_step": "time",
    "start_time": "time",
    "end_time": "time",
}

#: Kind of a bearing or profile value by the last part of its key path, to label a
#: plain-number axis in the combined file (values with units carry their own kind).
_KEY_KINDS = {
    "bore": "length", "outer_diameter": "length", "inner_diameter": "length",
    "width": "length", "diameter": "length", "pitch_diameter": "length",
    "axial_position": "length", "radial_clearance": "length", "pocket_clearance": "length",
    "land_clearance": "length", "shoulder_diameter": "length", "damping_depth": "length",
    "density": "density", "youngs_modulus": "pressure", "poisson_ratio": "dimensionless",
    "attached_mass": "mass", "attached_inertia": "inertia",
    "damping": "damping", "pocket_damping": "damping", "land_damping": "damping",
    "mu_static": "dimensionless", "mu_dynamic": "dimensionless",
    "v_static": "speed", "v_dynamic": "speed", "curvature_ratio": "dimensionless",
    "contact_angle": "angle", "land_stiffness": "stiffness_hertz", "count": "dimensionless",
    "duration": "time",
}

TOP_KEYS = ("name", "description", "bearing", "profile", "axes", "fixed", "solver", "cases",
            "realizations", "seed", "sensors")
#: The ensemble axis: realization k of ``realizations = N`` runs with ``solver.seed = seed + k``.
REALIZATION = "realization"
_SENSOR_KEYS = ("name", "position", "direction")
_RANGE_KEYS = ("start", "stop", "step")
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")

# Free text that does not change a result: left out of the case id.
_BEARING_METADATA = ("description", "source", "extra")
_PROFILE_METADATA = ("description",)


# --------------------------------------------------------------------------- data


@dataclass(frozen=True)
class Axis:
    """One sweep axis.

    Parameters
    ----------
    key : str
        The key as written (``"speed"``, ``"friction.mu_static"``, ``"solver.time_step"``).
    target : str
        ``"operating_point"``, ``"solver"``, ``"bearing"`` or ``"profile"``.
    values : tuple
        What each case receives: SI floats for operating-point and solver axes; for
        bearing and profile axes the value handed to ``apply_override`` (a unit string
        as written, or an SI float).
    coords : tuple
        The SI value of each entry (float), a bool, or a string for a categorical value;
        used as the coordinate of the combined file.
    kind : str or None
        Kind of :data:`pipeline.units.SI_UNITS`, ``"bool"``, ``"category"``, or None
        when unknown (a plain number on a bearing key not in the kind table).
    """

    key: str
    target: str
    values: tuple
    coords: tuple
    kind: str | None

    @property
    def name(self) -> str:
        """The CF variable/dimension name of this axis in the combined file."""
        return cf_name(self.key)

    @property
    def units(self) -> str:
        """UDUNITS string of the coordinates ('1' when dimensionless or unknown)."""
        if self.key == "speed":
            return "degree s-1"
        if self.kind in UDUNITS:
            return UDUNITS[self.kind]
        return "1"

    def __len__(self) -> int:
        return len(self.values)


@dataclass(frozen=True)
class CaseSpec:
    """One fully resolved case: everything a worker needs, in SI.

    Parameters
    ----------
    case_id : str
        16 hex digits (see the module docstring).
    point : dict
        Axis key -> coordinate value (SI float, bool or str) of this case, plus the
        three required operating-point values whether they are axes or fixed.
    bearing : rvcore.geometry.Bearing
    profile : rvcore.profile.Profile
    operating_point : rvcore.profile.OperatingPoint
        [rad s^-1, N, N, N m, rad]
    settings : rvcore.driver.SolverSettings
    configuration : str
        The resolved case as TOML (SI), stored in the case file.
    sensors : tuple of rvcore.driver.Sensor
        The sweep's virtual sensors.
    """

    case_id: str
    point: dict
    bearing: Bearing
    profile: Profile
    operating_point: OperatingPoint
    settings: SolverSettings
    configuration: str
    sensors: tuple = ()


@dataclass(frozen=True)
class Sweep:
    """A validated sweep: its axes and the resolved cases.

    ``axes`` are the dimensions of the grid in file order; for a list of explicit cases
    they are the keys the cases set, with their distinct values. ``cases`` are in grid
    order (the first axis varies slowest) or in the order of the list.
    """

    name: str
    file: Path
    description: str
    bearing_file: Path
    profile_file: Path
    axes: tuple
    fixed: dict
    settings: SolverSettings
    bearing: Bearing
    profile: Profile
    cases: tuple
    explicit: bool
    configuration: str
    configuration_hash: str
    sensors: tuple = ()
    realizations: int = 1

    def axis(self, key: str) -> Axis | None:
        for a in self.axes:
            if a.key == key:
                return a
        return None


# --------------------------------------------------------------------------- helpers


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


def case_configuration(bearing: Bearing, profile: Profile, op: OperatingPoint,
                       settings: SolverSettings, sensors=()) -> dict:
    """Everything that determines a case's result, as plain SI data (hashed for the id).

    The solver settings carry the seed of the random start, so each realization of an
    ensemble has its own id.
    """
    b = {k: v for k, v in plain(bearing).items() if k not in _BEARING_METADATA}
    p = {k: v for k, v in plain(profile).items() if k not in _PROFILE_METADATA}
    conf = {"model_version": MODEL_VERSION, "operating_point": plain(op),
            "solver": plain(settings), "bearing": b, "profile": p}
    if sensors:
        conf["sensors"] = plain(list(sensors))
    return conf


def _sensors(raw, file) -> tuple:
    """``[[sensors]]``: name, position (three lengths) and direction (three numbers)."""
    from rvcore.driver import Sensor

    if raw is None:
        return ()
    if not isinstance(raw, list) or not all(isinstance(t, dict) for t in raw):
        raise ConfigError(file, "sensors", None, "must be an array of tables ([[sensors]] sections)")
    out, names = [], set()
    for i, t in enumerate(raw):
        where = f"sensors[{i}]"
        for k in t:
            if k not in _SENSOR_KEYS:
                raise ConfigError(file, f"{where}.{k}", _short(t[k]), f"unknown key (allowed: {', '.join(_SENSOR_KEYS)})")
        for k in _SENSOR_KEYS:
            if k not in t:
                raise ConfigError(file, where, None, f"'{k}' is missing")
        name = t["name"]
        if not isinstance(name, str) or not _NAME.match(name):
            raise ConfigError(file, f"{where}.name", name, "must be a name of letters, digits, '.', '_' and '-'")
        if name in names:
            raise ConfigError(file, f"{where}.name", name, "duplicate sensor name")
        names.add(name)
        vec = {}
        for k, kind in (("position", "length"), ("direction", "dimensionless")):
            v = t[k]
            if not isinstance(v, list) or len(v) != 3:
                raise ConfigError(file, f"{where}.{k}", _short(v), "must be a list of three values (x, y, z)")
            vec[k] = tuple(_quantity(x, kind, file, f"{where}.{k}[{j}]") for j, x in enumerate(v))
        if not any(vec["direction"]):
            raise ConfigError(file, f"{where}.direction", t["direction"], "must not be the zero vector")
        out.append(Sensor(name, vec["position"], vec["direction"]))
    return tuple(out)


def _realization_axis(raw: dict, file) -> Axis | None:
    """The ``realization`` axis of ``realizations = N`` (and ``seed``), or None for N = 1
    without a seed (every ball at its pocket centre)."""
    n = raw.get("realizations", 1)
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ConfigError(file, "realizations", n, "must be a whole number of at least 1")
    seed = raw.get("seed")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise ConfigError(file, "seed", seed, "must be a whole number of at least 0")
    if n == 1 and seed is None:
        return None
    seeds = tuple(float((seed or 0) + k) for k in range(n))
    return Axis(REALIZATION, "solver", seeds, seeds, "dimensionless")


def _flatten(table: dict, prefix: str, file, where: str, ranges: bool) -> dict:
    """Nested TOML tables to dotted keys; ``{start, stop, step}`` tables are leaves."""
    out = {}
    for k, v in table.items():
        key = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict):
            if "start" in v or "stop" in v or "step" in v:
                if not ranges:
                    raise ConfigError(file, f"{where}.{key}", None,
                                      "a {start, stop, step} range belongs in [axes]; "
                                      "give one value here")
                out[key] = v
            elif not v:
                raise ConfigError(file, f"{where}.{key}", None, "empty table")
            else:
                out.update(_flatten(v, key, file, where, ranges))
        else:
            out[key] = v
    return out


def _target(key: str, file, where: str) -> tuple:
    """(target, key inside the target) of a sweep key; ConfigError if unknown."""
    if key in OPERATING_POINT:
        return "operating_point", key
    if key == REALIZATION:
        return "solver", "seed"
    head, _, rest = key.partition(".")
    if head == "solver" and rest:
        fields = {f.name for f in dataclasses.fields(SolverSettings)}
        if rest not in fields:
            raise ConfigError(file, f"{where}.{key}", None,
                              f"unknown solver setting (known: {', '.join(sorted(fields))})")
        return "solver", rest
    if head in ("bearing", "profile") and rest:
        config.parse_key_path(rest, file, None)
        return head, rest
    if "." in key or "[" in key:
        config.parse_key_path(key, file, None)
        return "bearing", key
    raise ConfigError(file, f"{where}.{key}", None,
                      "unknown key: not an operating-point value ("
                      + ", ".join(OPERATING_POINT)
                      + "), solver.<setting>, profile.<key> or a bearing key path such as "
                        "friction.mu_static (write bearing.<key> for a top-level bearing key)")


def _solver_kind(field: str):
    f = {x.name: x for x in dataclasses.fields(SolverSettings)}[field]
    if isinstance(f.default, bool):
        return "bool"
    return SOLVER_KINDS.get(field, "dimensionless")


def _kind_of_quantity(text: str):
    """Kind of a unit string by its dimensionality; None if it is not a quantity."""
    ureg = registry()
    try:
        q = ureg.Quantity(text.strip())
    except Exception:  # pint raises several types for text that is not a quantity
        return None
    if not hasattr(q, "dimensionality"):
        return "dimensionless"
    unit_text = str(q.units)
    angular = any(w in unit_text for w in ("radian", "degree", "revolution", "turn", "arcminute"))
    if q.dimensionless:
        return "angle" if angular else "dimensionless"
    for kind, target in SI_UNITS.items():
        if kind in ("angle", "dimensionless"):
            continue
        if q.dimensionality == ureg.Quantity(1, target).dimensionality:
            if kind in ("angular_speed", "frequency"):
                return "angular_speed" if angular else "frequency"
            return kind
    return None


def _override_coord(value, key: str, file, where: str):
    """(coordinate, kind) of a bearing/profile override value."""
    if isinstance(value, bool):
        return value, "bool"
    if isinstance(value, (int, float)):
        return float(value), _KEY_KINDS.get(re.sub(r"\[\d+\]$", "", key.split(".")[-1]))
    if isinstance(value, str):
        kind = _kind_of_quantity(value)
        if kind is None:
            return value, "category"
        return parse_quantity(value, kind, file=file, key=where), kind
    raise ConfigError(file, where, value, "an axis value must be a number, a string or a boolean")


def _quantity(value, kind: str, file, key: str):
    """An SI value of ``kind`` (bool for a boolean kind)."""
    if kind == "bool":
        if not isinstance(value, bool):
            raise ConfigError(file, key, value, "must be true or false")
        return value
    if isinstance(value, (dict, list)):
        raise ConfigError(file, key, None, "expected a single value")
    x = parse_quantity(value, kind, file=file, key=key)
    if not math.isfinite(x):
        raise ConfigError(file, key, value, "must be finite")
    return x


def _range(spec: dict, kind, file, key: str) -> tuple:
    """Expand ``{start, stop, step}`` (stop included) to (values, coords, kind).

    The values are computed in the unit ``start`` is written in, ``start + i·step`` for
    ``i = 0 … floor((stop − start)/step + 1e-9)``, and converted to SI afterwards, so
    "120 deg/s" by "60 deg/s" gives exactly 120, 180, … deg/s.
    """
    for k in spec:
        if k not in _RANGE_KEYS:
            raise ConfigError(file, f"{key}.{k}", spec[k], "unknown key in a range (allowed: start, stop, step)")
    for k in _RANGE_KEYS:
        if k not in spec:
            raise ConfigError(file, key, None, f"a range needs start, stop and step; '{k}' is missing")
    if kind is None:
        v = spec["start"]
        kind = _kind_of_quantity(v) if isinstance(v, str) else "dimensionless"
        if kind is None:
            raise ConfigError(file, f"{key}.start", v, "not a quantity")
    if kind in ("bool", "category"):
        raise ConfigError(file, key, None, "a range needs numbers")
    si = {k: _quantity(spec[k], kind, file, f"{key}.{k}") for k in _RANGE_KEYS}
    if not si["step"] > 0:
        raise ConfigError(file, f"{key}.step", spec["step"], "the step must be positive")
    if si["stop"] < si["start"]:
        raise ConfigError(file, key, None,
                          f"empty axis: stop ({spec['stop']!r}) is below start ({spec['start']!r})")
    ureg = registry()
    start = spec["start"]
    unit = ureg.Quantity(start.strip()).units if isinstance(start, str) else ureg.Unit(SI_UNITS[kind])
    scale = ureg.Quantity(1.0, unit).to(SI_UNITS[kind]).magnitude if kind != "dimensionless" else 1.0
    a, b, h = (si[k] / scale for k in _RANGE_KEYS)
    n = int(math.floor((b - a) / h + 1e-9)) + 1
    if n > 100_000:
        raise ConfigError(file, key, None, f"{n} values: too many for one axis")
    mags = [a + i * h for i in range(n)]
    # Whole-number steps in the written unit stay whole numbers (no 299.99999999999994).
    mags = [round(m) if abs(m - round(m)) < 1e-9 * max(1.0, abs(m)) else m for m in mags]
    values = tuple(float(m * scale) for m in mags)
    if all(isinstance(spec[k], int) and not isinstance(spec[k], bool) for k in _RANGE_KEYS):
        values = tuple(int(round(v)) for v in values)   # e.g. rows[0].balls.count
    return values, tuple(float(v) for v in values), kind


def _axis(key: str, spec, file) -> Axis:
    where = f"axes.{key}"
    target, inner = _target(key, file, "axes")
    if isinstance(spec, dict):
        kind = (OPERATING_POINT.get(inner) if target == "operating_point"
                else _solver_kind(inner) if target == "solver" else None)
        if target in ("bearing", "profile") and kind is None:
            v = spec.get("start")
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                kind = _KEY_KINDS.get(inner.split(".")[-1], "dimensionless")
        values, coords, kind = _range(spec, kind, file, where)
        return Axis(key, target, values, coords, kind)
    items = spec if isinstance(spec, list) else [spec]
    if not items:
        raise ConfigError(file, where, [], "empty axis: give at least one value")
    if target == "operating_point":
        kind = OPERATING_POINT[inner]
        values = tuple(_quantity(v, kind, file, f"{where}[{i}]") for i, v in enumerate(items))
        coords = values
    elif target == "solver":
        kind = _solver_kind(inner)
        values = tuple(_quantity(v, kind, file, f"{where}[{i}]") for i, v in enumerate(items))
        coords = values
    else:
        pairs = [_override_coord(v, inner, file, f"{where}[{i}]") for i, v in enumerate(items)]
        kinds = {k for _, k in pairs}
        if len(kinds) > 1:
            raise ConfigError(file, where, _short(items),
                              "the values of one axis must be of one kind (got "
                              + ", ".join(sorted(str(k) for k in kinds)) + ")")
        kind = kinds.pop()
        values = tuple(items)
        coords = tuple(c for c, _ in pairs)
    seen = {}
    for i, c in enumerate(coords):
        if c in seen:
            raise ConfigError(file, f"{where}[{i}]", items[i] if i < len(items) else c,
                              f"duplicate value (the same as {where}[{seen[c]}])")
        seen[c] = i
    return Axis(key, target, values, coords, kind)


def _short(v):
    return v if not isinstance(v, list) or len(v) <= 8 else None


def _resolve_file(sweep_file: Path, raw: dict, key: str) -> Path:
    if key not in raw:
        raise ConfigError(sweep_file, key, None, f"missing required key: the {key} file")
    v = raw[key]
    if not isinstance(v, str) or not v.strip():
        raise ConfigError(sweep_file, key, v, "must be a file path (a string)")
    p = config.resolve_path(sweep_file, v)
    if not p.is_file():
        raise ConfigError(sweep_file, key, v, f"no such {key} file ({p})")
    return p


class _Resolver:
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
            return config.apply_override(raw, key, value, file=self.sweep_file)
        except ConfigError as exc:
            if not exc.reason.startswith("unknown key"):
                raise ConfigError(self.sweep_file, where, value, exc.reason) from None
            # The file leaves the key at its default (e.g. friction.mu_static without a
            # [friction] table): create it; the loader rejects keys it does not know.
            created = _set_creating(raw, config.parse_key_path(key, self.sweep_file, value), value)
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
        loader = config.bearing_from_dict if kind == "bearing" else config.profile_from_dict
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
    import copy

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


def _check_operating_point(values: dict, file, where: dict):
    for k in REQUIRED_OPERATING_POINT:
        if k not in values:
            raise ConfigError(file, k, None,
                              "missing: give it in [axes] (several values) or [fixed] (one value)"
                              + (" or in every [[cases]] entry" if where.get("_cases") else ""))
    if values["radial_load"] < 0:
        raise ConfigError(file, where.get("radial_load", "radial_load"), values["radial_load"],
                          "must not be negative (its direction is load_angle)")


def _check_settings(settings: SolverSettings, file, where: str):
    if not settings.output_rate > 0:
        raise ConfigError(file, f"{where}.output_rate", settings.output_rate, "must be positive")
    if not settings.step_safety > 0:
        raise ConfigError(file, f"{where}.step_safety", settings.step_safety, "must be positive")
    for k in ("time_step", "start_time", "end_time"):
        if getattr(settings, k) < 0:
            raise ConfigError(file, f"{where}.{k}", getattr(settings, k), "must not be negative")
    if settings.end_time and settings.end_time <= settings.start_time:
        raise ConfigError(file, f"{where}.end_time", settings.end_time,
                          "must come after start_time (or be 0: the profile's duration)")


# --------------------------------------------------------------------------- loading


def load_sweep(path) -> Sweep:
    """Read, validate and expand a sweep file.

    Parameters
    ----------
    path : str or Path
        The sweep file [-].

    Returns
    -------
    Sweep
        With every case resolved (bearing, profile, operating point, settings, id).

    Raises
    ------
    ConfigError
        The first problem, naming the file, the key, the value and the reason.
    """
    file = Path(path)
    raw = config.read_toml(file)
    return sweep_from_dict(raw, file)


def sweep_from_dict(raw: dict, file) -> Sweep:
    """:func:`load_sweep` on already-read TOML (``file`` names it and anchors paths)."""
    file = Path(file)
    for k, v in raw.items():
        if k not in TOP_KEYS:
            hint = ""
            if k in OPERATING_POINT:
                hint = f"; put it in [axes] (several values) or [fixed] (one value)"
            elif k in {f.name for f in dataclasses.fields(SolverSettings)}:
                hint = f"; put it in [solver]"
            raise ConfigError(file, k, _short(v) if not isinstance(v, dict) else None,
                              f"unknown key (allowed: {', '.join(TOP_KEYS)}){hint}")
    name = raw.get("name", file.stem)
    if not isinstance(name, str) or not _NAME.match(name):
        raise ConfigError(file, "name", name,
                          "must be a folder name: letters, digits, '.', '_' and '-', "
                          "starting with a letter or digit")
    description = raw.get("description", "")
    if not isinstance(description, str):
        raise ConfigError(file, "description", None, "must be a string")

    bearing_file = _resolve_file(file, raw, "bearing")
    profile_file = _resolve_file(file, raw, "profile")
    bearing_raw = config.read_toml(bearing_file)
    profile_raw = config.read_toml(profile_file)
    resolver = _Resolver(file, bearing_file, bearing_raw, profile_file, profile_raw)

    # [solver]
    solver_raw = raw.get("solver", {})
    if not isinstance(solver_raw, dict):
        raise ConfigError(file, "solver", None, "must be a table ([solver])")
    fields = {f.name for f in dataclasses.fields(SolverSettings)}
    solver_values = {}
    for k, v in solver_raw.items():
        if k not in fields:
            raise ConfigError(file, f"solver.{k}", _short(v) if not isinstance(v, dict) else None,
                              f"unknown solver setting (known: {', '.join(sorted(fields))})")
        solver_values[k] = _quantity(v, _solver_kind(k), file, f"solver.{k}")

    # [fixed]
    fixed_raw = raw.get("fixed", {})
    if not isinstance(fixed_raw, dict):
        raise ConfigError(file, "fixed", None, "must be a table ([fixed])")
    fixed = {}         # key -> (target, inner, value given to the target, coordinate)
    for key, v in _flatten(fixed_raw, "", file, "fixed", ranges=False).items():
        fixed[key] = _fixed_value(key, v, file, "fixed")

    has_axes, has_cases = "axes" in raw, "cases" in raw
    if has_axes and has_cases:
        raise ConfigError(file, "cases", None, "give either [axes] (a grid) or [[cases]] (a list), not both")
    if not has_axes and not has_cases:
        raise ConfigError(file, "axes", None, "missing: give [axes] (a grid) or [[cases]] (a list of cases)")

    if has_axes:
        axes_raw = raw["axes"]
        if not isinstance(axes_raw, dict):
            raise ConfigError(file, "axes", None, "must be a table ([axes])")
        flat = _flatten(axes_raw, "", file, "axes", ranges=True)
        if not flat:
            raise ConfigError(file, "axes", None, "empty: give at least one axis")
        axes = tuple(_axis(k, v, file) for k, v in flat.items())
        ensemble = _realization_axis(raw, file)
        if ensemble is not None:
            if any(a.key == REALIZATION for a in axes):
                raise ConfigError(file, "realizations", raw.get("realizations"), "the realization axis is also in [axes]")
            axes = axes + (ensemble,)
        for a in axes:
            if a.key in fixed:
                raise ConfigError(file, f"fixed.{a.key}", None, "is also an axis in [axes]")
        points = []
        for combo in itertools.product(*(range(len(a)) for a in axes)):
            points.append({a.key: (a.target, _target(a.key, file, "axes")[1], a.values[i], a.coords[i],
                                   f"axes.{a.key}[{i}]")
                           for a, i in zip(axes, combo)})
        explicit = False
    else:
        cases_raw = raw["cases"]
        if _realization_axis(raw, file) is not None:
            raise ConfigError(file, "realizations", raw.get("realizations"),
                              "ensembles need a grid: give [axes] rather than [[cases]]")
        if not isinstance(cases_raw, list) or not all(isinstance(c, dict) for c in cases_raw):
            raise ConfigError(file, "cases", None, "must be an array of tables ([[cases]] sections)")
        if not cases_raw:
            raise ConfigError(file, "cases", [], "empty: give at least one case")
        points = []
        for i, c in enumerate(cases_raw):
            where = f"cases[{i}]"
            flat = _flatten(c, "", file, where, ranges=False)
            if not flat:
                raise ConfigError(file, where, None, "empty case")
            pt = {}
            for key, v in flat.items():
                if key in fixed:
                    raise ConfigError(file, f"{where}.{key}", v, "is also given in [fixed]")
                target, inner, value, coord = _fixed_value(key, v, file, where)
                pt[key] = (target, inner, value, coord, f"{where}.{key}")
            points.append(pt)
        keys = list(dict.fromkeys(k for pt in points for k in pt))
        for i, pt in enumerate(points):
            for k in keys:
                if k not in pt:
                    raise ConfigError(file, f"cases[{i}]", None,
                                      f"does not set '{k}', which other cases set; give it in "
                                      "every case (or in [fixed] and in no case)")
        axes = []
        for k in keys:
            target = points[0][k][0]
            coords = sorted({pt[k][3] for pt in points}, key=_sort_key)
            kinds = {_coord_kind(pt[k], k) for pt in points}
            axes.append(Axis(k, target, tuple(coords), tuple(coords), kinds.pop()))
        axes = tuple(axes)
        explicit = True

    sensors = _sensors(raw.get("sensors"), file)
    base_settings = SolverSettings(**solver_values)
    _check_settings(base_settings, file, "solver")
    base_bearing = resolver.bearing(tuple((inner, value, f"fixed.{k}")
                                          for k, (t, inner, value, _) in fixed.items() if t == "bearing"))
    base_profile = resolver.profile(tuple((inner, value, f"fixed.{k}")
                                          for k, (t, inner, value, _) in fixed.items() if t == "profile"))

    cases = []
    ids = {}
    for n, pt in enumerate(points):
        merged = {k: (t, inner, value, coord, f"fixed.{k}") for k, (t, inner, value, coord) in fixed.items()}
        merged.update(pt)
        op_values = {inner: value for (t, inner, value, _, _) in merged.values() if t == "operating_point"}
        op_where = {inner: w for (t, inner, _, _, w) in merged.values() if t == "operating_point"}
        op_where["_cases"] = explicit
        _check_operating_point(op_values, file, op_where)
        op = OperatingPoint(**op_values)
        solver_over = {inner: value for (t, inner, value, _, _) in merged.values() if t == "solver"}
        settings = dataclasses.replace(base_settings, **solver_over)
        settings = dataclasses.replace(settings, seed=int(settings.seed))
        if solver_over:
            _check_settings(settings, file, next(w for (t, _, _, _, w) in merged.values() if t == "solver"))
        bearing = resolver.bearing(tuple((inner, value, w) for (t, inner, value, _, w) in merged.values()
                                         if t == "bearing"))
        profile = resolver.profile(tuple((inner, value, w) for (t, inner, value, _, w) in merged.values()
                                         if t == "profile"))
        conf = case_configuration(bearing, profile, op, settings, sensors)
        case_id = hash_id(conf)
        if case_id in ids:
            raise ConfigError(file, "cases" if explicit else "axes", None,
                              f"case {n} is the same as case {ids[case_id]} (same resolved values)")
        ids[case_id] = n
        point = {k: merged[k][3] for k in REQUIRED_OPERATING_POINT}
        point.update({k: v[3] for k, v in pt.items()})
        cases.append(CaseSpec(case_id=case_id, point=point, bearing=bearing, profile=profile,
                              operating_point=op, settings=settings,
                              configuration=tomli_w.dumps(conf), sensors=sensors))

    sweep_conf = {
        "model_version": MODEL_VERSION,
        "name": name,
        "description": description,
        "sweep_file": str(file),
        "bearing_file": str(bearing_file),
        "profile_file": str(profile_file),
        "axes": {a.key: list(a.coords) for a in axes},
        "fixed": {k: coord for k, (_, _, _, coord) in fixed.items()},
        "solver": plain(base_settings),
        "case_ids": [c.case_id for c in cases],
        "bearing": {k: v for k, v in plain(base_bearing).items() if k != "extra"},
        "profile": plain(base_profile),
        "sensors": plain(list(sensors)),
    }
    return Sweep(name=name, file=file, description=description, bearing_file=bearing_file,
                 profile_file=profile_file, axes=axes,
                 fixed={k: coord for k, (_, _, _, coord) in fixed.items()},
                 settings=base_settings, bearing=base_bearing, profile=base_profile,
                 cases=tuple(cases), explicit=explicit,
                 configuration=tomli_w.dumps(plain(sweep_conf)),
                 configuration_hash=hash_id(sweep_conf), sensors=sensors,
                 realizations=int(raw.get("realizations", 1)))


def _sort_key(c):
    return (0, c, "") if isinstance(c, (int, float)) else (1, 0, str(c))


def _coord_kind(entry, key):
    target, inner, value, coord, _ = entry
    if target == "operating_point":
        return OPERATING_POINT[inner]
    if target == "solver":
        return _solver_kind(inner)
    if isinstance(coord, bool):
        return "bool"
    if isinstance(coord, str):
        return "category"
    if isinstance(value, str):
        return _kind_of_quantity(value)
    return _KEY_KINDS.get(inner.split(".")[-1])


def _fixed_value(key: str, v, file, prefix: str) -> tuple:
    """(target, inner key, value for the target, coordinate) of one value of ``[fixed]``
    or of a ``[[cases]]`` entry (``prefix`` names the table for error messages)."""
    where = f"{prefix}.{key}"
    target, inner = _target(key, file, prefix)
    if target == "operating_point":
        x = _quantity(v, OPERATING_POINT[inner], file, where)
        return target, inner, x, x
    if target == "solver":
        x = _quantity(v, _solver_kind(inner), file, where)
        return target, inner, x, x
    if isinstance(v, list):
        return target, inner, v, str(v)
    coord, _ = _override_coord(v, inner, file, where)
    return target, inner, v, coord
