"""How the files of a sweep behave: their mode, a damaged case file, a busy folder."""
from __future__ import annotations

import os
import stat

import numpy as np
import pytest
import xarray as xr

from pipeline.io.files import write_atomic, write_text_atomic


@pytest.fixture
def umask():
    """Set the umask for one test and restore it after."""
    old = os.umask(0o022)
    os.umask(old)
    yield lambda mask: os.umask(mask)
    os.umask(old)


@pytest.mark.parametrize("mask", [0o022, 0o027, 0o002])
def test_written_files_take_the_umask_mode(tmp_path, umask, mask):
    umask(mask)
    nc = write_atomic(xr.Dataset({"x": ("n", np.zeros(2))}), tmp_path / "a.nc", encoding={})
    txt = write_text_atomic(tmp_path / "a.json", "{}")
    expected = 0o666 & ~mask
    assert stat.S_IMODE(nc.stat().st_mode) == expected
    assert stat.S_IMODE(txt.stat().st_mode) == expected


# --------------------------------------------------------------------------- --out checked first

import subprocess  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import pipeline.run  # noqa: E402
import pipeline.run.cluster  # noqa: E402
from pipeline.cli import main  # noqa: E402
from pipeline.io.folders import LOCK_FILE, sweep_lock  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SMOKE = str(REPO / "sweeps" / "smoke.toml")
STUDY_BEARING = str(REPO / "sweeps" / "bearings" / "reduced-test.toml")


@pytest.fixture
def no_work(monkeypatch):
    """Fail the test if a case is computed or numba is warmed up."""
    def forbidden(*a, **k):
        raise AssertionError("work started before the output place was checked")
    monkeypatch.setattr(pipeline.run, "run_one_case", forbidden)
    monkeypatch.setattr(pipeline.run.cluster, "warm_up", forbidden)


def _one_line_error(capsys, code, *needles):
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for n in needles:
        assert n in err, err
    return err


def _simulate(out):
    return main(["simulate", "--bearing", STUDY_BEARING, "--speed", "660deg/s",
                 "--radial-load", "30kN", "--axial-load", "10kN", "--out", str(out)])


def _can_write_despite_mode(folder: Path) -> bool:
    """Root writes in a folder whatever its mode: a read-only mode then tests nothing."""
    try:
        (folder / "probe").touch()
    except OSError:
        return False
    (folder / "probe").unlink()
    return True


def test_simulate_out_naming_a_folder_fails_in_one_line_before_the_case(tmp_path, capsys, no_work):
    _one_line_error(capsys, _simulate(tmp_path), "--out", "is a folder")


def test_simulate_out_under_a_file_fails_in_one_line_before_the_case(tmp_path, capsys, no_work):
    (tmp_path / "plain").write_text("x")
    _one_line_error(capsys, _simulate(tmp_path / "plain" / "case.nc"), "--out", "plain")


def test_sweep_out_that_is_a_file_fails_in_one_line_before_any_case(tmp_path, capsys, no_work):
    (tmp_path / "plain").write_text("x")
    code = main(["sweep", SMOKE, "--out", str(tmp_path / "plain"), "--serial", "--no-progress"])
    _one_line_error(capsys, code, "--out", "plain")


def test_read_only_out_fails_in_one_line_before_any_case(tmp_path, capsys, no_work):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        if _can_write_despite_mode(ro):
            pytest.skip("running as root: a read-only mode does not stop writes")
        _one_line_error(capsys, _simulate(ro / "case.nc"), "--out", "Permission denied")
        code = main(["sweep", SMOKE, "--out", str(ro), "--serial", "--no-progress"])
        _one_line_error(capsys, code, "--out", "Permission denied")
    finally:
        ro.chmod(0o755)


def test_read_only_file_system_fails_in_one_line(capsys, no_work):
    """/proc is read-only for everyone, root included."""
    code = main(["sweep", SMOKE, "--out", "/proc/rvsweep-test", "--serial", "--no-progress"])
    _one_line_error(capsys, code, "--out /proc/rvsweep-test")


# --------------------------------------------------------------------------- one sweep per folder

HOLD = """
import sys, time
from pipeline.io.folders import sweep_lock
with sweep_lock(sys.argv[1]):
    print("held", flush=True)
    time.sleep(600)
"""


