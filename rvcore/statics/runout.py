"""The quasi-static runout path: the inner ring's pose over one revolution of an
imperfect bearing (docs/model.md §12), the reference its dynamics are compared with. SI.
"""
from __future__ import annotations

import math

import numpy as np

from ..bearing.geometry import epicyclic_cage_ratio
from ..bearing.imperfections import realize
from .equilibrium import solve_statics


def runout_path(bearing, radial_load: float, axial_load: float, moment: float = 0.0, load_angle: float = 0.0,
                *, points: int = 36, gravity: bool = True, seed: int = -1) -> dict:
    """The quasi-static pose of the inner ring at ``points`` ring angles over a revolution.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    radial_load, axial_load : float
        [N]
    moment : float
        Tilting moment about the axis normal to the radial load [N m].
    load_angle : float
        Direction of the radial load [rad].
    points : int
        Ring angles 2πk/points, k = 0 … points − 1.
    gravity : bool
        Include the ring's weight.
    seed : int
        The realization whose tolerance-class draws to use (−1: none; high points at 0).

    Returns
    -------
    dict
        ``ring_angle`` [rad], ``ball_angle`` [rad] (the cage's epicyclic share of the ring's
        turn, where the balls stand), ``displacement`` (points, 5) [m, rad],
        ``radial_displacement``, ``axial_displacement`` [m] and their ``*_range`` [m].

    Notes
    -----
    At ring angle φ the balls have rolled with the cage through
    ``φ·½(1 − D cos α/d_m)``: the pose is :func:`rvcore.statics.equilibrium.solve_statics` with
    ``ring_angle = φ`` and ``ball_angle`` that. A perfect bearing's path is flat but for
    its balls' varying compliance.
    """
    if points < 2:
        raise ValueError(f"points = {points!r}: need at least 2 ring angles")
    b = realize(bearing, seed)
    ratio = epicyclic_cage_ratio(b.rows[0])
    angles = 2.0 * math.pi * np.arange(points) / points
    poses = [solve_statics(b, radial_load, axial_load, moment, load_angle, gravity=gravity, stiffness=False,
                           ring_angle=float(a), ball_angle=float(ratio * a)) for a in angles]
    dr = np.array([p.radial_displacement for p in poses])
    da = np.array([p.axial_displacement for p in poses])
    return {"ring_angle": angles, "ball_angle": ratio * angles,
            "displacement": np.array([p.displacement for p in poses]),
            "radial_displacement": dr, "axial_displacement": da,
            "radial_displacement_range": float(dr.max() - dr.min()),
            "axial_displacement_range": float(da.max() - da.min())}
