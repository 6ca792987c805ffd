"""The duty cycle a rig ran, from channels of its data: the breakpoint profile the model runs.

A trace file's ``[trace.duty]`` names the recorded speed and radial and axial loads
(:mod:`pipeline.schema.tracefile`, units checked there); a load the rig held without
logging it is a constant instead. :func:`profile_from_channels`
turns them into a :class:`rvcore.profile.Profile` (linear breakpoint tables as fractions
of the steady operating point, and the phase windows) and that operating point, so that
``rvsweep simulate --profile`` runs the cycle the rig ran; :func:`profile_toml` writes it
as a profile file. SI throughout.
"""
from __future__ import annotations

import math

import numpy as np

from rvcore.profile import Channel, OperatingPoint, Profile

from ..errors import ConfigError


def breakpoints(time, x, tolerance: float) -> np.ndarray:
    """Indices of the samples a piecewise-linear line through them keeps within ``tolerance``.

    Parameters
    ----------
    time : ndarray
        Increasing sample times [s].
    x : ndarray
        Samples [any unit].
    tolerance : float
        The largest vertical distance allowed between a sample and the line [unit of x].

    Returns
    -------
    ndarray of int
        Sorted indices, the first and the last sample included.

    Notes
    -----
    Ramer–Douglas–Peucker (Ramer 1972, Computer Graphics and Image Processing 1, 244–256;
    Douglas and Peucker 1973, Cartographica 10, 112–122) with the vertical distance
    ``|x_i − (x_a + (x_b − x_a)(t_i − t_a)/(t_b − t_a))|`` in place of the perpendicular
    one, so that the bound is in the channel's own unit: a segment ``[a, b]`` is split at
    its farthest sample while that distance exceeds the tolerance.
    """
    t = np.asarray(time, dtype=np.float64)
    x = np.asarray(x, dtype=np.float64)
    keep = np.zeros(t.size, dtype=bool)
    keep[0] = keep[-1] = True
    stack = [(0, t.size - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        ti, xi = t[a + 1:b], x[a + 1:b]
        line = x[a] + (x[b] - x[a]) * (ti - t[a]) / (t[b] - t[a])
        d = np.abs(xi - line)
        k = int(np.argmax(d))
        if d[k] > tolerance:
            m = a + 1 + k
            keep[m] = True
            stack += [(a, m), (m, b)]
    return np.flatnonzero(keep)


def _fail(source, key, value, reason):
    raise ConfigError(source, key, value, reason)


def profile_from_channels(time, duty: dict, *, tolerance: float, name: str = "rig", source="<trace>",
                          channels=None):
    """The breakpoint profile and operating point of recorded speed and load channels.

    Parameters
    ----------
    time : ndarray
        Sample times from the first sample [s].
    duty : dict
        ``speed`` [rad s-1] over ``time``; ``radial_load`` and ``axial_load`` [N] over
        ``time``, or each a float: a load held constant over the record.
    tolerance : float
        Fraction of each channel's scale [1]: the breakpoint line keeps within
        ``tolerance/2`` of it, and the phase edges are where the speed is within
        ``tolerance`` of rest or of its steady value.
    name : str
        The profile's name.
    source : str
        The trace file, for the error messages.
    channels : dict or None
        The channels' names in the data (key -> name), for the error messages.

    Returns
    -------
    profile : rvcore.profile.Profile
        Linear breakpoint tables as fractions of the operating point (absolute where the
        steady value is 0), the phase windows, the duration of the record.
    operating_point : rvcore.profile.OperatingPoint
        The steady means of the speed [rad s-1] and the loads [N].

    Raises
    ------
    ConfigError
        A constant speed (no phases to find), a speed channel that never leaves rest, that does not start from rest before its
        steady value, or that does not come back to rest after it.

    Notes
    -----
    With ω̂ = max|ω| and ω0 the median of the samples where |ω| ≥ ω̂/2, the speed channel's
    breakpoints (:func:`breakpoints`, tolerance ``tolerance·ω̂/2``) set the phases: start-up
    from the last breakpoint at rest (|ω| ≤ tol·|ω0|) before the first breakpoint at speed
    (|ω| ≥ (1 − tol)|ω0|) to that one; deceleration from the last breakpoint at speed to the
    first at rest after it; steady between. The operating point is the mean of each channel
    over the steady window, and each channel's breakpoints (tolerance ``tolerance/2`` of
    the larger of its steady value and its largest magnitude) are divided by it. A load held
    constant at F is its own operating point, F0 = F exactly (not a mean of samples), and its
    table is the fraction 1 at the record's first and last sample; at F = 0 the table is the
    absolute value 0 N there, as for any channel whose steady mean is 0 (nothing is divided).
    """
    t = np.asarray(time, dtype=np.float64)
    names = channels or {}
    if np.ndim(duty["speed"]) == 0:
        _fail(source, "trace.duty.speed", duty["speed"], "a constant speed gives no phases: they are found "
                                                         "from the speed channel")
    w = np.asarray(duty["speed"], dtype=np.float64)
    key = "trace.duty.speed.channel"
    peak = float(np.max(np.abs(w)))
    if not peak > 0:
        _fail(source, key, names.get("speed"), "the speed never leaves zero: no duty cycle to read")
    w0 = float(np.median(w[np.abs(w) >= 0.5 * peak]))
    k = breakpoints(t, w, 0.5 * tolerance * peak)
    tk, vk = t[k], np.abs(w[k])
    at_speed = np.flatnonzero(vk >= (1 - tolerance) * abs(w0))
    at_rest = vk <= tolerance * abs(w0)
    b, c = int(at_speed[0]), int(at_speed[-1])
    before = np.flatnonzero(at_rest[:b])
    after = c + 1 + np.flatnonzero(at_rest[c + 1:])
    if before.size == 0:
        _fail(source, key, names.get("speed"), f"the speed does not start from rest (within {tolerance:g} of "
                                               f"{abs(w0):.6g} rad/s) before it reaches its steady value")
    if after.size == 0:
        _fail(source, key, names.get("speed"), f"the speed does not come back to rest (within {tolerance:g} of "
                                               f"{abs(w0):.6g} rad/s) after its steady value")
    t_a, t_b, t_c, t_d = float(tk[before[-1]]), float(tk[b]), float(tk[c]), float(tk[after[0]])
    if not t_b < t_c:
        _fail(source, key, names.get("speed"), "the speed holds its steady value for no time: no steady phase")
    steady = (t >= t_b) & (t < t_c)
    names3 = ("speed", "radial_load", "axial_load")
    held = {n for n in names3 if np.ndim(duty[n]) == 0}      # a load held constant: a float
    series = {n: (np.full(t.size, float(duty[n])) if n in held else np.asarray(duty[n], dtype=np.float64))
              for n in names3}
    op = {n: float(duty[n]) if n in held else float(np.mean(series[n][steady])) for n in names3}
    tables = {}
    for n in names3:
        x = series[n]
        scale = max(abs(op[n]), float(np.max(np.abs(x))))
        idx = k if n == "speed" else breakpoints(t, x, 0.5 * tolerance * scale)
        relative = op[n] != 0.0
        values = x[idx] / op[n] if relative else x[idx]
        tables[n] = Channel(tuple(float(v) for v in t[idx]), tuple(float(v) for v in values), relative=relative)
    profile = Profile(name, tables["radial_load"], tables["axial_load"], tables["speed"],
                      (("startup", t_a, t_b), ("steady", t_b, t_c), ("deceleration", t_c, t_d)), float(t[-1]),
                      description=f"the duty cycle recorded with the trace {name!r} (speed and load channels"
                                  + "".join(f", {n} held at {op[n]:.6g} N" for n in names3 if n in held)
                                  + f"), breakpoints within {tolerance / 2:g} of each channel's scale")
    return profile, OperatingPoint(op["speed"], op["radial_load"], op["axial_load"])


def profile_toml(profile: Profile, header: str = "") -> str:
    """A profile file (docs/inputs.md) of ``profile``: times in s, fractions or values in SI.

    Every number is written with :func:`repr` (round-trip exact); reading the file back
    (:func:`pipeline.schema.profilefile.load_profile`) gives ``profile`` again.
    """
    import tomli_w

    units = {"radial_load": "N", "axial_load": "N", "speed": "rad/s"}
    doc = {"name": profile.name, "description": profile.description, "duration": f"{profile.duration!r} s"}
    for n, ch in (("radial_load", profile.radial_load), ("axial_load", profile.axial_load),
                  ("speed", profile.speed)):
        table = {"time": [f"{v!r} s" for v in ch.times]}
        if ch.relative:
            table["fraction"] = [float(v) for v in ch.values]
        else:
            table["value"] = [f"{v!r} {units[n]}" for v in ch.values]
        table["interpolation"] = ch.interpolation
        doc[n] = table
    doc["phases"] = {p: [f"{s!r} s", f"{e!r} s"] for (p, s, e) in profile.phases}
    head = "".join(f"# {line}\n" for line in header.splitlines())
    return head + tomli_w.dumps(doc)


def operating_point_text(op: OperatingPoint) -> str:
    """The operating point as ``rvsweep simulate`` takes it (deg/s and kN)."""
    return (f"--speed {math.degrees(op.speed):.6g}deg/s --radial-load {op.radial_load / 1e3:.6g}kN "
            f"--axial-load {op.axial_load / 1e3:.6g}kN")
