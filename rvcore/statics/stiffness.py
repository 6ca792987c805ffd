"""Tangent stiffness of the inner ring at an equilibrium, SI in and SI out.

The ring's five free coordinates are ``u = (x, y, z, tilt_x, tilt_y)`` [m, m, m, rad,
rad]. The balls' reaction on the ring, ``F(u)`` = (fx, fy, fz [N], mx, my [N m]), with
every ball re-equilibrated between its arcs for each pose, defines the stiffness

    K_ij = −∂F_i/∂u_j        [N/m, N/rad, N m/m, N m/rad by block]

so that a small change of the applied load ``dL`` moves the ring by ``du = K⁻¹·dL``.

Notes
-----
``F = −∇V`` where ``V(u) = Σ_j min_P V_j(P, u)`` is the contact energy (see
:mod:`rvcore.statics.equilibrium`), so ``K`` is the Hessian of ``V``: symmetric, and positive
definite wherever the balls hold the ring in all five directions. It is formed here by
central differences of ``F``, one pair per coordinate, at two step sizes ``h`` and
``h/2`` combined by Richardson extrapolation,

    K = (4·K(h/2) − K(h)) / 3 ,

whose error is O(h⁴); ``|K(h/2) − K(h)|`` is returned as the convergence measure of the
plain central difference. Tilt steps are the translation step divided by a length (the
pitch radius), so both move the contacts by about the same distance.
"""
from __future__ import annotations

import math

import numpy as np

#: Names and units of the five coordinates of ``u`` (rows and columns of K).
COORDINATES = ("x", "y", "z", "tilt_x", "tilt_y")
COORDINATE_UNITS = ("m", "m", "m", "rad", "rad")


def _central(forces, u, steps):
    k = np.empty((5, 5))
    for j in range(5):
        du = np.zeros(5)
        du[j] = steps[j]
        k[:, j] = -(forces(u + du) - forces(u - du)) / (2.0 * steps[j])
    return k


def tangent_stiffness(forces, u, length: float, step: float = 2e-8):
    """Richardson-extrapolated central-difference stiffness of ``forces`` at ``u``.

    Parameters
    ----------
    forces : callable
        ``forces(u) -> ndarray (5,)``: the balls' force [N] and moment [N m] on the ring
        at pose ``u``, with the balls in equilibrium.
    u : array_like (5,)
        The equilibrium pose [m, m, m, rad, rad].
    length : float
        Length that turns the translation step into a tilt step (the pitch radius) [m].
    step : float
        Translation step ``h`` [m]; small against the contact penetrations (µm), large
        against the balls' equilibrium tolerance.

    Returns
    -------
    K : ndarray (5, 5)
        [N/m, N/rad; N m/m, N m/rad] by block.
    change : float
        ``max|K(h/2) − K(h)| / max|K|``: how far the plain central difference still
        moves when its step is halved [-].
    """
    u = np.asarray(u, dtype=float)
    steps = np.array([step, step, step, step / length, step / length])
    k1 = _central(forces, u, steps)
    k2 = _central(forces, u, steps / 2.0)
    scale = max(np.abs(k2).max(), 1e-300)
    return (4.0 * k2 - k1) / 3.0, float(np.abs(k2 - k1).max() / scale)


def load_frame(load_angle: float) -> np.ndarray:
    """Orthogonal 5×5 map from the bearing frame to the load frame.

    Rows: along the radial load (ψ), normal to it, axial, tilt about the radial load's
    axis, tilt about the normal axis (−sin ψ, cos ψ), the axis the tilting moment turns
    about.
    """
    c, s = math.cos(load_angle), math.sin(load_angle)
    t = np.zeros((5, 5))
    t[0, :2] = c, s
    t[1, :2] = -s, c
    t[2, 2] = 1.0
    t[3, 3:] = c, s
    t[4, 3:] = -s, c
    return t


def stiffness_scalars(k: np.ndarray, load_angle: float = 0.0):
    """The designer's three stiffnesses: direct terms of ``K`` in the load frame.

    Each is the force (moment) needed per unit displacement (tilt) in its own direction
    with the other four coordinates held, the convention of bearing catalogues and
    MESYS/KISSsoft's stiffness matrices.

    Parameters
    ----------
    k : ndarray (5, 5)
        Tangent stiffness in the bearing frame (:func:`tangent_stiffness`).
    load_angle : float
        Direction ψ of the radial load from +x [rad].

    Returns
    -------
    radial : float
        Along the radial load [N m^-1].
    axial : float
        Along z [N m^-1].
    tilting : float
        About the axis normal to the radial load, the moment's axis [N m rad^-1].
    """
    t = load_frame(load_angle)
    kl = t @ k @ t.T
    return float(kl[0, 0]), float(kl[2, 2]), float(kl[4, 4])


def free_stiffness_scalars(k: np.ndarray, load_angle: float = 0.0, tilt_held: bool = False):
    """The designer's three stiffnesses with the other coordinates free: ``1/C_ii``.

    Each is the load per unit displacement (tilt) in its own direction when only that
    load changes and the ring moves freely in the others, the compliance view: ``C =
    K⁻¹`` over the free coordinates, in the load frame. With the ring's tilts held
    (``tilt_held``) the compliance is over the three translations only, and the tilting
    stiffness is not defined (NaN).

    Parameters
    ----------
    k, load_angle
        As :func:`stiffness_scalars`.
    tilt_held : bool
        The tilts are held by a support (:attr:`rvcore.bearing.geometry.InnerRing.tilt`).

    Returns
    -------
    radial, axial, tilting : float
        As :func:`stiffness_scalars` [N m^-1, N m^-1, N m rad^-1]; the tilting one NaN
        when held.

    Notes
    -----
    ``1/C_ii ≤ K_ii`` always (K symmetric positive definite): freeing the other
    coordinates lets the ring give way along couplings that the direct term holds, such
    as the tilt that a single row's radial load brings.
    """
    t = load_frame(load_angle)
    kl = t @ np.asarray(k, dtype=float) @ t.T
    n = 3 if tilt_held else 5
    try:
        c = np.linalg.inv(kl[:n, :n])
    except np.linalg.LinAlgError:
        return math.nan, math.nan, math.nan
    inv = lambda x: 1.0 / x if x > 0.0 else math.nan  # noqa: E731  a singular direction has no stiffness
    return inv(c[0, 0]), inv(c[2, 2]), (math.nan if tilt_held else inv(c[4, 4]))
