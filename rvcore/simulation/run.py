"""``run_case``: the one entry point for a dynamic case. SI in, SI out.

Takes a bearing, a profile, an operating point and solver settings
(:mod:`rvcore.simulation.settings`); returns a :class:`rvcore.recording.results.CaseResult` of plain arrays,
which :mod:`pipeline.io.case` labels. The jobs it strings together have their own
modules: the initial state (:mod:`rvcore.simulation.initial_state`), the step
(:mod:`rvcore.integrate.step_size`), the loop (:mod:`rvcore.integrate.loop`), the reductions
(:mod:`rvcore.recording.plan`) and reading them back (:mod:`rvcore.recording.results`).
"""
from __future__ import annotations

import math
import time as time_module

import numpy as np

from ..recording.plan import build_plan, new_accumulators
from ..bearing.geometry import Arc, Bearing, Cage, ContactLaw, InnerRing, Material, Row, epicyclic_cage_ratio
from ..bearing.imperfections import realize
from ..contact.film import with_film_columns
from .initial_state import initial_state, peak_contact_load
from ..integrate.loop import C_ENDS, ENERGY, NONFINITE, OK, PENETRATION, Scratch, advance
from ..integrate.methods import METHODS, NAMES
from ..dynamics.energy import kinetic_energy_limit
from ..dynamics.rhs import new_diagnostics
from ..bearing.layout import (BALL_STATES, R_BALL0, R_CAGE0, R_CAGE_I, R_CAGE_M, R_HALF_D, R_IB, R_MB, R_PITCH_R, R_Z,
                    body_name, compile_bearing)
from ..statics.operating import steady_outputs
from ..profile import OperatingPoint, scaled_study_profile
from ..recording.results import (CaseResult, SimulationError, duty_cycle_outputs, read_energies, read_life_sums,
                      read_phase_metrics)
from .settings import SolverSettings
from ..recording.spectra import kinematic_frequencies, steady_spectra
from .shared_start import STARTS, Start, StartStore, shared_until, start_key, zero_speed
from ..integrate.schedule import SEG_DT, SEG_HELD, SEG_OUT_EVERY, SEG_STEPS, output_lines, step_schedule
from ..dynamics.ring_modes import DYNAMICS_MAX_ORDER, truncated, with_ring_modes
from ..rings.flexible import RIGID_RINGS, FlexibleRings


