"""Sweep files' keys and values: axes, ``[fixed]`` and ``[[cases]]`` values, sensors.

What kind each value is (an angular speed, a length, a switch) comes from the schema,
:mod:`pipeline.schema.fields`: operating-point keys, ``solver.<field>`` and bearing or
profile key paths alike. A value written with units carries its own kind.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import NamedTuple

from rvcore.simulation.settings import SolverSettings

from ..errors import ConfigError
from ..io.netcdf import cf_name
from . import fields
from .reader import check_value, short
from .tomlfile import parse_key_path
from .units import SI_UNITS, is_safe_text, parse_quantity, registry, si_udunits

#: Operating-point keys and their kinds (pipeline.schema.units.SI_UNITS), from the schema.
OPERATING_POINT = fields.operating_point()
REQUIRED_OPERATING_POINT = tuple(f.path for f in fields.fields_of("operating_point") if f.required)
#: Most cases one sweep file may define: a grid is expanded, hashed and written to one
#: combined file; beyond this, split the study into several sweeps.
MAX_CASES = 100_000
#: The ensemble axis: realization k of ``realizations = N`` runs with ``solver.seed = seed + k``.
REALIZATION = "realization"
_SENSOR_KEYS = ("name", "position", "direction")
_RANGE_KEYS = ("start", "stop", "step")
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*\Z")   # \Z, not $: "$" matches before a final newline


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
        Kind of :data:`pipeline.schema.units.SI_UNITS`, ``"bool"``, ``"category"``, or None
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
        # a kinematic viscosity (and an acceleration) axis has been labelled "1" so far
        if self.kind in SI_UNITS and self.kind not in ("acceleration", "kinematic_viscosity"):
            return si_udunits(self.kind)
        return "1"

    def __len__(self) -> int:
        return len(self.values)


def parse_sensors(raw, file) -> tuple:
    """``[[sensors]]``: name, position (three lengths) and direction (three numbers)."""
    from rvcore.simulation.settings import Sensor

    if raw is None:
        return ()
    if not isinstance(raw, list) or not all(isinstance(t, dict) for t in raw):
        raise ConfigError(file, "sensors", None, "must be an array of tables ([[sensors]] sections)")
    out, names = [], set()
    for i, t in enumerate(raw):
        where = f"sensors[{i}]"
        for k in t:
            if k not in _SENSOR_KEYS:
                raise ConfigError(file, f"{where}.{k}", short(t[k]), f"unknown key (allowed: {', '.join(_SENSOR_KEYS)})")
        for k in _SENSOR_KEYS:
            if k not in t:
                raise ConfigError(file, where, None, f"'{k}' is missing")
        name = t["name"]
        if not isinstance(name, str) or not NAME.match(name):
            raise ConfigError(file, f"{where}.name", name, "must be a name of letters, digits, '.', '_' and '-'")
        if name in names:
            raise ConfigError(file, f"{where}.name", name, "duplicate sensor name")
        names.add(name)
        vec = {}
        for k, kind in (("position", "length"), ("direction", "dimensionless")):
            v = t[k]
            if not isinstance(v, list) or len(v) != 3:
                raise ConfigError(file, f"{where}.{k}", short(v), "must be a list of three values (x, y, z)")
            vec[k] = tuple(quantity(x, kind, file, f"{where}.{k}[{j}]") for j, x in enumerate(v))
        if not any(vec["direction"]):
            raise ConfigError(file, f"{where}.direction", t["direction"], "must not be the zero vector")
        out.append(Sensor(name, vec["position"], vec["direction"]))
    return tuple(out)


def realization_axis(raw: dict, file) -> Axis | None:
    """The ``realization`` axis of ``realizations = N`` (and ``seed``), or None for N = 1
    without a seed (every ball at its pocket centre)."""
    n = raw.get("realizations", 1)
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ConfigError(file, "realizations", n, "must be a whole number of at least 1")
    if n > MAX_CASES:   # said before the seeds are listed, which alone could fill the memory
        raise ConfigError(file, "realizations", n, f"more than the {MAX_CASES} cases a sweep holds")
    seed = raw.get("seed")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise ConfigError(file, "seed", seed, "must be a whole number of at least 0")
    if seed is not None and seed + n - 1 > fields.MAX_SEED:
        raise ConfigError(file, "seed", seed, f"seed + realizations - 1 must be at most {fields.MAX_SEED} "
                                              "(2**53 - 1: the realization axis stores seeds as exact floats)")
    if n == 1 and seed is None:
        return None
    seeds = tuple(float((seed or 0) + k) for k in range(n))
    return Axis(REALIZATION, "solver", seeds, seeds, "dimensionless")


def flatten(table: dict, prefix: str, file, where: str, ranges: bool) -> dict:
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
                out.update(flatten(v, key, file, where, ranges))
        else:
            out[key] = v
    return out

def target_of(key: str, file, where: str) -> tuple:
    """(target, key inside the target) of a sweep key; ConfigError if unknown."""
    if key in OPERATING_POINT:
        return "operating_point", key
    if key == REALIZATION:
        return "solver", "seed"
    head, _, rest = key.partition(".")
    if head == "solver" and rest:
        known = fields.solver_fields()
        if rest not in known:
            raise ConfigError(file, f"{where}.{key}", None,
                              f"unknown solver setting (known: {', '.join(sorted(known))})")
        return "solver", rest
    if head in ("bearing", "profile") and rest:
        parse_key_path(rest, file, None)
        return head, rest
    if "." in key or "[" in key:
        parse_key_path(key, file, None)
        return "bearing", key
    raise ConfigError(file, f"{where}.{key}", None,
                      "unknown key: not an operating-point value ("
                      + ", ".join(OPERATING_POINT)
                      + "), solver.<setting>, profile.<key> or a bearing key path such as "
                        "friction.mu_static (write bearing.<key> for a top-level bearing key)")

def solver_kind(name: str):
    """Kind of a ``[solver]`` value, from the schema ("bool" for a switch, "category"
    for a choice such as ``method``)."""
    return fields.solver_fields()[name].axis_kind


def solver_value(name: str, value, file, key: str):
    """One ``[solver]`` value as written, checked against the schema: an SI float, a
    bool, or one of a choice's strings (``method = "imex"``)."""
    f = fields.solver_fields()[name]
    if f.kind == "choice":
        return check_value(f, value, file, key)
    return quantity(value, f.axis_kind, file, key)


