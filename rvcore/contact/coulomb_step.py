"""The study's friction law, ``coulomb_step``: Coulomb friction with STEP transitions
(docs/model.md §4), its slopes and its IMEX tangent. SI throughout.

A friction law is a module like this one and a name in
:data:`rvcore.bearing.laws.FRICTION_LAWS`; :mod:`rvcore.contact.laws` dispatches on the
record's kind (``law[LAW_KIND]``) to its six functions: ``coefficient``, ``slope``,
``slope_at_zero_slip``, ``falling_slope``, ``per_slip`` and ``tangent_curvature``. Every
function reads the law's parameters from its record ``law``
(:func:`rvcore.bearing.laws.pack_friction_law`).

Notes
-----
Slip speed ``s = |v_t|``::

    μ(s) = STEP(s, −v_s, −μ_s, v_s, μ_s)      s < v_s
         = STEP(s, v_s, μ_s, v_d, μ_d)        v_s ≤ s ≤ v_d
         = μ_d                                 s > v_d
"""
from __future__ import annotations

import math

from .._numba import kernel

from ..bearing.laws import LAW_INV_VS, LAW_MU_D, LAW_MU_S, LAW_V_D, LAW_V_S
from .step import step, step_slope


@kernel(inline=True)
def coefficient(s, law):
    """μ(s) of docs/model.md §4 [-] at the slip speed ``s`` ≥ 0 [m s^-1].

    The study's law (``coulomb_step``): ``STEP(s, −v_s, −μ_s, v_s, μ_s)`` below v_s,
    ``STEP(s, v_s, μ_s, v_d, μ_d)`` up to v_d, μ_d beyond.
    """
    mu_s, v_s, mu_d, v_d = law[LAW_MU_S], law[LAW_V_S], law[LAW_MU_D], law[LAW_V_D]
    rising = step(s, -v_s, -mu_s, v_s, mu_s)
    falling = step(s, v_s, mu_s, v_d, mu_d)
    return rising if s < v_s else (falling if s <= v_d else mu_d)


@kernel(inline=True)
def slope(s, law):
    """dμ/ds of :func:`coefficient` at ``s`` ≥ 0 [s m^-1]."""
    mu_s, v_s, mu_d, v_d = law[LAW_MU_S], law[LAW_V_S], law[LAW_MU_D], law[LAW_V_D]
    if s < v_s:
        return step_slope(s, -v_s, -mu_s, v_s, mu_s)
    if s <= v_d:
        return step_slope(s, v_s, mu_s, v_d, mu_d)
    return 0.0


@kernel(inline=True)
def slope_at_zero_slip(law):
    """dμ/ds at s = 0 [s m^-1] (the study's law: 1.5·μ_s/v_s).

    The law acts as a viscous damper ``c_f = Q·dμ/ds`` at small slip; the explicit step
    is sized from it (:func:`rvcore.integrate.rk4.rk4_time_step`).
    """
    return slope(0.0, law)


def falling_slope(law) -> float:
    """The steepest fall of μ with the slip, ``|min dμ/ds|`` [s m^-1] (0 for a law that
    never falls): an explicit stage's rate where the law falls (:mod:`rvcore.integrate.step_size`).
    The study's law falls from μ_s to μ_d along a cubic STEP, steepest at its middle:
    ``1.5·(μ_s − μ_d)/(v_d − v_s)``."""
    mu_s, v_s, mu_d, v_d = law[LAW_MU_S], law[LAW_V_S], law[LAW_MU_D], law[LAW_V_D]
    return -min(slope(0.5 * (v_s + v_d), law), 0.0) if mu_d < mu_s else 0.0


@kernel(inline=True)
def per_slip(s2, law):
    """``μ(s)/s`` [s m^-1] from the squared slip speed ``s2 = s²`` [m² s^-2].

    Below ``v_s`` the study's law is odd in s: with ``x = s/v_s``,
    ``STEP(s, −v_s, −μ_s, v_s, μ_s) = μ_s·(1.5·x − 0.5·x³)`` (Δ = (1 + x)/2 in the cubic),
    so ``μ/s = μ_s·(1.5 − 0.5·x²)/v_s`` needs no division by a small slip.
    tests/core/test_contact.py checks that this form and :func:`coefficient` agree
    over the whole range. Both forms are evaluated and one selected (:func:`unit_step`,
    Notes): in the vector loops of :mod:`rvcore.dynamics.races` the root costs next to nothing.
    """
    inv_vs, mu_s = law[LAW_INV_VS], law[LAW_MU_S]
    x2 = s2 * inv_vs * inv_vs
    s = math.sqrt(s2)
    sliding = coefficient(s, law) / s
    return mu_s * (1.5 - 0.5 * x2) * inv_vs if x2 < 1.0 else sliding


@kernel(inline=True)
def tangent_curvature(s2, law):
    """``(max(μ', 0) − μ/s)/s²`` [s^3 m^-3] at ``s2 = s²``: the coefficient of
    ``v_t·v_tᵀ`` in the friction force's tangent (:func:`rvcore.dynamics.tangent.friction_tangent`).

    Below v_s the study's law is a cubic, where it is ``−μ_s/v_s³`` exactly: nothing is
    divided by a small slip. Where the law falls, its slope is left out (the falling part
    stays explicit), so that the tangent is positive semi-definite.
    """
    inv_vs = law[LAW_INV_VS]
    if s2 * inv_vs * inv_vs < 1.0:
        return -law[LAW_MU_S] * inv_vs * inv_vs * inv_vs
    s = s2 ** 0.5
    return (max(slope(s, law), 0.0) - coefficient(s, law) / s) / s2
