"""Trust under faults (issue 39): damaged and swapped case files, a full disk, read-only
folders, bad scheduler addresses, a symlinked lock, the local cluster's interfaces.

Synthetic case functions stand in for the dynamics (as in test_sweep.py); every fault is
made here, by the test, and the facts asserted are those of the fault (which file, which
line, what was recomputed), never numbers taken from the code's output.
"""
from __future__ import annotations

import errno
import hashlib
import json
import os
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pipeline.cli import main
from pipeline.io import read_status
from pipeline.run import run_sweep
from tests.pipeline.test_sweep import Counting, assert_same_case_data, case_files, synthetic_case
from tests.schema.test_sweepfile import GRID, make_sweep

#: Internals that must not reach a user.
LEAKS = ("Traceback", "HDF error\n", "File \"")


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _one_line(err: str) -> str:
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


@pytest.fixture
def finished(tmp_path):
    """A 2 x 2 synthetic sweep run to the end: (sweep file, its folder, the case ids in order)."""
    path = make_sweep(tmp_path, GRID)
    out = tmp_path / "s"     # where ``rvsweep sweep --out tmp_path`` puts sweep "s"
    result = run_sweep(path, out, serial=True, case_fn=synthetic_case, progress=False)
    assert result.ok
    return path, out, [c.case_id for c in result.sweep.cases]


# --------------------------------------------------------------------------- item 2, 3


def test_a_swapped_case_file_is_set_aside_and_recomputed(finished, capsys):
    """Another case's file under this case's name: named in one line, moved aside, computed
    again; the file then holds the values of its own case."""
    path, out, ids = finished
    a, b = out / "cases" / f"{ids[0]}.nc", out / "cases" / f"{ids[3]}.nc"
    original = out.parent / "original.nc"
    original.write_bytes(a.read_bytes())
    a.write_bytes(b.read_bytes())                       # case 3's file under case 0's name
    capsys.readouterr()
    again = Counting()
    result = run_sweep(path, out, serial=True, case_fn=again, progress=False)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("warning:")]
    assert len(lines) == 1 and str(a) in lines[0] and "moved to" in lines[0], err
    assert result.ok and result.computed == [ids[0]] and len(again.calls) == 1
    assert (out / "cases" / f"{ids[0]}.nc.damaged").read_bytes() == b.read_bytes()
    assert_same_case_data(original, a)                  # its own case again (history apart)


def test_a_swapped_file_without_a_recorded_digest_is_caught_by_its_configuration_hash(finished, capsys):
    """With status.json gone, the file's own ``configuration_hash`` is compared to its name."""
    path, out, ids = finished
    (out / "status.json").unlink()
    a, b = out / "cases" / f"{ids[1]}.nc", out / "cases" / f"{ids[2]}.nc"
    a.write_bytes(b.read_bytes())
    capsys.readouterr()
    result = run_sweep(path, out, serial=True, case_fn=synthetic_case, progress=False)
    err = capsys.readouterr().err
    assert f"holds case {ids[2]}" in err and f"not {ids[1]}" in err, err
    assert result.computed == [ids[1]]


def _flip(path: Path, at: float = 0.6) -> None:
    data = bytearray(path.read_bytes())
    k = int(len(data) * at)
    for i in range(k, k + 64):
        data[i] ^= 0xFF
    path.write_bytes(bytes(data))


def test_a_case_file_with_flipped_bytes_is_set_aside_and_recomputed(finished, capsys):
    path, out, ids = finished
    victim = out / "cases" / f"{ids[2]}.nc"
    good = _sha(victim)
    original = out.parent / "original.nc"
    original.write_bytes(victim.read_bytes())
    _flip(victim)
    assert _sha(victim) != good
    capsys.readouterr()
    result = run_sweep(path, out, serial=True, case_fn=synthetic_case, progress=False)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("warning:")]
    assert len(lines) == 1 and str(victim) in lines[0] and "differ" in lines[0], err
    assert result.ok and result.computed == [ids[2]]
    assert_same_case_data(original, victim)
    assert read_status(out)[ids[2]]["sha256"] == _sha(victim)   # the new file's digest recorded


