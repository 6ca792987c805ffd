"""The sweep report: metrics, fits, figures and the comparison with the study.

:func:`build_report` reads a sweep folder (``sweep.nc`` or, for a sweep killed before
combining, its ``cases/*.nc``; ``status.json``), writes ``metrics.nc`` and ``fits.nc``
beside them and ``report/report.md``, ``report/report.html`` and ``report/figures/*.png``.

The report is built as a list of simple blocks (headings, paragraphs, tables, images)
rendered both to Markdown and to HTML here, without a Markdown library. It holds no
timestamps and the PNGs carry no software or time metadata, so the same sweep gives
byte-identical report files.

Every number in the prose is computed from the data, the sweep's configuration or the
reference-fit file; nothing is typed in.

Each figure and table says which displacement it shows: δ_r / δ_a at the ring centre, or
the reading of a virtual sensor (``sensor`` dimension) at a point of the ring along a
direction. With an ensemble (``realization`` dimension) the metrics are plotted as the
ensemble mean with ±1 standard-error bars over the faint individual realizations, and the
time histories show the first realization. Ranges whose extreme lies at the edge of the
phase window (``*_range_at_edge``) are drawn hollow and listed in their own section.
"""
from __future__ import annotations

import html
import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from rvcore.profile import PHASES

from ..errors import ConfigError
from ..io import read_status
from ..analysis import (DISPLACEMENT_COORD, fit_metrics, fit_statistic, line_band, load_reference_fits,
                   udunits_to_pint, write_fits)
from ..analysis import (REALIZATION, case_states, load_sweep, nearest, phase_metrics,
                      write_metrics)
from ..schema import parse_quantity, registry

#: The virtual-sensor dimension of sweep.nc and metrics.nc.
SENSOR = "sensor"

#: Keyword arguments of every ``savefig``: no software, no timestamps in the PNG.
PNG_KWARGS = {"dpi": 100, "format": "png", "metadata": {"Software": None}}

_PHASE_TITLE = {"startup": "start-up", "steady": "steady", "deceleration": "deceleration"}
_METRIC_TITLE = {"range": "variation range", "mean": "mean", "std": "standard deviation"}
_AXIS_TITLE = {"speed": "speed", "radial_load": "radial load"}
_CENTRE = {"radial": "δ_r at the ring centre", "axial": "δ_a at the ring centre"}
#: Largest number of grid points listed by name in the window-edge table.
_MAX_LISTED = 8


# --------------------------------------------------------------------------- blocks


@dataclass
class Heading:
    level: int
    text: str


@dataclass
class Para:
    text: str


@dataclass
class Warning_:
    text: str


@dataclass
class Bullets:
    items: list


@dataclass
class Table:
    header: list
    rows: list


@dataclass
class Image:
    path: str  # relative to the report folder
    alt: str


def _md_cell(text) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def render_markdown(blocks) -> str:
    """Blocks to Markdown text."""
    out = []
    for b in blocks:
        if isinstance(b, Heading):
            out.append("#" * b.level + " " + b.text)
        elif isinstance(b, Para):
            out.append(b.text.strip())
        elif isinstance(b, Warning_):
            out.append("\n".join("> " + line for line in b.text.splitlines()))
        elif isinstance(b, Bullets):
            out.append("\n".join(f"- {item}" for item in b.items))
        elif isinstance(b, Table):
            lines = ["| " + " | ".join(_md_cell(h) for h in b.header) + " |",
                     "|" + "|".join("---" for _ in b.header) + "|"]
            lines += ["| " + " | ".join(_md_cell(c) for c in row) + " |" for row in b.rows]
            out.append("\n".join(lines))
        elif isinstance(b, Image):
            out.append(f"![{b.alt}]({b.path})")
    return "\n\n".join(out) + "\n"


def _inline_html(text: str) -> str:
    s = html.escape(str(text), quote=False)
    s = re.sub(r"\*\*(.+?)\*\*", r"<strong>\1</strong>", s)
    s = re.sub(r"`(.+?)`", r"<code>\1</code>", s)
    return s


_CSS = """body{font-family:sans-serif;max-width:72em;margin:2em auto;padding:0 1em;line-height:1.45}
table{border-collapse:collapse;margin:1em 0;font-size:90%}th,td{border:1px solid #bbb;padding:.25em .5em;text-align:left}
th{background:#eee}.caveat{border-left:.4em solid #c00;background:#fee;padding:.5em 1em}img{max-width:100%}
code{background:#f4f4f4}"""


def render_html(blocks, title: str) -> str:
    """Blocks to a standalone HTML page."""
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           f"<title>{html.escape(title)}</title>", f"<style>{_CSS}</style>", "</head>", "<body>"]
    for b in blocks:
        if isinstance(b, Heading):
            out.append(f"<h{b.level}>{_inline_html(b.text)}</h{b.level}>")
        elif isinstance(b, Para):
            out.append(f"<p>{_inline_html(b.text.strip())}</p>")
        elif isinstance(b, Warning_):
            out.append('<div class="caveat">' + "".join(f"<p>{_inline_html(line)}</p>" for line in b.text.splitlines()) + "</div>")
        elif isinstance(b, Bullets):
            out.append("<ul>" + "".join(f"<li>{_inline_html(i)}</li>" for i in b.items) + "</ul>")
        elif isinstance(b, Table):
            rows = ["<tr>" + "".join(f"<th>{_inline_html(h)}</th>" for h in b.header) + "</tr>"]
            rows += ["<tr>" + "".join(f"<td>{_inline_html(c)}</td>" for c in r) + "</tr>" for r in b.rows]
            out.append("<table>" + "".join(rows) + "</table>")
        elif isinstance(b, Image):
            out.append(f'<p><img src="{html.escape(b.path)}" alt="{html.escape(b.alt)}"></p>')
    out += ["</body>", "</html>"]
    return "\n".join(out) + "\n"


# --------------------------------------------------------------------------- formatting


def _g(x, digits: int = 3) -> str:
    """A number with ``digits`` significant digits; 'n/a' for NaN/None."""
    if x is None:
        return "n/a"
    x = float(x)
    if not math.isfinite(x):
        return "n/a"
    return f"{x:.{digits}g}"


def _e(x, digits: int = 3) -> str:
    """Scientific notation with ``digits`` significant digits."""
    if x is None or not math.isfinite(float(x)):
        return "n/a"
    return f"{float(x):.{digits - 1}e}"


def _kn(newton: float) -> str:
    return f"{_g(newton / 1e3, 4)} kN"


def _dps(deg_s: float) -> str:
    return f"{_g(deg_s, 4)} °/s"


# --------------------------------------------------------------------------- configuration


def _flatten(obj, prefix: str = ""):
    """Nested TOML data to ``[(dotted.path[i], value)]`` in document order."""
    out = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            out += _flatten(v, f"{prefix}.{k}" if prefix else str(k))
    elif isinstance(obj, list) and obj and all(isinstance(v, dict) for v in obj):
        for i, v in enumerate(obj):
            out += _flatten(v, f"{prefix}[{i}]")
    else:
        out.append((prefix, obj))
    return out


def _norm(path: str) -> str:
    return re.sub(r"\[\d+\]", "", path)


def _lookup(flat, suffixes, exclude=()):
    """First ``(path, value)`` whose index-free path is or ends with one of ``suffixes``."""
    for suf in suffixes:
        for path, value in flat:
            n = _norm(path)
            if (n == suf or n.endswith("." + suf)) and not any(e in n for e in exclude):
                return path, value
    return None


def _find_table(doc, name: str, prefer: str = "profile"):
    """The first value stored under key ``name`` (depth first), preferring under ``prefer``."""
    def walk(obj, under):
        if isinstance(obj, dict):
            for k, v in obj.items():
                if k == name and isinstance(v, (dict, list)) and (under or prefer is None):
                    return v
            for k, v in obj.items():
                r = walk(v, under or k == prefer)
                if r is not None:
                    return r
        elif isinstance(obj, list):
            for v in obj:
                r = walk(v, under)
                if r is not None:
                    return r
        return None

    found = walk(doc, False)
    if found is None and prefer is not None:
        found = walk(doc, True)
    return found


@dataclass
class Context:
    """Everything the report is built from."""

    directory: Path
    sweep: xr.Dataset
    metrics: xr.Dataset
    fits: xr.Dataset
    status: dict
    references: list
    reference_path: Path
    config: dict = field(default_factory=dict)
    config_error: str = ""
    notes: list = field(default_factory=list)
    #: Line fits of the sensor metrics (made for the figures; not written to fits.nc).
    sensor_fits: xr.Dataset = field(default_factory=xr.Dataset)


def _parse_config(text: str):
    if not text:
        return {}, "the sweep carries no configuration"
    try:
        return tomllib.loads(text), ""
    except tomllib.TOMLDecodeError as exc:
        return {}, f"the configuration attribute is not valid TOML ({exc})"


def phase_windows(ctx: Context):
    """Phase windows ``{name: (start, end)}`` [s] and where they came from.

    From the sweep's ``phase_start``/``phase_end`` when it holds them (the windows the
    core accumulated the phase metrics over); otherwise from the configuration's profile
    ``phases`` table when it has one (either ``name = [start, end]``, ``name = {start =
    .., end = ..}`` or a list of ``{name, start, end}`` tables); otherwise from where
    ``inner_ring_speed`` ramps in the case with the highest speed.
    """
    windows, note = _windows_from_data(ctx)
    if len(windows) == len(PHASES):
        return windows, "the sweep's `phase_start`/`phase_end`" + note
    table = _find_table(ctx.config, "phases")
    windows = {}
    try:
        if isinstance(table, dict):
            items = table.items()
        elif isinstance(table, list):
            items = [(t.get("name"), t) if isinstance(t, dict) else (t[0], list(t[1:]))
                     for t in table if isinstance(t, dict) or (isinstance(t, list) and len(t) == 3)]
        else:
            items = []
        for name, spec in items:
            if name not in PHASES:
                continue
            if isinstance(spec, dict):
                a, b = spec.get("start", spec.get("from")), spec.get("end", spec.get("to"))
            elif isinstance(spec, list) and len(spec) == 2:
                a, b = spec
            else:
                continue
            windows[name] = (parse_quantity(a, "time", key=f"phases.{name}"),
                             parse_quantity(b, "time", key=f"phases.{name}"))
    except ConfigError:
        windows = {}
    if len(windows) == len(PHASES):
        return windows, "the profile's phase table"
    return _windows_from_speed(ctx), "where the inner-ring speed ramps (no phase table in the configuration)"


