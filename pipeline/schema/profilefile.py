"""Profile files: TOML in, a validated :class:`rvcore.profile.Profile` (SI) out.

Keys, kinds, bounds and defaults come from the schema (:mod:`pipeline.schema.fields`), and
the loader's one converter (:func:`pipeline.schema.convert.from_fields`) reads the Profile
and each channel's table by the field table: the cycle's duration and description, a
channel's times and interpolation. This module adds what one field cannot say
(:data:`SET_ELSEWHERE`: the optional channels, ``moment`` and ``load_direction``, left out or
given whole; a channel's values as ``fraction`` or ``value``, exactly one; only ``value`` for
``load_direction``, an angle offset, whose ``fraction`` the schema refuses,
:data:`pipeline.schema.fields.REFUSED_KEYS`) and the rules keys obey together, each run as
soon as what it ties is read: a channel's times strictly increasing and inside the cycle
(:func:`_times`), one value per time (:func:`_count`), the phase windows inside the cycle
and in order (:func:`_phases`). The file format is described in :mod:`pipeline.schema.config`.
"""
from __future__ import annotations

import dataclasses
import functools

from rvcore.profile import PHASES, Channel, Profile

from ..errors import ConfigError
from . import fields as schema
from .convert import from_fields
from .reader import Table, short, top_table
from .tomlfile import read_toml
from .units import unit_warnings_on_success

__all__ = ["profile_from_dict", "load_profile", "CHANNELS", "SET_ELSEWHERE"]

#: The profile's channels (tables), in file order (``rvcore.profile.CH_*`` order).
CHANNELS = tuple(schema.profile_channels())

#: The profile's dataclass fields that no one key holds, and what sets them (the readers
#: :func:`profile_from_dict` gives the converter); every other field is read by the field
#: table (``Field.source``; a channel's, from its table by :func:`_channel`); a test holds that
#: each field is one or the other.
SET_ELSEWHERE = {
    "name": "the file's name key, else its stem (pipeline.schema.reader.top_table)",
    "phases": "[phases]: the windows, in PHASES order, read and held against the cycle by the "
              "profile's rule (_phases)",
    **{f"{c}.values": "fraction (of the operating point) or value (absolute), exactly one (_values)"
       for c in CHANNELS},
    **{f"{c}.relative": "true where the file gives fraction (_values)" for c in CHANNELS},
}


def _values(t: Table) -> tuple:
    """A channel's values: its ``fraction`` or its ``value``, exactly one (a channel that takes
    no fraction, its ``value``). Their number against the times: :func:`_count`."""
    name = t.path[-1]
    _, unit, fraction_allowed, _ = schema.profile_channels()[name]
    has_f, has_v = t.has("fraction"), t.has("value")
    if not fraction_allowed and not has_v:
        raise ConfigError(t.file, t.key("value"), None, f"missing required key (the {name} in {unit})")
    if has_f == has_v:
        raise ConfigError(t.file, t.key(None), None,
                          "give exactly one of 'fraction' (of the operating point) or 'value' "
                          "(absolute)" + (", not both" if has_f else ""))
    return tuple(t.get("fraction" if has_f else "value"))


def _channel(top: Table, name: str, readers: dict, rules: dict) -> Channel | None:
    """Channel ``name``: its table read by the field table (:func:`from_fields`); None for an
    optional channel the file leaves out."""
    if not schema.profile_channels()[name][3] and not top.has(name):
        return None
    top.raw(name)   # a required channel left out: "missing required key"
    return from_fields(Channel, top.table(name), name, readers, rules=rules)


def _times(times: tuple, t: Table, duration: float) -> tuple:
    """A channel's times: strictly increasing, the last inside the cycle."""
    for i in range(1, len(times)):
        if not times[i] > times[i - 1]:
            raise ConfigError(t.file, f"{t.key('time')}[{i}]", t.raw("time")[i],
                              f"times must increase strictly (the previous one is "
                              f"{t.raw('time')[i - 1]!r})")
    if times[-1] > duration * (1 + 1e-12):
        raise ConfigError(t.file, f"{t.key('time')}[{len(times) - 1}]", t.raw("time")[-1],
                          f"breakpoint after the end of the cycle (duration = {duration:g} s)")
    return times


def _count(values: tuple, t: Table) -> tuple:
    """A channel's values: one per time."""
    n = len(t.get("time"))
    if len(values) != n:
        vkey = "fraction" if t.has("fraction") else "value"
        raise ConfigError(t.file, t.key(vkey), short(t.raw(vkey)),
                          f"has {len(values)} entries but '{t.key('time')}' has {n}")
    return values


def _phases(profile: Profile, top: Table) -> Profile:
    """The profile's rule: its phase windows ``[start, end]``, each ending after it starts and
    inside the cycle, in the order of :data:`rvcore.profile.PHASES`, none starting before the
    previous one ends."""
    ph = top.table("phases")
    file, duration = top.file, profile.duration
    phases = []
    previous_end, previous_name = 0.0, None
    for p in PHASES:
        se = ph.raw(p)
        if not isinstance(se, list) or len(se) != ph.field(p).length:
            raise ConfigError(file, ph.key(p), short(se), "must be a list [start, end] of two times")
        s, e = ph.get(p)
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
    return dataclasses.replace(profile, phases=tuple(phases))


@unit_warnings_on_success
def profile_from_dict(raw: dict, file="<input>") -> Profile:
    """Validate a profile file's contents and build the :class:`rvcore.profile.Profile`.

    ``raw`` and ``file`` as for :func:`pipeline.schema.bearingfile.bearing_from_dict`.

    Raises
    ------
    ConfigError
        Unknown keys, missing tables, times not strictly increasing, lists of unequal
        length, neither or both of ``fraction``/``value``, a ``fraction`` in
        ``load_direction``, an unknown interpolation, phases outside the cycle or out of
        order.
    """
    top, name = top_table(raw, file, "profile")
    # problems are said in this order: the top level's keys, each channel in file order, the phases
    top.get("description")
    duration = top.get("duration")   # the channels' and the phases' rules hold times against it
    readers = {"name": lambda _: name, "phases": lambda _: (),   # built by the rule (_phases)
               **{f"{c}.values": _values for c in CHANNELS},
               **{f"{c}.relative": lambda t: t.has("fraction") for c in CHANNELS}}
    rules = {Profile: _phases, **{f"{c}.times": lambda times, t: _times(times, t, duration) for c in CHANNELS},
             **{f"{c}.values": _count for c in CHANNELS}}
    readers |= {c: functools.partial(_channel, name=c, readers=readers, rules=rules) for c in CHANNELS}
    return from_fields(Profile, top, "", readers, rules=rules)


def load_profile(path) -> Profile:
    """Read and validate a profile file (:func:`read_toml` + :func:`profile_from_dict`)."""
    return profile_from_dict(read_toml(path), file=str(path))
