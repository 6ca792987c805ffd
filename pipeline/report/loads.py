"""The load distribution of the bearing at the extreme operating points of the sweep.

The statics at the steady operating point of the cases at the corners of the sweep's
loads (the smallest and the largest radial load, axial load, tilting moment, preload) are
solved when the sweep runs (:mod:`pipeline.run.corners`) and stored in ``statics.nc``
(:mod:`pipeline.io.statics`): the load of every ball per row and azimuth, each row's
radial and axial load. This module reads them and plots them; it computes no physics.
A results folder without ``statics.nc`` (written before the statics were stored, or with
no finished case) gets a section that says so and how to get them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from rvcore.dynamics.ring_modes import DYNAMICS_MAX_ORDER
from rvcore.statics.flexible import MODE_TRUNCATION_LIMIT

from ..io.statics import FLEXIBLE_VARIABLES, STATICS_FILE
from .context import Context
from .figures import new_figure, save_figure
from .render import Heading, Image, Para, Table, Warning_, fmt_kn, fmt_number, fmt_speed
from .select import finished_points


@dataclass
class Corner:
    """The stored statics of one extreme case (SI), without the file's padding.

    Per ball: ``azimuth`` [rad] from +x, ``row_of_ball``, ``ball_load`` [N] per arc column
    of its row, whose ring ``arc_ring`` gives (0 inner, 1 outer); per row: its force on the
    inner ring, radial and axial [N], its axial position [m] and nominal contact angle
    [rad]. ``error`` says why a case has no equilibrium (``solved`` False).
    """

    case_id: str
    speed: float
    radial_load: float
    axial_load: float
    moment: float
    load_angle: float
    preload: float
    solved: bool
    error: str = ""
    max_contact_load: float = math.nan
    azimuth: np.ndarray = None
    row_of_ball: np.ndarray = None
    ball_load: np.ndarray = None
    arc_ring: np.ndarray = None
    row_radial_load: np.ndarray = None
    row_axial_load: np.ndarray = None
    row_axial_position: np.ndarray = None
    row_contact_angle: np.ndarray = None
    flexible: dict = None
    # flexible rings (statics.nc's FLEXIBLE_VARIABLES): the compared numbers, each with its
    # "_rigid" twin, the rings' deformation and "ball_load_rigid"; None where the rings are rigid

    def label(self) -> str:
        """'390 °/s, 30 kN radial, 10 kN axial[, 2 kN m][, preload 2 kN]' at the steady point."""
        text = (f"{fmt_speed(math.degrees(self.speed))}, {fmt_kn(self.radial_load)} radial, "
                f"{fmt_kn(self.axial_load)} axial")
        if self.moment:
            text += f", {fmt_number(self.moment / 1e3, 4)} kN m"
        if self.preload:
            text += f", preload {fmt_kn(self.preload)}"
        return text

    def inner_columns(self) -> list:
        """The arc columns of the inner ring."""
        return [k for k in range(self.arc_ring.size) if int(self.arc_ring[k]) == 0]

    def row_label(self, r: int) -> str:
        """'row r (z = … mm, α = …°)'."""
        return (f"row {r} (z = {fmt_number(self.row_axial_position[r] * 1e3 + 0.0, 4)} mm, "
                f"α = {fmt_number(math.degrees(self.row_contact_angle[r]), 4)}°)")

    def azimuth_from_load(self) -> np.ndarray:
        """Each ball's azimuth from the radial load's direction, in (−180, 180] deg."""
        a = np.degrees(self.azimuth - self.load_angle)
        return -((-a + 180.0) % 360.0 - 180.0)


@dataclass
class StoredStatics:
    """``statics.nc`` as read: its corners, whether the ring's weight was included, and,
    when there is no file or it cannot be read, ``missing`` saying why (no corners)."""

    corners: list
    weight_included: bool = True
    missing: str = ""


def _corner(ds: xr.Dataset, i: int, errors: dict) -> Corner:
    """Corner ``i`` of ``statics.nc``, trimmed of the padding of smaller bearings."""
    c = ds.isel(corner=i)
    value = {k: float(c[k].values) for k in ("speed", "radial_load", "axial_load", "moment", "load_angle",
                                              "preload", "max_contact_load")}
    case_id = str(c["case_id"].values)
    solved = int(c["solved"].values) == 1
    if not solved:
        return Corner(case_id, **{k: v for k, v in value.items() if k != "max_contact_load"}, solved=False,
                      error=errors.get(case_id, "no equilibrium"))
    rows = np.asarray(c["ball_row"].values)
    balls = rows >= 0
    arcs = np.asarray(c["arc_ring"].values) >= 0
    n_rows = int(np.isfinite(c["row_axial_position"].values).sum())
    flexible = None
    if "flexible_rings" in c and int(c["flexible_rings"].values) == 1:
        names = [k for k, (dims, _, _) in FLEXIBLE_VARIABLES.items() if dims == ("corner",)]
        flexible = {k: float(c[k].values) for k in names + ["max_contact_load", "max_contact_pressure"]}
        flexible["ball_load_rigid"] = np.asarray(c["ball_load_rigid"].values)[np.ix_(balls, arcs)]
    return Corner(case_id, **value, solved=True, flexible=flexible,
                  azimuth=np.asarray(c["ball_azimuth"].values)[balls],
                  row_of_ball=rows[balls].astype(int),
                  ball_load=np.asarray(c["ball_load"].values)[np.ix_(balls, arcs)],
                  arc_ring=np.asarray(c["arc_ring"].values)[arcs],
                  **{k: np.asarray(c[k].values)[:n_rows] for k in ("row_radial_load", "row_axial_load",
                                                                   "row_axial_position", "row_contact_angle")})


def read_statics(directory: Path) -> StoredStatics:
    """The statics at the extreme operating points stored in ``<directory>/statics.nc``."""
    path = Path(directory) / STATICS_FILE
    if not path.is_file():
        return StoredStatics([], missing="absent")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            ds = ds.load()
    except (OSError, ValueError, RuntimeError) as exc:
        return StoredStatics([], missing=f"`{STATICS_FILE}` could not be read ({type(exc).__name__}: {exc})")
    errors = dict(e.split(": ", 1) for e in str(ds.attrs.get("statics_errors", "")).split(" | ") if ": " in e)
    try:
        corners = [_corner(ds, i, errors) for i in range(ds.sizes.get("corner", 0))]
    except KeyError as exc:   # a file of another layout
        return StoredStatics([], missing=f"`{STATICS_FILE}` lacks the variable {exc}")
    return StoredStatics(corners, weight_included=ds.attrs.get("ring_weight", "included") == "included")


def stored_statics(ctx: Context) -> StoredStatics:
    """:attr:`Context.statics`, read from the results folder the first time it is needed."""
    if ctx.statics is None:
        ctx.statics = read_statics(ctx.directory)
    return ctx.statics


def missing_statics_text(ctx: Context, stored: StoredStatics) -> str:
    """Why there is no load distribution to show, and how to get one."""
    if not finished_points(ctx):
        return "No case finished, so there are no statics at the extreme operating points to show."
    if stored.missing == "absent":
        name = str(ctx.sweep.attrs.get("sweep", "")) or ctx.directory.name
        return (f"The statics at the extreme operating points are not stored in this results folder "
                f"(`{STATICS_FILE}`): it was written before a sweep stored them. Running the sweep again into "
                f"it (`rvsweep sweep <sweep file> --out <folder>`, which writes `<folder>/{name}/`) reuses "
                "every finished case and stores them; then make the report again.")
    return f"The statics at the extreme operating points cannot be shown: {stored.missing}."


def figure_load_distribution(corners: list, path: Path) -> None:
    """Inner contact load [kN] against azimuth [deg], a line per row (and inner arc), a panel per case."""
    n = len(corners)
    ncols = min(n, 2)
    nrows = int(math.ceil(n / ncols))
    fig, axes = new_figure(nrows, ncols, (5.2 * ncols, 3.4 * nrows))
    for i, c in enumerate(corners):
        ax = axes[i // ncols, i % ncols]
        ax.set_title(c.label(), fontsize=8)
        if not c.solved:
            ax.text(0.5, 0.5, "no equilibrium", transform=ax.transAxes, ha="center", va="center",
                    fontsize=8, color="0.4")
            continue
        az = c.azimuth_from_load()
        cols = c.inner_columns()
        for r in range(c.row_axial_position.size):
            balls = np.flatnonzero(c.row_of_ball == r)
            order = balls[np.argsort(az[balls])]
            row_cols = [k for k in cols if np.any(c.ball_load[balls, k] > 0.0)] or cols[:1]
            for m, k in enumerate(row_cols):
                label = c.row_label(r) + (f", inner arc {cols.index(k)}" if len(row_cols) > 1 else "")
                ax.plot(az[order], c.ball_load[order, k] / 1e3, marker="o", ms=3, lw=1.0,
                        ls="-" if m == 0 else "--", color=f"C{r}", label=label)
                if c.flexible is not None:
                    ax.plot(az[order], c.flexible["ball_load_rigid"][order, k] / 1e3, lw=0.8, ls=":",
                            color=f"C{r}", label=label + ", rigid rings")
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


def _row_shares(corners: list) -> list:
    """The table's rows: each row's force on the inner ring, largest inner load, loaded balls."""
    rows = []
    for c in corners:
        if not c.solved:
            rows.append([c.label(), "-", "no equilibrium: " + c.error, "", "", ""])
            continue
        cols = c.inner_columns()
        for r in range(c.row_axial_position.size):
            balls = np.flatnonzero(c.row_of_ball == r)
            q = c.ball_load[np.ix_(balls, cols)] if cols else np.zeros((balls.size, 1))
            rows.append([c.label(), c.row_label(r), fmt_number(c.row_radial_load[r] / 1e3, 4),
                         fmt_number(c.row_axial_load[r] / 1e3, 4), fmt_number(q.max() / 1e3, 4),
                         f"{int((q.max(axis=1) > 0).sum())} of {balls.size}"])
    return rows


def section_load_distribution(ctx: Context) -> list:
    """The "Load distribution" section: figure and per-row table at the extreme cases, from
    ``statics.nc`` (:func:`stored_statics`)."""
    blocks = [Heading(2, "Load distribution")]
    stored = stored_statics(ctx)
    corners = stored.corners
    if not corners:
        blocks.append(Para(missing_statics_text(ctx, stored)))
        return blocks + mode_truncation_blocks(ctx)
    p = ctx.figure_path("load_distribution.png")
    figure_load_distribution(corners, p)
    several_rows = any(c.solved and c.row_axial_position.size > 1 for c in corners)
    blocks.append(Para(
        "The load of every ball at the inner ring at the steady operating point (the loads the profile "
        "applies in the middle of its steady phase) of the extreme cases of the sweep (the smallest and "
        "largest loads), one panel per case and one line per row"
        + (" (its axial position z and contact angle α)" if several_rows else "")
        + ". Quasi-static equilibrium of the inner ring with Hertz's law at every contact, the balls in "
        "equilibrium" + (" and the ring's weight" if stored.weight_included else " (the ring's weight left out)")
        + "; azimuth measured from the radial load's direction. Solved when the sweep ran, with each "
        f"case's own bearing, profile and operating point, and stored in `{STATICS_FILE}`."))
    blocks.append(Image(f"figures/{p.name}", "ball loads against azimuth at the extreme operating points"))
    blocks.append(Para("Each row's share of the load at those points (its force on the inner ring):"))
    blocks.append(Table(["case (steady loads)", "row", "radial load [kN]", "axial load [kN]",
                         "largest inner contact load [kN]", "loaded balls"], _row_shares(corners)))
    blocks += flexible_blocks(corners)
    blocks += mode_truncation_blocks(ctx)
    return blocks


#: The rows of the flexible-against-rigid table: (label, variable, scale, unit).
_COMPARED = (("largest contact load Q_max", "max_contact_load", 1e-3, "kN"),
             ("largest Hertz pressure", "max_contact_pressure", 1e-9, "GPa"),
             ("loaded balls", "loaded_ball_count", 1.0, ""),
             ("static safety s0 (4200 MPa/p_max)^3", "static_safety_factor", 1.0, ""),
             ("life L10r (ISO/TS 16281)", "reference_rating_life_L10r", 1e-6, "10^6 rev"),
             ("life L10 (ISO 281, the applied loads)", "basic_rating_life_L10", 1e-6, "10^6 rev"),
             ("radial stiffness", "radial_stiffness", 1e-6, "N/µm"),
             ("axial stiffness", "axial_stiffness", 1e-6, "N/µm"),
             ("tilting stiffness", "tilting_stiffness", 1e-3, "N m/mrad"))


def flexible_blocks(corners: list) -> list:
    """"Flexible rings against rigid rings": the compared numbers of each flexible corner
    beside the rigid rings' at the same loads, and the rings' deformation (none when every
    corner's rings are rigid)."""
    flexible = [c for c in corners if c.solved and c.flexible is not None]
    if not flexible:
        return []
    rows = []
    for c in flexible:
        f = c.flexible
        for label, name, scale, unit in _COMPARED:
            a, b = f[name], f[f"{name}_rigid"]
            change = fmt_number((a / b - 1.0) * 100.0, 3) + " %" if math.isfinite(a) and math.isfinite(b) and b else "-"
            rows.append([c.label(), label + (f" [{unit}]" if unit else ""), fmt_number(a * scale, 4),
                         fmt_number(b * scale, 4), change])
    deformation = []
    for c in flexible:
        for ring in ("inner", "outer"):
            values = [c.flexible[f"{ring}_ring_{k}"] for k in ("ovalisation", "max_radial_deformation",
                                                               "max_axial_deformation")]
            if all(math.isnan(v) for v in values):
                continue
            deformation.append([c.label(), ring] + [fmt_number(v * 1e6, 4) if math.isfinite(v) else "-"
                                                    for v in values])
    return [Heading(3, "Flexible rings against rigid rings"),
            Para("The bearing's rings are flexible in their supports (docs/model.md §16): the load distribution "
                 "above (solid lines) is theirs, the dotted lines are the rigid rings' at the same loads. The "
                 "numbers each way, and the change the flexible rings make:"),
            Table(["case (steady loads)", "quantity", "flexible rings", "rigid rings", "change"], rows),
            Para("The rings' deformation at those points, relative to their supports: the ovalisation is the "
                 "amplitude of the radial order k = 2 (the diameter changes by twice it):"),
            Table(["case (steady loads)", "ring", "ovalisation [µm]", "largest radial [µm]", "largest axial [µm]"],
                  deformation)]


#: The cases' truncation figure (rvcore.statics.flexible.mode_truncation), one a case.
TRUNCATION = "ring_mode_truncation"


def _file_orders(ctx: Context) -> str:
    """'inner ring 0–60, outer ring 0–60' from the stored bearing's ring supports ('' unknown)."""
    conf = getattr(ctx, "configuration", None)
    bearing = None if conf is None else conf.bearing
    if bearing is None:
        return ""
    parts = [f"{name} ring 0–{spec.max_order}" for name, spec in (("inner", bearing.inner_ring_support),
                                                                   ("outer", bearing.outer_ring_support))
             if spec is not None]
    return ", ".join(parts)


def _where(da, index: int) -> str:
    """' at 660 °/s, 30 kN' for the flat ``index`` of ``da`` (the sweep coordinates it has)."""
    at = dict(zip(da.dims, np.unravel_index(index, da.shape)))
    parts = []
    if "speed" in at:
        parts.append(fmt_speed(float(da["speed"].values[at["speed"]])))
    if "radial_load" in at:
        parts.append(fmt_kn(float(da["radial_load"].values[at["radial_load"]])))
    return " at " + ", ".join(parts) if parts else ""


def mode_truncation_blocks(ctx: Context) -> list:
    """The flexible rings' Fourier orders: ``statics.nc``'s corners keep the bearing file's,
    the cases' dynamics 0–6; each case's truncation figure (``ring_mode_truncation``), its
    largest over the sweep, and a warning where a case's exceeds
    :data:`rvcore.statics.flexible.MODE_TRUNCATION_LIMIT`. Nothing for rigid rings (no
    finite figure)."""
    if TRUNCATION not in ctx.metrics:
        return []
    da = ctx.metrics[TRUNCATION]
    v = np.asarray(da.values, dtype=np.float64)
    finite = np.isfinite(v)
    if not finite.any():
        return []
    k = int(np.nanargmax(np.where(finite, v, -np.inf)))
    largest, where = float(v.flat[k]), _where(da, k)
    above = int(np.count_nonzero(v[finite] > MODE_TRUNCATION_LIMIT))
    orders = _file_orders(ctx)
    limit = fmt_number(MODE_TRUNCATION_LIMIT * 100.0, 3)
    blocks = [Heading(3, "The flexible rings' Fourier orders"),
              Para(f"The corners' statics above (`{STATICS_FILE}`) keep every order the bearing file gives"
                   + (f" ({orders})" if orders else "") + f"; the cases' dynamics keep orders 0–{DYNAMICS_MAX_ORDER} "
                   "as states, and their steady outputs (stiffness, lives, film) are the statics on those "
                   "(docs/model.md §16.1). Each case records the difference at its steady operating point, "
                   f"`{TRUNCATION}`: the largest relative change of δ_r, δ_a and Q_max between the statics on "
                   f"orders 0–{DYNAMICS_MAX_ORDER} and on every order. Largest over the sweep: "
                   f"{fmt_number(largest * 100.0, 3)} %{where}"
                   + ("." if above else f", below the {limit} % to which the orders kept are held converged."))]
    if above:
        blocks.append(Warning_(
            f"**The ring modes kept are not converged for this seat:** `{TRUNCATION}` exceeds {limit} % at "
            f"{above} of {int(finite.sum())} cases (largest {fmt_number(largest * 100.0, 3)} %{where}). The seat's "
            "give under each ball needs orders the dynamics leave out, so the cases' ring deformation, transient "
            f"ranges and steady outputs miss it; the corners' statics above keep the file's orders (docs/model.md "
            "§16.1: the orders kept converge when the seat's local compliance under a ball is small against the "
            "contact's)."))
    return blocks