def _key_kind(target: str, key: str):
    """Kind of a bearing or profile value by its key path, from the schema (None if the
    schema has no kind for it); labels a plain-number axis in the combined file."""
    f = fields.field(target, key)
    return f.axis_kind if f is not None else None


def _kind_of_quantity(text: str):
    """Kind of a unit string by its dimensionality; None if it is not a quantity."""
    from .units import is_temperature_text

    ureg = registry()
    if is_temperature_text(text):   # "40 degC": pint will not multiply a number by an offset unit
        return "temperature"
    if not is_safe_text(text):   # "9**9**9 N" would not come back; the loader says why
        return None
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


def _override_coord(value, target: str, key: str, file, where: str):
    """(coordinate, kind) of a bearing/profile override value."""
    if isinstance(value, bool):
        return value, "bool"
    if isinstance(value, (int, float)):
        return float(value), _key_kind(target, key)
    if isinstance(value, str):
        if _key_kind(target, key) == "category":   # a choice ("5" is a tolerance class, not a number)
            return value, "category"
        kind = _kind_of_quantity(value)
        if kind is None:
            return value, "category"
        return parse_quantity(value, kind, file=file, key=where), kind
    raise ConfigError(file, where, value, "an axis value must be a number, a string or a boolean")


def quantity(value, kind: str, file, key: str):
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
    si = {k: quantity(spec[k], kind, file, f"{key}.{k}") for k in _RANGE_KEYS}
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


