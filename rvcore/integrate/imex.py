"""The coupled implicit–explicit integrator: the ball–race Hertz stiffness, friction at
small slip and contact damping implicit in every stage, everything else explicit. SI
throughout.

Why, and which scheme
---------------------
RK4's step is set by the friction law's slope at zero slip, ``c_f = 1.5·μ_s·Q/v_s``
≈ 5.3e3 N s/m per race contact at the study's 3.55 kN, a real-axis rate
λ_f ≈ 5.4e5 1/s that limits RK4 to 5.2e-6 s (:func:`rvcore.integrate.rk4.rk4_time_step`),
and behind it by the contact oscillation, ω_n = √(2k/m_b) ≈ 1.1e5 rad/s. Both are
implicit here. The friction is stiff through the rings too: a ball drags the inner ring
and its cage (``rvcore.dynamics.tangent``), so the implicit part couples every ball with the
ring, in every stage.

The scheme is an additive Runge–Kutta (IMEX-ARK) method on ``dy/dt = f(t, y) + g(t, y)``
with ``g = J·(y − ỹ(t))``: ``J`` the frozen tangent of :mod:`rvcore.dynamics.tangent` on the
implicit unknowns (the ring's pose and rates, every ball's centre, velocity and spin)::

    J = [[0, I], [−M⁻¹·K, −M⁻¹·D]]

``K`` the Hertz stiffness of the ball–race contacts on the positions (with the groove's
geometric stiffness, :func:`rvcore.dynamics.tangent.groove_blocks`), ``D`` the velocity
tangent of the friction and dampers, and ``f = F − g`` the rest. The splitting is exact
for any ``J`` and any reference ``ỹ``: the pair's order does not depend on them, only its
stability, so ``J`` may be frozen over several steps ("Step", below). Explicit tableau:
classical RK4 (``c = 0, ½, ½, 1``). Implicit tableau: an ESDIRK with the same nodes, the
same weights ``b̂ = b`` and the constant diagonal γ = 1/6, so one factorization serves
the three implicit stages. Stage i (e the deviation from the reference)::

    ê   = h·Σ_{j<i} (a_ij·F_j + (â_ij − a_ij)·g_j) − (ỹ_i − y_n)
    e_x = ê_x + h·γ·e_v
    (M + h·γ·D + (h·γ)²·K)·e_v = M·ê_v − h·γ·K·ê_x
    Y_i = ỹ_i + e,   g_i = (e − ê)/(h·γ)   (g_x = e_v),   g_1 = 0
    y_{n+1} = y_n + h·Σ_i b_i·F_i

with ``F_i = F(Y_i)`` the full right-hand side: four evaluations per step, as RK4.
``M + h·γ·D + (h·γ)²·K`` is block-arrowhead (each ball coupled only to the ring); it is
solved exactly through the Schur complement on the ring, O(Z) per stage. With ``b̂ = b``
the velocity update weighs the stages' full forces by ``b`` alone, so ``Σ b_i·T(Y_i)`` is
the drive torque whose impulse the step gave the balls (the step's torque that
:func:`rvcore.integrate.loop.integrate` accumulates). A change to ``b̂ ≠ b`` must change that.

The implicit tableau: all-pass
------------------------------
Its stability function is ``R(z) = ((1 + z/6)/(1 − z/6))³`` (that of three trapezoidal
steps of h/3), so ``|R(iy)| = 1``: the contact oscillation, now in the implicit part, is
integrated without numerical damping at any ω_n·h, and the energy its ring-downs carry
leaves through the damper, not the scheme. It is the only such function the structure
allows: with the denominator ``(1 − γz)³``, ``|R(iy)| = 1`` needs the numerator
``(1 + γz)³``, and ``R = e^z + O(z²)`` then fixes γ = 1/6; its z³ coefficient is
1/6 + 1/108, so the implicit tableau, and the pair, are of order 2 (order 3 and
``|R(iy)| = 1`` exclude each other here). Of the one-parameter family of tableaux with
this R (rows summing to c, ``b̂ = b``; ``â_43`` its parameter, ``â_32 = 2/(27·â_43)``), the
one below is stiffly accurate: its last row is ``b̂``, so the last stage is the step's
end. Its stage values of a stiff mode are at most 2× the step's start on the real and
imaginary axes (the family's least: the second stage alone reaches 2 at infinity; 2.65
at ``â_43 = ½``). On the bearing it keeps the energy of a combined load's oscillation
better than ``â_43 = ½`` did, by 2.3× (docs/performance.md, "IMEX at MODEL_VERSION
11"); a single Hertz contact shows no such gain, so this is a measured property of the
bearing, not of the tableau. The price:
an all-pass function cannot be L-stable, ``R(−x) → −1`` as x → ∞, so a stiff friction
mode is damped per step by ``|R(−λ_f·h)|`` only, which bounds the step (below).

Reference
---------
Linearised about ``y_n``, a ball's orbit is not a small deviation: over a step its
centre leaves the tangent by v²h²/(2ρ) (about 1 µm at 300 rad/s and 25 µs), which the
implicit Hertz stiffness reads as a change of penetration, and the explicit stages'
O(h²) error of the orbit's position turns into stage forces of order (ω_n·h)²·m_b·a.
So the balls' stages are deviations from ``ỹ(t)``: ``y_n`` turned about the bearing's
axis at the ball's orbital speed (centre, velocity and spin), and ``ê`` subtracts the
explicit row's own quadrature of ``ỹ'`` (the row's one entry, at the previous node) where
it would subtract ``ỹ_i − y_n``: then a ball on that orbit stays on it exactly, and the
centrifugal balance (docs/model.md §9.7) does not depend on the step. The ring and cages are
not turned (``ỹ = y_n`` for the ring; the cages are explicit).

Step
----
What bounds it (:func:`rvcore.integrate.imex.imex_time_step`):

- the stiff friction modes, implicit, damped per step by ``|R(−λ_f·h)|``: the step keeps
  ``λ_f·h ≤`` :data:`FRICTION_LIMIT`, where that factor is :data:`FRICTION_DAMPING`.
  Beyond it the friction's slip oscillates from step to step, and the law's saturation
  turns that into a chatter that dissipates energy the physics does not (the energy
  balances of tests/core/test_energy_balance.py broke, when measured with the loads' work
  then sampled; docs/performance.md, "Three more routes"); the chatter also moves the
  loads the tangents follow, so they are taken again at most steps: without the bound the
  study case at 30 kN took 1.12× the time at a 1.11× longer step (docs/performance.md,
  "The damping tableau and a longer steady step"). λ_f is RK4's friction-and-damping
  rate (:func:`rvcore.integrate.rk4.rk4_time_step`), so the IMEX step is
  ``FRICTION_LIMIT/2.785`` ≈ 8.2 times RK4's wherever friction binds RK4;
- the friction law's falling slope between v_s and v_d, explicit (at most
  ``1.5·(μ_s − μ_d)/(v_d − v_s)·Q``), on RK4's real-axis limit (where the loads are held,
  a guard instead: "Where the loads are held", below);
- the race contacts' oscillation, implicit and undamped: an accuracy bound,
  ``ω_n·h ≤`` :data:`CONTACT_LIMIT` = 5 at the peak contact load. The tableau turns its
  phase per step by ``6·atan(ω_n·h/6)`` against ω_n·h, a frequency error of about
  (ω_n·h)²/108: 12 % at ω_n·h = 4, 0.8 of the limit. Unlike RK4's, the scheme does not
  damp high-frequency motion. On the study bearing (660 °/s, 10 kN axial) the phase
  metrics move by at most 0.44 % at 30 kN against a tenth of the step (ω_n·h = 3.6, the
  friction's bound; docs/model.md §9.6: 1 %); against a tenth of the MODEL_VERSION 18
  step, by 0.27 % at 30 kN and 1.3 % at 20 kN (ω_n·h = 4, this bound), where that step
  gave 0.48 % and 1.9 % (docs/performance.md, "The step at MODEL_VERSION 19").

Until MODEL_VERSION 19 a race contact that closes within a step bounded it too: its
stiffness is not in the step's tangents, so for that step it is explicit, on the explicit
tableau's imaginary-axis limit. Now such a step is taken again in substeps ("Pocket impacts",
below): at each stage every ball's race loads are compared with the limit
``(Q₀^⅓ + c_on/h²)³`` set when the tangents were taken at the load ``Q₀``
(:func:`onset_constant`: the stiffness the tangents miss, ``1.5·K^(2/3)·(Q^⅓ − Q₀^⅓)``,
within :data:`ONSET_LIMIT` = 2√2 on ``√(Δk/m_b)·h`` at 0.8 of it). A contact that passes
it has the step taken again in ``n`` substeps with ``n² ≥ h²·Q^⅓/c_on``, each with its own
tangents. On the study cycle the steps taken again, for a contact's onset or a pocket
impact, are 0.5 % of the steps (701 of 138,000 at 30 kN).

The pair is of order 2, and so is its trajectory: on the 12-ball section its error,
about 1e-4 of the ring's travel at the default step, shifts the pocket impacts of the
steady phase, which is why IMEX misses docs/model.md §9.6 there and meets it on the
study bearing (docs/performance.md, "§9.6 on the study bearing"). The pockets' stiffness
and the cage–land contact stay explicit (``rvcore.dynamics.tangent``): their rates are
far below the race contacts' (a ball on a 100 N pocket contact: 4e4 rad/s against ω_n
1.1e5), within the explicit stages' limits at these steps; where a pocket impact is not
resolved, the pocket check takes the step again.

The tangents and the factorization are evaluated again when the contacts they were
taken at have moved, and at least every :data:`TANGENT_MAX_STEPS` steps; between, a step
costs four right-hand sides and three solves. The splitting stays exact with a frozen
``J``: what a stale tangent leaves out (``J_true − J``) is integrated by the explicit
tableau, so it must stay within that tableau's limits (for a closing contact, the onset
check above), and the energy a large oscillation
keeps depends on it (tests/core/test_imex_conservation.py). Both follow the race contacts'
loads: ``D`` of a contact in micro-slip is proportional to its load, and ``K`` to its
cube root. So at each step's end (the last stage, at t + h) every ball's inner- and
outer-race loads are compared with those the tangents were taken at; where one has moved
by more than :data:`TANGENT_LOAD_TOL` of the case's peak contact load
(:func:`rvcore.integrate.imex.tangent_load_tolerance`), the next step evaluates them again. A
ring-down or an impact then refreshes them every step; a running bearing, whose loads
move by a fraction of a newton per step, every :data:`TANGENT_MAX_STEPS`
(docs/performance.md, "IMEX at MODEL_VERSION 11").

Where the loads are held
------------------------
Where every channel of the profile is held (the steady phase of the study cycle; the
step schedule, :mod:`rvcore.integrate.schedule`), no contact closes for a load's change
and nothing drives the contact oscillation but the balls' passage through the load zone.
There the implicit part takes the held tableau instead of the all-pass one: the same
nodes and weights (``b̂ = b``, so the same drive impulse), γ = 1/3 (:data:`HELD_GAMMA`),
and the stability function ``R(z) = (1 − z²/6)/(1 − z/3)³``: of order 2, A-stable
(``|Q(iy)|² − |P(iy)|² = y⁴/108 + y⁶/729 ≥ 0``) and L-stable. It damps what the all-pass
tableau kept: a stiff friction mode (``R(−x) → 0``), and the contact oscillation, of which
it keeps 0.72 a step at ω_n·h = 4.8 and 0.996 at 1 (phase per step 3.04 rad against
4.8), so the oscillation, excited there by little but the load zone, is damped instead of
carried at a wrong frequency. Its free entries (:data:`HELD_I32`, :data:`HELD_I42`,
:data:`HELD_I43`) are the rational member whose stage values of a stiff mode stay within
1.25× the step's start. The step there (:func:`imex_time_step` with ``held``) is bounded
by the contact oscillation's accuracy alone, ``ω_n·h ≤`` :data:`HELD_CONTACT_LIMIT` = 7.5
(× 0.8): the friction adds no bound, and the friction law's falling slope, which would
(the explicit part's real-axis limit, as elsewhere), is left to a guard
(:func:`falling_guard`): a step at whose start a race contact slides faster than the
law's ``v_s`` is taken in substeps within that bound (the study's race contacts slide at
0.7–7 mm/s in every phase, against v_s = 100 mm/s). Over the study grid the held step is
1.29×, 1.16×, 1.28×, 1.36× and 1.47× MODEL_VERSION 21's at 20–40 kN (58.8, 52.6, 55.6,
52.6 and 52.6 µs). The step changes inside the loop, at output times, and each stretch
starts with new tangents, its own pocket tolerance, guard and tableau
(:func:`begin_segment`; the tangents' blocks carry ``h·γ``), and a held stretch ends
:data:`rvcore.integrate.schedule.HELD_END_MARGIN` (10 ms) before its window, so that the
next phase starts from the all-pass tableau's motion. Measured on the study
bearing (660 °/s, 10 kN axial): every steady metric within 0.35 %, 0.11 % and 0.20 % of a
tenth of the step at 20, 30 and 40 kN, and the case 0.80–0.85× as long (docs/performance.md,
"The held tableau (MODEL_VERSION 22)"); an oscillation step of ω_n·h = 7.2 (66.7 µs) moved
the steady sliding-speed peak by 6–8 %. Where the step is set by hand
(``SolverSettings.time_step``) it is the same throughout, and so is the tableau. The
held tableau and step also run where the ring stands still and no load grows (the study
cycle's unload; :func:`rvcore.integrate.schedule.unloading_windows`): no ball rolls, the
rings follow the falling loads slowly against the contact oscillation, and no contact
closes for them.

Flexible rings
--------------
A flexible ring's modes (:mod:`rvcore.dynamics.ring_modes`) are implicit unknowns too,
with their own stiffness and damping and the race contacts' Hertz stiffness, damper and
groove stiffness on them (:func:`rvcore.dynamics.tangent.modal_blocks`): the stage matrix
gains the modes' rows and columns, solved through their Schur complement beside the
arrowhead system (:func:`rvcore.integrate.arrowhead.factor_modes` with the tangents,
:func:`rvcore.integrate.arrowhead.solve_coupled` each stage). So the modes add no bound to
the step; the friction does not drive them (docs/model.md §16.1).

Pocket impacts
--------------
A ball that strikes its cage pocket does so in about three steps (ω_p·h ≈ 1), and a
step that cuts through the impact makes or loses a few per cent of its energy, implicit
or not (:mod:`rvcore.integrate.pocket_check`). So each step checks every pocket it touched: where
the pocket's elastic energy and the work the step gave its Hertz force disagree by more
than a tolerance, the step is taken again from its start in substeps. The first substep
of each try takes the tangents at its start; a later one takes them again as a step does,
where the race contacts' loads have moved from those they were taken at by the load
tolerance or after :data:`TANGENT_MAX_STEPS` substeps, and keeps them otherwise: the
pockets are explicit, so an impact alone does not stale them (docs/performance.md, "Retakes
that keep their tangents"). The first try takes the fewest substeps (at least :data:`FIRST_SUBSTEPS`,
doubling) that would bring the step's error ε to the tolerance if it fell as the
square of the substeps' share of the step, the scheme's order (n substeps of h/n, each
erring as (h/n)³): n² ≥ |ε|/tol. Then twice as many, until the substeps together keep
every pocket's energy over the step to the same tolerance, or :data:`SUBSTEPS` were
taken (kept then unchecked, as every retake was until MODEL_VERSION 18). So a retake
passes the check the step itself failed with as few substeps as it can: a bearing whose
balls strike their pockets often (256 balls at 660 °/s retake one step in six) paid 8
substeps of the whole bearing for each, where 2 mostly keep the energy
(docs/performance.md, "The shared kernel cache and the cost per ball-step"). The
tolerance is an energy, :data:`POCKET_ENERGY_TOL` of a race contact's elastic energy at
the case's peak contact load (the load the step is sized on), scaled as the step's cube
so that it puts no floor under the drift's convergence
(:func:`rvcore.integrate.imex.pocket_energy_tolerance`): what matters is the energy the
bearing gains or loses, and a tolerance relative to
each pocket's own energy would take the steady pocket contacts of a running bearing,
whose errors are tiny in joules, in substeps too (4 % of the study cycle's steps at 1e-3 of
their energy, against 0.4 % here: docs/performance.md).
"""
from __future__ import annotations

