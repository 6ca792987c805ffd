"""Performance figures: the core on the study bearing, a scipy comparison, sweep scaling.

Everything is measured in one run, side by side, and reported as figures; nothing here
asserts a time (these machines are noisy).

- ``full_cycle``: the study bearing (51 balls) through the whole 4.6 s cycle at
  660 deg/s, 30 kN radial and 10 kN axial, on one core, with each integrator of
  :data:`rvcore.integrate.methods.METHODS` in turn (``rk4_full_cycle_wall_s``,
  ``imex_full_cycle_wall_s``, ``rk4_steps``, ...; ``speedup_vs_rk4`` = RK4's wall over
  IMEX's). The unprefixed figures (``full_cycle_wall_s``, ``steps``, ...) are those of
  the default method, ``method`` (``SolverSettings().method``).
- ``scipy_ratio``: ``scipy.integrate.solve_ivp`` (DOP853) on the same numba right-hand
  side over the same short window of steady running, at a tolerance whose error against
  a fine reference is no larger than ours, timed (median of repeats) against our IMEX
  integrator over that window (``rk4_scipy_ratio``: the same against our RK4). All start
  from the same state; the reference is our RK4 at a step 8x smaller than RK4's own.
- ``phase_cost``: where the full cycle's integration time goes (:func:`phase_cost`): the
  same case run one stretch of the profile at a time (before the first phase, each phase,
  after the last), each from the state the last ended in: ``phase_wall_s_<k>``, ``phase_steps_<k>``,
  ``phase_us_per_step_<k>``, ``phase_refreshes_per_step_<k>`` and
  ``phase_substepped_per_step_<k>`` for stretch k of ``phase_names``/``phase_windows_s``.
- ``parallel_efficiency``: the smoke sweep run serially and on a 2-process LocalCluster:
  serial wall / (workers x parallel wall).
- ``scheduler_cost`` (``rvsweep bench --tasks 1000,10000``): the parent's CPU per case of
  a sweep on a 2-process LocalCluster, dask's scheduler included, with stand-in cases that
  compute nothing (:func:`scheduler_cost`): ``parent_cpu_per_task_ms_<N>``.
- ``ball_scaling`` (``rvsweep bench --balls 51,102,204``): µs per ball-step of the
  default method on the study bearing scaled to hold Z balls (:func:`scaled_study_bearing`:
  its pitch circle and every radial dimension moved out so that the balls' spacing and
  the rings' and cage's sections stay the study's), over a window of the short cycle
  (:func:`ball_scaling`): ``us_per_ball_step_<Z>`` and ``ball_scaling_ratio_<Z>``, the
  medians of ``--rounds`` rounds timing the counts side by side, with the ratios' range,
  and the steps taken again in substeps and the tangents' refreshes per step at each Z.
- ``imperfection_cost_ratio``: the study case made to ISO 492's Normal class (its
  eccentricities, high points and ball sizes drawn from seed 0) against the perfect one,
  over the cycle's first 0.6 s (load ramp and start-up) with the default method, in
  alternating pairs; the median of the pairs' wall-time ratios.
- ``lubricated_cost_ratio``: the study case with the lubricated contact law
  (``friction.law = "ehl_bair_winer"``, docs/model.md §4.1) against the dry one, the
  whole cycle in alternating pairs at 120 and 660 °/s (:func:`lubricated_cost`), the
  median of the pairs' wall-time ratios at the speed where it is largest; issue 40's
  goal ≤ 1.3.
- ``flexible_cost_ratio``: the flexible study bearing (``rv-main-flexible.toml``, both
  rings' modes to order 6 as states, docs/model.md §16.1) against the same bearing with
  rigid rings, the default method, 660 °/s, 30 kN + 10 kN, in alternating pairs; the
  median of the pairs' ratios of the integration's wall time, over 0.1 s of steady running
  from 1.5 s (:func:`flexible_cost`); ``flexible_cost_ratio_start`` the same over the
  cycle's first 0.05 s (the load ramp, where the tangents are evaluated at most steps).
  Issue 41's goal ≤ 1.5. ``coupling_*`` (:func:`modal_coupling`): why the balls and the
  modes share one implicit solve, the contacts' cross terms between them alone oscillating
  at ``coupling_cross_omega_h`` at the step, past the explicit tableau's 2√2.
"""
from __future__ import annotations

import math
import os
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from .schema.shipped import DEFAULT_BEARING, DEFAULT_PROFILE, shipped_file

STUDY_BEARING = shipped_file(DEFAULT_BEARING)
STUDY_PROFILE = shipped_file(DEFAULT_PROFILE)
SMOKE_SWEEP = shipped_file("smoke.toml")


