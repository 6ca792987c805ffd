"""The fixed step of each integrator, from the bearing's stiffest rates. SI throughout.

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

from ..contact.laws import friction_falling_slope, friction_slope_at_zero_slip
from ..bearing.laws import FRICTION_LAW_SIZE, LAW_ON
from . import imex
from .imex import FRICTION_LIMIT, ONSET_LIMIT
from ..dynamics.ring_modes import modal_rates
from ..bearing.layout import A_K, P_DAMP_C, P_DAMPING, P_LAW, R_ARC0, R_HALF_D, R_IB, R_MB, R_NARC

RK4_IMAG_LIMIT = 2.0 * math.sqrt(2.0)
RK4_REAL_LIMIT = 2.785
#: ``ω_c·h`` at most, ``ω_c`` the contacts' stiffness on a flexible ring's modes, which the
#: IMEX scheme takes explicitly (:mod:`rvcore.dynamics.ring_modes`): an accuracy limit, not
#: stability's (2√2). Measured on the 12-ball section, rings on a 1e10 N/m² seat, friction
#: and damping off (tests/core/test_ring_dynamics.py): the energy drifted by 1.6e-3 of the
#: oscillation at ω_c·h = 1.6 (the rigid step there), 9.6e-5 at 0.80, 2.1e-5 at 0.40; at
#: this limit (0.64 at the default safety) it keeps docs/model.md §9.4's 1e-4.
IMEX_MODAL_LIMIT = 0.8


def time_step(model, peak_contact_load: float, method: str, *, safety: float = 0.8) -> float:
    """The fixed step [s] of the method named ``method``: its module's ``time_step``
    (:data:`rvcore.integrate.methods.METHODS`)."""
    from .methods import method as method_module

    return method_module(method).time_step(model, peak_contact_load, safety=safety)


def rk4_time_step(model, peak_contact_load: float, *, safety: float = 0.8,
                  dynamic_margin: float = 1.0) -> float:
    """The fixed RK4 step [s] from the stiffest contact and friction rates.

    Parameters
    ----------
    model : rvcore.bearing.layout.CompiledBearing
    peak_contact_load : float
        Largest quasi-static ball–race load over the cycle [N].
    safety : float
        Fraction of the stability limit [-].
    dynamic_margin : float
        Factor on the quasi-static load for dynamic overshoot [-].

    Notes
    -----
    Per row, with ``Q = dynamic_margin·peak_contact_load``, ``K`` the stiffest arc,
    ``k = 1.5·K^(2/3)·Q^(1/3)``, ``c_f = Q·dμ/ds`` at zero slip
    (:func:`rvcore.contact.laws.friction_slope_at_zero_slip`, the law's own slope) and the two
    race contacts of a ball::

        ω_n = √(2k/m_b)                        (contact oscillation)
        λ   = 2·(c_f·max(1/m_b, r²/I_b) + c_max/m_b)   (friction and damping, real axis)
        dt  = safety · min(2√2/ω_n, 2.785/λ)

    and a flexible ring's modes on the same limits at their rates with the contacts'
    stiffness on them (:func:`rvcore.dynamics.ring_modes.modal_rates`).
    """
    q = max(dynamic_margin * peak_contact_load, 1.0)
    p = model.params
    law = p[P_LAW:P_LAW + FRICTION_LAW_SIZE]
    c_f = friction_slope_at_zero_slip(law) * q * law[LAW_ON]
    dts = []
    for omega, m, rot in row_rates(model, q):
        lam = 2.0 * (c_f * max(1.0 / m, rot) + p[P_DAMP_C] * p[P_DAMPING] / m)
        dts.append(min(RK4_IMAG_LIMIT / omega, RK4_REAL_LIMIT / lam if lam > 0 else np.inf))
    dts.extend(_modal_steps(model, q))
    return safety * min(dts)


def imex_time_step(model, peak_contact_load: float, *, safety: float = 0.8,
                   dynamic_margin: float = 1.0) -> float:
    """The fixed IMEX step [s] from the rates that bound it (:mod:`rvcore.integrate.imex`, "Step").

    Notes
    -----
    Per row, with ``Q = dynamic_margin·peak_contact_load``, ``c_f = Q·dμ/ds`` at zero
    slip and the two race contacts of a ball (the rates of :func:`rk4_time_step`)::

        λ_f = 2·(c_f·max(1/m_b, r²/I_b) + c_max/m_b)      (friction and damping, implicit)
        λ_− = 2·Q·|min μ'|·max(1/m_b, r²/I_b)             (the law's falling slope, explicit)
        dt  = safety · min(FRICTION_LIMIT/λ_f, 2.785/λ_−, ONSET_LIMIT·√2/ω_n)

    and a flexible ring's modes at ``ω_c·h ≤`` :data:`IMEX_MODAL_LIMIT`, ``ω_c`` the contacts'
    stiffness on them (their own is implicit, :func:`rvcore.dynamics.ring_modes.modal_solve`).
    ``|min μ'|`` the law's steepest fall (:func:`rvcore.contact.laws.friction_falling_slope`),
    and ω_n the contact oscillation of :func:`row_rates`, here only for a contact's first
    step (its oscillation is implicit from the next: the tableau keeps it undamped at any
    ω_n·h). :data:`rvcore.integrate.imex.FRICTION_LIMIT` and :data:`rvcore.integrate.imex.ONSET_LIMIT`, and
    why: :mod:`rvcore.integrate.imex`.
    """
    q = max(dynamic_margin * peak_contact_load, 1.0)
    p = model.params
    law = p[P_LAW:P_LAW + FRICTION_LAW_SIZE]
    c_f = friction_slope_at_zero_slip(law) * q * law[LAW_ON]
    falling = friction_falling_slope(law) * law[LAW_ON]
    dts = []
    for omega, m, rot in row_rates(model, q):
        lam_f = 2.0 * (c_f * max(1.0 / m, rot) + p[P_DAMP_C] * p[P_DAMPING] / m)
        lam = 2.0 * q * falling * max(1.0 / m, rot)
        dts.append(min(FRICTION_LIMIT / lam_f if lam_f > 0 else np.inf,
                       RK4_REAL_LIMIT / lam if lam > 0 else np.inf,
                       ONSET_LIMIT * math.sqrt(2.0) / omega))
    dts.extend(_modal_steps(model, q, implicit=True))
    return safety * min(dts)


def _modal_steps(model, q: float, *, implicit: bool = False):
    """The explicit limits of a flexible ring's modal states at the contact load ``q`` [N]
    (:func:`rvcore.dynamics.ring_modes.modal_rates`), on RK4's imaginary- and real-axis
    limits; ``implicit`` (IMEX) with the modes' own stiffness and damping implicit, the
    contacts' on them explicit, on :data:`IMEX_MODAL_LIMIT`. Empty for rigid rings."""
    imag = IMEX_MODAL_LIMIT if implicit else RK4_IMAG_LIMIT
    return [min(imag / omega if omega > 0 else np.inf, RK4_REAL_LIMIT / lam if lam > 0 else np.inf)
            for omega, lam in modal_rates(model, q, implicit=implicit)]


