"""Physical bounds of a bearing's values, computed from the bearing itself.

The geometry checks (:mod:`rvcore.bearing.checks`) refuse what cannot be built.
These refuse what can be written but makes no bearing: a clearance, a ball, a raceway
offset or waviness so large that the balls are crushed at rest or leave their groove, and
loads no set of balls can carry. Every bound is a fact of the bearing's own geometry and
Hertz contacts, not a number picked for the purpose:

- **the static limit approach** δ₀ of a row: the elastic approach of the two contacts of
  one ball (inner and outer, in series, at the row's nominal contact angle) when the more
  heavily stressed one reaches ISO 76's 4200 MPa, the pressure of a permanent dent of
  1e-4·D_w. A ball pressed further is damaged standing still. ``Q₀`` is that ball load.
- **the free contact angle** α₀ of a clearance: ``cos α₀ = 1 − P_d / (2A)`` with
  ``A = (f_i + f_o − 1)·D_w`` the distance of the groove centres (Harris). At
  ``P_d = 2A`` the balls touch their grooves at 90°: over the shoulders.
- **a ball on a wavy raceway** follows the wave only while the troughs curve less than the
  ball does (``2/D_w``); a tighter trough is bridged by the ball, which then touches two
  crests, not the one point the model reads the raceway at.

See docs/inputs.md ("Physical bounds") for the rules with their numbers for the shipped
bearings.
"""
from __future__ import annotations

import math

from rvcore.bearing import geometry as geo
from rvcore.hertz import effective_modulus, race_contact
from rvcore.standards.iso76 import ISO76_BALL_PRESSURE

__all__ = ["static_limit", "physical_problems", "load_capacity", "load_problems", "record_problems", "refuse_beyond_bounds", "MAX_RECORD_BYTES",
           "MAX_RUNOUT_POINTS"]

#: Largest record one case may store [bytes]: samples × signals × 8 bytes. The study's
#: case stores 4600 samples of 44 signals, 1.6 MB; 1 GiB is 650 times that, and a sweep's
#: workers each hold one case's record in memory while they write it.
MAX_RECORD_BYTES = 2**30

#: Most ring angles of ``statics --runout N``: each is a full quasi-static solve, and the
#: path is held in memory. 3600 is one angle every 0.1 degree, ten points per wave of a
#: waviness of order 360.
MAX_RUNOUT_POINTS = 3600


def _um(x: float) -> str:
    """A length in µm, or in mm from 1 mm on."""
    return f"{x * 1e6:.4g} µm" if abs(x) < 1e-3 else f"{x * 1e3:.4g} mm"


def _mm(x: float) -> str:
    return f"{x * 1e3:.4g} mm"


def static_limit(bearing: geo.Bearing, row: geo.Row) -> tuple:
    """The static limit of one ball of ``row``: ``(Q₀ [N], δ₀ [m])``.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
        For the materials [-].
    row : rvcore.bearing.geometry.Row
        The row [-].

    Returns
    -------
    tuple of float
        ``Q₀`` [N], the ball load at which the more stressed of the inner and outer
        contacts (first arcs, at the row's nominal contact angle) reaches ISO 76's
        ``p₀ = 4200 MPa``, and ``δ₀`` [m], the approach of both contacts together at ``Q₀``.

    Notes
    -----
    Hertz: ``p_max = c·Q^(1/3)`` and ``δ = (Q/K)^(2/3)`` for each contact, so
    ``Q₀ = min_ring (p₀/c)³`` and ``δ₀ = (Q₀/K_i)^(2/3) + (Q₀/K_o)^(2/3)``.
    """
    rm, bm = bearing.ring_material, bearing.ball_material
    e_eff = (effective_modulus(rm.youngs_modulus, rm.poisson_ratio) if rm == bm else
             effective_modulus(bm.youngs_modulus, bm.poisson_ratio, rm.youngs_modulus, rm.poisson_ratio))
    alpha = row.nominal_contact_angle
    inner = race_contact(row.ball_diameter, row.pitch_diameter, row.inner_arcs[0].curvature_ratio,
                         alpha, geo.INNER, e_eff)
    outer = race_contact(row.ball_diameter, row.pitch_diameter, row.outer_arcs[0].curvature_ratio,
                         alpha, geo.OUTER, e_eff)
    q0 = min((ISO76_BALL_PRESSURE / c.pressure_coefficient) ** 3 for c in (inner, outer))
    return q0, float(inner.deflection(q0) + outer.deflection(q0))