def _study():
    from rvcore.profile import OperatingPoint

    from .schema import load_bearing, load_profile

    return (load_bearing(STUDY_BEARING), load_profile(STUDY_PROFILE),
            OperatingPoint(math.radians(660.0), 30e3, 10e3))


#: The figures :func:`full_cycle_of` reports for one method (prefixed by its name in
#: :func:`full_cycle`; unprefixed for the default method).
CYCLE_FIGURES = ("full_cycle_wall_s", "integrator_wall_s", "simulated_s", "steps", "time_step_s",
                 "held_time_step_s", "rhs_evaluations", "ns_per_ball_rhs", "simulated_s_per_wall_s")


def full_cycle_of(method: str) -> dict:
    """The study bearing through the full cycle on one core with integrator ``method``.

    A short run of the same case first loads every kernel the method calls, so that the
    timed run holds no compilation or cache loading.
    """
    from rvcore.simulation.run import run_case, warm_up
    from rvcore.simulation.settings import SolverSettings

    warm_up()
    bearing, profile, op = _study()
    run_case(bearing, profile, op, SolverSettings(method=method, end_time=2e-4), starts=None)
    t0 = time.perf_counter()
    r = run_case(bearing, profile, op, SolverSettings(method=method), starts=None)
    wall = time.perf_counter() - t0
    n_balls = r.info["ball_count"]
    return {
        "full_cycle_wall_s": wall,
        "integrator_wall_s": r.info["wall_time"],
        "simulated_s": float(r.time[-1] - r.time[0]),
        "steps": int(r.info["steps"]),
        "time_step_s": float(r.info["time_step"]),
        "held_time_step_s": float(r.info["held_time_step"]),
        "rhs_evaluations": int(r.info["rhs_evaluations"]),
        "ball_count": int(n_balls),
        "ns_per_ball_rhs": r.info["wall_time"] / r.info["rhs_evaluations"] / n_balls * 1e9,
        "simulated_s_per_wall_s": float(r.time[-1] - r.time[0]) / wall,
    }


def full_cycle(methods=None) -> dict:
    """:func:`full_cycle_of` for each of ``methods`` (default: every method) in one run.

    Returns each method's figures prefixed by its name (``rk4_full_cycle_wall_s``), the
    default method's also unprefixed, ``method`` (the default) and, with both RK4 and
    IMEX, ``speedup_vs_rk4`` = RK4's full-cycle wall time over IMEX's [-].
    """
    from rvcore.simulation.settings import SolverSettings
    from rvcore.integrate.methods import NAMES as METHODS

    default = SolverSettings().method
    methods = tuple(methods or METHODS)
    per = {m: full_cycle_of(m) for m in methods}
    out = {"method": default}
    if default in per:
        out.update(per[default])
    for m, figures in per.items():
        out.update({f"{m}_{k}": v for k, v in figures.items()})
    if "rk4" in per and "imex" in per:
        out["speedup_vs_rk4"] = per["rk4"]["full_cycle_wall_s"] / per["imex"]["full_cycle_wall_s"]
    return out


def stretches(profile) -> list:
    """The profile's cycle cut at every phase's start and end: ``[(name, start, end), ...]``
    [s], a phase under its own name, what lies before the first phase, between two and
    after the last as ``"before <phase>"``/``"after <phase>"`` (the study's load ramp and
    unload)."""
    phases = sorted(profile.phases, key=lambda p: p[1])
    out, t = [], 0.0
    for name, start, end in phases:
        if start > t + 1e-12:
            out.append((f"before {name}", t, start))
        out.append((name, start, end))
        t = end
    if profile.duration > t + 1e-12:
        out.append((f"after {phases[-1][0]}", t, profile.duration))
    return out


def phase_cost(bearing=None, profile=None, op=None) -> dict:
    """The integration's cost stretch by stretch of the cycle (:func:`stretches`): the
    case run with the default settings one stretch at a time, each from the state the
    previous one ended in (so each stretch starts from the dynamics' own state, not a
    quasi-static one), each stretch's integrator timed alone. Default: the study case of
    :func:`full_cycle_of`.

    Returns ``phase_names``, ``phase_windows_s`` and per stretch k ``phase_wall_s_<k>``
    (the integrator's wall time) [s], ``phase_steps_<k>``, ``phase_us_per_step_<k>`` [µs],
    ``phase_refreshes_per_step_<k>`` and ``phase_substepped_per_step_<k>`` [-] (IMEX's
    tangent refreshes and steps taken again in substeps), and ``phase_total_wall_s``.

    Notes
    -----
    A run that starts from a given state evaluates its tangents at its first step, one
    refresh more a stretch than the whole cycle's run takes there. Each stretch is timed
    alone, not as the difference of two runs from t = 0, whose noise is that of the longer
    run.
    """
    from rvcore.simulation.run import run_case
    from rvcore.simulation.settings import SolverSettings

    if bearing is None:
        bearing, profile, op = _study()
    run_case(bearing, profile, op, SolverSettings(end_time=2e-4), starts=None)      # load every kernel
    parts = stretches(profile)
    out = {"phase_names": [p[0] for p in parts], "phase_windows_s": [(p[1], p[2]) for p in parts]}
    y, total = None, 0.0
    for k, (_, start, end) in enumerate(parts):
        r = run_case(bearing, profile, op, SolverSettings(start_time=start, end_time=end), initial_state_vector=y,
                     starts=None)
        info, y = r.info, r.final_state
        steps = max(int(info["steps"]), 1)
        out[f"phase_wall_s_{k}"] = float(info["wall_time"])
        out[f"phase_steps_{k}"] = int(info["steps"])
        out[f"phase_us_per_step_{k}"] = float(info["wall_time"]) / steps * 1e6
        out[f"phase_refreshes_per_step_{k}"] = int(info["tangent_refreshes"]) / steps
        out[f"phase_substepped_per_step_{k}"] = int(info["substepped_steps"]) / steps
        total += float(info["wall_time"])
    out["phase_total_wall_s"] = total
    return out