import math

import numpy as np
from .._numba import kernel

from .arrowhead import (N_SOLVE_FIELDS, WS, factor, factor_modes, harmonic_width, modal_block_rows, solve,
                        solve_coupled)
from ..dynamics.tangent import N_FX, N_JWORK, N_SCHUR
from ..dynamics.rhs import B_PP, B_PV, B_QI, B_QO, D_DRIVE_POWER, D_DRIVE_TORQUE, D_MAX_SLIDE2, rhs_jac, rhs_stage
from ..bearing.layout import (BALL_STATES, P_DAMP_C, P_DAMPING, P_LAW, P_RING_IT, P_RING_M, P_TILT_HELD,
                              R_BALL0, R_IB, R_MB, R_POCKET0, R_Z)
from .pocket_check import pocket_energy_error
from .schedule import SEG_HELD, SEG_LOAD_TOL, SEG_SLIP2, SEG_SUB_DT, SEG_TOL
from .protocol import S_OWN, S_REFRESHES, S_SUBSTEPPED, S_SUBSTEPS
from .protocol import new_state as new_counters
from .rk4 import RK4_REAL_LIMIT, stage_weighted_inertia
from .step_size import row_rates
from ..bearing.laws import FRICTION_LAW_SIZE, LAW_ON, LAW_V_S
from ..contact.laws import friction_falling_slope, friction_slope_at_zero_slip
from ..dynamics.ring_modes import FAMILIES, family_states, flexible, modal_implicit_masses
from ..dynamics.rhs import rhs
from ..recording.plan import add_substep_integrals, in_window

