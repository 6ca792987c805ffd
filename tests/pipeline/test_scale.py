"""The pipeline at scale (issue 42), guarded at small size without timings: the combine's
memory does not grow with the cases, status is appended per case and written whole a
fixed number of times, a resume opens no netCDF file, the streamed ``sweep.nc`` is the
in-memory combiner's, workers write their own case files, a cluster sweep keeps a bounded
window of cases submitted and the report opens ``sweep.nc`` lazily.

Synthetic case functions stand in for the dynamics (as in test_sweep.py). Each fact is
checked against an independent path (the in-memory combiner, file counts made here),
never against numbers taken from the code under test.
"""
from __future__ import annotations

import json
import os
import tracemalloc
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

import pipeline.io.status
import pipeline.run.runner
from pipeline.io import (STATUS_LOG, StatusLog, combine_cases, combined_encoding, grid_from_cases,
                         read_status, write_atomic)
from pipeline.run import run_sweep
from pipeline.run.runner import write_combined_sweep
from pipeline.schema import read_sweep_file
from tests.pipeline.synthetic import synthetic_result
from tests.pipeline.test_sweep import Counting, failing_case, synthetic_case
from tests.schema.test_sweepfile import GRID, make_sweep


def _grid(n_speeds: int, n_loads: int) -> str:
    speeds = ", ".join(f'"{120 + 60 * k} deg/s"' for k in range(n_speeds))
    loads = ", ".join(f'"{20 + k} kN"' for k in range(n_loads))
    return f'[axes]\nspeed = [{speeds}]\nradial_load = [{loads}]\n[fixed]\naxial_load = "10 kN"\n'


#: 3 x 3 cases; failing_case fails the one at 660 deg/s, 40 kN.
GRID_3X3 = ('[axes]\nspeed = ["120 deg/s", "390 deg/s", "660 deg/s"]\nradial_load = ["20 kN", "30 kN", "40 kN"]\n'
            '[fixed]\naxial_load = "10 kN"\n')


def uneven_case(bearing, profile, op, settings, sensors=()):
    """Like failing_case, but the sample times differ between speeds (the combine resamples)."""
    if op.speed > 10 and op.radial_load > 30e3:
        return failing_case(bearing, profile, op, settings)
    return synthetic_result(op.speed, op.radial_load, op.axial_load, n=47 if op.speed < 3 else 53)


def long_case(bearing, profile, op, settings, sensors=()):
    """A synthetic case with 4000 samples (about 0.5 MB of series): memory per case shows."""
    return synthetic_result(op.speed, op.radial_load, op.axial_load, n=4000)


class OpenCounter:
    """Counts the netCDF files opened (``netCDF4.Dataset``, which xarray's engine also uses)."""

    def __init__(self, monkeypatch):
        self.opened = []
        real = netCDF4.Dataset
        counter = self

        class Counted(real):
            def __init__(self, filename, *args, **kwargs):
                counter.opened.append(str(filename))
                super().__init__(filename, *args, **kwargs)

        monkeypatch.setattr(netCDF4, "Dataset", Counted)


def _header(path) -> list:
    """What ``ncdump -h -s`` shows, read with netCDF4: dimensions, and per variable its
    type, dimensions, chunking, filters and attributes; the global attributes but history."""
    out = []
    with netCDF4.Dataset(path) as nc:
        out += [f"{k} = {len(d)}" for k, d in nc.dimensions.items()]
        for k, v in nc.variables.items():
            out.append(f"{v.dtype} {k}{v.dimensions} {v.chunking()} {v.filters()}")
            out += [f"{k}:{a} = {v.getncattr(a)!r}" for a in v.ncattrs()]
        out += [f":{a}" for a in nc.ncattrs() if a != "history"]
    return out


# --------------------------------------------------------------------------- the combine


