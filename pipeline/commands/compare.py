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
                        help="where comparison.nc and comparison.json go (default: compare-<trace name>); "
                             "with --sweep also DIR/measured/<trace name>.nc, which the sweep's report shows")


def run(args) -> int:
    from ..analysis.compare import case_of_sweep, compare, comparison_dataset, simulated_case, table
    from ..io import write_atomic
    from ..io.folders import writable_folder
    from ..schema.profilefile import load_profile
    from ..schema.tracefile import DutyChannel, load_trace

    trace = load_trace(args.trace)
    phases, cycle, duty_profile, op = None, math.nan, None, None
    if trace.profile is not None:
        profile = load_profile(trace.profile)
        phases = [(s, e) for (_, s, e) in profile.phases]
        cycle = float(profile.duration)
    speed, radial_load, axial_load = trace.speed, trace.radial_load, trace.axial_load
    if trace.duty:
        from ..analysis.compare import read_trace
        from ..analysis.duty import profile_from_channels

        raw = read_trace(trace)
        duty_profile, op = profile_from_channels(raw["time"], raw["duty"], tolerance=trace.duty_tolerance,
                                                 name=trace.name, source=trace.source,
                                                 channels={k: d.name for k, d in trace.duty.items()
                                                           if isinstance(d, DutyChannel)})
        phases = [(s, e) for (_, s, e) in duty_profile.phases]
        cycle = float(duty_profile.duration) if args.case is None and args.sweep is None else math.nan
        speed = op.speed if not math.isfinite(speed) else speed
        radial_load = op.radial_load if not math.isfinite(radial_load) else radial_load
        axial_load = op.axial_load if not math.isfinite(axial_load) else axial_load
    case_path = args.case
    if args.sweep is not None:
        case_path = case_of_sweep(args.sweep, speed, radial_load, trace.source)
        writable_folder(args.sweep / "measured", f"--sweep {args.sweep}")
    case = simulated_case(case_path) if case_path is not None else None
    out = args.out or Path(f"compare-{trace.name}")
    writable_folder(out, f"--out {out}")
    point = {"speed": speed, "radial_load": radial_load, "axial_load": axial_load}
    for key in point:
        if not math.isfinite(point[key]) and case is not None and key in case.coords:
            v = float(case[key])
            point[key] = math.radians(v) if key == "speed" else v   # the case file's speed is in degree s-1
    speed = point["speed"]
    kinematic = None
    if trace.bearing is not None and math.isfinite(speed):
        from rvcore.recording.spectra import kinematic_frequencies

        from ..schema.bearingfile import load_bearing

        row0 = load_bearing(trace.bearing).rows[0]
        kinematic = kinematic_frequencies(row0.ball_count, row0.ball_diameter, row0.pitch_diameter,
                                          row0.nominal_contact_angle, speed)
    result = compare(trace, case, phases=phases, cycle=cycle, kinematic=kinematic)
    ds = comparison_dataset(trace, result, case_name=str(case_path or ""),
                            operating_point=point)
    write_atomic(ds, out / "comparison.nc")
    written = [out / "comparison.nc", out / "comparison.json"]
    if args.sweep is not None:
        stored = args.sweep / "measured" / f"{measured_stem(trace.name)}.nc"
        write_atomic(ds, stored)
        written.append(stored)
    summary = {"trace": trace.source, "case": str(case_path) if case_path else None, "lag_s": result["lag"],
               "sample_interval_s": result["interval"],
               "variables": {k: (float(v.values) if v.ndim == 0 else [float(x) for x in v.values])
                             for k, v in ds.data_vars.items() if not {"frequency", "elapsed_time"} & set(v.dims)},
               "units": {k: v.attrs["units"] for k, v in ds.data_vars.items()}}
    (out / "comparison.json").write_text(json.dumps(summary, indent=1, allow_nan=True) + "\n")
    if duty_profile is not None:
        from ..analysis.duty import operating_point_text, profile_toml

        header = (f"The duty cycle recorded with the trace {trace.source} (channels "
                  + ", ".join(f"{k} {d.name!r} in {d.unit}" if isinstance(d, DutyChannel) else f"{k} held at {d.text}"
                              for k, d in trace.duty.items())
                  + f"), at the steady operating point {operating_point_text(op)}.\n"
                  f"Written by rvsweep compare; run it with: rvsweep simulate --profile {out / 'profile.toml'} "
                  f"{operating_point_text(op)} --bearing ...")
        (out / "profile.toml").write_text(profile_toml(duty_profile, header))
        written.append(out / "profile.toml")
        print(f"duty cycle from the data's channels: {operating_point_text(op)}; phases "
              + ", ".join(f"{n} {a:.6g}-{b:.6g} s" for n, a, b in duty_profile.phases))
    print(table(result))
    print("wrote " + ", ".join(map(str, written)))
    return 0


def measured_stem(name: str) -> str:
    """A trace's name as a file name (``measured/<stem>.nc``): runs of other characters than
    letters, digits, '.', '_' and '-' become one '-'."""
    import re

    return re.sub(r"[^A-Za-z0-9._-]+", "-", name).strip("-") or "trace"
