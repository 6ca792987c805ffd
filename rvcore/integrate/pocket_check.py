"""The IMEX step's check on the cage-pocket impacts: each pocket's elastic energy against
the work the step gave its Hertz force. SI throughout.

Why
---
The pocket contact is explicit in the IMEX scheme (:mod:`rvcore.dynamics.tangent`). At the
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
lost at that pocket. :func:`rvcore.integrate.imex.imex_step` takes the step again in substeps where
``|ε|`` passes the tolerance of :func:`rvcore.integrate.imex.pocket_energy_tolerance`, and
checks a retake the same way: ``h·Σ b_i·P_i`` summed over its substeps (each substep's
``h`` its share of the step) against the pocket's energy from the step's start to its end.
"""
from __future__ import annotations

import math

from .._numba import kernel

from ..dynamics.energy import pocket_energy
from ..bearing.layout import R_CAGE0, R_POCKET0, R_Z


@kernel(inline=True)
def pocket_energy_error(y, dt, rows, pockets, start_energy, power_sum, touched):
    """The largest ``|ε|`` [J] over the pockets a step of ``dt`` [s] touched, at the step's
    end state ``y``: ``ε = V_{n+1} − V_n − h·Σ b_i·P_i`` (0 where none was touched).

    Per ball (indexed as the pockets): ``start_energy`` the pocket's elastic energy at the
    step's start [J], ``power_sum`` the stages' ``Σ b_i·P_i`` [W], ``touched`` nonzero
    where any stage had the ball in its pocket (only those are evaluated here).
    """
    worst = 0.0
    for r in range(rows.shape[0]):
        p0 = int(rows[r, R_POCKET0])
        phi = y[int(rows[r, R_CAGE0]) + 3]
        cphi, sphi = math.cos(phi), math.sin(phi)
        for j in range(int(rows[r, R_Z])):
            k = p0 + j
            if touched[k] == 0.0:
                continue
            v1 = pocket_energy(y, rows, pockets, r, j, cphi, sphi)
            worst = max(worst, abs(v1 - start_energy[k] - dt * power_sum[k]))
    return worst