def _windows_from_data(ctx: Context):
    """Windows ``{name: (start, end)}`` [s] from ``phase_start``/``phase_end`` and a note.

    The first finished case's windows; the note says so when other cases differ.
    """
    for ds in (ctx.metrics, ctx.sweep):
        if "phase_start" not in ds or "phase_end" not in ds:
            continue
        windows, differ = {}, False
        for k, name in enumerate(PHASES):
            a = ds["phase_start"].sel(phase=ds["phase"].values[k]).values.ravel()
            b = ds["phase_end"].sel(phase=ds["phase"].values[k]).values.ravel()
            ok = np.isfinite(a) & np.isfinite(b)
            if not ok.any():
                break
            windows[name] = (float(a[ok][0]), float(b[ok][0]))
            differ |= bool(np.ptp(a[ok]) > 1e-9 or np.ptp(b[ok]) > 1e-9)
        if len(windows) == len(PHASES):
            return windows, (" (they differ between cases; those of the first finished case are shown)"
                             if differ else "")
    return {}, ""


def _windows_from_speed(ctx: Context):
    sw = _base(ctx.sweep)
    if "inner_ring_speed" not in sw:
        return {}
    w_all = sw["inner_ring_speed"].transpose("speed", "radial_load", "elapsed_time").values
    t = sw["elapsed_time"].values
    best, wbest = None, -np.inf
    for i in range(w_all.shape[0]):
        for j in range(w_all.shape[1]):
            w = w_all[i, j]
            if np.all(~np.isfinite(w)):
                continue
            m = np.nanmax(np.abs(w))
            if m > wbest:
                best, wbest = np.abs(w), m
    if best is None or wbest <= 0:
        return {}
    w = np.nan_to_num(best)
    moving = np.flatnonzero(w > 1e-3 * wbest)
    top = np.flatnonzero(w >= (1 - 1e-3) * wbest)
    i0 = max(moving[0] - 1, 0)
    i3 = min(moving[-1] + 1, len(t) - 1)
    return {"startup": (float(t[i0]), float(t[top[0]])),
            "steady": (float(t[top[0]]), float(t[top[-1]])),
            "deceleration": (float(t[top[-1]]), float(t[i3]))}


def _extra_dims(ds) -> list:
    """Extra sweep dimensions of ``ds``: all but the grid axes, phase, time, the packed
    displacement metrics, the ensemble (``realization``) and the sensors."""
    return [d for d in ds.dims if d not in ("speed", "radial_load", "phase", "elapsed_time", DISPLACEMENT_COORD,
                                            REALIZATION, SENSOR)]


def _base(ds, first_realization: bool = True):
    """``ds`` at the first value of every extra sweep dimension.

    Parameters
    ----------
    ds : xarray.Dataset or xarray.DataArray
    first_realization : bool
        Also take the first realization (for time series); False keeps the ``realization``
        dimension (for ensemble statistics). The ``sensor`` dimension is always kept.
    """
    sel = {d: 0 for d in _extra_dims(ds)}
    if first_realization and REALIZATION in ds.dims:
        sel[REALIZATION] = 0
    return ds.isel(sel) if sel else ds


# --------------------------------------------------------------------------- ensembles and sensors


def realizations(ds):
    """Seeds of the ``realization`` dimension (float array), or None without one."""
    if REALIZATION not in ds.dims:
        return None
    if REALIZATION in ds.coords:
        return np.asarray(ds[REALIZATION].values, dtype=np.float64)
    return np.arange(ds.sizes[REALIZATION], dtype=np.float64)


def _ensemble_text(ctx: Context) -> str:
    """'N = 2 realizations (seeds 0, 1)'; '' without an ensemble."""
    seeds = realizations(ctx.metrics)
    if seeds is None:
        return ""
    shown = ", ".join(_g(v, 6) for v in seeds[:8]) + (", …" if seeds.size > 8 else "")
    return f"N = {seeds.size} realization{'s' if seeds.size != 1 else ''} (seed{'s' if seeds.size != 1 else ''} {shown})"


def _first_realization_text(ctx: Context) -> str:
    """'the first realization (seed 0) of N = 2'; '' without an ensemble."""
    seeds = realizations(ctx.sweep)
    if seeds is None:
        return ""
    return f"the first realization (seed {_g(seeds[0], 6)}) of N = {seeds.size}"


def ensemble_statistics(da: xr.DataArray):
    """Mean and standard error of the mean over ``realization``, NaN-safe and silent.

    Parameters
    ----------
    da : xarray.DataArray
        With a ``realization`` dimension [any unit].

    Returns
    -------
    mean, stderr : xarray.DataArray
        ``mean = Σ x_k / n`` and ``stderr = s/√n`` with ``s`` the sample standard deviation
        (ddof 1) of the n finite realizations [unit of ``da``]; NaN where n = 0 (mean) or
        n < 2 (stderr), as ``pipeline.metrics.ensemble_statistics``.
    """
    n = da.notnull().sum(REALIZATION)
    mean = da.sum(REALIZATION, skipna=True) / n.where(n > 0)
    var = ((da - mean) ** 2).sum(REALIZATION, skipna=True) / (n - 1).where(n >= 2)
    return mean, np.sqrt(var / n.where(n >= 2))


def _ensemble_of(m: xr.Dataset, name: str, sel: dict):
    """Ensemble mean and standard error of metric ``name`` at ``sel``.

    ``metrics.nc``'s ``<name>_ensemble_mean``/``_ensemble_stderr`` where it has them,
    otherwise :func:`ensemble_statistics` of the realizations.
    """
    mean_name, se_name = f"{name}_ensemble_mean", f"{name}_ensemble_stderr"
    if mean_name in m and se_name in m:
        return m[mean_name].sel(sel), m[se_name].sel(sel)
    return ensemble_statistics(m[name].sel(sel))


def _edge_flag(m: xr.Dataset, name: str, sel: dict):
    """``<x>_range_at_edge`` at ``sel`` for a range metric ``<x>_range``, else None."""
    if not name.endswith("_range"):
        return None
    flag = name.removesuffix("_range") + "_range_at_edge"
    return m[flag].sel(sel) if flag in m else None


@dataclass(frozen=True)
class SensorInfo:
    """One virtual displacement sensor of the sweep.

    Parameters
    ----------
    value : int
        Its flag value on the ``sensor`` coordinate.
    name : str
        Its name (from the coordinate's ``flag_meanings``).
    position : tuple of float
        The ring point it reads, bearing frame [m].
    direction : tuple of float
        Its unit measuring direction [1].
    """

    value: int
    name: str
    position: tuple
    direction: tuple

    def where(self) -> str:
        """'at (x, y, z) mm along (dx, dy, dz)'."""
        pos = ", ".join(_g(v * 1e3 + 0.0, 5) for v in self.position)
        d = ", ".join(_g(v + 0.0, 3) for v in self.direction)
        return f"at ({pos}) mm along ({d})"

    def label(self, code: bool = True) -> str:
        """'sensor `name` at (x, y, z) mm along (dx, dy, dz)' (name in backticks with ``code``)."""
        name = f"`{self.name}`" if code else self.name
        return f"sensor {name} {self.where()}"


def sensors(ds) -> list:
    """The sensors of ``ds``'s ``sensor`` dimension as :class:`SensorInfo`, [] without one."""
    if SENSOR not in ds.dims:
        return []
    c = ds[SENSOR]
    values = [int(v) for v in np.asarray(c.values).ravel()]
    meanings = str(c.attrs.get("flag_meanings", "")).split()
    flags = [int(v) for v in np.atleast_1d(c.attrs.get("flag_values", values))]
    out = []
    for k, v in enumerate(values):
        name = meanings[flags.index(v)] if v in flags and flags.index(v) < len(meanings) else f"{SENSOR}_{v}"

        def vec(prefix):
            return tuple(float(ds[f"{prefix}_{a}"].values[k]) if f"{prefix}_{a}" in ds.coords else math.nan
                         for a in "xyz")

        out.append(SensorInfo(v, name, vec("sensor_position"), vec("sensor_direction")))
    return out


def _bearing_numbers(ctx: Context) -> dict:
    """Ball diameter, ball density, ball mass and pitch diameter [SI], with their sources."""
    flat = _flatten(ctx.config)
    out = {}
    attrs = ctx.sweep.attrs

    def q(hit, kind):
        try:
            return parse_quantity(hit[1], kind, key=hit[0])
        except ConfigError:
            return math.nan

    hit = _lookup(flat, ("balls.diameter", "ball_diameter", "ball.diameter"))
    out["D"] = (q(hit, "length"), hit[0]) if hit else (math.nan, "")
    hit = _lookup(flat, ("ball_material.density", "materials.ball.density", "balls.material.density",
                         "ball.material.density", "balls.density", "materials.balls.density"))
    if hit is None:
        hit = _lookup(flat, ("material.density", "materials.density", "density"), exclude=("cage",))
    out["rho"] = (q(hit, "density"), hit[0]) if hit else (math.nan, "")
    if "solver_ball_mass" in attrs:
        out["m_b"] = (float(attrs["solver_ball_mass"]), "the solver's ball mass")
    else:
        out["m_b"] = (out["rho"][0] * math.pi * out["D"][0] ** 3 / 6.0, "ρ·π·D³/6")
    if "solver_pitch_diameter" in attrs:
        out["d_m"] = (float(attrs["solver_pitch_diameter"]), "the solver's pitch diameter")
    else:
        hit = _lookup(flat, ("pitch_diameter",))
        if hit:
            out["d_m"] = (q(hit, "length"), hit[0])
        else:
            bore = _lookup(flat, ("envelope.bore", "bore", "envelope.inner_diameter"), exclude=("cage",))
            od = _lookup(flat, ("envelope.outer_diameter",))
            if bore and od:
                out["d_m"] = ((q(bore, "length") + q(od, "length")) / 2.0,
                              f"({bore[0]} + {od[0]})/2")
            else:
                out["d_m"] = (math.nan, "")
    hit = _lookup(flat, ("outer_arcs.contact_angle", "outer_groove.arcs.contact_angle", "contact_angle"))
    out["alpha"] = (q(hit, "angle"), hit[0]) if hit else (math.nan, "")
    return out


# --------------------------------------------------------------------------- selection


def _ok_cases(ctx: Context, realization=None):
    """Grid points ``[(speed, load)]`` that finished.

    Parameters
    ----------
    realization : int, optional
        With an ensemble: the points whose realization of this index finished; default
        those where any realization finished.
    """
    ok = _base_states(ctx) == "ok"
    if REALIZATION in ok.dims:
        ok = ok.isel({REALIZATION: realization}) if realization is not None else ok.any(REALIZATION)
    pts = []
    for s in ok["speed"].values:
        for l in ok["radial_load"].values:
            if bool(ok.sel(speed=s, radial_load=l).item()):
                pts.append((float(s), float(l)))
    return pts


