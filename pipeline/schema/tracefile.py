"""The trace file: a measured rig test described in TOML (``rvsweep compare``).

A trace file names the data file and its format, each channel (name in the file, unit,
which displacement of the inner ring it measures, the sensor's position, its sign), the
time base (a time channel or a sample rate), the duty cycle the rig ran (a profile file)
and the bearing. The duty cycle is either a profile file (``profile``) or channels of the
data (``[trace.duty]``: the speed and the radial and axial loads the rig recorded), turned
into a breakpoint profile by :func:`pipeline.analysis.duty.profile_from_channels`. A load
the rig held without logging it (a dead weight, an unlogged preload, none) is a constant
with its unit instead of a channel: a table is always a channel of the data, a string
always a constant, so a channel's name is never read as a quantity. The speed must be a
channel: the phases are found from it. Every bad value is one
:class:`pipeline.errors.ConfigError` naming the file, the key, the value as typed and the
reason, raised before any data is read. The layout is in docs/outputs.md ("Measured traces").

Example::

    [trace]
    name = "rig-660"
    file = "example.csv"            # relative to this file
    format = "csv"                  # csv | tdms | hdf5 | mat
    time = { channel = "time", unit = "s" }     # or { rate = "2 kHz" }
    profile = "../profiles/study.toml"          # optional: the phase windows, the cycle's length
    bearing = "../bearings/study.toml"          # optional: the kinematic lines
    speed = "660 deg/s"                         # the operating point, for the kinematic lines
    radial_load = "30 kN"

    # instead of profile: the duty cycle from channels of the data
    # [trace.duty]
    # speed = { channel = "n", unit = "rpm" }
    # radial_load = { channel = "Fr", unit = "kN" }
    # axial_load = { channel = "Fa", unit = "kN" }   # or a constant held over the record: "10 kN", "0 kN"
    # tolerance = 0.02                          # of each channel's steady value

    [[trace.channel]]
    name = "laser_r"
    unit = "um"
    measures = "radial_displacement"           # or axial_displacement
    position = "outer ring, 0 deg, on the load line"
    sign = 1
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import ConfigError
from .tomlfile import read_toml, resolve_path
from .fields import field as schema_field
from .reader import check_value
from .units import SI_UNITS, numbers_in_si, parse_quantity, registry

#: Formats a trace's data file may have; MAT files of version 7.3 are HDF5 (read by h5py),
#: earlier ones by scipy.io.loadmat.
FORMATS = ("csv", "tdms", "hdf5", "mat")
#: The simulated series a channel may measure.
MEASURES = ("radial_displacement", "axial_displacement")

_TOP_KEYS = {"name", "description", "file", "format", "time", "profile", "bearing", "speed", "radial_load",
             "axial_load", "channel", "low_pass", "duty"}
#: The duty-cycle channels of ``[trace.duty]`` and the kind of unit each must be in.
DUTY_KINDS = {"speed": "angular_speed", "radial_load": "force", "axial_load": "force"}
_DUTY_KEYS = set(DUTY_KINDS) | {"tolerance"}
_DUTY_CHANNEL_KEYS = {"channel", "unit", "group"}
#: A constant's text starts with its number (a sign, a digit or a decimal point): ``"Fa"`` is
#: refused as a channel's name written where a constant goes, never read as a unit.
_NUMBER_FIRST = re.compile(r"\s*[-+]?(\d|\.\d)")
#: Unit names pint gives an angle (an angular speed must name one: 'Hz' or '1/s' would
#: leave revolutions and radians apart by 2π).
_ANGLES = {"radian", "degree", "revolution", "turn", "arcminute", "arcsecond", "revolutions_per_minute",
           "revolutions_per_second", "gradian", "cycle"}
#: Default tolerance of the breakpoint fit and of the phase edges, a fraction of each channel's steady value.
DUTY_TOLERANCE = 0.02
_CHANNEL_KEYS = {"name", "unit", "measures", "position", "sign", "group"}
_TIME_KEYS = {"channel", "unit", "rate", "group"}


@dataclass(frozen=True)
class TraceChannel:
    """One measured channel.

    Parameters
    ----------
    name : str
        Its name in the data file (CSV column, TDMS channel, HDF5 dataset path, MAT variable).
    scale : float
        Metres per unit of the file's numbers [m/unit], from ``unit``.
    unit : str
        The unit as typed [-].
    measures : str
        One of :data:`MEASURES`.
    sign : float
        +1 or −1: −1 where the sensor reads positive for a displacement towards −r or −z [-].
    position : str
        Where the sensor stands, as the rig engineer describes it [-].
    group : str
        The TDMS group holding the channel ('' for the first group) [-].
    """

    name: str
    scale: float
    unit: str
    measures: str
    sign: float = 1.0
    position: str = ""
    group: str = ""


@dataclass(frozen=True)
class DutyChannel:
    """One duty-cycle channel of the data (``[trace.duty]``).

    Parameters
    ----------
    name : str
        Its name in the data file [-].
    scale : float
        SI per unit of the file's numbers (rad s-1 or N per unit) [SI/unit].
    unit : str
        The unit as typed [-].
    group : str
        The TDMS group holding the channel ('' for the first group) [-].
    """

    name: str
    scale: float
    unit: str
    group: str = ""


@dataclass(frozen=True)
class DutyConstant:
    """One duty-cycle quantity the rig held over the whole record without logging it
    (``[trace.duty]``, e.g. ``axial_load = "10 kN"``).

    Parameters
    ----------
    value : float
        The constant, SI [N].
    text : str
        The value as typed [-].
    """

    value: float
    text: str


@dataclass(frozen=True)
class Trace:
    """A measured test, validated (:func:`load_trace`). Quantities SI."""

    source: str
    name: str
    file: Path
    format: str
    channels: tuple
    time_channel: str = ""
    time_scale: float = 1.0       # [s per unit of the time channel]
    time_group: str = ""
    rate: float = math.nan        # [Hz] when no time channel
    profile: Path | None = None
    bearing: Path | None = None
    speed: float = math.nan       # [rad s-1]
    radial_load: float = math.nan # [N]
    axial_load: float = math.nan  # [N]
    low_pass: float = math.nan    # [Hz], NaN: none
    description: str = ""
    duty: dict = field(default_factory=dict)   # "speed"/"radial_load"/"axial_load" -> DutyChannel or DutyConstant
    duty_tolerance: float = DUTY_TOLERANCE     # [1]
    extra: dict = field(default_factory=dict)


def _string(t: dict, key: str, file, where: str, required=True, default="") -> str:
    if key not in t:
        if required:
            raise ConfigError(file, where + key, None, "missing (required)")
        return default
    v = t[key]
    if not isinstance(v, str) or not v.strip():
        raise ConfigError(file, where + key, v, "expected a non-empty string")
    return v


def _unknown(t: dict, allowed: set, file, where: str) -> None:
    for k in t:
        if k not in allowed:
            raise ConfigError(file, where + k, t[k], f"unknown key (allowed: {', '.join(sorted(allowed))})")


_EXAMPLES = {"length": "'um' or 'mm'", "time": "'s' or 'ms'", "angular_speed": "'rpm' or 'deg/s'",
             "force": "'N' or 'kN'"}
_WHAT = {"length": "length", "time": "time", "angular_speed": "speed", "force": "force"}


def _scale(unit, kind: str, file, key: str) -> float:
    """Size of one ``unit`` in the SI unit of ``kind`` (``length``, ``time``, ``angular_speed``
    or ``force``; :data:`pipeline.schema.units.SI_UNITS`)."""
    what = _WHAT[kind]
    if not isinstance(unit, str) or not unit.strip():
        raise ConfigError(file, key, unit, f"expected a unit of {what}, e.g. {_EXAMPLES[kind]}")
    ureg = registry()
    try:
        q = ureg.Quantity(1.0, unit.strip())
    except Exception:
        raise ConfigError(file, key, unit, "not a unit") from None
    target = SI_UNITS[kind]
    if q.dimensionality != ureg.Quantity(1.0, target).dimensionality:
        raise ConfigError(file, key, unit, f"not a {what}: the channel must be in a unit convertible to {target}")
    if kind == "angular_speed":
        _names_an_angle(q, file, key, unit)
    return float(q.to(target).magnitude)


def _names_an_angle(q, file, key: str, typed) -> None:
    """Refuse an angular speed whose unit names no angle ('Hz', '1/s': revolutions and
    radians would be 2π apart)."""
    ureg = registry()
    if not any(ureg.get_name(u) in _ANGLES for u in q.units._units):
        raise ConfigError(file, key, typed, "not a speed: a frequency without an angle; write 'rpm', 'rev/s', "
                                            "'rad/s' or 'deg/s'")


def _duty_constant(v, name: str, kind: str, file, key: str) -> DutyConstant:
    """A constant of ``[trace.duty]`` as typed (a string: a number and its unit), checked as the
    operating point's key of the same name is (:mod:`pipeline.schema.fields`: unit kind, bounds)."""
    example = {"force": "'10 kN' or '0 kN'", "angular_speed": "'660 deg/s'"}[kind]
    channel = "a channel of the data is { channel = ..., unit = ... }"
    if isinstance(v, (bool, int, float)):
        raise ConfigError(file, key, v, f"a constant takes its unit, e.g. {example} ({channel})")
    if not isinstance(v, str):
        raise ConfigError(file, key, None, f"expected {{ channel = ..., unit = ... }} or a constant with its "
                                           f"unit, e.g. {example}")
    if not _NUMBER_FIRST.match(v):
        raise ConfigError(file, key, v, f"not a constant (a number and its unit, e.g. {example}); {channel}")
    with numbers_in_si():   # a constant without its unit is refused below, not read in SI
        value = check_value(schema_field("operating_point", name), v, file, key)
    q = registry().Quantity(v.strip())
    if not hasattr(q, "units") or q.unitless:
        raise ConfigError(file, key, v, f"a constant takes its unit, e.g. {example}")
    if kind == "angular_speed":
        _names_an_angle(q, file, key, v)
    return DutyConstant(value, v)


