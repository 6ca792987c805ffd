"""Service cycles as data: breakpoint tables for F_r, F_a and ω (model.md §6).

A profile has three channels. Each channel is a table of (time, value) breakpoints,
either absolute in SI or as fractions of the operating point, joined linearly or by the
cubic smoothstep (continuous derivative, so a smoothstep speed channel is a jerk-limited
S-curve). Before the first breakpoint a channel holds its first value, after the last
its last value. The phases (start-up, steady, deceleration) are named time windows.

The numba kernels read a resolved profile as three flat arrays (see
:func:`ResolvedProfile.arrays`); :func:`channel_value` and :func:`channel_rate` evaluate
them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from .contact import unit_step, unit_step_slope

LINEAR = 0
SMOOTHSTEP = 1
INTERPOLATIONS = {"linear": LINEAR, "smoothstep": SMOOTHSTEP}

#: Phase names in flag order; the NetCDF ``phase`` coordinate uses these flag values.
PHASES = ("startup", "steady", "deceleration")


@dataclass(frozen=True)
class Channel:
    """One breakpoint table.

    Parameters
    ----------
    times : tuple of float
        Strictly increasing breakpoint times [s].
    values : tuple of float
        Values at the breakpoints: SI, or fractions of the operating point if ``relative``.
    relative : bool
        Whether ``values`` are fractions of the operating point.
    interpolation : str
        ``"linear"`` or ``"smoothstep"``.
    """

    times: tuple
    values: tuple
    relative: bool = True
    interpolation: str = "linear"


@dataclass(frozen=True)
class OperatingPoint:
    """The operating point of one case.

    Parameters
    ----------
    speed : float
        Steady inner-ring speed ω0 [rad s^-1].
    radial_load : float
        Steady radial load F_r0 [N].
    axial_load : float
        Steady axial load F_a0 [N], positive towards +z.
    moment : float
        Steady tilting moment about the axis normal to the radial load [N m].
    load_angle : float
        Direction of the radial load in the x–y plane, from +x [rad].
    """

    speed: float
    radial_load: float
    axial_load: float
    moment: float = 0.0
    load_angle: float = 0.0


@dataclass(frozen=True)
class Profile:
    """A duty cycle: three channels, the phase windows and the cycle's end time [s]."""

    name: str
    radial_load: Channel
    axial_load: Channel
    speed: Channel
    phases: tuple  # ((name, start, end), ...) in PHASES order
    duration: float
    description: str = ""

    def resolve(self, op: OperatingPoint) -> "ResolvedProfile":
        """Absolute SI breakpoint tables for ``op``."""
        def scaled(ch: Channel, scale: float):
            v = np.asarray(ch.values, dtype=float) * (scale if ch.relative else 1.0)
            return (np.asarray(ch.times, dtype=float), v, INTERPOLATIONS[ch.interpolation])

        return ResolvedProfile(
            radial=scaled(self.radial_load, op.radial_load),
            axial=scaled(self.axial_load, op.axial_load),
            speed=scaled(self.speed, op.speed),
            phases=np.array([[s, e] for (_, s, e) in self.phases], dtype=float),
            duration=self.duration,
        )


@dataclass(frozen=True)
class ResolvedProfile:
    """Absolute tables ``(times, values, interpolation)`` per channel, phases, duration."""

    radial: tuple
    axial: tuple
    speed: tuple
    phases: np.ndarray
    duration: float

    def arrays(self):
        """Pack the three channels for numba.

        Returns
        -------
        table : ndarray (3, 2, n)
            ``table[c, 0]`` times and ``table[c, 1]`` values of channel c (radial, axial,
            speed), padded by repeating the last breakpoint.
        meta : ndarray (3, 2) of int64
            Number of breakpoints and interpolation kind per channel.
        """
        chans = (self.radial, self.axial, self.speed)
        n = max(len(c[0]) for c in chans)
        table = np.empty((3, 2, n))
        meta = np.empty((3, 2), dtype=np.int64)
        for i, (t, v, kind) in enumerate(chans):
            table[i, 0, : len(t)] = t
            table[i, 1, : len(v)] = v
            table[i, 0, len(t):] = t[-1]
            table[i, 1, len(v):] = v[-1]
            meta[i, 0] = len(t)
            meta[i, 1] = kind
        return table, meta

    def value(self, channel: int, t: float) -> float:
        table, meta = self.arrays()
        return channel_value(table, meta, channel, t)


@njit(cache=True, nogil=True)
def _segment(table, meta, c, t):
    n = meta[c, 0]
    times = table[c, 0]
    if t <= times[0]:
        return -1
    if t >= times[n - 1]:
        return n - 1
    k = 0
    while k < n - 2 and t >= times[k + 1]:
        k += 1
    return k


@njit(cache=True, nogil=True)
def channel_value(table, meta, c, t):
    """Value of channel ``c`` at time ``t`` (SI)."""
    n = meta[c, 0]
    k = _segment(table, meta, c, t)
    if k < 0:
        return table[c, 1, 0]
    if k >= n - 1:
        return table[c, 1, n - 1]
    t0, t1 = table[c, 0, k], table[c, 0, k + 1]
    v0, v1 = table[c, 1, k], table[c, 1, k + 1]
    s = (t - t0) / (t1 - t0)
    if meta[c, 1] == SMOOTHSTEP:
        s = unit_step(s)   # the cubic STEP of model.md §3, from its one home
    return v0 + (v1 - v0) * s


@njit(cache=True, nogil=True)
def channel_rate(table, meta, c, t):
    """Time derivative of channel ``c`` at time ``t`` (SI per second)."""
    n = meta[c, 0]
    k = _segment(table, meta, c, t)
    if k < 0 or k >= n - 1:
        return 0.0
    t0, t1 = table[c, 0, k], table[c, 0, k + 1]
    v0, v1 = table[c, 1, k], table[c, 1, k + 1]
    h = t1 - t0
    if meta[c, 1] == SMOOTHSTEP:
        return (v1 - v0) * unit_step_slope((t - t0) / h) / h
    return (v1 - v0) / h


def study_profile() -> Profile:
    """The study's cycle with t0…t4 = 0.3, 0.8, 3.8, 4.3, 4.6 s (model.md §6)."""
    t0, t1, t2, t3, t4 = 0.3, 0.8, 3.8, 4.3, 4.6
    load = Channel((0.0, t0, t3, t4), (0.0, 1.0, 1.0, 0.0))
    speed = Channel((t0, t1, t2, t3), (0.0, 1.0, 1.0, 0.0))
    return Profile("study", load, load, speed,
                   (("startup", t0, t1), ("steady", t1, t2), ("deceleration", t2, t3)), t4)


def scaled_study_profile(scale: float, name: str = "study-short") -> Profile:
    """The study's cycle with every time multiplied by ``scale`` (for reduced tests)."""
    p = study_profile()

    def sc(ch):
        return Channel(tuple(t * scale for t in ch.times), ch.values, ch.relative, ch.interpolation)

    return Profile(name, sc(p.radial_load), sc(p.axial_load), sc(p.speed),
                   tuple((n, s * scale, e * scale) for (n, s, e) in p.phases), p.duration * scale)
