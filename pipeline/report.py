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

from .errors import ConfigError
from .fits import (DISPLACEMENT_COORD, fit_metrics, fit_statistic, line_band, load_reference_fits,
                   udunits_to_pint, write_fits)
from .metrics import case_states, load_status, load_sweep, nearest, phase_metrics, write_metrics
from .units import parse_quantity, registry

#: Keyword arguments of every ``savefig``: no software, no timestamps in the PNG.
PNG_KWARGS = {"dpi": 100, "format": "png", "metadata": {"Software": None}}

_PHASE_TITLE = {"startup": "start-up", "steady": "steady", "deceleration": "deceleration"}
_METRIC_TITLE = {"range": "variation range", "mean": "mean", "std": "standard deviation"}
_AXIS_TITLE = {"speed": "speed", "radial_load": "radial load"}


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


def _parse_config(text: str):
    if not text:
        return {}, "the sweep carries no configuration"
    try:
        return tomllib.loads(text), ""
    except tomllib.TOMLDecodeError as exc:
        return {}, f"the configuration attribute is not valid TOML ({exc})"


def phase_windows(ctx: Context):
    """Phase windows ``{name: (start, end)}`` [s] and where they came from.

    From the configuration's profile ``phases`` table when it has one (either
    ``name = [start, end]``, ``name = {start = .., end = ..}`` or a list of
    ``{name, start, end}`` tables); otherwise from where ``inner_ring_speed`` ramps in the
    case with the highest speed.
    """
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
    return [d for d in ds.dims if d not in ("speed", "radial_load", "phase", "elapsed_time", DISPLACEMENT_COORD)]


def _base(ds):
    """``ds`` at the first value of every extra sweep dimension."""
    extra = _extra_dims(ds)
    return ds.isel({d: 0 for d in extra}) if extra else ds


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


def _ok_cases(ctx: Context):
    st = _base_states(ctx)
    pts = []
    for s in st["speed"].values:
        for l in st["radial_load"].values:
            if st.sel(speed=s, radial_load=l).item() == "ok":
                pts.append((float(s), float(l)))
    return pts


def _base_states(ctx: Context):
    st = case_states(ctx.sweep)
    extra = [d for d in st.dims if d not in ("speed", "radial_load")]
    return st.isel({d: 0 for d in extra}) if extra else st


def _extreme_cases(ctx: Context):
    pts = _ok_cases(ctx)
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


def _metric_value(ctx: Context, name: str, speed: float, load: float, phase: str) -> float:
    m = _base(ctx.metrics)
    if name not in m:
        return math.nan
    return float(m[name].sel(speed=speed, radial_load=load, phase=PHASES.index(phase)).item())


def _fit_at(ctx: Context, variable: str, axis: str, fixed_axis: str, fixed: float, phase: str) -> dict:
    f = _base(ctx.fits)
    out = {}
    for stat in ("slope", "intercept", "slope_stderr", "intercept_stderr", "slope_intercept_covariance",
                 "slope_ci95_lower", "slope_ci95_upper", "rsquared", "n"):
        try:
            da = fit_statistic(f, variable, axis, stat)
        except KeyError:
            return {}
        out[stat] = float(da.sel({fixed_axis: fixed, "phase": PHASES.index(phase)}).item())
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


def figure_time_histories(ctx: Context, windows, path: Path, cases) -> None:
    sw = _base(ctx.sweep)
    fig, axes = _new_figure(2, 1, (10.0, 6.0))
    t = sw["elapsed_time"].values
    for k, (name, label) in enumerate((("radial_displacement", "δ_r [µm]"), ("axial_displacement", "δ_a [µm]"))):
        ax = axes[k, 0]
        _shade(ax, windows)
        if name in sw:
            for (s, l) in cases:
                y = sw[name].sel(speed=s, radial_load=l).values * 1e6
                ax.plot(t, y, lw=1.0, label=f"{_dps(s)}, {_kn(l)}")
        ax.set_ylabel(label)
        ax.grid(True, lw=0.3)
    axes[1, 0].set_xlabel("elapsed time [s]")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="outside right upper")
    axes[0, 0].set_title("Inner-ring displacements of the extreme cases, phase windows shaded")
    _save(fig, path)