# ---- the tableaux (explicit a, b; implicit â, b̂), nodes c = (0, ½, ½, 1)
A21, A32, A43 = 0.5, 0.5, 1.0
B1, B2, B3, B4 = 1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0
#: The implicit tableau: the ESDIRK whose stability function is the all-pass
#: ((1 + z/6)/(1 − z/6))³ (module docstring), γ = 1/6, b̂ = b, rows summing to c. Of the
#: family (``I32 = 2/(27·I43)``, ``I42 = 10/9 − I43 − 4/(27·I43)``), ``I43 = 1/3``: the
#: stiffly accurate member (last row ``b̂``), with the least stage values.
GAMMA = 1.0 / 6.0
I32 = 2.0 / 9.0
I42, I43 = 1.0 / 3.0, 1.0 / 3.0
I21 = 0.5 - GAMMA
I31 = 0.5 - GAMMA - I32
I41 = 1.0 - GAMMA - I42 - I43
IB1, IB2, IB3, IB4 = B1, B2, B3, B4
#: The held tableau, where the loads and speed are held (module docstring, "Where the
#: loads are held"): an ESDIRK with the same nodes and weights (``b̂ = b``) and γ = 1/3,
#: whose stability function is ``(1 − z²/6)/(1 − z/3)³``: order 2, A- and L-stable. Its
#: rows sum to c; ``HELD_I32`` and ``HELD_I42``, ``HELD_I43`` are its free entries
#: (``â_31 = 0``, ``â_41 = 5/9``), chosen so that ``R(∞) = 0`` with a stiff mode's stage
#: values at most 1.25× the step's start on the real and imaginary axes.
HELD_GAMMA = 1.0 / 3.0
HELD_I32 = 1.0 / 6.0
HELD_I42, HELD_I43 = 5.0 / 9.0, -4.0 / 9.0
#: Largest ``λ_f·h`` (λ_f the friction's rate at zero slip, on the negative real axis):
#: where the implicit tableau damps a friction mode by at least :data:`FRICTION_DAMPING`
#: per step. ``R(−x) = ((6 − x)/(6 + x))³`` tends to −1 as x → ∞ (an all-pass function
#: cannot be L-stable), so the step must keep x below the root of ``|R(−x)| = ρ``:
#: ``x = 6·(1 + ρ^⅓)/(1 − ρ^⅓)``.
FRICTION_DAMPING = 0.2
FRICTION_LIMIT = 6.0 * (1.0 + FRICTION_DAMPING ** (1.0 / 3.0)) / (1.0 - FRICTION_DAMPING ** (1.0 / 3.0))
#: Limit on ``ω_n·h``, the race contacts' oscillation at the peak contact load
#: (:func:`rvcore.integrate.step_size.row_rates`), implicit and undamped: an accuracy bound.
#: The tableau turns its phase per step by ``6·atan(ω_n·h/6)``, a frequency error of 12 %
#: at 0.8 of the limit (ω_n·h = 4). There the study bearing's phase metrics at 30 kN
#: (its friction bound lifted, in a probe) move by at most 0.44 % against a tenth of the
#: step, and by 1.2 % at ω_n·h = 4.9 (docs/model.md §9.6: 1 %; docs/performance.md, "The
#: step at MODEL_VERSION 19").
CONTACT_LIMIT = 5.0
#: :data:`CONTACT_LIMIT` where the loads and speed are held, with the held tableau (module
#: docstring, "Where the loads are held"): it damps the contact oscillation (0.72 kept a
#: step at ω_n·h = 4.8 and 0.63 at 6.0, the limit's 0.8) instead of carrying it at a wrong
#: frequency.
#: Measured on the study bearing (660 °/s, 10 kN axial, against a tenth of the step): every
#: steady metric within 0.35 % at 20 kN (58.8 µs, ω_n·h = 6.0); at ω_n·h = 7.2 (66.7 µs,
#: the limit 9 in a probe) the steady sliding-speed peak moved by 6 % at 20 kN and 8 % at
#: 30 kN (docs/performance.md, "The held tableau (MODEL_VERSION 22)").
HELD_CONTACT_LIMIT = 7.5
#: Limit on ``ω_c·h`` for a race contact's stiffness that the tangents do not hold, such
#: as a contact that closes within a step: for that step it is explicit, on the explicit
#: tableau's imaginary-axis limit 2√2; ``ω_c = √(Δk/m_b)``, one contact on the ball (the
#: other side open, as for a ball that rattles). A step where a contact passes it is taken
#: again in substeps (:func:`onset_constant`, :func:`imex_step`).
ONSET_LIMIT = 2.0 * math.sqrt(2.0)
#: The share of :data:`ONSET_LIMIT` the onset check keeps (:func:`onset_constant`): the
#: default step safety's.
ONSET_SAFETY = 0.8
#: Most steps one evaluation of the tangents and one factorization serve (module
#: docstring, "Step"), whatever the loads.
TANGENT_MAX_STEPS = 8
#: A race contact's load may move by this fraction of the case's peak contact load from
#: the load the tangents were taken at before they are evaluated again (module docstring,
#: "Step"). A stale friction tangent leaves ``D_true − D`` to the explicit tableau, whose
#: real-axis limit 2.785 is 15 % of the implicit one at the default step
#: (``0.8·FRICTION_LIMIT``): the bound for stability. Accuracy asks for less: in the
#: ring-down of docs/model.md §9.4(a) the loads move by 0.1–1 % of the peak per step, and
#: tangents that lag 1 % leave 2.5× the drift of tangents taken at every step
#: (docs/performance.md, "IMEX at MODEL_VERSION 11"). A running bearing's loads move
#: by a fraction of a newton per step, so :data:`TANGENT_MAX_STEPS` sets its refreshes.
#: Read at each call of :func:`rvcore.integrate.imex.tangent_load_tolerance`, so that a test can
#: set it.
TANGENT_LOAD_TOL = 0.001
#: A step is taken again in substeps where some pocket's energy error
#: (:mod:`rvcore.integrate.pocket_check`) passes this fraction of the elastic energy of a race
#: contact at the case's peak contact load, at the step ``h₀ = 4/ω_n`` and scaled as
#: the step's cube (:func:`rvcore.integrate.imex.pocket_energy_tolerance`; module docstring,
#: "Pocket impacts"): 2e-7 at the default step (ω_n·h = 4 since MODEL_VERSION 19). Read at
#: each call of that function, so that a test can set it.
POCKET_ENERGY_TOL = 2e-7
#: The most substeps of a step taken again: an eighth of the step keeps a Hertz impact's
#: energy to 5e-5 (tests/core/test_imex_conservation.py), then with every substep's own
#: tangents.
SUBSTEPS = 8
#: The fewest substeps of a step's first retake; their number doubles until the step's
#: pockets keep their energy, to :data:`SUBSTEPS` (module docstring, "Pocket impacts"). Read at each
#: call of :func:`new_work`, so that a test can set it (:data:`SUBSTEPS`: every retake in
#: eighths, as until MODEL_VERSION 18).
FIRST_SUBSTEPS = 2

