"""Report sections on the cases themselves: the grid and its missing cases, the virtual
sensors, the ranges cut off by a phase window, and the cage slip."""
from __future__ import annotations

import math
import numpy as np

from rvcore.profile import PHASES

from ..analysis import REALIZATION
from .context import (SENSOR, Context, on_base_grid, ensemble_text, extra_dims, bearing_numbers, rows_of,
                      realizations, sensors, status_lookup)
from .figures import CAGE_SLIPS, figure_cage_slip
from .render import CENTRE_LABEL, PHASE_TITLE, Heading, Image, Para, Table, fmt_speed, fmt_number, fmt_kn
from .select import (axis_specs, base_states, extreme_points, fmt_mean_se, metric_stat, missing_cases,
                     unlisted_points)

#: Largest number of grid points listed by name in the window-edge table.
_MAX_LISTED = 8


def section_cases(ctx: Context):
    st = base_states(ctx)
    seeds = realizations(ctx.metrics) if REALIZATION in st.dims else None
    unlisted = unlisted_points(ctx)
    n_ok = int((st == "ok").sum())
    total = n_ok + missing_cases(ctx)
    blocks = [Heading(2, "Cases")]
    speeds = ", ".join(fmt_number(v, 4) for v in ctx.metrics["speed"].values)
    loads = ", ".join(fmt_number(v / 1e3, 4) for v in ctx.metrics["radial_load"].values)
    if unlisted:
        blocks.append(Para(f"The sweep lists its cases (`[[cases]]`): {len(unlisted)} of the grid's "
                           f"{st.sizes['speed'] * st.sizes['radial_load']} speed and load points are not "
                           "among them and are left out below (empty in sweep.nc, skipped by the fits)."))
    if seeds is None:
        blocks.append(Para(f"Grid: speed {speeds} °/s × radial load {loads} kN: {total} cases, "
                           f"{n_ok} finished ok, {total - n_ok} failed or missing."))
    else:
        n_points = st.sizes["speed"] * st.sizes["radial_load"]
        blocks.append(Para(f"Grid: speed {speeds} °/s × radial load {loads} kN × {ensemble_text(ctx)}: "
                           f"{n_points} grid points, {total} runs, {n_ok} finished ok, {total - n_ok} failed "
                           f"or missing. Each realization starts the balls at random places within their "
                           f"pocket play (the seed); the metrics are shown as ensemble means with their "
                           f"standard errors."))
    matched, unmatched = status_lookup(ctx)
    rows = []
    for s in st["speed"].values:
        for l in st["radial_load"].values:
            for ri, r in enumerate(seeds if seeds is not None else [None]):
                at = st.sel(speed=s, radial_load=l)
                state = (at.isel({REALIZATION: ri}) if r is not None else at).item()
                if state == "ok" or (float(s), float(l)) in unlisted:
                    continue
                key = (float(s), float(l), None if r is None else float(r))
                rec = matched.get(key) or matched.get(key[:2] + (None,))
                reason = rec[1] if rec and rec[1] else "no reason recorded"
                if rec and rec[0] == "failed" and state in ("not_run", "no_data"):
                    state = "failed"  # the grid only knows the case file is missing
                if state == "no_data":
                    state = "flagged ok but holds no data"
                cid = rec[2] if rec else "-"
                rows.append([fmt_speed(s), fmt_kn(l)] + ([f"seed {fmt_number(r, 6)}"] if r is not None else [])
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
    dims = extra_dims(ctx.metrics)
    if dims:
        def first(d):
            if d not in ctx.metrics.coords:
                return "index 0"
            units = str(ctx.metrics[d].attrs.get("units", ""))
            return f"{fmt_number(ctx.metrics[d].values[0], 4)} {units if units not in ('', '1') else ''}".strip()

        blocks.append(Para("Extra sweep dimensions: " + "; ".join(
            f"{d} ({ctx.metrics.sizes[d]} values); figures and the comparison use the first, {first(d)}"
            for d in dims) + "."))
    return blocks


def section_sensors(ctx: Context):
    """The virtual sensors: name, the ring point each reads [mm] and its direction."""
    sens = sensors(ctx.metrics)
    if not sens:
        return []
    rows = [[f"`{sn.name}`", "(" + ", ".join(fmt_number(v * 1e3 + 0.0, 5) for v in sn.position) + ")",
             "(" + ", ".join(fmt_number(v + 0.0, 3) for v in sn.direction) + ")"] for sn in sens]
    return [Heading(2, "Displacement sensors"),
            Para("Virtual sensors fixed in space, each reading the displacement of one point of the inner "
                 "ring (position in the unloaded, centred ring, bearing frame, z along the axis) along its "
                 "measuring direction:"),
            Table(["sensor", "position [mm]", "direction"], rows),
            Para("The study measured the ring with laser displacement sensors aimed at the ring, so a sensor "
                 "reading, which includes the ring's tilt, is the closer comparison with its δ. δ_r and δ_a "
                 "in the figures and tables are at the ring centre unless a sensor is named; the comparison "
                 "with the study's fits uses δ_r and δ_a at the ring centre.")]


def _last_time(ctx: Context) -> float:
    """The last output time of the sweep [s] (NaN without one)."""
    t = np.asarray(ctx.sweep["elapsed_time"].values, dtype=np.float64) if "elapsed_time" in ctx.sweep.coords else np.zeros(0)
    return float(t.max()) if t.size else math.nan


def window_coverage(ctx: Context, windows) -> str:
    """Sentences on windows that reach beyond the last output time; '' when none does."""
    t_end = _last_time(ctx)
    if not math.isfinite(t_end):
        return ""
    out = []
    for name, (a, b) in windows.items():
        if a >= t_end:
            out.append(f"the {PHASE_TITLE.get(name, name)} window ({fmt_number(a, 4)}–{fmt_number(b, 4)} s) has no data")
        elif b > t_end:
            out.append(f"the {PHASE_TITLE.get(name, name)} window's metrics cover only {fmt_number(a, 4)}–{fmt_number(t_end, 4)} s")
    if not out:
        return ""
    return f" The simulation ends at {fmt_number(t_end, 4)} s: " + "; ".join(out) + "."


def _range_signals(ctx: Context) -> list:
    """``[(flag variable, what, sensor flag or None)]`` of every range with a window-edge flag."""
    out = []
    for disp in ("radial", "axial"):
        if f"{disp}_displacement_range_at_edge" in ctx.metrics:
            out.append((f"{disp}_displacement_range_at_edge", CENTRE_LABEL[disp], None))
    if f"{SENSOR}_displacement_range_at_edge" in ctx.metrics:
        for sn in sensors(ctx.metrics):
            out.append((f"{SENSOR}_displacement_range_at_edge", sn.label(), sn.value))
    return out


def section_window_edges(ctx: Context) -> list:
    """Per phase and range: the grid points (or realizations) whose extreme lies at the window's edge.

    Reads the ``*_range_at_edge`` flags (1 where the largest or smallest value lies within
    one output interval of the start or end of the phase window).
    """
    windows = ctx.windows
    signals = _range_signals(ctx)
    if not signals:
        return []
    m = on_base_grid(ctx.metrics, first_realization=False)
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
                        listed.append(f"{fmt_speed(sp)}, {fmt_kn(ld)}"
                                      + (f" ({nf} of {int(finite[i, j].sum())})" if seeds is not None else ""))
            where = "; ".join(listed[:_MAX_LISTED]) + (f"; and {len(listed) - _MAX_LISTED} more"
                                                       if len(listed) > _MAX_LISTED else "")
            if seeds is None:
                count = f"{n_flag} of {n} grid points"
            else:
                count = (f"{n_flag} of {n} runs ({fmt_number(100.0 * n_flag / n, 3)} % of realizations), "
                         f"at {len(listed)} of {int(finite.any(axis=-1).sum())} grid points")
            rows.append([PHASE_TITLE[phase], f"range of {what}", count, where])
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
                           + ", ".join(f"{PHASE_TITLE[p]} ({fmt_number(windows[p][0], 4)}–{fmt_number(windows[p][1], 4)} s)"
                                       if p in windows else PHASE_TITLE[p] for p in empty)
                           + f" window{'s' if len(empty) > 1 else ''}"
                           + (f"; the simulation ends at {fmt_number(_last_time(ctx), 4)} s." if math.isfinite(_last_time(ctx))
                              else ".")))
    return blocks


