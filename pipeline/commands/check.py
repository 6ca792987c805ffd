"""``rvsweep check FILE... [--json]``: validate bearing, profile and sweep files.

The kind of each file is told by its content: a top-level ``bearing`` or ``profile`` key
(naming other files) means a sweep, checked with ``pipeline.sweepfile.load_sweep`` when
that module exists; otherwise a ``[[rows]]`` table (or ``[envelope]``) means a bearing,
and ``duration``/``[phases]`` a profile. For a bearing it prints what it derived: pitch diameter, balls, nominal
contact angle, groove ratios, radial clearance, Hertz K of the inner and outer contact at
the nominal angle, ball mass, the epicyclic cage ratio, the smallest pitch diameter for
the ball count, the masses of the inner ring and the cage, and the warnings. Warnings are
repeated on stderr as ``warning: ...``.

Exit status 0 when every file is valid. Otherwise each invalid file's error is one line
on stderr and the status is 2 (the last error is raised as a ConfigError and printed by
``pipeline.cli``).
"""
from __future__ import annotations

import importlib
import json
import math
import sys

from rvcore import geometry as geo
from rvcore.profile import PHASES

from ..schema import bearing_from_dict, profile_from_dict, read_toml
from ..errors import ConfigError, UserError

HELP = "validate bearing, profile and sweep files and print what they imply"

_BEARING_MARKERS = ("rows", "envelope")
_PROFILE_MARKERS = ("duration", "phases")
_SWEEP_MARKERS = ("bearing", "profile")


def add_arguments(parser):
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help="bearing (sweeps/bearings/*.toml), profile (sweeps/profiles/*.toml) "
                             "or sweep (sweeps/*.toml) files")
    parser.add_argument("--json", action="store_true",
                        help="print one JSON object per file (a list when several files are given)")


# --------------------------------------------------------------------------- derivations


def _hertz(row: geo.Row, bearing: geo.Bearing):
    """Hertz K [N m^-1.5] of the first inner and outer arc at the row's nominal angle."""
    from rvcore.hertz import effective_modulus, race_contact

    rm, bm = bearing.ring_material, bearing.ball_material
    if rm == bm:
        e_eff = effective_modulus(rm.youngs_modulus, rm.poisson_ratio)
    else:
        e_eff = effective_modulus(bm.youngs_modulus, bm.poisson_ratio,
                                  rm.youngs_modulus, rm.poisson_ratio)
    alpha = row.nominal_contact_angle
    ki = race_contact(row.ball_diameter, row.pitch_diameter, row.inner_arcs[0].curvature_ratio,
                      alpha, geo.INNER, e_eff).stiffness
    ko = race_contact(row.ball_diameter, row.pitch_diameter, row.outer_arcs[0].curvature_ratio,
                      alpha, geo.OUTER, e_eff).stiffness
    return ki, ko, e_eff


def _raceway_type(row: geo.Row) -> str:
    n = max(len(row.inner_arcs), len(row.outer_arcs))
    if n == 2:
        return "four-point"
    return "deep-groove" if row.nominal_contact_angle == 0.0 else "angular-contact"


def bearing_summary(bearing: geo.Bearing) -> dict:
    """What ``check`` derives from a bearing, SI, JSON-ready.

    The top-level per-row keys (``pitch_diameter_m`` ...) are those of row 0; ``rows``
    lists every row.
    """
    rows = []
    for row in bearing.rows:
        ki, ko, e_eff = _hertz(row, bearing)
        cage_mass, _ = geo.cage_mass_properties(row)
        rows.append({
            "raceway": _raceway_type(row),
            "pitch_diameter_m": row.pitch_diameter,
            "ball_diameter_m": row.ball_diameter,
            "ball_count": row.ball_count,
            "axial_position_m": row.axial_position,
            "contact_angle_rad": row.nominal_contact_angle,
            "contact_angle_deg": math.degrees(row.nominal_contact_angle),
            "inner_groove_ratio": row.inner_arcs[0].curvature_ratio,
            "outer_groove_ratio": row.outer_arcs[0].curvature_ratio,
            "inner_arcs": [{"curvature_ratio": a.curvature_ratio, "contact_angle_rad": a.contact_angle}
                           for a in row.inner_arcs],
            "outer_arcs": [{"curvature_ratio": a.curvature_ratio, "contact_angle_rad": a.contact_angle}
                           for a in row.outer_arcs],
            "radial_clearance_m": row.radial_clearance,
            "effective_modulus_pa": e_eff,
            "hertz_k_inner": ki,
            "hertz_k_outer": ko,
            "ball_mass_kg": geo.ball_mass(row, bearing.ball_material),
            "cage_speed_ratio": geo.epicyclic_cage_ratio(row),
            "min_pitch_diameter_m": geo.min_pitch_diameter(row.ball_count, row.ball_diameter),
            "cage_mass_kg": cage_mass,
            "cage_guidance": row.cage.guidance,
        })
    inner_mass, _, _ = geo.inner_ring_mass_properties(bearing)
    out = {"kind": "bearing", "name": bearing.name}
    out.update(rows[0])
    out.update({
        "bore_m": bearing.bore,
        "outer_diameter_m": bearing.outer_diameter,
        "width_m": bearing.width,
        "inner_ring_mass_kg": inner_mass,
        "gravity_m_per_s2": list(bearing.gravity),
        "allow_ball_overlap": bearing.allow_ball_overlap,
        "rows": rows,
        "assumptions": list(bearing.assumptions),
        "warnings": list(bearing.warnings),
    })
    return out


