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
    "solver.method" = ["rk4", "imex"]               # a choice: a categorical axis

    [fixed]                                 # one value each, for every case
    axial_load = "10 kN"
    "contact.damping" = "300 N s/m"

    [solver]                                # fields of rvcore.simulation.run.SolverSettings
    output_rate = "1000 Hz"
    method = "rk4"                          # the integrator: "rk4" or "imex"
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
- ``solver.<field>``: a :class:`rvcore.simulation.run.SolverSettings` field;
- ``profile.<key path>``: a value of the profile file;
- ``bearing.<key path>``, or the key path alone when it has a ``.`` or ``[i]``
  (``friction.mu_static``, ``rows[0].cage.pocket_clearance``): a value of the bearing
  file, applied with :func:`pipeline.schema.tomlfile.apply_override` and validated by
  :func:`pipeline.schema.bearingfile.bearing_from_dict` like the file itself.

Quantities are unit strings ("120 deg/s", "20 kN") read by
:func:`pipeline.schema.units.parse_quantity`, or plain numbers taken as SI. Written unquoted,
``friction.mu_static = [...]`` is a TOML dotted key and means the same.

Every problem (unknown key, bad unit, empty axis, missing bearing or profile file, a
bearing value out of range in some case) is a :class:`pipeline.errors.ConfigError`
raised by :func:`read_sweep_file`, before any case runs.

