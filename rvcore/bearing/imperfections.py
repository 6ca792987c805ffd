"""A real bearing's imperfections (docs/model.md §12): raceway eccentricity and waviness, the
raceways' axial runout, ball size variation, and the ISO tolerance classes that set them. SI throughout.

A row's :class:`Imperfections` is what the bearing file gives: explicit values, or a
tolerance class and a ball grade to draw them from. :func:`realize` turns it into the
geometry one case runs with: the eccentricities from ISO 492's runouts, their high-point
angles and the balls' deviations drawn from the case's seed.

Notes
-----
How each enters the contact (:func:`rvcore.dynamics.raceway.raceway_offset`, the one place): the
raceway's groove, at the contact's angle φ in that ring's frame, is moved radially by

    Δr(φ) = e·cos(φ − φ_e) + Σ_k A_k·cos(k·φ + φ_k)

(the inner ring's frame turns with the ring, by the integral of ω; the outer ring's is
fixed), and a ball larger by ΔD has its groove-to-ball radius difference ``(f − ½)·D``
smaller by ΔD/2. An eccentric raceway is a circle whose centre is offset by e: at angle
φ its radius is ``e·cos(φ − φ_e) + √(R² − e² sin²(φ − φ_e))``, the radial shift above to
within ``e²/2R`` (2.6 nm for 30 µm on the study's raceway). The Hertz curvatures stay
nominal: a waviness of amplitude A and order k changes the raceway's curvature by
``A·k²/R²``, 1e-4 of the groove's for the orders and amplitudes of a tolerance class.

The groove is also moved along the axis, in that ring's frame, by

    Δz(φ) = a·cos(φ − φ_a) + Σ_k B_k·cos(k·φ + ψ_k)

(the axial runout: a groove whose plane is tilted to its ring's axis by a/r, r the
groove's radius, and higher axial harmonics). The groove's section is translated, not
turned with the tilt: a rigid tilt would also turn it by a/r, 1e-4 rad for 15 µm on the
study's raceway, which moves the contact angle by as much (0.006°). ISO 492's ``S_ia``
and ``S_ea`` are total indicator readings of the ring's face against its raceway over a
revolution: a tilted plane gives ``S = 2a`` (at the face's measuring radius, taken as
the groove's: on the study's inner ring the face's middle, 165 mm, is 6 % inside the
groove's 176 mm), so
a tolerance class sets ``a = S/2`` where ISO 492 tabulates S (classes 5 and 4; Normal
and 6 have none: 0 unless given).

A ball's own out-of-roundness (ISO 3290's ``V_Dws``) is not modelled: balls are spheres
of their mean diameter, which differ within the lot's ``V_DwL``.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..standards.iso492 import (DEFAULT_BALL_GRADE, TOLERANCE_CLASSES, ball_lot_variation,  # noqa: F401
                                default_ball_grade, inner_axial_runout, inner_runout, outer_axial_runout,
                                outer_runout)

#: Most waviness terms per raceway (the kernels' fixed layout, :mod:`rvcore.bearing.layout`).
MAX_WAVINESS_TERMS = 8


@dataclass(frozen=True)
class Waviness:
    """One harmonic of a raceway's waviness: the radius changes by
    ``amplitude·cos(order·φ + phase)`` at the ring angle φ.

    Parameters
    ----------
    order : int
        Lobes per circumference [-], ≥ 1 (order 1 is an eccentricity).
    amplitude : float
        [m]
    phase : float
        [rad]
    """

    order: int
    amplitude: float
    phase: float = 0.0


@dataclass(frozen=True)
class Imperfections:
    """A row's imperfections as the bearing file gives them.

    Parameters
    ----------
    inner_eccentricity, outer_eccentricity : float or None
        Offset of the raceway's centre from its ring's axis [m]; None (the default):
        from the tolerance class, 0 without one.
    inner_eccentricity_angle, outer_eccentricity_angle : float or None
        Direction of the offset (the high point) in the ring's frame [rad]; None: drawn
        from the case's seed where it has one, else 0.
    inner_waviness, outer_waviness : tuple of Waviness
    inner_axial_amplitude, outer_axial_amplitude : float or None
        Amplitude ``a`` of the raceway's axial runout, a groove whose plane is tilted to
        its ring's axis [m] (half the runout's total indicator reading, ISO 492's
        ``S_ia``/``S_ea``); None (the default): ``S/2`` from the tolerance class where ISO
        492 gives S (classes 5, 4), else 0.
    inner_axial_angle, outer_axial_angle : float or None
        Where the groove stands furthest along +z (the tilt's high point) in the ring's
        frame [rad]; None: drawn from the case's seed where it has one, else 0.
    inner_axial_waviness, outer_axial_waviness : tuple of Waviness or None
        Higher harmonics of the axial runout: the groove moves along the axis by
        ``amplitude·cos(order·φ + phase)``; None: none.
    ball_diameter_deviation : tuple of float
        One deviation from the nominal diameter per ball [m]; empty: drawn within the
        ball grade's lot variation from the case's seed (seed 0 without one), or none
        when no grade applies.
    ball_grade : str
        ISO 3290 grade (``"G10"``, …); "" for the tolerance class's default, or none.
    tolerance_class : str
        ISO 492 class (``"normal"``, ``"6"``, ``"5"``, ``"4"``) that sets the
        eccentricities ``e = K/2``, the axial amplitudes ``a = S/2`` (classes 5, 4) and a
        default ball grade; "" for none.

    Notes
    -----
    The axial fields default to None (not 0 or an empty tuple) so that a bearing without
    them hashes as before (:func:`pipeline.schema.caseids.plain` drops None).
    """

    inner_eccentricity: float | None = None
    inner_eccentricity_angle: float | None = None
    outer_eccentricity: float | None = None
    outer_eccentricity_angle: float | None = None
    inner_waviness: tuple[Waviness, ...] = ()
    outer_waviness: tuple[Waviness, ...] = ()
    ball_diameter_deviation: tuple = ()
    ball_grade: str = ""
    tolerance_class: str = ""
    inner_axial_amplitude: float | None = None
    inner_axial_angle: float | None = None
    outer_axial_amplitude: float | None = None
    outer_axial_angle: float | None = None
    inner_axial_waviness: tuple[Waviness, ...] | None = None
    outer_axial_waviness: tuple[Waviness, ...] | None = None

    def __post_init__(self):
        if self.tolerance_class not in ("",) + TOLERANCE_CLASSES:
            raise ValueError(f"tolerance class {self.tolerance_class!r} is not one of {', '.join(TOLERANCE_CLASSES)}")
        _check_terms(self)


def _check_terms(imp) -> None:
    """At most :data:`MAX_WAVINESS_TERMS` harmonics a raceway, radial and axial, each of order ≥ 1."""
    for name in ("inner_waviness", "outer_waviness", "inner_axial_waviness", "outer_axial_waviness"):
        terms = getattr(imp, name) or ()
        if len(terms) > MAX_WAVINESS_TERMS:
            raise ValueError(f"{name}: at most {MAX_WAVINESS_TERMS} terms, got {len(terms)}")
        if any(int(w.order) < 1 for w in terms):
            raise ValueError(f"{name}: every order must be at least 1")


#: The perfect row.
PERFECT = Imperfections()


@dataclass(frozen=True)
class RealizedImperfections:
    """The geometry one case runs with (:func:`realize`): every value explicit, SI."""

    inner_eccentricity: float = 0.0
    inner_eccentricity_angle: float = 0.0
    outer_eccentricity: float = 0.0
    outer_eccentricity_angle: float = 0.0
    inner_waviness: tuple = ()
    outer_waviness: tuple = ()
    ball_diameter_deviation: tuple = ()
    inner_axial_amplitude: float = 0.0
    inner_axial_angle: float = 0.0
    outer_axial_amplitude: float = 0.0
    outer_axial_angle: float = 0.0
    inner_axial_waviness: tuple = ()
    outer_axial_waviness: tuple = ()

    def __post_init__(self):
        _check_terms(self)

    @property
    def perfect(self) -> bool:
        return (self.inner_eccentricity == 0.0 and self.outer_eccentricity == 0.0 and not self.inner_waviness
                and not self.outer_waviness and not any(self.ball_diameter_deviation)
                and self.inner_axial_amplitude == 0.0 and self.outer_axial_amplitude == 0.0
                and not self.inner_axial_waviness and not self.outer_axial_waviness)


def _angle(given, rng) -> float:
    if given is not None:
        return float(given)
    return float(rng.uniform(0.0, 2.0 * math.pi)) if rng is not None else 0.0


def realize_row(imp: Imperfections, bore: float, outer_diameter: float, ball_count: int,
                seed: int = -1, row_index: int = 0, ball_diameter: float = 0.0) -> RealizedImperfections:
    """One row's imperfections for a case with ``seed`` (−1: none).

    Parameters
    ----------
    imp : Imperfections
    bore, outer_diameter : float
        The bearing's envelope, which ISO 492's runouts are tabulated over [m].
    ball_count : int
    seed : int
        The case's realization seed; ≥ 0 draws the high-point angles and (with a
        grade) the ball deviations from it.
    row_index : int
        Row of the bearing: each row draws from its own stream.
    ball_diameter : float
        ``D_w`` [m], for the class's default ball grade
        (:func:`rvcore.standards.iso492.default_ball_grade`); 0: the class's own grade.

    Returns
    -------
    RealizedImperfections

    Notes
    -----
    ISO 492's ``K_ia``/``K_ea`` is the total indicator reading of the runout, twice the
    raceway's eccentricity: ``e = K/2``; its ``S_ia``/``S_ea`` likewise twice a tilted
    groove's axial amplitude, ``a = S/2``, where the class has them
    (:func:`rvcore.standards.iso492.axial_runout_limits`; else 0). The high points are
    drawn in the order inner, outer eccentricity, inner, outer axial runout, so that
    adding the axial runout leaves the eccentricities' draws as they were. The balls'
    deviations are drawn uniformly within ``±V_DwL/2`` of the grade (their spread is then
    within ISO 3290's lot variation).
    """
    rng = np.random.default_rng([seed, row_index]) if seed >= 0 else None
    cls = imp.tolerance_class
    e_i = imp.inner_eccentricity if imp.inner_eccentricity is not None else (
        inner_runout(bore, cls) / 2 if cls else 0.0)
    e_o = imp.outer_eccentricity if imp.outer_eccentricity is not None else (
        outer_runout(outer_diameter, cls) / 2 if cls else 0.0)
    a_i = _angle(imp.inner_eccentricity_angle, rng)
    a_o = _angle(imp.outer_eccentricity_angle, rng)
    z_i = imp.inner_axial_amplitude if imp.inner_axial_amplitude is not None else (
        (inner_axial_runout(bore, cls) or 0.0) / 2 if cls else 0.0)
    z_o = imp.outer_axial_amplitude if imp.outer_axial_amplitude is not None else (
        (outer_axial_runout(outer_diameter, cls) or 0.0) / 2 if cls else 0.0)
    b_i = _angle(imp.inner_axial_angle, rng)
    b_o = _angle(imp.outer_axial_angle, rng)
    balls = tuple(float(d) for d in imp.ball_diameter_deviation)
    if balls and len(balls) != ball_count:
        raise ValueError(f"ball_diameter_deviation has {len(balls)} values for {ball_count} balls")
    grade = imp.ball_grade or (default_ball_grade(cls, ball_diameter) if cls else "")
    if not balls and grade:
        half = ball_lot_variation(grade) / 2
        draw = np.random.default_rng([max(seed, 0), row_index, 1])
        balls = tuple(float(x) for x in draw.uniform(-half, half, ball_count))
    return RealizedImperfections(e_i, a_i, e_o, a_o, tuple(imp.inner_waviness), tuple(imp.outer_waviness), balls,
                                 float(z_i), b_i, float(z_o), b_o, tuple(imp.inner_axial_waviness or ()),
                                 tuple(imp.outer_axial_waviness or ()))


def realize(bearing, seed: int = -1):
    """``bearing`` with every row's imperfections realized for a case with ``seed``
    (rows already realized are kept as they are)."""
    rows = tuple(dataclasses.replace(row, imperfections=realize_row(
        row.imperfections, bearing.bore, bearing.outer_diameter, row.ball_count, seed, r, row.ball_diameter))
        if isinstance(row.imperfections, Imperfections) else row for r, row in enumerate(bearing.rows))
    return dataclasses.replace(bearing, rows=rows)