@pytest.mark.parametrize("case_fn", [failing_case, uneven_case], ids=["same-times", "resampled"])
def test_the_streamed_sweep_nc_is_the_in_memory_combiners(tmp_path, case_fn):
    """sweep.nc, written one case at a time, holds what the in-memory combiner
    (combine_cases, the path of a folder without sweep.nc) makes of the same case files:
    the same variables, values, attributes and coordinates; and written with the
    combined encoding, the same chunking and filters. One case failed (NaN, flagged 1);
    in the second variant the cases' sample times differ, so both resample."""
    path = make_sweep(tmp_path, GRID)
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=case_fn, progress=False)
    assert len(result.failed) == 1
    streamed = xr.load_dataset(result.combined)

    files = sorted((result.out_dir / "cases").glob("*.nc"))
    cases = [xr.load_dataset(f) for f in files]
    asked = [(e, e["state"]) for e in read_status(result.out_dir).values()]
    axes, entries, fixed = grid_from_cases(cases, asked)
    memory, resampled = combine_cases(axes, entries, output_rate=result.sweep.settings.output_rate,
                                      scalars=fixed)
    assert resampled == (case_fn is uneven_case)
    assert int((streamed["case_status"] == 1).sum()) == 1
    bare = streamed.copy()
    bare.attrs = {}                      # the global attributes are the runner's, not the combiner's
    assert memory.identical(bare), "the streamed variables differ from the in-memory combine"

    memory.attrs = dict(streamed.attrs)
    reference = tmp_path / "in-memory.nc"
    write_atomic(memory, reference, encoding=combined_encoding(memory, [a.name for a in axes]))
    assert _header(reference) == _header(result.combined)


def _in_memory(result) -> xr.Dataset:
    """What the in-memory combiner (combine_cases, the path of a folder without sweep.nc)
    makes of a run's case files, on the grid read off them."""
    files = sorted((result.out_dir / "cases").glob("*.nc"))
    asked = [(e, e["state"]) for e in read_status(result.out_dir).values()]
    axes, entries, fixed = grid_from_cases([xr.load_dataset(f) for f in files], asked)
    memory, _ = combine_cases(axes, entries, output_rate=result.sweep.settings.output_rate, scalars=fixed)
    return memory


def test_the_combine_copies_the_case_files_chunks_and_reads_any_other(tmp_path, monkeypatch):
    """Each variable that a case file of this package stores as one compressed chunk is
    copied into sweep.nc as stored (one copy per such variable and file, counted here from
    the files with netCDF4); a case file written with other filters (zlib level 1) or none
    is read and written as values. Either way sweep.nc holds what the in-memory combiner
    makes of the same files."""
    import pipeline.io.combine as combine

    path = make_sweep(tmp_path, GRID)
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=failing_case, progress=False,
                       combine_at_end=False)
    files = sorted((result.out_dir / "cases").glob("*.nc"))
    assert len(files) == 3
    # one file recompressed at level 1, one without compression: their chunks are not sweep.nc's
    for f, enc in ((files[1], {"zlib": True, "complevel": 1}), (files[2], {"zlib": False})):
        ds = xr.load_dataset(f)
        ds.to_netcdf(f, engine="netcdf4",
                     encoding={k: dict(enc, _FillValue=None) for k in ds.data_vars if ds[k].ndim})

    def stored_chunks(f) -> int:
        with netCDF4.Dataset(f) as nc:
            return sum(1 for k, v in nc.variables.items()
                       if k in combine.VARIABLES and v.ndim and v.filters().get("zlib")
                       and v.filters().get("complevel") == 4 and list(v.chunking()) == list(v.shape))

    assert stored_chunks(files[0]) > 0 and stored_chunks(files[1]) == stored_chunks(files[2]) == 0
    copies = []

    class Counted(combine._RawChunk):
        def __init__(self, *args):
            copies.append(1)
            super().__init__(*args)

    monkeypatch.setattr(combine, "_RawChunk", Counted)
    combined = write_combined_sweep(result.sweep, result.out_dir, states=result.states)
    assert len(copies) == stored_chunks(files[0])

    streamed = xr.load_dataset(combined)
    streamed.attrs = {}
    assert _in_memory(result).identical(streamed)


def _noting_readers(monkeypatch, notes: Path):
    """Each case file's read notes its process id in ``notes`` (the forked readers inherit it)."""
    import pipeline.io.combine as combine

    real = combine._case_slabs

    def noted(*args, **kwargs):
        with open(notes, "a") as f:
            f.write(f"{os.getpid()}\n")
        return real(*args, **kwargs)

    monkeypatch.setattr(combine, "_case_slabs", noted)


