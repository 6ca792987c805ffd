"""Where the cases of a sweep run: serially here, on a local cluster or an existing one.

The numba kernels are compiled in this process before any worker starts where the
cache has none (:func:`warm_up`); workers then only load the cache. On a cluster the cases are
submitted longest first (:func:`estimated_cost`), a bounded window of them at a time
(:func:`in_flight_window`), and yielded as they finish.
"""
from __future__ import annotations

import contextlib
import json
import logging
import os
import re
import time
import traceback
import uuid
from pathlib import Path

from ..errors import UserError
from ..schema import CaseSpec
from .cases import CaseOutcome, compute_and_write, compute_case, failure_reason

#: The only interface a local cluster listens on.
LOCAL_HOST = "127.0.0.1"

#: How often a local cluster retries a case whose worker died, before recording it.
DEFAULT_ALLOWED_FAILURES = 1


def warm_up(case_fn) -> float:
    """Compile the numba kernels here, before any worker starts (real core only), where
    the cache of these sources has none; where it has them, each worker (or the serial
    run's first case) loads them, and this process does not load them for nothing (about
    0.6 s of a sweep's start)."""
    if case_fn is not None:
        return 0.0
    from rvcore.simulation.run import warm_up as compile_kernels

    from .estimate import say_if_compiling

    if not say_if_compiling():   # a minute or more of silence otherwise
        return 0.0
    t0 = time.perf_counter()
    compile_kernels()
    return time.perf_counter() - t0


async def load_kernels_on_worker() -> None:
    """Import the core and load its numba cache in a worker, once, before any case.

    A coroutine, so that ``client.run`` awaits it on the worker's event loop while the
    loading runs in a thread: a host whose cache is cold compiles here for minutes, and
    a function run on the loop itself stops the worker's heartbeats (the scheduler
    removed both workers of a fresh two-worker cluster after 552 s without one,
    2026-11-27). Workers of one host compile once (``rvcore._numba.compile_lock``).
    """
    import asyncio

    from rvcore.simulation.run import warm_up

    await asyncio.get_running_loop().run_in_executor(None, warm_up)


#: Rough speed of each integrator relative to RK4's at the same ``step_safety`` [-]: the
#: IMEX scheme's step is about 7x RK4's on the study case and costs about two of RK4's
#: (``rvsweep bench`` reports the steps and the speed-up). Only the order of the cases
#: depends on it, never a result.
_STEP_LENGTH = {"rk4": 1.0, "imex": 3.6}


def estimated_cost(spec: CaseSpec) -> float:
    """A relative cost of a case, to start the longest ones first [-].

    The integrator's fixed step is inversely proportional to the peak contact load (the
    friction-mode limit, ``rvcore.integrate.rk4.rk4_time_step``), and each step costs in
    proportion to the number of balls, so the cost scales as
    ``balls × simulated time × peak load``, divided by the method's relative step length
    (:data:`_STEP_LENGTH`). The peak load is taken as the larger of the radial and axial
    loads (enough to order cases; it is not used for anything else).
    """
    balls = sum(row.ball_count for row in spec.bearing.rows)
    s = spec.settings
    duration = (s.end_time or spec.profile.duration) - s.start_time
    op = spec.operating_point
    peak = max(abs(op.radial_load), abs(op.axial_load), 1.0)
    if s.time_step > 0:
        return balls * duration / s.time_step
    return balls * duration * peak / (max(s.step_safety, 1e-9) * _STEP_LENGTH.get(s.method, 1.0))


#: A scheduler address: ``[scheme://]host:port`` with host a name, an IPv4 address or a
#: bracketed IPv6 address.
_ADDRESS = re.compile(r"^(?:(tcp|tls|ws|wss|ucx)://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):([0-9]{1,5})$")

#: The largest scheduler file read [bytes] (dask writes a few hundred).
_MAX_SCHEDULER_FILE = 1 << 20


def check_address(address: str, what: str) -> str:
    """``address`` if it is a dask scheduler address (``[tcp|tls|ws|wss|ucx://]host:port``),
    else a one-line :class:`UserError` starting with ``what``."""
    m = _ADDRESS.match(address.strip()) if isinstance(address, str) else None
    if m is None or not 0 < int(m.group(3)) < 65536:
        raise UserError(f"{what}: not a dask scheduler address; expected tcp://HOST:PORT "
                        "(tls://HOST:PORT for TLS), e.g. tcp://10.0.0.5:8786")
    return address.strip()


