"""The benchmark's pieces run against the current integrators (no timings are asserted).

``rvsweep bench`` calls the numba integrator directly, outside ``run_case``; a change to
the integrator's signature once broke it unnoticed. This runs its scipy comparison on a
1 ms window so that such a break fails here. Speed itself is measured by the command,
never asserted. The full cycle (tens of seconds per method) is not run here: how its
per-method figures are put together (prefixes, the default method's unprefixed copy,
``speedup_vs_rk4``) is checked on stand-in figures.
"""
from __future__ import annotations

import importlib.util
import json
import math

import numpy as np
import pytest

import pipeline.bench as bench
from pipeline.bench import CYCLE_FIGURES, scipy_comparison
from pipeline.cli import main
from rvcore.simulation.settings import SolverSettings
from rvcore.integrate.methods import NAMES as METHODS

_NO_IMEX = importlib.util.find_spec("rvcore.integrate.imex") is None


@pytest.mark.parametrize("method", [
    "rk4", pytest.param("imex", marks=pytest.mark.skipif(_NO_IMEX, reason="rvcore.integrate.imex not there yet"))])
def test_scipy_comparison_runs_and_matches_accuracy(method):
    figures = scipy_comparison(method, window=1e-3, repeats=1)
    assert figures["scipy_method"] == method
    # DOP853 was driven to at least our accuracy on the same window, and both ran
    assert math.isfinite(figures["scipy_ratio"]) and figures["scipy_ratio"] > 0, figures
    assert figures["scipy_position_error_m"] <= figures["ours_position_error_m"]
    # 4 right-hand sides per step (+1) for either method, over a whole number of steps
    steps = round(figures["scipy_window_s"] / figures["ours_window_time_step_s"])
    assert figures["ours_window_rhs_evaluations"] == 4 * steps + 1


def _stand_in_cycle(method: str) -> dict:
    """Figures of the shape full_cycle_of returns, different per method."""
    k = 1 + METHODS.index(method)
    return {name: (100 * k if name in ("steps", "rhs_evaluations") else 3.0 * k + 0.5)
            for name in CYCLE_FIGURES}


def _stand_in_scipy(method: str = "imex", **_) -> dict:
    return {"scipy_method": method, "scipy_ratio": 7.0 if method == "imex" else 2.0, "scipy_window_s": 0.01,
            "scipy_wall_s": 0.7, "ours_window_wall_s": 0.1 if method == "imex" else 0.35, "scipy_rtol": 1e-6,
            "scipy_position_error_m": 1e-9, "ours_position_error_m": 2e-9}


@pytest.fixture
def stand_ins(monkeypatch):
    monkeypatch.setattr(bench, "full_cycle_of", _stand_in_cycle)
    monkeypatch.setattr(bench, "scipy_comparison", _stand_in_scipy)
    monkeypatch.setattr(bench, "imperfection_cost", lambda: {
        "imperfection_perfect_wall_s": 2.0, "imperfection_normal_wall_s": 2.1, "imperfection_cost_ratio": 1.05})
    monkeypatch.setattr(bench, "lubricated_cost", lambda: {
        "lubricated_dry_wall_s": 2.0, "lubricated_wall_s": 2.2, "lubricated_cost_ratio": 1.1,
        "lubricated_cost_ratio_120": 1.05, "lubricated_cost_ratio_660": 1.1, "lubricated_cost_speed": 660.0})
    monkeypatch.setattr(bench, "phase_cost", lambda: {
        "phase_names": ["before startup", "startup"], "phase_windows_s": [(0.0, 0.3), (0.3, 0.8)],
        "phase_wall_s_0": 1.0, "phase_steps_0": 100, "phase_us_per_step_0": 10000.0,
        "phase_refreshes_per_step_0": 0.25, "phase_substepped_per_step_0": 0.01,
        "phase_wall_s_1": 3.0, "phase_steps_1": 200, "phase_us_per_step_1": 15000.0,
        "phase_refreshes_per_step_1": 0.125, "phase_substepped_per_step_1": 0.0, "phase_total_wall_s": 4.0})
    monkeypatch.setattr(bench, "modal_coupling", lambda: {
        "coupling_time_step_s": 3.0e-5, "coupling_balls_omega_h": 3.4, "coupling_modes_omega_h": 5.8,
        "coupling_cross_omega_h": 3.0})
    monkeypatch.setattr(bench, "flexible_cost", lambda: {
        f"{name}{suffix}": value for suffix in ("", "_start") for name, value in (
            ("flexible_cost_ratio", 1.4), ("flexible_wall_s", 1.4), ("flexible_rigid_wall_s", 1.0),
            ("flexible_time_step_s", 2.9e-5), ("flexible_rigid_time_step_s", 2.9e-5),
            ("flexible_us_per_step", 60.0), ("flexible_rigid_us_per_step", 43.0), ("flexible_window_s", (1.5, 1.6)))})