def test_a_second_sweep_into_a_busy_folder_says_so_and_a_killed_one_leaves_no_lock(tmp_path, capsys, no_work):
    folder = tmp_path / "smoke"
    folder.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", HOLD, str(folder)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        code = main(["sweep", SMOKE, "--out", str(tmp_path), "--serial", "--no-progress"])
        _one_line_error(capsys, code, "in use by another rvsweep sweep", f"pid {holder.pid}")
    finally:
        holder.kill()    # SIGKILL: no cleanup runs in the holder
        holder.wait()
    assert (folder / LOCK_FILE).exists()          # the file stays ...
    with sweep_lock(folder):                      # ... and means nothing once its holder is dead
        pass


# --------------------------------------------------------------------------- a damaged case file

def test_a_truncated_case_file_is_set_aside_and_its_case_recomputed(tmp_path, capsys):
    from pipeline.run import run_sweep
    from tests.pipeline.test_sweep import Counting, case_files, synthetic_case
    from tests.schema.test_sweepfile import GRID, make_sweep

    sweep = make_sweep(tmp_path, GRID)
    out = tmp_path / "out"
    run_sweep(sweep, out, serial=True, case_fn=synthetic_case, progress=False)
    damaged = case_files(out)[1]
    whole = damaged.read_bytes()
    damaged.write_bytes(whole[: len(whole) // 2])
    capsys.readouterr()

    counting = Counting()
    result = run_sweep(sweep, out, serial=True, case_fn=counting, progress=False)
    err = capsys.readouterr().err
    assert result.ok and len(counting.calls) == 1 and result.computed == [damaged.stem]
    warnings = [line for line in err.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1 and damaged.name in warnings[0] and "computed again" in warnings[0]
    aside = damaged.with_name(damaged.name + ".damaged")
    assert aside.read_bytes() == whole[: len(whole) // 2]      # kept as it was, not deleted
    assert damaged.read_bytes() != aside.read_bytes()
    with xr.open_dataset(damaged) as ds:                       # the new file reads
        assert ds.sizes["elapsed_time"] > 0
    with xr.open_dataset(result.combined) as ds:
        assert (ds["case_status"].values == 0).all()


# --------------------------------------------------------------------------- the netCDF writer


def _netcdf_structure(path):
    """Every dimension, global attribute and variable of a netCDF file, in file order: the
    variables' dimensions, type, filters, chunking, attributes and raw values."""
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        out = {"dims": [(k, len(d)) for k, d in nc.dimensions.items()],
               "attrs": [(k, str(nc.getncattr(k))) for k in nc.ncattrs()], "vars": []}
        for k, v in nc.variables.items():
            v.set_auto_maskandscale(False)
            values = v[...]
            out["vars"].append((k, v.dimensions, str(v.dtype), v.filters(), v.chunking(),
                                [(a, str(v.getncattr(a))) for a in v.ncattrs()],
                                values.tolist() if not isinstance(values, np.ndarray) or values.dtype == object
                                else values.tobytes()))
    return out


def test_write_netcdf_gives_the_file_xarray_writes(tmp_path, monkeypatch):
    """:func:`pipeline.io.netcdf.write_netcdf` (xarray declares, h5py writes the numeric
    values) against xarray's own write: the same dimensions, variables in the same order,
    types, filters, chunks, attributes and values, NaN included: float series, an int8
    flag, scalars, a non-index coordinate, a string coordinate, a packed variable and an
    empty one (those two written by xarray). The numeric variables' values are written by
    h5py; with a dask variable xarray writes the whole file."""
    import dask.array as da
    import h5py

    from pipeline.io.netcdf import encoding_for, write_netcdf

    t = np.linspace(0.0, 1.0, 50)
    ds = xr.Dataset(
        {"x": ("time", np.where(t > 0.5, np.nan, np.sin(t)), {"units": "m", "long_name": "x"}),
         "flag": ("time", (t > 0.3).astype(np.int8), {"flag_values": np.array([0, 1], np.int8)}),
         "peak": ((), 3.5, {"units": "N"}),
         "packed": ("time", t * 2.0, {"units": "s"}),
         "own": ("time", t * 3.0, {"units": "s"}),
         "none": ("empty", np.zeros(0))},
        coords={"time": ("time", t, {"units": "s"}), "speed": ((), 2.0, {"units": "rad s-1"}),
                "position": ("sensor", np.array([0.1, 0.2])), "sensor": ("sensor", np.array(["a", "bb"]))},
        attrs={"Conventions": "CF-1.8", "title": "t"})
    enc = encoding_for(ds)
    enc["packed"] = {**enc["packed"], "dtype": "int16", "scale_factor": 0.01, "_FillValue": np.int16(-32768)}
    del enc["own"]   # packed by its own encoding, which xarray takes where none is given
    ds["own"].encoding = {"dtype": "int16", "scale_factor": 0.01, "_FillValue": np.int16(-32768)}
    ds.to_netcdf(tmp_path / "xarray.nc", engine="netcdf4", format="NETCDF4", encoding=enc)
    written = []
    real_open = h5py.h5d.open

    class Spy:
        def __init__(self, fid, name):
            self.id, self.name = real_open(fid, name), name

        def write(self, *args):
            written.append(self.name.decode())
            return self.id.write(*args)

    monkeypatch.setattr(h5py.h5d, "open", lambda fid, name, *a: Spy(fid, name) if not a else real_open(fid, name, *a))
    write_netcdf(ds, tmp_path / "fast.nc", enc)
    assert sorted(written) == ["flag", "peak", "position", "speed", "x"]
    assert _netcdf_structure(tmp_path / "fast.nc") == _netcdf_structure(tmp_path / "xarray.nc")
    written.clear()
    lazy = ds.assign(x=ds["x"].copy(data=da.from_array(ds["x"].values)))
    write_netcdf(lazy, tmp_path / "lazy.nc", enc)
    assert written == []
    assert _netcdf_structure(tmp_path / "lazy.nc") == _netcdf_structure(tmp_path / "xarray.nc")


def test_a_layout_written_before_is_declared_from_its_bytes(tmp_path, monkeypatch):
    """A second file of the same layout (the same dimensions, variables, attributes and
    encodings) with other values and other global attributes: not declared again, copied
    from the first's declaration, and still the file xarray writes of it, global attributes
    (xarray's own ``coordinates`` after the dataset's) in their order. A layout that
    differs (another attribute) is declared."""
    import pipeline.io.netcdf as netcdf

    t = np.linspace(0.0, 1.0, 40)

    def case(k: int, unit: str = "m") -> xr.Dataset:
        return xr.Dataset(
            {"x": ("time", np.sin(k * t), {"units": unit, "long_name": "x"}), "peak": ((), 1.5 * k, {"units": "N"})},
            coords={"time": ("time", t, {"units": "s"}), "position": ("sensor", np.array([0.1, 0.2 * k]))},
            attrs={"Conventions": "CF-1.8", "history": f"case {k}" + " run" * k, "k": k})

    declared = []
    real = netcdf.declare_netcdf
    monkeypatch.setattr(netcdf, "declare_netcdf", lambda *a: declared.append(1) or real(*a))
    monkeypatch.setattr(netcdf, "_DECLARED", {})
    for k, unit, new in ((1, "m", True), (2, "m", False), (3, "m", False), (4, "mm", True)):
        ds = case(k, unit)
        enc = netcdf.encoding_for(ds)
        ds.to_netcdf(tmp_path / f"xarray{k}.nc", engine="netcdf4", format="NETCDF4", encoding=enc)
        n = len(declared)
        netcdf.write_netcdf(ds, tmp_path / f"fast{k}.nc", enc)
        assert len(declared) == n + new, k
        assert _netcdf_structure(tmp_path / f"fast{k}.nc") == _netcdf_structure(tmp_path / f"xarray{k}.nc"), k


def test_the_git_commit_is_asked_of_git_once_a_process(monkeypatch):
    """A case file's ``git_commit`` is the tree's (``git rev-parse HEAD`` here, or '' outside
    a checkout), and a worker's later cases take it without running git again."""
    from pipeline.io import case

    case.git_commit.cache_clear()
    here = Path(case.__file__).resolve().parent
    out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=here, capture_output=True, text=True)
    expected = out.stdout.strip() if out.returncode == 0 else ""
    calls = []
    run = subprocess.run
    monkeypatch.setattr(case.subprocess, "run", lambda *a, **k: calls.append(a) or run(*a, **k))
    try:
        assert case.git_commit() == expected
        assert case.git_commit() == expected
        assert len(calls) == 1
    finally:
        case.git_commit.cache_clear()
