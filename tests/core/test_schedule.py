"""The step schedule (rvcore.integrate.schedule): where the loads and speed are held, the
stretches on the output grid, and a run whose step changes inside the loop.

The held windows are read off each profile's own breakpoints here (the study cycle's
loads are held over 0.3–4.3 s and its speed over 0.8–3.8 s: sweeps/profiles/study.toml);
the steps from the methods' bounds at the case's peak contact load.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rvcore.bearing.layout import compile_bearing
from rvcore.integrate import imex, rk4
from rvcore.integrate.methods import time_step
from rvcore.integrate.schedule import (SEG_DT, SEG_HELD, SEG_OUT_EVERY, SEG_SLIP2, SEG_STEPS, SEG_SUB_DT, SEG_TOL,
                                       HELD_END_MARGIN, held_tableau_windows, held_windows, step_schedule,
                                       unloading_windows)
from rvcore.profile import Channel, OperatingPoint, Profile, scaled_study_profile, study_profile
from rvcore.simulation.initial_state import peak_contact_load
from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings

from .physics_cases import section_bearing

OP = OperatingPoint(math.radians(660.0), 30e3, 10e3)


def test_the_study_cycle_is_held_over_its_steady_phase_only():
    """Loads held 0.3–4.3 s, speed 0.8–3.8 s: everything held 0.8–3.8 s, the steady phase;
    a window inside it is held throughout, one across its edge from the edge on."""
    resolved = study_profile().resolve(OP)
    windows = held_windows(resolved, 0.0, 4.6)
    assert windows == [(pytest.approx(0.8), pytest.approx(3.8))]
    assert held_windows(resolved, 1.0, 2.0) == [(1.0, 2.0)]
    assert held_windows(resolved, 0.5, 1.0) == [(pytest.approx(0.8), 1.0)]
    assert held_windows(resolved, 0.0, 0.8) == []


def test_a_turning_load_or_a_changing_moment_is_not_held():
    """The load's direction and the moment are channels too: the steady phase with the
    load turning over 2–3 s is held before and after, and the schedule takes the held
    step on both stretches, each ending its margin before its window does; a moment that
    rises over 1.5–1.6 s splits it likewise."""
    base = study_profile()
    turning = Profile(base.name, base.radial_load, base.axial_load, base.speed, base.phases, base.duration,
                      load_direction=Channel((0.0, 2.0, 3.0), (0.0, 0.0, 1.0), relative=False))
    resolved = turning.resolve(OP)
    windows = held_windows(resolved, 0.0, 4.6)
    assert windows == [(pytest.approx(0.8), pytest.approx(2.0)), (pytest.approx(3.0), pytest.approx(3.8))]
    _, model = section_model()
    schedule = step_schedule(imex, model, peak_contact_load(model, resolved), resolved, 0.0, 4.6, 1000.0)
    assert schedule[:, SEG_HELD].tolist() == [0.0, 1.0, 0.0, 1.0, 0.0, 1.0]
    m = HELD_END_MARGIN
    np.testing.assert_allclose(np.cumsum(schedule[:, SEG_STEPS] * schedule[:, SEG_DT]),
                               [0.8, 2.0 - m, 3.0, 3.8 - m, 4.3, 4.6], rtol=1e-12)
    moment = Profile(base.name, base.radial_load, base.axial_load, base.speed, base.phases, base.duration,
                     moment=Channel((0.0, 1.5, 1.6), (0.0, 0.0, 1.0)))
    windows = held_windows(moment.resolve(dataclass_moment(OP)), 0.0, 4.6)
    assert windows == [(pytest.approx(0.8), pytest.approx(1.5)), (pytest.approx(1.6), pytest.approx(3.8))]


def test_the_unload_at_standstill_takes_the_held_tableau_and_the_load_ramp_does_not():
    """Where the ring stands still and no load grows (the study cycle's unload, 4.3–4.6 s)
    the held tableau runs; not where the loads ramp up at standstill (0–0.3 s), nor where
    the ring turns, a load falls through zero or the load's direction turns."""
    base = study_profile()
    resolved = base.resolve(OP)
    assert unloading_windows(resolved, 0.0, 4.6) == [(pytest.approx(4.3), 4.6)]
    assert unloading_windows(resolved, 0.0, 0.3) == []
    assert unloading_windows(resolved, 4.4, 4.5) == [(4.4, 4.5)]
    assert held_tableau_windows(resolved, 0.0, 4.6) == [(pytest.approx(0.8), pytest.approx(3.8)),
                                                         (pytest.approx(4.3), 4.6)]
    through_zero = Profile(base.name, base.radial_load,
                           Channel((0.0, 0.3, 4.3, 4.6), (0.0, 1.0, 1.0, -0.5)), base.speed, base.phases, base.duration)
    assert unloading_windows(through_zero.resolve(OP), 0.0, 4.6) == []
    turning = Profile(base.name, base.radial_load, base.axial_load, base.speed, base.phases, base.duration,
                      load_direction=Channel((0.0, 4.3, 4.6), (0.0, 0.0, 1.0), relative=False))
    assert unloading_windows(turning.resolve(OP), 0.0, 4.6) == []
    rolling = Profile(base.name, base.radial_load, base.axial_load,
                      Channel((0.3, 0.8, 4.6), (0.0, 1.0, 1.0)), base.phases, base.duration)
    assert unloading_windows(rolling.resolve(OP), 0.0, 4.6) == []


def dataclass_moment(op):
    """``op`` with a moment [N m], so that the moment channel has values to change."""
    import dataclasses

    return dataclasses.replace(op, moment=100.0)


def section_model():
    bearing = section_bearing(12)
    return bearing, compile_bearing(bearing)


def test_the_schedule_puts_the_longer_step_on_the_held_window_and_every_stretch_on_the_output_grid():
    """IMEX on the study cycle: four stretches, the second the steady phase and the last the
    unload at the method's held step (longer: the friction adds no bound there, the contact oscillation
    ω_n·h ≤ 7.5 instead of 5), each step dividing the output interval, each stretch a whole
    number of output intervals but the last, and the steps adding up to the cycle; each
    stretch's pocket tolerance the method's at its own step. The held stretch ends
    ``HELD_END_MARGIN`` (10 ms) before the steady phase, so that the deceleration starts
    from the plain tableau's motion, wherever the run is cut; a run that ends inside the
    held window is held to its end."""
    _, model = section_model()
    resolved = study_profile().resolve(OP)
    q = peak_contact_load(model, resolved)
    rate = 1000.0
    schedule = step_schedule(imex, model, q, resolved, 0.0, 4.6, rate)
    assert schedule[:, SEG_HELD].tolist() == [0.0, 1.0, 0.0, 1.0]
    plain, held = time_step(model, q, "imex"), time_step(model, q, "imex", held=True)
    assert held > plain
    for row, bound in zip(schedule, (plain, held, plain, held)):
        assert row[SEG_DT] <= bound and row[SEG_DT] * (row[SEG_OUT_EVERY] + 1) > 1.0 / rate * (1 - 1e-12)
        assert row[SEG_DT] * row[SEG_OUT_EVERY] == pytest.approx(1.0 / rate, rel=1e-12)
        assert row[SEG_TOL] == imex.pocket_energy_tolerance(model, q, row[SEG_DT])
    spans = schedule[:, SEG_STEPS] * schedule[:, SEG_DT]
    assert HELD_END_MARGIN == pytest.approx(0.01) and HELD_END_MARGIN * rate == round(HELD_END_MARGIN * rate)
    np.testing.assert_allclose(np.cumsum(spans), [0.8, 3.8 - HELD_END_MARGIN, 4.3, 4.6], rtol=1e-12)
    ends_held = step_schedule(imex, model, q, resolved, 0.0, 2.0, rate)
    assert ends_held[:, SEG_HELD].tolist() == [0.0, 1.0]
    np.testing.assert_allclose(np.cumsum(ends_held[:, SEG_STEPS] * ends_held[:, SEG_DT]), [0.8, 2.0], rtol=1e-12)
    # a run cut at the window's end, or inside its margin, ends the held stretch where the whole run does
    for cut in (3.8, 3.795):
        part = step_schedule(imex, model, q, resolved, 0.0, cut, rate)
        assert part[:, SEG_HELD].tolist() == [0.0, 1.0, 0.0]
        np.testing.assert_allclose(np.cumsum(part[:2, SEG_STEPS] * part[:2, SEG_DT]), [0.8, 3.8 - HELD_END_MARGIN],
                                   rtol=1e-12)
    second = step_schedule(imex, model, q, resolved, 2.0, 4.6, rate)
    assert second[:, SEG_HELD].tolist() == [1.0, 0.0, 1.0]
    assert second[0, SEG_STEPS] * second[0, SEG_DT] == pytest.approx(1.8 - HELD_END_MARGIN, rel=1e-12)


def test_rk4_and_a_step_set_by_hand_keep_one_step_throughout():
    """RK4's bounds are stability limits that held loads do not lift, and a step set by hand
    (``SolverSettings.time_step``) is the step everywhere: one stretch, not held."""
    _, model = section_model()
    resolved = study_profile().resolve(OP)
    q = peak_contact_load(model, resolved)
    assert time_step(model, q, "rk4", held=True) == time_step(model, q, "rk4")
    for schedule in (step_schedule(rk4, model, q, resolved, 0.0, 4.6, 1000.0),
                     step_schedule(imex, model, q, resolved, 0.0, 4.6, 1000.0, time_step=2e-5)):
        assert schedule.shape[0] == 1 and schedule[0, SEG_HELD] == 0.0
    assert step_schedule(imex, model, q, resolved, 0.0, 4.6, 1000.0, time_step=2e-5)[0, SEG_DT] == 2e-5


def test_a_run_changes_its_step_inside_the_loop_on_the_output_grid():
    """The 12-ball section on the study cycle scaled to 46 ms: the outputs keep the times
    ``k/output_rate`` through the three changes of step, the run's steps are its stretches',
    the held ones those of the steady phase less its end margin and of the unload (the last
    3 ms)."""
    bearing, _ = section_model()
    profile = scaled_study_profile(0.01)
    settings = SolverSettings(output_rate=1e4)
    result = run_case(bearing, profile, OP, settings)
    info = result.info
    assert info["held_time_step"] > info["time_step"]
    steady = profile.phases[1]
    unload = profile.duration - profile.phases[2][2]
    assert unload == pytest.approx(0.003)
    held_span = steady[2] - steady[1] - HELD_END_MARGIN + unload
    assert info["held_steps"] == round(held_span / info["held_time_step"])
    outside = profile.duration - held_span
    assert info["steps"] == info["held_steps"] + round(outside / info["time_step"])
    np.testing.assert_allclose(result.time, np.arange(result.time.size) / 1e4, rtol=0, atol=1e-15)
    assert result.time[-1] == pytest.approx(profile.duration)


def test_the_held_step_leaves_the_falling_slope_to_a_guard():
    """Where the loads are held the step no longer keeps the friction law's falling slope
    (μ_s to μ_d between v_s and v_d) within RK4's real-axis limit; the held stretch carries
    a guard instead: the squared slip v_s² above which a step is taken in substeps, and the
    longest substep ``0.8·2.785/λ_−``, ``λ_− = 2·Q·1.5·(μ_s − μ_d)/(v_d − v_s)·2.5/m_b``
    (the STEP law's steepest fall, a ball's ``max(1/m_b, r²/I_b) = 2.5/m_b``), computed here
    from the section's ball. The other stretches, RK4 and a law that never falls carry none."""
    bearing, model = section_model()
    resolved = study_profile().resolve(OP)
    q = peak_contact_load(model, resolved)
    c = bearing.contact
    row = bearing.rows[0]
    m_b = bearing.ball_material.density * math.pi * row.ball_diameter ** 3 / 6.0
    lam = 2.0 * q * 1.5 * (c.mu_static - c.mu_dynamic) / (c.v_dynamic - c.v_static) * 2.5 / m_b
    slip2, sub_dt = imex.falling_guard(model, q, safety=0.8, held=True)
    assert slip2 == pytest.approx(c.v_static ** 2, rel=1e-12)
    assert sub_dt == pytest.approx(0.8 * 2.785 / lam, rel=1e-3)
    held = time_step(model, q, "imex", held=True)
    assert held > sub_dt           # the guard is what keeps the bound there
    schedule = step_schedule(imex, model, q, resolved, 0.0, 4.6, 1000.0)
    assert schedule[:, SEG_SLIP2].tolist() == [0.0, slip2, 0.0, slip2]
    assert schedule[:, SEG_SUB_DT].tolist() == [0.0, sub_dt, 0.0, sub_dt]
    assert imex.falling_guard(model, q, held=False) == (0.0, 0.0)
    assert rk4.falling_guard(model, q, held=True) == (0.0, 0.0)
    lubricated = compile_bearing(dataclasses.replace(bearing, contact=dataclasses.replace(c, law="ehl_bair_winer")))
    assert imex.falling_guard(lubricated, q, held=True) == (0.0, 0.0)


def test_a_held_step_whose_race_contact_slides_past_v_s_is_taken_in_substeps(monkeypatch):
    """The 12-ball section on the study cycle scaled to 46 ms, its held stretch's guard set
    to a slip its race contacts pass at every step (1 µm/s): every held step is then taken
    in substeps within the falling slope's bound (steps of at most ``h_f``), so the run
    takes more steps again than without, and the inner ring's mean steady displacements
    agree with the plain run's to a few per cent (the same physics at a finer step; the
    section's pocket impacts make its other steady metrics spread far more, docs/model.md
    §9.6)."""
    bearing, _ = section_model()
    profile = scaled_study_profile(0.01)
    settings = SolverSettings(output_rate=1e4)
    plain = run_case(bearing, profile, OP, settings)
    guard = imex.falling_guard
    monkeypatch.setattr(imex, "falling_guard",
                        lambda *a, **k: (1e-12, guard(*a, **k)[1]) if k.get("held") else guard(*a, **k))
    guarded = run_case(bearing, profile, OP, settings)
    info = guarded.info
    assert info["held_time_step"] == plain.info["held_time_step"]
    assert info["substepped_steps"] >= info["held_steps"] + plain.info["substepped_steps"] // 2 > 0
    assert info["substeps_taken"] >= 2 * info["held_steps"]
    for name in ("radial_displacement_mean", "axial_displacement_mean"):
        assert guarded.phase_metrics[name][1] == pytest.approx(plain.phase_metrics[name][1], rel=0.05), name
