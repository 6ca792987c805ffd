"""``rvsweep report DIR``: metrics, fits and the report of a finished or partial sweep."""
from __future__ import annotations

import time
from pathlib import Path

HELP = "phase metrics, fits and the Markdown/HTML report of a finished or partial sweep"


def add_arguments(parser):
    parser.add_argument("directory", metavar="DIR", type=Path,
                        help="the sweep's output folder (holds sweep.nc or cases/, status.json)")
    add_report_options(parser)


def add_report_options(parser):
    """The report's options (the reference fits, a dry sweep beside, the headline's
    targets): ``rvsweep report``'s, and ``rvsweep sweep --report``'s."""
    parser.add_argument("--reference", metavar="FILE", type=Path, default=None,
                        help="reference-fit TOML to compare with (default: sweeps/reference/study-fits.toml)")
    parser.add_argument("--dry", metavar="DIR2", type=Path, default=None,
                        help="a dry sweep (friction.law coulomb_step) of the same grid: the report puts this "
                             "lubricated sweep's cage slip, drive torque and transient ranges beside its own")
    from ..report.targets import TARGETS

    for t in TARGETS:
        bound = "at least" if t.worst == "min" else "at most"
        parser.add_argument(t.flag, dest=f"target_{t.key}", metavar="VALUE", default=None,
                            help=f"target of the headline's {t.name}: {bound} this, e.g. {t.example}; the "
                                 "headline marks it pass or fail (default: no target)")


def report_options_given(args) -> list:
    """The report options set on the command line, as typed (``--target-s0``, …)."""
    from ..report.targets import TARGETS

    given = [f"--{name}" for name in ("reference", "dry") if getattr(args, name, None) is not None]
    return given + [t.flag for t in TARGETS if getattr(args, f"target_{t.key}", None) is not None]


def check_report_options(args) -> dict:
    """The headline's targets, parsed, and the ``--dry`` folder checked: a bad one is one
    line before any work, nothing written."""
    from ..errors import UserError
    from ..report.targets import TARGETS, parse_targets

    targets = parse_targets({t.key: getattr(args, f"target_{t.key}", None) for t in TARGETS})
    if args.dry is not None and not args.dry.is_dir():
        raise UserError(f"--dry {args.dry}: no such sweep folder" if not args.dry.exists()
                        else f"--dry {args.dry}: a file, not a sweep folder")
    return targets


def _check_folder(directory: Path) -> None:
    """The sweep folder exists and takes files (metrics.nc, fits.nc and report/ go there),
    or one line saying which and why, before any work."""
    from ..errors import UserError
    from ..io.folders import writable_folder

    if not directory.is_dir():
        raise UserError(f"{directory}: no such sweep folder" if not directory.exists()
                        else f"{directory}: a file, not a sweep folder")
    try:
        writable_folder(directory, str(directory))
    except UserError as exc:
        raise UserError(f"{exc}; the report writes metrics.nc, fits.nc and report/ there "
                        "(copy the folder somewhere writable)") from None


def write_report(directory: Path, args, targets: dict) -> None:
    """Build the report of the sweep folder ``directory`` and say what was written."""
    from ..report import build_report

    start = time.perf_counter()
    files = build_report(directory, reference=args.reference, targets=targets, dry=args.dry)
    elapsed = time.perf_counter() - start
    print(f"wrote {files.metrics}")
    print(f"wrote {files.fits}")
    print(f"wrote {files.markdown} and {files.html.name} with {len(files.figures)} figures ({elapsed:.1f} s)")
    if files.missing:
        print(f"note: {files.missing} case(s) failed or missing; the report lists them")


def run(args) -> int:
    # the targets are checked before any work starts: a bad one is one line, nothing written
    targets = check_report_options(args)
    _check_folder(args.directory)
    write_report(args.directory, args, targets)
    return 0
