"""Thin-ring Fourier modes of a bearing ring: in-plane (radial) bending and out-of-plane
(axial) bending with twist, their modal masses and stiffnesses per order ``k``, and the
modal set a ring's statics and dynamics read. Pure functions, SI in and out.

Notes
-----
A thin circular ring of centroid radius ``R``, section ``A``, second moments ``I_in``
(bending in its plane) and ``I_out`` (out of it), torsion constant ``J``, of a material
``E``, ``G = E/(2(1 + ν))``, ``ρ``; ``θ`` the angle round the ring.

**In plane, inextensional** (Hoppe 1871; Love §§ 287–289; Soedel §5.4): the radial
displacement ``w`` (outward) and the tangential ``v`` of mode ``k ≥ 1`` are
``w = a·cos kθ``, ``v = −(a/k)·sin kθ`` (the centre line does not stretch,
``w + ∂v/∂θ = 0``), and the change of curvature is ``(w + ∂²w/∂θ²)/R²``. Its strain and
kinetic energies give, per unit radial amplitude ``a``::

    K_k = π·E·I_in·(k² − 1)² / R³          M_k = π·ρ·A·R·(k² + 1) / k²
    ω_k² = K_k/M_k = E·I_in·k²·(k² − 1)² / (ρ·A·R⁴·(k² + 1))

``k = 1`` is the rigid translation (``K_1 = 0``, ``M_1 = 2πρAR``, the ring's mass). ``k = 0``
is the uniform expansion, which stretches the centre line: ``K_0 = 2π·E·A/R + 2π·E·I_in/R³``,
``M_0 = 2π·ρ·A·R`` (breathing, ``ω_0² ≈ E/(ρR²)``). Inextensional theory leaves ``k = 0``
out (an inextensible ring does not breathe): ``extension=False`` gives it an infinite
stiffness, zero displacement. The extension of the ``k ≥ 2`` modes is neglected (the thin
ring's assumption, ``t ≪ R``).

**Out of plane, bending with twist** (Love §§ 290–291; Timoshenko, *Vibration problems*,
§ on a ring's out-of-plane vibration; Soedel §5.5): with ``u`` the axial displacement and
``β`` the rotation of the section about the ring's tangent, the bending curvature and the
twist are ``κ = (β − u''/R)/R`` and ``τ = (β' + u'/R)/R`` (``'`` = ∂/∂θ; a rigid tilt gives
neither). For ``u = a·cos kθ``, ``β = b·cos kθ`` the twist amplitude that no torque drives
minimises the strain energy, ``b = −(a/R)·k²·(EI_out + GJ)/(EI_out + k²·GJ)``, and what is
left is, per unit axial amplitude::

    K_k = π·E·I_out·k²·(k² − 1)² / (R³·(k² + E·I_out/(G·J)))      M_k = π·ρ·A·R
    ω_k² = E·I_out·k²·(k² − 1)² / (ρ·A·R⁴·(k² + E·I_out/(G·J)))

(the section's rotary inertia neglected; for a circular wire ``E·I/(G·J) = 1 + ν``, Love's
form). ``k = 0`` (axial translation, ``M_0 = 2πρAR``) and ``k = 1`` (the two tilts) are rigid.

Each order ``k ≥ 1`` has two modes, ``cos kθ`` and ``sin kθ``, of the same mass and
stiffness; ``k = 0`` has one. A ring's support (:mod:`rvcore.rings.support`) adds its
stiffness to each order's. Modal damping: ``c_k = 2·ζ·√(K_k·M_k)``, ``ζ`` the modal damping
ratio (default :data:`DEFAULT_DAMPING_RATIO`, an assumption).

References
----------
A. E. H. Love, *A Treatise on the Mathematical Theory of Elasticity*, 4th ed., Cambridge
1927, §§ 287–291.
R. Hoppe, "Vibrationen eines Ringes in seiner Ebene", *J. reine angew. Math.* 73, 1871.
W. Soedel, *Vibrations of Shells and Plates*, 3rd ed., Marcel Dekker 2004, ch. 5 (rings).
S. Timoshenko, D. H. Young, W. Weaver, *Vibration Problems in Engineering*, 4th ed.,
Wiley 1974, §5.16 (rings).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bearing.geometry import DEFAULT_DAMPING_RATIO, Material
from .section import RingSection

__all__ = ["DEFAULT_DAMPING_RATIO", "DIRECTIONS", "RingModes", "free_ring_modes", "in_plane_mass",
           "in_plane_stiffness", "out_of_plane_mass", "out_of_plane_stiffness", "shear_modulus"]


#: The two families of modes: ``"radial"`` (in plane) and ``"axial"`` (out of plane).
DIRECTIONS = ("radial", "axial")


def shear_modulus(material: Material) -> float:
    """``G = E / (2·(1 + ν))`` [Pa] of an isotropic material."""
    return material.youngs_modulus / (2.0 * (1.0 + material.poisson_ratio))


def _orders(orders):
    k = np.asarray(orders, dtype=float)
    if k.ndim != 1 or np.any(k < 0) or np.any(k != np.round(k)):
        raise ValueError(f"mode orders must be integers >= 0, got {orders!r}")
    return k


def in_plane_stiffness(orders, youngs_modulus, i_in_plane, area, radius, *, extension=True):
    """Modal stiffness of the in-plane modes per unit radial amplitude [N m⁻¹] (module Notes).

    Parameters
    ----------
    orders : array_like of int
        ``k`` [-].
    youngs_modulus : float
        ``E`` [Pa].
    i_in_plane : float
        ``I_in`` [m⁴].
    area : float
        ``A`` [m²].
    radius : float
        ``R`` [m].
    extension : bool
        ``k = 0`` is the extensional breathing mode (True) or inextensible (``inf``).
    """
    k = _orders(orders)
    e, i, a, r = float(youngs_modulus), float(i_in_plane), float(area), float(radius)
    out = math.pi * e * i * (k * k - 1.0) ** 2 / r ** 3
    breathing = 2.0 * math.pi * (e * a / r + e * i / r ** 3) if extension else math.inf
    return np.where(k == 0, breathing, out)


def in_plane_mass(orders, density, area, radius):
    """Modal mass of the in-plane modes per unit radial amplitude [kg]: ``πρAR(k² + 1)/k²``,
    ``2πρAR`` at ``k = 0`` (module Notes).

    Parameters
    ----------
    orders : array_like of int
        ``k`` [-].
    density : float
        ``ρ`` [kg m⁻³].
    area : float
        ``A`` [m²].
    radius : float
        ``R`` [m].
    """
    k = _orders(orders)
    m = math.pi * float(density) * float(area) * float(radius)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(k == 0, 2.0 * m, m * (k * k + 1.0) / np.maximum(k * k, 1.0))


def out_of_plane_stiffness(orders, youngs_modulus, i_out_of_plane, shear_mod, torsion_constant, radius):
    """Modal stiffness of the out-of-plane modes per unit axial amplitude, the twist
    condensed out [N m⁻¹] (module Notes).

    Parameters
    ----------
    orders : array_like of int
        ``k`` [-].
    youngs_modulus : float
        ``E`` [Pa].
    i_out_of_plane : float
        ``I_out`` [m⁴].
    shear_mod : float
        ``G`` [Pa].
    torsion_constant : float
        ``J`` [m⁴].
    radius : float
        ``R`` [m].
    """
    k = _orders(orders)
    ei = float(youngs_modulus) * float(i_out_of_plane)
    gj = float(shear_mod) * float(torsion_constant)
    return math.pi * ei * k * k * (k * k - 1.0) ** 2 / (float(radius) ** 3 * (k * k + ei / gj))


def out_of_plane_mass(orders, density, area, radius):
    """Modal mass of the out-of-plane modes per unit axial amplitude [kg]: ``πρAR``,
    ``2πρAR`` at ``k = 0`` (module Notes).

    Parameters
    ----------
    orders : array_like of int
        ``k`` [-].
    density : float
        ``ρ`` [kg m⁻³].
    area : float
        ``A`` [m²].
    radius : float
        ``R`` [m].
    """
    k = _orders(orders)
    m = math.pi * float(density) * float(area) * float(radius)
    return np.where(k == 0, 2.0 * m, m)


@dataclass(frozen=True)
class RingModes:
    """One family of a ring's Fourier modes, per order ``k``.

    Parameters
    ----------
    direction : str
        ``"radial"`` (in plane) or ``"axial"`` (out of plane).
    orders : ndarray of int
        ``k`` [-].
    stiffness : ndarray
        ``K_k`` per unit amplitude, the support's included [N m⁻¹]; 0 for a rigid-body
        order, ``inf`` for an order held fixed.
    mass : ndarray
        ``M_k`` [kg].
    radius : float
        ``R``, the ring's centroid radius [m].
    damping_ratio : float
        ``ζ`` [-].
    """

    direction: str
    orders: np.ndarray
    stiffness: np.ndarray
    mass: np.ndarray
    radius: float
    damping_ratio: float = DEFAULT_DAMPING_RATIO

    def __post_init__(self):
        if self.direction not in DIRECTIONS:
            raise ValueError(f"ring modes: direction {self.direction!r} is not one of {', '.join(DIRECTIONS)}")
        if not (math.isfinite(self.damping_ratio) and self.damping_ratio >= 0.0):
            raise ValueError(f"ring modes: damping ratio must be a finite number >= 0, got {self.damping_ratio!r}")

    @property
    def frequencies(self) -> np.ndarray:
        """Undamped natural frequencies ``ω_k = √(K_k/M_k)`` [rad s⁻¹]."""
        return np.sqrt(self.stiffness / self.mass)

    @property
    def damping(self) -> np.ndarray:
        """Modal damping coefficients ``c_k = 2ζ√(K_k·M_k)`` [N s m⁻¹]."""
        return 2.0 * self.damping_ratio * np.sqrt(self.stiffness * self.mass)


def free_ring_modes(section: RingSection, material: Material, max_order: int, direction: str = "radial", *,
                    extension: bool = True, damping_ratio: float = DEFAULT_DAMPING_RATIO) -> RingModes:
    """The free (unsupported) ring's modes of orders ``0 … max_order`` (module Notes).

    Parameters
    ----------
    section : RingSection
    material : rvcore.bearing.geometry.Material
    max_order : int
        Highest order ``k`` kept [-].
    direction : {"radial", "axial"}
    extension : bool
        In plane: ``k = 0`` extensional (True) or inextensible.
    damping_ratio : float
        ``ζ`` [-].
    """
    if int(max_order) != max_order or max_order < 0:
        raise ValueError(f"ring modes: max_order must be an integer >= 0, got {max_order!r}")
    k = np.arange(int(max_order) + 1)
    r, a = section.centroid_radius, section.area
    if direction == "radial":
        stiffness = in_plane_stiffness(k, material.youngs_modulus, section.i_in_plane, a, r, extension=extension)
        mass = in_plane_mass(k, material.density, a, r)
    elif direction == "axial":
        stiffness = out_of_plane_stiffness(k, material.youngs_modulus, section.i_out_of_plane,
                                           shear_modulus(material), section.torsion_constant, r)
        mass = out_of_plane_mass(k, material.density, a, r)
    else:
        raise ValueError(f"ring modes: direction {direction!r} is not one of {', '.join(DIRECTIONS)}")
    return RingModes(direction, k, stiffness, mass, r, float(damping_ratio))