def _duty(top: dict, file) -> dict:
    """The ``[trace.duty]`` table: each channel (name, SI scale, unit, group) or constant, and the tolerance."""
    duty = top["duty"]
    if not isinstance(duty, dict):
        raise ConfigError(file, "trace.duty", duty, "expected a table of channels (speed, radial_load, axial_load)")
    _unknown(duty, _DUTY_KEYS, file, "trace.duty.")
    out = {}
    for name, kind in DUTY_KINDS.items():
        where = f"trace.duty.{name}"
        if name not in duty:
            raise ConfigError(file, where, None, "missing: the duty cycle needs the speed and both loads "
                                                 "({ channel = ..., unit = ... }, or a load held constant "
                                                 "with its unit, e.g. '0 kN')")
        c = duty[name]
        if not isinstance(c, dict):
            out[name] = _duty_constant(c, name, kind, file, where)
            continue
        _unknown(c, _DUTY_CHANNEL_KEYS, file, where + ".")
        cname = _string(c, "channel", file, where + ".")
        if "unit" not in c:
            raise ConfigError(file, where + ".unit", None, "missing: every measured series carries its unit")
        scale = _scale(c["unit"], kind, file, where + ".unit")
        out[name] = DutyChannel(cname, scale, c["unit"], _string(c, "group", file, where + ".", required=False))
    if isinstance(out["speed"], DutyConstant):
        raise ConfigError(file, "trace.duty.speed", duty["speed"],
                          "a constant speed gives no phases (they are found from the speed channel's rest "
                          "and steady levels): give the speed channel, or the cycle as a profile file (profile)")
    tol = duty.get("tolerance", DUTY_TOLERANCE)
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not (0 < tol < 0.5):
        raise ConfigError(file, "trace.duty.tolerance", tol, "must be a fraction between 0 and 0.5")
    return {"duty": out, "duty_tolerance": float(tol)}