def _ball_load(bearing, row, approach: float) -> float:
    """The ball load [N] at a total approach [m] of its two contacts (series springs)."""
    q0, d0 = static_limit(bearing, row)
    return q0 * (approach / d0) ** 1.5   # δ ∝ Q^(2/3) for both contacts alike


def physical_problems(bearing: geo.Bearing):
    """Values that make no bearing, as ``(row index, key, value [SI], reason)``.

    ``key`` is a row key (``radial_clearance``) or an imperfection key
    (``imperfections.inner_eccentricity``, ``imperfections.outer_waviness[1].order``,
    ``imperfections.ball_diameter_deviation[4]``); the caller finds where the file wrote it.

    The rules, per row (δ₀, Q₀ from :func:`static_limit`; ``P_d`` the radial clearance,
    which moves each arc by ``P_d/4`` so a ball's two contacts approach by ``−P_d/2`` with
    the rings centred):

    1. an interference (``P_d < 0``) presses every ball by ``−P_d/2``: at most δ₀;
    2. a clearance is less than ``2A = 2(f_i + f_o − 1)·D_w``, where the free contact
       angle reaches 90°;
    3. a ball's diameter deviation ΔD is at most δ₀ either way: larger, with the clearance,
       it is pressed beyond δ₀ at rest; smaller, it carries nothing until every other ball
       is dented (ISO 3290's coarsest grade, G100, varies by 5 µm within a lot);
    4. a raceway's eccentricity plus its waviness amplitudes ``s = e + Σ|A_k|`` is at most
       ``δ₀ + max(P_d, 0)/2``: a ring held concentric by its seat (the reducer's crank
       bearing seat, its housing) presses the ball at the high point by ``s − P_d/2``;
    5. each waviness term's trough curves less than the ball: ``A·k²/R² − 1/R < 2/D_w`` on
       the inner raceway (radius ``R = (d_m − D_w cos α)/2``, convex) and
       ``A·k²/R² + 1/R < 2/D_w`` on the outer (``R = (d_m + D_w cos α)/2``, concave);
    6. a raceway's axial runout plus its axial harmonics ``s_z = a + Σ|B_k|``, along the
       line of contact ``s_z·sin α``, is at most ``δ₀ + max(P_d, 0)/2``: a ring held square
       and in place (its seat's shoulder) presses the ball at the high point by
       ``s_z·sin α − P_d/2`` (rule 4 along the axis).
    """
    out = []
    for i, row in enumerate(bearing.rows):
        out += _row_problems(bearing, i, row)
    return out


