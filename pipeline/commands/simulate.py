"""rvsweep simulate: one dynamic case through its duty cycle, written as NetCDF."""
from __future__ import annotations

import sys
import time

from ..errors import UserError
from ..io.folders import writable_file
from .common import add_load_arguments, add_method_argument, check_out_option, one_case_sweep

HELP = "one dynamic case through the duty cycle to a CF NetCDF file"


def add_arguments(parser):
    add_load_arguments(parser, speed=True)
    parser.add_argument("--profile", metavar="FILE", help="duty-cycle TOML (default: the study's cycle)")
    parser.add_argument("--out", required=True, metavar="FILE", help="the NetCDF file to write")
    add_method_argument(parser)


def run(args):
    from rvcore.recording.results import SimulationError
    from ..io import write_atomic
    from ..run import run_one_case
    from ..run.estimate import say_if_compiling

    check_out_option(args.out)   # before any work
    sweep = one_case_sweep(args, profile=args.profile)
    out = writable_file(args.out, f"--out {args.out}")   # before the case, not after it
    spec = sweep.cases[0]
    for w in spec.bearing.warnings:
        print(f"warning: {w}", file=sys.stderr)
    say_if_compiling()
    t0 = time.perf_counter()
    try:
        ds = run_one_case(spec)
    except SimulationError as exc:
        raise UserError(str(exc)) from None
    write_atomic(ds, out)
    wall = time.perf_counter() - t0
    m = ds
    print(f"wrote {out} ({m.sizes['elapsed_time']} samples, {wall:.1f} s wall, case id {spec.case_id})")
    for ph, name in enumerate(("startup", "steady", "deceleration")):
        print(f"  {name:12s} delta_r range {float(m.radial_displacement_range[ph]) * 1e6:9.4f} um  "
              f"mean {float(m.radial_displacement_mean[ph]) * 1e6:9.4f} um   "
              f"delta_a range {float(m.axial_displacement_range[ph]) * 1e6:9.4f} um  "
              f"mean {float(m.axial_displacement_mean[ph]) * 1e6:9.4f} um")
    return 0