#: Rows of ``work``: F_1..F_4, the stage state, g_1..g_4, 1/mass, mass (both 0 off the
#: implicit velocities), 1 at the implicit velocities and 1 at the implicit positions (the
#: balls' centres, the ring's pose; 0 elsewhere: masks that keep the stage's loop free of
#: branches), the balls' reference offset ỹ − y_n, the step's start y_n, and per ball
#: (indexed as the pockets) the pocket's elastic energy at y_n, the stages' Σ b_i·P_i,
#: and whether any stage touched the pocket; per ball the inner- and outer-race loads the
#: tangents were taken at; ``work[W_SET, 0]`` is the pocket check's tolerance [J],
#: ``work[W_SET, 1]`` the tangents' load tolerance [N], ``work[W_SET, 2]`` the modes'
#: block's first row, ``work[W_SET, 3]`` the first retake's substeps
#: (:data:`FIRST_SUBSTEPS`), ``work[W_SET, SET_ONSET]`` the onset constant c_on
#: [N^(1/3) s^2] (:func:`onset_constant`) and ``work[W_SET, SET_ONSET_LOAD]`` the largest
#: race load [N] a stage of the step gave a contact beyond its onset limit (0: none); per
#: ball the reference's rotations (:func:`_orbit_rotations`), and the pockets'
#: ``Σ b_i·P_i`` over a retake's substeps, each substep's weighed by its share of the
#: step; per ball the inner- and outer-race onset limits [N] (``W_QLIM``, two rows: the
#: loads beyond which the tangents miss too much stiffness, module docstring, "Step");
#: ``work[W_SET, SET_GAMMA]``, ``SET_I32``, ``SET_I42`` and ``SET_I43`` the stretch's
#: implicit tableau (γ and its free entries; the all-pass one, or the held one where the
#: loads are held: :func:`begin_segment`); ``work[W_SET, SET_SLIP2]`` and ``SET_SUB_DT`` the
#: stretch's falling-slope guard (:func:`falling_guard`: the squared slip [m² s^-2] above
#: which a step is taken in substeps of at most ``SET_SUB_DT`` [s]; 0 and 0: none).
W_F, W_TMP, W_G, W_INVM, W_M, W_ISV, W_ISP, W_OFF = 0, 4, 5, 9, 10, 11, 12, 13
W_Y0, W_PV0, W_PACC, W_TOUCH, W_SET, W_QREF, W_ROT, W_PSUM, W_QLIM, W_SF = (14, 15, 16, 17, 18, 19, 21, 22, 23, 25)
N_WORK = 25      # and the rows of the packed factors from W_SF (new_work)
SET_ONSET, SET_ONSET_LOAD, SET_GAMMA, SET_I32, SET_I42, SET_I43, SET_SLIP2, SET_SUB_DT = 4, 5, 6, 7, 8, 9, 10, 11


