"""Where the cases of a sweep run: serially here, on a local cluster or an existing one.

The numba kernels are compiled in this process before any worker starts
(:func:`warm_up`); workers then only load the cache. On a cluster the cases are
submitted longest first (:func:`estimated_cost`) and yielded as they finish.
"""
from __future__ import annotations

import contextlib
import logging
import os
import time
import traceback
import uuid
from pathlib import Path

from ..errors import UserError
from ..schema import CaseSpec
from .cases import CaseOutcome, compute_case, failure_reason

#: How often a local cluster retries a case whose worker died, before recording it.
DEFAULT_ALLOWED_FAILURES = 1


def warm_up(case_fn) -> float:
    """Compile the numba kernels here, before any worker starts (real core only)."""
    if case_fn is not None:
        return 0.0
    from rvcore.simulation.run import warm_up as compile_kernels

    from .estimate import say_if_compiling

    say_if_compiling()   # a minute or more of silence otherwise
    t0 = time.perf_counter()
    compile_kernels()
    return time.perf_counter() - t0


def load_kernels_on_worker() -> None:
    """Import the core and load its numba cache in a worker, once, before any case."""
    from rvcore.simulation.run import warm_up

    warm_up()


#: Rough speed of each integrator relative to RK4's at the same ``step_safety`` [-]: the
#: IMEX scheme's step is about 7x RK4's on the study case and costs about two of RK4's
#: (``rvsweep bench`` reports the steps and the speed-up). Only the order of the cases
#: depends on it, never a result.
_STEP_LENGTH = {"rk4": 1.0, "imex": 3.6}


def estimated_cost(spec: CaseSpec) -> float:
    """A relative cost of a case, to start the longest ones first [-].

    The integrator's fixed step is inversely proportional to the peak contact load (the
    friction-mode limit, ``rvcore.integrate.step_size.rk4_time_step``), and each step costs in
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


def serial(todo, case_fn):
    for spec in todo:
        yield spec, compute_case(spec, case_fn)


@contextlib.contextmanager
def client(*, workers, scheduler, scheduler_file, n_cases, allowed_failures):
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


def on_cluster(client, todo, case_fn, allowed_failures):
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
                outcome = CaseOutcome(spec.case_id, False, None, failure_reason(exc),
                                      "".join(traceback.format_exception(exc)))
            fut.release()
            yield spec, outcome
    finally:
        if futures:
            with contextlib.suppress(Exception):
                client.cancel(list(futures))
