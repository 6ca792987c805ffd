"""The sweep says what it will cost before it starts, refuses a huge one without --yes,
and says when numba is compiling."""
from __future__ import annotations

import dataclasses

import math
from pathlib import Path

import pytest

import pipeline.run
import rvcore._numba
from pipeline.cli import main
from pipeline.run.estimate import (CONFIRM_CASES, case_seconds, duration_text, kernels_need_compiling,
                                   say_if_compiling)
from pipeline.schema import read_sweep_file
from tests.schema.test_sweepfile import make_sweep

REPO = Path(__file__).resolve().parents[2]


def _case(sweep, speed_deg, load_kn):
    return next(c for c in sweep.cases if math.isclose(math.degrees(c.point["speed"]), speed_deg)
                and math.isclose(c.point["radial_load"], load_kn * 1e3))


def test_the_estimate_matches_the_measurements_it_claims():
    """Measured on this project's 2-core machine (pipeline/run/estimate.py; the cases'
    seconds in status.json after `make sweep` and `make smoke` on a fresh clone): with
    IMEX, the default (MODEL_VERSION 23, 2026-11-30), the study sweep's 150 cases took
    533.7 s of the cores, 3.44 s a 30 kN case on average, a 40 kN case 1.19 times a 20 kN
    one, a smoke case 0.29 s; with RK4 (MODEL_VERSION 9) a smoke case 3.0 s, a study case
    26.8 s at 30 kN, a 40 kN study case 1.60 times a 20 kN one."""
    smoke = read_sweep_file(REPO / "sweeps" / "smoke.toml")
    study = read_sweep_file(REPO / "sweeps" / "study.toml")

    def rk4(spec):
        return dataclasses.replace(spec, settings=dataclasses.replace(spec.settings, method="rk4"))

    assert sum(case_seconds(c) for c in study.cases) == pytest.approx(533.7, rel=0.2)
    assert case_seconds(_case(study, 420, 30)) == pytest.approx(3.44, rel=0.2)
    assert case_seconds(_case(study, 420, 40)) / case_seconds(_case(study, 420, 20)) == pytest.approx(1.19, rel=0.1)
    assert case_seconds(_case(smoke, 390, 30)) == pytest.approx(0.29, rel=0.2)
    assert case_seconds(rk4(_case(smoke, 390, 30))) == pytest.approx(3.0, rel=0.2)
    assert case_seconds(rk4(_case(study, 420, 30))) == pytest.approx(26.8, rel=0.2)
    assert (case_seconds(rk4(_case(study, 420, 40))) / case_seconds(rk4(_case(study, 420, 20)))
            == pytest.approx(1.60, rel=0.1))


def test_a_flexible_ring_and_the_lubricated_law_cost_what_the_bench_measured():
    """``rvsweep bench``'s ratios on the study bearing (docs/performance.md): a flexible
    case 1.74–1.88× the same bearing with rigid rings, a lubricated one 1.03–1.20× the dry."""
    study = read_sweep_file(REPO / "sweeps" / "study.toml")
    flexible = read_sweep_file(REPO / "sweeps" / "study-flexible.toml")
    lubricated = read_sweep_file(REPO / "sweeps" / "study-lubricated.toml")
    dry = case_seconds(_case(study, 660, 30))
    assert 1.74 <= case_seconds(_case(flexible, 660, 30)) / dry <= 1.88
    assert 1.03 <= case_seconds(_case(lubricated, 660, 30)) / dry <= 1.20


@pytest.mark.parametrize("seconds, text", [(4, "4 s"), (44, "40 s"), (600, "10 min"), (3234, "54 min"),
                                           (9000, "2.5 h")])
def test_duration_text(seconds, text):
    assert duration_text(seconds) == text


def _big_grid(tmp_path):
    n = CONFIRM_CASES // 20 + 1   # 20 x n > CONFIRM_CASES
    speeds = ", ".join(f'"{100 + k} deg/s"' for k in range(n))
    loads = ", ".join(f'"{20 + k} kN"' for k in range(20))
    return make_sweep(tmp_path, f"[axes]\nspeed = [{speeds}]\nradial_load = [{loads}]\n[fixed]\naxial_load = \"10 kN\"\n")


class Started(Exception):
    pass


def test_a_huge_sweep_needs_yes(tmp_path, capsys, monkeypatch):
    def started(*a, **k):
        raise Started
    monkeypatch.setattr(pipeline.run, "run_sweep", started)
    path = _big_grid(tmp_path)
    code = main(["sweep", str(path), "--out", str(tmp_path / "out"), "--workers", "2", "--no-progress"])
    out, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1 and "--yes" in err, err
    n = len(read_sweep_file(path).cases)
    assert f"s: {n} cases, {n} to compute, about" in out and "on 2 workers" in out
    with pytest.raises(Started):
        main(["sweep", str(path), "--out", str(tmp_path / "out"), "--workers", "2", "--no-progress", "--yes"])


def test_the_smoke_run_said_its_cases_and_time_first(smoke_run):
    first = smoke_run.sweep_printed.splitlines()[0]
    assert first.startswith("smoke: 9 cases, 9 to compute, about ") and first.endswith("(rough estimate)")


def test_compiling_is_announced_only_when_it_happens(smoke_run, monkeypatch, capsys):
    # after the smoke run the kernels are in the cache
    assert not kernels_need_compiling()
    assert say_if_compiling() is False and capsys.readouterr().err == ""
    # other sources than those the cache was built from: compiling
    monkeypatch.setattr(rvcore._numba, "sources_hash", lambda: "0" * 64)
    assert kernels_need_compiling()
    assert say_if_compiling() is True
    assert capsys.readouterr().err.startswith("compiling the numba kernels")


def test_the_sweep_compiles_here_only_where_the_cache_has_no_kernels(monkeypatch, capsys):
    """pipeline.run.cluster.warm_up compiles the kernels in the sweep's own process only
    where the cache of these sources has none (then the workers only load them); where it
    has them, each worker loads them, and this process loads nothing."""
    import pipeline.run.cluster as cluster
    import rvcore.simulation.run

    calls = []
    monkeypatch.setattr(rvcore.simulation.run, "warm_up", lambda: calls.append(1))
    monkeypatch.setattr(rvcore._numba, "cache_dir", lambda: Path("/nonexistent-rvsweep-cache"))
    assert kernels_need_compiling()
    cluster.warm_up(None)
    assert calls == [1] and capsys.readouterr().err.startswith("compiling the numba kernels")
    monkeypatch.setattr("pipeline.run.estimate.kernels_need_compiling", lambda: False)
    assert cluster.warm_up(None) == 0.0 and calls == [1] and capsys.readouterr().err == ""
    assert cluster.warm_up(lambda *a, **k: None) == 0.0 and calls == [1]   # a stand-in core: nothing