def figure_metric(ctx: Context, refs, path: Path) -> list:
    """One panel per reference axis of a (phase, displacement, metric) group; returns notes."""
    r0 = refs[0]
    fig, axes = _new_figure(1, len(refs), (4.6 * len(refs), 3.6))
    notes = []
    m = _base(ctx.metrics)
    for k, ref in enumerate(refs):
        ax = axes[0, k]
        fixed, note = _fixed_choice(ctx, ref.fixed_axis, ref.fixed_coordinate)
        notes.append(f"against {_AXIS_TITLE[ref.axis]} {note}")
        phase = PHASES.index(ref.phase)
        x = m[ref.axis].values.astype(float)
        xs = x / 1e3 if ref.axis == "radial_load" else x
        if ref.variable in m:
            y = m[ref.variable].sel({ref.fixed_axis: fixed, "phase": phase}).transpose(ref.axis).values
            ax.plot(xs, y * 1e6, "o", color="k", ms=4, label="cases")
        fit = _fit_at(ctx, ref.variable, ref.axis, ref.fixed_axis, fixed, ref.phase)
        if fit and math.isfinite(fit["slope"]):
            grid = np.linspace(np.nanmin(x), np.nanmax(x), 50)
            yl, lo, hi = line_band(fit, grid)
            gs = grid / 1e3 if ref.axis == "radial_load" else grid
            ax.plot(gs, yl * 1e6, "-", color="C0", lw=1.2, label=f"OLS fit (R² = {_g(fit['rsquared'])})")
            ax.fill_between(gs, lo * 1e6, hi * 1e6, color="C0", alpha=0.2, lw=0, label="95 % band")
        ax.set_xlabel("steady speed [°/s]" if ref.axis == "speed" else "radial load [kN]")
        sym = "δ_r" if r0.displacement == "radial" else "δ_a"
        ax.set_ylabel(f"{_PHASE_TITLE[r0.phase]} {r0.metric} of {sym} [µm]")
        ax.set_title(note, fontsize=8)
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{_PHASE_TITLE[r0.phase]}: {r0.displacement} displacement {_METRIC_TITLE[r0.metric]}", fontsize=10)
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
    """``{(speed, load): (state, reason, id)}`` from status.json, matched to the grid."""
    ureg = registry()
    speeds = ctx.metrics["speed"].values
    loads = ctx.metrics["radial_load"].values
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

    for cid, state, reason, values, units in status_entries(ctx.status):
        hit = None
        for s in candidates(values.get("speed"), "speed", units):
            for l in candidates(values.get("radial_load"), "radial_load", units):
                si = [x for x in speeds if math.isclose(x, s, rel_tol=1e-6)]
                li = [x for x in loads if math.isclose(x, l, rel_tol=1e-6)]
                if si and li:
                    hit = (float(si[0]), float(li[0]))
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
    total = st.size
    n_ok = int((st == "ok").sum())
    blocks = [Heading(2, "Cases")]
    speeds = ", ".join(_g(v, 4) for v in ctx.metrics["speed"].values)
    loads = ", ".join(_g(v / 1e3, 4) for v in ctx.metrics["radial_load"].values)
    blocks.append(Para(f"Grid: speed {speeds} °/s × radial load {loads} kN: {total} cases, "
                       f"{n_ok} finished ok, {total - n_ok} failed or missing."))
    matched, unmatched = _status_lookup(ctx)
    rows = []
    for s in st["speed"].values:
        for l in st["radial_load"].values:
            state = st.sel(speed=s, radial_load=l).item()
            if state == "ok":
                continue
            rec = matched.get((float(s), float(l)))
            reason = rec[1] if rec and rec[1] else "no reason recorded"
            if rec and rec[0] == "failed" and state in ("not_run", "no_data"):
                state = "failed"  # the grid only knows the case file is missing
            if state == "no_data":
                state = "flagged ok but holds no data"
            cid = rec[2] if rec else "-"
            rows.append([_dps(s), _kn(l), state, reason, cid,
                         "excluded: NaN in metrics.nc, skipped by every fit (n counts the points used)"])
    if rows:
        blocks.append(Para("**Missing or failed cases.** The report is built from the cases that "
                           "finished; these are missing:"))
        blocks.append(Table(["speed", "radial load", "state", "reason", "case id", "handling"], rows))
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
        blocks.append(Para("Extra sweep dimensions: " + "; ".join(
            f"{d} ({ctx.metrics.sizes[d]} values); figures and the comparison use the first, "
            + (f"{_g(ctx.metrics[d].values[0], 4)} {ctx.metrics[d].attrs.get('units', '')}".strip()
               if d in ctx.metrics.coords else "index 0") for d in dims) + "."))
    return blocks


