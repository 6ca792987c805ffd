"""The load distribution of the bearing at the extreme operating points of the sweep.

The cases with the smallest and the largest loads (the corners of the load-like
quantities that vary over the sweep: radial load, axial load, tilting moment, the pair's
preload) are rebuilt from their stored configuration, and the quasi-static equilibrium at
their steady operating point (:func:`rvcore.operating.steady_statics`: rigid rings,
Hertz at every contact, balls in equilibrium, the ring's weight) gives the load of every
ball per row and azimuth, each row's radial and axial load and the tangent stiffness.

Where a case comes from:

- a case file (``cases/*.nc``) whose ``configuration`` is the resolved case
  (:func:`pipeline.schema.case_configuration`: bearing, profile, operating point) is
  rebuilt from it;
- otherwise, with a readable sweep configuration (:func:`pipeline.schema.stored_configuration`)
  and no sweep axis that changes the bearing or the profile, the case is the sweep's
  bearing and profile at the grid point's operating point (``speed``, ``radial_load``,
  ``axial_load``, ``moment``, ``load_angle`` from the grid, else the sweep's fixed values).
"""
from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvcore.geometry import Bearing
from rvcore.operating import steady_loads, steady_statics
from rvcore.preload import apply_preload
from rvcore.profile import OperatingPoint, Profile

from ..errors import ConfigError
from ..schema.stored import rebuild
from .context import Context
from .figures import new_figure, save_figure
from .render import Heading, Image, Para, Table, fmt_speed, fmt_number, fmt_kn

#: The operating-point keys a sweep axis or fixed value may set.
_OP_KEYS = tuple(f.name for f in dataclasses.fields(OperatingPoint))

#: Load-like quantities whose corners are the extreme operating points: (key, label, unit).
LOAD_QUANTITIES = (("radial_load", "radial load", "N"), ("axial_load", "axial load", "N"),
                   ("moment", "tilting moment", "N m"), ("preload", "preload", "N"))

#: Largest number of extreme cases shown.
MAX_CASES = 4


@dataclass(frozen=True)
class OperatingCase:
    """One case rebuilt for the statics (SI).

    ``source`` says where it was rebuilt from (a case file's name or the sweep's
    configuration); ``seed`` is the realization (cases that differ only in it are one).
    """

    bearing: Bearing
    profile: Profile
    op: OperatingPoint
    source: str

    def loads(self) -> dict:
        """Steady radial and axial load [N], moment [N m] and the pair's preload [N]."""
        fr, fa, m, _ = steady_loads(self.profile, self.op)
        return {"radial_load": fr, "axial_load": fa, "moment": m, "preload": self.bearing.preload}

    def label(self) -> str:
        """'390 °/s, 30 kN radial, 10 kN axial[, 2 kN m][, preload 2 kN]' at the steady point."""
        q = self.loads()
        text = f"{fmt_speed(math.degrees(self.op.speed))}, {fmt_kn(q['radial_load'])} radial, {fmt_kn(q['axial_load'])} axial"
        if q["moment"]:
            text += f", {fmt_number(q['moment'] / 1e3, 4)} kN m"
        if q["preload"]:
            text += f", preload {fmt_kn(q['preload'])}"
        return text


