"""Flexible rings in the dynamics: each flexible ring's Fourier modes
(:mod:`rvcore.rings.modes`, :mod:`rvcore.rings.support`) as states, the raceway's
displacement they give at a ball, and the contact forces that drive them. SI throughout.

Notes
-----
**States.** Each flexible ring and direction (a *family*: inner radial, inner axial,
outer radial, outer axial) keeps the amplitudes ``a_k^c``, ``a_k^s`` of its modes
``cos kθ``, ``sin kθ`` for the orders ``k = 0 … K`` (:data:`DYNAMICS_MAX_ORDER` by
default; ``a_0^s`` has no shape and stays 0) and their rates, appended after the rows'
states (:func:`with_ring_modes`: ``[a_0^c, a_0^s, a_1^c, a_1^s, …, ȧ_0^c, ȧ_0^s, …]``).
The orders ``k = 0, 1`` are the ring's motion relative to its support (their stiffness is
the support's, :mod:`rvcore.rings.support`); the inner ring's pose states are the support's
pose (the statics' convention, :mod:`rvcore.rings.flexible`).

**Frames.** The inner ring's modes are read in its tilted, non-spinning frame (the frame
of :func:`rvcore.contact.pose.to_ring_frame`), the outer ring's in the fixed frame, ``θ``
the ball's azimuth there. The inner ring's material turns through its modes at the
prescribed speed Ω: the gyroscopic and convective terms that adds are of order
``Ω/ω_k`` (about 1e-3 for the study bearing's ovalisation, ω_2 ≈ 1.5e3 rad/s, at
2 rad/s) and are neglected.

**Equations** (Lagrange's, per family and mode; ``M_k``, ``K_k``, ``c_k`` of
:class:`rvcore.rings.modes.RingModes`)::

    M_k·ä_k^c + c_k·ȧ_k^c + K_k·a_k^c = Q_k^c = Σ_j F_j·cos kθ_j    (and ^s with sin)

``F_j`` the ball ``j``'s normal contact force on the ring (Hertz and damper, ``q·n``),
resolved radially outward (radial family) or along +z (axial family) in the ring's frame
(:func:`rvcore.rings.deflection.generalized_forces`, the same virtual work). The raceway's
groove at ball ``j`` stands displaced by ``w(θ_j) = Σ_k a_k^c·cos kθ_j + a_k^s·sin kθ_j``
radially and ``u(θ_j)`` axially, entering the penetration exactly as in the flexible
statics (:func:`rvcore.statics.equilibrium._ball_contacts`: the groove's centre moved by
``w`` radially and ``u`` axially), and the groove's velocity ``ẇ·ê_r + u̇·ẑ`` enters the
contact's ``dδ/dt`` (its damper). The friction force does not drive the modes, and the
slip the friction law sees leaves out the groove's modal velocity: a micro-slip
friction slope on a modal state (``Z·c_f/M_k``, about 1e6 s⁻¹) would bind the explicit
step; the friction's radial and axial parts are ``μ`` times the normal force's at most.
So with friction and damping off the modes and the contacts conserve
``Σ ½M_k·ȧ_k² + ½K_k·a_k² + Σ ⅖K·δ^2.5`` (:mod:`rvcore.dynamics.energy`).

**Integration.** RK4 takes the modal states explicitly, its step bounded by their rates
with the contacts' stiffness on them (:func:`modal_rates`, :mod:`rvcore.integrate.step_size`).
The IMEX scheme takes the modes implicitly with everything stiff on them: their own
stiffness and damping (the support's included) and each race contact's Hertz stiffness,
groove stiffness and damper on them, coupled with the balls and the ring's pose
(:func:`rvcore.dynamics.tangent.modal_blocks`; the Schur complement on the modes beside the
arrowhead system, :func:`rvcore.integrate.arrowhead.factor_modes`): the modes add no bound
to its step.

**Packing** (the kernels take no objects): a record after the bearing's ``params``
(:data:`FX_HEAD`): per family its number of orders (0: rigid), the index of its first
state and of its first order's data; per order ``k, M_k, K_k, c_k``. A rigid bearing's
``params`` ends at :data:`rvcore.bearing.layout.N_PARAMS` and nothing here is read.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._numba import kernel
from ..bearing.layout import N_PARAMS, R_Z, CompiledBearing
from ..rings.deflection import static_amplitudes
from ..rings.flexible import FlexibleRings

__all__ = ["DYNAMICS_MAX_ORDER", "FAMILIES", "truncated", "with_ring_modes", "family_states", "set_static_modes",
           "modal_rates",
           "flexible", "surface", "groove", "modal_rhs", "modal_energy", "modal_implicit_masses", "modal_offset",
           "order_amplitude"]

#: The highest Fourier order the dynamics keep by default [-]: 0 (breathing, axial
#: translation) and 1 (translation, tilt) against the support, 2 (ovalisation),
#: 3 (triangularity) … 6. The statics keep 60 (their deflection under a point load
#: converges as ``K⁻³``); the dynamics need the low modes a load distribution excites, and
#: each order more is a mode whose rate may bind the explicit step.
DYNAMICS_MAX_ORDER = 6

#: The families, in their order in the record: the attribute names of
#: :class:`rvcore.rings.flexible.FlexibleRings`.
FAMILIES = ("inner_radial", "inner_axial", "outer_radial", "outer_axial")
F_INNER_RADIAL, F_INNER_AXIAL, F_OUTER_RADIAL, F_OUTER_AXIAL = range(4)
#: Where the record starts in ``params``; per family three values (orders, first state, first data).
FX_HEAD = N_PARAMS
FX_STRIDE = 3
#: Per order: k, M_k, K_k, c_k.
FX_ORDER = 4


def truncated(rings: FlexibleRings, max_order: int = DYNAMICS_MAX_ORDER) -> FlexibleRings:
    """``rings`` with the orders ``0 … max_order`` of each flexible ring only: the modes the
    dynamics keep (the statics that start a case use the same, so that it starts in their
    equilibrium)."""
    if int(max_order) != max_order or max_order < 0:
        raise ValueError(f"flexible rings: the dynamics' max order must be an integer >= 0, got {max_order!r}")
    out = {}
    for name in FAMILIES:
        modes = getattr(rings, name)
        if modes is not None:
            keep = modes.orders <= max_order
            modes = dataclasses.replace(modes, orders=modes.orders[keep], stiffness=modes.stiffness[keep],
                                        mass=modes.mass[keep])
        out[name] = modes
    return FlexibleRings(**out)


def set_static_modes(model: CompiledBearing, rings: FlexibleRings, ring_forces, azimuths, y) -> None:
    """Set the modal amplitudes in ``y`` to the static ones, ``a_k = Q_k/K_k``, of the balls'
    forces on the rings (``ring_forces``, the statics' ``(n_balls, 4)``: inner radial, inner
    axial, outer radial, outer axial [N]) at their azimuths ``azimuths`` [rad]
    (:func:`rvcore.rings.deflection.static_amplitudes`), the rates to 0."""
    for f, name in enumerate(FAMILIES):
        n, s0 = family_states(model, name)
        if n == 0:
            continue
        modes = getattr(rings, name)
        a_cos, a_sin = static_amplitudes(modes, ring_forces[:, f], azimuths)
        y[s0:s0 + 2 * n:2] = a_cos[:n]
        y[s0 + 1:s0 + 2 * n:2] = a_sin[:n]
        y[s0 + 2 * n:s0 + 4 * n] = 0.0


def with_ring_modes(model: CompiledBearing, rings, max_order: int = DYNAMICS_MAX_ORDER) -> CompiledBearing:
    """``model`` with the flexible rings' modes of orders ``0 … max_order`` as states.

    Parameters
    ----------
    model : rvcore.bearing.layout.CompiledBearing
    rings : rvcore.rings.flexible.FlexibleRings
    max_order : int
        Highest order kept [-] (module Notes).

    Returns
    -------
    rvcore.bearing.layout.CompiledBearing
        ``model`` itself when every ring is rigid; otherwise a copy whose ``params`` carry
        the record (module Notes) and whose ``n_states`` count the modal states.
    """
    if rings is None or rings.rigid:
        return model
    if int(max_order) != max_order or max_order < 0:
        raise ValueError(f"flexible rings: the dynamics' max order must be an integer >= 0, got {max_order!r}")
    head = np.zeros(FX_STRIDE * len(FAMILIES))
    data = []
    n_states = model.n_states
    data_at = FX_HEAD + head.size
    for f, name in enumerate(FAMILIES):
        modes = getattr(rings, name)
        if modes is None:
            continue
        keep = modes.orders <= max_order
        k = modes.orders[keep]
        if not np.array_equal(k, np.arange(k.size)):
            raise ValueError(f"flexible rings: {name} has the orders {modes.orders.tolist()}; the dynamics need "
                             f"every order from 0 to {max_order}")
        stiffness, mass, damping = modes.stiffness[keep], modes.mass[keep], modes.damping[keep]
        if not (np.all(np.isfinite(stiffness)) and np.all(stiffness > 0.0)):
            raise ValueError(f"flexible rings: {name} has an order held rigid or free (stiffness "
                             f"{stiffness.tolist()} N/m); the dynamics need a finite, positive stiffness "
                             f"per order: give the ring a finite support")
        head[FX_STRIDE * f:FX_STRIDE * f + 3] = k.size, n_states, data_at + FX_ORDER * len(data)
        data.extend(zip(k.astype(float), mass, stiffness, damping))
        n_states += 4 * k.size
    params = np.concatenate([model.params, head, np.array(data, dtype=float).ravel()])
    return dataclasses.replace(model, params=params, n_states=n_states)


def family_states(model: CompiledBearing, name: str):
    """``(orders, first state)`` of one family in ``model``'s state vector; ``(0, -1)``
    when that ring and direction is rigid. The amplitudes are at ``first + 2i`` (cos)
    and ``first + 2i + 1`` (sin), their rates ``2·orders`` further on."""
    f = FAMILIES.index(name)
    p = model.params
    if p.size <= N_PARAMS:
        return 0, -1
    n = int(p[FX_HEAD + FX_STRIDE * f])
    return (n, int(p[FX_HEAD + FX_STRIDE * f + 1])) if n > 0 else (0, -1)


def modal_implicit_masses(model: CompiledBearing):
    """``(amplitude state, rate state, M_k)`` of every mode (both of an order's), for the
    IMEX scheme's implicit unknowns (:func:`rvcore.integrate.arrowhead.solve_coupled`); none
    for rigid rings."""
    p = model.params
    out = []
    if p.size <= N_PARAMS:
        return out
    for f in range(len(FAMILIES)):
        n, s0, d0 = (int(p[FX_HEAD + FX_STRIDE * f + c]) for c in range(3))
        for i in range(n):
            for s in range(2):
                out.append((s0 + 2 * i + s, s0 + 2 * n + 2 * i + s, p[d0 + FX_ORDER * i + 1]))
    return out


@kernel(inline=True)
def family_record(params, f):
    """Family ``f``'s record in ``params`` (module Notes): its number of orders, its first
    state and where its per-order data start."""
    base = FX_HEAD + FX_STRIDE * f
    return int(params[base]), int(params[base + 1]), int(params[base + 2])


@kernel(inline=True)
def modal_offset(params, f):
    """The index of family ``f``'s first mode among the IMEX scheme's modal unknowns (every
    family's ``a_0^c, a_0^s, a_1^c, …`` in turn, :func:`rvcore.integrate.arrowhead.factor_modes`);
    ``f = 4``: their number."""
    o = 0
    for g in range(f):
        o += 2 * int(params[FX_HEAD + FX_STRIDE * g])
    return o


def modal_rates(model: CompiledBearing, q: float):
    """The rates of the modal states at the contact load ``q`` [N]: per family and order,
    ``(ω, λ)`` [rad s⁻¹, s⁻¹], the oscillation on the imaginary axis and the damping on the
    real one, for the explicit step (:mod:`rvcore.integrate.step_size`).

    Notes
    -----
    An upper bound: every ball of every row loaded at ``q`` on its stiffest arc and on
    the mode's crest (``cos² kθ_j = 1``), its Hertz tangent ``k_n = 1.5·K^(2/3)·q^(1/3)``
    in series with nothing (the ball held)::

        ω² = (K_k + Σ_rows Z·k_n) / M_k          λ = (c_k + Σ_rows Z·c_max) / M_k

    ``c_max`` the contact damper's full coefficient (``P_DAMP_C``, on when ``P_DAMPING``).
    RK4's (:func:`rvcore.integrate.rk4.rk4_time_step`); the IMEX scheme has them all implicit.
    """
    from ..bearing.layout import P_DAMP_C, P_DAMPING

    p = model.params
    out = []
    if p.size <= N_PARAMS:
        return out
    k_contacts, c_contacts = 0.0, 0.0
    for r in range(model.rows.shape[0]):
        k_hertz = model.stiffest_arc(r)
        z = model.rows[r, R_Z]
        k_contacts += z * 1.5 * k_hertz ** (2.0 / 3.0) * max(q, 1.0) ** (1.0 / 3.0)
        c_contacts += z * p[P_DAMP_C] * p[P_DAMPING]
    for f in range(len(FAMILIES)):
        n, d0 = int(p[FX_HEAD + FX_STRIDE * f]), int(p[FX_HEAD + FX_STRIDE * f + 2])
        for i in range(n):
            _, m, k, c = p[d0 + FX_ORDER * i:d0 + FX_ORDER * (i + 1)]
            out.append((math.sqrt((k + k_contacts) / m), (c + c_contacts) / m))
    return out


@kernel(inline=True)
def flexible(params):
    """True when ``params`` carry a flexible ring (module Notes, "Packing")."""
    return params.shape[0] > N_PARAMS


@kernel(inline=True)
def surface(params, y, f, c1, s1):
    """``(w, ẇ, ∂w/∂θ)`` of family ``f`` at the angle of cosine ``c1`` and sine ``s1``
    [m, m s⁻¹, m]: ``Σ_k a_k^c·cos kθ + a_k^s·sin kθ``, its rate and its slope along the
    ring (which turns the contact normal, :func:`rvcore.contact.laws.race_arc_penetration`);
    0 for a rigid one. ``cos kθ``, ``sin kθ`` by the rotation recurrence (no library
    trigonometry)."""
    n = int(params[FX_HEAD + FX_STRIDE * f])
    s0 = int(params[FX_HEAD + FX_STRIDE * f + 1])
    w, wd, ws = 0.0, 0.0, 0.0
    ck, sk = 1.0, 0.0
    for i in range(n):     # the orders are 0 … n − 1 (with_ring_modes)
        ac, as_ = y[s0 + 2 * i], y[s0 + 2 * i + 1]
        w += ac * ck + as_ * sk
        wd += y[s0 + 2 * n + 2 * i] * ck + y[s0 + 2 * n + 2 * i + 1] * sk
        ws += i * (as_ * ck - ac * sk)
        ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
    return w, wd, ws


@kernel(inline=True)
def groove(params, y, radial, axial, c1, s1):
    """One ring's groove at the angle of cosine ``c1`` and sine ``s1``: ``(w, ẇ, ∂w/∂θ,
    u, u̇, ∂u/∂θ)`` of its radial family ``radial`` and axial family ``axial``
    (:func:`surface`) [m, m s⁻¹, m, m, m s⁻¹, m]; the raceway's displacement that adds to
    an imperfection's (:func:`rvcore.dynamics.races.ring_surfaces`)."""
    w, wd, ws = surface(params, y, radial, c1, s1)
    u, ud, us = surface(params, y, axial, c1, s1)
    return w, wd, ws, u, ud, us


@kernel(inline=True)
def order_amplitude(params, y, f, k):
    """``√(a_k^c² + a_k^s²)`` of family ``f``'s order ``k`` [m]; 0 for a rigid family or
    an order it does not keep (:func:`rvcore.recording.plan.fill_state_signals`: the ovalisation)."""
    if params.shape[0] <= N_PARAMS:
        return 0.0
    n = int(params[FX_HEAD + FX_STRIDE * f])
    if k >= n:
        return 0.0
    s0 = int(params[FX_HEAD + FX_STRIDE * f + 1])
    return math.sqrt(y[s0 + 2 * k] ** 2 + y[s0 + 2 * k + 1] ** 2)


@kernel(inline=True)
def clear_modal_forces(params, dy):
    """Zero every family's generalized forces in ``dy`` (before
    :func:`rvcore.dynamics.races.ring_forces` adds the balls')."""
    for f in range(4):
        n = int(params[FX_HEAD + FX_STRIDE * f])
        s0 = int(params[FX_HEAD + FX_STRIDE * f + 1]) + 2 * n
        for m in range(s0, s0 + 2 * n):
            dy[m] = 0.0


@kernel(inline=True)
def modal_rhs(params, y, dy):
    """Every mode's ``dy/dt`` from its generalized force (in ``dy``'s rate slot, module
    Notes): ``ȧ`` and ``ä = (Q − K·a − c·ȧ)/M``."""
    for f in range(4):
        n, s0, d0 = family_record(params, f)
        for i in range(n):
            m, k, c = params[d0 + FX_ORDER * i + 1], params[d0 + FX_ORDER * i + 2], params[d0 + FX_ORDER * i + 3]
            for s in range(2):
                a, v = s0 + 2 * i + s, s0 + 2 * n + 2 * i + s
                dy[v] = (dy[v] - k * y[a] - c * y[v]) / m
                dy[a] = y[v]


@kernel(inline=True)
def modal_energy(params, y):
    """``(Σ ½M·ȧ², Σ ½K·a²)``: the modes' kinetic and strain energy, the support's
    included [J] (0 for rigid rings)."""
    kin, pot = 0.0, 0.0
    if params.shape[0] <= N_PARAMS:
        return kin, pot
    for f in range(4):
        n, s0, d0 = family_record(params, f)
        for i in range(n):
            m, k = params[d0 + FX_ORDER * i + 1], params[d0 + FX_ORDER * i + 2]
            for s in range(2):
                a, v = y[s0 + 2 * i + s], y[s0 + 2 * n + 2 * i + s]
                kin += 0.5 * m * v * v
                pot += 0.5 * k * a * a
    return kin, pot
