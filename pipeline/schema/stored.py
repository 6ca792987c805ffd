"""The resolved configuration a sweep stores, read back into the core's dataclasses.

:func:`pipeline.schema.read_sweep_file` writes the sweep's resolved configuration as the TOML
global attribute ``configuration`` of ``sweep.nc`` (and of every case file): the plain
form (:func:`pipeline.schema.sweepfile.plain`) of :class:`rvcore.bearing.geometry.Bearing`,
:class:`rvcore.profile.Profile`, :class:`rvcore.simulation.run.SolverSettings` and
:class:`rvcore.simulation.settings.Sensor`, plus ``name``, ``axes``, ``fixed``, ``case_ids``,
``model_version`` and, with draws, ``statistics`` (the ``[statistics]`` table, resolved). :func:`stored_configuration` rebuilds those dataclasses field by field:
nothing is guessed, and a text this version did not write is a
:class:`pipeline.errors.ConfigError` naming the key and the reason.
"""
from __future__ import annotations

import dataclasses
import tomllib
import types
import typing
from dataclasses import dataclass

from rvcore.simulation.settings import Sensor, SolverSettings
from rvcore.bearing.geometry import Bearing
from rvcore.profile import Profile

from ..errors import ConfigError
from . import fields
from .reader import check_value
from .sweepfile import MODEL_VERSION

#: Where the configuration comes from, in error messages.
WHERE = "configuration"

#: Keys of the stored configuration besides the dataclasses (read or ignored on purpose).
_BOOKKEEPING = ("description", "sweep_file", "bearing_file", "profile_file", "case_ids")


@dataclass(frozen=True)
class StoredConfiguration:
    """A sweep's resolved configuration (SI), as stored in ``sweep.nc``.

    Parameters
    ----------
    name : str
        The sweep's name.
    model_version : int
        :data:`pipeline.schema.MODEL_VERSION` of the version that wrote it.
    bearing : rvcore.bearing.geometry.Bearing
    profile : rvcore.profile.Profile
    settings : rvcore.simulation.run.SolverSettings
    sensors : tuple of rvcore.simulation.settings.Sensor
    axes : dict
        Axis key -> list of coordinate values (SI).
    fixed : dict
        Fixed key -> coordinate value (SI).
    statistics : dict or None
        The resolved ``[statistics]`` table (:class:`pipeline.schema.statistics.StatisticsSpec`
        as a table), None without draws.
    """

    name: str
    model_version: int
    bearing: Bearing
    profile: Profile
    settings: SolverSettings
    sensors: tuple
    axes: dict
    fixed: dict
    statistics: dict | None = None


def _tuple(value):
    """Lists (nested) as tuples, the plain form's inverse for tuple fields."""
    if isinstance(value, list):
        return tuple(_tuple(v) for v in value)
    return value


#: Type hint -> (accepts the stored value, converts it, the reason when it does not).
_SCALARS = {
    bool: (lambda v: isinstance(v, bool), bool, "must be true or false"),
    int: (lambda v: isinstance(v, int) and not isinstance(v, bool), int, "must be an integer"),
    float: (lambda v: isinstance(v, (int, float)) and not isinstance(v, bool), float, "must be a number"),
    str: (lambda v: isinstance(v, str), str, "must be a string"),
    tuple: (lambda v: isinstance(v, list), lambda v: _tuple(v), "must be an array"),
    dict: (lambda v: isinstance(v, dict), dict, "must be a table"),
}


def _scalar(value, hint, key: str):
    if hint not in _SCALARS:
        return value
    accepts, convert, reason = _SCALARS[hint]
    if not accepts(value):
        raise ConfigError(WHERE, key, value, reason)
    return convert(value)


def _optional(hint):
    """``X`` of a hint ``X | None`` (a dataclass field that may be absent); others as they are."""
    args = typing.get_args(hint)
    if len(args) == 2 and type(None) in args and typing.get_origin(hint) in (typing.Union, types.UnionType):
        return next(a for a in args if a is not type(None))
    return hint


