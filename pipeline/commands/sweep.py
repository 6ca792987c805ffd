"""rvsweep sweep: run a sweep file's cases (resumable) and combine them into sweep.nc."""
from __future__ import annotations

import contextlib
import logging
import os
import signal
import sys
import threading
import warnings
from pathlib import Path

from ..errors import UserError
from ..io.folders import writable_folder
from ..run.estimate import (CONFIRM_CASES, CONFIRM_SECONDS, duration_text, local_workers,
                            sweep_seconds)
from .common import SHIPPED_HELP, check_out_option, input_file

HELP = "run a sweep file's grid of cases (resumable, on dask) into <out>/<name>/"


def add_arguments(parser):
    parser.add_argument("sweep_file", metavar="SWEEP.toml", nargs="?", default=None,
                        help="the sweep file (default: the shipped study sweep, study.toml); "
                             + SHIPPED_HELP)
    parser.add_argument("--out", metavar="DIR", default="results",
                        help="results go under DIR/<sweep name>/ (default: results)")
    parser.add_argument("--workers", type=int, metavar="N", default=None,
                        help="processes of the local cluster (default: one per core)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on an existing dask cluster, e.g. tcp://10.0.0.5:8786")
    where.add_argument("--scheduler-file", metavar="F",
                       help="run on the existing dask cluster described by this scheduler file")
    where.add_argument("--serial", action="store_true",
                       help="run the cases one after the other in this process (no dask)")
    parser.add_argument("--rerun", action="store_true",
                        help="recompute every case, even those whose file exists")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--yes", action="store_true",
                        help=f"start a sweep of more than {CONFIRM_CASES} cases to compute or of "
                             f"more than {CONFIRM_SECONDS / 3600:.0f} h estimated (refused without it)")
    parser.add_argument("--report", action="store_true",
                        help="then write the sweep's metrics, fits and report in this process, as "
                             "`rvsweep report <out>/<name>` would (also after failed cases; not after a "
                             "stop); the report's options below go with it")
    from .report import add_report_options

    add_report_options(parser.add_argument_group("the report's options (with --report)"))


def sweep_path(arg) -> Path:
    """The sweep file of ``arg``; the shipped default sweep when ``arg`` is None."""
    from ..schema.shipped import DEFAULT_SWEEP, shipped_file

    return shipped_file(DEFAULT_SWEEP) if arg is None else input_file(arg)


def _announce(sweep, out: Path, args) -> None:
    """Say what is about to run (cases, a rough time) and refuse a very large sweep
    without --yes, before anything is computed."""
    todo = [c for c in sweep.cases if args.rerun or not (out / "cases" / f"{c.case_id}.nc").is_file()]
    external = bool(args.scheduler or args.scheduler_file)
    workers = 1 if args.serial else local_workers(args.workers, len(todo))
    line = f"{sweep.name}: {len(sweep.cases)} cases, {len(todo)} to compute"
    if todo:
        if external:
            line += f", about {duration_text(sweep_seconds(todo, 1))} of one core in all (rough)"
        else:
            line += (f", about {duration_text(sweep_seconds(todo, workers))} on {workers} "
                     f"worker{'s' if workers != 1 else ''} (rough estimate)")
    print(line, flush=True)
    seconds = sweep_seconds(todo, 1 if external else workers)
    if (len(todo) > CONFIRM_CASES or seconds > CONFIRM_SECONDS) and not args.yes:
        raise UserError(f"{sweep.file}: {len(todo)} cases to compute, about {duration_text(seconds)}: "
                        f"more than {CONFIRM_CASES} cases or {CONFIRM_SECONDS / 3600:.0f} h starts "
                        "only with --yes")


