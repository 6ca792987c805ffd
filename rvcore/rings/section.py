"""A bearing ring's cross-section: area, centroid, second moments and torsion constant,
from the ring's envelope and groove or given. Pure functions, SI in and out.

Notes
-----
The section lies in the meridian plane (radial ``r``, axial ``z``). Built from the
envelope, it is the rectangle ``r_in ≤ r ≤ r_out``, ``|z − z_0| ≤ b/2`` less one circular
segment per groove: the part of the groove's circle (radius ``a = f·D``, centre
``(r_c, z_c)``) that lies inside the rectangle, cut off by the raceway's cylinder
(``r = r_out`` for an inner ring, ``r = r_in`` for an outer ring). With ``d`` the distance
from the circle's centre to that cylinder, measured towards the ring's material, and the
segment's half angle ``φ = arccos(d/a)``, the segment's properties about the circle's centre
(``x`` across the chord, ``y`` along it) are, by direct integration::

    A_s  = a²·(φ − sin φ·cos φ)
    ∫x dA  = ⅔·a³·sin³φ
    ∫x² dA = a⁴/4·(φ − sin 4φ / 4)
    ∫y² dA = ⅔·a⁴·(3φ/8 − sin 2φ / 4 + sin 4φ / 32)

(each gives the full disc's ``πa²``, ``0``, ``πa⁴/4``, ``πa⁴/4`` at ``φ = π``). The
section's area, centroid and central second moments follow by superposition (parallel
axes). ``I_in`` = ∫(r − r̄)² dA is the second moment for bending in the ring's own plane
(radial displacement), ``I_out`` = ∫(z − z̄)² dA for bending out of it (axial
displacement); ``I_rz`` = ∫(r − r̄)(z − z̄) dA, non-zero for an asymmetric (angular-contact)
groove, is reported but the thin-ring modes (:mod:`rvcore.rings.modes`) take the section's
axes as principal and neglect it.

Torsion constant (an approximation, stated): the section's rectangle of the same width
``b`` and the same area (thickness ``t = A/b``), by Roark's formula for a solid rectangle
(``b ≥ t``; the two sides swap otherwise)::

    J ≈ b·t³·(1/3 − 0.21·(t/b)·(1 − t⁴/(12·b⁴)))

within about 0.2 % of Saint-Venant's series for any aspect ratio of a rectangle; the groove's
shape (a notch at the surface) is otherwise ignored.

Approximations: a groove is one circular arc (a four-point groove's two arcs are taken as
the first arc's circle); the groove must not cut the ring's side faces nor its far
cylinder; fillets and chamfers are ignored.

References
----------
W. C. Young, R. G. Budynas, *Roark's Formulas for Stress and Strain*, 7th ed., Table 10.7
(torsion of a solid rectangle) and Appendix A (properties of a circular segment).
S. P. Timoshenko, J. N. Goodier, *Theory of Elasticity*, 3rd ed., §109 (Saint-Venant's
torsion of a rectangle, the exact series).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..bearing.geometry import INNER, OUTER, Bearing, arc_geometry

__all__ = ["Groove", "RingSection", "given_section", "groove_segment", "ring_section",
           "section_from_envelope", "rectangle_torsion_constant"]


@dataclass(frozen=True)
class RingSection:
    """A ring's cross-section.

    Parameters
    ----------
    area : float
        ``A`` [m²].
    centroid_radius : float
        ``R``, radius of the section's centroid: the thin ring's radius [m].
    centroid_axial : float
        Axial coordinate of the centroid [m].
    i_in_plane : float
        ``I_in = ∫(r − R)² dA`` [m⁴]: bending in the ring's plane (radial displacement).
    i_out_of_plane : float
        ``I_out = ∫(z − z̄)² dA`` [m⁴]: bending out of its plane (axial displacement).
    torsion_constant : float
        Saint-Venant's ``J`` [m⁴].
    i_product : float
        ``∫(r − R)(z − z̄) dA`` [m⁴], neglected by the thin-ring modes.
    """

    area: float
    centroid_radius: float
    centroid_axial: float
    i_in_plane: float
    i_out_of_plane: float
    torsion_constant: float
    i_product: float = 0.0

    def __post_init__(self):
        for name in ("area", "centroid_radius", "i_in_plane", "i_out_of_plane", "torsion_constant"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"ring section: {name} must be a finite number > 0, got {value!r}")


@dataclass(frozen=True)
class Groove:
    """One raceway groove as its circle in the meridian plane.

    Parameters
    ----------
    centre_radius : float
        ``r_c``, radius of the circle's centre from the bearing axis [m].
    centre_axial : float
        ``z_c``, its axial coordinate [m].
    radius : float
        ``a = f·D`` [m].
    """

    centre_radius: float
    centre_axial: float
    radius: float


def given_section(area, centroid_radius, i_in_plane, i_out_of_plane, torsion_constant,
                  centroid_axial=0.0) -> RingSection:
    """A section given by its properties (a drawing, an FE model's beam section).

    Parameters
    ----------
    area : float
        [m²]
    centroid_radius : float
        [m]
    i_in_plane, i_out_of_plane : float
        [m⁴]
    torsion_constant : float
        [m⁴]
    centroid_axial : float
        [m]
    """
    return RingSection(float(area), float(centroid_radius), float(centroid_axial), float(i_in_plane),
                       float(i_out_of_plane), float(torsion_constant))


def rectangle_torsion_constant(b, t):
    """Saint-Venant's torsion constant of a solid ``b × t`` rectangle, Roark's formula [m⁴].

    Parameters
    ----------
    b, t : float
        The two sides [m] (either order).

    Notes
    -----
    ``J ≈ b·t³·(1/3 − 0.21·(t/b)·(1 − t⁴/(12·b⁴)))`` with ``b ≥ t`` (Roark, Table 10.7).
    """
    b, t = max(b, t), min(b, t)
    return b * t ** 3 * (1.0 / 3.0 - 0.21 * (t / b) * (1.0 - t ** 4 / (12.0 * b ** 4)))


def groove_segment(radius, depth_to_chord):
    """Area and moments of a circular segment about its circle's centre (module Notes).

    Parameters
    ----------
    radius : float
        ``a`` [m].
    depth_to_chord : float
        ``d``: distance from the centre to the chord, positive when the centre lies on the
        far side of the chord from the segment [m]; ``−a < d < a``.

    Returns
    -------
    area, first_x, second_x, second_y : float
        ``A_s`` [m²], ``∫x dA`` [m³], ``∫x² dA`` and ``∫y² dA`` [m⁴], ``x`` from the centre
        across the chord towards the segment, ``y`` along the chord.
    """
    a, d = float(radius), float(depth_to_chord)
    if not -a < d < a:
        raise ValueError(f"a groove of radius {a:.6g} m does not cut the raceway's surface (centre {d:.6g} m "
                         "from it)")
    phi = math.acos(d / a)
    area = a * a * (phi - math.sin(phi) * math.cos(phi))
    first = 2.0 / 3.0 * a ** 3 * math.sin(phi) ** 3
    second_x = a ** 4 / 4.0 * (phi - math.sin(4.0 * phi) / 4.0)
    second_y = 2.0 / 3.0 * a ** 4 * (3.0 * phi / 8.0 - math.sin(2.0 * phi) / 4.0 + math.sin(4.0 * phi) / 32.0)
    return area, first, second_x, second_y


def section_from_envelope(inner_radius, outer_radius, width, grooves=(), raceway="outer",
                          axial_centre=0.0) -> RingSection:
    """The section of a rectangular ring less its grooves (module Notes).

    Parameters
    ----------
    inner_radius, outer_radius : float
        The ring's bore and outside radii [m].
    width : float
        Axial width ``b`` [m].
    grooves : sequence of Groove
        The raceway grooves cut into the ring.
    raceway : {"outer", "inner"}
        Which cylinder the grooves are cut into: ``"outer"`` for an inner ring (its
        raceway faces outward), ``"inner"`` for an outer ring.
    axial_centre : float
        Axial coordinate of the rectangle's mid-plane [m].

    Returns
    -------
    RingSection
    """
    ri, ro, b, z0 = float(inner_radius), float(outer_radius), float(width), float(axial_centre)
    if not (0.0 < ri < ro and b > 0.0):
        raise ValueError(f"ring section: needs 0 < inner radius < outer radius and width > 0, got "
                         f"{ri!r}, {ro!r}, {b!r} m")
    if raceway not in ("outer", "inner"):
        raise ValueError(f"ring section: raceway {raceway!r} is not 'outer' or 'inner'")
    # moments about the rectangle's centre (r_m, z0): A, ∫ρ, ∫ζ, ∫ρ², ∫ζ², ∫ρζ
    rm = 0.5 * (ri + ro)
    t = ro - ri
    area, s_r, s_z = b * t, 0.0, 0.0
    ss_r, ss_z, ss_rz = b * t ** 3 / 12.0, t * b ** 3 / 12.0, 0.0
    for g in grooves:
        a = float(g.radius)
        # x runs from the circle's centre into the ring's material, across the raceway cylinder
        if raceway == "outer":
            d, sign = g.centre_radius - ro, -1.0
        else:
            d, sign = ri - g.centre_radius, 1.0
        sa, sx, sxx, syy = groove_segment(a, d)
        half_chord = math.sqrt(a * a - d * d)
        dz = g.centre_axial - z0
        if abs(dz) + half_chord > b / 2.0 or a - d > t:
            raise ValueError(f"ring section: a groove (radius {a * 1e3:.4g} mm at r = {g.centre_radius * 1e3:.6g} mm, "
                             f"z = {g.centre_axial * 1e3:.4g} mm) cuts the ring's side face or far cylinder")
        dr = g.centre_radius - rm
        # the segment in the rectangle's coordinates: ρ = dr + sign·x, ζ = dz + y
        area -= sa
        s_r -= dr * sa + sign * sx
        s_z -= dz * sa
        ss_r -= dr * dr * sa + 2.0 * dr * sign * sx + sxx
        ss_z -= dz * dz * sa + syy
        ss_rz -= dz * (dr * sa + sign * sx)
    if area <= 0.0:
        raise ValueError("ring section: the grooves leave no material")
    cr, cz = s_r / area, s_z / area
    i_in = ss_r - area * cr * cr
    i_out = ss_z - area * cz * cz
    i_rz = ss_rz - area * cr * cz
    return RingSection(area, rm + cr, z0 + cz, i_in, i_out, rectangle_torsion_constant(b, area / b), i_rz)


def ring_section(bearing: Bearing, ring: int, *, other_diameter: float | None = None) -> RingSection:
    """The section of one of a bearing's rings, its grooves those of its rows.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    ring : int
        :data:`rvcore.bearing.geometry.INNER` or :data:`~rvcore.bearing.geometry.OUTER`.
    other_diameter : float, optional
        The raceway side's diameter [m]: by default the inner ring's shoulder diameter
        (``inner_ring.shoulder_diameter``); an outer ring's shoulder (bore) diameter has no
        key in the bearing file and must be given.

    Notes
    -----
    Each row's groove is the circle of its first arc on that ring
    (:func:`rvcore.bearing.geometry.arc_geometry`), at the row's axial position; the ring's
    rectangle spans the bearing's width, centred on ``z = 0``.
    """
    if ring == INNER:
        ri = bearing.bore / 2.0
        ro = (bearing.inner_ring.shoulder_diameter if other_diameter is None else other_diameter) / 2.0
        raceway = "outer"
    elif ring == OUTER:
        if other_diameter is None:
            raise ValueError("ring section: the outer ring's shoulder diameter must be given (other_diameter)")
        ri, ro, raceway = other_diameter / 2.0, bearing.outer_diameter / 2.0, "inner"
    else:
        raise ValueError(f"ring {ring!r} is not INNER or OUTER")
    grooves = []
    for row in bearing.rows:
        arcs = row.inner_arcs if ring == INNER else row.outer_arcs
        cr, cz, _, _ = arc_geometry(row, arcs[0], ring)
        grooves.append(Groove(cr, row.axial_position + cz, arcs[0].curvature_ratio * row.ball_diameter))
    return section_from_envelope(ri, ro, bearing.width, grooves, raceway)
