"""The IMEX integrator against RK4 on the study bearing (slow).

The case is the study's: the bearing of ``sweeps/bearings/rv-main-study.toml`` (51 balls),
the cycle of ``sweeps/profiles/study.toml`` and the operating point of
``pipeline.bench._study`` (660 °/s, 30 kN radial, 10 kN axial), gravity on (the default).
The run ends where the last phase (deceleration) ends: nothing after it enters a metric.
It starts at t = 0 with the load ramp, so the steady phase and the transients are the
real ones.

What is compared
----------------
The reference is RK4 at ``step_safety`` 0.25 (a step 3.2× below RK4's default) from the
centred start (seed −1); the candidate is IMEX at its default settings
(``SolverSettings(method="imex")``), from the same start.

- **Steady metrics** (within 0.5 %, or within the reference's own step error where
  that is larger, see below): every per-phase metric of the steady phase
  (``CaseResult.phase_metrics``, the steady line), except the locators
  (``*_min_time``, ``*_max_time``, ``static_safety_factor_min_time``: when an extreme
  occurs, not a magnitude), the flags (``*_range_at_edge``), the windows
  (``phase_start``, ``phase_end``) and the prescribed ring speed
  (``inner_ring_speed_mean``: the profile's, not the integrator's). A metric that is
  NaN in both runs (nothing to measure) is skipped, and one that is exactly zero in both
  agrees. The cage slips (``cage_slip``, ``cage_slip_nominal``) are ``1 − ω_c/ω_epi``,
  differences near zero where a relative comparison means nothing: they are compared
  absolutely, against the same 0.5 % of the cage speed (``|Δslip| ≤ 0.005·(1 − slip)``,
  since ``Δslip = −Δω_c/ω_epi``).

  The reference is itself known only to within its step error, estimated as the change
  ``|RK4(0.8) − RK4(0.25)|`` from RK4's default step to the reference's (one more run,
  from the same centred start); a steady metric passes within the larger of 0.5 % and
  that. For every metric the 0.5 % is the larger by far (RK4 moved them by ≤ 0.2 %,
  the cage slip by 2e-8 absolute, the steady peak drive torque by 0.013 %). (Before
  MODEL_VERSION 5 the peak drive torque was the largest sampled ``|T|``, which carries
  the contact oscillation's chatter: RK4 moved it 5 %, 1.46 to 1.54 N m; it is now
  band-limited, rvcore.integrate.loop.TORQUE_BANDWIDTH. Before MODEL_VERSION 6 the filter
  took the inertial part ``I_p·ω̇`` at the step's start while the step's torque weighs it
  over the stages, which put a step's worth of the jump of ω̇ at the start of the steady
  phase into the filter: RK4 moved the steady peak 0.1 % and IMEX's ran 0.05 % low per
  µs of step, the error that bound IMEX's step.)
- **Transient ranges** (within 3 % or the ensemble's standard error, whichever is
  larger): the δ_r and δ_a ranges (max − min) of the start-up and deceleration phases.

The ensemble's standard error
-----------------------------
A transient range depends on where the balls start in their pockets (docs/model.md §8): a
different start is a different, equally valid realization, so two integrators cannot be
asked to agree closer than the spread of the realizations allows. The spread is
estimated from N = 3 random starts (``SolverSettings.seed`` 0, 1, 2) run with RK4 at its
default ``step_safety`` 0.8 (the seed spread is a property of the dynamics, not of the
step, and the default step costs a third of the reference's), and its standard error is
``s/√N`` with ``s`` the sample standard deviation (ddof 1). Three draws give a rough
``s`` (for normal draws ``s/σ`` lies within [0.16, 1.92] with 95 % probability); it only
widens the 3 % where the realizations really scatter by more, and three is what a slow
test can afford: six runs of the 4.3 s cycle in all (reference, RK4 default, candidate,
three seeds), which share the cores through threads (the kernels release the GIL).
Measured with RK4 at 0.5 as the candidate on two shared cores: 4.6 min (the reference
alone 3.2 min).

Verification of the test's logic
--------------------------------
``RV_IMEX_ACCURACY_CANDIDATE="rk4:0.5"`` (method, optionally ``:step_safety``) puts
another candidate in IMEX's place: RK4 at a step between the two must pass too (it
converges: test_dynamics.py, test_truth.py). (RK4 at 0.8 would pass by construction: it
is the step-error run itself.)
"""
from __future__ import annotations

