"""Argument helpers shared by the one-case commands (statics, simulate)."""
from __future__ import annotations

from pathlib import Path

from ..errors import ConfigError


def add_load_arguments(parser, *, speed: bool) -> None:
    parser.add_argument("--bearing", required=True, metavar="FILE", help="bearing TOML file")
    if speed:
        parser.add_argument("--speed", required=True, help='steady inner-ring speed, e.g. "660deg/s" or "110 rpm"')
    parser.add_argument("--radial-load", default="0 N", help='radial load, e.g. "30kN" (default 0)')
    parser.add_argument("--axial-load", default="0 N", help='axial load towards +z, e.g. "10kN" (default 0)')
    parser.add_argument("--moment", default="0 N*m", help='tilting moment, e.g. "0Nm" (default 0)')
    parser.add_argument("--load-angle", default="0 deg", help="direction of the radial load from +x (default 0)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help='override a bearing, profile or solver value, with units, e.g. '
                             '--set friction.mu_static=0.05 --set solver.output_rate="2 kHz"')


def parse_sets(items) -> dict:
    """``["a.b=1 mm", ...]`` -> ``{"a.b": "1 mm"}``; numbers stay numbers."""
    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        key, value = key.strip(), value.strip()
        if not sep or not key:
            raise ConfigError("--set", item, None, "expected KEY=VALUE, e.g. friction.mu_static=0.05")
        try:
            out[key] = int(value) if value.isdigit() else float(value)
        except ValueError:
            low = value.lower()
            out[key] = True if low == "true" else False if low == "false" else value.strip('"\'')
    return out


def one_case_sweep(args, *, profile: str | None):
    """A one-case sweep built from the command line, validated like a sweep file."""
    from ..schema import sweep_from_dict

    fixed = {"speed": getattr(args, "speed", "0 deg/s"), "radial_load": args.radial_load,
             "axial_load": args.axial_load, "moment": args.moment, "load_angle": args.load_angle}
    solver = {}
    for key, value in parse_sets(args.set).items():
        if key.startswith("solver."):
            solver[key.split(".", 1)[1]] = value
        else:
            fixed[key] = value
    raw = {"name": "cli", "bearing": str(Path(args.bearing).resolve()),
           "profile": str(Path(profile).resolve()) if profile else str(default_profile()),
           "solver": solver, "cases": [fixed]}
    return sweep_from_dict(raw, Path.cwd() / "command line")


def default_profile() -> Path:
    """The study's cycle shipped with the project."""
    from ..schema.shipped import DEFAULT_PROFILE, shipped_file

    return shipped_file(DEFAULT_PROFILE)
