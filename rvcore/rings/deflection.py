"""A ring's static deflection under point loads by the Fourier sum over its modes
(:mod:`rvcore.rings.modes`, :mod:`rvcore.rings.support`). Pure functions, SI.

Notes
-----
A load ``F_j`` at angle ``ψ_j`` (radial, positive outward, for the radial modes; axial,
positive towards +z, for the axial modes; applied on the ring's centroid circle) does the
virtual work ``F_j·δw(ψ_j)``, so its generalized forces on the modes ``cos kθ`` and
``sin kθ`` of order ``k`` are ``F_j·cos kψ_j`` and ``F_j·sin kψ_j``. In statics each mode
takes ``a_k = Q_k/K_k`` and the displacement at ``θ`` is the sum::

    w(θ) = Σ_k (Q_k^c·cos kθ + Q_k^s·sin kθ) / K_k
         = Σ_j F_j · Σ_k cos k(θ − ψ_j) / K_k        (K_0's term once, not twice)

truncated at the modes' highest order (the terms fall as ``k⁻⁴``, the error as
``k_max⁻³``). An order held fixed (``K = inf``) takes no displacement. A rigid order
(``K = 0``: a free ring's ``k = 1`` in plane, ``k = 0, 1`` out of plane) can carry no
generalized force: the loads must balance on it (within ``1e-9`` of their magnitudes),
and it then takes no displacement: the deflection is relative to the ring's rigid-body
position, as the theory of the free ring states it (Timoshenko & Gere).

References
----------
S. P. Timoshenko, J. M. Gere, *Theory of Elastic Stability*, 2nd ed., McGraw-Hill 1961, §7.4
(a ring by Fourier series); W. Soedel, *Vibrations of Shells and Plates*, 3rd ed., ch. 5
and 8 (modal expansion of a static load).
"""
from __future__ import annotations

import numpy as np

from .modes import RingModes

__all__ = ["generalized_forces", "static_amplitudes", "modal_displacement", "static_deflection"]

#: Relative size of a generalized force on a rigid order that counts as balanced [-].
BALANCE_TOLERANCE = 1e-9


def generalized_forces(orders, forces, angles):
    """``Q_k^c = Σ F_j cos kψ_j`` and ``Q_k^s = Σ F_j sin kψ_j`` [N].

    Parameters
    ----------
    orders : array_like of int
        ``k`` [-].
    forces : array_like
        ``F_j`` [N].
    angles : array_like
        ``ψ_j`` [rad].

    Returns
    -------
    q_cos, q_sin : ndarray
        Per order [N].
    """
    k = np.asarray(orders, dtype=float)[:, None]
    f = np.atleast_1d(np.asarray(forces, dtype=float))[None, :]
    psi = np.atleast_1d(np.asarray(angles, dtype=float))[None, :]
    if f.shape != psi.shape:
        raise ValueError(f"ring loads: {f.shape[1]} forces but {psi.shape[1]} angles")
    return (f * np.cos(k * psi)).sum(axis=1), (f * np.sin(k * psi)).sum(axis=1)


def static_amplitudes(modes: RingModes, forces, angles):
    """The modal amplitudes ``a_k = Q_k/K_k`` of a static load (module Notes).

    Parameters
    ----------
    modes : rvcore.rings.modes.RingModes
    forces : array_like
        ``F_j`` [N], in the modes' direction.
    angles : array_like
        ``ψ_j`` [rad].

    Returns
    -------
    a_cos, a_sin : ndarray
        Per order [m].

    Raises
    ------
    ValueError
        When a rigid order carries an unbalanced generalized force.
    """
    q_cos, q_sin = generalized_forces(modes.orders, forces, angles)
    scale = float(np.abs(np.asarray(forces, dtype=float)).sum())
    rigid = modes.stiffness == 0.0
    unbalanced = rigid & ((np.abs(q_cos) > BALANCE_TOLERANCE * scale) | (np.abs(q_sin) > BALANCE_TOLERANCE * scale))
    if np.any(unbalanced):
        k = int(modes.orders[np.argmax(unbalanced)])
        raise ValueError(f"ring loads: the {modes.direction} order k = {k} is rigid (a free ring's rigid-body "
                         f"motion) and the loads do not balance on it; give the ring a support")
    safe = np.where(rigid, 1.0, modes.stiffness)
    return np.where(rigid, 0.0, q_cos / safe), np.where(rigid, 0.0, q_sin / safe)


def modal_displacement(modes: RingModes, a_cos, a_sin, theta):
    """``Σ_k a_k^c·cos kθ + a_k^s·sin kθ`` [m] at the angles ``theta``.

    Parameters
    ----------
    modes : rvcore.rings.modes.RingModes
    a_cos, a_sin : array_like
        Modal amplitudes per order [m].
    theta : array_like
        ``θ`` [rad].
    """
    t = np.asarray(theta, dtype=float)
    k = modes.orders.astype(float).reshape((-1,) + (1,) * t.ndim)
    ac = np.asarray(a_cos, dtype=float).reshape(k.shape)
    as_ = np.asarray(a_sin, dtype=float).reshape(k.shape)
    return (ac * np.cos(k * t) + as_ * np.sin(k * t)).sum(axis=0)


def static_deflection(modes: RingModes, forces, angles, theta):
    """The ring's static displacement at ``theta`` under point loads (module Notes).

    Parameters
    ----------
    modes : rvcore.rings.modes.RingModes
        Radial modes for radial loads (displacement outward), axial for axial.
    forces : array_like
        ``F_j`` [N], positive outward (radial) or towards +z (axial).
    angles : array_like
        ``ψ_j`` [rad].
    theta : array_like
        Where to read the displacement [rad].

    Returns
    -------
    ndarray
        [m], the shape of ``theta``.
    """
    a_cos, a_sin = static_amplitudes(modes, forces, angles)
    return modal_displacement(modes, a_cos, a_sin, theta)
