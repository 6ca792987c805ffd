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
        "lubricated_dry_wall_s": 2.0, "lubricated_wall_s": 2.2, "lubricated_cost_ratio": 1.1})


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