import dataclasses
import math
import os
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings
from rvcore.profile import OperatingPoint
from tests.core.physics_cases import phase_metric_changes

REPO = Path(__file__).resolve().parents[2]
CANDIDATE_ENV = "RV_IMEX_ACCURACY_CANDIDATE"
REFERENCE_SAFETY = 0.25
ENSEMBLE_SEEDS = (0, 1, 2)
STEADY_TOL = 0.005       # every steady metric within 0.5 %
RANGE_TOL = 0.03         # every transient range within 3 % (or the standard error)
#: per-phase metrics that are not magnitudes of the motion (see the module docstring)
NOT_COMPARED = ("phase_start", "phase_end", "inner_ring_speed_mean")
SLIPS = ("cage_slip", "cage_slip_nominal")
RANGES = ("radial_displacement_range", "axial_displacement_range")


def study_case():
    """The study's bearing, cycle and operating point (those of ``pipeline.bench._study``)."""
    from pipeline.schema import load_bearing, load_profile

    return (load_bearing(REPO / "sweeps" / "bearings" / "rv-main-study.toml"),
            load_profile(REPO / "sweeps" / "profiles" / "study.toml"),
            OperatingPoint(math.radians(660.0), 30e3, 10e3))


def candidate_settings(end_time: float) -> SolverSettings:
    """IMEX at its defaults, or the candidate named by ``$RV_IMEX_ACCURACY_CANDIDATE``."""
    spec = os.environ.get(CANDIDATE_ENV, "").strip()
    if not spec:
        return SolverSettings(method="imex", end_time=end_time)
    method, _, safety = spec.partition(":")
    extra = {"step_safety": float(safety)} if safety else {}
    return SolverSettings(method=method, end_time=end_time, **extra)


def phase_index(profile, name: str) -> int:
    return [p[0] for p in profile.phases].index(name)


def agrees(c: float, r: float, tol: float) -> bool:
    """``c`` within ``tol`` of ``r`` (both exactly zero agree; a NaN in one does not)."""
    return (r == 0.0 and c == 0.0) or abs(c - r) <= tol


def steady_comparison(candidate: dict, reference: dict, coarse: dict, k: int) -> dict:
    """Every compared steady-phase metric (line ``k``): ``{name: (candidate, reference,
    tolerance)}``, the tolerance the larger of 0.5 % and the reference's step error
    ``|coarse − reference|``. The rules are the module docstring's.
    """
    out = {}
    for name, ref in reference.items():
        if name in NOT_COMPARED or name.endswith(("_time", "_at_edge")):
            continue
        r, c = float(np.asarray(ref)[k]), float(np.asarray(candidate[name])[k])
        if math.isnan(r) and math.isnan(c):
            continue
        step_error = abs(float(np.asarray(coarse[name])[k]) - r)
        out[name] = (c, r, max(STEADY_TOL * ((1.0 - r) if name in SLIPS else abs(r)), step_error))
    return out


def range_comparison(candidate: dict, reference: dict, ensemble: list, phases) -> dict:
    """The transient ranges: ``{(name, k): (candidate, reference, tolerance)}``, the
    tolerance the larger of 3 % and the ensemble's standard error.

    ``ensemble`` holds the phase metrics of the seeded runs; ``phases`` the phase lines.
    """
    out = {}
    for name in RANGES:
        for k in phases:
            r, c = float(reference[name][k]), float(candidate[name][k])
            draws = np.array([m[name][k] for m in ensemble])
            se = draws.std(ddof=1) / math.sqrt(len(draws))
            out[(name, k)] = (c, r, max(RANGE_TOL * abs(r), se))
    return out