def scheduler_file_address(path) -> str:
    """The scheduler address in a ``dask scheduler --scheduler-file`` file, checked, or a
    one-line :class:`UserError` naming the file and what is wrong with it."""
    what = f"--scheduler-file {path}"
    p = Path(path)
    if not p.is_file():
        raise UserError(f"{what}: no such file (start `dask scheduler --scheduler-file FILE` first)")
    try:
        if p.stat().st_size > _MAX_SCHEDULER_FILE:
            raise UserError(f"{what}: {p.stat().st_size} bytes, not a scheduler file "
                            f"(dask writes a few hundred)")
        doc = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        why = exc.msg if isinstance(exc, json.JSONDecodeError) else str(exc).splitlines()[0]
        raise UserError(f"{what}: not a scheduler file written by `dask scheduler` "
                        f"(not JSON: {why})") from None
    address = doc.get("address") if isinstance(doc, dict) else None
    if not isinstance(address, str):
        raise UserError(f"{what}: not a scheduler file written by `dask scheduler` "
                        "(no \"address\" in it)")
    return check_address(address, f"{what}: address {address!r}")


def check_scheduler(args) -> None:
    """Check ``--scheduler`` and ``--scheduler-file`` before any work starts (one line each)."""
    if getattr(args, "scheduler", None) is not None:
        check_address(args.scheduler, f"--scheduler {args.scheduler!r}")
    if getattr(args, "scheduler_file", None) is not None:
        scheduler_file_address(args.scheduler_file)


def serial(todo, case_fn, **write):
    """Run the cases here, one after the other; ``write`` as for :func:`on_cluster`."""
    for spec in todo:
        yield spec, compute_and_write(spec, case_fn, **write)


