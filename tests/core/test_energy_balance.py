"""Energy balance of a dynamic case: the drive's work against dissipation.

The balance, derived from the model's equations of motion (rvcore.dynamics.rhs.rhs)
-------------------------------------------------------------------------------
Let ``E_kin`` be the kinetic energy of the free motion (:func:`rvcore.dynamics.energy.kinetic_energy`:
ring translation and tilt rates, every ball and cage), ``½·I_p·ω²`` that of the ring's
prescribed spin, and ``V_el = Σ ⅖·K·δ^2.5`` the elastic energy of every contact
(:func:`rvcore.dynamics.energy.potential_energy` with no load and no gravity).

1. Every contact applies equal and opposite forces at one point, so the power of a
   contact's forces on the two bodies is ``F·u`` with ``u`` the slip velocity of the
   ball's (or cage's) material point against the other body's. Its normal part is
   ``−q·δ̇ = −K·δ^1.5·δ̇ − (q − K·δ^1.5)·δ̇`` = ``−dV_el/dt − P_damp``; its tangential
   part ``F_t·u = −P_fric ≤ 0``. Summed over all contacts, with the ring moving as the
   rigid body it is (angular velocity ``Ω``, :func:`rvcore.contact.pose.ring_angular_velocity`):
   ``P_contacts = −dV_el/dt − P_damp − P_fric``.
2. The ring's share of it is ``F_c·v + M_c·Ω``, ``M_c`` the contact moment about the ring
   centre. With ``Ω = θ̇x·Ry·x̂ + θ̇y·ŷ + ω·e`` (``e = R·ẑ``, the spin axis):
   ``M_c·Ω = θ̇x·(M_x·cos θy − M_z·sin θy) + θ̇y·M_y + ω·(M_c·e)``.
3. The model's ring equations (small tilt) put ``M_x`` (not ``M_x·cos θy − M_z·sin θy``)
   on ``θ̈x`` and carry the gyroscopic terms ``I_p·(ω̇·θ + ω·θ̇)``. Multiplying them by
   ``θ̇x, θ̇y`` and the translational one by ``v``: the ``ω·θ̇`` terms cancel and
   ``dE_kin/dt = P_contacts − ω·(M_c·e) − P_tilt + P_load``, with
   ``P_tilt = θ̇x·(M_x·(cos θy − 1) − M_z·sin θy) − I_p·ω̇·(θx·θ̇y − θy·θ̇x)``
   (what the small-tilt equations leave out of the rigid ring's power: second order in the
   tilt) and ``P_load`` the power of the applied force, moment and gravity on every body.
4. The drive torque is ``T = I_p·ω̇ − M_c·e`` (the moment about the spin axis that the
   prescribed spin needs), so ``−ω·(M_c·e) = T·ω − d(½·I_p·ω²)/dt`` and

       ∫T·ω dt + W_load = Δ(E_kin + ½·I_p·ω² + V_el) + E_fric + E_damp + E_tilt.

So T·ω is the whole drive power only up to ``E_tilt``, which the core reports; it is
checked here to be negligible (it is second order in the tilt). The core
(rvcore.integrate.loop) takes the drive's work as the steps' stage-weighted power (the
work of the impulse each step gave), the loads' and gravity's as the fall of their
potential across each step (exact for constant loads: a step's displacement is its
stages' weighted velocities), and friction, damping and ``E_tilt`` by the trapezoid rule
over the steps' states. Sampled powers alias the contact oscillation: the drive's did by
8 % of its work until MODEL_VERSION 10, the loads' by up to 1 % of the dissipation on the
study bearing until 2026-11-29 (docs/validation.md). (A rectangle rule left an O(dt) error
of 10 % of the drive's work after the start transient: the tests do resolve the
quadrature.)

The balance is the equations of motion's, whatever integrates them: the tests run for
every integrator of ``rvcore.integrate.methods.METHODS``, each at its default step.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from rvcore.simulation.run import run_case
from rvcore.simulation.initial_state import initial_state
from rvcore.simulation.settings import SolverSettings
from rvcore.integrate.methods import NAMES as METHODS
from rvcore.dynamics.energy import kinetic_energy, potential_energy
from rvcore.bearing.layout import (BALL_STATES, P_GX, P_GY, P_GZ, P_RING_IP, P_RING_M, R_BALL0, R_CAGE0, R_CAGE_M, R_MB,
                                  R_Z, compile_bearing)
from rvcore.profile import CH_SPEED, OperatingPoint, scaled_study_profile

from .physics_cases import constant_profile, section_bearing


def energy_balance_of(bearing, profile, op, settings):
    """Both sides of the balance over the run [J] and the run's result."""
    model = compile_bearing(bearing, friction=settings.friction, damping=settings.damping,
                            gravity=settings.gravity)
    resolved = profile.resolve(op)
    t0 = settings.start_time
    t1 = settings.end_time if settings.end_time > 0 else profile.duration
    y0 = initial_state(model, resolved, t0)
    res = run_case(bearing, profile, op, settings, initial_state_vector=y0)
    y1 = res.final_state
    t1 = float(res.time[-1])

    # elastic energy alone: potential_energy with no load and no gravity
    params = model.params.copy()
    params[[P_GX, P_GY, P_GZ]] = 0.0
    table0, meta0 = profile.resolve(OperatingPoint(op.speed, 0.0, 0.0)).arrays()

    def energy(y, t):
        kin = kinetic_energy(y, model.params, model.rows)
        spin = 0.5 * model.params[P_RING_IP] * resolved.value(CH_SPEED, t) ** 2
        el = potential_energy(t, y, params, model.rows, model.arcs, model.pockets, table0, meta0)
        return kin + spin + el

    e = {k: float(v[-1]) for k, v in res.energy.items()}   # the whole cycle
    supplied = e["drive"] + e["load"]
    stored_and_lost = energy(y1, t1) - energy(y0, t0) + e["friction"] + e["damping"] + e["tilt"]
    return supplied, stored_and_lost, e, res