def section_cage_slip(ctx: Context) -> list:
    """Cage slip against the epicyclic speed at the actual and at the nominal contact angle.

    A figure of the steady cage slip against speed and load and a table at the extreme
    finished grid points (:func:`.select.extreme_points`) per phase.
    """
    present = [(n, w) for n, w in CAGE_SLIPS if n in ctx.metrics]
    if not present:
        return []
    blocks = [Heading(2, "Cage slip")]
    alpha = bearing_numbers(ctx)["alpha"]
    defs = {"cage_slip": "`cage_slip` = 1 − ω̄_c/ω_epi against the epicyclic cage speed "
                         "ω_epi = ω_i/2·(1 − D·cos α/d_m) at the loaded balls' actual contact angles "
                         "(their mean cos α, time-averaged over the phase)",
            "cage_slip_nominal": "`cage_slip_nominal` against the epicyclic speed at the nominal contact angle"
                                 + (f" α = {fmt_number(math.degrees(alpha), 4)}°" if math.isfinite(alpha) else "")}
    text = ("Cage slip, positive when the cage lags its rolling-without-slip speed: "
            + "; ".join(defs[n] for n, _ in present) + ".")
    if len(present) < len(CAGE_SLIPS):
        missing = [n for n, _ in CAGE_SLIPS if n not in ctx.metrics]
        text += f" The sweep holds no {', '.join(f'`{n}`' for n in missing)} (written by an older version)."
    blocks.append(Para(text))
    specs = axis_specs(ctx, "steady")
    p = ctx.figure_path("cage_slip_steady.png")
    notes = figure_cage_slip(ctx, "steady", specs, p)
    ens = ensemble_text(ctx)
    blocks.append(Para("Steady-phase cage slip in %, "
                       + ("each row's own cage against its own epicyclic speed, a colour per row and definition, "
                          if rows_of(ctx.metrics, present[0][0]) != [None] else "")
                       + (f"ensemble means of {ens} with ±1 standard-error bars, the individual realizations "
                          "as faint small points just left of their mean; the two definitions are set slightly "
                          "apart along the axis, " if ens else "one marker per case, ")
                       + "; ".join(notes) + "."))
    blocks.append(Image(f"figures/{p.name}", "steady cage slip against speed and load"))
    rows = []
    bearing_rows = rows_of(ctx.metrics, present[0][0])
    for (sp, ld) in extreme_points(ctx):
        for phase in PHASES:
            for r in bearing_rows:
                vals = [metric_stat(ctx, n, sp, ld, phase, row=r) for n, _ in present]
                if not any(math.isfinite(v[0]) for v in vals):
                    continue
                epi = metric_stat(ctx, "epicyclic_cage_speed", sp, ld, phase, row=r)
                rows.append([fmt_speed(sp), fmt_kn(ld), PHASE_TITLE[phase]] + ([str(r)] if r is not None else [])
                            + [fmt_mean_se(m_, se, 100.0) for m_, se in vals] + [fmt_mean_se(*epi, scale=180.0 / math.pi)])
    if rows:
        blocks.append(Para("At the extreme cases, per phase" + (f" (ensemble mean ± standard error of {ens})"
                                                                 if ens else "") + ":"))
        blocks.append(Table(["speed", "radial load", "phase"] + (["row"] if bearing_rows != [None] else [])
                            + [f"`{n}` ({w}) [%]" for n, w in present] + ["ω_epi, actual angles [°/s]"],
                            rows))
    return blocks