def test_the_digest_in_status_is_that_of_the_file_written(finished):
    _, out, ids = finished
    status = read_status(out)
    for cid in ids:
        assert status[cid]["sha256"] == _sha(out / "cases" / f"{cid}.nc")


def test_without_a_recorded_digest_a_truncated_file_is_set_aside(finished, capsys):
    """No status.json (a folder of an older version): a file that does not read is named
    in one line and computed again; the others get their digest recorded. (Flipped bytes
    inside raw data need the digest: a read cannot see them.)"""
    path, out, ids = finished
    (out / "status.json").unlink()
    victim = out / "cases" / f"{ids[0]}.nc"
    victim.write_bytes(victim.read_bytes()[: victim.stat().st_size * 3 // 5])
    capsys.readouterr()
    result = run_sweep(path, out, serial=True, case_fn=synthetic_case, progress=False)
    err = capsys.readouterr().err
    assert result.ok and result.computed == [ids[0]], err
    assert str(victim) in err and "could not be read" in err, err
    status = read_status(out)
    assert all(status[cid]["sha256"] == _sha(out / "cases" / f"{cid}.nc") for cid in ids)


def test_the_combine_names_a_file_it_cannot_read(finished, capsys):
    """The combiner (also run on its own, e.g. by hand) names a case file it cannot read
    rather than dying with an anonymous HDF error."""
    from pipeline.run.runner import write_combined_sweep
    from pipeline.schema import read_sweep_file

    path, out, ids = finished
    victim = out / "cases" / f"{ids[3]}.nc"
    victim.write_bytes(victim.read_bytes()[:2000])      # truncated: does not open
    from pipeline.errors import UserError
    with pytest.raises(UserError) as err:
        write_combined_sweep(read_sweep_file(path), out)
    msg = str(err.value)
    assert msg.startswith(str(victim)) and "\n" not in msg and "cannot be read" in msg


# --------------------------------------------------------------------------- item 5


def _synthetic_cli(monkeypatch):
    """The command line on synthetic cases: no kernels compiled, no dynamics run."""
    import rvcore.simulation.run

    monkeypatch.setattr(rvcore.simulation.run, "run_case", synthetic_case)
    monkeypatch.setattr("pipeline.run.cluster.warm_up", lambda case_fn: 0.0)


def _enospc(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_a_full_disk_while_writing_cases_stops_in_one_line(tmp_path, monkeypatch, capsys):
    """The second case file hits a full disk: one line naming it, exit != 0, the first
    case kept, and a rerun (disk freed) computes only the rest."""
    import netCDF4

    path = make_sweep(tmp_path, GRID)
    real = netCDF4.Dataset
    calls = []

    class FullAfterOne(real):   # reading still works
        def __init__(self, filename, mode="r", *args, **kwargs):
            if mode != "r":
                calls.append(filename)
                if len(calls) >= 2:
                    _enospc()
            super().__init__(filename, mode, *args, **kwargs)

    monkeypatch.setattr(netCDF4, "Dataset", FullAfterOne)
    _synthetic_cli(monkeypatch)
    code = main(["sweep", str(path), "--out", str(tmp_path), "--serial", "--no-progress"])
    err = _one_line(capsys.readouterr().err)
    assert code != 0 and "No space left on device" in err and ".nc" in err, err
    out = tmp_path / "s"
    assert len(case_files(out)) == 1 and not list((out / "cases").glob(".*.tmp"))
    monkeypatch.setattr(netCDF4, "Dataset", real)
    again = Counting()
    result = run_sweep(path, out, serial=True, case_fn=again, progress=False)
    assert result.ok and len(again.calls) == 3 and len(result.reused) == 1


def test_a_full_disk_in_the_combine_stops_in_one_line(finished, monkeypatch, capsys):
    """Every case done, ``sweep.nc`` cannot be written: one line naming sweep.nc."""
    path, out, _ = finished
    (out / "sweep.nc").unlink()
    import netCDF4

    real = netCDF4.Dataset

    class NoSpaceToCreate(real):   # reading still works
        def __init__(self, filename, mode="r", *args, **kwargs):
            if mode != "r":
                _enospc()
            super().__init__(filename, mode, *args, **kwargs)

    # every netCDF writer (xarray's or the streaming combine's) creates its file here
    monkeypatch.setattr(netCDF4, "Dataset", NoSpaceToCreate)
    _synthetic_cli(monkeypatch)
    code = main(["sweep", str(path), "--out", str(out.parent), "--serial", "--no-progress"])
    err = _one_line(capsys.readouterr().err)
    assert code != 0 and "sweep.nc: cannot write (No space left on device)" in err, err
    assert not (out / "sweep.nc").exists() and not list(out.glob(".*.tmp"))


def test_a_full_disk_writing_status_stops_in_one_line(tmp_path, monkeypatch, capsys):
    path = make_sweep(tmp_path, GRID)
    monkeypatch.setattr("pipeline.io.files.os.fsync", _enospc)
    _synthetic_cli(monkeypatch)
    code = main(["sweep", str(path), "--out", str(tmp_path), "--serial", "--no-progress"])
    err = _one_line(capsys.readouterr().err)
    assert code != 0 and "status.json: cannot write (No space left on device)" in err, err


def test_report_on_a_read_only_folder_says_so_in_one_line(finished, monkeypatch, capsys):
    """Root ignores modes, so the read-only file system is simulated at the one place every
    write starts: creating a file in the folder answers EROFS."""
    import tempfile

    _, out, _ = finished

    def read_only(*args, **kwargs):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(tempfile, "NamedTemporaryFile", read_only)
    monkeypatch.setattr(tempfile, "mkstemp", read_only)
    before = sorted(p.name for p in out.iterdir())
    code = main(["report", str(out)])
    err = _one_line(capsys.readouterr().err)
    assert code != 0 and str(out) in err and "Read-only file system" in err, err
    assert sorted(p.name for p in out.iterdir()) == before      # nothing written


@pytest.mark.parametrize("flag, value, expect", [
    ("--scheduler", "notaurl", "--scheduler 'notaurl': not a dask scheduler address"),
    ("--scheduler", "tcp://", "--scheduler 'tcp://': not a dask scheduler address"),
    ("--scheduler", "tcp://10.0.0.5:99999", "not a dask scheduler address"),
])
def test_a_bad_scheduler_address_is_refused_in_one_line(grid_sweep_path, tmp_path, capsys, flag, value, expect):
    code = main(["sweep", str(grid_sweep_path), "--out", str(tmp_path / "o"), flag, value, "--no-progress"])
    err = _one_line(capsys.readouterr().err)
    assert code != 0 and expect in err, err
    assert not (tmp_path / "o").exists()                # refused before any work


@pytest.mark.parametrize("content, expect", [
    (b"\x00\xff garbage \x13", "not JSON"),
    (b"{\"type\": \"Scheduler\"}", "no \"address\""),
    (b"[1, 2]", "no \"address\""),
    (json.dumps({"address": "notaurl"}).encode(), "address 'notaurl': not a dask scheduler address"),
])
def test_a_garbage_scheduler_file_is_refused_in_one_line(grid_sweep_path, tmp_path, capsys, content, expect):
    f = tmp_path / "scheduler.json"
    f.write_bytes(content)
    code = main(["sweep", str(grid_sweep_path), "--out", str(tmp_path / "o"), "--scheduler-file", str(f),
                 "--no-progress"])
    err = _one_line(capsys.readouterr().err)
    assert code != 0 and f"--scheduler-file {f}" in err and expect in err, err
    assert not (tmp_path / "o").exists()


@pytest.fixture
def grid_sweep_path(tmp_path):
    return make_sweep(tmp_path, GRID)


# --------------------------------------------------------------------------- item 10, 11


def test_a_symlinked_lock_is_refused_and_its_target_untouched(tmp_path, capsys):
    path = make_sweep(tmp_path, GRID)
    out = tmp_path / "s"
    (out / "cases").mkdir(parents=True)
    target = tmp_path / "precious.txt"
    target.write_text("do not truncate me\n")
    stamp = target.stat().st_mtime_ns
    (out / ".rvsweep.lock").symlink_to(target)
    code = main(["sweep", str(path), "--out", str(tmp_path), "--serial", "--no-progress"])
    err = _one_line(capsys.readouterr().err)
    assert code != 0 and ".rvsweep.lock is a symbolic link" in err, err
    assert target.read_text() == "do not truncate me\n" and target.stat().st_mtime_ns == stamp
    assert (out / ".rvsweep.lock").is_symlink() and not case_files(out)


def test_a_dangling_symlinked_lock_creates_nothing(tmp_path):
    from pipeline.errors import UserError
    from pipeline.io.folders import sweep_lock

    (tmp_path / ".rvsweep.lock").symlink_to(tmp_path / "elsewhere")
    with pytest.raises(UserError, match="symbolic link"):
        with sweep_lock(tmp_path):
            pass
    assert not (tmp_path / "elsewhere").exists()


def test_a_hard_linked_lock_is_refused_and_its_target_untouched(tmp_path):
    from pipeline.errors import UserError
    from pipeline.io.folders import sweep_lock

    target = tmp_path / "precious.txt"
    target.write_text("keep\n")
    os.link(target, tmp_path / ".rvsweep.lock")
    with pytest.raises(UserError, match="hard link"):
        with sweep_lock(tmp_path):
            pass
    assert target.read_text() == "keep\n"


def test_the_local_cluster_listens_on_the_loopback_interface_only():
    """Every socket the local cluster listens on (scheduler, dashboard, workers) is bound
    to 127.0.0.1: read from the kernel's socket table of this process and its children."""
    import ipaddress

    import psutil

    from pipeline.run import cluster

    with cluster.client(workers=1, scheduler=None, scheduler_file=None, n_cases=1,
                        allowed_failures=1) as (client, _):
        client.wait_for_workers(1, timeout=60)
        me = psutil.Process()
        listening = []
        for proc in [me] + me.children(recursive=True):
            try:
                conns = proc.net_connections(kind="inet")
            except psutil.Error:
                continue
            listening += [c.laddr for c in conns if c.status == psutil.CONN_LISTEN]
    assert len(listening) >= 3, listening        # scheduler, its HTTP server (dashboard), a worker
    for addr in listening:
        assert ipaddress.ip_address(addr.ip).is_loopback, listening


# --------------------------------------------------------------------------- item 1

#: Three short real cases of the reduced bearing (0.03-0.06 s of the short cycle).
SIGNAL_SWEEP = """
[axes]
speed = ["120 deg/s", "390 deg/s", "660 deg/s"]
radial_load = ["30 kN"]

[fixed]
axial_load = "10 kN"

[solver]
output_rate = "1000 Hz"
start_time = "0.03 s"
end_time = "0.06 s"
"""


def _lock_is_free(folder: Path) -> bool:
    import fcntl

    fd = os.open(folder / ".rvsweep.lock", os.O_RDWR)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return True
    except OSError:
        return False
    finally:
        os.close(fd)


@pytest.mark.slow
@pytest.mark.parametrize("signame, to_group", [("SIGINT", True), ("SIGTERM", False)])
def test_a_signal_inside_a_case_write_ends_the_sweep_in_seconds(tmp_path, signame, to_group):
    """``rvsweep sweep`` on a 2-process local cluster, whose workers write their own case
    files, stopped while a worker is inside the write of the first case submitted: its
    data are in the temporary file, not yet fsync'ed nor renamed (the write pauses there,
    RVSWEEP_TEST_PAUSE_IN_WRITE), once the other worker has finished the second case (it
    then computes the third). Ctrl-C reaches the whole process group (a terminal's),
    SIGTERM only the sweep (a batch system's kill).

    Within 10 s: exit 128 + signal, one line on stderr, no traceback, the lock free, no
    temporary file. The case being written is not kept. How many are kept is read from
    the disk, not assumed: the other worker may have finished (and be writing) the third
    case before the signal was handled. The line's count is the number of case files; each is one that existed
    before the signal or appeared since, complete (it opens, names its case, every
    variable reads), recorded ok in the status with its SHA-256, and reused unchanged by
    the rerun, which computes only the others."""
    import re
    import signal
    import subprocess
    import sys
    import time

    from pipeline.io.files import PAUSE_ENV, PAUSED_ENV
    from pipeline.schema import read_sweep_file

    sig = getattr(signal, signame)
    path = make_sweep(tmp_path, SIGNAL_SWEEP)
    ids = [c.case_id for c in read_sweep_file(path).cases]
    paused = f"{ids[0]}.nc"           # submitted first, beside the second
    out = tmp_path / "s"
    cases = out / "cases"
    told = tmp_path / "paused.txt"     # the hook writes the temporary file's path there
    env = dict(os.environ, **{PAUSE_ENV: f"{paused}:120", PAUSED_ENV: str(told)})
    env["PYTHONPATH"] = os.pathsep.join([str(Path(__file__).resolve().parents[2])]
                                        + [p for p in [env.get("PYTHONPATH")] if p])
    proc = subprocess.Popen([sys.executable, "-m", "pipeline.cli", "sweep", str(path), "--out", str(tmp_path),
                             "--workers", "2", "--no-progress"], cwd=tmp_path, env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    try:
        deadline = time.monotonic() + 480
        # the paused write holds its data and a case file is finished
        while not (told.is_file() and told.read_text().endswith("\n") and list(cases.glob("*.nc"))):
            assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
            time.sleep(0.05)
        before = {p.name: p.read_bytes() for p in cases.glob("*.nc")}
        t0 = time.monotonic()
        if to_group:
            os.killpg(proc.pid, sig)
        else:
            proc.send_signal(sig)
        stdout, stderr = proc.communicate(timeout=30)
        took = time.monotonic() - t0
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    tmp = Path(told.read_text().strip())
    from pipeline.io.files import host_tag

    named = f".{paused}.@{host_tag()}."        # the writer's host, then its process id
    assert tmp.parent == cases and tmp.name.startswith(named)
    writer = int(tmp.name[len(named):].split(".")[0])
    assert writer != proc.pid          # a worker process was writing it, not the sweep's own
    assert took < 10.0, took
    assert proc.returncode == 128 + sig, (proc.returncode, stderr)
    assert stderr.count("\n") == 1 and "Traceback" not in stderr, stderr
    said = re.search(rf"stopped by {signame}: (\d+) of 3 cases finished and kept in (.+); run the same "
                     "command again", stderr)
    assert said and Path(said.group(2)) == out, stderr
    assert _lock_is_free(out)
    assert not list(cases.glob(".*.tmp")) and not tmp.exists()

    kept = {p.name: p.read_bytes() for p in cases.glob("*.nc")}
    assert paused not in kept                              # the write it stopped is dropped
    assert all(kept.get(name) == data for name, data in before.items())   # nothing finished lost
    assert int(said.group(1)) == len(kept) >= 1
    status = read_status(out)
    assert {cid for cid, e in status.items() if e["state"] == "ok"} == {n[:-3] for n in kept}
    for name, data in kept.items():
        assert status[name[:-3]]["sha256"] == hashlib.sha256(data).hexdigest()
        with xr.open_dataset(cases / name) as ds:
            assert ds.attrs["configuration_hash"] == name[:-3]
            ds.load()                                      # every variable reads
    with xr.open_dataset(out / "sweep.nc") as ds:
        assert int((ds["case_status"].values == 0).sum()) == len(kept)

    again = run_sweep(path, out, serial=True, progress=False)
    assert again.ok and sorted(again.reused) == sorted(n[:-3] for n in kept)
    assert sorted(again.computed) == sorted(set(ids) - {n[:-3] for n in kept})
    assert {p.name: p.read_bytes() for p in cases.glob("*.nc") if p.name in kept} == kept


def test_a_stop_keeps_a_case_file_its_writer_finished_unrecorded_and_removes_dead_writers_temporaries(
        tmp_path, monkeypatch):
    """What a stopped sweep finds when its writers are gone (serial here; on a local cluster
    the killed workers): case 0 recorded, case 1's file renamed into place by its writer
    before the sweep took that outcome, and a dead writer's temporary file of case 2. The
    stop keeps case 1 as a resume would (recorded ok with the SHA-256 of its bytes), removes
    the temporary file, and the rerun computes only cases 2 and 3."""
    import subprocess
    import sys

    from pipeline.run import cluster
    from pipeline.run.cases import compute_and_write

    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()

    def stopped(todo, case_fn, **write):
        yield todo[0], compute_and_write(todo[0], case_fn, **write)
        compute_and_write(todo[1], case_fn, **write)        # its outcome is never taken
        half = Path(write["cases_dir"]) / f".{todo[2].case_id}.nc.{dead.pid}.k1l2m3.tmp"
        half.write_bytes(b"the start of a case file")
        raise KeyboardInterrupt

    path = make_sweep(tmp_path, GRID)
    out = tmp_path / "s"
    with monkeypatch.context() as m:
        m.setattr(cluster, "serial", stopped)
        with pytest.raises(KeyboardInterrupt):
            run_sweep(path, out, serial=True, case_fn=synthetic_case, progress=False)
    ids = [p.stem for p in case_files(out)]
    assert not list((out / "cases").glob(".*.tmp"))
    status = read_status(out)
    assert {cid for cid, e in status.items() if e["state"] == "ok"} == set(ids) and len(ids) == 2
    for cid in ids:
        assert status[cid]["sha256"] == _sha(out / "cases" / f"{cid}.nc")
    with xr.open_dataset(out / "sweep.nc") as ds:
        assert int((ds["case_status"].values == 0).sum()) == 2
    kept = {cid: _sha(out / "cases" / f"{cid}.nc") for cid in ids}
    again = Counting()
    result = run_sweep(path, out, serial=True, case_fn=again, progress=False)
    assert result.ok and sorted(result.reused) == sorted(ids) and len(again.calls) == 2
    assert {cid: _sha(out / "cases" / f"{cid}.nc") for cid in ids} == kept


def test_a_temporary_file_of_another_host_is_left_alone(tmp_path):
    """On a file system that several hosts share (a cluster's workers writing case files
    into one folder), a process id means something only on its own host: a temporary file
    that names another host is kept whatever its process id, while this host's file of a
    process that no longer exists is removed, and so is one in the form without a host
    (written before the host was named)."""
    import subprocess
    import sys

    from pipeline.io.files import temp_path, host_tag, remove_stale_temporaries

    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()                                           # a process id that is gone here
    here, other = host_tag(), host_tag() + "-other"
    mine = tmp_path / f".a.nc.@{here}.{child.pid}.k3j.tmp"
    theirs = tmp_path / f".b.nc.@{other}.{child.pid}.k3j.tmp"
    legacy = tmp_path / f".c.nc.{child.pid}.k3j.tmp"
    for f in (mine, theirs, legacy):
        f.write_bytes(b"half")
    assert sorted(remove_stale_temporaries(tmp_path)) == sorted([mine, legacy])
    assert theirs.exists()
    # and every writer names its host and process in its temporary file
    tmp = temp_path(tmp_path / "d.txt")
    assert tmp.name.startswith(f".d.txt.@{here}.{os.getpid()}.") and tmp.name.endswith(".tmp")


def test_a_writer_that_has_exited_but_is_not_yet_reaped_counts_as_gone(tmp_path):
    """A killed worker is a zombie until its parent joins it: it answers kill(pid, 0) but
    writes nothing more, so its temporary file is stale (Linux: its /proc state is Z)."""
    import subprocess
    import sys
    import time

    from pipeline.io.files import process_alive, remove_stale_temporaries

    if not Path("/proc/self/stat").is_file():
        pytest.skip("no /proc")
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    try:
        state = Path(f"/proc/{child.pid}/stat")
        for _ in range(1000):                       # until it has exited (10 s at most)
            if state.read_text().rsplit(")", 1)[1].split()[0] == "Z":
                break
            time.sleep(0.01)
        os.kill(child.pid, 0)                       # still there, unreaped
        half = tmp_path / f".abc.nc.{child.pid}.x1y2.tmp"
        half.write_bytes(b"half")
        running = tmp_path / f".def.nc.{os.getppid()}.x1y2.tmp"
        running.write_bytes(b"in progress")
        assert not process_alive(child.pid) and process_alive(os.getppid())
        assert remove_stale_temporaries(tmp_path) == [half] and running.exists()
    finally:
        child.wait()


# --------------------------------------------------------------------------- item 4

GRID_3X3 = """
[axes]
speed = ["120 deg/s", "390 deg/s", "660 deg/s"]
radial_load = ["20 kN", "30 kN", "40 kN"]

[fixed]
axial_load = "10 kN"
"""


@pytest.fixture
def killed_3_of_9(tmp_path):
    """A 3 x 3 synthetic sweep killed after 3 cases, before it combined (no sweep.nc)."""
    path = make_sweep(tmp_path, GRID_3X3)
    out = tmp_path / "s"
    with pytest.raises(KeyboardInterrupt):
        run_sweep(path, out, serial=True, case_fn=Counting(interrupt_after=3), progress=False)
    (out / "sweep.nc").unlink()
    assert len(case_files(out)) == 3
    return out


def test_the_case_files_of_a_partial_sweep_combine_on_the_grid_it_asked_for(killed_3_of_9):
    """Without sweep.nc the analysis lays the 3 finished cases on the 3 x 3 grid that
    status.json lists: 3 speeds, 3 loads, 3 ok and 6 not run, the missing ones NaN."""
    from pipeline.analysis import open_results
    from pipeline.io import CASE_STATUS

    finished = [xr.open_dataset(p) for p in case_files(killed_3_of_9)]
    assert len({float(c["speed"]) for c in finished}) < 3    # they alone span less
    for c in finished:
        c.close()
    ds = open_results(killed_3_of_9)
    assert ds.sizes["speed"] == 3 and ds.sizes["radial_load"] == 3
    assert sorted(ds["speed"].values.tolist()) == [120.0, 390.0, 660.0]
    assert sorted(ds["radial_load"].values.tolist()) == [20e3, 30e3, 40e3]
    flags = ds["case_status"].values
    assert (flags == CASE_STATUS.index("ok")).sum() == 3 and (flags == CASE_STATUS.index("not_run")).sum() == 6
    mean = ds["radial_displacement_mean"].values
    assert np.isnan(mean[flags != 0]).all() and not np.isnan(mean[flags == 0]).any()


@pytest.mark.slow
def test_a_partial_sweep_without_sweep_nc_reports_the_grid_it_asked_for(killed_3_of_9, capsys):
    """3 of a 3 x 3 sweep's cases finished, then the run was killed before it combined
    (sweep.nc removed): the report states the 9-case grid and that 3 finished, 6 missing,
    not a grid made of the 3 finished cases."""
    out = killed_3_of_9
    finished_speeds = set()
    for p in case_files(out):
        with xr.open_dataset(p) as ds:
            finished_speeds.add(float(ds["speed"]))
    code = main(["report", str(out)])
    printed = capsys.readouterr().out
    assert code == 0 and "6 case(s) failed or missing" in printed, printed
    md = (out / "report" / "report.md").read_text()
    assert "grid 3 speeds × 3 radial loads = 9 cases" in md, md[:2000]
    assert "9 cases, 3 finished ok, 6 failed or missing" in md
    assert len(finished_speeds) < 3     # the finished cases alone would not span the grid