def scipy_comparison(method: str = "imex", window: float = 0.01, t_start: float = 1.5,
                     repeats: int = 3) -> dict:
    """Our integrator ``method`` against solve_ivp(DOP853) on the same right-hand side and
    window [s], from the state at ``t_start`` [s]; medians of ``repeats`` timings.

    The accuracy both must reach is measured against our RK4 at a step 8x smaller than
    RK4's own, whatever ``method`` is. ``ours_window_rhs_evaluations`` counts 4 per step
    (+1) for either method, and 4 per substep of an IMEX step taken again (rvcore.integrate.imex).
    """
    from scipy.integrate import solve_ivp

    from rvcore.integrate import loop as ig
    from rvcore.recording.plan import build_plan, new_accumulators
    from rvcore.integrate.imex import pocket_energy_tolerance, tangent_load_tolerance
    from rvcore.integrate.methods import time_step
    from rvcore.integrate.schedule import uniform_schedule
    from rvcore.simulation.initial_state import initial_state, peak_contact_load
    from rvcore.dynamics.rhs import new_diagnostics, rhs
    from rvcore.bearing.layout import R_BALL0, compile_bearing

    bearing, profile, op = _study()
    model = compile_bearing(bearing)
    resolved = profile.resolve(op)
    table, meta = resolved.arrays()
    y0 = initial_state(model, resolved, t_start)
    q_peak = peak_contact_load(model, resolved)
    dt_rk4 = time_step(model, q_peak, "rk4")
    dt_ours = time_step(model, q_peak, method)
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    args = (model.params, model.rows, model.arcs, model.pockets, table, meta)
    counts = []     # right-hand-side evaluations of each run of ours()

    def ours(dt, method=method):
        y = y0.copy()
        n = int(math.ceil(window / dt))
        plan = build_plan(model.rows.shape[0], 0)
        out = np.zeros((n + 2, plan.series.shape[0]))
        acc = new_accumulators(plan, 0)
        phases = np.zeros((0, 2))
        sensors = np.zeros((0, 6))
        t0 = time.perf_counter()
        schedule = uniform_schedule(n, window / n, n, pocket_energy_tolerance(model, q_peak, window / n),
                                    tangent_load_tolerance(q_peak))
        status, _, _, _, _, _, substeps = ig.advance(method, y, t_start, schedule, model, table, meta,
                                                 phases, sensors, out, acc, plan, diag, bdiag, 1.0, 1e30,
                                                 np.ones(model.rows.shape[0]))
        wall = time.perf_counter() - t0
        assert status == ig.OK
        # a step taken again in substeps (rvcore.integrate.imex) evaluates 4 per substep besides its own
        counts.append(4 * n + 1 + 4 * substeps)
        return y, wall

    ours(dt_ours)  # compile / warm
    reference, _ = ours(dt_rk4 / 8, "rk4")
    y_ours, _ = ours(dt_ours)
    ours_walls = [ours(dt_ours)[1] for _ in range(repeats)]

    def error(y):
        # inner-ring displacement and every ball centre: the positions that matter [m]
        b0 = int(model.rows[0, R_BALL0])
        pos = np.r_[0:3, [b0 + 9 * j + k for j in range(model.n_balls) for k in range(3)]].astype(int)
        return float(np.max(np.abs(y[pos] - reference[pos])))

    err_ours = error(y_ours)
    dy = np.zeros_like(y0)

    def fun(t, y):
        rhs(t, y, dy, *args, diag, bdiag)
        return dy.copy()

    scale = np.maximum(np.abs(y0), 1e-3)
    chosen = None
    for rtol in (1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10):
        sol = solve_ivp(fun, (t_start, t_start + window), y0, method="DOP853", rtol=rtol,
                        atol=rtol * scale * 1e-3)
        if not sol.success:
            continue
        err = error(sol.y[:, -1])
        if err <= err_ours:
            chosen = (rtol, err, sol.nfev)
            break
    if chosen is None:
        return {"scipy_method": method, "scipy_ratio": float("nan"),
                "scipy_note": "DOP853 did not reach our accuracy"}
    rtol = chosen[0]
    scipy_walls = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        solve_ivp(fun, (t_start, t_start + window), y0, method="DOP853", rtol=rtol, atol=rtol * scale * 1e-3)
        scipy_walls.append(time.perf_counter() - t0)
    ours_med, scipy_med = statistics.median(ours_walls), statistics.median(scipy_walls)
    return {
        "scipy_method": method,
        "scipy_ratio": scipy_med / ours_med,
        "scipy_window_s": window,
        "scipy_wall_s": scipy_med,
        "ours_window_wall_s": ours_med,
        "scipy_rtol": rtol,
        "scipy_rhs_evaluations": int(chosen[2]),
        "ours_window_time_step_s": window / int(math.ceil(window / dt_ours)),
        "ours_window_rhs_evaluations": counts[-1],
        "ours_position_error_m": err_ours,
        "scipy_position_error_m": chosen[1],
    }