class _Stop:
    """SIGINT (Ctrl-C) and SIGTERM (a batch system's stop) end a sweep within seconds,
    with one line.

    The first signal raises KeyboardInterrupt in the main thread: the case being written
    is dropped (its temporary file removed), ``status.json`` is saved, the cluster is
    closed and what finished is combined. dask's own logging is silenced from then on,
    so that the closing cluster prints no tracebacks. Should that take more than
    :attr:`GRACE` seconds, or should a second signal come, the process ends at once:
    every finished case file and ``status.json`` are already complete on disk (they are
    written atomically), and the kernel releases the folder lock of an exiting process.
    """

    GRACE = 7.0

    def __init__(self, sweep, out: Path):
        self.sweep, self.out = sweep, out
        self.signum = None
        self.previous = {}
        self._said = threading.Lock()
        self._timer = None

    def __enter__(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                self.previous[sig] = signal.signal(sig, self._handle)
            except ValueError:  # not the main thread: leave the signals alone
                break
        return self

    def __exit__(self, *exc):
        # After a signal the watchdog stays armed until the process has exited: it also
        # bounds the interpreter's own shutdown (dask's exit hooks).
        if self._timer is not None and self.signum is None:
            self._timer.cancel()
        for sig, handler in self.previous.items():
            signal.signal(sig, handler)
        return False

    def _handle(self, signum, frame):
        if self.signum is not None:   # a second signal: stop now
            self.exit_now()
        self.signum = signum
        _silence_dask()
        self._timer = threading.Timer(self.GRACE, self.exit_now)
        self._timer.daemon = True
        self._timer.start()
        raise KeyboardInterrupt

    def line(self) -> str:
        """The one line: which signal, how many cases are kept where, how to resume."""
        name = signal.Signals(self.signum).name if self.signum else "an interrupt"
        done = sum((self.out / "cases" / f"{c.case_id}.nc").is_file() for c in self.sweep.cases)
        n = len(self.sweep.cases)
        return (f"rvsweep sweep: stopped by {name}: {done} of {n} case{'s' if n != 1 else ''} "
                f"finished and kept in {self.out}; run the same command again to compute the rest")

    def say(self) -> bool:
        """Print :meth:`line` on stderr, once per process (False when already said)."""
        if not self._said.acquire(blocking=False):
            return False
        with contextlib.suppress(Exception):
            sys.stderr.write(self.line() + "\n")
            sys.stderr.flush()
        return True

    def exit_now(self):
        """End the process at once with the one line (the watchdog and a second signal)."""
        self.say()
        _end_children()
        os._exit(128 + (self.signum or signal.SIGINT))


def _silence_dask() -> None:
    """No log lines or warnings from dask, tornado or asyncio while a stopped sweep closes
    its cluster (cancelled tasks and closing comms log tracebacks at ERROR)."""
    for name in ("distributed", "dask", "tornado", "asyncio", "bokeh"):
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)
    warnings.simplefilter("ignore")


def _end_children() -> None:
    """Kill this process's own children (the local cluster's nannies and workers), which
    would otherwise wait for their scheduler's timeout."""
    with contextlib.suppress(Exception):
        import psutil

        for child in psutil.Process().children(recursive=True):
            with contextlib.suppress(Exception):
                child.kill()


def run(args) -> int:
    from ..run import run_sweep, summary
    from ..run.cluster import check_scheduler
    from ..schema import read_sweep_file

    if args.workers is not None:
        if args.workers < 1:
            raise UserError(f"--workers {args.workers}: must be at least 1")
        if args.scheduler or args.scheduler_file or args.serial:
            raise UserError("--workers sizes the local cluster; it does not apply with "
                            "--scheduler, --scheduler-file or --serial")
    check_scheduler(args)
    check_out_option(args.out)   # before any work
    from .report import check_report_options, report_options_given, write_report

    given = report_options_given(args)
    if given and not args.report:
        raise UserError(f"{given[0]}: a report option; it needs --report")
    targets = check_report_options(args) if args.report else {}
    sweep = read_sweep_file(sweep_path(args.sweep_file))   # every ConfigError before any case runs
    out = Path(args.out) / sweep.name
    writable_folder(out / "cases", f"--out {args.out}")
    _announce(sweep, out, args)
    with _Stop(sweep, out) as stop:
        try:
            result = run_sweep(sweep, out, workers=args.workers, scheduler=args.scheduler,
                               scheduler_file=args.scheduler_file, serial=args.serial,
                               progress=not args.no_progress, resume=not args.rerun)
        except KeyboardInterrupt:
            stop.say()
            if stop.signum is not None:
                # Everything is saved and the lock released; the interpreter's own
                # shutdown after a stopped cluster takes seconds more (measured 3 s), and
                # a batch system's grace period is short: end here.
                with contextlib.suppress(Exception):
                    sys.stdout.flush()
                os._exit(128 + stop.signum)
            return 130
    print(summary(result), flush=True)
    if args.report:
        write_report(out, args, targets)
    return 0 if result.ok else 1