def test_full_cycle_times_every_method_and_reports_the_speedup(stand_ins):
    f = bench.run_all(quick=True)
    default = SolverSettings().method
    assert f["method"] == default
    for m in METHODS:
        for name in CYCLE_FIGURES:
            assert f[f"{m}_{name}"] == _stand_in_cycle(m)[name], (m, name)
    for name in CYCLE_FIGURES:   # the unprefixed figures are the default method's
        assert f[name] == f[f"{default}_{name}"]
    assert f["speedup_vs_rk4"] == f["rk4_full_cycle_wall_s"] / f["imex_full_cycle_wall_s"]
    # scipy_ratio is the new integrator's, rk4_scipy_ratio RK4's
    assert f["scipy_method"] == "imex" and f["scipy_ratio"] == 7.0
    assert f["rk4_scipy_method"] == "rk4" and f["rk4_scipy_ratio"] == 2.0
    assert "parallel_efficiency" not in f   # --quick
    assert f["imperfection_cost_ratio"] == 1.05
    assert f["lubricated_cost_ratio"] == 1.1
    assert f["flexible_cost_ratio"] == 1.4 and f["flexible_cost_ratio_start"] == 1.4


def test_bench_command_prints_json_and_a_table_of_both_methods(stand_ins, capsys):
    assert main(["bench", "--quick", "--json"]) == 0
    f = json.loads(capsys.readouterr().out)
    for key in ("method", "full_cycle_wall_s", "rk4_full_cycle_wall_s", "imex_full_cycle_wall_s",
                "speedup_vs_rk4", "rk4_steps", "imex_steps", "rk4_time_step_s", "imex_time_step_s",
                "scipy_ratio", "rk4_scipy_ratio"):
        assert key in f, key
    assert main(["bench", "--quick"]) == 0
    text = capsys.readouterr().out
    header = next(line for line in text.splitlines() if "rk4" in line and "imex" in line)
    assert header.split() == list(METHODS)
    speedup = next(line for line in text.splitlines() if line.strip().startswith("speedup vs rk4"))
    assert float(speedup.split()[-1]) == pytest.approx(f["speedup_vs_rk4"], abs=0.005)
    assert "Imperfections:" in text and "1.050x" in text
    lubricated = next(line for line in text.splitlines() if line.startswith("Lubricated law"))
    assert "1.100x" in lubricated and "2.20 s vs 2.00 s" in lubricated
    assert "120 deg/s 1.050x" in lubricated and "660 deg/s 1.100x" in lubricated
    stretch = next(line for line in text.splitlines() if line.strip().startswith("startup"))
    assert stretch.split()[1:5] == ["0.3-0.8", "3.00", "75.0%", "200"]
    flexible = [line for line in text.splitlines() if line.startswith("Flexible rings")]
    assert len(flexible) == 2 and all("1.400x" in line and "1.40 s vs 1.00 s" in line for line in flexible)
    assert "oscillate at omega*h 3.00 at the 30.0 us step" in text


