"""The kernels' cache is shared by installs at different paths (rvcore._numba, issue 42).

A cluster's workers run from installs of their own (two clones here, at two paths), and
a user-wide cache directory named by the sources' hash and the CPU model, found by a
locator that ignores the install's path, lets them share one compile per CPU model.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import time
from pathlib import Path

import pytest

from tests.pipeline.processes import dask_bin, stop
from tests.schema.test_sweepfile import make_sweep

REPO = Path(__file__).resolve().parents[2]


#: Two real cases of the reduced 12-ball bearing, a little of the start of the short cycle.
TINY_REAL = """
[axes]
speed = ["120 deg/s", "660 deg/s"]
radial_load = ["30 kN"]

[fixed]
axial_load = "10 kN"

[solver]
output_rate = "2000 Hz"
start_time = "0.03 s"
end_time = "0.04 s"
"""


def _install(where: Path) -> Path:
    """A copy of the project's packages at ``where`` (an install at another path)."""
    for pkg in ("rvcore", "pipeline"):
        shutil.copytree(REPO / pkg, where / pkg, ignore=shutil.ignore_patterns("__pycache__"))
    return where


@pytest.mark.slow
def test_two_workers_installed_at_different_paths_compile_the_kernels_once(tmp_path):
    """Two dask workers, one from each of two installs at different paths, with one empty
    user-wide cache: both load the kernels as the sweep starts (together, as the runner
    asks them), and between them every kernel is compiled once: one worker compiles,
    the other compiles nothing, and both compute their cases."""
    from distributed import Client

    from pipeline.run import run_sweep

    cache = tmp_path / "cache"
    installs = [_install(tmp_path / "a"), _install(tmp_path / "b")]
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "PYTHONPATH")}
    env["RVSWEEP_CACHE_DIR"] = str(cache)
    env["RVSWEEP_COMPILE_NOTICES"] = "1"
    scheduler_file = tmp_path / "scheduler.json"
    logs = tmp_path / "logs"
    logs.mkdir()
    procs = []
    try:
        procs.append(subprocess.Popen(
            [str(dask_bin()), "scheduler", "--host", "127.0.0.1", "--port", "0", "--dashboard-address", ":0",
             "--scheduler-file", str(scheduler_file)],
            cwd=tmp_path, env=dict(env, PYTHONPATH=str(installs[0])), stdout=subprocess.DEVNULL,
            stderr=open(logs / "scheduler.log", "wb")))
        deadline = time.monotonic() + 60
        while not scheduler_file.exists():
            assert procs[0].poll() is None and time.monotonic() < deadline, (logs / "scheduler.log").read_text()
            time.sleep(0.2)
        for k, install in enumerate(installs):
            procs.append(subprocess.Popen(
                [str(dask_bin()), "worker", "--scheduler-file", str(scheduler_file), "--nthreads", "1",
                 "--no-nanny", "--no-dashboard", "--host", "127.0.0.1", "--name", f"w{k}"],
                cwd=tmp_path, env=dict(env, PYTHONPATH=str(install)), stdout=open(logs / f"w{k}.out", "wb"),
                stderr=open(logs / f"w{k}.log", "wb")))
        with Client(json.loads(scheduler_file.read_text())["address"], timeout="30s") as client:
            client.wait_for_workers(2, timeout=120)
            result = run_sweep(make_sweep(tmp_path, TINY_REAL), tmp_path / "out", scheduler_file=scheduler_file,
                               progress=False)
            assert result.ok, result
            from rvcore._numba import cache_report

            reports = sorted(client.run(cache_report).values(), key=lambda r: r["package"])
    finally:
        for p in reversed(procs):
            stop(p)
    # each worker ran its own install, and both cached in the one directory under the root
    assert [Path(r["package"]) for r in reports] == [i / "rvcore" for i in installs]
    assert reports[0]["cache_dir"] == reports[1]["cache_dir"]
    assert Path(reports[0]["cache_dir"]).is_relative_to(cache)
    compiled = sorted(len(r["compiled"]) for r in reports)
    notices = sum((logs / f"w{k}.log").read_text().count("rvcore: compiled ") for k in range(2))
    # one compile: one worker compiled the kernels, the other none; the notices agree
    assert compiled[0] == 0 and compiled[1] > 10, reports
    assert notices == compiled[1]
    # the kernels are there, and nowhere in either install
    assert any(cache.rglob("*.nbi"))
    assert not [p for i in installs for p in (i / "rvcore").rglob("*.nbi")]
