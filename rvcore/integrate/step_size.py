"""Why each integrator takes a fixed step, and the bearing's rates that bound it. SI throughout.

Each method computes its own step from these rates (:func:`rvcore.integrate.rk4.rk4_time_step`,
:func:`rvcore.integrate.imex.imex_time_step`); the loop takes it by the method's name
(:func:`rvcore.integrate.methods.time_step`).

Why a fixed step, and how large
-------------------------------
The bearing is stiff in two ways, and both set a hard explicit stability limit that an
adaptive pair would only rediscover by rejecting steps:

1. *Contact oscillation.* A ball between two Hertz contacts has the linearised stiffness
   ``k = 1.5·K^(2/3)·Q^(1/3)`` per contact. Study bearing at Q = 3.5 kN (40 kN radial):
   K ≈ 4.5e10 N/m^1.5 → k ≈ 2.9e8 N/m, two contacts on m_b = 0.050 kg give
   ω_n = √(2k/m_b) ≈ 1.1e5 rad/s. RK4 is stable on the imaginary axis to
   |λ·dt| ≤ 2√2, so dt ≤ 2.6e-5 s.
2. *Friction at small slip.* The friction law rises from zero with slope
   dμ/ds = 1.5·μ_s/v_s = 1.5 s/m, a viscous damper ``c_f = 1.5·μ_s·Q/v_s`` ≈ 5.3e3 N s/m
   at 3.55 kN (the study's 30 kN + 10 kN). A ball between an inner and an outer contact
   has two tangential modes: translation (rate 2·c_f/m_b) and rolling-direction rotation
   (rate 2·c_f·r²/I_b = 5·c_f/m_b, the faster), so λ_f ≈ 5.4e5 1/s on the negative real
   axis, where RK4 is stable to |λ·dt| ≤ 2.785: dt ≤ 5.2e-6 s.

For RK4 the friction limit dominates by ~5×, so its step is derived from it at the peak
quasi-static contact load of the cycle, and is the same at every step: deterministic,
reproducible bit for bit, four right-hand-side evaluations per step and no error norm.
The IMEX scheme (:mod:`rvcore.integrate.imex`) takes the Hertz contacts, the friction and the
damping implicitly, so its step comes from the friction modes' damping per step and
from what stays explicit. ``SolverSettings.step_safety`` scales either; the
convergence check of docs/model.md §9.6 halves it tenfold. Beyond the limit the friction
mode does not always diverge: the saturating friction law can bound it into a slip
chatter that spoils the metrics silently, which is why the step is held below the limit
rather than found by trial. A step that turns out far too large is caught by the
blow-up detection of :func:`rvcore.integrate.loop.integrate`.
"""
from __future__ import annotations

import math

import numpy as np

from ..bearing.layout import R_HALF_D, R_IB, R_MB
from ..dynamics.ring_modes import modal_rates


def row_rates(model, q: float):
    """Per row: the contact oscillation ``ω_n = √(2k/m_b)`` [rad s^-1] of a ball between
    its two race contacts at the load ``q`` [N] (``k = 1.5·K^(2/3)·q^(1/3)``, K of the
    stiffest arc), the ball mass ``m_b`` [kg] and ``r²/I_b`` [kg^-1]: the rates both
    integrators' steps come from."""
    for r in range(model.rows.shape[0]):
        row = model.rows[r]
        k_hertz = model.stiffest_arc(r)
        m, i_b, h = row[R_MB], row[R_IB], row[R_HALF_D]
        yield math.sqrt(2.0 * 1.5 * k_hertz ** (2.0 / 3.0) * q ** (1.0 / 3.0) / m), m, h * h / i_b


def modal_steps(model, q: float, imag_limit: float, real_limit: float):
    """The explicit limits [s] of a flexible ring's modal states at the contact load ``q`` [N]
    (:func:`rvcore.dynamics.ring_modes.modal_rates`): ``imag_limit/ω`` and ``real_limit/λ``
    per mode [-]. Empty for rigid rings: the rates the step of
    :func:`rvcore.integrate.rk4.rk4_time_step` takes for the modes (the IMEX scheme's has
    them implicit, :func:`rvcore.integrate.imex.imex_time_step`)."""
    return [min(imag_limit / omega if omega > 0 else np.inf, real_limit / lam if lam > 0 else np.inf)
            for omega, lam in modal_rates(model, q)]