Case ids
--------
A case's id is the first 16 hex digits of the SHA-256 of the canonical JSON (sorted
keys, no spaces, ``repr`` floats) of everything that determines its result: the
resolved bearing, profile, solver settings and operating point, all in SI, and
:data:`MODEL_VERSION`. The same values written in other units give the same id; a
changed value gives new ids to exactly the cases it changes. A few values are hashed
every time, defaults included (MODEL_VERSION 13 retired the exceptions that had kept
older ids: a configuration of another model version is refused anyway).
"""
from __future__ import annotations

import dataclasses
import functools
import itertools
import math
from dataclasses import dataclass, field
from pathlib import Path

import tomli_w

from rvcore.simulation.settings import SolverSettings
from rvcore.bearing.geometry import Bearing
from rvcore.profile import OperatingPoint, Profile

from rvcore import MODEL_VERSION

from ..errors import ConfigError
from . import fields
from .caseids import IdentityMemo, canonical_json, hash_id, hash_plain, plain
from .reader import short
from .physical import refuse_beyond_bounds
from .resolver import Resolver, read_named_file
from .sweepaxes import (MAX_CASES, NAME, OPERATING_POINT, REALIZATION, REQUIRED_OPERATING_POINT, Axis,
                        Setting, check_operating_point, check_settings, coord_kind, fixed_value,
                        flatten, parse_axis, parse_sensors, realization_axis, solver_value,
                        sort_key, target_of)
from .statistics import DRAW, SAMPLE, Draws, apply_draw, parse_statistics, sample_names
from .tomlfile import read_toml
from .units import unit_warnings_on_success

__all__ = ["MODEL_VERSION", "OPERATING_POINT", "REQUIRED_OPERATING_POINT", "REALIZATION", "TOP_KEYS",
           "Axis", "CaseSpec", "Setting",
           "Sweep", "case_configuration", "plain", "canonical_json", "hash_id", "read_sweep_file",
           "sweep_from_dict"]


TOP_KEYS = ("name", "description", "bearing", "profile", "axes", "fixed", "solver", "cases",
            "realizations", "seed", "sensors", "statistics")

def _plain_without(obj, drop=()) -> dict:
    """A dataclass's plain form (:func:`plain`) with the top-level attributes ``drop`` left out."""
    return {k: v for k, v in plain(obj).items() if k not in drop}


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
    bearing : rvcore.bearing.geometry.Bearing
    profile : rvcore.profile.Profile
    operating_point : rvcore.profile.OperatingPoint
        [rad s^-1, N, N, N m, rad]
    settings : rvcore.simulation.run.SolverSettings
    resolved : dict
        The resolved case as plain SI data (:func:`case_configuration`), the hashed form.
        Cases of one sweep share its bearing and profile parts: never modified.
    sensors : tuple of rvcore.simulation.settings.Sensor
        The sweep's virtual sensors.

    Attributes
    ----------
    configuration : str
        ``resolved`` as TOML, stored in the case file; written on first use (by the
        worker that runs the case), not when the sweep is expanded.
    """

    case_id: str
    point: dict
    bearing: Bearing
    profile: Profile
    operating_point: OperatingPoint
    settings: SolverSettings
    resolved: dict = field(repr=False)
    sensors: tuple = ()

    @functools.cached_property
    def configuration(self) -> str:
        return tomli_w.dumps(self.resolved)


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
    statistics: object = None

    def axis(self, key: str) -> Axis | None:
        for a in self.axes:
            if a.key == key:
                return a
        return None


def case_configuration(bearing: Bearing, profile: Profile, op: OperatingPoint,
                       settings: SolverSettings, sensors=(), memo: IdentityMemo | None = None) -> dict:
    """Everything that determines a case's result, as plain SI data (hashed for the id).

    The solver settings carry the seed of the random start, so each realization of an
    ensemble has its own id, and the integrator. With ``memo``, the bearing's and the
    profile's plain forms are computed once per object and shared by the cases that
    hold the same object.
    """
    # free text that changes no result is left out (the field table's ``hashed``)
    if memo is None:
        memo = IdentityMemo()
    b = memo.get(bearing, "hashed", lambda o: _plain_without(o, fields.unhashed("bearing")))
    p = memo.get(profile, "hashed", lambda o: _plain_without(o, fields.unhashed("profile")))
    conf = {"model_version": MODEL_VERSION, "operating_point": plain(op),
            "solver": plain(settings), "bearing": b, "profile": p}
    if sensors:
        conf["sensors"] = plain(list(sensors))
    return conf

# --------------------------------------------------------------------------- loading


@unit_warnings_on_success
def read_sweep_file(path) -> Sweep:
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
    raw = read_toml(file)
    return sweep_from_dict(raw, file)


#: A sweep file names a bearing and a profile; these keys say a file is one of those instead
#: (the markers ``rvsweep check`` tells the kinds of file apart by).
_OTHER_KINDS = {"bearing": ("rows", "envelope"), "profile": ("duration", "phases")}


def _refuse_other_kinds(raw: dict, file) -> None:
    """A bearing or profile file given where a sweep file belongs: say which it is, not
    "unknown key" about its first key."""
    if any(k in raw for k in ("bearing", "profile")):
        return
    for kind, markers in _OTHER_KINDS.items():
        if any(k in raw for k in markers):
            raise ConfigError(file, None, None,
                              f"this is a {kind} file, not a sweep file; a sweep file names a bearing "
                              f"and a profile and gives the grid, e.g. bearing = \"bearings/rv-main-study.toml\", "
                              f"profile = \"profiles/study.toml\" and [axes] (see sweeps/smoke.toml)")


@unit_warnings_on_success
def sweep_from_dict(raw: dict, file) -> Sweep:
    """:func:`read_sweep_file` on already-read TOML (``file`` names it and anchors paths)."""
    file = Path(file)
    _refuse_other_kinds(raw, file)
    _check_top_keys(raw, file)
    name, description = _name_and_description(raw, file)
    bearing_file, bearing_raw = read_named_file(file, raw, "bearing")
    profile_file, profile_raw = read_named_file(file, raw, "profile")
    resolver = Resolver(file, bearing_file, bearing_raw, profile_file, profile_raw)
    solver_values = _solver_values(raw, file)
    fixed = _fixed_settings(raw, file)
    if ("axes" in raw) == ("cases" in raw):
        if "axes" in raw:
            raise ConfigError(file, "cases", None, "give either [axes] (a grid) or [[cases]] (a list), not both")
        raise ConfigError(file, "axes", None, "missing: give [axes] (a grid) or [[cases]] (a list of cases)")
    explicit = "cases" in raw
    axes, points = _listed_points(raw, file, fixed) if explicit else _grid_points(raw, file, fixed)
    draws = _draws(raw, file, fixed, points, resolver)
    if draws is not None:
        axes, points = _with_draws(axes, points, draws, file)

    sensors = parse_sensors(raw.get("sensors"), file)
    base_settings = SolverSettings(**solver_values)
    check_settings(base_settings, file, "solver")
    base_bearing = resolver.bearing(_overrides(fixed.values(), "bearing"))
    base_profile = resolver.profile(_overrides(fixed.values(), "profile"))

    cases, ids, memo = [], {}, IdentityMemo()
    for n, point in enumerate(points):
        case = _resolve_case(point, fixed, explicit, base_settings, resolver, sensors, file, raw, draws, memo)
        if case.case_id in ids:
            raise ConfigError(file, "cases" if explicit else "axes", None,
                              f"case {n} is the same as case {ids[case.case_id]} (same resolved values)")
        ids[case.case_id] = n
        cases.append(case)

    fixed_coords = {k: setting.coord for k, setting in fixed.items()}
    sweep_conf = {
        "model_version": MODEL_VERSION,
        "name": name,
        "description": description,
        "sweep_file": str(file),
        "bearing_file": str(bearing_file),
        "profile_file": str(profile_file),
        "axes": {a.key: list(a.coords) for a in axes},
        "fixed": fixed_coords,
        "solver": plain(base_settings),
        "case_ids": [c.case_id for c in cases],
        "bearing": plain(base_bearing),
        "profile": plain(base_profile),
        "sensors": plain(list(sensors)),
    }
    if draws is not None:
        sweep_conf["statistics"] = plain(draws.spec)
    return Sweep(name=name, file=file, description=description, bearing_file=bearing_file,
                 profile_file=profile_file, axes=axes, fixed=fixed_coords,
                 settings=base_settings, bearing=base_bearing, profile=base_profile,
                 cases=tuple(cases), explicit=explicit,
                 configuration=tomli_w.dumps(plain(sweep_conf)),
                 configuration_hash=hash_id(sweep_conf), sensors=sensors,
                 realizations=int(raw.get("realizations", 1)),
                 statistics=draws.spec if draws is not None else None)


def _draws(raw: dict, file: Path, fixed: dict, points: list, resolver: Resolver):
    """The sweep's :class:`~pipeline.schema.statistics.Draws` (None without ``[statistics]``),
    its inputs checked against the first grid point's bearing."""
    if raw.get("statistics") is None:
        return None
    first = list({**fixed, **points[0]}.values())
    bearing = resolver.bearing(_overrides(first, "bearing"))
    spec = parse_statistics(raw["statistics"], file, bearing)
    return Draws.of(spec, bearing)


