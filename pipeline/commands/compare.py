"""``rvsweep compare TRACE.toml``: a measured rig trace beside a simulated case."""
from __future__ import annotations

import json
import math
from pathlib import Path

HELP = "a measured rig trace (CSV, TDMS, HDF5, MAT) beside a simulated case: phase metrics, lag, Sprague-Geers errors"


def add_arguments(parser):
    parser.add_argument("trace", metavar="TRACE.toml", type=Path, help="the trace file (docs/outputs.md)")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--case", metavar="FILE", type=Path, default=None, help="a simulated case file (cases/<id>.nc)")
    which.add_argument("--sweep", metavar="DIR", type=Path, default=None,
                       help="a sweep folder: its case nearest the trace's speed and radial_load")
    parser.add_argument("--out", metavar="DIR", type=Path, default=None,
                        help="where comparison.nc and comparison.json go (default: compare-<trace name>)")


def run(args) -> int:
    from ..analysis.compare import case_of_sweep, compare, comparison_dataset, simulated_case, table
    from ..io import write_atomic
    from ..io.folders import writable_folder
    from ..schema.profilefile import load_profile
    from ..schema.tracefile import load_trace

    trace = load_trace(args.trace)
    phases, cycle = None, math.nan
    if trace.profile is not None:
        profile = load_profile(trace.profile)
        phases = [(s, e) for (_, s, e) in profile.phases]
        cycle = float(profile.duration)
    case_path = args.case
    if args.sweep is not None:
        case_path = case_of_sweep(args.sweep, trace.speed, trace.radial_load, trace.source)
    case = simulated_case(case_path) if case_path is not None else None
    out = args.out or Path(f"compare-{trace.name}")
    writable_folder(out, f"--out {out}")
    kinematic = None
    if trace.bearing is not None:
        from rvcore.recording.spectra import kinematic_frequencies

        from ..schema.bearingfile import load_bearing

        speed = trace.speed
        if not math.isfinite(speed) and case is not None and "speed" in case.coords:
            speed = math.radians(float(case["speed"]))     # the case file's speed is in degree s-1
        if math.isfinite(speed):
            row0 = load_bearing(trace.bearing).rows[0]
            kinematic = kinematic_frequencies(row0.ball_count, row0.ball_diameter, row0.pitch_diameter,
                                              row0.nominal_contact_angle, speed)
    result = compare(trace, case, phases=phases, cycle=cycle, kinematic=kinematic)
    ds = comparison_dataset(trace, result, case_name=str(case_path or ""))
    write_atomic(ds, out / "comparison.nc")
    summary = {"trace": trace.source, "case": str(case_path) if case_path else None, "lag_s": result["lag"],
               "sample_interval_s": result["interval"],
               "variables": {k: (float(v.values) if v.ndim == 0 else [float(x) for x in v.values])
                             for k, v in ds.data_vars.items() if "frequency" not in v.dims},
               "units": {k: v.attrs["units"] for k, v in ds.data_vars.items()}}
    (out / "comparison.json").write_text(json.dumps(summary, indent=1, allow_nan=True) + "\n")
    print(table(result))
    print(f"wrote {out / 'comparison.nc'} and {out / 'comparison.json'}")
    return 0
