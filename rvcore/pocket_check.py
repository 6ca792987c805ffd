"""The IMEX step's check on the cage-pocket impacts: each pocket's elastic energy against
the work the step gave its Hertz force. SI throughout.

Why
---
The pocket contact is explicit in the IMEX scheme (:mod:`rvcore.implicit`). At the
scheme's step an impact lasts about three steps (ω_p·h ≈ 1 at 160 N on the study
bearing), and a step that cuts through it makes or loses a few per cent of the impact's
energy. Taking the pocket implicitly would not help: an unresolved Hertz impact is not
conserved by the implicit stages either
(``tests/core/test_imex_conservation.py::test_an_unresolved_hertz_impact_is_not_conserved_explicit_or_implicit``).
Resolving it in time does, and the steps that need it are few: the error gathers in a
handful of steps per impact, 0.4 % of the study cycle's (docs/performance.md).

What is checked
---------------
For the Hertz part of a pocket force, a conservative force, the step's quadrature of its
power, ``h·Σ b_i·P_i`` with ``P = K_p·δ^1.5·δ̇`` at stage i (what the step's update gives
the bodies), equals the change of its elastic energy ``V = ⅖·K_p·δ^2.5`` over the step
exactly in the limit of small steps. Their difference ε is the energy the step made or
lost at that pocket. :func:`rvcore.imex.imex_step` takes the step again in substeps where
``|ε|`` passes the tolerance of :func:`rvcore.timestep.pocket_energy_tolerance`.
"""
from __future__ import annotations

import math

from numba import njit

from .contact import FAST, cage_pocket_penetration, hertz_energy
from .model import (BALL_STATES, R_BALL0, R_CAGE0, R_CAGE_RI, R_CAGE_RO, R_GUIDE, R_HALF_D, R_PITCH_R,
                    R_POCKET0, R_POCKET_K, R_POCKET_R, R_ZROW)


@njit(cache=True, nogil=True, fastmath=FAST, error_model="numpy")
def pocket_energy(y, rows, pockets, r, j):
    """Elastic energy ``⅖·K_p·δ^2.5`` [J] of ball ``j`` of row ``r`` against its cage
    pocket at the state ``y`` (the penetration of :func:`rvcore.contact.cage_pocket_penetration`,
    as the right-hand side takes it)."""
    c0 = int(rows[r, R_CAGE0])
    b = int(rows[r, R_BALL0]) + BALL_STATES * j
    k = int(rows[r, R_POCKET0]) + j
    xc, yc, zc, phi = y[c0], y[c0 + 1], y[c0 + 2], y[c0 + 3]
    cphi, sphi = math.cos(phi), math.sin(phi)
    cs0, sn0 = pockets[k, 0], pockets[k, 1]
    delta, _, _, _, _ = cage_pocket_penetration(
        rows[r, R_GUIDE], y[b] - xc, y[b + 1] - yc, y[b + 2] - zc - rows[r, R_ZROW], cphi * cs0 - sphi * sn0,
        sphi * cs0 + cphi * sn0, rows[r, R_PITCH_R], rows[r, R_POCKET_R], rows[r, R_HALF_D], rows[r, R_CAGE_RI],
        rows[r, R_CAGE_RO])
    return hertz_energy(rows[r, R_POCKET_K], delta)