def run_case(bearing, profile, op, settings: SolverSettings = SolverSettings(), initial_state_vector=None,
             sensors=(), rings: FlexibleRings = RIGID_RINGS, ring_max_order: int = DYNAMICS_MAX_ORDER,
             starts: StartStore = STARTS) -> CaseResult:
    """Integrate one case through its duty cycle.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    profile : rvcore.profile.Profile
    op : rvcore.profile.OperatingPoint
    settings : SolverSettings
    initial_state_vector : ndarray, optional
        A previous ``CaseResult.final_state`` to continue from; default: quasi-static
        equilibrium at ``settings.start_time`` (random ball positions with
        ``settings.seed`` ≥ 0).
    sensors : sequence of Sensor
        Virtual displacement sensors; each adds a reading over time and its phase metrics.
    rings : rvcore.rings.flexible.FlexibleRings
        Each ring rigid (the default) or flexible in its support: its modes of orders
        ``0 … ring_max_order`` are then states (:mod:`rvcore.dynamics.ring_modes`); the
        orders beyond, where ``rings`` has them (the bearing file's ``max_order``), serve only
        the steady outputs' truncation figure, ``ring_mode_truncation``.
    ring_max_order : int
        Highest Fourier order of a flexible ring the dynamics keep [-].
    starts : rvcore.simulation.shared_start.StartStore or None
        Where the start before the ring turns is looked up and kept
        (:mod:`rvcore.simulation.shared_start`; default the process's); None computes it
        whatever was kept, as a benchmark must. The results are the same bits either way.

    Returns
    -------
    CaseResult

    Raises
    ------
    SimulationError
        On blow-up, naming the simulated time and the body.
    """
    # the imperfections this case runs with: a tolerance class's high-point angles and
    # ball sizes drawn from its seed (rvcore.bearing.imperfections)
    bearing = realize(bearing, int(settings.seed))
    model = with_film_columns(compile_bearing(bearing, friction=settings.friction, damping=settings.damping,
                                              gravity=settings.gravity), bearing)
    flexing = rings is not None and not rings.rigid
    all_rings = rings
    if flexing:
        rings = truncated(rings, ring_max_order)
        model = with_ring_modes(model, rings, ring_max_order)
    resolved = profile.resolve(op)
    table, meta = resolved.arrays()
    t_start = settings.start_time
    t_end = settings.end_time if settings.end_time > 0 else profile.duration
    if t_end <= t_start:
        raise ValueError(f"end time {t_end} s is not after start time {t_start} s")
    if settings.method not in METHODS:
        raise ValueError(f"solver method {settings.method!r} is not one of {', '.join(NAMES)}")
    method = METHODS[settings.method]
    # the start before the ring turns is computed from the profile at zero speed, so that
    # the grid's speeds share it (rvcore.simulation.shared_start)
    t_split = shared_until(resolved, t_start, t_end, settings.output_rate)
    still = zero_speed(profile, op) if t_split > t_start else resolved
    # the start's initial state and peak load, which the speeds of a load and seed share
    pre_key = (start_key("initial state", (model.params, model.rows, model.arcs, model.pockets) + still.arrays(),
                         (t_start, int(settings.seed)))
               if starts is not None and t_split > t_start and initial_state_vector is None and not flexing
               else None)
    pre = starts.initial(pre_key) if pre_key is not None else None
    if pre is not None:
        y, q_still = pre
    else:
        y = (np.array(initial_state_vector, dtype=float) if initial_state_vector is not None
             else initial_state(model, still, t_start, seed=int(settings.seed), rings=rings if flexing else None))
        q_still = peak_contact_load(model, still) if t_split > t_start else None
        if pre_key is not None:
            starts.keep_initial(pre_key, y, q_still)
    if y.shape != (model.n_states,):
        raise ValueError(f"initial state has {y.size} values; this bearing needs {model.n_states}")

    q_peak = peak_contact_load(model, resolved)
    # The steps divide the output interval exactly, so every case of a sweep samples at
    # the same times t_start + k/output_rate whatever its own stability limit; where the
    # loads and speed are held the step may be longer (rvcore.integrate.schedule). Each
    # part of a run in two is sized on its own profile's peak contact load.
    parts = [(t_start, t_split, still, q_still)] if t_split > t_start else []
    parts.append((t_split, t_end, resolved, q_peak))
    schedules = [step_schedule(method, model, q, res, a, b, settings.output_rate, safety=settings.step_safety,
                               time_step=settings.time_step) for a, b, res, q in parts]
    schedule = np.vstack(schedules)
    dt = float(schedule[0, SEG_DT])
    n_steps = int(schedule[:, SEG_STEPS].sum())
    n_out_max = sum(output_lines(s) for s in schedules)
    sensor_rows = (np.array([s.as_row() for s in sensors], dtype=float) if len(sensors)
                   else np.zeros((0, 6)))
    n_sensors = sensor_rows.shape[0]
    n_rows = model.rows.shape[0]
    plan = build_plan(n_rows, n_sensors)
    out = np.zeros((n_out_max, plan.series.shape[0]))
    acc = new_accumulators(plan, resolved.phases.shape[0])
    diag, bdiag = new_diagnostics(n_rows, model.n_balls, n_sensors)
    pen_limit = 0.1 * 2 * float(model.rows[:, R_HALF_D].min())
    ke_limit = kinetic_energy_limit(model, resolved, bearing.outer_diameter)
    cos_nominal = np.array([math.cos(row.nominal_contact_angle) for row in bearing.rows])

    t0 = time_module.perf_counter()
    out_time = np.zeros(n_out_max)
    scratch = Scratch(settings.method, model, schedule, diag, ends=t_split == t_start)
    n_out = 0
    if t_split > t_start:
        first = schedules[0]
        table0, meta0 = still.arrays()
        ke_limit0 = kinetic_energy_limit(model, still, bearing.outer_diameter)
        args = (model, table0, meta0, resolved.phases, sensor_rows, out, acc, plan, diag, bdiag, pen_limit,
                ke_limit0, cos_nominal)
        key = start_key(settings.method,
                        (model.params, model.rows, model.arcs, model.pockets, table0, meta0, resolved.phases,
                         sensor_rows, first, y, plan.series, plan.reductions, acc, diag, bdiag, cos_nominal,
                         scratch.work, scratch.jwork, scratch.schur, scratch.state, scratch.inner, scratch.carry,
                         np.array(out.shape[1:])),   # not the buffer's length: the rest's output lines
                        (t_start, pen_limit, ke_limit0))
        start = starts.get(key) if starts is not None else None
        if start is None:
            status, t_fail, where, n_out, _, _, _ = advance(settings.method, y, t_start, first, *args, out_time,
                                                           scratch=scratch)
            if status != OK:
                _blew_up(status, t_fail, where, model, y, pen_limit, ke_limit0, dt, settings)
            if starts is not None:
                starts.put(key, Start(y, scratch, diag, bdiag, acc, out[:n_out], out_time[:n_out]))
        else:
            y[:], diag[:], bdiag[:], acc[:] = start.y, start.diag, start.bdiag, start.acc
            scratch = start.scratch
            n_out = start.out.shape[0]
            out[:n_out], out_time[:n_out] = start.out, start.out_time
        scratch.carry[C_ENDS] = 1.0
    status, t_fail, where, n_out, substepped, refreshes, substeps_taken = advance(
        settings.method, y, t_split, schedule[len(schedules[0]) if t_split > t_start else 0:], model, table, meta,
        resolved.phases, sensor_rows, out, acc, plan, diag, bdiag, pen_limit, ke_limit, cos_nominal, out_time,
        scratch=scratch)
    wall = time_module.perf_counter() - t0
    if status != OK:
        _blew_up(status, t_fail, where, model, y, pen_limit, ke_limit, dt, settings)
    out = out[:n_out]
    # the output lines' times: on the output grid t_start + k/output_rate (each stretch of
    # the schedule starts on it), the last at the run's end
    k = np.arange(n_out)
    on_grid = int(schedule[-1, SEG_STEPS]) % int(schedule[-1, SEG_OUT_EVERY]) == 0
    time = np.where((k < n_out - 1) | on_grid, t_start + k / settings.output_rate, out_time[n_out - 1])
    series = {}
    for c, (name, instance) in enumerate(plan.series_labels):
        series.setdefault(name, []).append(out[:, c])
    # one column a sensor; one a row where the bearing has several (a single row's drops it)
    series = {name: (np.column_stack(cols) if (name == "sensor_displacement" or len(cols) > 1) else cols[0].copy())
              for name, cols in series.items()}
    metrics = read_phase_metrics(acc, plan, resolved.phases, 1.0 / settings.output_rate)
    life_sums = read_life_sums(acc, plan)
    life = duty_cycle_outputs(bearing, life_sums, resolved.phases.shape[0])
    if "fatigue_damage" in life:
        metrics["fatigue_damage"] = life.pop("fatigue_damage")
    energy = read_energies(acc, plan)
    held = schedule[schedule[:, SEG_HELD] != 0.0]
    info = {"steps": n_steps, "time_step": dt, "shared_start_end": t_split,
            "held_time_step": float(held[0, SEG_DT]) if held.size else dt,
            "held_steps": int(held[:, SEG_STEPS].sum()),
            "rhs_evaluations": method.rhs_evaluations(n_steps, substeps_taken),
            "substepped_steps": substepped, "substeps_taken": substeps_taken, "tangent_refreshes": refreshes,
            "method": settings.method,
            "wall_time": wall, "ball_count": model.n_balls, "peak_contact_load_estimate": q_peak,
            "ball_mass": float(model.rows[0, R_MB]), "pitch_diameter": 2.0 * float(model.rows[0, R_PITCH_R]),
            "epicyclic_cage_ratio": epicyclic_cage_ratio(bearing.rows[0]),
            "seed": int(settings.seed), "inner_ring_tilt": bearing.inner_ring.tilt}
    row0 = bearing.rows[0]
    kinematic = kinematic_frequencies(row0.ball_count, row0.ball_diameter, row0.pitch_diameter,
                                      row0.nominal_contact_angle, op.speed)
    spectra = steady_spectra(time, series, tuple(resolved.phases[1]), kinematic)
    if spectra:
        spectra["kinematic_frequency"] = kinematic
    return CaseResult(time=time, series=series, phase_metrics=metrics, final_state=y.copy(), info=info,
                      ball_diag=bdiag.copy(),
                      steady=steady_outputs(bearing, profile, op, gravity=settings.gravity,
                                            rings=rings if flexing else None, all_rings=all_rings if flexing else None),
                      life_sums=life_sums, life=life, energy=energy, spectra=spectra)