def _values(path) -> xr.Dataset:
    ds = xr.load_dataset(path)
    ds.attrs.pop("history")
    return ds


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="the readers are forked where there are two CPUs")
@pytest.mark.parametrize("case_fn", [failing_case, uneven_case], ids=["same-times", "resampled"])
def test_the_combine_reads_in_forked_readers_what_it_reads_here(tmp_path, monkeypatch, case_fn):
    """9 cases, one failed: sweep.nc combined with its case files read in forked processes
    holds what the combine reading them in this process writes: the same header, values and
    attributes, and the same bytes but the history line's. The reads' process ids are not
    this process's. In the second variant the cases' sample times differ: a reader finds the
    file that differs from the first, and the combine starts again with every file scanned."""
    import pipeline.io.combine as combine

    path = make_sweep(tmp_path, GRID_3X3)
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=case_fn, progress=False,
                       combine_at_end=False)
    assert len(result.failed) == 1
    notes = tmp_path / "pids"
    _noting_readers(monkeypatch, notes)
    forked = tmp_path / "forked.nc"
    write_combined_sweep(result.sweep, result.out_dir, states=result.states).rename(forked)
    pids = set(notes.read_text().split())
    assert str(os.getpid()) not in pids and len(pids) >= 2, pids

    notes.unlink()
    monkeypatch.setattr(combine, "MAX_READERS", 1)
    here = write_combined_sweep(result.sweep, result.out_dir, states=result.states)
    assert set(notes.read_text().split()) == {str(os.getpid())}
    assert ("comment" in _values(here)["radial_displacement"].attrs) == (case_fn is uneven_case)
    assert _values(forked).identical(_values(here))
    assert _header(forked) == _header(here)
    # and both what the in-memory combiner makes of the case files
    bare = _values(forked)
    bare.attrs = {}
    assert _in_memory(result).identical(bare)
    a, b = forked.read_bytes(), here.read_bytes()
    assert len(a) == len(b) and sum(x != y for x, y in zip(a, b)) < 40   # the history's time


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="the readers are forked where there are two CPUs")
def test_a_reader_that_dies_leaves_the_rest_of_the_combine_to_the_parent(tmp_path, monkeypatch):
    """A forked reader ends itself at the fifth case file: the combine reads that file and
    the rest in this process, and sweep.nc holds every case."""
    import pipeline.io.combine as combine

    path = make_sweep(tmp_path, _grid(3, 3))
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=synthetic_case, progress=False,
                       combine_at_end=False)
    files = sorted((result.out_dir / "cases").glob("*.nc"))
    parent, real = os.getpid(), combine._case_slabs

    def dying(p, *args, **kwargs):
        if os.getpid() != parent and Path(p) == files[4]:
            os._exit(3)
        return real(p, *args, **kwargs)

    monkeypatch.setattr(combine, "_case_slabs", dying)
    combined = _values(write_combined_sweep(result.sweep, result.out_dir, states=result.states))
    assert int((combined["case_status"] == 0).sum()) == 9
    combined.attrs = {}
    assert _in_memory(result).identical(combined)


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="the readers are forked where there are two CPUs")
def test_a_pool_found_broken_when_a_file_is_sent_leaves_the_rest_to_the_parent(tmp_path, monkeypatch):
    """A reader that dies between two results breaks the pool before the next file is sent:
    there the pool's ``submit`` raises, not a result. The pool here breaks at its seventh
    submission (its first is the readers' start, then four files ahead and one a result),
    every time; the combine reads that file and the rest in this process."""
    import concurrent.futures
    from concurrent.futures.process import BrokenProcessPool

    class BreaksAtTheSeventhSubmit(concurrent.futures.ProcessPoolExecutor):
        submitted = 0

        def submit(self, fn, /, *args, **kwargs):
            type(self).submitted += 1
            if type(self).submitted >= 7:
                raise BrokenProcessPool("a child process terminated abruptly")
            return super().submit(fn, *args, **kwargs)

    path = make_sweep(tmp_path, _grid(3, 3))
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=synthetic_case, progress=False,
                       combine_at_end=False)
    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", BreaksAtTheSeventhSubmit)
    combined = _values(write_combined_sweep(result.sweep, result.out_dir, states=result.states))
    assert BreaksAtTheSeventhSubmit.submitted == 7
    assert int((combined["case_status"] == 0).sum()) == 9
    combined.attrs = {}
    assert _in_memory(result).identical(combined)


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="the readers are forked where there are two CPUs")
def test_a_case_file_a_reader_cannot_read_is_named(tmp_path):
    """The seventh of 9 case files truncated: the reader's error reaches the combine's
    caller as one line naming the file."""
    from pipeline.errors import UserError

    path = make_sweep(tmp_path, _grid(3, 3))
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=synthetic_case, progress=False,
                       combine_at_end=False)
    victim = sorted((result.out_dir / "cases").glob("*.nc"))[6]
    victim.write_bytes(victim.read_bytes()[:2000])
    with pytest.raises(UserError) as err:
        write_combined_sweep(result.sweep, result.out_dir, states=result.states)
    msg = str(err.value)
    assert msg.startswith(str(victim)) and "\n" not in msg and "cannot be read" in msg