def profile_summary(profile) -> dict:
    """What ``check`` derives from a profile, SI, JSON-ready."""
    chans = {}
    for name in ("radial_load", "axial_load", "speed"):
        ch = getattr(profile, name)
        chans[name] = {
            "time_s": list(ch.times),
            ("fraction" if ch.relative else "value_si"): list(ch.values),
            "interpolation": ch.interpolation,
        }
    return {
        "kind": "profile",
        "name": profile.name,
        "duration_s": profile.duration,
        "channels": chans,
        "phases": {n: [s, e] for (n, s, e) in profile.phases},
        "warnings": [],
    }


def _sweep_summary(sweep, file) -> dict:
    """A summary of a ``pipeline.sweepfile.Sweep`` (read defensively: another module's type)."""
    warnings = list(getattr(sweep, "warnings", ()) or ())
    cases = getattr(sweep, "cases", None)
    cases = cases() if callable(cases) else cases
    bearings = [getattr(sweep, "bearing", None)] + [getattr(c, "bearing", None) for c in (cases or ())]
    for b in bearings:
        if isinstance(b, geo.Bearing):
            warnings += [w for w in b.warnings if w not in warnings]
    out = {"kind": "sweep", "name": getattr(sweep, "name", None)}
    for attr in ("bearing_file", "profile_file"):
        if getattr(sweep, attr, None) is not None:
            out[attr] = str(getattr(sweep, attr))
    if cases is not None:
        out["case_count"] = len(cases)
    axes = getattr(sweep, "axes", None)
    if axes:
        out["axes"] = {str(getattr(a, "key", a)): len(getattr(a, "values", ()) or ()) for a in axes}
    bearing = getattr(sweep, "bearing", None)
    if isinstance(bearing, geo.Bearing):
        out["allow_ball_overlap"] = bearing.allow_ball_overlap
    out["warnings"] = warnings
    return out


def _load_sweep_function():
    try:
        mod = importlib.import_module("pipeline.sweepfile")
    except ModuleNotFoundError as exc:
        if exc.name == "pipeline.sweepfile":
            return None
        raise
    return getattr(mod, "load_sweep", None)


def check_file(path) -> dict:
    """Validate one file and return its summary (``file`` and ``kind`` included).

    Raises
    ------
    ConfigError
        The file's first problem.
    """
    raw = read_toml(path)
    file = str(path)
    # A sweep names its bearing and profile files; bearing and profile files never do.
    if any(isinstance(raw.get(k), (str, dict)) for k in _SWEEP_MARKERS):
        load_sweep = _load_sweep_function()
        if load_sweep is None:
            raise ConfigError(file, None, None,
                              "looks like a sweep file, but this installation cannot check "
                              "sweep files yet (pipeline.sweepfile.load_sweep is missing)")
        summary = _sweep_summary(load_sweep(path), file)
    elif any(k in raw for k in _BEARING_MARKERS):
        summary = bearing_summary(bearing_from_dict(raw, file=file))
    elif any(k in raw for k in _PROFILE_MARKERS):
        summary = profile_summary(profile_from_dict(raw, file=file))
    else:
        raise ConfigError(file, None, None,
                          "not a bearing file (no [[rows]] / [envelope]), profile file "
                          "(no duration / [phases]) or sweep file (no bearing / profile key)")
    return {"file": file, **summary}


# --------------------------------------------------------------------------- printing


def _mm(x):
    return f"{x * 1e3:.6g} mm"


def _explain(s: dict, warning: str) -> str:
    """A warning with the context a reader needs (the overlap: why it is not an error)."""
    if s.get("allow_ball_overlap") and "need a pitch diameter" in warning:
        return (f"{warning} (accepted because allow_ball_overlap = true; the balls do not "
                "touch each other in this model, and every output repeats this caveat)")
    return warning


