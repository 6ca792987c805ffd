"""Running sweeps: resumable atomic case files, failures, schedulers, the command line.

Synthetic case functions stand in for the dynamics (the physics is not the point here);
they are module-level so that dask workers can import them by reference.
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import rvcore.simulation.run
from pipeline.cli import main
from pipeline.io import read_status, status_counts
from pipeline.run import run_sweep
from pipeline.schema import read_sweep_file
from tests.pipeline.synthetic import synthetic_result
from tests.pipeline.processes import dask_bin, stop
from tests.schema.test_sweepfile import GRID, make_sweep

REPO = Path(__file__).resolve().parents[2]

# the 2 x 2 grid of GRID
SPEEDS = (math.radians(120), math.radians(660))
LOADS = (20e3, 40e3)


def synthetic_case(bearing, profile, op, settings, sensors=()):
    """A made-up but well-formed CaseResult of the operating point (no dynamics)."""
    return synthetic_result(op.speed, op.radial_load, op.axial_load, n=47)


def failing_case(bearing, profile, op, settings, sensors=()):
    """Like synthetic_case, but the 660 deg/s, 40 kN case blows up."""
    if op.speed > 10 and op.radial_load > 30e3:
        raise rvcore.simulation.run.SimulationError("simulation blew up at t = 0.1 s (test)")
    return synthetic_case(bearing, profile, op, settings)


#: Where :func:`worker_killing_case` notes each attempt of its killing case (the workers
#: inherit the environment of the process that starts the local cluster).
ATTEMPTS_FILE = "RVSWEEP_TEST_ATTEMPTS_FILE"


def worker_killing_case(bearing, profile, op, settings, sensors=()):
    """Like synthetic_case, but the 120 deg/s, 40 kN case kills its worker process
    (after appending a line to the file named by ``$RVSWEEP_TEST_ATTEMPTS_FILE``, if set)."""
    if op.speed < 3 and op.radial_load > 30e3:
        if os.environ.get(ATTEMPTS_FILE):
            with open(os.environ[ATTEMPTS_FILE], "a") as f:
                f.write(f"{os.getpid()}\n")
        os._exit(13)
    return synthetic_case(bearing, profile, op, settings)


class Counting:
    """A case function that records which operating points it computed (serial runs)."""

    def __init__(self, fn=synthetic_case, interrupt_after=None):
        self.fn = fn
        self.calls = []
        self.interrupt_after = interrupt_after

    def __call__(self, bearing, profile, op, settings, sensors=()):
        if self.interrupt_after is not None and len(self.calls) == self.interrupt_after:
            raise KeyboardInterrupt
        self.calls.append((op.speed, op.radial_load))
        return self.fn(bearing, profile, op, settings)


def fingerprint(folder: Path) -> dict:
    """name -> (mtime_ns, sha256) of every case file."""
    return {p.name: (p.stat().st_mtime_ns, hashlib.sha256(p.read_bytes()).hexdigest())
            for p in sorted((folder / "cases").glob("*.nc"))}


def case_files(folder: Path) -> list:
    return sorted((folder / "cases").glob("*.nc"))


def assert_same_case_data(a: Path, b: Path):
    """Data, coordinates, encodings and attributes identical; only ``history`` may differ."""
    with xr.open_dataset(a) as da, xr.open_dataset(b) as db:
        da, db = da.load(), db.load()
    assert "history" in da.attrs and "history" in db.attrs
    for d in (da, db):
        del d.attrs["history"]
    xr.testing.assert_identical(da, db)
    for name in da.variables:
        for k in ("zlib", "chunksizes", "dtype", "complevel"):
            assert da[name].encoding.get(k) == db[name].encoding.get(k), (name, k)


@pytest.fixture
def grid_sweep(tmp_path):
    return make_sweep(tmp_path, GRID)


@pytest.fixture(scope="module")
def serial_reference(tmp_path_factory):
    """The 2 x 2 synthetic sweep, run serially once for comparisons."""
    folder = tmp_path_factory.mktemp("serial")
    path = make_sweep(folder, GRID)
    result = run_sweep(path, folder / "out", serial=True, case_fn=synthetic_case, progress=False)
    return path, result


# --------------------------------------------------------------------------- serial


def test_serial_sweep_writes_case_files_status_and_the_combined_grid(grid_sweep, tmp_path):
    sweep = read_sweep_file(grid_sweep)
    out = tmp_path / "out"
    result = run_sweep(sweep, out, serial=True, case_fn=synthetic_case, progress=False)
    assert result.ok and len(result.computed) == 4 and not result.reused

    ids = {c.case_id for c in sweep.cases}
    assert {p.stem for p in case_files(out)} == ids
    assert not [p for p in (out / "cases").iterdir() if p.suffix != ".nc"]   # no temporaries
    for p in case_files(out):
        with xr.open_dataset(p) as ds:
            assert ds.attrs["configuration_hash"] == p.stem

    status = read_status(out)
    assert set(status) == ids
    assert status_counts(status) == {"ok": 4, "failed": 0, "not_run": 0}
    points = {(round(v["speed"], 12), v["radial_load"]) for v in status.values()}
    assert points == {(round(w, 12), f) for w in SPEEDS for f in LOADS}

    with xr.open_dataset(out / "sweep.nc") as ds:
        assert ds["radial_displacement"].dims == ("speed", "radial_load", "elapsed_time")
        assert ds["radial_displacement_range"].dims == ("speed", "radial_load", "phase")
        assert list(ds["speed"].values) == [120.0, 660.0]
        assert ds["speed"].attrs["units"] == "degree s-1"
        assert list(ds["radial_load"].values) == [20e3, 40e3]
        assert float(ds["axial_load"]) == 10e3
        assert (ds["case_status"].values == 0).all()
        # each case sits at its own grid point: the synthetic profile reaches the
        # operating point's load and speed exactly
        for w in (120.0, 660.0):
            for f in (20e3, 40e3):
                cell = ds.sel(speed=w, radial_load=f)
                assert float(cell["applied_radial_load"].max()) == f
                assert math.isclose(float(cell["inner_ring_speed"].max()), math.radians(w), rel_tol=1e-12)
        assert len(ds.attrs["history"].splitlines()) == 3


# --------------------------------------------------------------------------- resuming


def test_rerun_after_lost_cases_computes_only_those(grid_sweep, tmp_path):
    out = tmp_path / "out"
    run_sweep(grid_sweep, out, serial=True, case_fn=synthetic_case, progress=False)
    files = case_files(out)
    lost = files[:2]
    for p in lost:
        p.unlink()
    kept = fingerprint(out)
    assert len(kept) == 2

    counting = Counting()
    result = run_sweep(grid_sweep, out, serial=True, case_fn=counting, progress=False)
    assert len(counting.calls) == 2
    assert sorted(result.computed) == sorted(p.stem for p in lost)
    assert sorted(result.reused) == sorted(Path(n).stem for n in kept)
    after = fingerprint(out)
    for name, fp in kept.items():
        assert after[name] == fp          # not rewritten: same bytes, same mtime
    assert set(after) == {p.name for p in files}


def test_interrupted_sweep_keeps_finished_cases_and_resumes(grid_sweep, tmp_path):
    out = tmp_path / "out"
    first = Counting(interrupt_after=2)            # Ctrl-C while the third case runs
    with pytest.raises(KeyboardInterrupt):
        run_sweep(grid_sweep, out, serial=True, case_fn=first, progress=False)
    assert len(case_files(out)) == 2
    for p in case_files(out):
        with xr.open_dataset(p) as ds:             # complete, readable files
            assert ds["radial_displacement"].size > 0
    status = read_status(out)
    assert status_counts(status) == {"ok": 2, "failed": 0, "not_run": 2}
    with xr.open_dataset(out / "sweep.nc") as ds:
        assert sorted(ds["case_status"].values.ravel().tolist()) == [0, 0, 2, 2]
        missing = ds["case_status"].values == 2
        means = ds["radial_displacement_mean"].values          # (speed, radial_load, phase)
        assert np.isnan(means[missing]).all()
        assert not np.isnan(means[~missing]).any()
    kept = fingerprint(out)

    second = Counting()
    result = run_sweep(grid_sweep, out, serial=True, case_fn=second, progress=False)
    assert result.ok
    assert sorted(second.calls) == sorted(set((w, f) for w in SPEEDS for f in LOADS) - set(first.calls))
    after = fingerprint(out)
    assert all(after[n] == fp for n, fp in kept.items())


def test_a_changed_value_reruns_only_the_cases_it_changes(tmp_path):
    out = tmp_path / "out"
    run_sweep(make_sweep(tmp_path, GRID, "a.toml"), out, serial=True, case_fn=synthetic_case,
              progress=False)
    before = fingerprint(out)
    counting = Counting()
    changed = make_sweep(tmp_path, GRID.replace('"40 kN"', '"30 kN"'), "b.toml")
    result = run_sweep(changed, out, serial=True, case_fn=counting, progress=False)
    assert sorted(f for _, f in counting.calls) == [30e3, 30e3]
    assert len(result.reused) == 2
    after = fingerprint(out)
    for name in result.reused:
        assert after[f"{name}.nc"] == before[f"{name}.nc"]


def test_stale_temporaries_of_dead_writers_are_removed(grid_sweep, tmp_path):
    out = tmp_path / "out"
    (out / "cases").mkdir(parents=True)
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = out / "cases" / f".0123456789abcdef.nc.{dead.pid}.x1y2z3.tmp"
    stale.write_bytes(b"half a file")
    live = out / "cases" / f".fedcba9876543210.nc.{os.getppid()}.a1b2c3.tmp"
    live.write_bytes(b"someone else's file in progress")
    run_sweep(grid_sweep, out, serial=True, case_fn=synthetic_case, progress=False)
    assert not stale.exists()
    assert live.exists()
    assert len(case_files(out)) == 4


def ramp_case(bearing, profile, op, settings, sensors=()):
    """inner_ring_z = 1 um/s * t, sampled at 31 or 47 points depending on the load."""
    r = synthetic_result(op.speed, op.radial_load, op.axial_load, n=31 if op.radial_load > 30e3 else 47)
    r.series["inner_ring_z"] = 1e-6 * r.time
    return r


def test_cases_with_different_sample_times_share_one_time_grid(tmp_path):
    path = make_sweep(tmp_path, GRID + '[solver]\noutput_rate = "10 Hz"\n')
    result = run_sweep(path, tmp_path / "out", serial=True, case_fn=ramp_case, progress=False)
    with xr.open_dataset(result.combined) as ds:
        t = ds["elapsed_time"].values
        np.testing.assert_allclose(t, np.arange(47) * 0.1, rtol=0, atol=1e-12)   # 0 ... 4.6 s by 1/10 s
        # a straight line is interpolated exactly, whichever samples a case had
        z = ds["inner_ring_z"].values
        np.testing.assert_allclose(z, np.broadcast_to(1e-6 * t, z.shape), rtol=1e-9, atol=1e-18)
        assert "interpolated" in ds["inner_ring_z"].attrs["comment"]
        assert "interpolated" in ds.attrs["history"]


def test_explicit_cases_sit_on_the_grid_of_their_values(tmp_path):
    path = make_sweep(tmp_path, """