def parallel_efficiency(workers: int = 2, repeats: int = 3) -> dict:
    """The smoke sweep serially and on a LocalCluster of ``workers`` processes.

    Serial and parallel runs alternate ``repeats`` times; the medians are reported.
    ``wall_time`` counts from the first case submitted to the last one finished; the
    totals add the numba warm-up and the cluster's start and stop.
    """
    from .run import run_sweep
    from .schema import read_sweep_file

    sweep = read_sweep_file(SMOKE_SWEEP)
    tmp = Path(tempfile.mkdtemp(prefix="rvsweep-bench-"))
    ser, par, ser_tot, par_tot = [], [], [], []
    try:
        for k in range(repeats):
            t0 = time.perf_counter()
            ser.append(run_sweep(sweep, tmp / f"serial{k}", serial=True, progress=False, resume=False).wall_time)
            ser_tot.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            par.append(run_sweep(sweep, tmp / f"parallel{k}", workers=workers, progress=False,
                                 resume=False).wall_time)
            par_tot.append(time.perf_counter() - t0)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    med = statistics.median
    return {
        "smoke_cases": len(sweep.cases),
        "smoke_repeats": repeats,
        "smoke_serial_wall_s": med(ser),
        "smoke_parallel_wall_s": med(par),
        "smoke_serial_total_s": med(ser_tot),
        "smoke_parallel_total_s": med(par_tot),
        "smoke_workers": workers,
        "parallel_efficiency": med(ser) / (workers * med(par)),
        "parallel_efficiency_total": med(ser_tot) / (workers * med(par_tot)),
        "cpu_count": os.cpu_count(),
    }


def no_case(bearing, profile, op, settings, **keywords):
    """A case that computes nothing (:func:`scheduler_cost`'s stand-in for the dynamics)."""
    return None


def scheduler_cost(counts=(1000, 10000), workers: int = 2) -> dict:
    """The parent's CPU per case of a sweep on a local dask cluster, dask's part included.

    For each ``N`` in ``counts``: the smoke sweep's first case copied under ``N`` case ids,
    submitted through the sweep's own code (:func:`pipeline.run.cluster.client` with
    ``workers`` processes, :func:`pipeline.run.cluster.on_cluster`) with a case function
    that computes nothing (:func:`no_case`), and every outcome collected. The parent's
    CPU (``time.process_time``: this process's threads, the scheduler's event loop
    among them, since a LocalCluster's scheduler runs here) from the first submission to
    the last outcome, over N: ``parent_cpu_per_task_ms_<N>``, with the wall time
    ``scheduler_wall_s_<N>`` and the cluster's start ``cluster_start_s_<N>``. What the
    cases write and the status lines cost the parent is measured apart (docs/performance.md,
    "Parent per case").
    """
    import dataclasses

    from .run.cluster import client, on_cluster
    from .schema import read_sweep_file

    spec = read_sweep_file(SMOKE_SWEEP).cases[0]
    out = {"scheduler_workers": workers}
    for n in counts:
        specs = [dataclasses.replace(spec, case_id=f"{i:016x}") for i in range(int(n))]
        t0 = time.perf_counter()
        with client(workers=workers, scheduler=None, scheduler_file=None, n_cases=len(specs),
                    allowed_failures=0) as (c, _):
            out[f"cluster_start_s_{n}"] = time.perf_counter() - t0
            w0, c0 = time.perf_counter(), time.process_time()
            done = sum(1 for _, outcome in on_cluster(c, specs, no_case, 0) if outcome.ok)
            c1, w1 = time.process_time(), time.perf_counter()
        if done != len(specs):
            raise RuntimeError(f"{len(specs) - done} of {len(specs)} stand-in cases failed")
        out[f"parent_cpu_per_task_ms_{n}"] = 1e3 * (c1 - c0) / len(specs)
        out[f"scheduler_wall_s_{n}"] = w1 - w0
    return out