def _base_states(ctx: Context):
    """Case states over ``(speed, radial_load[, realization])`` at the first value of any other axis."""
    st = case_states(ctx.sweep)
    extra = [d for d in st.dims if d not in ("speed", "radial_load", REALIZATION)]
    st = st.isel({d: 0 for d in extra}) if extra else st
    return st.transpose("speed", "radial_load", *[d for d in st.dims if d == REALIZATION])


def _extreme_cases(ctx: Context, realization=None):
    """The finished grid points nearest to the four corners of the grid (see :func:`_ok_cases`)."""
    pts = _ok_cases(ctx, realization)
    if not pts:
        return []
    s = np.array([p[0] for p in pts])
    l = np.array([p[1] for p in pts])
    srange = max(np.ptp(s), 1e-12)
    lrange = max(np.ptp(l), 1e-12)
    out = []
    for cs in (s.min(), s.max()):
        for cl in (l.min(), l.max()):
            d = ((s - cs) / srange) ** 2 + ((l - cl) / lrange) ** 2
            k = int(np.argmin(d))
            if pts[k] not in out:
                out.append(pts[k])
    return out


def _metric_stat(ctx: Context, name: str, speed: float, load: float, phase: str, sensor=None):
    """A phase metric at one grid point and its standard error [its units].

    With realizations, the ensemble mean and its standard error; otherwise the value and
    NaN. ``sensor`` is the sensor flag of a sensor metric (default the first). NaN, NaN
    when the metric is absent.
    """
    m = _base(ctx.metrics, first_realization=False)
    if name not in m:
        return math.nan, math.nan
    sel = {"speed": speed, "radial_load": load, "phase": PHASES.index(phase)}
    if SENSOR in m[name].dims:
        sel[SENSOR] = sensor if sensor is not None else m[SENSOR].values[0]
    if REALIZATION in m[name].dims:
        mean, se = _ensemble_of(m, name, sel)
        return float(mean.item()), float(se.item())
    return float(m[name].sel(sel).item()), math.nan


def _metric_value(ctx: Context, name: str, speed: float, load: float, phase: str, sensor=None) -> float:
    """A phase metric at one grid point [its units]: the ensemble mean when there are
    realizations; at sensor flag ``sensor`` (default the first) for a sensor metric."""
    return _metric_stat(ctx, name, speed, load, phase, sensor)[0]


def _axis_specs(ctx: Context, phase: str | None = None) -> list:
    """``[(axis, fixed_axis, fixed, note)]``: the axes the study's fits of ``phase`` (any phase
    when it has none) are drawn against, at the grid value nearest to the study's fixed one."""
    refs = [r for r in ctx.references if r.phase == phase] or list(ctx.references)
    out, seen = [], set()
    for r in refs:
        if r.axis in seen:
            continue
        seen.add(r.axis)
        fixed, note = _fixed_choice(ctx, r.fixed_axis, r.fixed_coordinate)
        out.append((r.axis, r.fixed_axis, fixed, note))
    if not out:
        for axis, other in (("speed", "radial_load"), ("radial_load", "speed")):
            fixed = float(ctx.metrics[other].values[0])
            out.append((axis, other, fixed, f"at {_dps(fixed) if other == 'speed' else _kn(fixed)}"))
    return out


def _pm(mean: float, se: float, scale: float = 1.0, digits: int = 3) -> str:
    """'mean ± se' (or the mean alone when se is NaN) after multiplying by ``scale``."""
    if math.isfinite(se):
        return f"{_g(mean * scale, digits)} ± {_g(se * scale, 2)}"
    return _g(mean * scale, digits)


def _fit_at(ctx: Context, variable: str, axis: str, fixed_axis: str, fixed: float, phase: str,
            sensor=None) -> dict:
    """Statistics of our line fit of ``variable`` along ``axis`` at ``fixed`` (SI / coordinate
    units); a sensor metric's from :attr:`Context.sensor_fits` at sensor flag ``sensor``."""
    f = _base(ctx.sensor_fits if variable.startswith(f"{SENSOR}_") else ctx.fits)
    out = {}
    for stat in ("slope", "intercept", "slope_stderr", "intercept_stderr", "slope_intercept_covariance",
                 "slope_ci95_lower", "slope_ci95_upper", "rsquared", "n"):
        try:
            da = fit_statistic(f, variable, axis, stat)
        except KeyError:
            return {}
        sel = {fixed_axis: fixed, "phase": PHASES.index(phase)}
        if SENSOR in da.dims:
            sel[SENSOR] = sensor if sensor is not None else da[SENSOR].values[0]
        out[stat] = float(da.sel(sel).item())
    return out


def _fixed_choice(ctx: Context, fixed_axis: str, wanted: float):
    """Nearest available value of ``fixed_axis`` to ``wanted`` [coordinate units] and a note."""
    values = ctx.metrics[fixed_axis].values
    got = nearest(values, wanted)
    fmt = _dps if fixed_axis == "speed" else _kn
    if math.isclose(got, wanted, rel_tol=1e-6, abs_tol=1e-9):
        return got, f"at {fmt(got)}"
    return got, f"at {fmt(got)} (nearest available to the study's {fmt(wanted)})"


# --------------------------------------------------------------------------- figures


def _new_figure(nrows: int, ncols: int, size):
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def _save(fig, path: Path):
    fig.savefig(path, **PNG_KWARGS)


def _shade(ax, windows):
    colours = {"startup": "#4c72b0", "steady": "#55a868", "deceleration": "#c44e52"}
    for name, (a, b) in windows.items():
        ax.axvspan(a, b, color=colours.get(name, "#999999"), alpha=0.12, lw=0,
                   label=f"{_PHASE_TITLE.get(name, name)} window")


def _legend_outside(fig, ax) -> None:
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="outside right upper")


def figure_time_histories(ctx: Context, windows, path: Path, cases) -> None:
    """δ_r and δ_a at the ring centre of ``cases`` [(speed °/s, load N)] against time, in µm.

    The first realization of an ensemble; the phase ``windows`` [s] shaded.
    """
    sw = _base(ctx.sweep)
    fig, axes = _new_figure(2, 1, (10.0, 6.0))
    t = sw["elapsed_time"].values
    for k, (name, label) in enumerate((("radial_displacement", "δ_r at the ring centre [µm]"),
                                       ("axial_displacement", "δ_a at the ring centre [µm]"))):
        ax = axes[k, 0]
        _shade(ax, windows)
        if name in sw:
            for (s, l) in cases:
                y = sw[name].sel(speed=s, radial_load=l).values * 1e6
                ax.plot(t, y, lw=1.0, label=f"{_dps(s)}, {_kn(l)}")
        ax.set_ylabel(label)
        ax.grid(True, lw=0.3)
    axes[1, 0].set_xlabel("elapsed time [s]")
    _legend_outside(fig, axes[0, 0])
    first = _first_realization_text(ctx)
    axes[0, 0].set_title("Inner-ring displacements at the ring centre of the extreme cases, phase windows shaded"
                         + (f"\n{first}" if first else ""), fontsize=10)
    _save(fig, path)


def figure_sensor_time_histories(ctx: Context, windows, path: Path, cases) -> None:
    """The virtual sensors' readings of ``cases`` against time, one panel per sensor, in µm.

    The first realization of an ensemble; the phase ``windows`` [s] shaded.
    """
    sw = _base(ctx.sweep)
    sens = sensors(ctx.sweep)
    fig, axes = _new_figure(len(sens), 1, (10.0, 1.0 + 2.5 * len(sens)))
    t = sw["elapsed_time"].values
    for k, sn in enumerate(sens):
        ax = axes[k, 0]
        _shade(ax, windows)
        for (s, l) in cases:
            y = sw["sensor_displacement"].sel({"speed": s, "radial_load": l, SENSOR: sn.value}).values * 1e6
            ax.plot(t, y, lw=1.0, label=f"{_dps(s)}, {_kn(l)}")
        ax.set_title(sn.label(code=False), fontsize=8)
        ax.set_ylabel(f"{sn.name} [µm]")
        ax.grid(True, lw=0.3)
    axes[-1, 0].set_xlabel("elapsed time [s]")
    _legend_outside(fig, axes[0, 0])
    first = _first_realization_text(ctx)
    fig.suptitle("Virtual sensor readings of the extreme cases, phase windows shaded"
                 + (f"\n{first}" if first else ""), fontsize=10)
    _save(fig, path)


def _metric_panel(ax, ctx: Context, name: str, axis: str, fixed_axis: str, fixed: float, phase: str, *,
                  sensor=None, scale: float = 1e6, colour: str = "k", marker: str = "o",
                  label: str = "cases", realization_label: str | None = "individual realizations",
                  dodge: float = 0.0) -> int:
    """Plot one phase metric against ``axis`` at ``fixed`` on ``ax``; return the hollow markers drawn.

    Without an ensemble: one marker per case. With one: the ensemble mean with ±1
    standard-error bars and each realization as a faint small marker, drawn 2.5 % of the
    axis span to the left of its mean so that the bars do not hide it. A range whose
    ``_range_at_edge`` flag is set is drawn hollow (a mean marker when any of its
    realizations is). Values are multiplied by ``scale`` (1e6: m to µm; 100: 1 to %);
    ``axis`` values in °/s or kN, shifted by ``dodge`` times the axis span (to set two
    series side by side).
    """
    m = _base(ctx.metrics, first_realization=False)
    if name not in m:
        return 0
    sel = {fixed_axis: fixed, "phase": PHASES.index(phase)}
    if sensor is not None:
        sel[SENSOR] = sensor
    da = m[name].sel(sel)
    if not bool(da.notnull().any()):
        ax.text(0.5, 0.5, "no data in this phase's window", transform=ax.transAxes, ha="center",
                va="center", fontsize=8, color="0.4")
        return 0
    flag = _edge_flag(m, name, sel)
    x = m[axis].values.astype(float)
    xs = x / 1e3 if axis == "radial_load" else x
    span = float(np.ptp(xs)) if xs.size > 1 and np.ptp(xs) > 0 else max(abs(float(xs[0])), 1.0)
    xs = xs + dodge * span
    def points(xv, yv, hollow, **kw):
        if not xv.size:
            return
        style = dict(ls="none", marker=marker, color=colour, **kw)
        if hollow:
            style.update(mfc="none", mec=colour)
        ax.plot(xv, yv, **style)

    if REALIZATION in da.dims:
        vals = da.transpose(axis, REALIZATION).values * scale
        fl = (flag.transpose(axis, REALIZATION).values == 1) if flag is not None else np.zeros(vals.shape, bool)
        xr_ = xs - 0.025 * span
        for k in range(vals.shape[1]):
            points(xr_[~fl[:, k]], vals[~fl[:, k], k], False, ms=2.5, alpha=0.35)
            points(xr_[fl[:, k]], vals[fl[:, k], k], True, ms=2.5, alpha=0.5)
        mean, se = _ensemble_of(m, name, sel)
        mean = mean.transpose(axis).values * scale
        se = se.transpose(axis).values * scale
        any_fl = fl.any(axis=1)
        ax.errorbar(xs, mean, yerr=se, fmt="none", ecolor=colour, elinewidth=1.0, capsize=3)
        points(xs[~any_fl], mean[~any_fl], False, ms=5)
        points(xs[any_fl], mean[any_fl], True, ms=5, mew=1.2)
        ax.plot([], [], ls="none", marker=marker, color=colour, ms=5, label=label)   # legend keys, filled
        if realization_label:
            ax.plot([], [], ls="none", marker=marker, ms=2.5, color=colour, alpha=0.35, label=realization_label)
        return int(fl.sum())
    y = da.transpose(axis).values * scale
    fl = (flag.transpose(axis).values == 1) if flag is not None else np.zeros(y.shape, bool)
    points(xs[~fl], y[~fl], False, ms=4)
    points(xs[fl], y[fl], True, ms=4, mew=1.2)
    ax.plot([], [], ls="none", marker=marker, color=colour, ms=4, label=label)   # legend key, filled
    return int(fl.sum())