def _blew_up(status, t_fail, where, model, y, pen_limit, ke_limit, dt, settings):
    """Raise the :class:`SimulationError` of a run that stopped with ``status``."""
    what = {NONFINITE: "a non-finite state value",
            PENETRATION: f"a penetration beyond {pen_limit * 1e3:.3g} mm (10 % of the ball diameter)",
            ENERGY: f"kinetic energy beyond the physical bound {ke_limit:.3g} J"}[status]
    if where < 0:  # energy bound: name the body holding the most kinetic energy
        where = _most_energetic_state(model, y)
    body = body_name(model, where)
    hint = ("try a smaller solver.time_step" if settings.time_step > 0
            else "try a smaller solver.step_safety")
    raise SimulationError(f"simulation blew up at t = {t_fail:.6g} s: {what} in {body} "
                          f"(time step {dt:.3g} s; {hint})")


def _most_energetic_state(model, y) -> int:
    """First state index of the body with the largest kinetic energy in ``y``."""
    p = model.params
    best = (0.5 * p[0] * float(y[5:8] @ y[5:8]) + 0.5 * p[2] * float(y[8:10] @ y[8:10]), 0)
    for row in model.rows:
        c0 = int(row[R_CAGE0])
        e = 0.5 * row[R_CAGE_M] * float(y[c0 + 4:c0 + 7] @ y[c0 + 4:c0 + 7]) + 0.5 * row[R_CAGE_I] * y[c0 + 7] ** 2
        best = max(best, (e, c0))
        for j in range(int(row[R_Z])):
            b = int(row[R_BALL0]) + BALL_STATES * j
            e = 0.5 * row[R_MB] * float(y[b + 3:b + 6] @ y[b + 3:b + 6]) + 0.5 * row[R_IB] * float(y[b + 6:b + 9] @ y[b + 6:b + 9])
            best = max(best, (e, b))
    return best[1]