def _combine_peak(tmp_path, n_speeds, n_loads) -> int:
    """tracemalloc's peak [bytes] of write_combined_sweep over a finished grid of long cases."""
    folder = tmp_path / f"g{n_speeds}x{n_loads}"
    folder.mkdir()
    path = make_sweep(folder, _grid(n_speeds, n_loads))
    result = run_sweep(path, folder / "s", serial=True, case_fn=long_case, progress=False, combine_at_end=False)
    assert result.ok and len(result.computed) == n_speeds * n_loads
    sweep = read_sweep_file(path)
    write_combined_sweep(sweep, folder / "s")          # imports and caches warmed
    tracemalloc.start()
    try:
        write_combined_sweep(sweep, folder / "s")
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return peak


@pytest.mark.slow  # over 25 s of CPU: make test-all
def test_the_combines_memory_does_not_grow_with_the_cases(tmp_path):
    """8 cases against 32 of about 0.5 MB of series each: the combine's peak allocation
    (tracemalloc) stays within 1.3x; holding every case, as the combine once did, the
    32-case peak would be about 4x the 8-case one."""
    small = _combine_peak(tmp_path, 2, 4)
    large = _combine_peak(tmp_path, 4, 8)
    per_case = 4000 * 8 * 15            # samples x bytes x the synthetic series, one case
    assert small > per_case             # a case's data passes through memory
    assert large < 1.3 * small, (small, large)


# --------------------------------------------------------------------------- status


def _count_status_writes(monkeypatch):
    whole, lines = [], []
    real_write, real_append = pipeline.io.status.write_text_atomic, StatusLog.append

    def counted_write(path, text):
        if Path(path).name == "status.json":
            whole.append(path)
        return real_write(path, text)

    def counted_append(self, state):
        lines.append(state.case_id)
        return real_append(self, state)

    monkeypatch.setattr(pipeline.io.status, "write_text_atomic", counted_write)
    monkeypatch.setattr(StatusLog, "append", counted_append)
    return whole, lines


@pytest.mark.parametrize("n_speeds,n_loads", [(2, 2), (3, 4)])
def test_status_is_appended_once_per_case_and_written_whole_twice(tmp_path, monkeypatch, n_speeds, n_loads):
    """4 and 12 cases: one appended line per computed case, status.json written whole
    twice (start and end), whatever the number of cases; afterwards status.json records
    every case with the SHA-256 of its file, and the log is gone (folded in)."""
    import hashlib

    whole, lines = _count_status_writes(monkeypatch)
    path = make_sweep(tmp_path, _grid(n_speeds, n_loads))
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=synthetic_case, progress=False)
    n = n_speeds * n_loads
    assert result.ok and len(result.computed) == n
    assert sorted(lines) == sorted(result.computed) and len(whole) == 2
    assert not (result.out_dir / STATUS_LOG).exists()
    status = json.loads((result.out_dir / "status.json").read_text())
    for cid in result.computed:
        f = result.out_dir / "cases" / f"{cid}.nc"
        assert status[cid]["state"] == "ok" and status[cid]["sha256"] == hashlib.sha256(f.read_bytes()).hexdigest()