def new_work(model, pocket_tolerance, load_tolerance):
    """``(work, jwork, schur)`` for :func:`rvcore.integrate.loop.integrate` with the IMEX method;
    ``pocket_tolerance`` [J] is the pocket check's and ``load_tolerance`` [N] the
    tangents' (:func:`imex_step`)."""
    n = model.n_states
    modal = modal_implicit_masses(model)
    # from W_SF the block solve's packed factors, a row of the bearing in N_SOLVE_FIELDS·WS
    work = np.zeros((N_WORK + -(-model.rows.shape[0] * N_SOLVE_FIELDS * WS // n), n))
    inv_m = work[W_INVM]
    p, rows = model.params, model.rows
    inv_m[5:8] = 1.0 / p[P_RING_M]
    # a held ring's tilts (InnerRing.tilt "held") are constrained: an inertia 1e12 times
    # its own keeps the implicit solve from giving them a rate (its coupling to the
    # balls then drops out of the Schur complement to 1e-12), and the right-hand side
    # reads them as 0 whatever they hold
    inv_m[8:10] = 1.0 / (p[P_RING_IT] * (1e12 if p[P_TILT_HELD] != 0.0 else 1.0))
    work[W_ISP, 0:5] = 1.0
    for r in range(rows.shape[0]):     # the implicit unknowns: the ring's and balls' velocities
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            inv_m[b + 3:b + 6] = 1.0 / rows[r, R_MB]
            inv_m[b + 6:b + 9] = 1.0 / rows[r, R_IB]
            work[W_ISP, b:b + 3] = 1.0
    # a flexible ring's modes (rvcore.dynamics.ring_modes): implicit with the contacts'
    # stiffness and damping on them (arrowhead.factor_modes, solve_coupled), their block of
    # rows after the packed factors, from work[W_SET, 2]
    for amplitude, rate, m in modal:
        inv_m[rate] = 1.0 / m
        work[W_ISP, amplitude] = 1.0
    work[W_M] = np.where(inv_m > 0, 1.0 / np.where(inv_m > 0, inv_m, 1.0), 0.0)
    work[W_ISV] = np.where(inv_m > 0, 1.0, 0.0)
    work[W_SET, 0] = pocket_tolerance
    work[W_SET, 1] = load_tolerance
    if not (FIRST_SUBSTEPS >= 1 and SUBSTEPS % FIRST_SUBSTEPS == 0
            and (SUBSTEPS // FIRST_SUBSTEPS) & (SUBSTEPS // FIRST_SUBSTEPS - 1) == 0):
        raise ValueError(f"FIRST_SUBSTEPS = {FIRST_SUBSTEPS}: SUBSTEPS ({SUBSTEPS}) over it must be a power of two")
    work[W_SET, 3] = FIRST_SUBSTEPS
    work[W_SET, SET_ONSET] = onset_constant(model)
    _set_tableau(work, False)
    if not modal:
        return work, np.zeros((model.n_balls + 1, N_JWORK)), np.zeros((N_SCHUR, 5))
    orders = max(family_states(model, name)[0] for name in FAMILIES)
    work[W_SET, 2] = work.shape[0]
    work = np.vstack([work, np.zeros((modal_block_rows(len(modal), orders, n, model.rows.shape[0]), n))])
    # a flexible ball's jwork columns: its modes' (N_FX), the shape φ (2 values an order) and
    # the harmonics m < 2·orders − 1 (cos and sin, each in arrowhead.harmonic_width) that
    # arrowhead.factor_modes sums
    columns = N_JWORK + N_FX + 2 * orders + 2 * harmonic_width(orders)
    return work, np.zeros((model.n_balls + 1, columns)), np.zeros((N_SCHUR, 5))


@kernel(inline=True)
def _implicit_stage(i, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag, bdiag,
                    a1, a2, a3, i1, i2, i3, c):
    """Stage ``i`` (1–3, 0-based): Ŷ, the solve, g_i and F_i (module docstring). ``i1``
    weighs g_1, which is 0 (the reference at t_n is y_n): it drops out."""
    n = y.size
    tmp, g, f = work[W_TMP], work[W_G + i], work[W_F + i]
    f0, f1, f2 = work[W_F], work[W_F + 1], work[W_F + 2]
    g1, g2 = work[W_G + 1], work[W_G + 2]
    mass, isv, isp = work[W_M], work[W_ISV], work[W_ISP]
    for m in range(n):
        s = a1 * f0[m]         # g_1 = 0: the reference at t_n is y_n
        if i >= 2:
            s += a2 * f1[m] + (i2 - a2) * g1[m]
        if i >= 3:
            s += a3 * f2[m] + (i3 - a3) * g2[m]
        tmp[m] = dt * s        # Ŷ − y_n
    # The balls' stages are solved as deviations from a reference ỹ(t): y_n turned about
    # the bearing's axis at the ball's orbital speed Ω = (x·v_y − y·v_x)/ρ² (centre,
    # velocity and spin; module docstring, "Reference"). ê = Ŷ − y_n − h·a·ỹ'(t_prev)
    # (the explicit row's own quadrature of ỹ', one node back) and Y = ỹ(t_i) + e, so that
    # a ball on that orbit stays on it exactly. Rotations are Cayley's (orthogonal).
    off, rot = work[W_OFF], work[W_ROT]
    ap = a1 if i == 1 else (a2 if i == 2 else a3)
    # this stage's rotations (_orbit_rotations): through Ω·c·h, and the explicit row's
    # previous node's, through Ω·h/2 (stages 2 and 3) or 0 (stage 1)
    k_now = 1 if c == 0.5 else 5
    k_prev = 7 if i == 1 else 3
    for r in range(rows.shape[0]):
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            om = rot[b]
            cm1, sn = rot[b + k_now], rot[b + k_now + 1]
            cp1, snp = rot[b + k_prev], rot[b + k_prev + 1]
            w = dt * ap * om
            for o in (0, 3, 6):         # centre, velocity, spin: the x and y components
                ux, uy = y[b + o], y[b + o + 1]
                off[b + o] = cm1 * ux - sn * uy
                off[b + o + 1] = sn * ux + cm1 * uy
                # h·a·Ω·(ẑ × R(φ_prev)·u)
                tmp[b + o] -= w * -(snp * ux + cp1 * uy)
                tmp[b + o + 1] -= w * (cp1 * ux - snp * uy)
    for m in range(n):
        g[m] = tmp[m]          # ê, for g_i below
    hg = dt * work[W_SET, SET_GAMMA]
    if flexible(params):       # the modes among the unknowns (their positions done there)
        solve_coupled(tmp, g, schur, rows, mass, work[W_SF:].reshape(-1), jwork, params,
                      work[int(work[W_SET, 2]):], hg)
    else:
        solve(tmp, schur, rows, mass, work[W_SF:].reshape(-1))
    inv_hg = 1.0 / hg
    # the positions: e_x = ê_x + h·γ·e_v and g_x = e_v (the velocities still increments)
    for m in range(5):
        g[m] = tmp[m + 5]
        tmp[m] = tmp[m] + hg * g[m]
    for r in range(rows.shape[0]):
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            for m in range(b, b + 3):
                g[m] = tmp[m + 3]
                tmp[m] = tmp[m] + hg * g[m]
    # the velocities: g_v = (e_v − ê_v)/(h·γ); 0 off the implicit unknowns
    for m in range(n):
        g[m] = isv[m] * ((tmp[m] - g[m]) * inv_hg) + isp[m] * g[m]
        tmp[m] += y[m] + off[m]
    rhs_stage(t + c * dt, tmp, f, params, rows, arcs, pockets, table, meta, diag, bdiag)
    return diag[D_DRIVE_TORQUE]


@kernel(inline=True)
def _orbit_rotations(y, dt, rows, rot):
    """Per ball, from its state in ``y``, into ``rot[b:b + 9]`` (b the ball's first state):
    its orbital speed Ω = (x·v_y − y·v_x)/ρ², the Cayley rotation's (cos − 1, sin) through
    Ω·h/2 and (cos, sin) through the same angle, (cos − 1, sin) through Ω·h, and (cos, sin)
    through 0: what the three stages turn the reference by (:func:`_implicit_stage`). Once
    a step, not once a stage: they depend on the step's start alone."""
    for r in range(rows.shape[0]):
        b0 = int(rows[r, R_BALL0])
        for j in range(int(rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            px, py, vx, vy = y[b], y[b + 1], y[b + 3], y[b + 4]
            om = (px * vy - py * vx) / (px * px + py * py)
            rot[b] = om
            phi = om * 0.5 * dt
            d = 1.0 / (1.0 + 0.25 * phi * phi)
            rot[b + 1], rot[b + 2] = -0.5 * phi * phi * d, phi * d
            rot[b + 3], rot[b + 4] = 1.0 - 0.5 * phi * phi * d, phi * d
            phi = om * 1.0 * dt
            d = 1.0 / (1.0 + 0.25 * phi * phi)
            rot[b + 5], rot[b + 6] = -0.5 * phi * phi * d, phi * d
            phi = om * 0.0 * dt
            d = 1.0 / (1.0 + 0.25 * phi * phi)
            rot[b + 7], rot[b + 8] = 1.0 - 0.5 * phi * phi * d, phi * d


@kernel(inline=True)
def _pocket_power(work, bdiag, weight):
    """Add ``weight·P`` of the stage just evaluated to each ball's Σ b_i·P_i, and mark
    the balls whose pocket it touched; keep in ``work[W_SET, SET_ONSET_LOAD]`` the largest
    race load of the stage beyond its contact's onset limit (``work[W_QLIM]``)."""
    worst = work[W_SET, SET_ONSET_LOAD]
    for k in range(bdiag.shape[0]):
        work[W_PACC, k] += weight * bdiag[k, B_PP]
        if bdiag[k, B_PV] > 0.0:
            work[W_TOUCH, k] = 1.0
        qi, qo = bdiag[k, B_QI], bdiag[k, B_QO]
        if qi > work[W_QLIM, k]:
            worst = max(worst, qi)
        if qo > work[W_QLIM + 1, k]:
            worst = max(worst, qo)
    work[W_SET, SET_ONSET_LOAD] = worst


# compiled once, not inlined: imex_step calls it for the step and for each substep
@kernel
def _stages(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur):
    """The three implicit stages and the update ``y_{n+1} = y_n + h·Σ b_i·F_i`` (b̂ = b:
    the g_i drop out; module docstring); returns ``Σ_{i≥2} b_i·T(Y_i)`` and
    ``Σ_{i≥2} b_i·T(Y_i)·ω(t_i)``."""
    _orbit_rotations(y, dt, rows, work[W_ROT])
    # the stretch's implicit tableau (begin_segment): γ and the free entries, the rows summing to c
    gamma, i32, i42, i43 = work[W_SET, SET_GAMMA], work[W_SET, SET_I32], work[W_SET, SET_I42], work[W_SET, SET_I43]
    i21, i31, i41 = 0.5 - gamma, 0.5 - gamma - i32, 1.0 - gamma - i42 - i43
    torque = B2 * _implicit_stage(1, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag,
                                  bdiag, A21, 0.0, 0.0, i21, 0.0, 0.0, 0.5)
    _pocket_power(work, bdiag, B2)
    power = B2 * diag[D_DRIVE_POWER]
    torque += B3 * _implicit_stage(2, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag,
                                   bdiag, 0.0, A32, 0.0, i31, i32, 0.0, 0.5)
    _pocket_power(work, bdiag, B3)
    power += B3 * diag[D_DRIVE_POWER]
    torque += B4 * _implicit_stage(3, t, dt, y, work, jwork, schur, params, rows, arcs, pockets, table, meta, diag,
                                   bdiag, 0.0, 0.0, A43, i41, i42, i43, 1.0)
    _pocket_power(work, bdiag, B4)
    power += B4 * diag[D_DRIVE_POWER]
    f0, f1, f2, f3 = work[W_F], work[W_F + 1], work[W_F + 2], work[W_F + 3]
    for m in range(y.size):
        y[m] += dt * (B1 * f0[m] + B2 * f1[m] + B3 * f2[m] + B4 * f3[m])
    return torque, power


@kernel(inline=True)
def _tangents_stale(work, bdiag):
    """Whether a ball's inner- or outer-race load in ``bdiag`` has moved from the one the
    tangents were taken at (``work[W_QREF]``, ``work[W_QREF + 1]``) by more than the
    load tolerance ``work[W_SET, 1]`` (module docstring, "Step")."""
    tol = work[W_SET, 1]
    for k in range(bdiag.shape[0]):
        if (abs(bdiag[k, B_QI] - work[W_QREF, k]) > tol
                or abs(bdiag[k, B_QO] - work[W_QREF + 1, k]) > tol):
            return True
    return False


@kernel
def imex_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, refresh,
              inner):
    """Advance ``y`` by one IMEX step of ``dt``.

    On entry ``work[W_F]`` holds ``F(y)``, ``diag`` and ``bdiag`` that evaluation's
    diagnostics, and ``jwork`` and ``schur`` the blocks that
    :func:`rvcore.dynamics.rhs.rhs_jac` accumulated with ``h·γ = dt·GAMMA``: at ``(t, y)``
    when ``refresh`` (then factored here), or as factored at an earlier step. Where a
    pocket the step touched did not keep its energy to the tolerance ``work[W_SET, 0]``
    (:func:`rvcore.integrate.pocket_check.pocket_energy_error`), or a race contact's load
    at a stage passed its onset limit (``W_QLIM``, :func:`onset_constant`), the
    step is taken again from ``y`` in substeps, the first of each try with the tangents of
    its start and a later one with its own where they are stale (module docstring, "Pocket
    impacts"):
    first the fewest, from ``work[W_SET, 3]`` (:data:`FIRST_SUBSTEPS`) doubling, whose
    square reaches the step's error over the tolerance and the onset's ``h²·Q^⅓/c_on``
    (Q the largest such load), then twice as many until every
    pocket the substeps touched kept its energy over the whole step to the same tolerance,
    or :data:`SUBSTEPS` were taken; ``inner`` then receives the diagnostics at the last
    retake's substep starts as :func:`rvcore.recording.plan.add_substep_integrals` takes
    them.

    Returns
    -------
    torque : float
        The step's drive torque less the first stage's ``b_1·T(y)``, which the caller
        has [N m]: ``Σ_{i≥2} b_i·T(Y_i)``, or over the kept substeps their mean less
        ``b_1·T(y)``.
    power : float
        The same of the drive's power ``T·ω`` [W].
    substeps : int
        The substeps of the retake kept, 0 if the step was not taken again: the tangents
        left in ``jwork`` are then the last substep's, and the next step must evaluate
        its own.
    computed : int
        The substeps the retake computed, the tries that did not keep included.
    stale : bool
        Whether the race contacts' loads at the step's last stage have moved from those
        the tangents were taken at by more than the load tolerance (module docstring,
        "Step"): the next step must evaluate its own.
    """
    n = y.size
    if refresh:
        factor(jwork, schur, rows, work[W_M], work[W_SF:].reshape(-1))
        if flexible(params):
            factor_modes(jwork, schur, rows, params, work[int(work[W_SET, 2]):], dt * work[W_SET, SET_GAMMA],
                         work[W_SF:].reshape(-1))
        grow = work[W_SET, SET_ONSET] / (dt * dt)
        for k in range(bdiag.shape[0]):
            work[W_QREF, k] = bdiag[k, B_QI]
            work[W_QREF + 1, k] = bdiag[k, B_QO]
            work[W_QLIM, k] = (np.cbrt(max(bdiag[k, B_QI], 0.0)) + grow) ** 3
            work[W_QLIM + 1, k] = (np.cbrt(max(bdiag[k, B_QO], 0.0)) + grow) ** 3
    work[W_SET, SET_ONSET_LOAD] = 0.0
    first, first_power = B1 * diag[D_DRIVE_TORQUE], B1 * diag[D_DRIVE_POWER]
    for m in range(n):
        work[W_Y0, m] = y[m]
    for k in range(bdiag.shape[0]):
        work[W_PV0, k] = bdiag[k, B_PV]
        work[W_PACC, k] = B1 * bdiag[k, B_PP]
        work[W_TOUCH, k] = 1.0 if bdiag[k, B_PV] > 0.0 else 0.0
    # the falling-slope guard (falling_guard): where the stretch's step is beyond the
    # falling slope's bound and a race contact slides faster than the law's v_s at the
    # step's start, the step is taken in substeps within that bound from the start
    sub_dt = work[W_SET, SET_SUB_DT]
    if sub_dt > 0.0 and diag[D_MAX_SLIDE2] > work[W_SET, SET_SLIP2]:
        n_sub = 2
        while n_sub < SUBSTEPS and n_sub * sub_dt < dt:
            n_sub *= 2
    else:
        torque, power = _stages(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur)
        error = pocket_energy_error(y, dt, rows, pockets, work[W_PV0], work[W_PACC], work[W_TOUCH])
        onset = work[W_SET, SET_ONSET_LOAD]
        if error <= work[W_SET, 0] and onset == 0.0:
            return torque, power, 0, 0, _tangents_stale(work, bdiag)
        # the first retake: the fewest substeps (from work[W_SET, 3]) whose error, falling as
        # the square of their share of the step (the scheme's order: n substeps of h/n, each
        # erring as (h/n)³), would meet the tolerance; and, where a race contact closed beyond
        # its onset limit, enough that the contact at the largest load it reached is within
        # that limit at the substeps' step (n² ≥ h²·Q^⅓/c_on); at most SUBSTEPS
        ratio = error / work[W_SET, 0]
        n_sub = int(work[W_SET, 3])
        while n_sub < SUBSTEPS and n_sub * n_sub < ratio:
            n_sub *= 2
        if onset > 0.0:
            need = dt * dt * np.cbrt(onset) / work[W_SET, SET_ONSET]
            while n_sub < SUBSTEPS and n_sub * n_sub < need:
                n_sub *= 2
    first_try = n_sub
    while True:
        for m in range(n):
            y[m] = work[W_Y0, m]
        for k in range(bdiag.shape[0]):
            work[W_PSUM, k] = 0.0
            work[W_TOUCH, k] = 1.0 if work[W_PV0, k] > 0.0 else 0.0
        h = dt / n_sub
        total, total_power = 0.0, 0.0
        since = 0       # substeps since this try's tangents were taken
        for s in range(n_sub):
            ts = t + s * h
            # the try's first substep takes the tangents at its start; a later one where the
            # race loads moved from those they were taken at (W_QREF), as a step does
            fresh = s == 0 or since >= TANGENT_MAX_STEPS or _tangents_stale(work, bdiag)
            if fresh:
                rhs_jac(ts, y, work[W_F], params, rows, arcs, pockets, table, meta, diag, bdiag, h * work[W_SET, SET_GAMMA], jwork,
                        schur)
                since = 0
            else:
                rhs(ts, y, work[W_F], params, rows, arcs, pockets, table, meta, diag, bdiag)
                since += 1
            for m in range(inner.size):
                inner[m] = -0.5 * (n_sub - 1) * diag[m] if s == 0 else inner[m] + diag[m]
            diag_torque, diag_power = diag[D_DRIVE_TORQUE], diag[D_DRIVE_POWER]
            if fresh:
                factor(jwork, schur, rows, work[W_M], work[W_SF:].reshape(-1))
                if flexible(params):
                    factor_modes(jwork, schur, rows, params, work[int(work[W_SET, 2]):], h * work[W_SET, SET_GAMMA],
                                 work[W_SF:].reshape(-1))
                for k in range(bdiag.shape[0]):
                    work[W_QREF, k] = bdiag[k, B_QI]
                    work[W_QREF + 1, k] = bdiag[k, B_QO]
            for k in range(bdiag.shape[0]):
                work[W_PACC, k] = B1 * bdiag[k, B_PP]
                if bdiag[k, B_PV] > 0.0:
                    work[W_TOUCH, k] = 1.0
            later, later_power = _stages(ts, y, h, params, rows, arcs, pockets, table, meta, diag, bdiag, work,
                                         jwork, schur)
            for k in range(bdiag.shape[0]):
                work[W_PSUM, k] += work[W_PACC, k] / n_sub
            total += B1 * diag_torque + later
            total_power += B1 * diag_power + later_power
        if n_sub == SUBSTEPS or (pocket_energy_error(y, dt, rows, pockets, work[W_PV0], work[W_PSUM], work[W_TOUCH])
                                 <= work[W_SET, 0]):
            # computed: first_try + 2·first_try + … + n_sub
            return total / n_sub - first, total_power / n_sub - first_power, n_sub, 2 * n_sub - first_try, True
        n_sub *= 2


# ---- the method's protocol (rvcore.integrate.protocol)
#: Right-hand sides a step evaluates (and each of its substeps, when taken again).
STAGES = 4
#: The method's own counters in ``state``: steps since the tangents were evaluated, whether
#: they no longer fit the contacts' loads (1), and whether this step evaluates them (1).
S_SINCE, S_STALE, S_REFRESH = S_OWN, S_OWN + 1, S_OWN + 2

def time_step(model, peak_contact_load: float, *, safety: float = 0.8, held: bool = False) -> float:
    """IMEX's fixed step [s] (:func:`imex_time_step`); ``held``: where the loads and speed
    are held (the held tableau)."""
    return imex_time_step(model, peak_contact_load, safety=safety, held=held)


def imex_time_step(model, peak_contact_load: float, *, safety: float = 0.8,
                   dynamic_margin: float = 1.0, held: bool = False) -> float:
    """The fixed IMEX step [s] from the rates that bound it (:mod:`rvcore.integrate.imex`, "Step").

    Notes
    -----
    Per row, with ``Q = dynamic_margin·peak_contact_load`` and the two race contacts of a
    ball (the rates of :func:`rvcore.integrate.rk4.rk4_time_step`)::

        λ_f = 2·(c_f·max(1/m_b, r²/I_b) + c_max/m_b)      (friction and damping, implicit)
        λ_− = 2·Q·|min μ'|·max(1/m_b, r²/I_b)             (the law's falling slope, explicit)
        dt  = safety · min(FRICTION_LIMIT/λ_f, 2.785/λ_−, CONTACT_LIMIT/ω_n)

    with ``c_f = Q·dμ/ds`` at zero slip, ``|min μ'|`` the law's steepest fall
    (:func:`rvcore.contact.laws.friction_falling_slope`), and ω_n the contact oscillation of
    :func:`rvcore.integrate.step_size.row_rates`. Where the loads and speed are held
    (``held``), the held tableau damps the friction modes at any ``λ_f·h``, so the
    friction adds no bound; the falling slope's is left to the guard (:func:`falling_guard`)
    up to :data:`SUBSTEPS` times it, so that the guard's substeps keep it; and the contact
    oscillation's is :data:`HELD_CONTACT_LIMIT` (module docstring, "Where the loads are
    held")::

        dt_held = safety · min(HELD_CONTACT_LIMIT/ω_n, SUBSTEPS·2.785/λ_−)

    A contact that closes within a step adds
    no bound (the step is taken again in substeps, :func:`onset_constant`), nor does a
    flexible ring's modes: their own stiffness and damping and the contacts' Hertz
    stiffness, groove stiffness and damper on them are implicit
    (:func:`rvcore.integrate.arrowhead.factor_modes`), and the friction does not drive them.
    :data:`rvcore.integrate.imex.FRICTION_LIMIT` and :data:`rvcore.integrate.imex.CONTACT_LIMIT`,
    and why: :mod:`rvcore.integrate.imex`.
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
        if held:    # the falling slope to the guard (falling_guard), within its substeps
            dts.append(min(HELD_CONTACT_LIMIT / omega, SUBSTEPS * RK4_REAL_LIMIT / lam if lam > 0 else np.inf))
        else:
            dts.append(min(FRICTION_LIMIT / lam_f if lam_f > 0 else np.inf,
                           RK4_REAL_LIMIT / lam if lam > 0 else np.inf,
                           CONTACT_LIMIT / omega))
    return safety * min(dts)


def onset_constant(model) -> float:
    """The onset constant ``c_on`` [N^(1/3) s^2] of the IMEX step's onset check
    (:func:`imex_step`): a race contact whose load grows within a step of ``h`` from the
    load ``Q₀`` its tangent was taken at to a load beyond ``(Q₀^⅓ + c_on/h²)³`` carries
    a stiffness the tangent does not hold, ``Δk = 1.5·K^(2/3)·(Q^⅓ − Q₀^⅓)``, beyond the
    explicit tableau's limit ``√(Δk/m_b)·h ≤ ONSET_SAFETY·ONSET_LIMIT``::

        c_on = m_b·(ONSET_SAFETY·ONSET_LIMIT)² / (1.5·K^(2/3)) = 2·(ONSET_SAFETY·ONSET_LIMIT)² / ω_n(1 N)²

    with ω_n(1 N) the contact oscillation at 1 N (:func:`rvcore.integrate.step_size.row_rates`,
    K of the row's stiffest arc); the smallest over the rows."""
    return float(min(2.0 * (ONSET_SAFETY * ONSET_LIMIT) ** 2 / omega ** 2 for omega, _, _ in row_rates(model, 1.0)))


def pocket_energy_tolerance(model, peak_contact_load: float, time_step: float) -> float:
    """The IMEX pocket check's tolerance [J] (:func:`rvcore.integrate.imex.imex_step`) at the step
    ``time_step`` [s].

    Notes
    -----
    :data:`rvcore.integrate.imex.POCKET_ENERGY_TOL` of ``⅖·Q·δ``, the elastic energy of a race
    contact at ``Q = peak_contact_load`` [N] (``δ = (Q/K)^(2/3)``, K of the row's stiffest
    arc; the smallest over the rows), at the step ``h₀ = ONSET_LIMIT·√2/ω_n = 4/ω_n`` (the
    default step's ω_n·h, 0.8·CONTACT_LIMIT, :func:`imex_time_step`), and scaled as ``(h/h₀)³``::

        tol = POCKET_ENERGY_TOL · ⅖·Q·δ · (h/h₀)³

    Why the cube: an impact the check lets pass leaves an error of up to the tolerance at
    each of its steps, ``τ/h`` of them (τ the impact's duration); ``(h/h₀)³`` makes that
    fall as h², the scheme's order, so that the check puts no floor under the drift's
    convergence when the step is halved (docs/model.md §9.4(a)). At the study case's
    default step, 2e-7 of 26 mJ: 5.2e-9 J.
    """
    q = max(peak_contact_load, 1.0)
    energies, onset = [], []
    for r in range(model.rows.shape[0]):
        energies.append(0.4 * q * (q / model.stiffest_arc(r)) ** (2.0 / 3.0))
    for omega, _, _ in row_rates(model, q):
        onset.append(ONSET_LIMIT * math.sqrt(2.0) / omega)
    return POCKET_ENERGY_TOL * min(energies) * (time_step / min(onset)) ** 3


def tangent_load_tolerance(peak_contact_load: float) -> float:
    """The load [N] by which a race contact may move before the IMEX tangents are
    evaluated again (:func:`rvcore.integrate.imex.imex_step`): :data:`rvcore.integrate.imex.TANGENT_LOAD_TOL`
    of ``peak_contact_load`` [N]. On the study case 3.6 N."""
    return TANGENT_LOAD_TOL * max(peak_contact_load, 1.0)


def new_state():
    """The counters of a run: no tangents yet, so the first step evaluates them."""
    state = new_counters()
    state[S_SINCE] = TANGENT_MAX_STEPS
    state[S_STALE] = 1
    return state


def load_tolerance(peak_contact_load: float) -> float:
    """The tangents' load tolerance [N] a stretch of the step schedule hands
    :func:`begin_segment` (:data:`rvcore.integrate.schedule.SEG_LOAD_TOL`):
    :func:`tangent_load_tolerance` of the peak contact load [N] it was sized on."""
    return tangent_load_tolerance(peak_contact_load)


def segment_constant(model, peak_contact_load: float, time_step: float) -> float:
    """The constant a stretch of the step schedule hands :func:`begin_segment` at the step
    ``time_step`` [s]: the pocket check's tolerance [J] (:func:`pocket_energy_tolerance`)."""
    return pocket_energy_tolerance(model, peak_contact_load, time_step)


def falling_guard(model, peak_contact_load: float, *, safety: float = 0.8, held: bool = False):
    """``(s², h_f)`` for a stretch of the step schedule: where the loads are held the step
    (:func:`imex_time_step` with ``held``) does not keep the friction law's falling slope
    within its bound, so a step at whose start a race contact slides faster than the law's
    ``v_s`` (``s² = v_s²`` [m² s^-2]) is taken in substeps of at most ``h_f`` [s], that
    bound: ``h_f = safety·min over the rows of 2.785/λ_−``, ``λ_− = 2·Q·|min μ'|·max(1/m_b,
    r²/I_b)`` at ``Q = peak_contact_load`` [N] (:func:`imex_time_step`). ``(0, 0)`` (none)
    elsewhere, and for a law that never falls. The slip is the largest race contact's at
    the step's start (``max_race_sliding_speed``, in the diagnostics every step's start
    evaluates); such a step counts as taken again, its substeps as computed
    (:func:`imex_step`), and :func:`rhs_evaluations` counts its first try too."""
    p = model.params
    law = p[P_LAW:P_LAW + FRICTION_LAW_SIZE]
    falling = friction_falling_slope(law) * law[LAW_ON]
    if not held or falling <= 0.0:
        return 0.0, 0.0
    q = max(peak_contact_load, 1.0)
    lam = max(2.0 * q * falling * max(1.0 / m, rot) for _, m, rot in row_rates(model, q))
    return float(law[LAW_V_S]) ** 2, safety * RK4_REAL_LIMIT / lam


@kernel(inline=True)
def begin_segment(segment, work, state):
    """A stretch of the step schedule begins (:mod:`rvcore.integrate.schedule`): its pocket
    tolerance and tangents' load tolerance, the held tableau where the loads and speed
    are held (the all-pass one elsewhere), and tangents evaluated anew at its first step
    (their blocks carry the step and the tableau's γ, ``h·γ``)."""
    work[W_SET, 0] = segment[SEG_TOL]
    work[W_SET, 1] = segment[SEG_LOAD_TOL]
    work[W_SET, SET_SLIP2] = segment[SEG_SLIP2]
    work[W_SET, SET_SUB_DT] = segment[SEG_SUB_DT]
    _set_tableau(work, segment[SEG_HELD] != 0.0)
    state[S_STALE] = 1


@kernel(inline=True)
def _set_tableau(work, held):
    """The implicit tableau's γ and free entries into ``work[W_SET]``: the held tableau
    (:data:`HELD_GAMMA`, ...) where ``held``, else the all-pass one (:data:`GAMMA`, ...)."""
    if held:
        work[W_SET, SET_GAMMA], work[W_SET, SET_I32] = HELD_GAMMA, HELD_I32
        work[W_SET, SET_I42], work[W_SET, SET_I43] = HELD_I42, HELD_I43
    else:
        work[W_SET, SET_GAMMA], work[W_SET, SET_I32] = GAMMA, I32
        work[W_SET, SET_I42], work[W_SET, SET_I43] = I42, I43


def rhs_evaluations(n_steps: int, substeps: int) -> int:
    """Right-hand sides of a run: four a step and the last step's end, and four a
    substep computed in the steps taken again."""
    return STAGES * n_steps + 1 + STAGES * substeps


@kernel(inline=True)
def evaluate(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state):
    """The right-hand side at the step's start into ``work[W_F]``, and with it the
    tangents (:func:`rvcore.dynamics.rhs.rhs_jac`, ``h·γ = dt·GAMMA``) where the contacts'
    loads have moved from those they were taken at, after :data:`TANGENT_MAX_STEPS` steps,
    and after a step taken in substeps (module docstring, "Step"); they stay frozen in
    between."""
    refresh = state[S_STALE] != 0 or state[S_SINCE] >= TANGENT_MAX_STEPS
    if refresh:
        state[S_SINCE] = 0
        state[S_REFRESHES] += 1
        state[S_REFRESH] = 1
        rhs_jac(t, y, work[W_F], params, rows, arcs, pockets, table, meta, diag, bdiag, dt * work[W_SET, SET_GAMMA], jwork,
                schur)
    else:
        state[S_REFRESH] = 0
        rhs(t, y, work[W_F], params, rows, arcs, pockets, table, meta, diag, bdiag)


@kernel(inline=True)
def step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state, inner,
         acc, reductions, phases):
    """One step (:func:`imex_step`) after :func:`evaluate`; a step taken again adds its
    substeps' integrals to the accumulator lines whose window holds ``t``
    (:func:`rvcore.recording.plan.add_substep_integrals`). Returns as
    :func:`rvcore.integrate.rk4.step`, the end weight's divisor the kept substeps' number
    after a step taken again."""
    torque = B1 * diag[D_DRIVE_TORQUE]
    power = B1 * diag[D_DRIVE_POWER]
    later, later_power, again, computed, stale = imex_step(t, y, dt, params, rows, arcs, pockets, table, meta, diag,
                                                 bdiag, work, jwork, schur, state[S_REFRESH] != 0, inner)
    torque += later
    power += later_power
    state[S_STALE] = 1 if stale else 0
    state[S_SINCE] += 1
    divisor = 1.0
    if again > 0:
        state[S_SUBSTEPPED] += 1
        state[S_SUBSTEPS] += computed
        divisor = float(again)
        n_ph = phases.shape[0]
        for k in range(n_ph + 1):
            if in_window(phases, k, n_ph, t):
                add_substep_integrals(acc[k], reductions, inner, dt / again)
    return torque, power, stage_weighted_inertia(t, dt, params, table, meta), divisor
