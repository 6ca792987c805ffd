"""Run a sweep: cases on dask (or serially), written atomically and resumably, combined.

Layout of a sweep's folder (pipeline.md, "What a sweep writes")::

    <out>/cases/<case id>.nc   one file per finished case (atomic: temp name, os.replace)
    <out>/status.json          case id -> its values (SI), ok / failed + reason / not_run
    <out>/sweep.nc             all cases on the grid (speed, radial_load, [extra axes],
                               elapsed_time | phase), with ``case_status``

How a run goes
--------------
1. The sweep file is expanded and validated (:func:`pipeline.sweepfile.load_sweep`);
   any problem stops here, before a case runs.
2. Cases whose file exists are reused (their id hashes everything that determines the
   result, see :mod:`pipeline.sweepfile`); the others are computed.
3. The numba kernels are compiled in this process (``rvcore.driver.warm_up``) so that
   workers only read the cache.
4. The cases run serially in this process, on a ``distributed.LocalCluster`` (one
   process per core, one thread each), or on an existing cluster. Workers only
   compute: each returns its :class:`rvcore.driver.CaseResult` (or the reason it
   failed), and this process labels it (:func:`pipeline.case.case_dataset`) and writes
   it, so the files do not depend on where a case ran and workers need no access to
   the output folder.
5. As each case finishes its file and ``status.json`` are written, and one progress
   bar advances. A case that raises is recorded with its reason; a case that kills its
   worker is retried (``allowed_failures`` times on a local cluster) and then recorded.
   Ctrl-C (or a kill) loses no finished case.
6. The case files are combined into ``sweep.nc``.
"""
from __future__ import annotations

import contextlib
import json
import logging
import math
import os
import sys
import time
import traceback
import uuid
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from .. import __version__
from ..io import REFERENCES, VARIABLES, case_dataset, git_commit, phase_coordinate
from ..errors import UserError
from ..io import (CASE_STATUS, UDUNITS, CaseState, case_status_variable, combined_encoding, history_line,
                  read_status, remove_stale_temporaries, write_atomic, write_status)
from ..schema import MODEL_VERSION, OPERATING_POINT, CaseSpec, Sweep, load_sweep
from ..schema import format_quantity

__all__ = [
    "CaseOutcome", "CaseState", "SweepResult", "run_sweep", "compute_case", "label_case",
    "run_one_case", "combine", "read_status", "status_counts", "summary", "MODEL_VERSION",
]

#: How often a local cluster retries a case whose worker died, before recording it.
DEFAULT_ALLOWED_FAILURES = 1

#: Keys of ``CaseResult.info`` that vary from run to run (timings): they go into the
#: ``history`` line of a case file, not into its attributes, so that case files are
#: identical whatever ran them.
TIMING_INFO = ("wall_time",)

# The combined file's first two dimensions, always present (length 1 when fixed).
LEADING = ("speed", "radial_load")

_OP_LONG_NAMES = {
    "speed": "steady inner-ring speed",
    "radial_load": "steady radial load",
    "axial_load": "steady axial load",
    "moment": "steady tilting moment",
    "load_angle": "direction of the radial load from +x",
}


# --------------------------------------------------------------------------- one case


@dataclass
class CaseOutcome:
    """What a worker sends back for one case.

    Parameters
    ----------
    case_id : str
    ok : bool
    result : rvcore.driver.CaseResult or None
        The arrays when ``ok``.
    reason : str
        One line: why it failed.
    traceback : str
        The full traceback of the failure ('' when ok).
    seconds : float
        Wall time of the case on its worker [s].
    """

    case_id: str
    ok: bool
    result: object = None
    reason: str = ""
    traceback: str = ""
    seconds: float = 0.0


def _default_case_fn():
    # Looked up at call time so that the core (or a test's monkeypatch) is current.
    from rvcore import driver

    return driver.run_case