def imperfection_cost(pairs: int = 3, end_time: float = 0.6) -> dict:
    """Wall time of the Normal-class study case over the perfect one (module docstring)."""
    import dataclasses

    from rvcore.simulation.run import run_case
    from rvcore.simulation.settings import SolverSettings
    from rvcore.bearing.imperfections import Imperfections

    bearing, profile, op = _study()
    normal = dataclasses.replace(bearing, rows=tuple(
        dataclasses.replace(r, imperfections=Imperfections(tolerance_class="normal")) for r in bearing.rows))
    settings = SolverSettings(end_time=end_time, seed=0)
    run_case(normal, profile, op, dataclasses.replace(settings, end_time=0.01), starts=None)   # load every kernel
    perfect, imperfect = [], []
    for _ in range(pairs):
        perfect.append(run_case(bearing, profile, op, settings, starts=None).info["wall_time"])
        imperfect.append(run_case(normal, profile, op, settings, starts=None).info["wall_time"])
    return {"imperfection_perfect_wall_s": statistics.median(perfect),
            "imperfection_normal_wall_s": statistics.median(imperfect),
            "imperfection_cost_ratio": statistics.median([b / a for a, b in zip(perfect, imperfect)])}


#: The study's steady speeds the lubricated law's cost is measured at [deg/s]: the grid's two
#: ends, all boundary lubrication at 120 °/s and a mixed-film steady phase at 660 °/s
#: (docs/validation.md, "The study grid greased").
LUBRICATED_COST_SPEEDS = (120.0, 660.0)


def lubricated_cost(pairs: int = 2, speeds=LUBRICATED_COST_SPEEDS) -> dict:
    """Wall time of the lubricated study case over the dry one, the whole cycle at each of
    ``speeds`` [deg/s], 30 kN + 10 kN (module docstring).

    Returns ``lubricated_cost_ratio_<speed>`` (the median of ``pairs`` alternating
    pairs' ratios) at each speed, and ``lubricated_cost_ratio``, ``lubricated_wall_s``
    and ``lubricated_dry_wall_s`` at the speed where the ratio is largest.
    """
    import dataclasses

    from rvcore.bearing.laws import LUBRICATED_LAW
    from rvcore.profile import OperatingPoint
    from rvcore.simulation.run import run_case
    from rvcore.simulation.settings import SolverSettings

    bearing, profile, op = _study()
    wet = dataclasses.replace(bearing, contact=dataclasses.replace(bearing.contact, law=LUBRICATED_LAW))
    settings = SolverSettings()
    run_case(wet, profile, op, dataclasses.replace(settings, end_time=0.01), starts=None)   # load every kernel
    out, worst = {}, None
    for speed in speeds:
        point = OperatingPoint(math.radians(speed), op.radial_load, op.axial_load)
        dry_s, wet_s = [], []
        for _ in range(pairs):
            dry_s.append(run_case(bearing, profile, point, settings, starts=None).info["wall_time"])
            wet_s.append(run_case(wet, profile, point, settings, starts=None).info["wall_time"])
        ratio = statistics.median([b / a for a, b in zip(dry_s, wet_s)])
        out[f"lubricated_cost_ratio_{speed:g}"] = ratio
        if worst is None or ratio > worst[0]:
            worst = (ratio, statistics.median(wet_s), statistics.median(dry_s), speed)
    out.update(lubricated_cost_ratio=worst[0], lubricated_wall_s=worst[1], lubricated_dry_wall_s=worst[2],
               lubricated_cost_speed=worst[3])
    return out


#: The flexible study bearing (issue 41; docs/model.md §16.1).
FLEXIBLE_BEARING = shipped_file("bearings/rv-main-flexible.toml")
#: The windows :func:`flexible_cost` times [s]: (start, end) of steady running and of the
#: load ramp at the cycle's start.
FLEXIBLE_COST_WINDOWS = {"": (1.5, 1.6), "_start": (0.0, 0.05)}