def test_modal_coupling_rates_follow_hertz_at_the_case_s_own_step():
    """The flexible study bearing at 1.5 s: the step is the flexible case's own; the balls'
    block's fastest rate is a ball between its two race contacts, ``ω² = (k_i + k_o)/m_b``
    with ``k = 1.5·K^(2/3)·Q^(1/3)`` (Hertz) at the most loaded ball, which lies between the
    rates of the row's softest and stiffest arc taken twice (computed here from the arcs and
    the ball loads of a right-hand side at the same state); the cross terms are a finite,
    positive rate."""
    import dataclasses

    from pipeline.schema import load_bearing
    from rvcore.bearing.layout import A_K, R_ARC0, R_MB, R_NARC
    from rvcore.dynamics.ring_modes import DYNAMICS_MAX_ORDER
    from rvcore.rings.flexible import bearing_rings
    from rvcore.simulation.run import run_case

    f = bench.modal_coupling()
    _, profile, op = bench._study()
    flexible = load_bearing(bench.FLEXIBLE_BEARING)
    rings = bearing_rings(flexible, max_order=DYNAMICS_MAX_ORDER)
    info = run_case(flexible, profile, op, dataclasses.replace(SolverSettings(), end_time=2e-4), rings=rings).info
    h = f["coupling_time_step_s"]
    assert h == pytest.approx(info["time_step"], rel=1e-12)
    # the bracket, from the state's ball loads (a flexible case's initial state at 1.5 s)
    from rvcore.bearing.imperfections import realize
    from rvcore.contact.film import with_film_columns
    from rvcore.dynamics.rhs import B_QI, B_QO, new_diagnostics, rhs
    from rvcore.dynamics.ring_modes import truncated, with_ring_modes
    from rvcore.simulation.initial_state import initial_state
    from rvcore.simulation.run import compile_bearing

    b = realize(flexible, 0)
    rings = truncated(bearing_rings(b, max_order=DYNAMICS_MAX_ORDER), DYNAMICS_MAX_ORDER)
    model = with_ring_modes(with_film_columns(compile_bearing(b, friction=False, damping=False, gravity=True), b),
                            rings, DYNAMICS_MAX_ORDER)
    resolved = profile.resolve(op)
    table, meta = resolved.arrays()
    y = initial_state(model, resolved, 1.5, seed=0, rings=rings)
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    rhs(1.5, y, np.zeros_like(y), model.params, model.rows, model.arcs, model.pockets, table, meta, diag, bdiag)
    row = model.rows[0]
    k_arc = model.arcs[int(row[R_ARC0]):int(row[R_ARC0]) + int(row[R_NARC]), A_K]
    q = max(bdiag[:, B_QI].max(), bdiag[:, B_QO].max())
    lo, hi = (math.sqrt(2 * 1.5 * k ** (2 / 3) * q ** (1 / 3) / row[R_MB]) * h for k in (k_arc.min(), k_arc.max()))
    assert 0.97 * lo <= f["coupling_balls_omega_h"] <= 1.03 * hi, (lo, f["coupling_balls_omega_h"], hi)
    assert 0 < f["coupling_cross_omega_h"] < math.inf


def test_phase_cost_cuts_the_cycle_at_the_phases_and_counts_every_step_once():
    """The reduced bearing on the short cycle: the stretches are the profile's phases with
    what lies before and after them, end to end from 0 to the cycle's duration; each
    stretch's steps are its length over the case's step (the phases' edges are whole
    output intervals, which the step divides): the longer step where the loads and speed
    are held, in the steady phase but for its last ``HELD_END_MARGIN``
    (rvcore.integrate.schedule), and in the unload after the deceleration (the ring at
    standstill, the loads falling), and together they are the whole cycle's."""
    from pipeline.schema import load_bearing, load_profile
    from pipeline.schema.shipped import shipped_file
    from rvcore.integrate.schedule import HELD_END_MARGIN
    from rvcore.profile import OperatingPoint
    from rvcore.simulation.run import run_case

    bearing = load_bearing(shipped_file("bearings/reduced-test.toml"))
    profile = load_profile(shipped_file("profiles/short.toml"))
    op = OperatingPoint(math.radians(660.0), 30e3, 10e3)
    f = bench.phase_cost(bearing, profile, op)
    names = [p[0] for p in sorted(profile.phases, key=lambda p: p[1])]
    assert f["phase_names"] == [f"before {names[0]}", *names, f"after {names[-1]}"]
    windows = f["phase_windows_s"]
    assert windows[0][0] == 0.0 and windows[-1][1] == pytest.approx(profile.duration)
    assert all(a[1] == b[0] for a, b in zip(windows, windows[1:]))
    whole = run_case(bearing, profile, op, SolverSettings()).info
    steps = [f[f"phase_steps_{k}"] for k in range(len(windows))]
    assert whole["held_time_step"] > whole["time_step"]
    m = HELD_END_MARGIN
    expected = {"steady": lambda a, b: round((b - a - m) / whole["held_time_step"]) + round(m / whole["time_step"]),
                f"after {names[-1]}": lambda a, b: round((b - a) / whole["held_time_step"])}
    plain = lambda a, b: round((b - a) / whole["time_step"])   # noqa: E731
    assert steps == [expected.get(name, plain)(a, b) for (a, b), name in zip(windows, f["phase_names"])]
    assert sum(steps) == whole["steps"]


