"""What holds a bearing ring: an elastic foundation (a seat of given radial and axial
stiffness per unit circumference), or a second, thicker ring (a housing or a carrier)
holding it through such a seat; the ring's modes with their support. Pure functions, SI.

Notes
-----
**Elastic foundation** (Winkler; Hetényi ch. 1; Soedel §5.6): a seat of radial stiffness
``k_r`` and axial stiffness ``k_a`` per unit circumference [N m⁻²] stores
``½∫k_r·w²·R dθ`` and ``½∫k_a·u²·R dθ``, which add to mode ``k``'s stiffness::

    K_k^seat = π·k·R    (k ≥ 1)          K_0^seat = 2π·k·R

with ``k = k_r`` for the radial modes and ``k_a`` for the axial ones, at the ring's
centroid radius ``R`` (a thin ring: the seat's own radius differs by half the ring's
thickness, neglected). The foundation is radial and axial only: it does not resist the
in-plane modes' tangential motion nor the section's twist.

**A housing (or carrier) ring** of its own section and material, centroid radius ``R_h``,
holds the bearing ring through a seat (``seat``, the fit's contact stiffness; infinite =
bonded) and is itself held by a foundation (``ground``, what holds the housing; zero =
free). Both rings move in the same Fourier order ``k`` (the problem is axisymmetric), the
housing condensed statically (its inertia neglected), so per order the seat and the
housing act **in series** and the result **in parallel** with the bearing ring's own
stiffness::

    K_k^support = 1 / (1/K_k^seat + 1/(K_k^housing + K_k^ground))
    K_k = K_k^ring + K_k^support

``K_k^housing`` is :mod:`rvcore.rings.modes`' free-ring stiffness of the housing's section at
``R_h`` (its ``k = 0`` always extensional), the radial displacement taken equal through
the housing's thickness and the axial one at its centroid (the housing's twist times the
radial offset of the seat neglected). ``K_k^ground`` is the ground's foundation at ``R_h``.
A rigid seat on a free housing therefore gives ``K_k = K_k^ring + K_k^housing``: the two rings
bending together.

**A support reduced from an FE model** (:class:`OrderStiffness`): the housing's or carrier's
stiffness per Fourier order as the FE model gives it, read at the bearing ring's seat.
Order ``k``'s radial (axial) stiffness is the generalized force ``Q_k = ∫q(θ)·cos kθ·R dθ``
of the line load ``q(θ)`` [N m⁻¹] that holds the seat displaced by ``a·cos kθ`` radially
(axially), over ``a`` [N m⁻¹] (a modal compliance ``c_k`` gives ``K_k = 1/c_k``). For a
distributed seat load ``q = q_0·cos kθ``: ``K_k = π·R·q_0/a`` (``k ≥ 1``) and ``2π·R·q_0/a``
(``k = 0``); a Winkler foundation of ``k_r`` is then ``K_k = π·k_r·R`` (``2π·k_r·R`` at 0),
as above. The FE model's seat is taken as the ring's centroid circle (the thin ring).
The per-order stiffness adds to the ring's own like the foundation's (a condensed,
massless support: Craig–Bampton without its interior modes).

The support's stiffness is relative to what holds it: the ring's rigid translations and
tilts (``k = 0, 1``) then have the support's stiffness, and its displacements are those
relative to the support (the statics' pose is the support's). A free ring (no support)
has them rigid (stiffness 0).

References
----------
M. Hetényi, *Beams on Elastic Foundation*, University of Michigan Press 1946, ch. 1 and
§ on rings.
W. Soedel, *Vibrations of Shells and Plates*, 3rd ed., Marcel Dekker 2004, ch. 5.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bearing.geometry import Material
from .modes import (DEFAULT_DAMPING_RATIO, RingModes, free_ring_modes)
from .section import RingSection

__all__ = ["Foundation", "HousingRing", "OrderStiffness", "RIGID_SEAT", "support_stiffness", "supported_ring_modes"]


@dataclass(frozen=True)
class Foundation:
    """An elastic foundation: stiffness per unit circumference.

    Parameters
    ----------
    radial : float
        ``k_r`` [N m⁻²], ≥ 0 (``inf``: rigid).
    axial : float
        ``k_a`` [N m⁻²], ≥ 0 (``inf``: rigid).
    """

    radial: float = 0.0
    axial: float = 0.0

    def __post_init__(self):
        for name in ("radial", "axial"):
            value = getattr(self, name)
            if math.isnan(value) or value < 0.0:
                raise ValueError(f"foundation: {name} stiffness must be >= 0 N/m^2, got {value!r}")

    def stiffness(self, orders, direction, radius):
        """``K_k^seat`` per order [N m⁻¹] (module Notes).

        Parameters
        ----------
        orders : array_like of int
            ``k`` [-].
        direction : {"radial", "axial"}
        radius : float
            ``R`` [m].
        """
        k = np.asarray(orders, dtype=float)
        value = self.radial if direction == "radial" else self.axial
        if value == 0.0:
            return np.zeros_like(k)
        return np.where(k == 0, 2.0, 1.0) * math.pi * value * float(radius)


#: A bonded seat: the bearing ring and its housing move together.
RIGID_SEAT = Foundation(math.inf, math.inf)


@dataclass(frozen=True)
class HousingRing:
    """A second, thicker ring holding the bearing ring (module Notes).

    Parameters
    ----------
    section : rvcore.rings.section.RingSection
        The housing's (or carrier's) section; its centroid radius is ``R_h``.
    material : rvcore.bearing.geometry.Material
    seat : Foundation
        The fit between the bearing ring and the housing, per unit circumference of the
        bearing ring [N m⁻²]; rigid (bonded) by default.
    ground : Foundation
        What holds the housing, per unit circumference of the housing [N m⁻²]; free by
        default.
    """

    section: RingSection
    material: Material
    seat: Foundation = RIGID_SEAT
    ground: Foundation = Foundation()


@dataclass(frozen=True)
class OrderStiffness:
    """A support's stiffness per Fourier order, as reduced from an FE model (module Notes).

    Parameters
    ----------
    orders : array_like of int
        ``k = 0, 1, …, N``, every order once, in order [-].
    radial, axial : array_like
        ``K_k^support`` per unit radial and axial modal amplitude [N m⁻¹], ≥ 0 (``inf``: held).
    """

    orders: tuple
    radial: tuple
    axial: tuple

    def __post_init__(self):
        k = np.asarray(self.orders)
        if k.ndim != 1 or k.size == 0 or not np.array_equal(k, np.arange(k.size)):
            raise ValueError(f"order stiffness: the orders must run 0, 1, …, N once each, got {self.orders!r}")
        for name in ("radial", "axial"):
            v = np.asarray(getattr(self, name), dtype=float)
            if v.shape != k.shape or np.any(np.isnan(v)) or np.any(v < 0.0):
                raise ValueError(f"order stiffness: {name} needs one value >= 0 N/m per order, got "
                                 f"{getattr(self, name)!r}")

    @property
    def max_order(self) -> int:
        """``N``, the highest order given [-]."""
        return len(self.orders) - 1

    def stiffness(self, orders, direction, radius=None):
        """``K_k^support`` per order [N m⁻¹].

        Parameters
        ----------
        orders : array_like of int
            ``k`` [-], at most :attr:`max_order`.
        direction : {"radial", "axial"}
        radius : float, optional
            Unused: the table is already at the ring's seat [m].
        """
        k = np.asarray(orders, dtype=int)
        if k.size and int(k.max()) > self.max_order:
            raise ValueError(f"order stiffness: order {int(k.max())} asked for, the table gives orders up to "
                             f"{self.max_order}")
        table = np.asarray(self.radial if direction == "radial" else self.axial, dtype=float)
        return table[k]


def _series(a, b):
    """``1/(1/a + 1/b)`` elementwise, with 0 and ``inf`` as limits."""
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    out = np.zeros_like(a)
    inf_a, inf_b = np.isinf(a), np.isinf(b)
    out[inf_a] = b[inf_a]
    out[inf_b & ~inf_a] = a[inf_b & ~inf_a]
    finite = ~inf_a & ~inf_b & (a + b > 0.0)
    out[finite] = a[finite] * b[finite] / (a[finite] + b[finite])
    return out


def support_stiffness(support, orders, direction, radius):
    """The support's stiffness per order ``k`` at the bearing ring [N m⁻¹] (module Notes).

    Parameters
    ----------
    support : Foundation or HousingRing or OrderStiffness or None
        ``None``: a free ring (0).
    orders : array_like of int
        ``k`` [-].
    direction : {"radial", "axial"}
    radius : float
        The bearing ring's centroid radius ``R`` [m].
    """
    k = np.asarray(orders, dtype=int)
    if support is None:
        return np.zeros(k.shape)
    if isinstance(support, (Foundation, OrderStiffness)):
        return support.stiffness(k, direction, radius)
    if isinstance(support, HousingRing):
        housing = free_ring_modes(support.section, support.material, int(k.max(initial=0)), direction)
        own = housing.stiffness[k] + support.ground.stiffness(k, direction, support.section.centroid_radius)
        return _series(support.seat.stiffness(k, direction, radius), own)
    raise TypeError(f"support {support!r} is not a Foundation, a HousingRing, an OrderStiffness or None")


def supported_ring_modes(section: RingSection, material: Material, max_order: int, direction: str = "radial",
                         support=None, *, extension: bool = True,
                         damping_ratio: float = DEFAULT_DAMPING_RATIO) -> RingModes:
    """A ring's modes of orders ``0 … max_order`` with its support's stiffness added.

    Parameters
    ----------
    section : rvcore.rings.section.RingSection
    material : rvcore.bearing.geometry.Material
    max_order : int
        Highest order ``k`` kept [-].
    direction : {"radial", "axial"}
    support : Foundation or HousingRing or OrderStiffness or None
    extension : bool
        In plane: the ring's ``k = 0`` extensional (True) or inextensible.
    damping_ratio : float
        ``ζ`` [-].

    Returns
    -------
    rvcore.rings.modes.RingModes
    """
    free = free_ring_modes(section, material, max_order, direction, extension=extension,
                           damping_ratio=damping_ratio)
    added = support_stiffness(support, free.orders, direction, section.centroid_radius)
    return RingModes(direction, free.orders, free.stiffness + added, free.mass, free.radius, free.damping_ratio)