def _fit_line(ax, ctx: Context, variable: str, axis: str, fixed_axis: str, fixed: float, phase: str,
              sensor=None) -> None:
    """Our fitted line of ``variable`` and its 95 % band on ``ax`` [µm against °/s or kN]."""
    fit = _fit_at(ctx, variable, axis, fixed_axis, fixed, phase, sensor)
    if fit and math.isfinite(fit["slope"]):
        x = ctx.metrics[axis].values.astype(float)
        grid = np.linspace(np.nanmin(x), np.nanmax(x), 50)
        yl, lo, hi = line_band(fit, grid)
        gs = grid / 1e3 if axis == "radial_load" else grid
        seeds = realizations(ctx.metrics)
        kind = "WLS" if seeds is not None and seeds.size >= 2 else "OLS"
        ax.plot(gs, yl * 1e6, "-", color="C0", lw=1.2, label=f"{kind} fit (R² = {_g(fit['rsquared'])})")
        ax.fill_between(gs, lo * 1e6, hi * 1e6, color="C0", alpha=0.2, lw=0, label="95 % band")


def _finish_panel(ax, axis: str, ylabel: str, title: str, hollow: int) -> None:
    """Axis labels, title, grid and legend of a metric panel (and the hollow-marker key)."""
    if hollow:
        ax.plot([], [], ls="none", marker="o", mfc="none", mec="0.3", label="extreme at window edge")
    ax.set_xlabel("steady speed [°/s]" if axis == "speed" else "radial load [kN]")
    ax.set_ylabel(ylabel)
    ax.ticklabel_format(axis="y", useOffset=False)
    ax.set_title(title, fontsize=8)
    ax.grid(True, lw=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)


def _ensemble_label(ctx: Context) -> str:
    return "ensemble mean ± 1 SE" if realizations(ctx.metrics) is not None else "cases"


def figure_metric(ctx: Context, refs, path: Path):
    """One panel per reference axis of a (phase, displacement, metric) group, at the ring centre.

    Returns
    -------
    notes : list of str
        Where each panel's other axis is held ('against speed at 30 kN').
    hollow : int
        Markers drawn hollow (range with an extreme at the window's edge).
    """
    r0 = refs[0]
    fig, axes = _new_figure(1, len(refs), (4.6 * len(refs), 3.6))
    notes, hollow = [], 0
    sym = "δ_r" if r0.displacement == "radial" else "δ_a"
    for k, ref in enumerate(refs):
        ax = axes[0, k]
        fixed, note = _fixed_choice(ctx, ref.fixed_axis, ref.fixed_coordinate)
        notes.append(f"against {_AXIS_TITLE[ref.axis]} {note}")
        n = _metric_panel(ax, ctx, ref.variable, ref.axis, ref.fixed_axis, fixed, ref.phase,
                          label=_ensemble_label(ctx))
        hollow += n
        _fit_line(ax, ctx, ref.variable, ref.axis, ref.fixed_axis, fixed, ref.phase)
        _finish_panel(ax, ref.axis, f"{_PHASE_TITLE[r0.phase]} {r0.metric} of {sym} [µm]", note, n)
    fig.suptitle(f"{_PHASE_TITLE[r0.phase]}: {r0.displacement} displacement {_METRIC_TITLE[r0.metric]}, "
                 f"{_CENTRE[r0.displacement]}", fontsize=10)
    _save(fig, path)
    return notes, hollow


def figure_sensor_metric(ctx: Context, phase: str, metric: str, specs, path: Path):
    """Sensor metric ``sensor_displacement_<metric>`` of ``phase``: a row per sensor, a column
    per ``(axis, fixed_axis, fixed)`` of ``specs``; fit lines from :attr:`Context.sensor_fits`.

    Returns
    -------
    notes : list of str
    hollow : int
    """
    name = f"{SENSOR}_displacement_{metric}"
    sens = sensors(ctx.metrics)
    fig, axes = _new_figure(len(sens), len(specs), (4.6 * len(specs), 0.6 + 3.0 * len(sens)))
    notes, hollow = [], 0
    for j, (axis, fixed_axis, fixed, note) in enumerate(specs):
        notes.append(f"against {_AXIS_TITLE[axis]} {note}")
        for i, sn in enumerate(sens):
            ax = axes[i, j]
            n = _metric_panel(ax, ctx, name, axis, fixed_axis, fixed, phase, sensor=sn.value,
                              label=_ensemble_label(ctx))
            hollow += n
            _fit_line(ax, ctx, name, axis, fixed_axis, fixed, phase, sensor=sn.value)
            _finish_panel(ax, axis, f"{_PHASE_TITLE[phase]} {metric} of {sn.name} [µm]",
                          f"{sn.label(code=False)}\n{note}", n)
    fig.suptitle(f"{_PHASE_TITLE[phase]}: sensor reading {_METRIC_TITLE[metric]}", fontsize=10)
    _save(fig, path)
    return notes, hollow


#: Cage-slip variables and their labels: against the actual and the nominal contact angle.
CAGE_SLIPS = (("cage_slip", "actual contact angles"), ("cage_slip_nominal", "nominal contact angle"))


def figure_cage_slip(ctx: Context, phase: str, specs, path: Path) -> list:
    """Cage slip of ``phase`` [%] against each ``(axis, fixed_axis, fixed)`` of ``specs``, both
    definitions of :data:`CAGE_SLIPS` present; returns the notes."""
    fig, axes = _new_figure(1, len(specs), (4.6 * len(specs), 3.6))
    notes = []
    for j, (axis, fixed_axis, fixed, note) in enumerate(specs):
        ax = axes[0, j]
        notes.append(f"against {_AXIS_TITLE[axis]} {note}")
        for k, (name, what) in enumerate(CAGE_SLIPS):
            if name in ctx.metrics:
                _metric_panel(ax, ctx, name, axis, fixed_axis, fixed, phase, scale=100.0, colour=f"C{k}",
                              marker="os"[k], label=f"{name}: {what}", realization_label=None,
                              dodge=0.012 * (2 * k - 1))
        ax.axhline(0.0, color="0.5", lw=0.6)
        _finish_panel(ax, axis, f"{_PHASE_TITLE[phase]} cage slip [%]", note, 0)
    fig.suptitle(f"{_PHASE_TITLE[phase]}: cage slip 1 − ω̄_c/ω_epi", fontsize=10)
    _save(fig, path)
    return notes


# --------------------------------------------------------------------------- sections


def status_entries(status: dict) -> list:
    """Cases of a ``status.json`` as ``[(id, state, reason, axis values, units)]``.

    Reads the sweep's layout (``{"units": {...}, "cases": {id: {"point": {...}, "state",
    "reason", ...}}}``) and the flat one (``{id: {"state", "reason", <axis>: value}}``).
    """
    if isinstance(status.get("cases"), dict):
        units = status["units"] if isinstance(status.get("units"), dict) else {}
        items = status["cases"].items()
    else:
        units, items = {}, status.items()
    out = []
    for cid, e in sorted(items):
        if not isinstance(e, dict):
            continue
        if isinstance(e.get("point"), dict):
            values = dict(e["point"])
        else:
            values = {k: v for k, v in e.items()
                      if k not in ("state", "reason", "traceback", "seconds", "index")}
        out.append((str(cid), str(e.get("state", "")), str(e.get("reason", "") or ""), values, units))
    return out


def _status_lookup(ctx: Context):
    """``{(speed, load, seed): (state, reason, id)}`` from status.json, matched to the grid.

    ``seed`` is the entry's ``realization`` when the grid has that dimension and the
    entry names one of its seeds, otherwise None.
    """
    ureg = registry()
    speeds = ctx.metrics["speed"].values
    loads = ctx.metrics["radial_load"].values
    seeds = realizations(ctx.metrics)
    matched, unmatched = {}, []
    target = {"speed": "degree/s", "radial_load": "N"}

    def candidates(v, key, units):
        try:
            if isinstance(v, str):
                return [float(ureg.Quantity(v).to(target[key]).magnitude)]
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                if key in units:
                    return [float(ureg.Quantity(float(v), udunits_to_pint(units[key])).to(target[key]).magnitude)]
                # no units given: coordinate units, or SI (rad/s) for the speed
                return [float(v), math.degrees(v)] if key == "speed" else [float(v)]
        except Exception:  # pint raises several types for a bad unit
            return []
        return []

    def seed_of(values):
        r = values.get(REALIZATION)
        if seeds is None or isinstance(r, bool) or not isinstance(r, (int, float)):
            return None
        hit = [float(x) for x in seeds if math.isclose(x, float(r), rel_tol=0.0, abs_tol=1e-9)]
        return hit[0] if hit else None

    for cid, state, reason, values, units in status_entries(ctx.status):
        hit = None
        for s in candidates(values.get("speed"), "speed", units):
            for l in candidates(values.get("radial_load"), "radial_load", units):
                si = [x for x in speeds if math.isclose(x, s, rel_tol=1e-6)]
                li = [x for x in loads if math.isclose(x, l, rel_tol=1e-6)]
                if si and li:
                    hit = (float(si[0]), float(li[0]), seed_of(values))
                    break
            if hit:
                break
        if hit:
            matched.setdefault(hit, (state, reason, cid))
        else:
            unmatched.append((cid, state, reason, values))
    return matched, unmatched