def rebuild(cls, data, key: str):
    """An instance of dataclass ``cls`` from its plain form ``data`` (``key`` names it): the one
    read-back converter, the inverse of :func:`pipeline.schema.caseids.plain` for every
    dataclass (a ``tuple[Row, ...]`` annotation names a tuple's items, :func:`fields.item_class`)."""
    if not isinstance(data, dict):
        raise ConfigError(WHERE, key, None, f"must be a table ({cls.__name__})")
    members = {f.name: f for f in dataclasses.fields(cls)}
    for k in data:
        if k not in members:
            raise ConfigError(WHERE, f"{key}.{k}", None, f"unknown field of {cls.__name__}")
    hints = typing.get_type_hints(cls)
    kwargs = {}
    for name, f in members.items():
        where = f"{key}.{name}"
        if name not in data:
            if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
                raise ConfigError(WHERE, where, None, f"missing (a required field of {cls.__name__})")
            continue
        value, hint = data[name], _optional(hints[name])
        element = fields.item_class(hint)
        if element is not None:
            if not isinstance(value, list):
                raise ConfigError(WHERE, where, None, f"must be an array of {element.__name__} tables")
            kwargs[name] = tuple(rebuild(element, v, f"{where}[{i}]") for i, v in enumerate(value))
        elif fields.dataclass_of(hint) is not None:   # a dataclass, or one or None (None is not stored)
            kwargs[name] = rebuild(fields.dataclass_of(hint), value, where)
        else:
            kwargs[name] = _scalar(value, hint, where)
    try:
        return cls(**kwargs)
    except (TypeError, ValueError) as exc:
        raise ConfigError(WHERE, key, None, f"not a valid {cls.__name__} ({exc})") from None


def _table(doc: dict, key: str) -> dict:
    if key not in doc:
        raise ConfigError(WHERE, key, None, "missing")
    if not isinstance(doc[key], dict):
        raise ConfigError(WHERE, key, None, "must be a table")
    return doc[key]


def stored_configuration(text: str) -> StoredConfiguration:
    """The sweep configuration ``text`` (TOML, as ``sweep.nc`` stores it) as dataclasses.

    Raises
    ------
    pipeline.errors.ConfigError
        Naming the key and the reason when ``text`` is not a configuration this version
        of the pipeline wrote (not TOML, another model version, a missing or unknown field,
        a value of the wrong type).
    """
    if not text:
        raise ConfigError(WHERE, None, None, "empty: the sweep carries no configuration")
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(WHERE, None, None, f"not valid TOML ({exc})") from None
    version = doc.get("model_version")
    if version != MODEL_VERSION:
        raise ConfigError(WHERE, "model_version", version,
                          f"written by another model version (this one is {MODEL_VERSION})")
    known = {"model_version", "name", "axes", "fixed", "solver", "bearing", "profile", "sensors", "statistics",
             *_BOOKKEEPING}
    for k in doc:
        if k not in known:
            raise ConfigError(WHERE, k, None, "unknown key")
    name = doc.get("name")
    if not isinstance(name, str):
        raise ConfigError(WHERE, "name", name, "must be a string")
    solver = _table(doc, "solver")
    settings = rebuild(SolverSettings, solver, "solver")
    for k, f in fields.solver_fields().items():
        if f.kind == "choice":
            check_value(f, getattr(settings, k), WHERE, f"solver.{k}")
    sensors = doc.get("sensors", [])
    if not isinstance(sensors, list):
        raise ConfigError(WHERE, "sensors", None, "must be an array of tables")
    return StoredConfiguration(
        name=name, model_version=version,
        bearing=rebuild(Bearing, _table(doc, "bearing"), "bearing"),
        profile=rebuild(Profile, _table(doc, "profile"), "profile"),
        settings=settings,
        sensors=tuple(rebuild(Sensor, s, f"sensors[{i}]") for i, s in enumerate(sensors)),
        axes=dict(_table(doc, "axes")), fixed=dict(_table(doc, "fixed")),
        statistics=dict(_table(doc, "statistics")) if "statistics" in doc else None)