def parse_axis(key: str, spec, file) -> Axis:
    where = f"axes.{key}"
    target, inner = target_of(key, file, "axes")
    if isinstance(spec, dict):
        kind = (OPERATING_POINT.get(inner) if target == "operating_point"
                else solver_kind(inner) if target == "solver" else None)
        if target in ("bearing", "profile") and kind is None:
            v = spec.get("start")
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                kind = _key_kind(target, inner) or "dimensionless"
        values, coords, kind = _range(spec, kind, file, where)
        return Axis(key, target, values, coords, kind)
    items = spec if isinstance(spec, list) else [spec]
    if not items:
        raise ConfigError(file, where, [], "empty axis: give at least one value")
    if target == "operating_point":
        kind = OPERATING_POINT[inner]
        values = tuple(quantity(v, kind, file, f"{where}[{i}]") for i, v in enumerate(items))
        coords = values
    elif target == "solver":
        kind = solver_kind(inner)
        values = tuple(solver_value(inner, v, file, f"{where}[{i}]") for i, v in enumerate(items))
        coords = values
    else:
        pairs = [_override_coord(v, target, inner, file, f"{where}[{i}]") for i, v in enumerate(items)]
        kinds = {k for _, k in pairs}
        if len(kinds) > 1:
            raise ConfigError(file, where, short(items),
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


def check_operating_point(values: dict, file, where: dict):
    for k in REQUIRED_OPERATING_POINT:
        if k not in values:
            raise ConfigError(file, k, None,
                              "missing: give it in [axes] (several values) or [fixed] (one value)"
                              + (" or in every [[cases]] entry" if where.get("_cases") else ""))
    for k, f in fields.field_map("operating_point").items():
        if k in values and f.bounds == "nonnegative" and values[k] < 0:
            raise ConfigError(file, where.get(k, k), values[k], f.why or "must not be negative")


def check_settings(settings: SolverSettings, file, where):
    """The solver settings within the schema's bounds, and the window in order.

    ``where`` names the table (``"solver"``: keys ``solver.<name>``), or maps a setting's
    name to the key its value was written under (a case's axis or ``[fixed]`` entry);
    settings it does not name are ``solver.<name>``."""
    def key(k):
        return where.get(k, f"solver.{k}") if isinstance(where, dict) else f"{where}.{k}"

    for k, f in fields.solver_fields().items():
        x = getattr(settings, k)
        if f.bounds == "positive" and not x > 0:
            raise ConfigError(file, key(k), x, "must be positive")
        if f.bounds == "nonnegative" and x < 0:
            raise ConfigError(file, key(k), x, "must not be negative")
        if f.bounds == "fraction" and not 0 < x <= 1:
            raise ConfigError(file, key(k), x, f.why or "must lie in (0, 1]")
        if f.kind == "choice":
            check_value(f, x, file, key(k))
        if f.kind == "integer" and not (isinstance(x, bool) or (f.minimum is not None and x < f.minimum)
                                        or (f.maximum is not None and x > f.maximum)) and x != int(x):
            raise ConfigError(file, key(k), x, "must be a whole number")
        if f.kind == "integer" and f.minimum is not None and x < f.minimum:
            raise ConfigError(file, key(k), x, f"must be at least {f.minimum}")
        if f.kind == "integer" and f.maximum is not None and x > f.maximum:
            raise ConfigError(file, key(k), x, f"must be at most {f.maximum}" + (f" ({f.why})" if f.why else ""))
    if settings.end_time and settings.end_time <= settings.start_time:
        raise ConfigError(file, key("end_time"), settings.end_time,
                          "must come after start_time (or be 0: the profile's duration)")

def sort_key(c):
    return (0, c, "") if isinstance(c, (int, float)) else (1, 0, str(c))


def coord_kind(setting: Setting):
    """The kind of a setting's coordinate (as :attr:`Axis.kind`)."""
    if setting.target == "operating_point":
        return OPERATING_POINT[setting.inner]
    if setting.target == "solver":
        return solver_kind(setting.inner)
    if isinstance(setting.coord, bool):
        return "bool"
    if isinstance(setting.coord, str):
        return "category"
    if isinstance(setting.value, str):
        return _kind_of_quantity(setting.value)
    return _key_kind(setting.target, setting.inner)


class Setting(NamedTuple):
    """One value a case receives: where it goes, and where the sweep file wrote it.

    Parameters
    ----------
    target : str
        ``"operating_point"``, ``"solver"``, ``"bearing"`` or ``"profile"``.
    inner : str
        The key inside the target: a field name or a key path.
    value : object
        What the target receives: an SI float for operating-point and solver values; for
        bearing and profile values the value handed to ``apply_override``.
    coord : float, bool or str
        Its coordinate in the combined file.
    where : str
        The key as written, for error messages (``"axes.speed[2]"``, ``"fixed.axial_load"``).
    """

    target: str
    inner: str
    value: object
    coord: object
    where: str


def fixed_value(key: str, v, file, prefix: str) -> Setting:
    """The :class:`Setting` of one value of ``[fixed]`` or of a ``[[cases]]`` entry
    (``prefix`` names the table for error messages)."""
    where = f"{prefix}.{key}"
    target, inner = target_of(key, file, prefix)
    if target == "operating_point":
        x = quantity(v, OPERATING_POINT[inner], file, where)
        return Setting(target, inner, x, x, where)
    if target == "solver":
        x = solver_value(inner, v, file, where)
        return Setting(target, inner, x, x, where)
    if isinstance(v, list):
        return Setting(target, inner, v, str(v), where)
    coord, _ = _override_coord(v, target, inner, file, where)
    return Setting(target, inner, v, coord, where)