def _reason(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    line = f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__
    return line if len(line) <= 500 else line[:497] + "..."


def compute_case(spec: CaseSpec, case_fn=None) -> CaseOutcome:
    """Run one case; never raises for a failing case (the outcome carries the reason).

    Parameters
    ----------
    spec : pipeline.sweepfile.CaseSpec
        The resolved case (SI).
    case_fn : callable, optional
        ``case_fn(bearing, profile, op, settings, sensors=()) -> CaseResult``; default
        ``rvcore.driver.run_case``.
    """
    t0 = time.perf_counter()
    fn = case_fn if case_fn is not None else _default_case_fn()
    try:
        result = fn(spec.bearing, spec.profile, spec.operating_point, spec.settings, sensors=spec.sensors)
    except Exception as exc:  # the case failed: record why and let the others go on
        return CaseOutcome(spec.case_id, False, None, _reason(exc), traceback.format_exc(),
                           time.perf_counter() - t0)
    return CaseOutcome(spec.case_id, True, result, seconds=time.perf_counter() - t0)


def label_case(spec: CaseSpec, result, *, source: str = "rvcore.driver.run_case",
               sweep_name: str = "") -> xr.Dataset:
    """The case file's dataset: :func:`pipeline.case.case_dataset` with the case's id.

    Timings in ``result.info`` (:data:`TIMING_INFO`) go into the ``history`` line
    rather than into attributes, so that two runs of the same case give the same data
    and attributes; only ``history`` carries when and how long.
    """
    op = spec.operating_point
    info = dict(getattr(result, "info", {}) or {})
    timings = {k: info.pop(k) for k in TIMING_INFO if k in info}
    if timings:
        result = _with_info(result, info)
    spent = "".join(f", {k} {v:.3f} s" for k, v in timings.items() if isinstance(v, (int, float)))
    where = f" in sweep {sweep_name}" if sweep_name else ""
    history = history_line(f"{source}: case {spec.case_id}{where}{spent}")
    return case_dataset(
        result, speed=op.speed, radial_load=op.radial_load, axial_load=op.axial_load,
        configuration=spec.configuration, configuration_hash=spec.case_id,
        bearing_name=spec.bearing.name, profile_name=spec.profile.name,
        caveats=spec.bearing.warnings, assumptions=spec.bearing.assumptions, history=history,
        sensors=spec.sensors, realization=int(spec.settings.seed))


def _with_info(result, info):
    import copy

    new = copy.copy(result)
    new.info = info
    return new


def _source_name(case_fn) -> str:
    if case_fn is None:
        return "rvcore.driver.run_case"
    return f"{getattr(case_fn, '__module__', '?')}.{getattr(case_fn, '__qualname__', repr(case_fn))}"


def run_one_case(spec: CaseSpec, case_fn=None) -> xr.Dataset:
    """Build, run and label one case (in this process); raises if the case fails."""
    fn = case_fn if case_fn is not None else _default_case_fn()
    result = fn(spec.bearing, spec.profile, spec.operating_point, spec.settings, sensors=spec.sensors)
    return label_case(spec, result, source=_source_name(case_fn))


# --------------------------------------------------------------------------- status


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


# --------------------------------------------------------------------------- running


def _warm_up(case_fn) -> float:
    """Compile the numba kernels here, before any worker starts (real core only)."""
    if case_fn is not None:
        return 0.0
    try:
        from rvcore import driver
    except ImportError:
        return 0.0
    warm = getattr(driver, "warm_up", None)
    if not callable(warm):
        return 0.0
    t0 = time.perf_counter()
    warm()
    return time.perf_counter() - t0


def _load_kernels_on_worker() -> None:
    """Import the core and load its numba cache in a worker, once, before any case."""
    from rvcore.driver import warm_up

    warm_up()


def estimated_cost(spec: CaseSpec) -> float:
    """A relative cost of a case, to start the longest ones first [-].

    The integrator's fixed step is inversely proportional to the peak contact load (the
    friction-mode limit, ``rvcore.integrator.stable_time_step``), and each step costs in
    proportion to the number of balls, so the cost scales as
    ``balls × simulated time × peak load``. The peak load is taken as the larger of the
    radial and axial loads (enough to order cases; it is not used for anything else).
    """
    balls = sum(row.ball_count for row in spec.bearing.rows)
    s = spec.settings
    duration = (s.end_time or spec.profile.duration) - s.start_time
    op = spec.operating_point
    peak = max(abs(op.radial_load), abs(op.axial_load), 1.0)
    if s.time_step > 0:
        return balls * duration / s.time_step
    return balls * duration * peak / max(s.step_safety, 1e-9)


def _serial(todo, case_fn):
    for spec in todo:
        yield spec, compute_case(spec, case_fn)


@contextlib.contextmanager
def _client(*, workers, scheduler, scheduler_file, n_cases, allowed_failures):
    """A dask Client: on an existing scheduler, or on a new LocalCluster of processes."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler or scheduler_file:
        if scheduler_file and not Path(scheduler_file).is_file():
            raise UserError(f"--scheduler-file {scheduler_file}: no such file (start "
                            "`dask scheduler --scheduler-file FILE` first)")
        try:
            client = (Client(scheduler, timeout="20s") if scheduler
                      else Client(scheduler_file=str(scheduler_file), timeout="20s"))
        except (OSError, TimeoutError) as exc:
            where = scheduler or f"the address in {scheduler_file}"
            raise UserError(f"cannot reach the dask scheduler at {where}: {exc}") from None
        try:
            try:
                client.wait_for_workers(1, timeout=60)
            except TimeoutError:
                raise UserError(f"the dask scheduler at {client.scheduler.address} has no "
                                "workers (start some with `dask worker`)") from None
            yield client, f"scheduler {client.scheduler.address}"
        finally:
            client.close()
        return

    n = max(1, min(int(workers or os.cpu_count() or 1), n_cases))
    settings = {
        "distributed.scheduler.allowed-failures": int(allowed_failures),
        # One task per worker thread at a time: a worker that dies takes only its own
        # case with it (others are not marked suspicious), and long cases balance.
        "distributed.scheduler.worker-saturation": 1.0,
        # The workers' sampling profiler wakes every 10 ms; on a machine with one core
        # per worker it takes its time from the cases.
        "distributed.worker.profile.enabled": False,
    }
    with dask.config.set(settings):
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=":0", silence_logs=logging.ERROR)
        client = Client(cluster)
    try:
        yield client, f"local cluster of {n} process{'es' if n != 1 else ''}"
    finally:
        with contextlib.suppress(Exception):
            client.close()
        with contextlib.suppress(Exception):
            cluster.close()


def _on_cluster(client, todo, case_fn, allowed_failures):
    """Submit every case; yield (spec, outcome) as they finish, in completion order."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    token = uuid.uuid4().hex[:8]
    futures = {}
    # longest cases first: with one case per worker at a time, this balances the load
    for spec in sorted(todo, key=estimated_cost, reverse=True):
        fut = client.submit(compute_case, spec, case_fn, key=f"rvsweep-{spec.case_id}-{token}",
                            pure=False)
        futures[fut] = spec
    try:
        for fut in as_completed(list(futures)):
            spec = futures.pop(fut)
            try:
                outcome = fut.result()
            except KilledWorker as exc:
                outcome = CaseOutcome(spec.case_id, False, None,
                                      "its worker process died while running it, also on the "
                                      f"retry (KilledWorker: {exc})".splitlines()[0][:500])
            except Exception as exc:  # a scheduler-side error: record it for this case
                outcome = CaseOutcome(spec.case_id, False, None, _reason(exc),
                                      "".join(traceback.format_exception(exc)))
            fut.release()
            yield spec, outcome
    finally:
        if futures:
            with contextlib.suppress(Exception):
                client.cancel(list(futures))


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
        ``rvcore.driver.run_case`` (tests use synthetic results). It must be picklable
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
        sweep = load_sweep(sweep)
    out = Path(out_dir) if out_dir is not None else Path("results") / sweep.name
    cases_dir = out / "cases"
    cases_dir.mkdir(parents=True, exist_ok=True)
    remove_stale_temporaries(cases_dir)
    remove_stale_temporaries(out)

    states = {}
    todo = []
    for i, spec in enumerate(sweep.cases):
        st = CaseState(spec.case_id, i, spec.point)
        if resume and (cases_dir / f"{spec.case_id}.nc").is_file():
            st.state = "ok"
        else:
            todo.append(spec)
        states[spec.case_id] = st
    n_reused = len(sweep.cases) - len(todo)

    history = [history_line(
        f"rvsweep {__version__} sweep {sweep.file}: {len(sweep.cases)} cases, "
        f"{n_reused} reused, {len(todo)} to compute")]
    write_status(out, states)

    warm = _warm_up(case_fn) if todo else 0.0
    source = _source_name(case_fn)
    scheduler_text = "serial"
    n_workers = 1
    wall = 0.0
    interrupted = False

    from tqdm.auto import tqdm

    bar = None
    try:
        with contextlib.ExitStack() as stack:
            if serial or not todo:
                outcomes = _serial(todo, case_fn)
            else:
                client, scheduler_text = stack.enter_context(_client(
                    workers=workers, scheduler=scheduler, scheduler_file=scheduler_file,
                    n_cases=len(todo), allowed_failures=allowed_failures))
                n_workers = max(1, len(client.scheduler_info().get("workers", {})))
                if case_fn is None:
                    # every worker loads the kernels now (part of starting the cluster),
                    # not inside its first case
                    client.run(_load_kernels_on_worker)
                outcomes = _on_cluster(client, todo, case_fn, allowed_failures)
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
                    if outcome.ok:
                        try:
                            ds = label_case(spec, outcome.result, source=source, sweep_name=sweep.name)
                            write_atomic(ds, cases_dir / f"{spec.case_id}.nc")
                            st.state, st.reason, st.traceback = "ok", "", ""
                        except Exception as exc:  # bad result arrays: this case fails
                            st.state, st.reason = "failed", f"could not write the case file: {_reason(exc)}"
                            st.traceback = traceback.format_exc()
                    else:
                        st.state, st.reason, st.traceback = "failed", outcome.reason, outcome.traceback
                    if st.state == "failed":
                        n_failed += 1
                        bar.set_postfix(failed=n_failed, refresh=False)
                    write_status(out, states)
                    bar.update(1)
            finally:
                wall = time.perf_counter() - t0
                with contextlib.suppress(Exception):
                    outcomes.close()
    except KeyboardInterrupt:
        interrupted = True
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
    if combine_at_end:
        combined = combine(sweep, out, states=states, history=history)
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
                            attrs={"units": UDUNITS[OPERATING_POINT[key]], "long_name": _OP_LONG_NAMES[key]})
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