@contextlib.contextmanager
def client(*, workers, scheduler, scheduler_file, n_cases, allowed_failures):
    """A dask Client: on an existing scheduler, or on a new LocalCluster of processes."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler or scheduler_file:
        address = (check_address(scheduler, f"--scheduler {scheduler!r}") if scheduler
                   else scheduler_file_address(scheduler_file))
        try:
            client = Client(address, timeout="20s")
        except Exception as exc:  # OSError, TimeoutError, ValueError from the comm layer
            where = scheduler or f"{address} (from {scheduler_file})"
            raise UserError(f"cannot reach the dask scheduler at {where}: "
                            f"{str(exc).splitlines()[0] if str(exc) else type(exc).__name__}") from None
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
        # Dask's own housekeeping, set for a sweep's long tasks on a cluster of a few
        # processes (its loops run in the sweep's process, the scheduler's and the nannies',
        # and in each worker beside its case): the event loops' health tick (20 ms by
        # default, 50 wake-ups a second in every loop; its warning still comes after 3 s
        # unresponsive), the memory monitors' polls (100 ms; a case's memory grows over
        # seconds, and the nanny still stops a worker past 95 % of its limit), the system
        # monitor's samples for a dashboard nobody reads (500 ms), and work stealing, which
        # has nothing to steal with one task a worker and the rest queued on the scheduler.
        # The sweep's process took 5-6 % of a core while the cases ran, 2.3-3.2 % so
        # (docs/performance.md, "Dask's housekeeping").
        "distributed.admin.tick.interval": "1s",
        "distributed.worker.memory.monitor-interval": "1s",
        "distributed.admin.system-monitor.interval": "5s",
        "distributed.scheduler.work-stealing": False,
        "distributed.deploy.cluster-repr-interval": "10s",
        "distributed.scheduler.active-memory-manager.start": False,
    }
    with dask.config.set(settings):
        # Every listening socket on the loopback interface: the scheduler, the workers and
        # the dashboard (a dask scheduler runs code for whoever reaches it). The workers'
        # own logging stays quiet: a worker's heartbeat that meets the scheduler already
        # closing logs a traceback at ERROR, and a case's failure is the sweep's to report.
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               host=LOCAL_HOST, dashboard_address=f"{LOCAL_HOST}:0",
                               silence_logs=logging.CRITICAL)
        client = Client(cluster)
    stopped = False
    try:
        yield client, f"local cluster of {n} process{'es' if n != 1 else ''}"
    except BaseException:
        stopped = True   # Ctrl-C, SIGTERM, a full disk: the cases at work are abandoned
        raise
    finally:
        if stopped:
            _kill_workers(cluster)
        with contextlib.suppress(Exception):
            client.close(timeout=5 if stopped else None)
        with contextlib.suppress(Exception):
            cluster.close(timeout=5 if stopped else None)


#: How long a stopped sweep waits for its killed workers to be gone [s] (SIGKILL takes
#: milliseconds; a bound, not a delay).
KILL_WAIT = 2.0


def _kill_workers(cluster) -> None:
    """Kill the worker processes of a local cluster at once, and wait until they are gone.

    A closing cluster asks each worker to finish and waits for it (seconds, a case
    long); a stopped sweep abandons those cases anyway, so their processes are killed
    and the close that follows has nothing to wait for. Once they are gone (at most
    :data:`KILL_WAIT`), no case file can appear or change any more: the sweep then counts
    what is on disk and removes its workers' temporary files
    (:func:`pipeline.io.files.remove_stale_temporaries`)."""
    import signal

    from ..io.files import process_alive

    killed = []
    for nanny in list(getattr(cluster, "workers", {}).values()):
        with contextlib.suppress(Exception):
            pid = nanny.process.process.pid
            if pid:
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)
    deadline = time.monotonic() + KILL_WAIT
    while any(process_alive(pid) for pid in killed) and time.monotonic() < deadline:
        time.sleep(0.01)


#: The fewest cases a sweep keeps submitted to the scheduler at a time; with more worker
#: threads, :data:`IN_FLIGHT_PER_THREAD` a thread. What the parent and the scheduler hold
#: for the cases grows with this window, not with the sweep: about 0.03 MB a submitted case
#: (measured on the 10,000-case sweep, docs/performance.md, "Sweeps at scale").
IN_FLIGHT_MIN = 64
#: Cases submitted a worker thread: one running, the rest queued so no thread waits for
#: the parent between cases.
IN_FLIGHT_PER_THREAD = 4


def in_flight_window(client) -> int:
    """How many cases to keep submitted: ``max(IN_FLIGHT_MIN, IN_FLIGHT_PER_THREAD × threads)``,
    the threads of the workers the scheduler knows now (a cluster that grows is read again
    as the cases finish, :func:`on_cluster`)."""
    try:
        threads = sum(client.nthreads().values())
    except Exception:  # a scheduler that does not answer here answers as_completed's wait
        threads = 0
    return max(IN_FLIGHT_MIN, IN_FLIGHT_PER_THREAD * int(threads))


def on_cluster(client, todo, case_fn, allowed_failures, *, window=None, **write):
    """Submit the cases, longest first, at most a window of them at a time; yield (spec,
    outcome) as they finish, in completion order.

    ``window`` is the most cases submitted and not yet yielded (default
    :func:`in_flight_window`, read again every window's worth of finished cases): a new
    case is submitted as one finishes, so the parent's and the scheduler's memory for the
    cases is bounded by the window, whatever the sweep's size. ``write`` (``cases_dir``,
    ``source``, ``sweep_name``) goes to :func:`pipeline.run.cases.compute_and_write`: a
    worker that sees ``cases_dir`` writes its case's file itself."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    token = uuid.uuid4().hex[:8]
    futures = {}
    # longest cases first: with one case per worker at a time, this balances the load
    queue = iter(sorted(todo, key=estimated_cost, reverse=True))
    fixed = window is not None
    size = int(window) if fixed else in_flight_window(client)

    def submit_next():
        spec = next(queue, None)
        if spec is None:
            return None
        fut = client.submit(compute_and_write, spec, case_fn, key=f"rvsweep-{spec.case_id}-{token}",
                            pure=False, **write)
        futures[fut] = spec
        return fut

    first = [f for f in (submit_next() for _ in range(max(1, size))) if f is not None]
    pending = as_completed(first)
    done = 0
    try:
        for fut in pending:
            spec = futures.pop(fut)
            try:
                outcome = fut.result()
            except KilledWorker as exc:
                outcome = CaseOutcome(spec.case_id, False, None,
                                      "its worker process died while running it, also on the "
                                      f"retry (KilledWorker: {exc})".splitlines()[0][:500])
            except Exception as exc:  # a scheduler-side error: record it for this case
                outcome = CaseOutcome(spec.case_id, False, None, failure_reason(exc),
                                      "".join(traceback.format_exception(exc)))
            fut.release()
            done += 1
            if not fixed and done % size == 0:
                size = in_flight_window(client)
            # keep the window full: one in for the one out (more if the cluster grew)
            while len(futures) < size:
                nxt = submit_next()
                if nxt is None:
                    break
                pending.add(nxt)
            yield spec, outcome
    finally:
        if futures:
            with contextlib.suppress(Exception):
                client.cancel(list(futures))