@pytest.mark.parametrize("method", METHODS)
def test_energy_balance_at_constant_speed_and_load(method):
    """Loads held and the ring spinning at 660 °/s from the start (rolling start at the
    statics): the drive's work and the elastic energy the start transient releases go
    into friction and damping; the balance closes within 1 % of the drive's work."""
    bearing = section_bearing(8)
    op = OperatingPoint(math.radians(660.0), 20e3, 5e3)
    supplied, balance, e, res = energy_balance_of(bearing, constant_profile(0.0, 0.02), op,
                                         SolverSettings(output_rate=1e3, method=method))
    assert res.info["method"] == method
    assert e["drive"] > 0.0 and e["friction"] > 0.0 and e["damping"] > 0.0
    assert abs(e["tilt"]) < 1e-3 * e["drive"]
    assert balance == pytest.approx(supplied, rel=0.01, abs=0.0)
    # at constant ω the drive's work in a phase is the phase mean of the drive torque
    # (accumulated at every step) times ω times the phase's duration
    m = res.phase_metrics
    duration = m["phase_end"] - m["phase_start"]
    # (within 1 % of the whole cycle's: the endpoint halves of the trapezoid differ)
    np.testing.assert_allclose(m["inner_ring_drive_torque_mean"] * op.speed * duration, res.energy["drive"][:3],
                               rtol=0.0, atol=0.01 * e["drive"])


