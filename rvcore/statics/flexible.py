"""The statics on flexible rings beside the rigid rings': the headline numbers a designer
compares (load distribution, Q_max, s₀, the lives, the stiffness) and the rings'
deformation. Pure functions, SI.

Notes
-----
A bearing whose ``inner_ring_support`` or ``outer_ring_support`` is set
(:class:`rvcore.bearing.geometry.RingSupport`) is solved twice at the same loads: with its
rings (:func:`rvcore.rings.flexible.bearing_rings`, docs/model.md §16) and with rigid rings
(today's model). :func:`headline` reads the same numbers off each; the ISO 281 ``L10``
depends on the applied loads only and so does not change, while ISO/TS 16281's ``L10r``
follows the load distribution. :func:`ring_deformation` gives each flexible ring's
ovalisation (its radial order ``k = 2`` amplitude) and its largest radial and axial
displacement relative to its support
(:meth:`rvcore.rings.flexible.FlexibleRings.deformation`). :func:`mode_truncation` compares
the statics on a ring's kept orders (the dynamics': orders 0–6) with the statics on every
order the bearing file gives: the truncation's error at that point (docs/model.md §16.1).
"""
from __future__ import annotations

import math

import numpy as np

from ..bearing.geometry import INNER, OUTER
from ..rings.flexible import FlexibleRings
from ..standards.iso16281 import LifeError, static_life
from ..standards.iso76 import static_safety_factor_from_pressure
from .equilibrium import StaticResult

__all__ = ["HEADLINE", "DEFORMATION", "MODE_TRUNCATION_LIMIT", "headline", "ring_deformation",
           "mode_truncation"]

#: The numbers :func:`headline` gives: name -> (unit, what it is).
HEADLINE = {
    "max_contact_load": ("N", "largest ball-race normal force"),
    "max_contact_pressure": ("Pa", "largest Hertz contact pressure"),
    "loaded_ball_count": ("1", "balls loaded on both races"),
    "static_safety_factor": ("1", "ISO 76 static safety factor s0 = (4200 MPa / p_max)^3"),
    "reference_rating_life_L10r": ("1", "ISO/TS 16281 reference rating life from the ball loads, in revolutions "
                                        "of the inner ring"),
    "basic_rating_life_L10": ("1", "ISO 281 basic rating life (the applied loads only), in revolutions of the "
                                   "inner ring"),
    "radial_stiffness": ("N m-1", "radial stiffness along the radial load, the other coordinates held"),
    "axial_stiffness": ("N m-1", "axial stiffness, the other coordinates held"),
    "tilting_stiffness": ("N m rad-1", "tilting stiffness about the axis normal to the radial load, the "
                                       "other coordinates held"),
}

#: The numbers :func:`ring_deformation` gives, per ring: name -> (unit, what it is).
DEFORMATION = {
    "ovalisation": ("m", "amplitude of the ring's radial order k = 2 (its diameter changes by twice it)"),
    "max_radial_deformation": ("m", "largest radial displacement of the ring's raceway relative to its support"),
    "max_axial_deformation": ("m", "largest axial displacement of the ring's raceway relative to its support"),
}

#: The truncation figure (:func:`mode_truncation`) above which the kept orders are not
#: converged for the rings' seats [-]: the 2 % to which the start-up ranges are held
#: converged with the modes (tests/core/test_ring_dynamics.py; docs/model.md §16.1).
MODE_TRUNCATION_LIMIT = 0.02

#: A displacement's change is relative to at least this fraction of the ring's whole
#: displacement ``|(δ_r, δ_a)|`` [-] (:func:`mode_truncation`, Notes).
_DISPLACEMENT_FLOOR = 0.1