def test_a_sweep_killed_before_its_compaction_resumes_from_the_log(tmp_path, monkeypatch):
    """Killed after every case but before status.json is written again (its cases are
    in status.jsonl only, the last line torn): the rerun computes nothing, opens no
    netCDF file to check them, and a case file changed since is still caught."""
    path = make_sweep(tmp_path, GRID)
    out = tmp_path / "s"
    real = pipeline.run.runner.write_status
    calls = []

    def killed_at_the_end(folder, states):
        calls.append(1)
        if len(calls) == 2:
            raise SystemExit("killed")          # not an exception the runner handles
        return real(folder, states)

    monkeypatch.setattr(pipeline.run.runner, "write_status", killed_at_the_end)
    with pytest.raises(SystemExit):
        run_sweep(path, out, serial=True, case_fn=synthetic_case, progress=False)
    monkeypatch.setattr(pipeline.run.runner, "write_status", real)
    on_disk = json.loads((out / "status.json").read_text())
    assert all(e["state"] == "not_run" for e in on_disk.values())       # the start's whole write
    log = out / STATUS_LOG
    assert len(log.read_text().splitlines()) == 4
    with open(log, "a") as fh:
        fh.write('{"case": "0123456789abcdef", "status": {"sta')         # a torn last line
    ids = [c.case_id for c in read_sweep_file(path).cases]
    assert all(read_status(out)[cid]["state"] == "ok" for cid in ids)

    again = Counting()
    with pytest.MonkeyPatch.context() as patch:   # no counted file outlives the count
        counter = OpenCounter(patch)
        result = run_sweep(path, out, serial=True, case_fn=again, progress=False, combine_at_end=False)
    assert result.ok and again.calls == [] and len(result.reused) == 4
    assert counter.opened == []
    assert not log.exists() and json.loads((out / "status.json").read_text())[ids[0]]["state"] == "ok"

    victim = out / "cases" / f"{ids[1]}.nc"
    data = bytearray(victim.read_bytes())
    data[len(data) // 2] ^= 0xFF
    victim.write_bytes(bytes(data))
    result = run_sweep(path, out, serial=True, case_fn=again, progress=False, combine_at_end=False)
    assert result.computed == [ids[1]]


def test_a_resume_opens_no_netcdf_file(tmp_path, monkeypatch):
    """A finished sweep run again: every case reused on its recorded SHA-256, no netCDF
    file opened (before the combine)."""
    path = make_sweep(tmp_path, _grid(2, 3))
    first = run_sweep(path, tmp_path / "s", serial=True, case_fn=synthetic_case, progress=False)
    assert first.ok
    again = Counting()
    with pytest.MonkeyPatch.context() as patch:
        counter = OpenCounter(patch)
        result = run_sweep(path, tmp_path / "s", serial=True, case_fn=again, progress=False, combine_at_end=False)
    assert len(result.reused) == 6 and again.calls == [] and counter.opened == []


def test_a_resume_of_a_finished_sweep_keeps_its_combined_file_and_opens_no_case(tmp_path):
    """The combine included: a finished sweep run again keeps the ``sweep.nc`` combined from
    these very case files (its key and SHA-256 in ``sweep.nc.json``) and opens no netCDF
    file at all. A ``sweep.nc`` whose bytes changed since is combined again (to the same
    content as the first), and so is one when a case was computed again."""
    path = make_sweep(tmp_path, _grid(2, 3))
    out = tmp_path / "s"
    first = run_sweep(path, out, serial=True, case_fn=synthetic_case, progress=False)
    combined = first.combined
    original = combined.read_bytes()
    with pytest.MonkeyPatch.context() as patch:
        counter = OpenCounter(patch)
        again = run_sweep(path, out, serial=True, case_fn=Counting(), progress=False)
    assert len(again.reused) == 6 and counter.opened == []
    assert again.combined == combined and combined.read_bytes() == original
    # a flipped byte near the end of sweep.nc: combined again, to the first run's data
    damaged = bytearray(original)
    damaged[-100] ^= 0xFF
    combined.write_bytes(bytes(damaged))
    run_sweep(path, out, serial=True, case_fn=Counting(), progress=False)
    (tmp_path / "first.nc").write_bytes(original)
    with xr.open_dataset(combined) as ds, xr.open_dataset(tmp_path / "first.nc") as ref:
        xr.testing.assert_identical(ds.drop_attrs(), ref.drop_attrs())
    # a case computed again (its file removed): combined again (one more line of history)
    def history():
        with netCDF4.Dataset(combined) as nc:
            return nc.history.splitlines()

    before = history()
    next(iter(sorted((combined.parent / "cases").glob("*.nc")))).unlink()
    run_sweep(path, out, serial=True, case_fn=synthetic_case, progress=False)
    assert len(history()) > len(before) and "1 to compute" in history()[len(before)]



def test_a_finished_sweep_run_from_another_folder_keeps_its_combined_file(tmp_path):
    """The same sweep whose files sit elsewhere (another install's, a cluster host's clone)
    run again into the same folder: its cases are the same (their ids hash what the files
    hold, not where they sit), so ``sweep.nc`` is kept and no netCDF file is opened; a
    sweep that differs in more than where its files sit (its description) is combined
    again."""
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    here, there = make_sweep(tmp_path / "a", _grid(2, 2)), make_sweep(tmp_path / "b", _grid(2, 2))
    out = tmp_path / "s"
    combined = run_sweep(here, out, serial=True, case_fn=synthetic_case, progress=False).combined
    original = combined.read_bytes()
    with pytest.MonkeyPatch.context() as patch:
        counter = OpenCounter(patch)
        again = run_sweep(there, out, serial=True, case_fn=Counting(), progress=False)
    assert len(again.reused) == 4 and counter.opened == []
    assert combined.read_bytes() == original
    there.write_text('description = "the same cases, described"\n' + there.read_text())
    run_sweep(there, out, serial=True, case_fn=Counting(), progress=False)
    with netCDF4.Dataset(combined) as nc:
        assert "the same cases, described" in nc.configuration


# --------------------------------------------------------------------------- who writes


def test_workers_write_their_own_case_files(tmp_path, monkeypatch):
    """The process that computes a case writes its file; the parent only records it (its
    labelling and writing are never called)."""
    import pipeline.run.runner as runner

    def not_here(*args, **kwargs):
        raise AssertionError("the parent labelled or wrote a case")

    monkeypatch.setattr(runner, "label_case", not_here)
    monkeypatch.setattr(runner, "write_atomic", not_here)
    path = make_sweep(tmp_path, GRID)
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=synthetic_case, progress=False)
    assert result.ok and len(list((tmp_path / "s" / "cases").glob("*.nc"))) == 4
    assert not list((tmp_path / "s" / "cases").glob(".rvsweep-*"))      # the run's marker removed