@pytest.mark.parametrize("method", METHODS)
def test_load_work_is_the_fall_of_the_loads_potential(method):
    """With constant loads the work of the applied force and of gravity over a run is
    ``F_r·Δx + F_a·Δz + Σ m·g·Δr`` over the ring, the cages and the balls, whatever the
    path: the core's load work (one step at a time) equals it to round-off. The sum is
    formed here from the run's first and last states (the radial load along +x, load angle
    0; the axial along +z)."""
    bearing = section_bearing(8)
    op = OperatingPoint(math.radians(660.0), 20e3, 5e3)
    settings = SolverSettings(output_rate=1e3, method=method)
    model = compile_bearing(bearing, friction=settings.friction, damping=settings.damping,
                            gravity=settings.gravity)
    y0 = initial_state(model, constant_profile(0.0, 0.01).resolve(op), 0.0)
    res = run_case(bearing, constant_profile(0.0, 0.01), op, settings, initial_state_vector=y0)
    y1 = res.final_state
    g = model.params[[P_GX, P_GY, P_GZ]]
    assert g[2] != 0.0 or g[0] != 0.0 or g[1] != 0.0      # gravity on: it does work too
    d = y1 - y0
    work = op.radial_load * d[0] + op.axial_load * d[2] + model.params[P_RING_M] * (g @ d[0:3])
    for r in range(model.rows.shape[0]):
        c0, b0 = int(model.rows[r, R_CAGE0]), int(model.rows[r, R_BALL0])
        work += model.rows[r, R_CAGE_M] * (g @ d[c0:c0 + 3])
        for j in range(int(model.rows[r, R_Z])):
            b = b0 + BALL_STATES * j
            work += model.rows[r, R_MB] * (g @ d[b:b + 3])
    assert abs(op.radial_load * d[0]) > 1e-4   # the ring moved under its load [J]
    assert res.energy["load"][-1] == pytest.approx(work, rel=1e-9, abs=1e-12)


def test_imex_energy_balance_closes_as_its_step_shrinks():
    """IMEX's remaining gap at the rolling start is a step effect, not a term the scheme or
    the bookkeeping leaves out: as the step shrinks (step_safety 0.8, 0.4, 0.2) the gap
    shrinks, and at a quarter of the default step the balance closes within the same 1 %
    of the drive's work. (Until MODEL_VERSION 10 the drive's work was a trapezoid of the
    instantaneous T·ω, whose chatter it aliased: the gap was −8 % at the default step.)"""
    bearing = section_bearing(8)
    op = OperatingPoint(math.radians(660.0), 20e3, 5e3)
    gaps = {}
    for safety in (0.8, 0.4, 0.2):
        supplied, balance, e, res = energy_balance_of(bearing, constant_profile(0.0, 0.02), op, SolverSettings(
            output_rate=1e3, method="imex", step_safety=safety))
        assert res.info["method"] == "imex"
        gaps[safety] = (abs(balance - supplied), supplied)
    assert gaps[0.8][0] > gaps[0.4][0] > gaps[0.2][0], gaps
    assert gaps[0.2][0] < 0.01 * gaps[0.2][1], gaps


@pytest.mark.parametrize("method", METHODS)
def test_energy_balance_over_a_study_cycle(method):
    """The study's cycle scaled to 60 ms (speed and loads ramp up, hold and the speed
    ramps down): the drive's work, positive while the ring speeds up and negative while it
    slows, plus the work of the ramping loads equals the change of kinetic (free and spin)
    and elastic energy plus friction and damping, within 1 % of the energy dissipated."""
    bearing = section_bearing(8)
    op = OperatingPoint(math.radians(660.0), 30e3, 10e3)
    profile = scaled_study_profile(0.02)
    supplied, balance, e, res = energy_balance_of(bearing, profile, op, SolverSettings(output_rate=1e3, method=method))
    assert res.info["method"] == method
    dissipated = e["friction"] + e["damping"]
    assert dissipated > 0.0
    assert abs(e["tilt"]) < 1e-3 * dissipated
    # the drive work changes sign with the acceleration: start-up > 0 > deceleration
    assert res.energy["drive"][0] > 0.0 > res.energy["drive"][2]
    assert abs(balance - supplied) < 0.01 * dissipated


@pytest.mark.parametrize("method", METHODS)
def test_energy_balance_fails_without_the_damping_term(method):
    """The check can fail: leaving out the damper's dissipation breaks the balance by more
    than the tolerance (at constant speed with a stiff damper, 100× the default: from a
    clean rolling start the damper takes only what the balls' small vibrations carry, 2 %
    of the supply at 25 kN s/m)."""
    bearing = section_bearing(8, damping=25000.0)
    op = OperatingPoint(math.radians(660.0), 20e3, 5e3)
    supplied, balance, e, _ = energy_balance_of(bearing, constant_profile(0.0, 0.01), op,
                                       SolverSettings(output_rate=1e3, method=method))
    assert e["damping"] > 0.015 * supplied
    assert abs(balance - e["damping"] - supplied) > 0.015 * supplied