RESAMPLED_COMMENT = ("linearly interpolated from each case's own output samples (cases/<id>.nc) "
                     "onto the common elapsed_time grid; NaN outside a case's simulated window")


def _output_rate(sweep: Sweep) -> float:
    """The sweep's output rate [Hz] (the highest, when it is an axis)."""
    rates = {c.settings.output_rate for c in sweep.cases}
    return max(rates) if rates else sweep.settings.output_rate


def common_time_grid(times, output_rate: float) -> np.ndarray:
    """A shared ``elapsed_time`` grid [s] for cases whose sample times differ.

    Parameters
    ----------
    times : sequence of ndarray
        Each case's sample times [s].
    output_rate : float
        Samples per second [Hz].

    Notes
    -----
    ``t_k = t_0 + k / f`` for ``k = 0 … floor((t_1 − t_0)·f + 1e-9)``, with ``t_0`` the
    earliest first sample and ``t_1`` the latest last one. The integrator writes every
    m-th step of its own step ``Δt``, so a case's samples are ``m·Δt`` apart rather
    than exactly ``1/f``, and ``Δt`` differs between cases.
    """
    t0 = min(float(t[0]) for t in times if len(t))
    t1 = max(float(t[-1]) for t in times if len(t))
    n = int(math.floor((t1 - t0) * output_rate + 1e-9))
    return t0 + np.arange(n + 1, dtype=np.float64) / output_rate