def _format_bearing(s: dict) -> list:
    lines = [f"{s['file']}: bearing '{s['name']}' ({len(s['rows'])} row{'s' if len(s['rows']) > 1 else ''}), "
             f"bore {_mm(s['bore_m'])}, outer diameter {_mm(s['outer_diameter_m'])}, width {_mm(s['width_m'])}"]
    for i, r in enumerate(s["rows"]):
        arcs = lambda arcs: ", ".join(f"f = {a['curvature_ratio']:g} at {math.degrees(a['contact_angle_rad']):g} deg"
                                      for a in arcs)
        lines += [
            f"  row {i}: {r['raceway']}, {r['ball_count']} balls of {_mm(r['ball_diameter_m'])} "
            f"on a pitch diameter of {_mm(r['pitch_diameter_m'])} "
            f"(at least {r['min_pitch_diameter_m'] * 1e3:.1f} mm needed for {r['ball_count']} balls)",
            f"    nominal contact angle {r['contact_angle_deg']:.6g} deg; radial clearance "
            f"{_mm(r['radial_clearance_m'])}",
            f"    inner groove: {arcs(r['inner_arcs'])}; outer groove: {arcs(r['outer_arcs'])}",
            f"    Hertz K at {r['contact_angle_deg']:.6g} deg: inner {r['hertz_k_inner']:.4g} N/m^1.5, "
            f"outer {r['hertz_k_outer']:.4g} N/m^1.5 (E' = {r['effective_modulus_pa'] / 1e9:.4g} GPa)",
            f"    ball mass {r['ball_mass_kg']:.4g} kg; epicyclic cage speed / inner-ring speed "
            f"{r['cage_speed_ratio']:.5f}; cage {r['cage_guidance']} guided, {r['cage_mass_kg']:.3g} kg",
        ]
    lines.append(f"  inner ring mass {s['inner_ring_mass_kg']:.4g} kg (with attachments); gravity "
                 f"({', '.join(f'{g:.4g}' for g in s['gravity_m_per_s2'])}) m/s^2 in the bearing frame")
    if s["assumptions"]:
        lines.append(f"  assumptions ({len(s['assumptions'])}): {', '.join(s['assumptions'])}")
    for w in s["warnings"]:
        lines.append(f"  warning: {_explain(s, w)}")
    if not s["warnings"]:
        lines.append("  no warnings")
    return lines


def _format_profile(s: dict) -> list:
    lines = [f"{s['file']}: profile '{s['name']}', duration {s['duration_s']:g} s"]
    for name, ch in s["channels"].items():
        vals = ch.get("fraction", ch.get("value_si"))
        what = "fraction" if "fraction" in ch else "value (SI)"
        pts = ", ".join(f"{t:g} s: {v:g}" for t, v in zip(ch["time_s"], vals))
        lines.append(f"  {name} ({what}, {ch['interpolation']}): {pts}")
    lines.append("  phases: " + ", ".join(f"{n} {s['phases'][n][0]:g}-{s['phases'][n][1]:g} s"
                                          for n in PHASES if n in s["phases"]))
    return lines


def _format(s: dict) -> list:
    if s["kind"] == "bearing":
        return _format_bearing(s)
    if s["kind"] == "profile":
        return _format_profile(s)
    lines = [f"{s['file']}: sweep '{s.get('name')}'"
             + (f", {s['case_count']} cases" if "case_count" in s else "")]
    if "axes" in s:
        lines.append("  axes: " + ", ".join(f"{k} ({n} values)" for k, n in s["axes"].items()))
    for attr in ("bearing_file", "profile_file"):
        if attr in s:
            lines.append(f"  {attr.replace('_file', '')}: {s[attr]}")
    lines += [f"  warning: {_explain(s, w)}" for w in s["warnings"]]
    return lines


def _json_default(x):
    if hasattr(x, "item"):  # numpy scalars
        return x.item()
    return str(x)


def run(args) -> int:
    summaries, errors = [], []
    for path in args.files:
        try:
            summaries.append(check_file(path))
        except UserError as exc:
            errors.append(exc)
    if args.json:
        payload = summaries[0] if len(args.files) == 1 and summaries else summaries
        if summaries or len(args.files) > 1:
            print(json.dumps(payload, indent=2, default=_json_default))
    else:
        for s in summaries:
            print("\n".join(_format(s)))
    for s in summaries:
        for w in s["warnings"]:
            print(f"warning: {s['file']}: {_explain(s, w)}", file=sys.stderr)
    if errors:
        for exc in errors[:-1]:
            print(f"rvsweep check: error: {exc}", file=sys.stderr)
        raise errors[-1]
    return 0