def flexible_cost(pairs: int = 3, windows=None) -> dict:
    """The flexible study case's integration wall time over the rigid one's, in alternating
    pairs over each of ``windows`` (module docstring; :data:`FLEXIBLE_COST_WINDOWS`).

    Returns per window (its suffix) ``flexible_cost_ratio<suffix>`` (the median of the
    pairs' ratios), ``flexible_wall_s<suffix>`` and ``flexible_rigid_wall_s<suffix>`` (the
    medians), and both cases' ``time_step_s`` and ``us_per_step`` (median wall a step).
    """
    import dataclasses

    from rvcore.dynamics.ring_modes import DYNAMICS_MAX_ORDER
    from rvcore.rings.flexible import bearing_rings
    from rvcore.simulation.run import run_case
    from rvcore.simulation.settings import SolverSettings

    from .schema import load_bearing

    _, profile, op = _study()
    bearing = load_bearing(FLEXIBLE_BEARING)
    rings = bearing_rings(bearing, max_order=DYNAMICS_MAX_ORDER)
    settings = SolverSettings()
    # load every kernel
    run_case(bearing, profile, op, dataclasses.replace(settings, end_time=2e-4), rings=rings, starts=None)
    out = {}
    for suffix, (start, end) in (windows or FLEXIBLE_COST_WINDOWS).items():
        window = dataclasses.replace(settings, start_time=start, end_time=end)
        rigid, flexible = [], []
        for _ in range(pairs):
            rigid.append(run_case(bearing, profile, op, window, starts=None).info)
            flexible.append(run_case(bearing, profile, op, window, rings=rings, starts=None).info)
        ratios = [b["wall_time"] / a["wall_time"] for a, b in zip(rigid, flexible)]
        out[f"flexible_cost_ratio{suffix}"] = statistics.median(ratios)
        out[f"flexible_wall_s{suffix}"] = statistics.median(i["wall_time"] for i in flexible)
        out[f"flexible_rigid_wall_s{suffix}"] = statistics.median(i["wall_time"] for i in rigid)
        for name, infos in (("flexible", flexible), ("flexible_rigid", rigid)):
            out[f"{name}_time_step_s{suffix}"] = float(infos[0]["time_step"])
            out[f"{name}_us_per_step{suffix}"] = statistics.median(i["wall_time"] / i["steps"] for i in infos) * 1e6
        out[f"flexible_window_s{suffix}"] = (start, end)
    return out


def modal_coupling(bearing=None, profile=None, op=None, time: float = 1.5, eps: float = 1e-10) -> dict:
    """How stiff the contacts' coupling between the balls and a flexible ring's modes is, as
    oscillation rates at the step (docs/performance.md, "Flexible rings in the dynamics").

    At the state :func:`rvcore.simulation.initial_state.initial_state` gives at ``time`` [s]
    (friction and damping off, gravity on), the right-hand side's Jacobian by central
    differences of ``eps`` [m] (of the balls' centres and the modes' amplitudes; the first
    row's balls): ``A_bb`` (balls' accelerations on balls' centres), ``A_mm`` (modes on
    modes) and the cross blocks ``A_bm``, ``A_mb``. Default: the flexible study bearing
    (:data:`FLEXIBLE_BEARING`) at 660 °/s, 30 kN + 10 kN.

    Returns ``coupling_time_step_s`` (the default method's step, fitted to the output
    interval as :func:`rvcore.simulation.run.run_case` fits it [s]) and ``ω·h`` [-] of:
    ``coupling_balls_omega_h`` and ``coupling_modes_omega_h`` (the largest ``√|λ|`` of
    ``A_bb``, ``A_mm``), ``coupling_cross_omega_h`` (the cross terms alone: ``ω⁴`` the
    largest ``|λ|`` of ``A_bm·A_mb``) and ``coupling_cross_omega_h_<family>`` within each
    family of modes.
    """
    from rvcore.bearing.imperfections import realize
    from rvcore.bearing.layout import BALL_STATES, R_BALL0, R_Z
    from rvcore.contact.film import with_film_columns
    from rvcore.dynamics.rhs import new_diagnostics, rhs
    from rvcore.dynamics.ring_modes import DYNAMICS_MAX_ORDER, FAMILIES, family_states, truncated, with_ring_modes
    from rvcore.integrate.methods import METHODS
    from rvcore.rings.flexible import bearing_rings
    from rvcore.simulation.initial_state import initial_state, peak_contact_load
    from rvcore.simulation.run import compile_bearing
    from rvcore.simulation.settings import SolverSettings

    from .schema import load_bearing

    if bearing is None:
        _, profile, op = _study()
        bearing = load_bearing(FLEXIBLE_BEARING)
    bearing = realize(bearing, 0)
    rings = truncated(bearing_rings(bearing, max_order=DYNAMICS_MAX_ORDER), DYNAMICS_MAX_ORDER)
    model = with_film_columns(compile_bearing(bearing, friction=False, damping=False, gravity=True), bearing)
    model = with_ring_modes(model, rings, DYNAMICS_MAX_ORDER)
    resolved = profile.resolve(op)
    table, meta = resolved.arrays()
    y = initial_state(model, resolved, time, seed=0, rings=rings)
    settings = SolverSettings()
    case = with_ring_modes(with_film_columns(compile_bearing(      # the case's own model sets its step
        bearing, friction=settings.friction, damping=settings.damping, gravity=settings.gravity), bearing),
        rings, DYNAMICS_MAX_ORDER)
    h_max = METHODS[settings.method].time_step(case, peak_contact_load(case, resolved), safety=settings.step_safety)
    h = 1.0 / (settings.output_rate * math.ceil(1.0 / (settings.output_rate * h_max) - 1e-9))   # as run_case fits it
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    args = (model.params, model.rows, model.arcs, model.pockets, table, meta, diag, bdiag)
    row = model.rows[0]
    b0, z = int(row[R_BALL0]), int(row[R_Z])
    ball_x = [b0 + BALL_STATES * j + c for j in range(z) for c in range(3)]
    ball_a = [i + 3 for i in ball_x]
    mode_x, mode_a, family = [], [], []
    for name in FAMILIES:
        n, s0 = family_states(model, name)
        mode_x += range(s0, s0 + 2 * n)
        mode_a += range(s0 + 2 * n, s0 + 4 * n)
        family += [name] * (2 * n)

    def jacobian(columns, rows):
        out = np.zeros((len(rows), len(columns)))
        for i, c in enumerate(columns):
            up, down = y.copy(), y.copy()
            up[c] += eps
            down[c] -= eps
            fu, fd = np.zeros_like(y), np.zeros_like(y)
            rhs(time, up, fu, *args)
            rhs(time, down, fd, *args)
            out[:, i] = (fu[rows] - fd[rows]) / (2.0 * eps)
        return out

    def rate(matrix, power):
        return float(np.abs(np.linalg.eigvals(matrix)).max()) ** (1.0 / power) * h

    a_bb, a_mm = jacobian(ball_x, ball_a), jacobian(mode_x, mode_a)
    a_bm, a_mb = jacobian(mode_x, ball_a), jacobian(ball_x, mode_a)
    out = {"coupling_time_step_s": h, "coupling_balls_omega_h": rate(a_bb, 2),
           "coupling_modes_omega_h": rate(a_mm, 2), "coupling_cross_omega_h": rate(a_bm @ a_mb, 4)}
    for name in dict.fromkeys(family):
        k = [i for i, f in enumerate(family) if f == name]
        out[f"coupling_cross_omega_h_{name}"] = rate(a_bm[:, k] @ a_mb[k, :], 4)
    return out


