"""rvsweep sweep: run a sweep file's cases (resumable) and combine them into sweep.nc."""
from __future__ import annotations

import signal
import sys
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


def _terminate_as_interrupt(signum, frame):
    raise KeyboardInterrupt


def run(args) -> int:
    from ..run import run_sweep, summary
    from ..schema import read_sweep_file

    if args.workers is not None:
        if args.workers < 1:
            raise UserError(f"--workers {args.workers}: must be at least 1")
        if args.scheduler or args.scheduler_file or args.serial:
            raise UserError("--workers sizes the local cluster; it does not apply with "
                            "--scheduler, --scheduler-file or --serial")
    check_out_option(args.out)   # before any work
    sweep = read_sweep_file(sweep_path(args.sweep_file))   # every ConfigError before any case runs
    out = Path(args.out) / sweep.name
    writable_folder(out / "cases", f"--out {args.out}")
    _announce(sweep, out, args)
    previous = signal.getsignal(signal.SIGTERM)
    try:
        signal.signal(signal.SIGTERM, _terminate_as_interrupt)   # a kill saves like Ctrl-C
    except ValueError:  # not the main thread
        previous = None
    try:
        result = run_sweep(sweep, out, workers=args.workers, scheduler=args.scheduler,
                           scheduler_file=args.scheduler_file, serial=args.serial,
                           progress=not args.no_progress, resume=not args.rerun)
    except KeyboardInterrupt as exc:
        if exc.args:
            print(exc.args[0], file=sys.stderr)
        raise
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    print(summary(result))
    return 0 if result.ok else 1
