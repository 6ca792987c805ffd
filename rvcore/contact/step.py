"""The cubic STEP, the one smooth transition of the contact laws and the profiles. SI
throughout.

Notes
-----
Cubic step (docs/model.md §3)::

    STEP(x, x0, h0, x1, h1) = h0                          x ≤ x0
                            = h0 + (h1−h0)·Δ²·(3 − 2Δ)    Δ = (x−x0)/(x1−x0)
                            = h1                          x ≥ x1
"""
from __future__ import annotations

from .._numba import kernel


@kernel(inline=True)
def unit_step(d):
    """The cubic STEP on the unit interval, ``STEP(d, 0, 0, 1, 1)`` [-].

    The one place the cubic ``d²·(3 − 2d)`` is written; every STEP is this, scaled.

    Parameters
    ----------
    d : float
        Normalised argument ``Δ = (x − x0)/(x1 − x0)`` [-].

    Returns
    -------
    float
        0 for ``d ≤ 0``, 1 for ``d ≥ 1``, ``d²·(3 − 2d)`` between [-].

    Notes
    -----
    One expression of selects, as every law here that the ball–race contacts call: several
    ``return`` statements become a switch that keeps LLVM from vectorising the loops of
    :mod:`rvcore.dynamics.races`.
    """
    return 0.0 if d <= 0.0 else (1.0 if d >= 1.0 else d * d * (3.0 - 2.0 * d))


@kernel(inline=True)
def unit_step_slope(d):
    """``d/dΔ`` of :func:`unit_step`: ``6·Δ·(1 − Δ)`` inside (0, 1), 0 outside [-]."""
    if d <= 0.0 or d >= 1.0:
        return 0.0
    return 6.0 * d * (1.0 - d)


@kernel(inline=True)
def step(x, x0, h0, x1, h1):
    """The cubic ``STEP(x, x0, h0, x1, h1)`` of docs/model.md §3 [units of h].

    Parameters
    ----------
    x : float
        Argument [units of x].
    x0, x1 : float
        Start and end of the transition, ``x0 < x1`` [units of x].
    h0, h1 : float
        Values below ``x0`` and above ``x1`` [units of h].
    """
    inside = h0 + (h1 - h0) * unit_step((x - x0) / (x1 - x0))
    return h0 if x <= x0 else (h1 if x >= x1 else inside)


@kernel(inline=True)
def step_slope(x, x0, h0, x1, h1):
    """``dSTEP/dx`` of :func:`step` [units of h per unit of x]."""
    w = x1 - x0
    return (h1 - h0) * unit_step_slope((x - x0) / w) / w