def trace_from_dict(raw: dict, file="<input>") -> Trace:
    """Validate a trace file's contents (see the module docstring).

    Raises
    ------
    ConfigError
        Unknown keys, a missing ``file``/``format``/``time``/channel, an unknown format, a
        channel unit that is not a length, a time unit that is not a time, a sample rate
        that is not positive, a sign other than ±1, a missing data or profile file, a duty
        channel whose unit is not a speed or a force, a profile and ``[trace.duty]`` both.
    """
    if set(raw) != {"trace"}:
        extra = sorted(set(raw) - {"trace"})
        raise ConfigError(file, extra[0] if extra else "trace", None,
                          "a trace file holds one table, [trace]" if extra else "missing table [trace]")
    top = raw["trace"]
    if not isinstance(top, dict):
        raise ConfigError(file, "trace", top, "expected a table")
    _unknown(top, _TOP_KEYS, file, "trace.")
    name = _string(top, "name", file, "trace.", required=False, default=Path(str(file)).stem)
    data = resolve_path(file, _string(top, "file", file, "trace."))
    fmt = _string(top, "format", file, "trace.")
    if fmt.lower() not in FORMATS:
        raise ConfigError(file, "trace.format", fmt, f"unknown format (known: {', '.join(FORMATS)})")
    if not data.is_file():
        raise ConfigError(file, "trace.file", top["file"], f"no such data file ({data})")
    time = top.get("time")
    if not isinstance(time, dict):
        raise ConfigError(file, "trace.time", time, "missing or not a table: give { channel = ..., unit = ... } "
                                                     "or { rate = '2 kHz' }")
    _unknown(time, _TIME_KEYS, file, "trace.time.")
    kw = {}
    if "channel" in time:
        if "rate" in time:
            raise ConfigError(file, "trace.time.rate", time["rate"], "give either a time channel or a rate, not both")
        kw["time_channel"] = _string(time, "channel", file, "trace.time.")
        kw["time_scale"] = _scale(time.get("unit", "s"), "time", file, "trace.time.unit")
        kw["time_group"] = _string(time, "group", file, "trace.time.", required=False)
    elif "rate" in time:
        rate = parse_quantity(time["rate"], "frequency", file=file, key="trace.time.rate")
        if not (rate > 0 and math.isfinite(rate)):
            raise ConfigError(file, "trace.time.rate", time["rate"], "must be positive")
        kw["rate"] = rate
    else:
        raise ConfigError(file, "trace.time", time, "give a time channel (channel, unit) or a sample rate (rate)")
    chans = top.get("channel")
    if not isinstance(chans, list) or not chans:
        raise ConfigError(file, "trace.channel", chans, "missing: give at least one [[trace.channel]]")
    channels = []
    for i, c in enumerate(chans):
        where = f"trace.channel[{i}]."
        if not isinstance(c, dict):
            raise ConfigError(file, where[:-1], c, "expected a table")
        _unknown(c, _CHANNEL_KEYS, file, where)
        cname = _string(c, "name", file, where)
        if "unit" not in c:
            raise ConfigError(file, where + "unit", None, "missing: every measured series carries its unit")
        scale = _scale(c["unit"], "length", file, where + "unit")
        measures = _string(c, "measures", file, where)
        if measures not in MEASURES:
            raise ConfigError(file, where + "measures", measures, f"unknown (known: {', '.join(MEASURES)})")
        sign = c.get("sign", 1)
        if isinstance(sign, bool) or sign not in (1, -1):
            raise ConfigError(file, where + "sign", sign, "must be 1 or -1")
        if any(ch.measures == measures for ch in channels):
            raise ConfigError(file, where + "measures", measures, "a second channel for the same displacement")
        channels.append(TraceChannel(cname, scale, c["unit"], measures, float(sign),
                                     _string(c, "position", file, where, required=False),
                                     _string(c, "group", file, where, required=False)))
    if "duty" in top:
        if "profile" in top:
            raise ConfigError(file, "trace.duty", None, "give the duty cycle either as a profile file (profile) "
                                                        "or as channels of the data ([trace.duty]), not both")
        kw.update(_duty(top, file))
    for key in ("profile", "bearing"):
        if key in top:
            p = resolve_path(file, _string(top, key, file, "trace."))
            if not p.is_file():
                raise ConfigError(file, f"trace.{key}", top[key], f"no such file ({p})")
            kw[key] = p
    for key, kind in (("speed", "angular_speed"), ("radial_load", "force"), ("axial_load", "force")):
        if key in top:
            kw[key] = parse_quantity(top[key], kind, file=file, key=f"trace.{key}")
    if "low_pass" in top:
        f = parse_quantity(top["low_pass"], "frequency", file=file, key="trace.low_pass")
        if not (f > 0 and math.isfinite(f)):
            raise ConfigError(file, "trace.low_pass", top["low_pass"], "must be a positive frequency")
        kw["low_pass"] = f
    return Trace(source=str(file), name=name, file=data, format=fmt.lower(), channels=tuple(channels),
                 description=str(top.get("description", "")), **kw)


def load_trace(path) -> Trace:
    """Read and validate a trace file (:func:`read_toml` + :func:`trace_from_dict`)."""
    return trace_from_dict(read_toml(path), file=str(path))
