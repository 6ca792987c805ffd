"""Service cycles as data: breakpoint tables for F_r, F_a, ω, M and ψ (docs/model.md §6).

A profile has five channels, numbered by the ``CH_*`` constants below (their one home):

========== =================== ========================================================
index      channel             resolved value (SI)
========== =================== ========================================================
CH_RADIAL  ``radial_load``     radial load F_r [N], along the direction ψ
CH_AXIAL   ``axial_load``      axial load F_a [N], towards +z
CH_SPEED   ``speed``           prescribed inner-ring speed ω [rad s^-1]
CH_MOMENT  ``moment``          tilting moment M [N m] about (−sin ψ, cos ψ, 0), the axis
                               normal to the radial load
CH_DIRECTION ``load_direction`` direction ψ of the radial load (and of the moment's
                               lever) in the x–y plane, from +x [rad]
========== =================== ========================================================

Each channel is a table of (time, value) breakpoints, either absolute in SI or as
fractions of the operating point, joined linearly or by the cubic smoothstep
(continuous derivative, so a smoothstep speed channel is a jerk-limited S-curve).
Before the first breakpoint a channel holds its first value, after the last its last
value. The phases (start-up, steady, deceleration) are named time windows.

The moment and the direction channels are optional:

- ``moment`` left out follows the radial-load channel's table (same times, same
  interpolation), scaled so that M(t) = M0·F_r(t)/F_r0 — the moment ramps with the load
  as it does when both come from one eccentric load. With the operating point's M0 = 0
  (the default) it is zero throughout.
- ``load_direction`` is always an absolute angle *offset* [rad] added to the operating
  point's ``load_angle`` (a fraction of an angle means nothing); left out it is a
  constant 0, so ψ = ``load_angle``.

The numba kernels read a resolved profile as two flat arrays (see
:func:`ResolvedProfile.arrays`); :func:`channel_value` and :func:`channel_rate` evaluate
them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from ._numba import kernel

from .contact.step import unit_step, unit_step_slope

LINEAR = 0
SMOOTHSTEP = 1
INTERPOLATIONS = {"linear": LINEAR, "smoothstep": SMOOTHSTEP}

#: Channel indices of the resolved table (:meth:`ResolvedProfile.arrays`), in row order.
CH_RADIAL, CH_AXIAL, CH_SPEED, CH_MOMENT, CH_DIRECTION = range(5)
N_CHANNELS = 5

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


#: The direction channel of a profile that gives none: a constant offset of 0 rad.
NO_DIRECTION_OFFSET = Channel((0.0,), (0.0,), relative=False)


@dataclass(frozen=True)
class Profile:
    """A duty cycle: the channels, the phase windows and the cycle's end time [s].

    ``moment`` None follows the radial-load channel (:meth:`moment_channel`);
    ``load_direction`` None is a constant 0 rad offset. ``load_direction`` must be
    absolute (``relative`` False): its values [rad] are added to the operating point's
    ``load_angle``.
    """

    name: str
    radial_load: Channel
    axial_load: Channel
    speed: Channel
    phases: tuple  # ((name, start, end), ...) in PHASES order
    duration: float
    description: str = ""
    moment: Channel | None = None
    load_direction: Channel | None = None

    def __post_init__(self):
        if self.load_direction is not None and self.load_direction.relative:
            raise ValueError(f"profile {self.name!r}: the load_direction channel is an absolute angle "
                             "offset [rad]; a fraction of the operating point's angle means nothing")

    def direction_channel(self) -> Channel:
        """The direction channel in effect: offsets [rad] added to ``load_angle``."""
        return NO_DIRECTION_OFFSET if self.load_direction is None else self.load_direction

    def moment_channel(self, op: "OperatingPoint") -> Channel:
        """The moment channel in effect for ``op``.

        Without a moment channel of its own, the radial-load channel's times and
        interpolation with values M0·F_r(t)/F_r0 as fractions of ``op.moment``: its own
        fractions when it is relative; for an absolute radial channel its values over
        ``op.radial_load``, or over their largest magnitude when ``op.radial_load`` is 0
        (all zero when the channel is). M0 = 0 gives zero throughout.
        """
        if self.moment is not None:
            return self.moment
        ch = self.radial_load
        values = np.asarray(ch.values, dtype=float)
        if not ch.relative:
            peak = float(np.max(np.abs(values)))
            scale = op.radial_load if op.radial_load != 0.0 else peak
            values = values / scale if scale != 0.0 else np.zeros_like(values)
        return Channel(ch.times, tuple(float(v) for v in values), relative=True,
                       interpolation=ch.interpolation)

    def resolve(self, op: OperatingPoint) -> "ResolvedProfile":
        """Absolute SI breakpoint tables for ``op``."""
        def scaled(ch: Channel, scale: float):
            v = np.asarray(ch.values, dtype=float) * (scale if ch.relative else 1.0)
            return (np.asarray(ch.times, dtype=float), v, INTERPOLATIONS[ch.interpolation])

        d_times, d_offsets, d_kind = scaled(self.direction_channel(), 1.0)
        return ResolvedProfile(
            radial=scaled(self.radial_load, op.radial_load),
            axial=scaled(self.axial_load, op.axial_load),
            speed=scaled(self.speed, op.speed),
            moment=scaled(self.moment_channel(op), op.moment),
            direction=(d_times, op.load_angle + d_offsets, d_kind),
            phases=np.array([[s, e] for (_, s, e) in self.phases], dtype=float),
            duration=self.duration,
        )


@dataclass(frozen=True)
class ResolvedProfile:
    """Absolute tables ``(times, values, interpolation)`` per channel, phases, duration.

    ``direction`` holds the radial load's direction ψ itself [rad] (the operating point's
    ``load_angle`` plus the profile's offset), ``moment`` the moment [N m].
    """

    radial: tuple
    axial: tuple
    speed: tuple
    moment: tuple
    direction: tuple
    phases: np.ndarray
    duration: float

    def channels(self) -> tuple:
        """The channel tables in ``CH_*`` order."""
        return (self.radial, self.axial, self.speed, self.moment, self.direction)

    def arrays(self):
        """Pack the channels for numba.

        Returns
        -------
        table : ndarray (N_CHANNELS, 2, n)
            ``table[c, 0]`` times and ``table[c, 1]`` values of channel c (``CH_*``),
            padded by repeating the last breakpoint.
        meta : ndarray (N_CHANNELS, 2) of int64
            Number of breakpoints and interpolation kind per channel.
        """
        chans = self.channels()
        n = max(len(c[0]) for c in chans)
        table = np.empty((N_CHANNELS, 2, n))
        meta = np.empty((N_CHANNELS, 2), dtype=np.int64)
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


@kernel
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


@kernel
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
        s = unit_step(s)   # the cubic STEP of docs/model.md §3, from its one home
    return v0 + (v1 - v0) * s


@kernel
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


@kernel
def _antiderivative(table, meta, c, t):
    """``∫`` of channel ``c`` from its first breakpoint to ``t`` (negative before it)."""
    n = meta[c, 0]
    times, values = table[c, 0], table[c, 1]
    if t <= times[0]:
        return values[0] * (t - times[0])
    total = 0.0
    for k in range(n - 1):
        t0, t1 = times[k], times[k + 1]
        v0, v1 = values[k], values[k + 1]
        h = t1 - t0
        s = min((t - t0) / h, 1.0)
        # ∫₀ˢ of the linear ramp s, or of the cubic STEP 3s² − 2s³ (smoothstep)
        ramp = s * s * s - 0.5 * s * s * s * s if meta[c, 1] == SMOOTHSTEP else 0.5 * s * s
        total += h * (v0 * s + (v1 - v0) * ramp)
        if t <= t1:
            return total
    return total + values[n - 1] * (t - times[n - 1])


@kernel
def channel_integral(table, meta, c, t):
    """``∫₀ᵗ`` of channel ``c`` (SI times seconds): for the speed channel, the angle the
    inner ring has turned through since t = 0 [rad], exact for either interpolation."""
    return _antiderivative(table, meta, c, t) - _antiderivative(table, meta, c, 0.0)


def study_profile() -> Profile:
    """The study's cycle with t0…t4 = 0.3, 0.8, 3.8, 4.3, 4.6 s (docs/model.md §6)."""
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
                   tuple((n, s * scale, e * scale) for (n, s, e) in p.phases), p.duration * scale,
                   p.description, *(None if ch is None else sc(ch) for ch in (p.moment, p.load_direction)))
