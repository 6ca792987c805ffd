"""Run a sweep: cases on dask (or serially), written atomically and resumably, combined.

Layout of a sweep's folder (docs/outputs.md, "What a sweep writes")::

    <out>/cases/<case id>.nc   one file per finished case (atomic: temp name, os.replace)
    <out>/status.json          case id -> its values (SI), ok / failed + reason / not_run
    <out>/status.jsonl         while a sweep runs: one line per case finished since
                               status.json was written whole (folded in at the end)
    <out>/sweep.nc             all cases on the grid (speed, radial_load, [extra axes],
                               elapsed_time | phase), with ``case_status``
    <out>/sweep.nc.json        what sweep.nc was combined from: its SHA-256 and the key of
                               the case records it holds (:func:`combined_is_current`)

How a run goes
--------------
1. The sweep file is expanded and validated (:func:`pipeline.schema.read_sweep_file`);
   any problem stops here, before a case runs.
2. Cases whose file exists are reused (their id hashes everything that determines the
   result, see :mod:`pipeline.schema.sweepfile`) when the file is the one written for
   that case: its SHA-256 is the one ``status.json`` recorded when it was written (or,
   without a record, it names the case in ``configuration_hash`` and every variable
   reads). Any other file is set aside as ``<name>.damaged`` with one line saying why;
   those cases and the rest are computed.
3. Where the cache of rvcore's sources has no kernels, they are compiled in this process
   (``rvcore.simulation.run.warm_up``) so that workers only read the cache.
4. The cases run serially in this process, on a ``distributed.LocalCluster`` (one
   process per core, one thread each), or on an existing cluster. A worker that sees
   the ``cases/`` folder (a local cluster; a cluster on a shared file system) labels
   its case (:func:`pipeline.io.case.case_dataset`), writes its file and returns only
   its SHA-256 (:func:`pipeline.run.cases.compute_and_write`), so this process's cost
   per case is a status line; a worker that does not see it returns its
   :class:`rvcore.simulation.run.CaseResult` (or the reason it failed), and this process
   labels and writes it. The files do not depend on where a case ran, and workers need
   no access to the output folder.
5. As each case finishes its file is written, one line recording it is appended to
   ``status.jsonl`` (``status.json`` is written whole only when the run starts and ends:
   :mod:`pipeline.io.status`), and one progress bar advances. A case that raises is recorded with its reason; a case that kills its
   worker is retried (``allowed_failures`` times on a local cluster) and then recorded.
   Ctrl-C (or a kill) loses no finished case.
6. The case files are combined into ``sweep.nc`` by the one combiner,
   :func:`pipeline.io.combine.combine_cases`, on the sweep file's grid. A run that
   computed nothing keeps a ``sweep.nc`` already combined from the same case records
   (:func:`combined_is_current`): a resume of a finished sweep opens no case file.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import os
import sys
import time
import tomllib
import traceback
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from .. import __version__
from ..errors import UserError
from ..io.folders import sweep_lock, writable_folder
from ..io.combine import CaseFileError, NeedsFullScan, first_file_scan, scan_case_files, write_streamed
from ..io.files import netcdf_atomic, write_text_atomic
from ..io.statics import STATICS_FILE
from ..io import (REFERENCES, CaseEntry, CaseState, GridAxis, WriteError, combine_cases,
                  combined_encoding, file_digest, git_commit, history_line, read_status, remove_stale_temporaries, status_counts,
                  StatusLog, write_atomic, write_status)
from ..schema import MODEL_VERSION, OPERATING_POINT, Sweep, format_quantity, read_sweep_file, si_udunits
from ..schema.caseids import hash_id
from . import cluster
from .cases import (CaseOutcome, compute_case, failure_reason, label_case, run_one_case,
                    source_name, starts_folder)
from .cluster import DEFAULT_ALLOWED_FAILURES
from .corners import store_corner_statics_or_warn

__all__ = ["SweepResult", "describe_point", "run_sweep", "summary", "write_combined_sweep"]


# The combined file's first two dimensions, always present (length 1 when fixed).
LEADING = ("speed", "radial_load")

_OP_LONG_NAMES = {
    "speed": "steady inner-ring speed",
    "radial_load": "steady radial load",
    "axial_load": "steady axial load",
    "moment": "steady tilting moment",
    "load_angle": "direction of the radial load from +x",
}


# --------------------------------------------------------------------------- result


@dataclass
class SweepResult:
    """What :func:`run_sweep` did.

    ``wall_time`` [s] is the time from the first case submitted to the last one
    finished (no validation, warm-up, cluster start or combining); ``total_time`` [s]
    is the whole call. ``workers`` is 1 for a serial run.
    """

    sweep: Sweep
    out_dir: Path
    combined: Path | None
    states: dict
    workers: int
    scheduler: str
    wall_time: float
    total_time: float
    warm_up_time: float = 0.0
    interrupted: bool = False
    history: list = field(default_factory=list)

    @property
    def computed(self) -> list:
        return [cid for cid, st in self.states.items() if st.computed and st.state == "ok"]

    @property
    def reused(self) -> list:
        return [cid for cid, st in self.states.items() if st.state == "ok" and not st.computed]

    @property
    def failed(self) -> dict:
        return {cid: st.reason for cid, st in self.states.items() if st.state == "failed"}

    @property
    def not_run(self) -> list:
        return [cid for cid, st in self.states.items() if st.state == "not_run"]

    @property
    def ok(self) -> bool:
        return not self.failed and not self.not_run


def describe_point(point: dict) -> str:
    """``speed=120 deg/s radial_load=20 kN ...`` for messages."""
    parts = []
    for k, v in point.items():
        if k == "speed":
            parts.append(f"speed={format_quantity(v, 'deg/s', 'angular_speed')}")
        elif k in ("radial_load", "axial_load"):
            parts.append(f"{k}={format_quantity(v, 'kN', 'force')}")
        else:
            parts.append(f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}")
    return " ".join(parts)


def summary(result: SweepResult) -> str:
    """The end-of-run summary: counts, where the files are, one line per failed case."""
    n = len(result.states)
    lines = [
        f"{result.sweep.name}: {n} case{'s' if n != 1 else ''}: {n - len(result.failed) - len(result.not_run)} ok "
        f"({len(result.computed)} computed, {len(result.reused)} reused), {len(result.failed)} failed, "
        f"{len(result.not_run)} not run; {result.scheduler}, {result.wall_time:.1f} s"
        + (f" -> {result.combined}" if result.combined else f" -> {result.out_dir}")
    ]
    for cid, st in result.states.items():
        if st.state == "failed":
            lines.append(f"  failed {cid} ({describe_point(st.point)}): {st.reason}")
    if result.failed:
        lines.append(f"  details: {result.out_dir / 'status.json'}")
    return "\n".join(lines)


def run_sweep(sweep, out_dir=None, *, workers: int | None = None, scheduler: str | None = None,
              scheduler_file=None, serial: bool = False, case_fn=None, progress: bool = True,
              resume: bool = True, allowed_failures: int = DEFAULT_ALLOWED_FAILURES,
              combine_at_end: bool = True) -> SweepResult:
    """Run every case of a sweep that has no file yet, then combine them.

    Parameters
    ----------
    sweep : Sweep or str or Path
        A loaded sweep, or a sweep file (validated first; a ConfigError stops the run
        before any case runs).
    out_dir : str or Path, optional
        The sweep's folder [-]; default ``results/<sweep name>``.
    workers : int, optional
        Processes of the local cluster [-]; default one per core (never more than the
        cases to run). Ignored with ``scheduler``/``scheduler_file``/``serial``.
    scheduler, scheduler_file : str, optional
        Address or scheduler file of an existing dask cluster to run on.
    serial : bool
        Run the cases one after the other in this process, without dask.
    case_fn : callable, optional
        ``case_fn(bearing, profile, op, settings) -> CaseResult`` in place of
        ``rvcore.simulation.run.run_case`` (tests use synthetic results). It must be picklable
        by reference or by value (cloudpickle) to run on a cluster.
    progress : bool
        Show a tqdm progress bar on stderr.
    resume : bool
        Reuse the case files that exist (default); False recomputes every case.
    allowed_failures : int
        Retries of a case whose worker died, on a local cluster [-]. An existing
        cluster uses its scheduler's ``distributed.scheduler.allowed-failures``.
    combine_at_end : bool
        Write ``sweep.nc`` at the end (also after an interrupt).

    Returns
    -------
    SweepResult

    Raises
    ------
    KeyboardInterrupt
        After saving the status and combining what finished.

    Notes
    -----
    The parallel efficiency of a sweep on ``n`` workers is
    ``E = T_serial / (n · T_n)`` with ``T`` the ``wall_time`` of a run with
    ``serial=True`` and of one with ``workers=n`` (each with ``resume=False``).
    """
    t_start = time.perf_counter()
    if not isinstance(sweep, Sweep):
        sweep = read_sweep_file(sweep)
    out = Path(out_dir) if out_dir is not None else Path("results") / sweep.name
    writable_folder(out / "cases", str(out))
    with sweep_lock(out, str(out)):
        return _run_sweep(sweep, out, t_start, workers=workers, scheduler=scheduler,
                          scheduler_file=scheduler_file, serial=serial, case_fn=case_fn,
                          progress=progress, resume=resume, allowed_failures=allowed_failures,
                          combine_at_end=combine_at_end)


#: The case file's global attribute that names the case it holds (its case id).
ID_ATTRIBUTE = "configuration_hash"


def _set_aside(path: Path, why: str) -> Path:
    """Move a case file that must not be reused to ``<name>.damaged`` (``.damaged2``, ...),
    not deleted (it may be worth a look), and say so in one line on stderr."""
    aside = path.with_name(path.name + ".damaged")
    k = 1
    while aside.exists():
        k += 1
        aside = path.with_name(f"{path.name}.damaged{k}")
    os.replace(path, aside)
    print(f"warning: {path}: {why}; moved to {aside.name}, the case will be computed again",
          file=sys.stderr)
    return aside


def _first_line(exc: BaseException) -> str:
    return str(exc).splitlines()[0] if str(exc) else exc.__class__.__name__


def _held_case(path: Path) -> str | None:
    """The case id a case file says it holds (its ``configuration_hash``), or None."""
    import netCDF4

    with netCDF4.Dataset(path, "r") as nc:
        return str(nc.getncattr(ID_ATTRIBUTE)) if ID_ATTRIBUTE in nc.ncattrs() else None


def _read_fully(path: Path) -> None:
    """Open a case file and read every variable (each chunk is inflated and checked)."""
    import netCDF4

    with netCDF4.Dataset(path, "r") as nc:
        nc.set_auto_mask(False)
        for var in nc.variables.values():
            var[...]


def _reusable(path: Path, case_id: str, recorded: str = "") -> str:
    """The SHA-256 of a case file that may be reused for ``case_id``, or '' (computed again).

    A file is reused only when it is the one written for this case:

    - with a digest recorded in ``status.json`` when it was written, its bytes must give
      that digest (one read of the file, no netCDF; flipped bytes or another case's file
      differ);
    - without one (a folder of an older version, files copied in), it must open, say it
      holds ``case_id`` (its ``configuration_hash``) and every variable must read.

    A file that fails is set aside by :func:`_set_aside` with one line saying why.
    """
    if not path.is_file():
        return ""
    from ..io import file_digest

    try:
        digest = file_digest(path)
    except OSError as exc:
        _set_aside(path, f"could not be read ({_first_line(exc)})")
        return ""
    if recorded and digest == recorded:
        return digest
    try:
        held = _held_case(path)
        if held != case_id:
            _set_aside(path, f"holds case {held or '(none named)'} ({ID_ATTRIBUTE}), not {case_id}")
            return ""
        if recorded:   # the right case, but not the bytes that were written
            _set_aside(path, "its bytes differ from those written (SHA-256 recorded in status.json)")
            return ""
        _read_fully(path)
    except Exception as exc:  # netCDF4/HDF5 raise OSError, RuntimeError, ...
        _set_aside(path, f"could not be read ({_first_line(exc)})")
        return ""
    return digest


#: The file that shows a worker it sees this run's ``cases/`` folder: ``.rvsweep-<random>.here``.
_MARKER = ".rvsweep-{}.here"


def _here_marker(cases_dir: Path, stack) -> str:
    """Make this run's marker file in ``cases_dir`` and the folder beside it through which
    its workers share their starts (:func:`pipeline.run.cases.starts_folder`), both removed
    when ``stack`` closes (those of killed runs first), and return the marker's name; ''
    when it cannot be made (the parent then writes every case file)."""
    import shutil
    import uuid

    for old in cases_dir.glob(_MARKER.format("*")):
        with contextlib.suppress(OSError):
            old.unlink()
    for old in cases_dir.glob(starts_folder(_MARKER.format("*"))):
        if old.is_dir() and not old.is_symlink():
            shutil.rmtree(old, ignore_errors=True)
    name = _MARKER.format(uuid.uuid4().hex)
    try:
        (cases_dir / name).touch()
    except OSError:
        return ""
    stack.callback(lambda: (cases_dir / name).unlink(missing_ok=True))
    starts = cases_dir / starts_folder(name)
    with contextlib.suppress(OSError):
        starts.mkdir()
        stack.callback(lambda: shutil.rmtree(starts, ignore_errors=True))
    return name


def _recorded_digests(out: Path) -> dict:
    """case id -> the SHA-256 recorded in ``status.json`` when its file was written."""
    try:
        status = read_status(out)
    except UserError:   # an unreadable status.json: every file is checked in full
        return {}
    return {cid: str(e.get("sha256", "")) for cid, e in status.items() if e.get("state") == "ok"}


def _keep_what_finished(cases_dir: Path, states: dict, *, check: bool) -> None:
    """After a stop, once every writer of this run has ended (this process; the local
    cluster's workers, killed and waited for by :func:`pipeline.run.cluster.client`):
    remove their temporary files, and record as ok each case whose file a worker finished
    before this process took its outcome.

    Such a file was renamed into place whole (fsync'ed first), but no digest was recorded
    for it: it is checked as a resume checks a file without one (:func:`_reusable`: it
    names its case and every variable reads), then recorded with its SHA-256, so that the
    stop's line, ``status.json``, ``sweep.nc`` and the next run agree on what was kept.
    With ``check`` False (``resume=False``: files of an earlier run may still sit under
    the names of cases this run had not reached) nothing is recorded; the next run checks
    those files before it reuses any.
    """
    remove_stale_temporaries(cases_dir)
    if not check:
        return
    for st in states.values():
        if st.state == "not_run":
            digest = _reusable(cases_dir / f"{st.case_id}.nc", st.case_id)
            if digest:
                st.state, st.sha256, st.computed = "ok", digest, True


def _run_sweep(sweep, out, t_start, *, workers, scheduler, scheduler_file, serial, case_fn,
               progress, resume, allowed_failures, combine_at_end) -> SweepResult:
    """:func:`run_sweep` once its folder is checked and locked."""
    cases_dir = out / "cases"
    remove_stale_temporaries(cases_dir)
    remove_stale_temporaries(out)

    states = {}
    todo = []
    recorded = _recorded_digests(out) if resume else {}
    for i, spec in enumerate(sweep.cases):
        st = CaseState(spec.case_id, i, spec.point)
        digest = _reusable(cases_dir / f"{spec.case_id}.nc", spec.case_id,
                           recorded.get(spec.case_id, "")) if resume else ""
        if digest:
            st.state, st.sha256 = "ok", digest
        else:
            todo.append(spec)
        states[spec.case_id] = st
    n_reused = len(sweep.cases) - len(todo)

    history = [history_line(
        f"rvsweep {__version__} sweep {sweep.file}: {len(sweep.cases)} cases, "
        f"{n_reused} reused, {len(todo)} to compute")]
    write_status(out, states)

    warm = cluster.warm_up(case_fn) if todo else 0.0
    source = source_name(case_fn)
    scheduler_text = "serial"
    n_workers = 1
    wall = 0.0
    interrupted = False

    from tqdm.auto import tqdm

    bar = None
    log = StatusLog(out)   # one line per finished case; status.json is written whole at the end
    try:
        with contextlib.ExitStack() as stack:
            stack.callback(log.close)
            write = {"cases_dir": str(cases_dir), "source": source, "sweep_name": sweep.name,
                     "marker": _here_marker(cases_dir, stack)}
            if serial or not todo:
                outcomes = cluster.serial(todo, case_fn, **write)
            else:
                client, scheduler_text = stack.enter_context(cluster.client(
                    workers=workers, scheduler=scheduler, scheduler_file=scheduler_file,
                    n_cases=len(todo), allowed_failures=allowed_failures))
                n_workers = max(1, len(client.scheduler_info().get("workers", {})))
                if case_fn is None:
                    # every worker loads the kernels now (part of starting the cluster),
                    # not inside its first case
                    client.run(cluster.load_kernels_on_worker)
                outcomes = cluster.on_cluster(client, todo, case_fn, allowed_failures, **write)
            # One bar, whatever runs the cases; its rate and ETA count this run's cases.
            bar = tqdm(total=len(sweep.cases), initial=n_reused, desc=sweep.name, unit="case",
                       disable=not progress or not todo, file=sys.stderr, smoothing=0.0,
                       dynamic_ncols=True)
            t0 = time.perf_counter()
            n_failed = 0
            try:
                for spec, outcome in outcomes:
                    st = states[spec.case_id]
                    st.seconds = outcome.seconds
                    st.computed = True
                    if outcome.write_error:   # the worker's full disk, read-only folder: stop, in one line
                        raise WriteError(outcome.write_error)
                    if outcome.ok and outcome.written:   # the worker wrote the file
                        st.sha256 = outcome.sha256
                        st.state, st.reason, st.traceback = "ok", "", ""
                    elif outcome.ok:   # a worker that does not see the folder: written here
                        try:
                            ds = label_case(spec, outcome.result, source=source, sweep_name=sweep.name)
                            path = write_atomic(ds, cases_dir / f"{spec.case_id}.nc")
                            st.sha256 = file_digest(path)
                            st.state, st.reason, st.traceback = "ok", "", ""
                        except WriteError:   # a full disk, a read-only folder: stop, in one line
                            raise
                        except Exception as exc:  # bad result arrays: this case fails
                            st.state, st.reason = "failed", f"could not write the case file: {failure_reason(exc)}"
                            st.traceback = traceback.format_exc()
                    else:
                        st.state, st.reason, st.traceback = "failed", outcome.reason, outcome.traceback
                    if st.state == "failed":
                        n_failed += 1
                        bar.set_postfix(failed=n_failed, refresh=False)
                    log.append(st)
                    bar.update(1)
            finally:
                wall = time.perf_counter() - t0
                with contextlib.suppress(Exception):
                    outcomes.close()
    except KeyboardInterrupt:
        interrupted = True
        if serial or not (scheduler or scheduler_file):   # this run's writers are gone
            _keep_what_finished(cases_dir, states, check=resume)
    finally:
        if bar is not None:
            bar.close()

    ok = sum(st.state == "ok" for st in states.values())
    failed = sum(st.state == "failed" for st in states.values())
    history.append(history_line(
        f"rvsweep sweep {sweep.name}: {ok} ok, {failed} failed, "
        f"{len(states) - ok - failed} not run{' (interrupted)' if interrupted else ''}; "
        f"{scheduler_text}, {wall:.1f} s"))
    write_status(out, states)
    combined = None
    if combine_at_end and not todo and not interrupted and combined_is_current(sweep, out, states):
        combined = out / "sweep.nc"    # combined from these very case files: kept, none opened
        if not (out / STATICS_FILE).is_file():
            store_corner_statics_or_warn(sweep, out, states)
    elif combine_at_end:
        combined = write_combined_sweep(sweep, out, states=states, history=history)
        store_corner_statics_or_warn(sweep, out, states)   # the report reads the load distribution there
    result = SweepResult(sweep=sweep, out_dir=out, combined=combined, states=states,
                         workers=n_workers, scheduler=scheduler_text, wall_time=wall,
                         total_time=time.perf_counter() - t_start, warm_up_time=warm,
                         interrupted=interrupted, history=history)
    if interrupted:
        raise KeyboardInterrupt(summary(result))
    return result


# --------------------------------------------------------------------------- combining


def _dimension_values(sweep: Sweep):
    """[(dim name, key, sorted SI/bool/str values)] of the combined grid."""
    dims = []
    for key in LEADING:
        axis = sweep.axis(key)
        if axis is not None:
            values = sorted(set(axis.coords))
        else:
            values = sorted({c.point[key] for c in sweep.cases})
        dims.append((key, key, values, axis))
    for axis in sweep.axes:
        if axis.key in LEADING:
            continue
        values = sorted(set(axis.coords), key=lambda c: (isinstance(c, str), c))
        dims.append((axis.name, axis.key, values, axis))
    names = [d[0] for d in dims]
    if len(set(names)) != len(names):
        raise UserError(f"{sweep.file}: two sweep axes map to the same NetCDF name "
                        f"({', '.join(names)}); rename one")
    return dims


def _coordinate(name, key, values, axis) -> xr.DataArray:
    if key == "speed":
        # 12 significant digits: radians(120) back in degrees is 119.99999999999999, and
        # sweep.sel(speed=120) should find it.
        data = np.array([float(f"{x:.12g}") for x in np.degrees(np.asarray(values, dtype=np.float64))])
        return xr.DataArray(data, dims=name, attrs={"units": "degree s-1", "long_name": _OP_LONG_NAMES[key]})
    if key in OPERATING_POINT:
        return xr.DataArray(np.asarray(values, dtype=np.float64), dims=name,
                            attrs={"units": si_udunits(OPERATING_POINT[key]), "long_name": _OP_LONG_NAMES[key]})
    long_name = f"sweep axis {key}"
    if all(isinstance(v, bool) for v in values):
        return xr.DataArray(np.asarray(values, dtype=np.int8), dims=name,
                            attrs={"long_name": long_name, "sweep_key": key,
                                   "flag_values": np.array([0, 1], dtype=np.int8),
                                   "flag_meanings": "false true"})
    if any(isinstance(v, str) for v in values):
        meanings = " ".join(str(v).replace(" ", "_") for v in values)
        return xr.DataArray(np.arange(len(values), dtype=np.int8), dims=name,
                            attrs={"long_name": long_name, "sweep_key": key,
                                   "flag_values": np.arange(len(values), dtype=np.int8),
                                   "flag_meanings": meanings})
    return xr.DataArray(np.asarray(values, dtype=np.float64), dims=name,
                        attrs={"units": axis.units if axis is not None else "1",
                               "long_name": long_name, "sweep_key": key})


def _output_rate(sweep: Sweep) -> float:
    """The sweep's output rate [Hz] (the highest, when it is an axis)."""
    rates = {c.settings.output_rate for c in sweep.cases}
    return max(rates) if rates else sweep.settings.output_rate


def write_combined_sweep(sweep: Sweep, out_dir, *, states: dict | None = None, history=()) -> Path:
    """Combine the case files of a sweep folder into ``sweep.nc`` (atomically).

    Parameters
    ----------
    sweep : Sweep
    out_dir : str or Path
        The sweep's folder [-].
    states : dict, optional
        case id -> :class:`CaseState`; default from ``status.json`` (a case without a
        file that is not recorded as failed is 'not_run').
    history : sequence of str
        Timestamped lines of this run, appended to those of an earlier ``sweep.nc``.

    Notes
    -----
    Dimensions ``(speed, radial_load, <extra axes>, elapsed_time)`` for the time
    series and ``(…, phase)`` for the phase metrics, with the case files' names and
    attributes; a grid point without a finished case is NaN, and ``case_status``
    (int8 flags 0 ok, 1 failed, 2 not_run) says why. When every case has the same
    sample times they are ``elapsed_time``; otherwise the series are interpolated
    linearly onto :func:`pipeline.io.combine.common_time_grid` (noted in their ``comment`` and in
    ``history``). The phase metrics are never resampled: they come from every
    integrator step.
    """
    out = Path(out_dir)
    cases_dir = out / "cases"
    if states is None:   # failures known from an earlier run's status.json
        states = {}
        for cid, entry in read_status(out).items():
            if isinstance(entry, dict):
                states[cid] = CaseState(cid, entry.get("index", -1), {}, state=entry.get("state", "not_run"),
                                        reason=entry.get("reason", ""))
    dims = _dimension_values(sweep)
    axes = [GridAxis(name, values, _coordinate(name, key, values, axis)) for name, key, values, axis in dims]
    entries = []
    for spec in sweep.cases:
        st = states.get(spec.case_id) if states else None
        entry = CaseEntry(tuple(a.index(spec.point[key]) for a, (_, key, _, _) in zip(axes, dims)),
                          state=st.state if st is not None else "not_run")
        p = cases_dir / f"{spec.case_id}.nc"
        if p.is_file():
            entry.path = p
        entries.append(entry)
    paths = [e.path for e in entries if e.path is not None]
    fixed = {key: xr.DataArray(float(value), attrs={"units": si_udunits(OPERATING_POINT[key]),
                                                    "long_name": _OP_LONG_NAMES[key]})
             for key, value in sweep.fixed.items() if key in OPERATING_POINT and key not in LEADING}
    output_rate = _output_rate(sweep)
    case_dims = tuple(a.name for a in axes)
    previous = []
    target = out / "sweep.nc"
    if target.is_file():
        with contextlib.suppress(Exception), xr.open_dataset(target, engine="netcdf4") as old:
            previous = [line for line in str(old.attrs.get("history", "")).splitlines() if line.strip()]
    # The grid (sample times, sensors, rows, spectra, attributes) is first taken from the
    # first case file, and every file opened once: its slab is read and written into its
    # one-case chunk, so memory does not grow with the cases. A file that disagrees with
    # the first (other sample times: the series are resampled) restarts the write after a
    # pass over every file for the grid. A file that does not read stops it; sweep.nc is
    # then untouched.
    try:
        try:
            scan = first_file_scan(paths)
            _write_combined(target, sweep, axes, entries, scan, output_rate, fixed, case_dims, previous, history)
        except NeedsFullScan:
            scan = scan_case_files(paths)
            _write_combined(target, sweep, axes, entries, scan, output_rate, fixed, case_dims, previous, history)
    except CaseFileError as exc:
        raise UserError(f"{exc.path}: cannot be read ({exc.why}); move it away and run "
                        "the sweep again to compute that case again") from None
    write_text_atomic(out / COMBINED_RECORD, json.dumps(
        {"sha256": file_digest(target), "cases": _combine_key(sweep, states)}, indent=1) + "\n")
    return target


#: Beside ``sweep.nc``: ``{"sha256": <sweep.nc's>, "cases": <_combine_key>}`` (docs/outputs.md).
COMBINED_RECORD = "sweep.nc.json"


#: The entries of a sweep's configuration that say where its files sit, not what they hold
#: (the case ids hash what the bearing and profile files hold): left out of the combine's key.
_FILE_PLACES = ("sweep_file", "bearing_file", "profile_file")


def _combine_key(sweep: Sweep, states: dict) -> str:
    """A key of what ``sweep.nc`` is combined from: this package's version, the sweep's
    configuration less where its files sit (:data:`_FILE_PLACES`: the same sweep run from
    another install or folder, a cluster host's, keeps its ``sweep.nc``), and every case's
    id, state and recorded SHA-256, in the sweep's order (SHA-256, hex)."""
    conf = {k: v for k, v in tomllib.loads(sweep.configuration).items() if k not in _FILE_PLACES}
    h = hashlib.sha256(f"{__version__} {hash_id(conf)}".encode())
    for spec in sweep.cases:
        st = states.get(spec.case_id)
        h.update(f"\n{spec.case_id} {getattr(st, 'state', 'not_run')} {getattr(st, 'sha256', '')}".encode())
    return h.hexdigest()


def combined_is_current(sweep: Sweep, out, states: dict) -> bool:
    """Whether ``<out>/sweep.nc`` is the one combined from the case records ``states``
    (case id -> :class:`CaseState`): ``sweep.nc.json`` records its key
    (:func:`_combine_key`) and the file's SHA-256, and the file still has it. A file
    changed since, or combined from other files, is combined again."""
    out = Path(out)
    try:
        record = json.loads((out / COMBINED_RECORD).read_text(encoding="utf-8"))
        return (record.get("cases") == _combine_key(sweep, states)
                and record.get("sha256") == file_digest(out / "sweep.nc"))
    except (OSError, ValueError, AttributeError):
        return False


def _write_combined(target, sweep, axes, entries, scan, output_rate, fixed, case_dims, previous, history):
    """sweep.nc's global attributes for ``scan``, and the file written by
    :func:`pipeline.io.combine.write_streamed` (atomically)."""
    loaded = scan.n_files
    _, resampled = scan.elapsed(output_rate)
    lines = previous + list(history) + [history_line(
        f"pipeline.run.runner.write_combined_sweep: {loaded} of {len(sweep.cases)} case files into sweep.nc"
        + ("; time series linearly interpolated onto a common elapsed_time grid" if resampled else ""))]

    caveats = " | ".join(sweep.bearing.warnings)
    attrs = {
        "Conventions": "CF-1.8",
        "title": f"RV main-bearing dynamics sweep '{sweep.name}': {sweep.bearing.name}, "
                 f"{sweep.profile.name} cycle, {len(sweep.cases)} cases",
        "source": f"rv-bearing-sweep {__version__} (rvcore numba contact dynamics, model version {MODEL_VERSION})",
        "history": "\n".join(lines),
        "references": REFERENCES,
        "configuration": sweep.configuration,
        "configuration_hash": sweep.configuration_hash,
        "git_commit": str(scan.global_attrs.get("git_commit", "")) if loaded else git_commit(),
        "bearing": sweep.bearing.name,
        "profile": sweep.profile.name,
        "caveats": caveats,
        "assumptions": ", ".join(sweep.bearing.assumptions),
        "sweep": sweep.name,
        "sweep_axes": " ".join(case_dims),
        # how the inner ring's tilts were held (docs/model.md §11): every result depends on it
        "inner_ring_tilt": " and ".join(sorted({c.bearing.inner_ring.tilt for c in sweep.cases}))
                           or sweep.bearing.inner_ring.tilt,
    }
    if sweep.description:
        attrs["comment"] = sweep.description
    with netcdf_atomic(target) as tmp:
        write_streamed(tmp, axes, entries, scan, output_rate=output_rate, scalars=fixed, attrs=attrs,
                       encoding_of=combined_encoding)