def section_parameters(ctx: Context):
    attrs = ctx.sweep.attrs
    blocks = [Heading(2, "Bearing, profile and parameters")]
    items = [f"bearing: **{attrs.get('bearing', '') or 'not named'}**",
             f"profile: **{attrs.get('profile', '') or 'not named'}**"]
    if "axial_load" in ctx.metrics.coords:
        vals = np.atleast_1d(ctx.metrics["axial_load"].values)
        items.append("axial load: " + ", ".join(_kn(float(v)) for v in vals))
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
    blocks.append(Para(
        f"Ordinary least-squares lines of our phase metrics, in the study's units, beside the fits of "
        f"`{ctx.reference_path.name}`. Each line is fitted at the value of the other axis named in "
        "'at'; the slope's 95 % confidence interval is in brackets. 'Sign agrees' compares the slopes' "
        "signs; '(interval spans 0)' marks a slope our data cannot tell from zero."))
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
            Para("Plane fits z = a + b·speed + c·load + d·speed·load over the whole grid; the "
                 "interaction d in mm per (°/s·N) with its standard error:"),
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
    sw = _base(ctx.sweep)
    if "max_inner_contact_load" in sw and "steady" in windows:
        t = sw["elapsed_time"].values
        a, b = windows["steady"]
        mask = (t >= a) & (t < b)
        ser = sw["max_inner_contact_load"].sel(speed=s, radial_load=load).values
        if mask.any():
            q = float(np.nanmean(ser[mask]))
    if math.isfinite(f_c) and math.isfinite(q) and q > 0:
        paras.append(
            f"**Centrifugal loading.** At the highest speed, {_dps(s)} with {_kn(load)} radial load, "
            f"the cage turns at ω_c = {_g(w_c)} rad/s ({w_c_src}). A ball of m_b = {_g(m_b)} kg "
            f"(D = {_g(D * 1e3)} mm, ρ = {_g(bn['rho'][0], 4)} kg/m³) on the pitch radius "
            f"d_m/2 = {_g(r * 1e3, 4)} mm feels F_c = m_b·(d_m/2)·ω_c² = {_g(f_c)} N, while the largest "
            f"inner-race contact load averages {_g(q / 1e3)} kN over the steady phase: F_c is "
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
                   ": the two are of a similar order."))

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


def _span_change(c, span: float) -> float:
    """Change of our fitted line over ``span`` [coordinate units], in mm."""
    fit = c["fit"]
    if not fit or not math.isfinite(fit.get("slope", math.nan)):
        return math.nan
    return fit["slope"] * span * 1e3


# --------------------------------------------------------------------------- entry point


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
    from .fits import default_reference_path

    ctx = Context(directory=directory, sweep=sweep, metrics=metrics, fits=fits,
                  status=load_status(directory), references=refs,
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
    blocks += section_cases(ctx)

    figures = []
    blocks.append(Heading(2, "Time histories"))
    cases = _extreme_cases(ctx)
    if cases:
        p = figdir / "time_histories.png"
        figure_time_histories(ctx, windows, p, cases)
        figures.append(p)
        blocks.append(Para("δ_r and δ_a of the extreme cases ("
                           + "; ".join(f"{_dps(s)}, {_kn(l)}" for s, l in cases)
                           + f"). Phase windows from {windows_src}: "
                           + ", ".join(f"{_PHASE_TITLE.get(k, k)} {_g(a, 4)}–{_g(b, 4)} s" for k, (a, b) in windows.items())
                           + "."))
        blocks.append(Image(f"figures/{p.name}", "time histories of the extreme cases"))
    else:
        blocks.append(Para("No case finished; there are no time histories to show."))

    blocks.append(Heading(2, "Metrics against speed and load"))
    groups = {}
    for ref in refs:
        groups.setdefault((ref.phase, ref.displacement, ref.metric), [])
        if ref.axis not in [g.axis for g in groups[(ref.phase, ref.displacement, ref.metric)]]:
            groups[(ref.phase, ref.displacement, ref.metric)].append(ref)
    for (phase, disp, metric), grefs in groups.items():
        p = figdir / f"metric_{phase}_{disp}_{metric}.png"
        notes = figure_metric(ctx, grefs, p)
        figures.append(p)
        blocks.append(Heading(3, f"{_PHASE_TITLE[phase]} {disp} displacement {_METRIC_TITLE[metric]}"))
        blocks.append(Para("Cases (points), OLS line and its 95 % confidence band, " + "; ".join(notes) + "."))
        blocks.append(Image(f"figures/{p.name}", f"{phase} {disp} {metric}"))

    comparison = _comparison(ctx)
    blocks += section_comparison(ctx, comparison)
    blocks += section_plane(ctx)
    blocks += section_physics(ctx, comparison, windows)
    blocks.append(Heading(2, "Files"))
    blocks.append(Bullets(["`metrics.nc`: range, mean and std of δ_r and δ_a, cage slip, peak contact "
                           "pressure over (speed, radial_load, phase)",
                           "`fits.nc`: line fits along each axis and the interaction plane, per metric and phase"]))

    md = outdir / "report.md"
    ht = outdir / "report.html"
    md.write_text(render_markdown(blocks), encoding="utf-8")
    ht.write_text(render_html(blocks, f"Sweep report: {directory.name}"), encoding="utf-8")
    missing = int((_base_states(ctx) != "ok").sum())
    return ReportFiles(markdown=md, html=ht, figures=figures, metrics=directory / "metrics.nc",
                       fits=directory / "fits.nc", missing=missing)
