"""Profile files: TOML in, a validated :class:`rvcore.profile.Profile` (SI) out.

Keys, kinds, bounds and defaults come from the schema (:mod:`pipeline.schema.fields`);
this module adds the rules across fields: times strictly increasing and inside the
cycle, exactly one of ``fraction``/``value`` with as many entries as ``time`` (only
``value`` for ``load_direction``, an angle offset), the optional channels (``moment``,
``load_direction``) left out or given whole, phases inside the cycle and in order. The
file format is described in :mod:`pipeline.schema.config`.
"""
from __future__ import annotations


from rvcore.profile import PHASES, Channel, Profile

from ..errors import ConfigError
from . import fields as schema
from .reader import Table, short, top_table
from .tomlfile import read_toml

__all__ = ["profile_from_dict", "load_profile", "CHANNELS"]

#: The profile's channels (tables), in file order (``rvcore.profile.CH_*`` order).
CHANNELS = tuple(schema.profile_channels())


def _channel(top: Table, name: str, duration: float) -> Channel | None:
    """Channel ``name`` of the file; None for an optional channel the file leaves out."""
    _, unit, fraction_allowed, required = schema.profile_channels()[name]
    if not required and not top.has(name):
        return None
    raw = top.raw(name)
    if not fraction_allowed and isinstance(raw, dict) and "fraction" in raw:
        raise ConfigError(top.file, top.key(name) + ".fraction", short(raw["fraction"]),
                          f"{name} takes only 'value' (an angle in {unit}, added to the operating "
                          f"point's load_angle): a fraction of an angle means nothing")
    t = top.table(name)
    times = t.get("time")
    for i in range(1, len(times)):
        if not times[i] > times[i - 1]:
            raise ConfigError(t.file, f"{t.key('time')}[{i}]", t.raw("time")[i],
                              f"times must increase strictly (the previous one is "
                              f"{t.raw('time')[i - 1]!r})")
    if times[-1] > duration * (1 + 1e-12):
        raise ConfigError(t.file, f"{t.key('time')}[{len(times) - 1}]", t.raw("time")[-1],
                          f"breakpoint after the end of the cycle (duration = {duration:g} s)")
    has_f, has_v = t.has("fraction"), t.has("value")
    if not fraction_allowed and not has_v:
        raise ConfigError(t.file, t.key("value"), None, f"missing required key (the {name} in {unit})")
    if has_f == has_v:
        raise ConfigError(t.file, t.key(None), None,
                          "give exactly one of 'fraction' (of the operating point) or 'value' "
                          "(absolute)" + (", not both" if has_f else ""))
    vkey = "fraction" if has_f else "value"
    values = t.get(vkey)
    if len(values) != len(times):
        raise ConfigError(t.file, t.key(vkey), short(t.raw(vkey)),
                          f"has {len(values)} entries but '{t.key('time')}' has {len(times)}")
    return Channel(times=tuple(times), values=tuple(values), relative=has_f,
                   interpolation=t.get("interpolation"))


def _phases(top: Table, duration: float) -> tuple:
    ph = top.table("phases")
    file = top.file
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
    return tuple(phases)


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
    description = top.get("description")
    duration = top.get("duration")
    channels = {c: _channel(top, c, duration) for c in CHANNELS}
    return Profile(name=name, radial_load=channels["radial_load"], axial_load=channels["axial_load"],
                   speed=channels["speed"], phases=_phases(top, duration), duration=duration,
                   description=description, moment=channels["moment"],
                   load_direction=channels["load_direction"])


def load_profile(path) -> Profile:
    """Read and validate a profile file (:func:`read_toml` + :func:`profile_from_dict`)."""
    return profile_from_dict(read_toml(path), file=str(path))