def _row_problems(bearing, i, row):
    out = []
    d = row.ball_diameter
    q0, d0 = static_limit(bearing, row)
    limit = (f"δ₀ = {_um(d0)}, the approach at which a ball's contact reaches ISO 76's "
             f"{ISO76_BALL_PRESSURE / 1e6:.0f} MPa (a permanent dent) under {q0 / 1e3:.4g} kN")
    pd = row.radial_clearance
    if -pd / 2.0 > d0:
        out.append((i, "radial_clearance", pd,
                    f"an interference of {_mm(-pd)} presses every ball by {_um(-pd / 2)} at rest "
                    f"({_ball_load(bearing, row, -pd / 2) / 1e3:.4g} kN a ball); a radial preload may "
                    f"press it by at most {limit}, i.e. a radial clearance of at least {_um(-2 * d0)}"))
    big_a = (row.inner_arcs[0].curvature_ratio + row.outer_arcs[0].curvature_ratio - 1.0) * d
    if pd >= 2.0 * big_a:
        out.append((i, "radial_clearance", pd,
                    f"the balls would touch their grooves at 90 deg, over the shoulders: a clearance "
                    f"must be less than 2(f_i + f_o - 1)·D_w = {_mm(2 * big_a)}, where the free "
                    f"contact angle arccos(1 - P_d/(2(f_i + f_o - 1)·D_w)) reaches 90 deg"))
    imp = row.imperfections
    for j, dev in enumerate(getattr(imp, "ball_diameter_deviation", ()) or ()):
        if abs(dev) > d0 or dev - pd / 2.0 > d0:
            if d + dev <= 0:
                why = (f"a ball of {_mm(d + dev)}: the deviation must be far smaller than the ball "
                       f"({_mm(d)}); at most {limit}")
            elif dev < 0:
                why = (f"a ball smaller than its set by {_um(-dev)} carries no load until every other "
                       f"ball is dented: a deviation may be at most {limit}")
            else:
                why = (f"a ball larger by {_um(dev)} (with the clearance of {_um(pd)}) is pressed by "
                       f"{_um(dev - pd / 2)} at rest; at most {limit}")
            out.append((i, f"imperfections.ball_diameter_deviation[{j}]", dev, why))
    pitch = row.pitch_diameter
    cos_a = math.cos(row.nominal_contact_angle)
    for ring, sign in (("inner", -1.0), ("outer", 1.0)):
        e = getattr(imp, f"{ring}_eccentricity", None) or 0.0
        waves = getattr(imp, f"{ring}_waviness", ()) or ()
        shift = abs(e) + sum(abs(w.amplitude) for w in waves)
        allowed = d0 + max(pd, 0.0) / 2.0
        if shift > allowed:
            key = (f"imperfections.{ring}_eccentricity" if abs(e) >= max((abs(w.amplitude) for w in waves),
                                                                         default=0.0)
                   else f"imperfections.{ring}_waviness[{max(range(len(waves)), key=lambda n: abs(waves[n].amplitude))}].amplitude")
            value = e if key.endswith("eccentricity") else None
            if value is None:
                value = max((w.amplitude for w in waves), key=abs)
            out.append((i, key, value,
                        f"moves the {ring} raceway by up to {_um(shift)} (eccentricity + waviness "
                        f"amplitudes): held concentric, its high point would press a ball by more than "
                        f"{limit}" + (f" plus half the clearance, {_um(pd / 2)}" if pd > 0 else "")))
        axial = getattr(imp, f"{ring}_axial_amplitude", None) or 0.0
        axial_waves = getattr(imp, f"{ring}_axial_waviness", None) or ()
        shift_z = abs(axial) + sum(abs(w.amplitude) for w in axial_waves)
        sin_a = abs(math.sin(row.nominal_contact_angle))
        if shift_z * sin_a > allowed:
            big = max(range(len(axial_waves)), key=lambda n: abs(axial_waves[n].amplitude), default=None)
            if big is None or abs(axial) >= abs(axial_waves[big].amplitude):
                key, value = f"imperfections.{ring}_axial_amplitude", axial
            else:
                key, value = f"imperfections.{ring}_axial_waviness[{big}].amplitude", axial_waves[big].amplitude
            out.append((i, key, value,
                        f"moves the {ring} groove along the axis by up to {_um(shift_z)} (axial runout + "
                        f"harmonics), {_um(shift_z * sin_a)} along the line of contact: held square, its high "
                        f"point would press a ball by more than {limit}"
                        + (f" plus half the clearance, {_um(pd / 2)}" if pd > 0 else "")))
        radius = (pitch + sign * d * cos_a) / 2.0
        for n, w in enumerate(waves):
            trough = abs(w.amplitude) * w.order ** 2 / radius ** 2 + sign / radius
            if trough >= 2.0 / d:
                k_max = math.floor(radius * math.sqrt(max(2.0 / d - sign / radius, 0.0) / abs(w.amplitude)))
                out.append((i, f"imperfections.{ring}_waviness[{n}].order", w.order,
                            f"at {_um(w.amplitude)} a wave of {w.order} lobes curves its troughs by "
                            f"{trough * 1e-3:.4g} /mm, more than the ball's 2/D_w = {2e-3 / d:.4g} /mm: "
                            f"the ball bridges them and touches two crests, not the one point the model "
                            f"reads; at this amplitude the order may be at most {k_max}"))
    return out


def load_capacity(bearing: geo.Bearing) -> tuple:
    """The most force [N] and moment [N m] any set of the bearing's balls carries, and the
    number of balls.

    Every ball's load is at most ``Q₀`` (:func:`static_limit`) before it is dented, and
    each ball's share of a force is at most its load (``Q cos α cos ψ``, ``Q sin α``), so
    the bearing carries at most ``Σ_rows Z·Q₀`` of radial or axial force, and at most
    ``Σ_rows Z·Q₀·((d_m + D_w)/2 + |z_row|)`` of moment (no contact lies farther from the
    centre).
    """
    force, moment = 0.0, 0.0
    for row in bearing.rows:
        q0, _ = static_limit(bearing, row)
        force += row.ball_count * q0
        moment += row.ball_count * q0 * ((row.pitch_diameter + row.ball_diameter) / 2.0 + abs(row.axial_position))
    return force, moment, sum(r.ball_count for r in bearing.rows)