def warm_up() -> None:
    """Compile (or load from the numba cache) every kernel by running a tiny case.

    Under :func:`rvcore._numba.compile_lock`: processes of one host that start together
    (a sweep's workers) compile once, the others load what the first wrote. Each
    method's step size is computed too: its kernels are called from Python by any case
    that sets no ``time_step``, and two workers' first cases compiled them each.
    """
    from .._numba import compile_lock

    steel = Material(7800.0, 208e9, 0.3)
    cage = Cage(0.0545, 0.0575, 0.008, 0.3e-3, 0.3e-3, "outer-land", Material(8500.0, 100e9, 0.34), 1e9)
    row = Row(6, 0.008, 0.056, 0.0, (Arc(0.52, math.radians(15)),), (Arc(0.53, math.radians(15)),), cage)
    b = Bearing("warm-up", 0.045, 0.068, 0.012, (row,), steel, steel, InnerRing(0.050),
                ContactLaw(50.0, 1e-6, 10.0, 10.0))
    with compile_lock():
        run_case(b, scaled_study_profile(0.002), OperatingPoint(1.0, 100.0, 50.0),
                 SolverSettings(output_rate=1e4, time_step=2e-6))
        # the fixed step above skips the step-size kernels a case calls from Python
        # (the friction law's slopes): compiled here too, under the lock
        model = compile_bearing(b)
        for name in NAMES:
            METHODS[name].time_step(model, 100.0)