def combine(sweep: Sweep, out_dir, *, states: dict | None = None, history=()) -> Path:
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
    linearly onto :func:`common_time_grid` (noted in their ``comment`` and in
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
    shape = tuple(len(v) for _, _, v, _ in dims)
    index = [{v: i for i, v in enumerate(values)} for _, _, values, _ in dims]

    loaded = {}
    for spec in sweep.cases:
        p = cases_dir / f"{spec.case_id}.nc"
        if p.is_file():
            with xr.open_dataset(p, engine="netcdf4") as ds:
                loaded[spec.case_id] = ds.load()

    times = [ds["elapsed_time"].values for ds in loaded.values()]
    resampled = False
    if times and all(t.shape == times[0].shape and np.array_equal(t, times[0]) for t in times):
        elapsed = times[0]
    elif times:
        elapsed = common_time_grid(times, _output_rate(sweep))
        resampled = True
    else:
        elapsed = np.zeros(0)
    n_t, n_p = len(elapsed), len(phase_coordinate())

    def attrs_of(name):
        for ds in loaded.values():
            if name in ds:
                return dict(ds[name].attrs)
        _, units, long_name = VARIABLES[name]
        return {"units": units, "long_name": long_name}

    # every case of a sweep has the same sensors: the first case file labels them
    sensor_case = next((ds for ds in loaded.values() if "sensor" in ds.dims), None)
    n_s = sensor_case.sizes["sensor"] if sensor_case is not None else 0
    sizes = {"elapsed_time": n_t, "phase": n_p, "sensor": n_s}
    arrays = {k: np.full(shape + tuple(sizes[d] for d in dims), np.nan) for k, (dims, _, _) in VARIABLES.items()
              if all(sizes[d] for d in dims)}
    status = np.full(shape, CASE_STATUS.index("not_run"), dtype=np.int8)
    for spec in sweep.cases:
        at = tuple(index[d][spec.point[key]] for d, (_, key, _, _) in enumerate(dims))
        st = states.get(spec.case_id) if states else None
        ds = loaded.get(spec.case_id)
        if ds is not None:
            status[at] = CASE_STATUS.index("ok")
            t = ds["elapsed_time"].values
            for k, arr in arrays.items():
                if k not in ds:
                    continue
                v = ds[k].transpose(*VARIABLES[k][0]).values
                if resampled and VARIABLES[k][0][0] == "elapsed_time":
                    v = np.stack([np.interp(elapsed, t, col, left=np.nan, right=np.nan)
                                  for col in v.reshape(len(t), -1).T], axis=-1).reshape((n_t,) + v.shape[1:])
                arr[at] = v
        elif st is not None and st.state == "failed":
            status[at] = CASE_STATUS.index("failed")

    case_dims = tuple(d[0] for d in dims)
    coords = {name: _coordinate(name, key, values, axis) for name, key, values, axis in dims}
    coords["phase"] = phase_coordinate()
    if n_t:
        coords["elapsed_time"] = xr.DataArray(
            np.asarray(elapsed, dtype=np.float64), dims="elapsed_time",
            attrs={"units": "s", "long_name": "simulated time since the start of the cycle"})
    for key, value in sweep.fixed.items():
        if key in OPERATING_POINT and key not in LEADING:
            coords[key] = xr.DataArray(float(value), attrs={"units": UDUNITS[OPERATING_POINT[key]],
                                                            "long_name": _OP_LONG_NAMES[key]})
    if sensor_case is not None:
        for name, c in sensor_case.coords.items():
            if c.dims == ("sensor",):
                coords[name] = xr.DataArray(c.values, dims="sensor", attrs=dict(c.attrs))
    data = {}
    for k, arr in arrays.items():
        attrs = attrs_of(k)
        if resampled and VARIABLES[k][0][0] == "elapsed_time":
            attrs["comment"] = RESAMPLED_COMMENT
        data[k] = xr.DataArray(arr, dims=case_dims + VARIABLES[k][0], attrs=attrs)
    data["case_status"] = case_status_variable(status, case_dims)

    previous = []
    target = out / "sweep.nc"
    if target.is_file():
        with contextlib.suppress(Exception), xr.open_dataset(target, engine="netcdf4") as old:
            previous = [line for line in str(old.attrs.get("history", "")).splitlines() if line.strip()]
    lines = previous + list(history) + [history_line(
        f"pipeline.sweep.combine: {len(loaded)} of {len(sweep.cases)} case files into sweep.nc"
        + ("; time series linearly interpolated onto a common elapsed_time grid" if resampled else ""))]

    first = next(iter(loaded.values()), None)
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
        "git_commit": first.attrs.get("git_commit", "") if first is not None else git_commit(),
        "bearing": sweep.bearing.name,
        "profile": sweep.profile.name,
        "caveats": caveats,
        "assumptions": ", ".join(sweep.bearing.assumptions),
        "sweep": sweep.name,
        "sweep_axes": " ".join(case_dims),
    }
    if sweep.description:
        attrs["comment"] = sweep.description
    ds = xr.Dataset(data_vars=data, coords=coords, attrs=attrs)
    write_atomic(ds, target, encoding=combined_encoding(ds, case_dims))
    return target