@pytest.mark.slow
def test_imex_matches_rk4_on_the_study_cycle():
    """IMEX's steady metrics within 0.5 % of RK4 at step_safety 0.25, its
    start-up and deceleration ranges within 3 % or the seed ensemble's standard error."""
    bearing, profile, op = study_case()
    k_start, k_steady, k_decel = (phase_index(profile, n) for n in ("startup", "steady", "deceleration"))
    end = max(p[2] for p in profile.phases)
    assert end < profile.duration   # only the unloading after the last phase is left out

    jobs = {"reference": SolverSettings(method="rk4", step_safety=REFERENCE_SAFETY, end_time=end),
            "rk4 default": SolverSettings(method="rk4", end_time=end),
            "candidate": candidate_settings(end)}
    jobs.update({f"seed {s}": SolverSettings(method="rk4", seed=s, end_time=end) for s in ENSEMBLE_SEEDS})

    def run(item):
        label, settings = item
        t0 = time.perf_counter()
        res = run_case(bearing, profile, op, settings)
        return label, res, time.perf_counter() - t0

    # the kernels release the GIL: the six runs share the cores
    with ThreadPoolExecutor(max_workers=min(len(jobs), os.cpu_count() or 1)) as pool:
        done = {label: (res, wall) for label, res, wall in pool.map(run, jobs.items())}
    for label, (res, wall) in done.items():
        print(f"{label}: {res.info['method']} dt = {res.info['time_step']:.3g} s, "
              f"{res.info['steps']} steps, {wall:.1f} s")
    ref, cand = done["reference"][0], done["candidate"][0]
    ensemble = [done[f"seed {s}"][0].phase_metrics for s in ENSEMBLE_SEEDS]

    # the runs are what they claim to be
    assert cand.info["method"] == jobs["candidate"].method
    assert ref.info["method"] == "rk4"
    coarse = done["rk4 default"][0]
    assert ref.info["time_step"] < 0.35 * coarse.info["time_step"]
    assert float(cand.time[-1]) == pytest.approx(end) and float(ref.time[-1]) == pytest.approx(end)
    # the seeds are different realizations of the transients, and the ranges are real
    for name in RANGES:
        for k in (k_start, k_decel):
            draws = [m[name][k] for m in ensemble]
            assert len(set(draws)) == len(draws), (name, k, draws)
            assert ref.phase_metrics[name][k] > 0.0

    steady = steady_comparison(cand.phase_metrics, ref.phase_metrics, coarse.phase_metrics, k_steady)
    assert len(steady) >= 20, sorted(steady)   # the displacements, speeds, forces, energies, angles
    ranges = range_comparison(cand.phase_metrics, ref.phase_metrics, ensemble, (k_start, k_decel))
    for key, (c, r, tol) in {**steady, **ranges}.items():   # with -s: how close each came
        print(f"{key}: candidate {c:.6g}, reference {r:.6g}, |Δ|/tolerance "
              + (f"{abs(c - r) / tol:.3g}" if tol else f"{abs(c - r):.3g} against a zero tolerance"))
    bad = {key: v for key, v in {**steady, **ranges}.items() if not agrees(*v)}
    assert not bad, bad


@pytest.mark.slow
@pytest.mark.parametrize("radial_load", [20e3, 30e3, 40e3], ids=["20kN", "30kN", "40kN"])
def test_imex_convergence_tenfold_smaller_step_on_the_study_bearing(radial_load):
    """docs/model.md §9.6 in its unreduced form for IMEX: the study bearing (51 balls), the
    study cycle to the end of its last phase, in gravity, at 660 °/s and 10 kN axial, at
    the study grid's smallest, middle and largest radial load; the default step against a
    tenth of it. Every phase metric moves by less than 1 % (the cage slips by less than
    0.001 absolute), the rules of tests/core/physics_cases.py::phase_metric_changes. The
    step differs along the load axis, and so does what bounds it
    (docs/performance.md, "The study sweep in five minutes"): 38.5 µs at 20 kN, 33.3 µs at
    30 kN (the friction), 26.3 µs at 40 kN, and in the steady phase, where the loads and
    speed are held, 58.8, 55.6 and 52.6 µs in the held tableau (rvcore.integrate.schedule):
    the step and tableau change inside the loop at 0.8 and 3.79 s, so the torque peaks'
    window edges are checked too.

    The reduced 12-ball section of test_dynamics.py is where IMEX fails the same check: its
    steady phase is a chain of pocket impacts that RK4 itself does not converge on once
    gravity is on (docs/performance.md, "§9.6 on the study bearing"). Measured at
    MODEL_VERSION 22: the worst change 0.69 % at 20 kN, 0.44 % at 30 kN and 0.62 % at 40 kN
    (each the start-up pocket-force peak, as at 19–21); every steady metric ≤ 0.35 %,
    0.11 % and 0.20 %, every deceleration metric ≤ 0.44 %, 0.31 % and 0.05 %. About 50 s a
    load on two cores (the fine run is 0.85–1.05 million steps).
    """
    bearing, profile, op = study_case()
    op = dataclasses.replace(op, radial_load=radial_load)
    end = max(p[2] for p in profile.phases)
    jobs = [SolverSettings(method="imex", end_time=end),
            SolverSettings(method="imex", step_safety=0.08, end_time=end)]
    with ThreadPoolExecutor(max_workers=2) as pool:   # the kernels release the GIL
        coarse, fine = pool.map(lambda s: run_case(bearing, profile, op, s), jobs)
    assert fine.info["time_step"] == pytest.approx(coarse.info["time_step"] / 10, rel=0.02)
    changes = phase_metric_changes(coarse, fine)
    assert len(changes) >= 20, sorted(changes)   # displacements, speeds, forces, energies, lives
    for name, change in changes.items():
        limit = 1e-3 if name.startswith("cage_slip") else 0.01
        assert np.all(change < limit), (name, change)