[fixed]
axial_load = "10 kN"
[[cases]]
speed = "120 deg/s"
radial_load = "30 kN"
[[cases]]
speed = "660 deg/s"
radial_load = "30 kN"
[[cases]]
speed = "120 deg/s"
radial_load = "20 kN"
""")
    result = run_sweep(path, tmp_path / "out", serial=True, case_fn=synthetic_case, progress=False)
    assert result.ok and len(result.computed) == 3
    with xr.open_dataset(result.combined) as ds:
        assert list(ds["speed"].values) == [120.0, 660.0]
        assert list(ds["radial_load"].values) == [20e3, 30e3]
        # the one combination no case asked for is empty and says so
        assert ds["case_status"].values.tolist() == [[0, 0], [2, 0]]
        assert bool(ds["radial_displacement"].sel(speed=660.0, radial_load=20e3).isnull().all())
        assert float(ds["applied_radial_load"].sel(speed=660.0, radial_load=30e3).max()) == 30e3


# --------------------------------------------------------------------------- failures


def test_a_failing_case_is_recorded_and_the_others_finish(grid_sweep, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(rvcore.simulation.run, "run_case", failing_case)
    code = main(["sweep", str(grid_sweep), "--out", str(tmp_path / "res"), "--serial", "--no-progress"])
    assert code != 0
    out = tmp_path / "res" / "s"
    sweep = read_sweep_file(grid_sweep)
    bad = [c for c in sweep.cases if c.operating_point.speed > 10 and c.operating_point.radial_load > 30e3]
    assert len(bad) == 1
    bad_id = bad[0].case_id
    printed = capsys.readouterr().out
    assert bad_id in printed and "blew up" in printed

    assert {p.stem for p in case_files(out)} == {c.case_id for c in sweep.cases} - {bad_id}
    status = read_status(out)
    assert status[bad_id]["state"] == "failed"
    assert "SimulationError" in status[bad_id]["reason"]
    assert status[bad_id]["radial_load"] == 40e3
    assert status_counts(status) == {"ok": 3, "failed": 1, "not_run": 0}
    with xr.open_dataset(out / "sweep.nc") as ds:
        assert int(ds["case_status"].sel(speed=660.0, radial_load=40e3)) == 1
        assert bool(ds["radial_displacement"].sel(speed=660.0, radial_load=40e3).isnull().all())
        assert int((ds["case_status"] == 0).sum()) == 3


def test_sweep_with_report_writes_the_report_in_its_process_also_after_a_failed_case(
        grid_sweep, tmp_path, monkeypatch, capsys):
    """``rvsweep sweep --report``: the report of the folder the sweep wrote, as
    ``rvsweep report`` writes it, after the summary and also where a case failed (the exit
    status still says so); a report option without --report is refused before any case."""
    monkeypatch.setattr(rvcore.simulation.run, "run_case", failing_case)
    out = tmp_path / "res"
    assert main(["sweep", str(grid_sweep), "--out", str(out), "--serial", "--no-progress", "--target-s0", "2"]) == 2
    assert "--target-s0: a report option; it needs --report" in capsys.readouterr().err
    assert not out.exists()
    code = main(["sweep", str(grid_sweep), "--out", str(out), "--serial", "--no-progress", "--report",
                 "--target-s0", "2"])
    assert code == 1
    printed = capsys.readouterr().out
    folder = out / "s"
    assert printed.index("1 failed") < printed.index(f"wrote {folder / 'metrics.nc'}")
    assert "note: 1 case(s) failed or missing" in printed
    assert (folder / "report" / "report.html").is_file() and (folder / "fits.nc").is_file()
    assert "| ≥ 2 |" in (folder / "report" / "report.md").read_text(encoding="utf-8")   # the target, in the headline


def _spy_run_case(monkeypatch):
    calls = []
    monkeypatch.setattr(rvcore.simulation.run, "run_case", lambda *a, **k: calls.append(a))
    return calls


@pytest.mark.parametrize("what,edit,key", [
    ("unknown key", lambda g: g + "\n[solver]\nstepsize = 1\n", "solver.stepsize"),
    ("bad unit", lambda g: g.replace('"20 kN"', '"20 kPa"'), "axes.radial_load[0]"),
    ("empty axis", lambda g: g.replace('["120 deg/s", "660 deg/s"]', "[]"), "axes.speed"),
    ("missing bearing", None, "bearing"),
])
def test_bad_sweep_file_fails_in_one_line_before_any_case(tmp_path, monkeypatch, capsys, what, edit, key):
    if edit is None:
        path = make_sweep(tmp_path, GRID, header='bearing = "bearings/gone.toml"\nprofile = "profiles/short.toml"\n')
    else:
        path = make_sweep(tmp_path, edit(GRID))
    calls = _spy_run_case(monkeypatch)
    code = main(["sweep", str(path), "--out", str(tmp_path / "res"), "--serial", "--no-progress"])
    err = capsys.readouterr().err
    assert code != 0
    assert err.count("\n") == 1, err                        # one line
    assert str(path) in err and key in err, err
    assert "Traceback" not in err
    assert calls == []
    assert not (tmp_path / "res").exists()


# --------------------------------------------------------------------------- schedulers


def test_local_cluster_gives_the_serial_case_files(serial_reference, tmp_path):
    path, reference = serial_reference
    result = run_sweep(path, tmp_path / "local", workers=2, case_fn=synthetic_case, progress=False)
    assert result.ok and result.scheduler.startswith("local cluster of 2")
    names = [p.name for p in case_files(reference.out_dir)]
    assert names == [p.name for p in case_files(tmp_path / "local")]
    for name in names:
        assert_same_case_data(reference.out_dir / "cases" / name, tmp_path / "local" / "cases" / name)
    assert_same_case_data(reference.out_dir / "sweep.nc", tmp_path / "local" / "sweep.nc")


@pytest.mark.slow  # over 25 s of CPU: make test-all
def test_a_case_that_kills_its_worker_is_retried_then_recorded(grid_sweep, tmp_path, monkeypatch):
    # The retry is counted, not timed: with allowed_failures=1 the case runs once, is
    # retried once on a fresh worker process, and is then recorded as failed (a sweep that
    # hung instead would never return; pytest's own run would show it).
    attempts = tmp_path / "attempts.txt"
    monkeypatch.setenv(ATTEMPTS_FILE, str(attempts))
    result = run_sweep(grid_sweep, tmp_path / "out", workers=2, case_fn=worker_killing_case,
                       progress=False, allowed_failures=1)
    pids = attempts.read_text().split()
    assert len(pids) == 2 and pids[0] != pids[1]
    sweep = result.sweep
    killer = [c.case_id for c in sweep.cases
              if c.operating_point.speed < 3 and c.operating_point.radial_load > 30e3]
    assert list(result.failed) == killer
    assert "died" in result.failed[killer[0]]
    assert len(result.computed) == 3
    assert read_status(tmp_path / "out")[killer[0]]["state"] == "failed"


@pytest.fixture
def external_cluster(tmp_path):
    """``dask scheduler`` and ``dask worker`` (2 processes, 1 thread each) as subprocesses."""
    scheduler_file = tmp_path / "scheduler.json"
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO)] + [p for p in [env.get("PYTHONPATH")] if p])
    logs = tmp_path / "dask-logs"
    logs.mkdir()
    procs = []
    try:
        procs.append(subprocess.Popen(
            [str(dask_bin()), "scheduler", "--host", "127.0.0.1", "--port", "0",
             "--dashboard-address", ":0", "--scheduler-file", str(scheduler_file)],
            cwd=tmp_path, env=env, stdout=subprocess.DEVNULL,
            stderr=open(logs / "scheduler.log", "wb")))
        deadline = time.monotonic() + 60
        while not scheduler_file.exists():
            if procs[0].poll() is not None or time.monotonic() > deadline:
                pytest.fail("dask scheduler did not start: " + (logs / "scheduler.log").read_text())
            time.sleep(0.2)
        procs.append(subprocess.Popen(
            [str(dask_bin()), "worker", "--scheduler-file", str(scheduler_file),
             "--nworkers", "2", "--nthreads", "1", "--no-dashboard"],
            cwd=tmp_path, env=env, stdout=subprocess.DEVNULL,
            stderr=open(logs / "worker.log", "wb")))
        yield scheduler_file
    finally:
        for p in reversed(procs):
            stop(p)


@pytest.mark.slow  # over 25 s of CPU: make test-all
def test_external_cluster_gives_the_serial_case_files(serial_reference, external_cluster, tmp_path):
    path, reference = serial_reference
    address = json.loads(external_cluster.read_text())["address"]
    names = [p.name for p in case_files(reference.out_dir)]
    for how, kwargs in (("file", {"scheduler_file": external_cluster}), ("address", {"scheduler": address})):
        out = tmp_path / how
        result = run_sweep(path, out, case_fn=synthetic_case, progress=False, **kwargs)
        assert result.ok and result.scheduler == f"scheduler {address}"
        assert names == [p.name for p in case_files(out)]
        for name in names:
            assert_same_case_data(reference.out_dir / "cases" / name, out / "cases" / name)
        assert_same_case_data(reference.out_dir / "sweep.nc", out / "sweep.nc")


def test_cli_sweep_on_a_scheduler_file_that_does_not_exist(grid_sweep, tmp_path, capsys):
    code = main(["sweep", str(grid_sweep), "--out", str(tmp_path), "--scheduler-file",
                 str(tmp_path / "none.json"), "--no-progress"])
    err = capsys.readouterr().err
    assert code != 0 and err.count("\n") == 1 and "none.json" in err


@pytest.mark.slow
def test_real_smoke_cases_do_not_depend_on_the_scheduler(tmp_path):
    """The real core, serial and on a 2-process local cluster: identical case files."""
    smoke = REPO / "sweeps" / "smoke.toml"
    serial = run_sweep(smoke, tmp_path / "serial", serial=True, progress=False)
    local = run_sweep(smoke, tmp_path / "local", workers=2, progress=False)
    assert serial.ok and local.ok
    names = [p.name for p in case_files(serial.out_dir)]
    assert len(names) == 9 and names == [p.name for p in case_files(local.out_dir)]
    for name in names:
        assert_same_case_data(serial.out_dir / "cases" / name, local.out_dir / "cases" / name)


#: Two real cases of the reduced 12-ball bearing, through start-up into steady running
#: (0.03-0.1 s of the short cycle): cheap, but the whole contact dynamics.
REDUCED_REAL = """
[axes]
speed = ["120 deg/s", "660 deg/s"]
radial_load = ["30 kN"]