#: The balls of the study bearing [-] (``rows.balls.count`` of rv-main-study.toml).
STUDY_BALLS = 51


def scaled_study_bearing(balls: int):
    """The study bearing scaled to hold ``balls`` balls at the study's spacing.

    The pitch diameter is multiplied by ``s = balls/51`` and every other diameter (bore,
    outside diameter, the inner ring's shoulder, the cage's inner and outer diameters)
    moved by the same ``Δ = (s − 1)·d_m`` [m], so the balls' pitch ``π·d_m/Z``, the
    ball size, the grooves and the sections of the rings and cage stay the study's
    (51 balls: the study bearing itself). The inner ring's attached mass scales as s and
    its attached inertia as s³ (zero on the study bearing).
    """
    import dataclasses

    from .schema import load_bearing

    bearing = load_bearing(STUDY_BEARING)
    if balls == STUDY_BALLS:
        return bearing
    s = balls / STUDY_BALLS
    rows = []
    for row in bearing.rows:
        delta = (s - 1.0) * row.pitch_diameter
        cage = dataclasses.replace(row.cage, inner_diameter=row.cage.inner_diameter + delta,
                                   outer_diameter=row.cage.outer_diameter + delta)
        rows.append(dataclasses.replace(row, ball_count=int(balls), pitch_diameter=row.pitch_diameter + delta,
                                        cage=cage))
    delta = (s - 1.0) * bearing.rows[0].pitch_diameter
    ring = bearing.inner_ring
    ring = dataclasses.replace(ring, shoulder_diameter=ring.shoulder_diameter + delta,
                               attached_mass=ring.attached_mass * s, attached_inertia=ring.attached_inertia * s ** 3)
    return dataclasses.replace(bearing, name=f"{bearing.name}-{balls}-balls", bore=bearing.bore + delta,
                               outer_diameter=bearing.outer_diameter + delta, rows=tuple(rows), inner_ring=ring)


#: Rounds of :func:`ball_scaling` (``rvsweep bench --balls``, ``--rounds``).
BALL_ROUNDS = 5