def section_cases(ctx: Context):
    st = _base_states(ctx)
    seeds = realizations(ctx.metrics) if REALIZATION in st.dims else None
    total = st.size
    n_ok = int((st == "ok").sum())
    blocks = [Heading(2, "Cases")]
    speeds = ", ".join(_g(v, 4) for v in ctx.metrics["speed"].values)
    loads = ", ".join(_g(v / 1e3, 4) for v in ctx.metrics["radial_load"].values)
    if seeds is None:
        blocks.append(Para(f"Grid: speed {speeds} °/s × radial load {loads} kN: {total} cases, "
                           f"{n_ok} finished ok, {total - n_ok} failed or missing."))
    else:
        n_points = st.sizes["speed"] * st.sizes["radial_load"]
        blocks.append(Para(f"Grid: speed {speeds} °/s × radial load {loads} kN × {_ensemble_text(ctx)}: "
                           f"{n_points} grid points, {total} runs, {n_ok} finished ok, {total - n_ok} failed "
                           f"or missing. Each realization starts the balls at random places within their "
                           f"pocket play (the seed); the metrics are shown as ensemble means with their "
                           f"standard errors."))
    matched, unmatched = _status_lookup(ctx)
    rows = []
    for s in st["speed"].values:
        for l in st["radial_load"].values:
            for ri, r in enumerate(seeds if seeds is not None else [None]):
                at = st.sel(speed=s, radial_load=l)
                state = (at.isel({REALIZATION: ri}) if r is not None else at).item()
                if state == "ok":
                    continue
                key = (float(s), float(l), None if r is None else float(r))
                rec = matched.get(key) or matched.get(key[:2] + (None,))
                reason = rec[1] if rec and rec[1] else "no reason recorded"
                if rec and rec[0] == "failed" and state in ("not_run", "no_data"):
                    state = "failed"  # the grid only knows the case file is missing
                if state == "no_data":
                    state = "flagged ok but holds no data"
                cid = rec[2] if rec else "-"
                rows.append([_dps(s), _kn(l)] + ([f"seed {_g(r, 6)}"] if r is not None else [])
                            + [state, reason, cid,
                               "excluded: NaN in metrics.nc, skipped by every fit (n counts the points used)"])
    if rows:
        blocks.append(Para("**Missing or failed cases.** The report is built from the cases that "
                           "finished; these are missing:"))
        blocks.append(Table(["speed", "radial load"] + (["realization"] if seeds is not None else [])
                            + ["state", "reason", "case id", "handling"], rows))
    else:
        blocks.append(Para("Every case of the grid finished."))
    extra = [u for u in unmatched if u[1] != "ok"]
    if extra:
        blocks.append(Para("Entries of status.json that are not on this grid:"))
        blocks.append(Table(["case id", "state", "reason", "axis values"],
                            [[cid, state, reason, ", ".join(f"{k} = {v}" for k, v in values.items())]
                             for cid, state, reason, values in extra]))
    dims = _extra_dims(ctx.metrics)
    if dims:
        def first(d):
            if d not in ctx.metrics.coords:
                return "index 0"
            units = str(ctx.metrics[d].attrs.get("units", ""))
            return f"{_g(ctx.metrics[d].values[0], 4)} {units if units not in ('', '1') else ''}".strip()

        blocks.append(Para("Extra sweep dimensions: " + "; ".join(
            f"{d} ({ctx.metrics.sizes[d]} values); figures and the comparison use the first, {first(d)}"
            for d in dims) + "."))
    return blocks


def section_parameters(ctx: Context):
    attrs = ctx.sweep.attrs
    blocks = [Heading(2, "Bearing, profile and parameters")]
    items = [f"bearing: **{attrs.get('bearing', '') or 'not named'}**",
             f"profile: **{attrs.get('profile', '') or 'not named'}**"]
    if "axial_load" in ctx.metrics.coords:
        vals = np.atleast_1d(ctx.metrics["axial_load"].values)
        items.append("axial load: " + ", ".join(_kn(float(v)) for v in vals))
    grav = _gravity_text(ctx)
    if grav:
        items.append(grav)
    if realizations(ctx.metrics) is not None:
        items.append(f"ensemble: {_ensemble_text(ctx)} per grid point")
    sens = sensors(ctx.metrics)
    if sens:
        items.append(f"virtual displacement sensors: {len(sens)} (see below)")
    if attrs.get("configuration_hash"):
        items.append(f"configuration hash: `{attrs['configuration_hash']}`")
    if attrs.get("source"):
        items.append(f"source: {attrs['source']}")
    blocks.append(Bullets(items))
    assumptions = [a.strip() for a in str(attrs.get("assumptions", "")).split(",") if a.strip()]
    listed = ctx.config.get("bearing", {}).get("assumptions", []) if isinstance(ctx.config.get("bearing"), dict) else []
    for a in listed if isinstance(listed, list) else []:
        if isinstance(a, str) and a not in assumptions:
            assumptions.append(a)
    if assumptions:
        blocks.append(Para("**Assumed values** (the study does not give them; marked 'assumed' in the table below): "
                           + ", ".join(f"`{a}`" for a in assumptions) + "."))
    if ctx.config_error:
        blocks.append(Para(f"Configuration: {ctx.config_error}."))
        return blocks
    canon = [_canonical_key(a) for a in assumptions]

    def assumed(path):
        c = _canonical_key(path)
        return any(c == a or c.endswith("." + a) or c.startswith(a + ".") or ("." + a + ".") in c
                   or ("." + a + "[") in c or c.startswith(a + "[") for a in canon)

    rows = []
    for path, value in _flatten(ctx.config):
        last = _norm(path).rsplit(".", 1)[-1]
        if last in _CONFIG_HIDDEN:
            continue
        shown = _show(value)
        rows.append([f"`{path}`", str(shown), "**assumed**" if assumed(path) else ""])
    blocks.append(Para("The sweep's resolved configuration (numbers without a unit are SI: m, kg, s, N, rad):"))
    blocks.append(Table(["key", "value", "assumption"], rows))
    return blocks


def _gravity_text(ctx: Context) -> str:
    """'gravity: on, g = (0, −9.807, 0) m/s² in the bearing frame (along −y)' from the configuration."""
    solver = ctx.config.get("solver") if isinstance(ctx.config.get("solver"), dict) else {}
    bearing = ctx.config.get("bearing") if isinstance(ctx.config.get("bearing"), dict) else {}
    on, vec = solver.get("gravity"), bearing.get("gravity")
    if on is False:
        return "gravity: off (`solver.gravity = false`)"
    if not (isinstance(vec, list) and len(vec) == 3 and all(isinstance(v, (int, float)) for v in vec)):
        return "gravity: on" if on is True else ""
    g = np.asarray(vec, dtype=np.float64)
    norm = float(np.linalg.norm(g))
    along = ""
    if norm > 0:
        k = int(np.argmax(np.abs(g)))
        if abs(g[k]) >= (1 - 1e-9) * norm:
            axis = "vertical" if k == 2 else "horizontal"
            along = f" (along {'−' if g[k] < 0 else '+'}{'xyz'[k]}: the bearing axis {axis})"
    shown = ", ".join(_g(v + 0.0, 4) for v in g)
    return f"gravity: {'on' if on is not False else 'off'}, g = ({shown}) m/s² in the bearing frame{along}"


def section_sensors(ctx: Context):
    """The virtual sensors: name, the ring point each reads [mm] and its direction."""
    sens = sensors(ctx.metrics)
    if not sens:
        return []
    rows = [[f"`{sn.name}`", "(" + ", ".join(_g(v * 1e3 + 0.0, 5) for v in sn.position) + ")",
             "(" + ", ".join(_g(v + 0.0, 3) for v in sn.direction) + ")"] for sn in sens]
    return [Heading(2, "Displacement sensors"),
            Para("Virtual sensors fixed in space, each reading the displacement of one point of the inner "
                 "ring (position in the unloaded, centred ring, bearing frame, z along the axis) along its "
                 "measuring direction:"),
            Table(["sensor", "position [mm]", "direction"], rows),
            Para("The study measured the ring with laser displacement sensors aimed at the ring, so a sensor "
                 "reading, which includes the ring's tilt, is the closer comparison with its δ. δ_r and δ_a "
                 "in the figures and tables are at the ring centre unless a sensor is named; the comparison "
                 "with the study's fits uses δ_r and δ_a at the ring centre.")]


def _show(value) -> str:
    """A configuration value for the table: floats to 12 digits, long lists shortened."""
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return f"{value:.12g}"
    if isinstance(value, list):
        items = [_show(v) for v in value[:4]] if len(value) > 8 else [_show(v) for v in value]
        more = f", … ({len(value)} values)" if len(value) > 8 else ""
        return "[" + ", ".join(items) + more + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_show(v)}" for k, v in value.items()) + "}"
    return str(value)


#: Configuration leaves left out of the parameter table (shown elsewhere or bookkeeping).
_CONFIG_HIDDEN = {"case_ids", "assumptions", "warnings"}

#: Bearing-file key spellings and their resolved-configuration (dataclass) spellings.
_KEY_ALIASES = (
    (r"inner_groove\.arcs", "inner_arcs"), (r"outer_groove\.arcs", "outer_arcs"),
    (r"balls\.diameter", "ball_diameter"), (r"balls\.count", "ball_count"),
    (r"cage\.(density|youngs_modulus|poisson_ratio)", r"cage.material.\1"),
    (r"^envelope\.", ""), (r"^friction\.", "contact."),
)


def _canonical_key(key: str) -> str:
    """A dotted key in the resolved-configuration spelling, without a ``bearing.`` prefix."""
    k = key.removeprefix("bearing.")
    for pattern, repl in _KEY_ALIASES:
        k = re.sub(pattern, repl, k)
    return k


def _last_time(ctx: Context) -> float:
    """The last output time of the sweep [s] (NaN without one)."""
    t = np.asarray(ctx.sweep["elapsed_time"].values, dtype=np.float64) if "elapsed_time" in ctx.sweep.coords else np.zeros(0)
    return float(t.max()) if t.size else math.nan


def _window_coverage(ctx: Context, windows) -> str:
    """Sentences on windows that reach beyond the last output time; '' when none does."""
    t_end = _last_time(ctx)
    if not math.isfinite(t_end):
        return ""
    out = []
    for name, (a, b) in windows.items():
        if a >= t_end:
            out.append(f"the {_PHASE_TITLE.get(name, name)} window ({_g(a, 4)}–{_g(b, 4)} s) has no data")
        elif b > t_end:
            out.append(f"the {_PHASE_TITLE.get(name, name)} window's metrics cover only {_g(a, 4)}–{_g(t_end, 4)} s")
    if not out:
        return ""
    return f" The simulation ends at {_g(t_end, 4)} s: " + "; ".join(out) + "."


