"""The inner ring's pose: its rotation, its angular velocity, and the change between
its frame and the bearing's. SI throughout.

The pose is ``R = Ry(θy)·Rx(θx)`` and the ring spins at the prescribed ω about its own
(tilted) axis ``R·ẑ`` (docs/model.md §1). Every function is a kernel (rvcore._numba) on scalars,
inlined into its callers (:mod:`rvcore.dynamics.rhs`, :mod:`rvcore.dynamics.energy`,
:mod:`rvcore.statics.equilibrium`), and allocates nothing.
"""
from __future__ import annotations

import math

from .._numba import kernel


@kernel(inline=True)
def ring_rotation(tilt_x, tilt_y):
    """Rotation matrix ``R = Ry(θy)·Rx(θx)`` of the inner ring, row by row [-].

    Parameters
    ----------
    tilt_x, tilt_y : float
        Tilts about x and y [rad].

    Returns
    -------
    tuple of float
        ``(r00, r01, r02, r10, r11, r12, r20, r21, r22)``; a point fixed in the ring at
        ``p`` (ring frame) is at ``r_ring + R·p``.
    """
    ca, sa, cb, sb = math.cos(tilt_x), math.sin(tilt_x), math.cos(tilt_y), math.sin(tilt_y)
    return cb, sb * sa, sb * ca, 0.0, ca, -sa, -sb, cb * sa, cb * ca


@kernel(inline=True)
def ring_angular_velocity(w_ring, tilt_rate_x, tilt_rate_y, r00, r20, r02, r12, r22):
    """Inertial angular velocity Ω of the inner ring [rad s^-1] (rvcore.dynamics.rhs notes).

    ``w_ring`` [rad s^-1] is the prescribed spin about the ring's own axis
    ``R·ẑ = (r02, r12, r22)``; ``r00 = cos θy`` and ``r20 = −sin θy`` turn the tilt rate
    about x [rad s^-1] into Ry(θy)·x̂.
    """
    return (tilt_rate_x * r00 + w_ring * r02, tilt_rate_y + w_ring * r12,
            tilt_rate_x * r20 + w_ring * r22)


@kernel(inline=True)
def to_ring_frame(px, py, pz, xi, yi, zi, r00, r01, r02, r10, r11, r12, r20, r21, r22, zrow):
    """A point P [m] in the inner ring's frame, ``Rᵀ·(P − r_ring)``, axial coordinate
    measured from the row plane ``zrow`` [m]; returns ``(x, y, z, √(x² + y²))`` [m]."""
    dx, dy, dz = px - xi, py - yi, pz - zi
    plx = r00 * dx + r10 * dy + r20 * dz
    ply = r01 * dx + r11 * dy + r21 * dz
    plz = r02 * dx + r12 * dy + r22 * dz - zrow
    return plx, ply, plz, math.sqrt(plx * plx + ply * ply)


@kernel(inline=True)
def ring_to_global(x, y, z, r00, r01, r02, r10, r11, r12, r20, r21, r22):
    """A vector given in the inner ring's frame, in the fixed frame: ``R·v`` [as v]."""
    return (r00 * x + r01 * y + r02 * z, r10 * x + r11 * y + r12 * z,
            r20 * x + r21 * y + r22 * z)
