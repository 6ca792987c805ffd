"""``rvsweep check [FILE...] [--json] [--fields]``: validate bearing, profile and sweep files.

With no FILE it checks the shipped default sweep (``pipeline.schema.shipped``) and the
bearing and profile files it names, from any directory. A FILE that does not exist but
names a shipped file (``bearings/rv-main-study.toml``) is that file. ``--fields`` lists
the input schema (:data:`pipeline.schema.fields.FIELDS`): key, kind, unit, default,
bounds and doc. Values are printed in the schema's display unit of their field.

The kind of each file is told by its content: a top-level ``bearing`` or ``profile`` key
(naming other files) means a sweep, checked with ``pipeline.schema.read_sweep_file``; otherwise a ``[[rows]]`` table (or ``[envelope]``) means a bearing,
and ``duration``/``[phases]`` a profile. For a bearing it prints what it derived: pitch diameter, balls, nominal
contact angle, groove ratios, radial clearance, Hertz K of the inner and outer contact at
the nominal angle, ball mass, the epicyclic cage ratio, the smallest pitch diameter for
the ball count, the masses of the inner ring and the cage, the row count and preload force
(``row_count``, ``preload_N``: 0 for a single row), and how many warnings it has. The
warnings go to stderr as ``warning: <file>: ...``, each text once however many of the
files checked carry it.

Exit status 0 when every file is valid. Otherwise each invalid file's error is one line
on stderr and the status is 2 (the last error is raised as a ConfigError and printed by
``pipeline.cli``).
"""
from __future__ import annotations

import json
import math
import sys
from typing import TYPE_CHECKING

from ..errors import ConfigError, UserError
from .common import SHIPPED_HELP, input_file

# rvcore, the schema and what they import (numba, pint, scipy) are imported by the
# functions that use them, so that `rvsweep --help` does not load them.
if TYPE_CHECKING:
    from rvcore.bearing import geometry as geo

HELP = "validate bearing, profile and sweep files and print what they imply"

_BEARING_MARKERS = ("rows", "envelope")
_PROFILE_MARKERS = ("duration", "phases")
_SWEEP_MARKERS = ("bearing", "profile")


def add_arguments(parser):
    parser.add_argument("files", nargs="*", metavar="FILE",
                        help="bearing (sweeps/bearings/*.toml), profile (sweeps/profiles/*.toml) "
                             "or sweep (sweeps/*.toml) files; none: the shipped default sweep and "
                             "its bearing and profile. Each is " + SHIPPED_HELP)
    parser.add_argument("--json", action="store_true",
                        help="print one JSON object per file (a list when several files are given)")
    parser.add_argument("--fields", action="store_true",
                        help="list the input schema instead: every key of the bearing file, the "
                             "profile file, the sweep's [solver] table and the operating point, with "
                             "kind, unit, default, bounds and doc")


# --------------------------------------------------------------------------- derivations