# --------------------------------------------------------------------------- ball scaling
def test_the_scaled_study_bearing_keeps_the_study_spacing_and_sections():
    """Z balls at the study's spacing: the pitch circle's circumference over Z is the
    study's π·351.5 mm/51 (rv-main-study.toml), and the rings' and cage's radial
    sections are the study's (Table 2: bore 320, outside 383, cage 354.5-366 mm)."""
    from rvcore.bearing.layout import compile_bearing

    for z in (51, 102, 204):
        b = bench.scaled_study_bearing(z)
        row = b.rows[0]
        assert row.ball_count == z and compile_bearing(b).n_balls == z
        assert math.isclose(math.pi * row.pitch_diameter / z, math.pi * 0.3515 / 51, rel_tol=1e-12)
        assert math.isclose(b.outer_diameter - b.bore, 0.383 - 0.320, rel_tol=1e-9)
        assert math.isclose(row.cage.outer_diameter - row.cage.inner_diameter, 0.366 - 0.3545, rel_tol=1e-9)
        assert math.isclose(row.cage.inner_diameter - row.pitch_diameter, 0.3545 - 0.3515, abs_tol=1e-12)
        assert row.ball_diameter == 0.023


def test_ball_scaling_reports_a_cost_per_ball_step_at_each_count():
    """A 0.5 ms window at 12 and 24 balls, three rounds: each count's figures, the first
    count's ratio 1 in every round, each ratio's median within its rounds' range, a whole
    number of steps over the window (no timing asserted)."""
    f = bench.ball_scaling((12, 24), start_time=0.03, end_time=0.0305, rounds=3)
    assert f["ball_scaling_counts"] == [12, 24] and f["ball_scaling_rounds"] == 3
    assert f["ball_scaling_ratio_range_12"] == [1.0, 1.0]
    lo, hi = f["ball_scaling_ratio_range_24"]
    assert lo <= f["ball_scaling_ratio_24"] <= hi
    for z in (12, 24):
        # a difference of two CPU times over a window this short may come out of either
        # sign (the case's fixed costs vary more): finite is all a test can say of it
        assert math.isfinite(f[f"us_per_ball_step_{z}"])
        assert f[f"ball_scaling_steps_{z}"] >= 1
        assert 0.0 <= f[f"ball_scaling_substepped_per_step_{z}"] <= 1.0
        assert 0.0 < f[f"ball_scaling_refreshes_per_step_{z}"] <= 1.0     # the first step evaluates them
    assert f["ball_scaling_ratio_12"] == 1.0


@pytest.mark.parametrize("text", ["51,x", "300", "", "11", "51,,102"])
def test_bench_balls_refuses_a_bad_list_in_one_line(text, capsys):
    assert main(["bench", "--balls", text]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--balls" in err and repr(text) in err


@pytest.mark.parametrize("argv", [["--balls", "51,102", "--rounds", "x"], ["--balls", "51", "--rounds", "0"],
                                  ["--balls", "51", "--rounds", "5,6"], ["--rounds", "3"]])
def test_bench_rounds_refuses_a_bad_value_in_one_line(argv, capsys):
    """A bad --rounds, or --rounds without --balls: one line naming --rounds and the value
    as typed, before any work."""
    assert main(["bench", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--rounds" in err and repr(argv[-1]) in err


@pytest.mark.parametrize("text", ["1000,x", "0", "", "2000000", "10,,20"])
def test_bench_tasks_refuses_a_bad_list_in_one_line(text, capsys):
    assert main(["bench", "--tasks", text]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--tasks" in err and repr(text) in err


def test_scheduler_cost_runs_every_stand_in_case_through_the_sweep_s_cluster():
    """Six stand-in cases on the sweep's own local cluster (bound to 127.0.0.1 by
    pipeline.run.cluster.client): each submitted case comes back (the function raises
    otherwise), and the figures are those of a CPU time over the cases (no timing asserted)."""
    f = bench.scheduler_cost((6,), workers=1)
    assert f["scheduler_workers"] == 1
    assert f["parent_cpu_per_task_ms_6"] > 0.0 and f["scheduler_wall_s_6"] > 0.0
    assert f["cluster_start_s_6"] > 0.0