def pocket_energy_tolerance(model, peak_contact_load: float, time_step: float) -> float:
    """The IMEX pocket check's tolerance [J] (:func:`rvcore.integrate.imex.imex_step`) at the step
    ``time_step`` [s].

    Notes
    -----
    :data:`rvcore.integrate.imex.POCKET_ENERGY_TOL` of ``⅖·Q·δ``, the elastic energy of a race
    contact at ``Q = peak_contact_load`` [N] (``δ = (Q/K)^(2/3)``, K of the row's stiffest
    arc; the smallest over the rows), at the step of the onset limit
    ``h₀ = ONSET_LIMIT·√2/ω_n`` (:func:`imex_time_step`), and scaled as ``(h/h₀)³``::

        tol = POCKET_ENERGY_TOL · ⅖·Q·δ · (h/h₀)³

    Why the cube: an impact the check lets pass leaves an error of up to the tolerance at
    each of its steps, ``τ/h`` of them (τ the impact's duration); ``(h/h₀)³`` makes that
    fall as h², the scheme's order, so that the check puts no floor under the drift's
    convergence when the step is halved (docs/model.md §9.4(a)). At the study case's
    default step, 1.0e-7 of 26 mJ: 2.6e-9 J.
    """
    q = max(peak_contact_load, 1.0)
    energies, onset = [], []
    for r in range(model.rows.shape[0]):
        row = model.rows[r]
        a0, na = int(row[R_ARC0]), int(row[R_NARC])
        k_hertz = model.arcs[a0:a0 + na, A_K].max()
        energies.append(0.4 * q * (q / k_hertz) ** (2.0 / 3.0))
    for omega, _, _ in row_rates(model, q):
        onset.append(ONSET_LIMIT * math.sqrt(2.0) / omega)
    return imex.POCKET_ENERGY_TOL * min(energies) * (time_step / min(onset)) ** 3


def tangent_load_tolerance(peak_contact_load: float) -> float:
    """The load [N] by which a race contact may move before the IMEX tangents are
    evaluated again (:func:`rvcore.integrate.imex.imex_step`): :data:`rvcore.integrate.imex.TANGENT_LOAD_TOL`
    of ``peak_contact_load`` [N]. On the study case 3.6 N."""
    return imex.TANGENT_LOAD_TOL * max(peak_contact_load, 1.0)


def row_rates(model, q: float):
    """Per row: the contact oscillation ``ω_n = √(2k/m_b)`` [rad s^-1] of a ball between
    its two race contacts at the load ``q`` [N] (``k = 1.5·K^(2/3)·q^(1/3)``, K of the
    stiffest arc), the ball mass ``m_b`` [kg] and ``r²/I_b`` [kg^-1]: the rates both
    integrators' steps come from."""
    for r in range(model.rows.shape[0]):
        row = model.rows[r]
        a0, na = int(row[R_ARC0]), int(row[R_NARC])
        k_hertz = model.arcs[a0:a0 + na, A_K].max()
        m, i_b, h = row[R_MB], row[R_IB], row[R_HALF_D]
        yield math.sqrt(2.0 * 1.5 * k_hertz ** (2.0 / 3.0) * q ** (1.0 / 3.0) / m), m, h * h / i_b