def _hertz(row: geo.Row, bearing: geo.Bearing):
    """Hertz K [N m^-1.5] of the first inner and outer arc at the row's nominal angle."""
    from rvcore.hertz import effective_modulus, race_contact
    from rvcore.bearing import geometry as geo

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
    from rvcore.bearing import geometry as geo

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
    from rvcore.statics.preload import preload_force

    inner_mass, _, _ = geo.inner_ring_mass_properties(bearing)
    out = {"kind": "bearing", "name": bearing.name}
    out.update(rows[0])
    out.update({
        "row_count": len(bearing.rows),
        "arrangement": bearing.arrangement,
        "preload_N": preload_force(bearing),
        "preload_offset_m": bearing.preload_offset,
        "bore_m": bearing.bore,
        "outer_diameter_m": bearing.outer_diameter,
        "width_m": bearing.width,
        "inner_ring_mass_kg": inner_mass,
        # each ring rigid, or flexible in its support (docs/inputs.md "Flexible rings")
        "ring_supports": {r: ("rigid" if getattr(bearing, f"{r}_ring_support") is None
                              else getattr(bearing, f"{r}_ring_support").kind) for r in ("inner", "outer")},
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


def _axis_range(axis):
    """"first ... last" of a numeric axis in its schema field's display unit, the values
    of a categorical one (``solver.method``: "rk4, imex"), or None."""
    from ..schema.fields import check_set_key
    from ..schema.parameters import format_value

    if axis.coords and all(isinstance(c, str) for c in axis.coords):
        return ", ".join(axis.coords)
    try:
        f = check_set_key(axis.key)
    except UserError:
        return None
    coords = [c for c in axis.coords if isinstance(c, (int, float)) and not isinstance(c, bool)]
    if f.kind not in ("quantity", "integer") or not coords or len(coords) != len(axis.coords):
        return None
    return f"{format_value(f, min(coords))} ... {format_value(f, max(coords))}"


def _sweep_summary(sweep) -> dict:
    """A summary of a :class:`pipeline.schema.sweepfile.Sweep`: its files, cases, axes and
    the geometry warnings of its bearings (each once)."""
    warnings = []
    for b in [sweep.bearing] + [c.bearing for c in sweep.cases]:
        warnings += [w for w in b.warnings if w not in warnings]
    out = {"kind": "sweep", "name": sweep.name, "bearing_file": str(sweep.bearing_file),
           "profile_file": str(sweep.profile_file), "case_count": len(sweep.cases)}
    if sweep.axes:
        out["axes"] = {a.key: len(a.values) for a in sweep.axes}
        out["axis_ranges"] = {a.key: r for a in sweep.axes if (r := _axis_range(a)) is not None}
    if sweep.statistics is not None:
        from ..schema.statistics import statistics_note

        out["statistics"] = statistics_note(sweep.statistics)
    out["allow_ball_overlap"] = sweep.bearing.allow_ball_overlap
    out["warnings"] = warnings
    return out


def check_file(path) -> dict:
    """Validate one file and return its summary (``file`` and ``kind`` included).

    Raises
    ------
    ConfigError
        The file's first problem.
    """
    from ..schema import bearing_from_dict, profile_from_dict, read_sweep_file, read_toml

    path = input_file(path)
    raw = read_toml(path)
    file = str(path)
    # A sweep names its bearing and profile files; bearing and profile files never do.
    if any(isinstance(raw.get(k), (str, dict)) for k in _SWEEP_MARKERS):
        summary = _sweep_summary(read_sweep_file(path))
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


def _show(file: str, key: str, value) -> str:
    """``value`` (SI) in the display unit the schema gives the field at ``key``."""
    from ..schema.fields import field
    from ..schema.parameters import format_value

    return format_value(field(file, key), value)


def _bearing_value(key: str, value) -> str:
    return _show("bearing", key, value)


def _explain(s: dict, warning: str) -> str:
    """A warning with the context a reader needs (the overlap: why it is not an error)."""
    if s.get("allow_ball_overlap") and "need a pitch diameter" in warning:
        return (f"{warning} (accepted because allow_ball_overlap = true; the balls do not "
                "touch each other in this model, and every output repeats this caveat)")
    return warning


def _format_bearing(s: dict) -> list:
    lines = [f"{s['file']}: bearing '{s['name']}' ({len(s['rows'])} row{'s' if len(s['rows']) > 1 else ''}), "
             f"bore {_bearing_value('envelope.bore', s['bore_m'])}, outer diameter "
             f"{_bearing_value('envelope.outer_diameter', s['outer_diameter_m'])}, "
             f"width {_bearing_value('envelope.width', s['width_m'])}"]
    if s["arrangement"]:
        spacing = s["rows"][-1]["axial_position_m"] - s["rows"][0]["axial_position_m"]
        lines.append(f"  {s['arrangement']} pair, rows {_bearing_value('pair.row_spacing', abs(spacing))} apart; "
                     f"preload {_bearing_value('pair.preload', s['preload_N'])} "
                     f"(inner-raceway offset {_bearing_value('pair.preload_offset', s['preload_offset_m'])})")
    for i, r in enumerate(s["rows"]):
        angle = lambda x: _bearing_value("rows[].inner_groove.arcs[].contact_angle", x)  # noqa: E731
        arcs = lambda arcs: ", ".join(f"f = {a['curvature_ratio']:g} at {angle(a['contact_angle_rad'])}"  # noqa: E731
                                      for a in arcs)
        lines += [
            f"  row {i}: {r['raceway']}, {r['ball_count']} balls of "
            f"{_bearing_value('rows[].balls.diameter', r['ball_diameter_m'])} "
            f"on a pitch diameter of {_bearing_value('rows[].pitch_diameter', r['pitch_diameter_m'])} "
            f"(at least {_bearing_value('rows[].pitch_diameter', r['min_pitch_diameter_m'])} needed for "
            f"{r['ball_count']} balls)",
            f"    nominal contact angle {angle(r['contact_angle_rad'])}; radial clearance "
            f"{_bearing_value('rows[].radial_clearance', r['radial_clearance_m'])}"
            + (" (interference)" if r["radial_clearance_m"] < 0 else "")
            + (f"; axial position {_bearing_value('rows[].axial_position', r['axial_position_m'])}"
               if len(s["rows"]) > 1 else ""),
            f"    inner groove: {arcs(r['inner_arcs'])}; outer groove: {arcs(r['outer_arcs'])}",
            f"    Hertz K at {angle(r['contact_angle_rad'])}: inner {r['hertz_k_inner']:.4g} N/m^1.5, "
            f"outer {r['hertz_k_outer']:.4g} N/m^1.5 (E' = {r['effective_modulus_pa'] / 1e9:.4g} GPa)",
            f"    ball mass {r['ball_mass_kg']:.4g} kg; epicyclic cage speed / inner-ring speed "
            f"{r['cage_speed_ratio']:.5f}; cage {r['cage_guidance']} guided, {r['cage_mass_kg']:.3g} kg",
        ]
    lines.append(f"  inner ring mass {s['inner_ring_mass_kg']:.4g} kg (with attachments); gravity "
                 f"{_bearing_value('gravity', s['gravity_m_per_s2'])} in the bearing frame")
    if set(s["ring_supports"].values()) != {"rigid"}:
        from rvcore.dynamics.ring_modes import DYNAMICS_MAX_ORDER

        lines.append(f"  rings: inner {s['ring_supports']['inner']}, outer {s['ring_supports']['outer']} (flexible; "
                     f"the dynamics keep their modes up to order {DYNAMICS_MAX_ORDER}, docs/model.md §16.1)")
    if s["assumptions"]:
        lines.append(f"  assumptions ({len(s['assumptions'])}): {', '.join(s['assumptions'])}")
    lines.append(_warning_count(s))
    return lines


def _warning_count(s: dict) -> str:
    """The summary's line about warnings; their text goes to stderr once (:func:`run`)."""
    n = len(s["warnings"])
    return f"  {n} warning{'s' if n != 1 else ''} (on stderr)" if n else "  no warnings"


def _format_profile(s: dict) -> list:
    from rvcore.profile import PHASES

    lines = [f"{s['file']}: profile '{s['name']}', duration {_show('profile', 'duration', s['duration_s'])}"]
    for name, ch in s["channels"].items():
        what = "fraction" if "fraction" in ch else "value"
        vals = ch.get("fraction", ch.get("value_si"))
        time = lambda t: _show("profile", f"{name}.time", t)  # noqa: E731
        pts = ", ".join(f"{time(t)}: {_show('profile', f'{name}.{what}', v)}"
                        for t, v in zip(ch["time_s"], vals))
        lines.append(f"  {name} ({what}, {ch['interpolation']}): {pts}")
    lines.append("  phases: " + ", ".join(f"{n} {s['phases'][n][0]:g}-{_show('profile', f'phases.{n}', s['phases'][n][1])}"
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
        ranges = s.get("axis_ranges", {})
        lines.append("  axes: " + ", ".join(f"{k} ({n} values" + (f", {ranges[k]})" if k in ranges else ")")
                                            for k, n in s["axes"].items()))
    if "statistics" in s:
        lines.append(f"  statistics: {s['statistics']}")
    for attr in ("bearing_file", "profile_file"):
        if attr in s:
            lines.append(f"  {attr.replace('_file', '')}: {s[attr]}")
    lines.append(_warning_count(s))
    return lines


def _json_default(x):
    if hasattr(x, "item"):  # numpy scalars
        return x.item()
    return str(x)


def schema_rows() -> list:
    """The input schema as JSON-ready dicts: key, file, kind, unit, default, bounds, doc."""
    from ..schema import FIELDS, REQUIRED
    from ..schema.parameters import format_value

    rows = []
    for f in FIELDS:
        default = "required" if f.default is REQUIRED else f.default
        if isinstance(default, float) and f.unit and f.unit_kind:
            default = format_value(f, default)
        key = f.path if f.file in ("bearing", "operating_point", "solver", "statistics") else f"profile.{f.path}"
        rows.append({"key": key, "file": f.file, "kind": f.kind + (f" ({f.unit_kind})" if f.unit_kind else ""),
                     "unit": f.unit, "default": default, "bounds": f.bounds_text(), "doc": f.doc})
    return rows


def _print_fields(as_json: bool) -> None:
    rows = schema_rows()
    if as_json:
        print(json.dumps(rows, indent=1, default=_json_default))
        return
    width = max(len(r["key"]) for r in rows)
    for r in rows:
        default = "" if r["default"] == "" else f"default {r['default']}; "
        unit = f"[{r['unit']}] " if r["unit"] else ""
        bounds = f"{r['bounds']}; " if r["bounds"] else ""
        print(f"{r['key']:<{width}}  {r['kind']} {unit}- {default}{bounds}{r['doc']}")


def _default_files() -> list:
    """The shipped default sweep, then the bearing and profile files it names."""
    from ..schema.shipped import DEFAULT_SWEEP, shipped_file
    from ..schema import read_toml

    sweep = shipped_file(DEFAULT_SWEEP)
    raw = read_toml(sweep)
    return [sweep] + [input_file(sweep.parent / raw[k]) for k in _SWEEP_MARKERS if isinstance(raw.get(k), str)]


def run(args) -> int:
    if args.fields:
        _print_fields(args.json)
        return 0
    files = list(args.files) or _default_files()
    summaries, errors = [], []
    for path in files:
        try:
            summaries.append(check_file(path))
        except UserError as exc:
            errors.append(exc)
    if args.json:
        payload = summaries[0] if len(files) == 1 and summaries else summaries
        if summaries or len(files) > 1:
            print(json.dumps(payload, indent=2, default=_json_default))
    else:
        for s in summaries:
            print("\n".join(_format(s)))
    # Each warning once: a sweep carries its bearing's warnings, and the default check
    # reads the sweep and its bearing, so the same text would come twice (four times when
    # the summaries repeated it too).
    seen = set()
    for s in summaries:
        for w in s["warnings"]:
            if w not in seen:
                seen.add(w)
                print(f"warning: {s['file']}: {_explain(s, w)}", file=sys.stderr)
    if errors:
        for exc in errors[:-1]:
            print(f"rvsweep check: error: {exc}", file=sys.stderr)
        raise errors[-1]
    return 0