def headline(bearing, st: StaticResult) -> dict:
    """The numbers compared between flexible and rigid rings at one equilibrium, SI.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    st : rvcore.statics.equilibrium.StaticResult
        With its stiffness matrix.

    Returns
    -------
    dict
        The names of :data:`HEADLINE`; a life is NaN where not rated and inf where nothing
        is loaded.
    """
    out = {"max_contact_load": float(st.max_contact_load), "max_contact_pressure": float(st.max_contact_pressure),
           "loaded_ball_count": float(st.loaded_ball_count),
           "static_safety_factor": float(static_safety_factor_from_pressure(st.max_contact_pressure))}
    try:
        life = static_life(bearing, st)
        out["reference_rating_life_L10r"] = life["reference_rating_life_L10r_Mrev"] * 1e6
        out["basic_rating_life_L10"] = life["basic_rating_life_L10_Mrev"] * 1e6
    except LifeError:
        out["reference_rating_life_L10r"] = out["basic_rating_life_L10"] = math.nan
    k = st.stiffness_scalars() if st.stiffness_matrix is not None else (math.nan,) * 3
    out.update(zip(("radial_stiffness", "axial_stiffness", "tilting_stiffness"), (float(x) for x in k)))
    return out


def ring_deformation(rings: FlexibleRings, st: StaticResult) -> dict:
    """Each ring's deformation at the equilibrium ``st`` solved on ``rings``, SI.

    Parameters
    ----------
    rings : rvcore.rings.flexible.FlexibleRings
    st : rvcore.statics.equilibrium.StaticResult
        Solved with ``rings=rings`` (its ``ring_forces``).

    Returns
    -------
    dict
        ``"<ring>_ring_<name>"`` for ring ``inner``, ``outer`` and each name of
        :data:`DEFORMATION` [m]; NaN where the ring (or that direction) is rigid.
    """
    out = {}
    forces = st.ring_forces
    for ring, name, cols in ((INNER, "inner", (0, 1)), (OUTER, "outer", (2, 3))):
        if forces is None:
            d = dict.fromkeys(("ovalisation", "max_radial", "max_axial"), math.nan)
        else:
            d = rings.deformation(ring, forces[:, cols[0]], forces[:, cols[1]], np.asarray(st.azimuths))
        out[f"{name}_ring_ovalisation"] = d["ovalisation"]
        out[f"{name}_ring_max_radial_deformation"] = d["max_radial"]
        out[f"{name}_ring_max_axial_deformation"] = d["max_axial"]
    return out


def mode_truncation(kept: StaticResult, every: StaticResult) -> float:
    """The largest relative change of δ_r, δ_a and Q_max when the flexible rings keep fewer
    Fourier orders [-].

    Parameters
    ----------
    kept : rvcore.statics.equilibrium.StaticResult
        The statics on the rings' kept orders (the dynamics', ``0 … 6``).
    every : rvcore.statics.equilibrium.StaticResult
        The statics at the same loads on every order (the bearing file's ``max_order``).

    Returns
    -------
    float
        ``max(|Δδ_r|/d_r, |Δδ_a|/d_a, |ΔQ_max|/Q_max)``, NaN where ``every`` carries no load.

    Notes
    -----
    Each change is relative to the value with every order; a displacement's denominator is
    ``d = max(|δ|, 0.1·|(δ_r, δ_a)|)``, so that a component under a tenth of the ring's
    displacement (δ_a under a nearly radial load; 0 under a pure radial load on a
    symmetric row) is measured against the ring's displacement, where its relative change
    stops saying anything about it. The kept orders converge when the seat's local compliance under a ball
    is small against the contact's (docs/model.md §16.1): the figure says whether that holds
    at this point, above :data:`MODE_TRUNCATION_LIMIT` not.
    """
    floor = _DISPLACEMENT_FLOOR * math.hypot(every.radial_displacement, every.axial_displacement)
    q = float(every.max_contact_load)
    if not (q > 0.0 and floor > 0.0):
        return math.nan
    changes = [abs(kept.radial_displacement - every.radial_displacement) / max(abs(every.radial_displacement), floor),
               abs(kept.axial_displacement - every.axial_displacement) / max(abs(every.axial_displacement), floor),
               abs(float(kept.max_contact_load) - q) / q]
    return float(max(changes))