def _range_signals(ctx: Context) -> list:
    """``[(flag variable, what, sensor flag or None)]`` of every range with a window-edge flag."""
    out = []
    for disp in ("radial", "axial"):
        if f"{disp}_displacement_range_at_edge" in ctx.metrics:
            out.append((f"{disp}_displacement_range_at_edge", _CENTRE[disp], None))
    if f"{SENSOR}_displacement_range_at_edge" in ctx.metrics:
        for sn in sensors(ctx.metrics):
            out.append((f"{SENSOR}_displacement_range_at_edge", sn.label(), sn.value))
    return out


def section_window_edges(ctx: Context, windows):
    """Per phase and range: the grid points (or realizations) whose extreme lies at the window's edge.

    Reads the ``*_range_at_edge`` flags (1 where the largest or smallest value lies within
    one output interval of the start or end of the phase window).
    """
    signals = _range_signals(ctx)
    if not signals:
        return []
    m = _base(ctx.metrics, first_realization=False)
    seeds = realizations(m)
    speeds, loads = m["speed"].values, m["radial_load"].values
    rows, empty = [], []
    for k, phase in enumerate(PHASES):
        has_data = False
        for name, what, sv in signals:
            da = m[name].sel(phase=m["phase"].values[k])
            if sv is not None:
                da = da.sel({SENSOR: sv})
            da = da.transpose("speed", "radial_load", *[d for d in da.dims if d == REALIZATION])
            v = da.values
            finite = np.isfinite(v)
            if not finite.any():
                continue
            has_data = True
            flagged = finite & (v == 1)
            n_flag, n = int(flagged.sum()), int(finite.sum())
            if not n_flag:
                continue
            listed = []
            for i, sp in enumerate(speeds):
                for j, ld in enumerate(loads):
                    nf = int(flagged[i, j].sum())
                    if nf:
                        listed.append(f"{_dps(sp)}, {_kn(ld)}"
                                      + (f" ({nf} of {int(finite[i, j].sum())})" if seeds is not None else ""))
            where = "; ".join(listed[:_MAX_LISTED]) + (f"; and {len(listed) - _MAX_LISTED} more"
                                                       if len(listed) > _MAX_LISTED else "")
            if seeds is None:
                count = f"{n_flag} of {n} grid points"
            else:
                count = (f"{n_flag} of {n} runs ({_g(100.0 * n_flag / n, 3)} % of realizations), "
                         f"at {len(listed)} of {int(finite.any(axis=-1).sum())} grid points")
            rows.append([_PHASE_TITLE[phase], f"range of {what}", count, where])
        if not has_data:
            empty.append(phase)
    blocks = [Heading(2, "Ranges cut off by the phase window"),
              Para("A range whose largest or smallest value lies within one output interval of the start or "
                   "end of its phase window was still changing when the window opened or closed: such a range "
                   "is cut off by the window and is a lower bound of the signal's excursion. These are drawn "
                   "hollow in the metric figures"
                   + (" (realizations hollow where flagged, an ensemble mean hollow when any of its "
                      "realizations is)" if seeds is not None else "") + ".")]
    if rows:
        blocks.append(Table(["phase", "metric", "extreme at the window's edge",
                             "grid points" + (" (flagged of finished realizations)" if seeds is not None else "")],
                            rows))
        blocks.append(Para("No other range has an extreme at the edge of its window."))
    else:
        blocks.append(Para("No range of any phase has an extreme at the edge of its window."))
    if empty:
        blocks.append(Para("No finished case holds data in the "
                           + ", ".join(f"{_PHASE_TITLE[p]} ({_g(windows[p][0], 4)}–{_g(windows[p][1], 4)} s)"
                                       if p in windows else _PHASE_TITLE[p] for p in empty)
                           + f" window{'s' if len(empty) > 1 else ''}"
                           + (f"; the simulation ends at {_g(_last_time(ctx), 4)} s." if math.isfinite(_last_time(ctx))
                              else ".")))
    return blocks


def section_cage_slip(ctx: Context, figdir: Path, cases):
    """Cage slip against the epicyclic speed at the actual and at the nominal contact angle.

    A figure of the steady cage slip against speed and load and a table at ``cases``
    [(speed °/s, load N)] per phase. Returns the blocks and the figures written.
    """
    present = [(n, w) for n, w in CAGE_SLIPS if n in ctx.metrics]
    if not present:
        return [], []
    blocks = [Heading(2, "Cage slip")]
    alpha = _bearing_numbers(ctx)["alpha"][0]
    defs = {"cage_slip": "`cage_slip` = 1 − ω̄_c/ω_epi against the epicyclic cage speed "
                         "ω_epi = ω_i/2·(1 − D·cos α/d_m) at the loaded balls' actual contact angles "
                         "(their mean cos α, time-averaged over the phase)",
            "cage_slip_nominal": "`cage_slip_nominal` against the epicyclic speed at the nominal contact angle"
                                 + (f" α = {_g(math.degrees(alpha), 4)}°" if math.isfinite(alpha) else "")}
    text = ("Cage slip, positive when the cage lags its rolling-without-slip speed: "
            + "; ".join(defs[n] for n, _ in present) + ".")
    if len(present) < len(CAGE_SLIPS):
        missing = [n for n, _ in CAGE_SLIPS if n not in ctx.metrics]
        text += f" The sweep holds no {', '.join(f'`{n}`' for n in missing)} (written by an older version)."
    blocks.append(Para(text))
    figures = []
    specs = _axis_specs(ctx, "steady")
    p = figdir / "cage_slip_steady.png"
    notes = figure_cage_slip(ctx, "steady", specs, p)
    figures.append(p)
    ens = _ensemble_text(ctx)
    blocks.append(Para("Steady-phase cage slip in %, "
                       + (f"ensemble means of {ens} with ±1 standard-error bars, the individual realizations "
                          "as faint small points just left of their mean; the two definitions are set slightly "
                          "apart along the axis, " if ens else "one marker per case, ")
                       + "; ".join(notes) + "."))
    blocks.append(Image(f"figures/{p.name}", "steady cage slip against speed and load"))
    rows = []
    for (sp, ld) in cases:
        for phase in PHASES:
            vals = [_metric_stat(ctx, n, sp, ld, phase) for n, _ in present]
            if not any(math.isfinite(v[0]) for v in vals):
                continue
            epi = _metric_stat(ctx, "epicyclic_cage_speed", sp, ld, phase)
            rows.append([_dps(sp), _kn(ld), _PHASE_TITLE[phase]] + [_pm(m_, se, 100.0) for m_, se in vals]
                        + [_pm(*epi)])
    if rows:
        blocks.append(Para("At the extreme cases, per phase" + (f" (ensemble mean ± standard error of {ens})"
                                                                 if ens else "") + ":"))
        blocks.append(Table(["speed", "radial load", "phase"]
                            + [f"`{n}` ({w}) [%]" for n, w in present] + ["ω_epi, actual angles [rad/s]"],
                            rows))
    return blocks, figures


def _comparison(ctx: Context):
    """One dict per reference fit: the study's fit and ours in the study's units."""
    rows = []
    for ref in ctx.references:
        fixed, note = _fixed_choice(ctx, ref.fixed_axis, ref.fixed_coordinate)
        fit = _fit_at(ctx, ref.variable, ref.axis, ref.fixed_axis, fixed, ref.phase)
        row = {"ref": ref, "fixed": fixed, "note": note, "fit": fit}
        if fit and math.isfinite(fit["slope"]):
            s, i = ref.to_reference_units(fit["slope"], fit["intercept"])
            lo, _ = ref.to_reference_units(fit["slope_ci95_lower"], 0.0)
            hi, _ = ref.to_reference_units(fit["slope_ci95_upper"], 0.0)
            row.update(slope=s, intercept=i, lo=lo, hi=hi, r2=fit["rsquared"], n=fit["n"],
                       agrees=bool(np.sign(s) == np.sign(ref.slope)),
                       significant=bool(lo > 0 or hi < 0))
        else:
            row.update(slope=math.nan, intercept=math.nan, lo=math.nan, hi=math.nan,
                       r2=math.nan, n=fit.get("n", 0) if fit else 0, agrees=None, significant=False)
        rows.append(row)
    return rows


def section_comparison(ctx: Context, comparison):
    blocks = [Heading(2, "Fits beside the study's (Tables 3 and 4)")]
    ens = _ensemble_text(ctx)
    what = (f"Weighted least-squares lines of the ensemble means ({ens}; weights 1/standard error², ordinary "
            "least squares for a line where any point lacks a standard error) of our phase metrics"
            if ens else "Ordinary least-squares lines of our phase metrics")
    sens = sensors(ctx.metrics)
    blocks.append(Para(
        f"{what}, δ_r and δ_a at the ring centre, in the study's units, beside the fits of "
        f"`{ctx.reference_path.name}`. Each line is fitted at the value of the other axis named in "
        "'at'; the slope's 95 % confidence interval is in brackets. 'Sign agrees' compares the slopes' "
        "signs; '(interval spans 0)' marks a slope our data cannot tell from zero. "
        + ("The study's δ come from laser sensors on the ring, which also see the ring's tilt; the sensor "
           "figures above show our virtual sensors' readings." if sens else
           "The study's δ come from laser sensors on the ring, which also see the ring's tilt; a sweep with "
           "`[[sensors]]` reports such readings too.")))
    rows = []
    for c in comparison:
        ref = c["ref"]
        if c["agrees"] is None:
            sign = "n/a (too few cases)"
        else:
            flat = "" if c["significant"] else (
                " (interval spans 0)" if math.isfinite(c["lo"]) else " (no resolvable slope)")
            sign = ("yes" if c["agrees"] else "no") + flat
        rows.append([
            ref.label, c["note"].removeprefix("at "),
            f"{_e(ref.slope)} {ref.slope_units}", f"{_g(ref.intercept, 4)} {ref.intercept_units}",
            f"{_e(c['slope'])} [{_e(c['lo'])}, {_e(c['hi'])}] {ref.slope_units}",
            f"{_e(c['intercept'])} {ref.intercept_units}", _g(c["r2"]), str(int(c["n"])), sign,
        ])
    blocks.append(Table(["study fit", "at", "study slope", "study intercept", "our slope [95 % CI]",
                         "our intercept", "our R²", "n", "sign agrees"], rows))
    n_agree = sum(1 for c in comparison if c["agrees"])
    n_known = sum(1 for c in comparison if c["agrees"] is not None)
    blocks.append(Para(f"{n_agree} of {n_known} slope signs agree with the study"
                       + (f" ({len(comparison) - n_known} could not be fitted)." if n_known < len(comparison) else ".")))
    return blocks