def ball_scaling(balls=(51, 102, 204), start_time: float = 0.03, end_time: float = 0.1,
                 rounds: int = BALL_ROUNDS) -> dict:
    """µs per ball-step of the default method at each ball count in ``balls`` [-].

    The bearing of :func:`scaled_study_bearing` on the short cycle (the study's shape,
    every time × 0.1; ``profiles/short.toml``) at 660 °/s, 30 kN radial and 10 kN axial
    times ``Z/51`` (the same load a ball), from ``start_time`` (the loads applied, the
    speed ramp starting) to ``end_time`` [s] (into steady running): start-up's impacts
    and steady running. The figure is the CPU time of the run less that of a 0.2 ms run
    of the same case (which also loads every kernel), over the steps between them times
    the balls [µs]: the case's fixed costs and the machine's other load left out
    (``ball_scaling_wall_us_per_ball_step_<Z>``: the integrator's wall time instead).

    The counts are timed side by side in ``rounds`` rounds, each count once a round, in
    turn forward and backward: ``us_per_ball_step_<Z>`` is the median over the rounds,
    ``ball_scaling_ratio_<Z>`` the median of each round's figure over that round's figure
    at ``balls[0]``, and ``ball_scaling_ratio_range_<Z>`` their least and largest (one
    run of a window this short moves by several percent with the machine).
    """
    import dataclasses

    from rvcore.profile import OperatingPoint
    from rvcore.simulation.run import run_case, warm_up
    from rvcore.simulation.settings import SolverSettings

    from .schema import load_profile

    warm_up()
    profile = load_profile(shipped_file("profiles/short.toml"))
    out = {"ball_scaling_counts": [int(z) for z in balls], "ball_scaling_window_s": [start_time, end_time],
           "ball_scaling_rounds": int(rounds)}
    settings = SolverSettings(start_time=start_time, end_time=end_time)
    short_settings = dataclasses.replace(settings, end_time=start_time + 2e-4)
    cases = {}
    for z in balls:
        s = z / STUDY_BALLS
        cases[z] = (scaled_study_bearing(int(z)), OperatingPoint(math.radians(660.0), 30e3 * s, 10e3 * s))
        # an untimed short run first: whatever this bearing's first run does once (a kernel
        # first reached with its shapes, the statics' caches) stays out of every timing
        run_case(cases[z][0], profile, cases[z][1], short_settings, starts=None)
    per_round = {z: [] for z in balls}
    for k in range(rounds):
        for z in (balls if k % 2 == 0 else balls[::-1]):
            bearing, op = cases[z]
            c0 = time.thread_time()
            short = run_case(bearing, profile, op, short_settings, starts=None)
            c1 = time.thread_time()
            r = run_case(bearing, profile, op, settings, starts=None)
            c2 = time.thread_time()
            steps = int(r.info["steps"])
            # CPU time of this thread, the short run's taken off: what the extra steps cost,
            # without the case's fixed costs (statics, outputs) and whatever else the machine runs
            extra = max(steps - int(short.info["steps"]), 1)
            per_round[z].append(((c2 - c1) - (c1 - c0)) / extra / z * 1e6)
            out[f"ball_scaling_wall_us_per_ball_step_{z}"] = r.info["wall_time"] / steps / z * 1e6
            out[f"ball_scaling_wall_s_{z}"] = float(r.info["wall_time"])
            out[f"ball_scaling_steps_{z}"] = steps
            out[f"ball_scaling_substepped_per_step_{z}"] = int(r.info["substepped_steps"]) / steps
            out[f"ball_scaling_refreshes_per_step_{z}"] = int(r.info["tangent_refreshes"]) / steps
    first = per_round[balls[0]]
    for z in balls:
        ratios = [a / b for a, b in zip(per_round[z], first)]
        out[f"us_per_ball_step_{z}"] = statistics.median(per_round[z])
        out[f"ball_scaling_ratio_{z}"] = statistics.median(ratios)
        out[f"ball_scaling_ratio_range_{z}"] = [min(ratios), max(ratios)]
    return out


def run_all(*, quick: bool = False, balls=None, tasks=None, rounds: int = BALL_ROUNDS) -> dict:
    """Every figure of the module docstring, as one flat dict (``rvsweep bench --json``);
    with ``balls`` (ball counts) only :func:`ball_scaling`'s, with ``tasks`` (case counts)
    only :func:`scheduler_cost`'s."""
    if balls:
        return ball_scaling(tuple(balls), rounds=rounds)
    if tasks:
        return scheduler_cost(tuple(tasks))
    out = {}
    out.update(full_cycle())
    out.update(phase_cost())
    out.update(scipy_comparison("imex"))
    out.update({f"rk4_{k}": v for k, v in scipy_comparison("rk4").items()})
    out.update(imperfection_cost())
    out.update(lubricated_cost())
    out.update(flexible_cost())
    out.update(modal_coupling())
    if not quick:
        out.update(parallel_efficiency())
    return out