def load_problems(bearing: geo.Bearing, op, capacity: tuple | None = None) -> list:
    """Loads no set of balls can carry, as ``(key, value [SI], reason)``.

    A load beyond :func:`load_capacity` (given as ``capacity`` when already computed for
    this bearing) dents a ball at rest whatever its distribution.
    """
    force, moment, balls = capacity if capacity is not None else load_capacity(bearing)
    out = []
    for key, value, cap, unit in (("radial_load", op.radial_load, force, "N"), ("axial_load", op.axial_load, force, "N"),
                                  ("moment", op.moment, moment, "N m")):
        if abs(value) > cap:
            out.append((key, value,
                        f"more than the bearing can carry: {balls} balls at their ISO 76 limit "
                        f"({ISO76_BALL_PRESSURE / 1e6:.0f} MPa, a permanent dent) carry at most "
                        f"{cap:.4g} {unit}; a larger load dents a ball standing still"))
    return out


def record_problems(settings, profile, bearing, sensors=()) -> list:
    """An output rate the step cannot feed or the memory cannot hold, as ``(key, value [SI], reason)``.

    - a fixed ``time_step`` computes one state a step: a stored sample more often than
      that repeats a state, so ``output_rate ≤ 1/time_step``;
    - the record holds ``output_rate × window`` samples of
      :func:`rvcore.output_table.signal_count` signals of 8 bytes: at most
      :data:`MAX_RECORD_BYTES`.
    """
    from rvcore.output_table import signal_count

    rate = settings.output_rate
    out = []
    if settings.time_step > 0 and rate * settings.time_step > 1.0 + 1e-12:
        out.append(("output_rate", rate,
                    f"{rate:g} Hz is more samples than steps: the fixed time_step of "
                    f"{settings.time_step * 1e6:g} us computes at most {1 / settings.time_step:.6g} states a second"))
        return out
    end = settings.end_time or profile.duration
    window = max(end - settings.start_time, 0.0)
    signals = signal_count(len(bearing.rows), len(sensors))
    size = rate * window * signals * 8.0
    if size > MAX_RECORD_BYTES:
        most = MAX_RECORD_BYTES / (window * signals * 8.0)
        out.append(("output_rate", rate,
                    f"{rate:g} Hz over the {window:g} s window stores {rate * window:.4g} samples of "
                    f"{signals} signals, {size / 2**30:.4g} GiB, more than the {MAX_RECORD_BYTES / 2**30:g} GiB "
                    f"a case's record may take; at most {most:.4g} Hz here"))
    return out


def refuse_beyond_bounds(bearing, profile, op, settings, sensors, file, settings_of, raw, memo=None) -> None:
    """A load no set of balls carries, or an output rate the step cannot feed or the memory
    cannot hold (:mod:`pipeline.schema.physical`), said about the key that set it, before
    any case runs (:func:`load_problems`, :func:`record_problems`).

    ``settings_of`` are the case's :class:`pipeline.schema.sweepaxes.Setting` values (where
    each was written); ``raw`` the sweep file's TOML, to show the value as typed; ``memo``
    (a :class:`pipeline.schema.caseids.IdentityMemo`) computes each bearing's
    :func:`load_capacity` once.

    Raises
    ------
    ConfigError
        The first problem, naming the sweep file, the key and the value as typed.
    """
    from ..errors import ConfigError
    from .tomlfile import lookup

    capacity = memo.get(bearing, "load_capacity", load_capacity) if memo is not None else None
    problems = [("operating_point", *p) for p in load_problems(bearing, op, capacity)]
    problems += [("solver", *p) for p in record_problems(settings, profile, bearing, sensors)]
    for target, key, value, reason in problems[:1]:
        where = next((s.where for s in settings_of if s.target == target and s.inner == key),
                     key if target == "operating_point" else f"solver.{key}")
        typed = lookup((raw or {}), where, None) if raw is not None else None
        if typed is None or isinstance(typed, (dict, list)):
            unit = {"radial_load": "N", "axial_load": "N", "moment": "N m", "output_rate": "Hz"}[key]
            typed = f"{value:g} {unit}"
        raise ConfigError(file, where, typed, reason)