def section_plane(ctx: Context):
    f = _base(ctx.fits)
    groups = []
    for ref in ctx.references:
        key = (ref.phase, ref.variable)
        if key not in groups:
            groups.append(key)
    rows = []
    for phase, var in groups:
        sel = {"phase": PHASES.index(phase)}
        try:
            fit_statistic(f, var, "plane", "interaction")
        except KeyError:
            continue
        g = lambda s: float(fit_statistic(f, var, "plane", s).sel(sel).item())  # noqa: E731
        conv = 1e3  # m -> mm; per (degree s-1 N) unchanged
        rows.append([f"{_PHASE_TITLE[phase]} {var.replace('_displacement_', ' ')}",
                     f"{_e(g('interaction') * conv)} ± {_e(g('interaction_stderr') * conv)}",
                     f"[{_e(g('interaction_ci95_lower') * conv)}, {_e(g('interaction_ci95_upper') * conv)}]",
                     _g(g("rsquared")), str(int(g("n")))])
    if not rows:
        return []
    return [Heading(2, "Interaction of speed and load"),
            Para("Plane fits z = a + b·speed + c·load + d·speed·load over the whole grid"
                 + (" (of the ensemble means, unweighted)" if realizations(ctx.metrics) is not None else "")
                 + ", δ_r and δ_a at the ring centre; the interaction d in mm per (°/s·N) with its standard error:"),
            Table(["metric", "d ± standard error", "95 % CI", "R²", "n"], rows)]


def _find_ref(comparison, phase, displacement, metric, axis):
    for c in comparison:
        r = c["ref"]
        if (r.phase, r.displacement, r.metric, r.axis) == (phase, displacement, metric, axis):
            return c
    return None


def section_physics(ctx: Context, comparison, windows):
    """The plain-words paragraph: where our physics agrees with the study and where not."""
    blocks = [Heading(2, "Where our physics agrees with the study and where it does not")]
    paras = []
    pts = _ok_cases(ctx)
    if not pts:
        return blocks + [Para("No case finished, so there is nothing to compare.")]
    speeds = sorted({p[0] for p in pts})
    s_lo, s_hi = speeds[0], speeds[-1]
    c_rs = _find_ref(comparison, "steady", "radial", "mean", "speed")
    want_load = c_rs["fixed"] if c_rs else nearest(ctx.metrics["radial_load"].values, 30e3)
    at_hi = [p for p in pts if p[0] == s_hi]
    case = min(at_hi, key=lambda p: abs(p[1] - want_load))
    s, load = case

    # Centrifugal force against the contact loads.
    bn = _bearing_numbers(ctx)
    w_i = _metric_value(ctx, "inner_ring_speed_mean", s, load, "steady")
    if not math.isfinite(w_i):
        w_i = math.radians(s)
    w_c = _metric_value(ctx, "epicyclic_cage_speed", s, load, "steady")
    w_c_src = "the epicyclic cage speed at the loaded balls' actual contact angles"
    if not math.isfinite(w_c):
        slip = _metric_value(ctx, "cage_slip", s, load, "steady")
        w_c = _metric_value(ctx, "cage_speed_mean", s, load, "steady") / (1.0 - slip) if slip != 1.0 else math.nan
        w_c_src = "the epicyclic cage speed implied by the measured cage speed and slip"
    D, d_m, alpha = bn["D"][0], bn["d_m"][0], bn["alpha"][0]
    if not math.isfinite(w_c) and math.isfinite(D) and math.isfinite(d_m):
        a = alpha if math.isfinite(alpha) else 0.0
        w_c = 0.5 * w_i * (1.0 - D * math.cos(a) / d_m)
        w_c_src = (f"ω_c = ω_i/2·(1 − D·cos α/d_m) with α = {_g(math.degrees(a))}°"
                   + ("" if math.isfinite(alpha) else " (no contact angle in the configuration)"))
    m_b = bn["m_b"][0]
    r = d_m / 2.0
    f_c = m_b * r * w_c**2
    q = math.nan
    sw = _base(ctx.sweep, first_realization=False)
    if "max_inner_contact_load" in sw and "steady" in windows:
        t = sw["elapsed_time"].values
        a, b = windows["steady"]
        mask = (t >= a) & (t < b)
        ser = sw["max_inner_contact_load"].sel(speed=s, radial_load=load).transpose(..., "elapsed_time").values
        sel = ser.reshape(-1, t.size)[:, mask]   # every realization's steady samples
        if np.isfinite(sel).any():
            q = float(sel[np.isfinite(sel)].mean())
    if math.isfinite(f_c) and math.isfinite(q) and q > 0:
        paras.append(
            f"**Centrifugal loading.** At the highest speed, {_dps(s)} with {_kn(load)} radial load, "
            f"the cage turns at ω_c = {_g(w_c)} rad/s ({w_c_src}). A ball of m_b = {_g(m_b)} kg "
            f"(D = {_g(D * 1e3)} mm, ρ = {_g(bn['rho'][0], 4)} kg/m³) on the pitch radius "
            f"d_m/2 = {_g(r * 1e3, 4)} mm feels F_c = m_b·(d_m/2)·ω_c² = {_g(f_c)} N, while the largest "
            f"inner-race contact load averages {_g(q / 1e3)} kN over the steady phase"
            + (" (all realizations)" if realizations(ctx.sweep) is not None else "") + ": F_c is "
            f"{_g(100 * f_c / q, 2)} % of it. Whatever a speed does to the steady displacements through "
            f"centrifugal force is therefore of that relative order, so speed trends in the steady δ "
            f"should be tiny.")
    else:
        missing = [k for k, v in (("ball diameter", D), ("ball density", bn["rho"][0]),
                                  ("pitch diameter", d_m), ("cage speed", w_c), ("contact load", q))
                   if not math.isfinite(v)]
        paras.append("**Centrifugal loading.** The centrifugal force on a ball could not be estimated: "
                     f"missing {', '.join(missing)} in the configuration or the data.")

    # Speed trends of the steady means.
    for disp, sym in (("radial", "δ_r"), ("axial", "δ_a")):
        c = _find_ref(comparison, "steady", disp, "mean", "speed")
        if c is None:
            continue
        ref = c["ref"]
        span = s_hi - s_lo
        ours_um = _span_change(c, span) * 1e3
        study_um = ref.slope_in_coordinate_units() * span * 1e6 if span > 0 else math.nan
        if not math.isfinite(ours_um):
            paras.append(f"**Steady mean {sym} against speed.** Too few cases {c['note']} to fit a line.")
            continue
        agree = "the same sign as" if c["agrees"] else "the opposite sign to"
        ratio = abs(study_um / ours_um) if ours_um != 0 else math.inf
        paras.append(
            f"**Steady mean {sym} against speed** ({c['note']}). Ours changes by {_g(ours_um)} µm "
            f"from {_dps(s_lo)} to {_dps(s_hi)} (R² = {_g(c['r2'])}), {agree} the study's fit, which "
            f"changes by {_g(study_um)} µm over the same span, {_g(ratio)} times as much. "
            + ("Our interval on the slope spans zero: within our data the speed has no resolvable "
               "effect. " if not c["significant"] else "")
            + ("A centrifugal force of the size above cannot produce a trend as large as the study's; "
               "we do not reproduce it." if ratio > 10 else
               "The two are of a similar order." if 0.5 <= ratio <= 2 else "").rstrip())

    # The study's ~2 mm axial offset.
    c = _find_ref(comparison, "steady", "axial", "mean", "speed")
    if c is not None:
        ref = c["ref"]
        study_mm = (ref.intercept_si() + ref.slope_in_coordinate_units() * s_lo) * 1e3
        ours = _metric_value(ctx, "axial_displacement_mean", s_lo, c["fixed"], "steady") * 1e3
        fa = float(np.atleast_1d(ctx.metrics["axial_load"].values)[0]) if "axial_load" in ctx.metrics.coords else math.nan
        if math.isfinite(ours):
            pct = 100 * study_mm / (D * 1e3) if math.isfinite(D) else math.nan
            far = ours == 0 or abs(study_mm / ours) > 10
            paras.append(
                f"**Mean axial displacement.** The study's steady mean δ_a at {_dps(s_lo)} is "
                f"{_g(study_mm, 4)} mm (its fit, intercept {_g(ref.intercept, 4)} {ref.intercept_units}); "
                f"ours at the same point is {_g(ours, 3)} mm"
                + (f", so the study's is {_g(abs(study_mm / ours))} times ours" if ours != 0 else "")
                + (f". {_g(study_mm, 3)} mm is {_g(pct, 2)} % of the ball diameter" if math.isfinite(pct) else "")
                + (f", while the axial load is {_kn(fa)}" if math.isfinite(fa) else "")
                + (": in our model δ_a is the contact deflection plus the take-up of internal clearance, "
                   "and the study's value is far beyond that; it most likely includes an offset of its "
                   "own datum that the text does not describe." if far else
                   ": the two are of a similar order.")
                + _axial_sensor_sentence(ctx, s_lo, c["fixed"]))

    # Load trends.
    for disp, sym in (("radial", "δ_r"), ("axial", "δ_a")):
        c = _find_ref(comparison, "steady", disp, "mean", "radial_load")
        if c is None or not math.isfinite(c["slope"]):
            continue
        ref = c["ref"]
        paras.append(
            f"**Steady mean {sym} against load** ({c['note']}). Our slope is {_e(c['slope'])} "
            f"{ref.slope_units}, the study's {_e(ref.slope)} {ref.slope_units}: "
            + ("the signs agree" if c["agrees"] else "the signs differ")
            + (", and ours is significant at 95 %." if c["significant"] else
               ", but ours cannot be told from zero at 95 %.")
            + (" More load compresses the Hertz contacts further." if disp == "radial" else ""))

    # Transients.
    trans = [c for c in comparison if c["ref"].phase in ("startup", "deceleration") and c["agrees"] is not None]
    if trans:
        n_agree = sum(1 for c in trans if c["agrees"])
        acc = ""
        if "startup" in windows:
            a, b = windows["startup"]
            if b > a:
                acc = (f" Our start-up ramps the speed over {_g(b - a)} s, an angular acceleration of "
                       f"{_g(math.radians(s_lo) / (b - a))} to {_g(math.radians(s_hi) / (b - a))} rad/s² "
                       f"over the grid, the quantity the study attributes the transient ranges to.")
        paras.append(f"**Transient ranges.** {n_agree} of {len(trans)} start-up and deceleration range "
                     f"slopes have the study's sign.{acc}")
    n_agree = sum(1 for c in comparison if c["agrees"])
    n_known = sum(1 for c in comparison if c["agrees"] is not None)
    if n_known:
        paras.append(f"Altogether {n_agree} of {n_known} fitted slopes agree in sign with the study.")
    else:
        paras.append("None of the reference fits could be compared: each needs at least 3 finished "
                     "cases along its axis.")
    return blocks + [Para(p) for p in paras]