def _with_draws(axes: tuple, points: list, draws, file: Path) -> tuple:
    """The axes and points with the ``draw`` axis (and ``sample`` with ``sensitivity``) last."""
    for a in axes:
        if a.key in (DRAW, SAMPLE):
            raise ConfigError(file, f"axes.{a.key}", None, "is the [statistics] table's own axis; "
                                                          "set the draws there")
    n = draws.spec.draws
    extra = [Axis(DRAW, "statistics", tuple(float(k) for k in range(n)), tuple(float(k) for k in range(n)),
                  "dimensionless")]
    if draws.spec.sensitivity:
        names = sample_names(draws.spec)
        extra.append(Axis(SAMPLE, "statistics", names, names, "category"))
    size = len(points) * math.prod(len(a) for a in extra)
    if size > MAX_CASES:
        raise ConfigError(file, "statistics.draws", n, f"{size} cases with the grid: more than the {MAX_CASES} "
                                                       "a sweep holds")
    out = [{**p, **{a.key: Setting("statistics", a.key, a.values[i], a.coords[i], f"statistics.{a.key}[{i}]")
                    for a, i in zip(extra, combo)}}
           for p in points for combo in itertools.product(*(range(len(a)) for a in extra))]
    return axes + tuple(extra), out


def _check_top_keys(raw: dict, file: Path) -> None:
    """Refuse an unknown top-level key, saying where an operating-point or solver key goes."""
    for k, v in raw.items():
        if k not in TOP_KEYS:
            hint = ""
            if k in OPERATING_POINT:
                hint = "; put it in [axes] (several values) or [fixed] (one value)"
            elif k in fields.solver_fields():
                hint = "; put it in [solver]"
            raise ConfigError(file, k, short(v), f"unknown key (allowed: {', '.join(TOP_KEYS)}){hint}")