def _from_case_text(text: str, source: str):
    """An :class:`OperatingCase` from a resolved case's configuration, or None when ``text``
    is not one (a sweep's configuration has no ``operating_point``)."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return None
    if not isinstance(doc.get("operating_point"), dict):
        return None
    try:
        return OperatingCase(rebuild(Bearing, doc.get("bearing"), "bearing"),
                             rebuild(Profile, doc.get("profile"), "profile"),
                             rebuild(OperatingPoint, doc["operating_point"], "operating_point"), source)
    except ConfigError:
        return None


def _case_file_cases(directory: Path) -> list:
    """Cases rebuilt from ``cases/*.nc`` that store their resolved configuration."""
    import netCDF4

    out = []
    for f in sorted((directory / "cases").glob("*.nc")):
        try:
            with netCDF4.Dataset(f) as nc:
                text = str(nc.getncattr("configuration")) if "configuration" in nc.ncattrs() else ""
        except OSError:
            continue
        case = _from_case_text(text, f"cases/{f.name}")
        if case is not None:
            out.append(case)
    return out


def _grid_cases(ctx: Context) -> tuple:
    """Cases at the finished grid points from the sweep's configuration, and why none when
    they cannot be rebuilt that way."""
    conf = ctx.configuration
    if conf is None:
        return [], f"the sweep's configuration could not be read ({ctx.config_error})"
    other = [k for k in conf.axes if k not in _OP_KEYS and k != "realization"]
    if other:
        return [], ("the case files, which hold each case's resolved configuration, are missing, and the "
                    f"sweep axes {', '.join(other)} change the bearing or the profile")
    from .select import base_states

    ok = base_states(ctx) == "ok"
    if "realization" in ok.dims:
        ok = ok.any("realization")
    base = {k: float(v) for k, v in conf.fixed.items() if k in _OP_KEYS and isinstance(v, (int, float))}
    out = []
    dims = [d for d in ok.dims]
    for idx in np.ndindex(*ok.shape):
        if not bool(ok.values[idx]):
            continue
        values = dict(base)
        for d, i in zip(dims, idx):
            if d in _OP_KEYS:
                v = float(ok[d].values[i])
                values[d] = math.radians(v) if d == "speed" else v
        for d in _OP_KEYS:
            if d in ctx.sweep.coords and ctx.sweep[d].ndim == 0 and d not in values:
                values[d] = float(ctx.sweep[d].values)
        values.setdefault("axial_load", 0.0)
        try:
            op = OperatingPoint(**{k: values[k] for k in _OP_KEYS if k in values})
        except TypeError:
            continue
        out.append(OperatingCase(conf.bearing, conf.profile, op, "the sweep's configuration"))
    return out, ""


def operating_cases(ctx: Context) -> tuple:
    """Every rebuildable case of the sweep (:class:`OperatingCase`) and, when there is none, why."""
    cases = _case_file_cases(ctx.directory)
    why = ""
    if not cases:
        cases, why = _grid_cases(ctx)
    # slowest first, so that of the cases at one load the corner takes the slowest
    return sorted(cases, key=lambda c: (c.op.speed, c.source)), why


def extreme_cases(cases: list) -> list:
    """The cases nearest to the corners of the load-like quantities that vary among ``cases``.

    With one or two such quantities, every corner (min/max of each, at most 4); with more,
    the all-smallest and the all-largest corner. Distance is measured in each quantity's
    span; ties go to the first case (:func:`operating_cases` puts the slowest first). Cases that differ only in
    speed or realization are one operating point for the statics: at most one of them is
    taken per corner. Without any varying load, the first case alone.
    """
    if not cases:
        return []
    q = np.array([[c.loads()[k] for k, _, _ in LOAD_QUANTITIES] for c in cases], dtype=np.float64)
    varying = [j for j in range(q.shape[1]) if np.ptp(q[:, j]) > 1e-9 * max(np.abs(q[:, j]).max(), 1.0)]
    if not varying:
        return [cases[0]]
    lo, hi = q[:, varying].min(axis=0), q[:, varying].max(axis=0)
    span = hi - lo
    if len(varying) <= 2:
        corners = [np.array(c) for c in np.array(np.meshgrid(*[(a, b) for a, b in zip(lo, hi)],
                                                             indexing="ij")).reshape(len(varying), -1).T]
    else:
        corners = [lo, hi]
    out, seen = [], []
    for corner in corners:
        d = (((q[:, varying] - corner) / span) ** 2).sum(axis=1)
        k = int(np.argmin(d))
        key = tuple(q[k])
        if key not in seen:
            seen.append(key)
            out.append(cases[k])
    return out[:MAX_CASES]


def _prepared(bearing: Bearing) -> Bearing:
    """The bearing as the core runs it: a pair's preload force turned into its offset."""
    if bearing.preload > 0.0 and bearing.preload_offset == 0.0:
        return apply_preload(bearing)
    return bearing


@dataclass
class Solved:
    """The statics at one extreme case: ``result`` (:class:`rvcore.quasistatic.StaticResult`)
    or ``error`` (why there is none)."""

    case: OperatingCase
    result: object = None
    error: str = ""


def solve_extremes(ctx: Context) -> tuple:
    """The statics at the extreme operating points: ``([Solved], why none)``."""
    cases, why = operating_cases(ctx)
    solved = []
    for c in extreme_cases(cases):
        try:
            solved.append(Solved(c, steady_statics(_prepared(c.bearing), c.profile, c.op)))
        except (ValueError, ArithmeticError) as exc:   # NoEquilibriumError is a ValueError
            solved.append(Solved(c, error=f"{type(exc).__name__}: {exc}"))
    return solved, why


def _inner_columns(st) -> list:
    return [k for k in range(st.ball_loads.shape[1]) if int(st.arc_rings[k]) == 0]


def _row_label(bearing: Bearing, r: int) -> str:
    row = bearing.rows[r]
    return (f"row {r} (z = {fmt_number(row.axial_position * 1e3 + 0.0, 4)} mm, "
            f"α = {fmt_number(math.degrees(row.nominal_contact_angle), 4)}°)")


def _azimuth_from_load(st) -> np.ndarray:
    """Each ball's azimuth from the radial load's direction, in (−180, 180] deg."""
    a = np.degrees(np.asarray(st.azimuths) - st.load_angle)
    return -((-a + 180.0) % 360.0 - 180.0)


def figure_load_distribution(solved: list, path: Path) -> None:
    """Inner contact load [kN] against azimuth [deg], a line per row (and inner arc), a panel per case."""
    n = len(solved)
    ncols = min(n, 2)
    nrows = int(math.ceil(n / ncols))
    fig, axes = new_figure(nrows, ncols, (5.2 * ncols, 3.4 * nrows))
    for i, s in enumerate(solved):
        ax = axes[i // ncols, i % ncols]
        ax.set_title(s.case.label(), fontsize=8)
        if s.result is None:
            ax.text(0.5, 0.5, "no equilibrium", transform=ax.transAxes, ha="center", va="center",
                    fontsize=8, color="0.4")
            continue
        st = s.result
        az = _azimuth_from_load(st)
        cols = _inner_columns(st)
        for r in range(len(s.case.bearing.rows)):
            balls = np.flatnonzero(np.asarray(st.row_of_ball) == r)
            order = balls[np.argsort(az[balls])]
            row_cols = [k for k in cols if np.any(st.ball_loads[balls, k] > 0.0)] or cols[:1]
            for m, k in enumerate(row_cols):
                label = _row_label(s.case.bearing, r) + (f", inner arc {cols.index(k)}" if len(row_cols) > 1 else "")
                ax.plot(az[order], st.ball_loads[order, k] / 1e3, marker="o", ms=3, lw=1.0,
                        ls="-" if m == 0 else "--", color=f"C{r}", label=label)
        ax.axvline(0.0, color="0.5", lw=0.6)
        ax.set_xlim(-180.0, 180.0)
        ax.set_xticks(np.arange(-180, 181, 60))
        ax.set_xlabel("azimuth from the radial load's direction [deg]")
        ax.set_ylabel("inner contact load [kN]")
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=8)
    for j in range(n, nrows * ncols):
        axes[j // ncols, j % ncols].set_visible(False)
    fig.suptitle("Ball loads at the inner ring at the steady operating point (quasi-static)", fontsize=10)
    save_figure(fig, path)


def section_load_distribution(ctx: Context, figdir: Path, solved: list, why: str = ""):
    """The "Load distribution" section: figure and per-row table at the extreme cases."""
    blocks = [Heading(2, "Load distribution")]
    if not solved:
        blocks.append(Para("No case could be rebuilt for the statics" + (f": {why}." if why else ".")))
        return blocks, []
    p = figdir / "load_distribution.png"
    figure_load_distribution(solved, p)
    n_rows = {len(s.case.bearing.rows) for s in solved}
    blocks.append(Para(
        "The load of every ball at the inner ring at the steady operating point (the loads the profile "
        "applies in the middle of its steady phase) of the extreme cases of the sweep (the smallest and "
        "largest loads), one panel per case and one line per row"
        + (" (its axial position z and contact angle α)" if max(n_rows) > 1 else "")
        + ". Quasi-static equilibrium of the inner ring with Hertz's law at every contact, the balls in "
        "equilibrium and the ring's weight; azimuth measured from the radial load's direction. Each case "
        "is rebuilt from " + ", ".join(sorted({s.case.source if not s.case.source.startswith('cases/')
                                               else 'its case file' for s in solved})) + "."))
    blocks.append(Image(f"figures/{p.name}", "ball loads against azimuth at the extreme operating points"))
    rows = []
    for s in solved:
        if s.result is None:
            rows.append([s.case.label(), "-", "no equilibrium: " + s.error, "", "", ""])
            continue
        st = s.result
        cols = _inner_columns(st)
        for r in range(len(s.case.bearing.rows)):
            balls = np.flatnonzero(np.asarray(st.row_of_ball) == r)
            q = st.ball_loads[np.ix_(balls, cols)] if cols else np.zeros((balls.size, 1))
            rows.append([s.case.label(), _row_label(s.case.bearing, r), fmt_number(st.row_radial_loads[r] / 1e3, 4),
                         fmt_number(st.row_axial_loads[r] / 1e3, 4), fmt_number(q.max() / 1e3, 4),
                         f"{int((q.max(axis=1) > 0).sum())} of {balls.size}"])
    blocks.append(Para("Each row's share of the load at those points (its force on the inner ring):"))
    blocks.append(Table(["case (steady loads)", "row", "radial load [kN]", "axial load [kN]",
                         "largest inner contact load [kN]", "loaded balls"], rows))
    return blocks, [p]
