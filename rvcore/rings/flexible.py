"""A bearing's rings as the statics see them: each rigid (the default) or flexible in its
support, by its radial and axial Fourier modes; the displacement of each ring's raceway
at every ball under the balls' contact forces. Pure functions, SI.

Notes
-----
The balls' forces on a ring, resolved at each ball's azimuth ``ψ_j`` into a radial part
``F_r,j`` (outward positive) and an axial part ``F_z,j``, load the ring's radial and axial
modes (:mod:`rvcore.rings.deflection`); the raceway's groove at ball ``j`` then stands
displaced by ``w(ψ_j)`` radially and ``u(ψ_j)`` axially from where the rigid ring would
hold it, relative to the ring's support. Both are read on the ring's centroid circle: the
section's rotation (the in-plane modes' ``∂w/∂θ``-related turn, the out-of-plane twist)
times the few millimetres between the centroid and the raceway is neglected, as is the
offset of the contact point from the centroid when the loads are applied.

A flexible ring needs a support (:mod:`rvcore.rings.support`): with none, its rigid
orders (``k = 1`` in plane, ``k = 0, 1`` out of plane) would have no stiffness, and the
statics' pose, which is the support's, would not hold it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bearing.geometry import INNER, OUTER, Bearing, Material, RingSupport
from .deflection import modal_displacement, static_amplitudes, static_deflection
from .modes import DEFAULT_DAMPING_RATIO, RingModes
from .section import RingSection, given_section, ring_section
from .support import Foundation, HousingRing, OrderStiffness, supported_ring_modes

__all__ = ["FlexibleRings", "RIGID_RINGS", "bearing_rings", "flexible_rings", "flexible_ring", "ring_support",
           "DEFORMATION_POINTS"]

#: Points round a ring at which its largest deformation is read (every half degree) [-].
DEFORMATION_POINTS = 720


@dataclass(frozen=True)
class FlexibleRings:
    """The modes of each flexible ring; ``None`` where a ring (or a direction) is rigid.

    Parameters
    ----------
    inner_radial, inner_axial, outer_radial, outer_axial : rvcore.rings.modes.RingModes or None
        Each ring's radial (in plane) and axial (out of plane) modes, its support included.
    """

    inner_radial: RingModes | None = None
    inner_axial: RingModes | None = None
    outer_radial: RingModes | None = None
    outer_axial: RingModes | None = None

    def __post_init__(self):
        for name in ("inner_radial", "inner_axial", "outer_radial", "outer_axial"):
            modes = getattr(self, name)
            if modes is None:
                continue
            if modes.direction != name.split("_")[1]:
                raise ValueError(f"flexible rings: {name} holds {modes.direction} modes")
            if np.any(modes.stiffness <= 0.0):
                k = int(modes.orders[np.argmax(modes.stiffness <= 0.0)])
                raise ValueError(f"flexible rings: {name} order k = {k} has no stiffness; a flexible ring needs a "
                                 "support that holds its rigid-body orders")

    @property
    def rigid(self) -> bool:
        """True when every ring is rigid in every direction."""
        return all(getattr(self, n) is None for n in ("inner_radial", "inner_axial", "outer_radial", "outer_axial"))

    def raceway_displacements(self, ring: int, radial_forces, axial_forces, angles):
        """Radial and axial displacement of one ring's raceway at the loads' own angles.

        Parameters
        ----------
        ring : int
            :data:`rvcore.bearing.geometry.INNER` or :data:`~rvcore.bearing.geometry.OUTER`.
        radial_forces, axial_forces : array_like
            The balls' forces on the ring at each ball [N], outward and towards +z positive.
        angles : array_like
            The balls' azimuths ``ψ_j`` [rad].

        Returns
        -------
        w, u : ndarray
            Radial (outward) and axial displacement at each ball [m]; 0 where rigid.
        """
        psi = np.asarray(angles, dtype=float)
        radial, axial = ((self.inner_radial, self.inner_axial) if ring == INNER
                         else (self.outer_radial, self.outer_axial))
        w = np.zeros_like(psi) if radial is None else static_deflection(radial, radial_forces, psi, psi)
        u = np.zeros_like(psi) if axial is None else static_deflection(axial, axial_forces, psi, psi)
        return w, u

    def deformation(self, ring: int, radial_forces, axial_forces, angles) -> dict:
        """One ring's deformation under the balls' forces: its ovalisation and its largest
        radial and axial displacement round the ring.

        Parameters
        ----------
        ring : int
            :data:`rvcore.bearing.geometry.INNER` or :data:`~rvcore.bearing.geometry.OUTER`.
        radial_forces, axial_forces : array_like
            The balls' forces on the ring [N], outward and towards +z positive.
        angles : array_like
            The balls' azimuths [rad].

        Returns
        -------
        dict
            ``ovalisation`` [m]: the amplitude ``√(a_2c² + a_2s²)`` of the radial order
            ``k = 2`` (the diameter changes by twice it, up along one axis and down across);
            ``max_radial``, ``max_axial`` [m]: the largest ``|w(θ)|`` and ``|u(θ)|`` over
            :data:`DEFORMATION_POINTS` angles, relative to the support; NaN where the ring
            (direction) is rigid.

        Notes
        -----
        The amplitudes are :func:`rvcore.rings.deflection.static_amplitudes`'
        ``a_k = Q_k/K_k``; the displacement their Fourier sum (module Notes).
        """
        radial, axial = ((self.inner_radial, self.inner_axial) if ring == INNER
                         else (self.outer_radial, self.outer_axial))
        theta = np.linspace(0.0, 2.0 * np.pi, DEFORMATION_POINTS, endpoint=False)
        out = dict.fromkeys(("ovalisation", "max_radial", "max_axial"), float("nan"))
        if radial is not None:
            ac, as_ = static_amplitudes(radial, radial_forces, angles)
            out["ovalisation"] = float(np.hypot(ac[2], as_[2])) if radial.orders.size > 2 else 0.0
            out["max_radial"] = float(np.abs(modal_displacement(radial, ac, as_, theta)).max())
        if axial is not None:
            ac, as_ = static_amplitudes(axial, axial_forces, angles)
            out["max_axial"] = float(np.abs(modal_displacement(axial, ac, as_, theta)).max())
        return out


#: Every ring rigid: today's model.
RIGID_RINGS = FlexibleRings()


def flexible_ring(section: RingSection, material: Material, support, max_order: int, *,
                  damping_ratio: float = DEFAULT_DAMPING_RATIO):
    """The radial and axial modes of one ring in its support.

    Parameters
    ----------
    section : rvcore.rings.section.RingSection
    material : rvcore.bearing.geometry.Material
    support : rvcore.rings.support.Foundation, HousingRing or OrderStiffness
    max_order : int
        Highest Fourier order kept [-].
    damping_ratio : float
        ``ζ`` [-].

    Returns
    -------
    radial, axial : rvcore.rings.modes.RingModes
    """
    if support is None:
        raise ValueError("flexible ring: a flexible ring needs a support (a Foundation, a HousingRing or an "
                         "OrderStiffness)")
    return tuple(supported_ring_modes(section, material, max_order, d, support, damping_ratio=damping_ratio)
                 for d in ("radial", "axial"))


def flexible_rings(bearing: Bearing, inner=None, outer=None, *, max_order: int = 60,
                   outer_shoulder_diameter: float | None = None,
                   damping_ratio: float = DEFAULT_DAMPING_RATIO) -> FlexibleRings:
    """A bearing's rings, each rigid (``None``) or flexible in the support given.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    inner, outer : rvcore.rings.support.Foundation or rvcore.rings.support.HousingRing, optional
        Each ring's support; ``None`` keeps that ring rigid.
    max_order : int
        Highest Fourier order kept [-] (the deflection's error falls as ``max_order⁻³``).
    outer_shoulder_diameter : float, optional
        The outer ring's bore at its shoulders [m], needed for a flexible outer ring's section.
    damping_ratio : float
        ``ζ`` [-].
    """
    out = {}
    if inner is not None:
        sec = ring_section(bearing, INNER)
        out["inner_radial"], out["inner_axial"] = flexible_ring(sec, bearing.ring_material, inner, max_order,
                                                                damping_ratio=damping_ratio)
    if outer is not None:
        sec = ring_section(bearing, OUTER, other_diameter=outer_shoulder_diameter)
        out["outer_radial"], out["outer_axial"] = flexible_ring(sec, bearing.ring_material, outer, max_order,
                                                                damping_ratio=damping_ratio)
    return FlexibleRings(**out)


def ring_support(spec: RingSupport, ring_material: Material):
    """The support object a :class:`rvcore.bearing.geometry.RingSupport` describes.

    Parameters
    ----------
    spec : rvcore.bearing.geometry.RingSupport
    ring_material : rvcore.bearing.geometry.Material
        The bearing ring's material (the housing's when the spec names none).

    Returns
    -------
    Foundation or HousingRing or OrderStiffness
    """
    seat = Foundation(spec.seat_radial, spec.seat_axial)
    if spec.kind == "foundation":
        return seat
    if spec.kind == "housing":
        material = spec.housing_material if spec.housing_material is not None else ring_material
        return HousingRing(given_section(*spec.housing_section), material, seat,
                           Foundation(spec.ground_radial, spec.ground_axial))
    return OrderStiffness(tuple(spec.orders), tuple(spec.radial_stiffness), tuple(spec.axial_stiffness))


def _spec_section(bearing: Bearing, ring: int, spec: RingSupport) -> RingSection:
    """The ring's own section: given, or from the envelope and grooves."""
    if spec.section:
        return given_section(*spec.section)
    return ring_section(bearing, ring, other_diameter=spec.shoulder_diameter or None)


def bearing_rings(bearing: Bearing, *, max_order: int | None = None) -> FlexibleRings:
    """A bearing's rings as its ``inner_ring_support`` and ``outer_ring_support`` describe
    them (:class:`rvcore.bearing.geometry.RingSupport`; None: rigid).

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    max_order : int, optional
        Highest Fourier order kept [-], for both rings; by default each ring's own
        (``RingSupport.max_order``).

    Returns
    -------
    FlexibleRings
        :data:`RIGID_RINGS` when both rings are rigid.
    """
    out = {}
    for ring, name, spec in ((INNER, "inner", bearing.inner_ring_support),
                             (OUTER, "outer", bearing.outer_ring_support)):
        if spec is None:
            continue
        order = spec.max_order if max_order is None else int(max_order)
        out[f"{name}_radial"], out[f"{name}_axial"] = flexible_ring(
            _spec_section(bearing, ring, spec), bearing.ring_material, ring_support(spec, bearing.ring_material),
            order, damping_ratio=spec.damping_ratio)
    return FlexibleRings(**out) if out else RIGID_RINGS