@pytest.mark.slow
def test_imex_deceleration_converges_after_the_held_stretch():
    """§9.6 where the held tableau showed in the next phase: the study bearing and cycle at
    600 °/s, 40 kN + 10 kN, seed 2 (the study sweep's draw), the default steps against a
    tenth of them; every deceleration metric moves by less than 1 % (the cage slip by less
    than 0.001), by the rules of tests/core/physics_cases.py::phase_metric_changes. The held
    tableau damps a slow part of the rings' motion that the physics keeps, so the held
    stretch ends ``HELD_END_MARGIN`` (10 ms) before the deceleration
    (rvcore.integrate.schedule). Measured at MODEL_VERSION 22: the deceleration's axial
    range 0.14 % below the tenth step's, against 1.36 % below with the stretch run to the
    window's edge (docs/performance.md, "The held tableau"). About 45 s on two cores."""
    bearing, profile, op = study_case()
    op = dataclasses.replace(op, speed=math.radians(600.0), radial_load=40e3)
    end = max(p[2] for p in profile.phases)
    jobs = [SolverSettings(method="imex", end_time=end, seed=2, step_safety=safety) for safety in (0.8, 0.08)]
    with ThreadPoolExecutor(max_workers=2) as pool:   # the kernels release the GIL
        coarse, fine = pool.map(lambda s: run_case(bearing, profile, op, s), jobs)
    assert coarse.info["held_steps"] > 0 and fine.info["held_time_step"] < coarse.info["held_time_step"] / 5
    decel = phase_index(profile, "deceleration")
    changes = phase_metric_changes(coarse, fine)
    assert "axial_displacement_range" in changes
    for name, change in changes.items():
        limit = 1e-3 if name.startswith("cage_slip") else 0.01
        assert np.asarray(change)[decel] < limit, (name, change)


@pytest.mark.slow
def test_imex_unload_converges_in_the_held_tableau():
    """The unload (4.3–4.6 s: the ring at standstill, the loads falling to zero) runs the
    held tableau at the held step (rvcore.integrate.schedule.unloading_windows). The study
    bearing and cycle at 660 °/s, 40 kN + 10 kN, seed 0, whose plain step the friction's
    bound halves there: the inner ring's radial and axial displacements over the unload at
    the default steps against a tenth of them differ by less than 1 % of their travel over
    it. Measured at MODEL_VERSION 23: 0.14 % and 0.38 % (the plain tableau at its step gave
    0.25 % and 0.42 %; at 120 °/s, 20 kN 0.15 % and 0.27 % against 0.09 % and 0.13 %;
    docs/performance.md, "The unload in the held tableau"). About 50 s on two cores."""
    bearing, profile, op = study_case()
    op = dataclasses.replace(op, speed=math.radians(660.0), radial_load=40e3)
    jobs = [SolverSettings(method="imex", seed=0, step_safety=safety) for safety in (0.8, 0.08)]
    with ThreadPoolExecutor(max_workers=2) as pool:   # the kernels release the GIL
        coarse, fine = pool.map(lambda s: run_case(bearing, profile, op, s), jobs)
    unload_start = max(p[2] for p in profile.phases)
    assert unload_start == pytest.approx(4.3) and profile.duration == pytest.approx(4.6)
    # the unload's steps are held ones: more held steps than the steady phase's alone
    steady = profile.phases[phase_index(profile, "steady")]
    assert coarse.info["held_steps"] * coarse.info["held_time_step"] > (steady[2] - steady[1]) + 0.25
    np.testing.assert_array_equal(coarse.time, fine.time)
    u = coarse.time >= unload_start - 1e-9
    for name in ("radial_displacement", "axial_displacement"):
        a, b = coarse.series[name][u], fine.series[name][u]
        travel = np.ptp(b)
        assert travel > 1e-5, name                     # tens of µm: the ring comes back
        assert np.max(np.abs(a - b)) < 0.01 * travel, (name, np.max(np.abs(a - b)) / travel)