def _axial_sensor_sentence(ctx: Context, speed: float, load: float) -> str:
    """' Sensor `x` at … reads a steady mean of … mm there.' for each sensor aimed along the axis."""
    out = []
    for sn in sensors(ctx.metrics):
        if not abs(sn.direction[2]) >= 0.9:
            continue
        v = _metric_value(ctx, f"{SENSOR}_displacement_mean", speed, load, "steady", sn.value)
        if math.isfinite(v):
            out.append(f" The {sn.label()}, which also sees the ring's tilt, reads a steady mean of "
                       f"{_g(v * 1e3, 3)} mm there.")
    return "".join(out)


def _span_change(c, span: float) -> float:
    """Change of our fitted line over ``span`` [coordinate units], in mm."""
    fit = c["fit"]
    if not fit or not math.isfinite(fit.get("slope", math.nan)):
        return math.nan
    return fit["slope"] * span * 1e3


# --------------------------------------------------------------------------- entry point


#: Sensor metrics fitted for the sensor figures.
_SENSOR_FITTED = tuple(f"{SENSOR}_displacement_{k}" for k in ("range", "mean", "std"))


def _fit_text(ctx: Context) -> str:
    """What our fitted lines are: OLS of the cases or WLS of the ensemble means."""
    seeds = realizations(ctx.metrics)
    if seeds is not None and seeds.size >= 2:
        return ("the weighted least-squares line of the means (weights 1/standard error²; ordinary least "
                "squares where any point lacks a standard error) and its 95 % confidence band")
    return "OLS line and its 95 % confidence band"


def _has_data(ctx: Context, name: str, phase: str) -> bool:
    """Whether metric ``name`` has any finite value in ``phase``."""
    return name in ctx.metrics and bool(ctx.metrics[name].sel(phase=PHASES.index(phase)).notnull().any())


def _metric_caption(ctx: Context, what: str, notes, hollow: int, is_range: bool, has_data: bool = True) -> str:
    """The caption of a metric figure: what is plotted, the fit, the axes, the hollow markers."""
    if not has_data:
        return (f"{what}, " + "; ".join(notes) + ": no finished case holds data in this phase's window, "
                "so there is nothing to plot.")
    ens = _ensemble_text(ctx)
    if ens:
        text = (f"{what}. Ensemble mean of {ens} per case with ±1 standard-error bars, the individual "
                f"realizations as faint small points just left of their mean; {_fit_text(ctx)}, ")
    else:
        text = f"{what}. Cases (points), {_fit_text(ctx)}, "
    text += "; ".join(notes) + "."
    if is_range:
        if hollow:
            text += (f" Hollow markers ({hollow} {'realization' if ens else 'case'}{'s' if hollow != 1 else ''}"
                     f"{(' and the mean it belongs to' if hollow == 1 else ' and the means they belong to') if ens else ''}"
                     "): the range has an extreme at the "
                     "window's edge, so it is cut off by the window and is a lower bound.")
        else:
            text += " No range drawn here has an extreme at the window's edge."
    return text


@dataclass
class ReportFiles:
    """Paths written by :func:`build_report`."""

    markdown: Path
    html: Path
    figures: list
    metrics: Path
    fits: Path
    missing: int


def build_report(directory, reference=None) -> ReportFiles:
    """Metrics, fits and the report of a finished or partial sweep.

    Parameters
    ----------
    directory : path-like
        The sweep folder (``results/<name>/``).
    reference : path-like, optional
        A reference-fit TOML file; default ``sweeps/reference/study-fits.toml``.

    Returns
    -------
    ReportFiles

    Raises
    ------
    UserError
        When the folder holds no sweep, or the reference file is invalid.
    """
    directory = Path(directory)
    sweep = load_sweep(directory)
    refs = load_reference_fits(reference)
    metrics = phase_metrics(sweep)
    fits = fit_metrics(metrics)
    write_metrics(metrics, directory / "metrics.nc")
    write_fits(fits, directory / "fits.nc")
    config, err = _parse_config(str(sweep.attrs.get("configuration", "")))
    from ..analysis import default_reference_path

    ctx = Context(directory=directory, sweep=sweep, metrics=metrics, fits=fits,
                  status=read_status(directory), references=refs,
                  reference_path=Path(reference) if reference else default_reference_path(),
                  config=config, config_error=err)
    outdir = directory / "report"
    figdir = outdir / "figures"
    figdir.mkdir(parents=True, exist_ok=True)
    windows, windows_src = phase_windows(ctx)

    blocks = [Heading(1, f"Sweep report: {directory.name}")]
    caveats = [c.strip() for c in str(sweep.attrs.get("caveats", "")).split(" | ") if c.strip()]
    if caveats:
        blocks.append(Warning_("**Geometry caveat.** This bearing is not buildable as specified; "
                               "its results are reported with that caveat:\n" + "\n".join(caveats)))
    blocks += section_parameters(ctx)
    blocks += section_sensors(ctx)
    blocks += section_cases(ctx)
    sens = sensors(ctx.metrics)
    ens = _ensemble_text(ctx)
    if sens:
        ctx.sensor_fits = fit_metrics(ctx.metrics, names=[n for n in _SENSOR_FITTED if n in ctx.metrics])

    figures = []
    blocks.append(Heading(2, "Time histories"))
    cases = _extreme_cases(ctx, realization=0 if realizations(ctx.sweep) is not None else None)
    if cases:
        first = _first_realization_text(ctx)
        which = "; ".join(f"{_dps(s)}, {_kn(l)}" for s, l in cases)
        p = figdir / "time_histories.png"
        figure_time_histories(ctx, windows, p, cases)
        figures.append(p)
        blocks.append(Para(f"δ_r and δ_a at the ring centre of the extreme cases ({which})"
                           + (f", {first} (the other realizations are in `sweep.nc`)" if first else "")
                           + f". Phase windows from {windows_src}: "
                           + ", ".join(f"{_PHASE_TITLE.get(k, k)} {_g(a, 4)}–{_g(b, 4)} s" for k, (a, b) in windows.items())
                           + "." + _window_coverage(ctx, windows)))
        blocks.append(Image(f"figures/{p.name}", "time histories of the extreme cases"))
        if sens and "sensor_displacement" in ctx.sweep:
            p = figdir / "sensor_time_histories.png"
            figure_sensor_time_histories(ctx, windows, p, cases)
            figures.append(p)
            blocks.append(Para("Readings of the virtual sensors for the same cases"
                               + (f", {first}" if first else "") + ", one panel per sensor: "
                               + "; ".join(sn.label() for sn in sens) + ". Phase windows shaded as above."))
            blocks.append(Image(f"figures/{p.name}", "sensor readings of the extreme cases"))
    else:
        blocks.append(Para("No case finished; there are no time histories to show."))

    blocks.append(Heading(2, "Metrics against speed and load"))
    if ens:
        blocks.append(Para(f"With {ens}, every metric is shown as the ensemble mean over the realizations "
                           "with ±1 standard-error bars, and each realization as a faint small point."))
    groups = {}
    for ref in refs:
        groups.setdefault((ref.phase, ref.displacement, ref.metric), [])
        if ref.axis not in [g.axis for g in groups[(ref.phase, ref.displacement, ref.metric)]]:
            groups[(ref.phase, ref.displacement, ref.metric)].append(ref)
    for (phase, disp, metric), grefs in groups.items():
        p = figdir / f"metric_{phase}_{disp}_{metric}.png"
        notes, hollow = figure_metric(ctx, grefs, p)
        figures.append(p)
        blocks.append(Heading(3, f"{_PHASE_TITLE[phase]} {disp} displacement {_METRIC_TITLE[metric]}, "
                                 f"at the ring centre"))
        blocks.append(Para(_metric_caption(ctx, f"{_CENTRE[disp]}", notes, hollow, metric == "range",
                                           _has_data(ctx, grefs[0].variable, phase))))
        blocks.append(Image(f"figures/{p.name}", f"{phase} {disp} {metric}"))
    if sens:
        pairs = []
        for ref in refs:
            if (ref.phase, ref.metric) not in pairs:
                pairs.append((ref.phase, ref.metric))
        for phase, metric in pairs:
            if f"{SENSOR}_displacement_{metric}" not in ctx.metrics:
                continue
            p = figdir / f"sensor_{phase}_{metric}.png"
            notes, hollow = figure_sensor_metric(ctx, phase, metric, _axis_specs(ctx, phase), p)
            figures.append(p)
            blocks.append(Heading(3, f"{_PHASE_TITLE[phase]} sensor reading {_METRIC_TITLE[metric]}"))
            blocks.append(Para(_metric_caption(
                ctx, "The virtual sensors' readings, a row per sensor (" + "; ".join(sn.label() for sn in sens)
                + ")", notes, hollow, metric == "range", _has_data(ctx, f"{SENSOR}_displacement_{metric}", phase))
                + (" The sensors' lines are fitted for this report and not stored in `fits.nc`."
                   if _has_data(ctx, f"{SENSOR}_displacement_{metric}", phase) else "")))
            blocks.append(Image(f"figures/{p.name}", f"{phase} sensor {metric}"))

    slip_blocks, slip_figures = section_cage_slip(ctx, figdir, _extreme_cases(ctx))
    blocks += slip_blocks
    figures += slip_figures
    blocks += section_window_edges(ctx, windows)
    comparison = _comparison(ctx)
    blocks += section_comparison(ctx, comparison)
    blocks += section_plane(ctx)
    blocks += section_physics(ctx, comparison, windows)
    blocks.append(Heading(2, "Files"))
    dims = "speed, radial_load" + (", realization" if ens else "") + ", phase" + (", sensor" if sens else "")
    blocks.append(Bullets([
        "`metrics.nc`: range, mean and std of δ_r and δ_a at the ring centre"
        + (" and of each sensor's reading" if sens else "")
        + ", the times of their extremes and the window-edge flags (`*_range_at_edge`), the cage slip at the "
        "actual (`cage_slip`) and nominal (`cage_slip_nominal`) contact angles, the epicyclic cage speed, the peak "
        f"contact pressure and the phase windows (`phase_start`, `phase_end`) over ({dims})"
        + ("; the ensemble means and standard errors (`*_ensemble_mean`, `*_ensemble_stderr`) and the fraction of "
           "realizations flagged at the window's edge (`*_range_at_edge_fraction`)" if ens else ""),
        "`fits.nc`: line fits along each axis and the interaction plane, per metric and phase"
        + (" (of the ensemble means, weighted by their standard errors)" if ens else "")
        + (", at the ring centre" if sens else "")]))

    md = outdir / "report.md"
    ht = outdir / "report.html"
    md.write_text(render_markdown(blocks), encoding="utf-8")
    ht.write_text(render_html(blocks, f"Sweep report: {directory.name}"), encoding="utf-8")
    missing = int((_base_states(ctx) != "ok").sum())
    return ReportFiles(markdown=md, html=ht, figures=figures, metrics=directory / "metrics.nc",
                       fits=directory / "fits.nc", missing=missing)