def test_a_worker_that_does_not_see_the_folder_returns_the_result(tmp_path):
    """A folder of the same name without this run's marker (another host): the worker
    writes nothing there and sends the result back for the parent to write."""
    from pipeline.run.cases import compute_and_write

    spec = read_sweep_file(make_sweep(tmp_path, GRID)).cases[0]
    elsewhere = tmp_path / "cases"
    elsewhere.mkdir()
    outcome = compute_and_write(spec, synthetic_case, cases_dir=str(elsewhere), marker=".rvsweep-x.here")
    assert outcome.ok and outcome.result is not None and not outcome.written
    assert list(elsewhere.iterdir()) == []
    (elsewhere / ".rvsweep-x.here").touch()
    outcome = compute_and_write(spec, synthetic_case, cases_dir=str(elsewhere), marker=".rvsweep-x.here")
    assert outcome.ok and outcome.result is None and outcome.written
    assert (elsewhere / f"{spec.case_id}.nc").is_file()


def test_the_workers_share_their_starts_through_the_runs_folder(tmp_path, monkeypatch):
    """Where a worker sees the run's marker, the core's cases share their starts through
    the folder beside it (rvcore.simulation.shared_start) while they run, and only then; a
    run makes that folder, removes it at its end, and removes a killed run's first, but not
    a link of that name (nor what it points to)."""
    import pipeline.run.cluster
    import rvcore.simulation.run as driver
    from pipeline.run.cases import compute_and_write
    from rvcore.simulation.shared_start import STARTS

    seen = []

    def core(*args, **kwargs):
        seen.append(STARTS.folder)
        return synthetic_case(*args, **kwargs)

    monkeypatch.setattr(driver, "run_case", core)
    monkeypatch.setattr(pipeline.run.cluster, "warm_up", lambda case_fn: 0.0)   # no kernels for a fake core
    path = make_sweep(tmp_path, GRID)
    cases = tmp_path / "s" / "cases"
    cases.mkdir(parents=True)
    stale = cases / ".rvsweep-0ld.starts"
    stale.mkdir()
    (stale / "k.npz").write_bytes(b"x")
    keep = tmp_path / "keep"
    keep.mkdir()
    (cases / ".rvsweep-1ink.starts").symlink_to(keep)
    assert run_sweep(path, tmp_path / "s", serial=True, progress=False).ok
    assert len(seen) == 4 and len(set(seen)) == 1 and seen[0] is not None
    folder = seen[0]
    assert folder.parent == cases and folder.name.startswith(".rvsweep-") and folder.name.endswith(".starts")
    assert not folder.exists() and not stale.exists() and STARTS.folder is None
    assert keep.is_dir() and (cases / ".rvsweep-1ink.starts").is_symlink()
    # a worker that does not see this run's marker keeps its starts to itself
    spec = read_sweep_file(path).cases[0]
    assert compute_and_write(spec, None, cases_dir=str(cases), marker=".rvsweep-other.here").result is not None
    assert seen[-1] is None