def _name_and_description(raw: dict, file: Path) -> tuple:
    """The sweep's name (a folder name; the file's stem by default) and description."""
    name = raw.get("name", file.stem)
    if not isinstance(name, str) or not NAME.match(name):
        raise ConfigError(file, "name", name,
                          "must be a folder name: letters, digits, '.', '_' and '-', "
                          "starting with a letter or digit")
    description = raw.get("description", "")
    if not isinstance(description, str):
        raise ConfigError(file, "description", None, "must be a string")
    return name, description


def _solver_values(raw: dict, file: Path) -> dict:
    """``[solver]`` as SolverSettings keyword arguments (SI)."""
    solver_raw = raw.get("solver", {})
    if not isinstance(solver_raw, dict):
        raise ConfigError(file, "solver", None, "must be a table ([solver])")
    known = fields.solver_fields()
    values = {}
    for k, v in solver_raw.items():
        if k not in known:
            raise ConfigError(file, f"solver.{k}", short(v),
                              f"unknown solver setting (known: {', '.join(sorted(known))})")
        values[k] = solver_value(k, v, file, f"solver.{k}")
    return values


def _fixed_settings(raw: dict, file: Path) -> dict:
    """``[fixed]``: key -> :class:`Setting`."""
    fixed_raw = raw.get("fixed", {})
    if not isinstance(fixed_raw, dict):
        raise ConfigError(file, "fixed", None, "must be a table ([fixed])")
    return {key: fixed_value(key, v, file, "fixed")
            for key, v in flatten(fixed_raw, "", file, "fixed", ranges=False).items()}


def _grid_points(raw: dict, file: Path, fixed: dict) -> tuple:
    """``[axes]`` (and ``realizations``): the axes, and every grid point as
    ``{key: Setting}``, the first axis varying slowest."""
    axes_raw = raw["axes"]
    if not isinstance(axes_raw, dict):
        raise ConfigError(file, "axes", None, "must be a table ([axes])")
    flat = flatten(axes_raw, "", file, "axes", ranges=True)
    if not flat:
        raise ConfigError(file, "axes", None, "empty: give at least one axis")
    axes = tuple(parse_axis(k, v, file) for k, v in flat.items())
    ensemble = realization_axis(raw, file)
    if ensemble is not None:
        if any(a.key == REALIZATION for a in axes):
            raise ConfigError(file, "realizations", raw.get("realizations"), "the realization axis is also in [axes]")
        axes = axes + (ensemble,)
    for a in axes:
        if a.key in fixed:
            raise ConfigError(file, f"fixed.{a.key}", None, "is also an axis in [axes]")
    size = math.prod(len(a) for a in axes)
    if size > MAX_CASES:   # said before the grid is built, which alone would take minutes
        raise ConfigError(file, "axes", None,
                          f"{' x '.join(str(len(a)) for a in axes)} = {size} cases: more than the "
                          f"{MAX_CASES} a sweep holds; split it into several sweeps")
    inner = {a.key: target_of(a.key, file, "axes")[1] for a in axes}
    points = [{a.key: Setting(a.target, inner[a.key], a.values[i], a.coords[i], f"axes.{a.key}[{i}]")
               for a, i in zip(axes, combo)}
              for combo in itertools.product(*(range(len(a)) for a in axes))]
    return axes, points


