"""The report's first screen: the answer to the designer, before any definition or table.

Two blocks open the report, right under its title and run line:

- **what was run, when it is not the study**: a run on another bearing or on a cycle of
  another length than the study's (the shipped ``sweeps/bearings/rv-main-study.toml`` and
  ``sweeps/profiles/study.toml``) says so in one paragraph, derived from the stored
  configuration: the bearing's name and ball count against the study bearing's, the
  profile's duration against the study cycle's (the smoke sweep: the 12-ball test bearing
  on a cycle ten times shorter);
- **the headline**: the worst value over the sweep of each number a design turns on (the
  smallest static safety factor s₀, the shortest rating life L10r of the duty cycle, a slot
  for ISO 281's modified life L_nm, the largest start-up drive torque, the smallest radial,
  axial and tilting stiffness), each with the grid point and phase where it occurs and a
  pass/fail mark against a target the user sets with ``rvsweep report --target-…``
  (:data:`TARGETS`).

The values are those of the summary table (:func:`.summary.summary_values`: ensemble means
with realizations, the first value of any further sweep axis), so the headline and the
table never disagree.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ConfigError
from .context import Context, ensemble_text, extra_dims
from .figures import SAME_WITHIN
from .render import Heading, Para, Table, Warning_, fmt_kn, fmt_number, fmt_speed
from .summary import ABSENT, COLUMNS, Summary, table_cell
from .targets import TARGETS, Target

#: Two values closer than this (relative) count as the same: "every speed" rather than one
#: (the figures' :data:`.figures.SAME_WITHIN`, which draws such lines as one).
TIE = SAME_WITHIN

#: The verdict cells (render.py colours a cell that starts with the mark).
PASS, FAIL, NO_TARGET = "✓ pass", "✗ FAIL", "no target set"


assert all(any(c.key == t.key for c in COLUMNS) for t in TARGETS), "a headline target names no summary column"


# --------------------------------------------------------------------------- where it occurs


def _worst(values: np.ndarray, how: str):
    """``(value, [(i, j), …])``: the worst finite value of ``values`` (speed, load) and every
    grid point within :data:`TIE` of it, in grid order; ``(nan, [])`` without a finite one."""
    v = np.asarray(values, dtype=np.float64)
    ok = np.isfinite(v) | (np.isinf(v) & (v > 0))
    if not ok.any():
        return math.nan, []
    filled = np.where(ok, v, np.inf if how == "min" else -np.inf)
    w = float(filled.min() if how == "min" else filled.max())
    if math.isinf(w):
        return w, [tuple(int(k) for k in ij) for ij in np.argwhere(ok & (v == w))]
    tied = np.argwhere(ok & np.isclose(v, w, rtol=TIE, atol=0.0))
    return w, [tuple(int(k) for k in ij) for ij in tied]


def location_text(s: Summary, points: list, values=None) -> str:
    """Where the worst value occurs: '390 °/s, 40 kN'; 'every speed, 40 kN' when it is the
    same (within :data:`TIE`) at every speed of one load ('every speed with a result' when
    some point of that load has none in ``values``), likewise 'every radial load';
    '(and k more points)' for other ties."""
    if not points:
        return ABSENT
    shape = (s.speeds.size, s.loads.size)
    held = (np.isfinite(values) | np.isinf(values)) if values is not None else np.ones(shape, bool)
    loads = {j for _, j in points}
    speeds = {i for i, _ in points}
    if len(loads) == 1 and len(speeds) > 1:
        j = next(iter(loads))
        if speeds == set(np.flatnonzero(held[:, j]).tolist()):
            some = " with a result" if len(speeds) < s.speeds.size else ""
            return f"every speed{some}, {fmt_kn(s.loads[j])}"
    if len(speeds) == 1 and len(loads) > 1:
        i = next(iter(speeds))
        if loads == set(np.flatnonzero(held[i, :]).tolist()):
            some = " with a result" if len(loads) < s.loads.size else ""
            return f"{fmt_speed(s.speeds[i])}, every radial load{some}"
    i, j = points[0]
    text = f"{fmt_speed(s.speeds[i])}, {fmt_kn(s.loads[j])}"
    if len(points) > 1:
        text += f" (and {len(points) - 1} more point{'s' if len(points) > 2 else ''})"
    return text


def verdict(t: Target, value: float, target: float | None) -> str:
    """:data:`PASS`, :data:`FAIL` or :data:`NO_TARGET` of ``value`` against ``target``."""
    if target is None:
        return NO_TARGET
    if not (math.isfinite(value) or (math.isinf(value) and value > 0)):
        return ABSENT
    ok = value >= target if t.worst == "min" else value <= target
    return PASS if ok else FAIL


def _target_text(t: Target, target: float | None) -> str:
    if target is None:
        return f"— (set `{t.flag}`)"
    bound = "≥" if t.worst == "min" else "≤"
    return f"{bound} {fmt_number(target, 4)}" + (f" {t.unit}" if t.unit else "")


def headline_rows(s: Summary, targets: dict) -> list:
    """One row per :data:`TARGETS` entry the sweep holds:
    ``[quantity, worst value, where (speed, load), when (phase), target, verdict]``."""
    rows = []
    for t in TARGETS:
        v = s.values.get(t.key)
        if v is None:
            continue
        w, points = _worst(v, t.worst)
        when = t.where
        if t.key == "safety" and points:
            when = s.phase_text(*points[0])
            phases = {s.phase_text(i, j).split(",")[0] for i, j in points}
            if len(phases) > 1:
                when += " (differs between the tied points)"
        unit = f" {t.unit}" if t.unit else ""
        where = location_text(s, points, np.asarray(v, dtype=np.float64))
        rows.append([t.name, table_cell(w) + unit if points else ABSENT, where, when or ABSENT,
                     _target_text(t, targets.get(t.key)), verdict(t, w, targets.get(t.key))])
    return rows


# --------------------------------------------------------------------------- the study's run


def reduced_run_text(ctx: Context) -> str:
    """A sentence saying how this run differs from the study's bearing and cycle, '' when it
    does not (or without a stored configuration).

    The study's are the shipped ``bearings/rv-main-study.toml`` and ``profiles/study.toml``
    (:mod:`pipeline.schema.shipped`); this run's are read from ``sweep.nc``'s stored
    configuration. The bearing differs when its name or its ball count does; the cycle
    when its duration differs by more than 1 %, stated as 'k times shorter' (or longer).
    """
    conf = ctx.configuration
    if conf is None:
        return ""
    from ..schema import load_bearing, load_profile
    from ..schema.shipped import DEFAULT_BEARING, DEFAULT_PROFILE, shipped_file

    try:
        study_b = load_bearing(shipped_file(DEFAULT_BEARING))
        study_p = load_profile(shipped_file(DEFAULT_PROFILE))
    except (ConfigError, OSError):
        return ""
    b, p = conf.bearing, conf.profile

    def balls(bearing) -> str:
        counts = [r.ball_count for r in bearing.rows]
        sizes = {fmt_number(r.ball_diameter * 1e3, 4) for r in bearing.rows}
        n = " + ".join(str(c) for c in counts)
        return f"{n} balls of {'/'.join(sorted(sizes))} mm"

    parts = []
    n_run, n_study = sum(r.ball_count for r in b.rows), sum(r.ball_count for r in study_b.rows)
    if b.name != study_b.name or n_run != n_study:
        parts.append(f"the bearing `{b.name}`, {balls(b)} (the study's `{study_b.name}`: {balls(study_b)})")
    ratio = study_p.duration / p.duration if p.duration > 0 else math.nan
    if math.isfinite(ratio) and abs(ratio - 1.0) > 0.01:
        how = (f"{fmt_number(ratio, 3)} times shorter" if ratio > 1 else f"{fmt_number(1 / ratio, 3)} times longer")
        parts.append(f"the profile `{p.name}`, a cycle of {fmt_number(p.duration, 4)} s, {how} than the study's "
                     f"{fmt_number(study_p.duration, 4)} s")
    if not parts:
        return ""
    text = "**Not the study's run.** This report shows " + " on ".join(parts) + "."
    if math.isfinite(ratio) and ratio > 1.01:
        text += (f" Its starts and stops are {fmt_number(ratio, 3)} times faster, so its transient metrics are "
                 "not comparable with the study's.")
    return text + " Its numbers describe this run, not the study's bearing on the study's cycle."

# --------------------------------------------------------------------------- the section


def section_headline(ctx: Context) -> list:
    """The report's first section: how this run differs from the study's, then the
    worst value of each design number, where it occurs and its verdict (a list of blocks)."""
    from .summary import summary_values

    if ctx.summary is None:
        ctx.summary = summary_values(ctx)
    s = ctx.summary
    targets = dict(getattr(ctx, "targets", None) or {})
    blocks = [Heading(2, "Headline")]
    reduced = reduced_run_text(ctx)
    if reduced:
        blocks.append(Warning_(reduced))
    rows = headline_rows(s, targets)
    if not rows:
        return blocks + [Para("This sweep holds none of the design numbers (safety factor, lives, torque, "
                              "stiffness): it was written by a version that did not compute them.")]
    total = s.speeds.size * s.loads.size
    held = [np.isfinite(np.asarray(s.values[t.key], dtype=np.float64)) | np.isinf(s.values[t.key])
            for t in TARGETS if s.values.get(t.key) is not None]
    finished = int(np.logical_or.reduce(held).sum())
    ens = ensemble_text(ctx)
    intro = (f"The worst value of each design number over the sweep's {total} operating points"
             + (f" ({finished} with a result)" if finished < total else "")
             + (f", each the ensemble mean of {ens}" if ens else "")
             + (" (other sweep axes at their first value, as in the summary)" if extra_dims(ctx.metrics) else "")
             + ", where it occurs, and its verdict against the target set with `rvsweep report --target-…`.")
    blocks.append(Para(intro))
    set_rows = [r for r in rows if r[5] in (PASS, FAIL)]
    if set_rows:
        failed = [r[0] for r in set_rows if r[5] == FAIL]
        blocks.append(Para(f"**{len(set_rows) - len(failed)} of {len(set_rows)} targets met**"
                           + (": missed: " + "; ".join(failed) + "." if failed else ".")))
    blocks.append(Table(["quantity", "worst over the sweep", "where (speed, radial load)", "when",
                         "target", "verdict"], rows))
    if not set_rows:
        blocks.append(Para("No target set: give them with `rvsweep report DIR --target-s0 2 --target-life 50 "
                           "--target-torque \"20 N m\" --target-radial-stiffness \"500 N/um\"` (or `make report "
                           "REPORTARGS='…'`) for a pass/fail mark."))
    if any(r[2].startswith("every ") or ", every " in r[2] for r in rows):
        blocks.append(Para(f"'every speed' (or 'every radial load'): the worst value is the same within "
                           f"{fmt_number(TIE * 100, 2)} % at each of them."))
    blocks.append(Para("Definitions, every operating point and the figures follow: the summary table "
                       "below, then what each number is."))
    return blocks