@pytest.mark.slow
@pytest.mark.parametrize("speed_deg", [120.0, 180.0])
def test_imex_seed_means_converge_with_the_step_at_a_low_speed(speed_deg):
    """§9.6 at the grid's low speeds, where one case is not the figure to read: there a
    case's transients are draws of where the balls start in their pockets, which a tenth
    of the step moves as another seed does (docs/validation.md, "Known limits": at 20 kN
    and 120–240 °/s single cases' start-up stds by up to 4.4 %, steady ranges and torque
    peaks by up to 1.6 %). The seeds' means are (the sweep's ``*_ensemble_mean``): the study
    bearing and cycle at 120 and at 180 °/s, 20 kN + 10 kN, seeds 0–2, at the default steps and at a
    tenth of them; the mean over the seeds of every steady and deceleration metric moves
    by less than 1 % (the cage slips by less than 0.001), by the rules of
    tests/core/physics_cases.py::phase_metric_changes. The steady phase runs at the longer
    step where the loads are held (rvcore.integrate.schedule). Measured at MODEL_VERSION 20
    (the same seeds as the study sweep's): within 0.54 % at 180 °/s (the steady radial
    range). At MODEL_VERSION 22, whose held tableau moves one draw's steady sliding-speed
    peak at 120 °/s (seed 2, a spike within 1.082–1.083 s) by 2.1 % against
    its tenth step: the means within 0.83 % at 120 °/s (that peak) and 0.54 % at 180 °/s
    (the steady radial range), the held stretch ending 10 ms before the deceleration.
    About 85 s a speed on two cores."""
    from types import SimpleNamespace

    bearing, profile, _ = study_case()
    op = OperatingPoint(math.radians(speed_deg), 20e3, 10e3)
    end = max(p[2] for p in profile.phases)
    jobs = [SolverSettings(method="imex", end_time=end, seed=seed, step_safety=safety)
            for safety in (0.8, 0.08) for seed in (0, 1, 2)]
    with ThreadPoolExecutor(max_workers=2) as pool:   # the kernels release the GIL
        runs = list(pool.map(lambda s: run_case(bearing, profile, op, s), jobs))

    def seed_means(results):
        return SimpleNamespace(phase_metrics={name: np.mean([np.asarray(r.phase_metrics[name], dtype=float)
                                                             for r in results], axis=0)
                                              for name in results[0].phase_metrics})

    coarse, fine = seed_means(runs[:3]), seed_means(runs[3:])
    # each step is fitted down to a divisor of the output interval: a tenth within 5 %
    assert runs[3].info["held_time_step"] == pytest.approx(runs[0].info["held_time_step"] / 10, rel=0.05)
    changes = phase_metric_changes(coarse, fine)
    assert len(changes) >= 20, sorted(changes)
    later = [phase_index(profile, "steady"), phase_index(profile, "deceleration")]
    worst = max((float(np.nanmax(np.asarray(c)[later])), n) for n, c in changes.items() if not n.startswith("cage_slip"))
    print(f"the seeds' means at a tenth of the step: worst steady or deceleration change {worst[0]:.3%} ({worst[1]})")
    for name, change in changes.items():
        limit = 1e-3 if name.startswith("cage_slip") else 0.01
        assert np.all(np.asarray(change)[later] < limit), (name, change)