def _listed_points(raw: dict, file: Path, fixed: dict) -> tuple:
    """``[[cases]]``: the axes (each key the cases set, with its distinct values) and each
    case as ``{key: Setting}``, in the order of the list."""
    cases_raw = raw["cases"]
    if realization_axis(raw, file) is not None:
        raise ConfigError(file, "realizations", raw.get("realizations"),
                          "ensembles need a grid: give [axes] rather than [[cases]]")
    if not isinstance(cases_raw, list) or not all(isinstance(c, dict) for c in cases_raw):
        raise ConfigError(file, "cases", None, "must be an array of tables ([[cases]] sections)")
    if not cases_raw:
        raise ConfigError(file, "cases", [], "empty: give at least one case")
    points = []
    for i, c in enumerate(cases_raw):
        where = f"cases[{i}]"
        flat = flatten(c, "", file, where, ranges=False)
        if not flat:
            raise ConfigError(file, where, None, "empty case")
        point = {}
        for key, v in flat.items():
            if key in fixed:
                raise ConfigError(file, f"{where}.{key}", v, "is also given in [fixed]")
            point[key] = fixed_value(key, v, file, where)
        points.append(point)
    keys = list(dict.fromkeys(k for point in points for k in point))
    for i, point in enumerate(points):
        for k in keys:
            if k not in point:
                raise ConfigError(file, f"cases[{i}]", None,
                                  f"does not set '{k}', which other cases set; give it in "
                                  "every case (or in [fixed] and in no case)")
    axes = []
    for k in keys:
        coords = tuple(sorted({point[k].coord for point in points}, key=sort_key))
        kinds = {coord_kind(point[k]) for point in points}
        axes.append(Axis(k, points[0][k].target, coords, coords, kinds.pop()))
    return tuple(axes), points


def _overrides(settings, target: str) -> tuple:
    """``(inner key, value, where)`` of the settings for ``target``, as the resolver takes them."""
    return tuple((s.inner, s.value, s.where) for s in settings if s.target == target)


def _resolve_case(point: dict, fixed: dict, explicit: bool, base_settings: SolverSettings,
                  resolver: Resolver, sensors: tuple, file: Path, raw: dict | None = None,
                  draws=None, memo: IdentityMemo | None = None) -> CaseSpec:
    """One case: ``[fixed]`` with the point's settings over it, resolved and hashed
    (``memo``: the sweep's, see :func:`case_configuration`)."""
    merged = {**fixed, **point}
    settings_of = list(merged.values())
    op_values = {s.inner: s.value for s in settings_of if s.target == "operating_point"}
    op_where = {s.inner: s.where for s in settings_of if s.target == "operating_point"}
    op_where["_cases"] = explicit
    check_operating_point(op_values, file, op_where)
    op = OperatingPoint(**op_values)
    solver_over = {s.inner: s.value for s in settings_of if s.target == "solver"}
    settings = dataclasses.replace(base_settings, **solver_over)
    settings = dataclasses.replace(settings, seed=int(settings.seed))
    if solver_over:
        check_settings(settings, file, {s.inner: s.where for s in settings_of if s.target == "solver"})
    bearing = resolver.bearing(_overrides(settings_of, "bearing"))
    stats = {s.inner: s for s in settings_of if s.target == "statistics"}
    if draws is not None and DRAW in stats:
        sample = stats[SAMPLE].value if SAMPLE in stats else "A"
        bearing = apply_draw(bearing, draws, int(stats[DRAW].value), sample, file, stats[DRAW].where)
    profile = resolver.profile(_overrides(settings_of, "profile"))
    refuse_beyond_bounds(bearing, profile, op, settings, sensors, file, settings_of, raw, memo)
    conf = case_configuration(bearing, profile, op, settings, sensors, memo)
    coords = {k: merged[k].coord for k in REQUIRED_OPERATING_POINT}
    coords.update({k: s.coord for k, s in point.items()})
    return CaseSpec(case_id=hash_plain(conf), point=coords, bearing=bearing, profile=profile,
                    operating_point=op, settings=settings, resolved=conf, sensors=sensors)