[fixed]
axial_load = "10 kN"

[solver]
output_rate = "2000 Hz"
start_time = "0.03 s"
end_time = "0.1 s"
"""


@pytest.mark.slow  # over 25 s of CPU: make test-all
def test_real_reduced_cases_do_not_depend_on_the_scheduler(tmp_path):
    """The real core on the reduced bearing, serial and on a 2-process local cluster:
    the same case files (data, coordinates, encodings, attributes; history apart)."""
    path = make_sweep(tmp_path, REDUCED_REAL)
    serial = run_sweep(path, tmp_path / "serial", serial=True, progress=False)
    local = run_sweep(path, tmp_path / "local", workers=2, progress=False)
    assert serial.ok and local.ok and local.scheduler.startswith("local cluster of 2")
    names = [p.name for p in case_files(serial.out_dir)]
    assert len(names) == 2 and names == [p.name for p in case_files(local.out_dir)]
    for name in names:
        assert_same_case_data(serial.out_dir / "cases" / name, local.out_dir / "cases" / name)
        with xr.open_dataset(serial.out_dir / "cases" / name) as ds:   # real dynamics ran
            assert ds.sizes["elapsed_time"] > 100
            assert np.isfinite(ds["radial_displacement"]).all()
            assert float(ds["radial_displacement"].max()) > 0.0
    assert_same_case_data(serial.out_dir / "sweep.nc", local.out_dir / "sweep.nc")


def test_case_files_alone_combine_as_sweep_nc(grid_sweep, tmp_path):
    """One combiner: without sweep.nc, the analysis combines cases/*.nc to the same
    variables, coordinates and status as the sweep's own sweep.nc."""
    from pipeline.analysis import open_results

    result = run_sweep(grid_sweep, tmp_path / "out", serial=True, case_fn=synthetic_case, progress=False)
    with xr.open_dataset(result.combined) as ds:
        combined = ds.load()
    result.combined.unlink()
    alone = open_results(result.out_dir)
    assert set(alone.data_vars) == set(combined.data_vars)
    for name in combined.data_vars:
        xr.testing.assert_equal(alone[name].reset_coords(drop=True), combined[name].reset_coords(drop=True))
    assert float(alone["axial_load"]) == float(combined["axial_load"]) == 10e3


def test_case_files_are_written_atomically(tmp_path, monkeypatch):
    """write_case goes through the one atomic writer: a write that fails half-way (the
    file declared, its values not yet written) leaves the old file and no temporary
    behind."""
    import h5py

    from pipeline.io import case_dataset, write_case

    ds = case_dataset(synthetic_result(math.radians(120.0), 20e3), speed=math.radians(120.0),
                      radial_load=20e3, axial_load=10e3)
    path = tmp_path / "case.nc"
    write_case(ds, path)
    before = path.read_bytes()
    real = h5py.File
    opened = []

    def broken(name, mode="r", *args, **kwargs):
        if mode != "r":
            opened.append(Path(name))
            assert Path(name).is_file()          # the temporary file, declared
            raise OSError("disk full")
        return real(name, mode, *args, **kwargs)

    monkeypatch.setattr(h5py, "File", broken)
    with pytest.raises(OSError, match="disk full"):
        write_case(ds, path)
    assert path.read_bytes() == before and len(opened) == 1 and opened[0] != path
    assert [p.name for p in tmp_path.iterdir()] == ["case.nc"]