# --------------------------------------------------------------------------- the report


def test_the_report_opens_sweep_nc_lazily(tmp_path):
    """The report's context holds the metrics in memory and leaves every time series of
    sweep.nc on disk (a section reads only the cases it draws)."""
    from pipeline.report.build import load_context

    path = make_sweep(tmp_path, GRID)
    result = run_sweep(path, tmp_path / "s", serial=True, case_fn=synthetic_case, progress=False)
    ctx = load_context(result.out_dir)
    try:
        series = [k for k, v in ctx.sweep.data_vars.items() if "elapsed_time" in v.dims]
        assert "radial_displacement" in series
        assert not any(ctx.sweep[k].variable._in_memory for k in series)
        assert ctx.metrics["radial_displacement_range"].variable._in_memory
        one = ctx.sweep["radial_displacement"].isel(speed=0, radial_load=0).values
        with xr.open_dataset(result.combined) as ds:
            assert np.array_equal(one, ds["radial_displacement"].values[0, 0])
    finally:
        ctx.sweep.close()


# --------------------------------------------------------------------------- the parent's window


def test_a_cluster_sweep_keeps_at_most_its_window_of_cases_submitted():
    """The parent submits a new case as one finishes, never more than ``window`` submitted
    and not yet collected (what it holds for the cases is bounded by the window, not the
    sweep's size); every case is collected once, and they are submitted longest first."""
    import dataclasses

    window = 2
    from pipeline.bench import SMOKE_SWEEP, no_case
    from pipeline.run.cluster import client, estimated_cost, on_cluster

    base = read_sweep_file(SMOKE_SWEEP).cases
    specs = [dataclasses.replace(base[i % len(base)], case_id=f"{i:016x}") for i in range(10)]
    submitted, outstanding = [], []
    with client(workers=1, scheduler=None, scheduler_file=None, n_cases=len(specs), allowed_failures=0) as (c, _):
        real_submit = c.submit

        def counting_submit(fn, spec, *args, **kwargs):
            submitted.append(spec.case_id)
            return real_submit(fn, spec, *args, **kwargs)

        c.submit = counting_submit
        collected = []
        for spec, outcome in on_cluster(c, specs, no_case, 0, window=window):
            collected.append(spec.case_id)
            outstanding.append(len(submitted) - len(collected))
            assert outcome.ok, outcome
    assert sorted(collected) == sorted(s.case_id for s in specs) == sorted(submitted)
    assert max(outstanding) <= window
    costs = {s.case_id: estimated_cost(s) for s in specs}
    assert [costs[i] for i in submitted] == sorted(costs.values(), reverse=True)


def test_the_local_clusters_housekeeping_wakes_seldom():
    """The local cluster's loops (the scheduler's and nannies' in this process, each
    worker's beside its case) check their health, memory and system once a second or less
    often, and the scheduler runs no work stealing: dask's defaults of 20, 100 and 500 ms
    woke this process for 5-6 % of a core while a sweep's cases ran."""
    from pipeline.run.cluster import client

    with client(workers=1, scheduler=None, scheduler_file=None, n_cases=1, allowed_failures=0) as (c, _):
        c.wait_for_workers(1, timeout=60)

        def callback_ms(server):
            return {k: v.callback_time for k, v in server.periodic_callbacks.items()}

        worker = next(iter(c.run(lambda dask_worker: callback_ms(dask_worker)).values()))
        scheduler, extensions = c.run_on_scheduler(
            lambda dask_scheduler: (callback_ms(dask_scheduler), sorted(dask_scheduler.extensions)))
        nannies = [callback_ms(n) for n in c.cluster.workers.values()]
    for loop in [worker, scheduler] + nannies:
        assert loop["tick"] >= 1000 and loop["monitor"] >= 1000, loop
    assert worker["memory_monitor"] >= 1000 and all(n["memory_monitor"] >= 1000 for n in nannies)
    assert "stealing" not in extensions and "stealing" not in scheduler
