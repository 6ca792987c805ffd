"""A bearing file's flexible rings: ``[inner_ring.flexible]`` and ``[outer_ring.flexible]``
into :class:`rvcore.bearing.geometry.RingSupport`, and the FE support file they may name.

Each ring is rigid unless its table is there (docs/inputs.md, "Flexible rings"). The keys,
kinds, bounds and defaults are the schema's (:mod:`pipeline.schema.fields`); this module adds
what one field cannot say: a section is given whole (all five properties) or not at all,
a housing's section by its properties or as a rectangle, which keys each support takes,
and the FE file.

The FE support file (``support = "fe_file"``, ``file = "…"``, relative to the bearing file)
is CSV (RFC 4180, read by :mod:`csv`): lines starting with ``#`` are comments; the first
other line names the columns, the next gives each column's unit (pint spelling; ``order``'s
is empty or ``1``), then one line per Fourier order ``k = 0, 1, …, N`` in order::

    # carrier flange, reduced at the bearing seat
    order,radial_stiffness,axial_stiffness
    1,N/m,N/m
    0,5.1e10,2.2e10
    1,3.4e9,1.9e9
    …

The columns are ``order`` and either ``radial_stiffness`` and ``axial_stiffness`` (the
support's stiffness per unit modal amplitude, [N m⁻¹]) or ``radial_compliance`` and
``axial_compliance`` (their inverses, [m N⁻¹]; 0 compliance: held), as
:class:`rvcore.rings.support.OrderStiffness` defines them. Every problem is one line naming
the file, the line and the column.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

from rvcore.bearing.geometry import DEFAULT_RING_MAX_ORDER, INNER, OUTER, RingSupport
from rvcore.rings.section import section_from_envelope

from ..errors import ConfigError
from .fields import MAX_RING_ORDER
from .reader import Table
from .units import parse_quantity

__all__ = ["ring_supports", "check_ring_supports", "read_support_file", "SUPPORT_COLUMNS"]

#: The FE file's column sets: (radial, axial, kind of pipeline.schema.units.SI_UNITS).
SUPPORT_COLUMNS = (("radial_stiffness", "axial_stiffness", "stiffness"),
                   ("radial_compliance", "axial_compliance", "compliance"))

_SECTION_KEYS = ("area", "centroid_diameter", "i_in_plane", "i_out_of_plane", "torsion_constant")
_RECTANGLE_KEYS = ("inner_diameter", "outer_diameter", "width")

#: Which keys of ``[<ring>_ring.flexible]`` each support takes (besides max_order,
#: damping_ratio, section and shoulder_diameter).
_SUPPORT_KEYS = {"foundation": ("seat_radial_stiffness", "seat_axial_stiffness"),
                 "housing": ("seat_radial_stiffness", "seat_axial_stiffness", "housing"),
                 "fe_file": ("file",)}
_COMMON_KEYS = ("support", "max_order", "damping_ratio", "section", "shoulder_diameter")


def ring_supports(top: Table) -> dict:
    """``{"inner_ring_support": …, "outer_ring_support": …}`` of a bearing file (None: rigid).

    Parameters
    ----------
    top : pipeline.schema.reader.Table
        The bearing file's top level.
    """
    out = {}
    for ring, name in ((INNER, "inner"), (OUTER, "outer")):
        holder = top.table(f"{name}_ring", required=False)
        if name == "outer" and holder.data and not holder.has("flexible"):
            holder.raw("flexible")   # [outer_ring] holds only [outer_ring.flexible]
        t = holder.table("flexible", required=False) if holder.data else None
        out[f"{name}_ring_support"] = _ring_support(t, ring) if t is not None and t.data else None
    return out


def _ring_support(t: Table, ring: int) -> RingSupport:
    kind = t.get("support")
    for k in t.data:
        if k not in _COMMON_KEYS + _SUPPORT_KEYS[kind]:
            raise ConfigError(t.file, t.key(k), None if isinstance(t.data[k], dict) else t.data[k],
                              f"does not apply to support = \"{kind}\" (it takes "
                              + ", ".join(_COMMON_KEYS[1:] + _SUPPORT_KEYS[kind]) + ")")
    section = _given_section(t.table("section", required=False)) if t.has("section") else ()
    shoulder = 0.0
    if ring == OUTER:
        if t.has("shoulder_diameter") and section:
            raise ConfigError(t.file, t.key("shoulder_diameter"), t.raw("shoulder_diameter"),
                              "give either shoulder_diameter (the section from the envelope and groove) or "
                              "section.*, not both")
        if not section:
            shoulder = t.get("shoulder_diameter", default=None)
            if shoulder is None:
                raise ConfigError(t.file, t.key("shoulder_diameter"), None,
                                  "missing: the outer ring's section from the envelope needs its bore at the "
                                  "shoulders (or give section.*)")
    kw = {"kind": kind, "damping_ratio": t.get("damping_ratio"), "section": section,
          "shoulder_diameter": shoulder}
    if t.has("max_order"):
        kw["max_order"] = t.get("max_order")
    if kind == "foundation":
        for d in ("radial", "axial"):
            kw[f"seat_{d}"] = t.get(f"seat_{d}_stiffness", default=None)
            if kw[f"seat_{d}"] is None:
                raise ConfigError(t.file, t.key(f"seat_{d}_stiffness"), None,
                                  "missing: a foundation is its seat's stiffness per unit circumference "
                                  "(e.g. \"2e5 N/mm^2\")")
    elif kind == "housing":
        for d in ("radial", "axial"):
            kw[f"seat_{d}"] = t.get(f"seat_{d}_stiffness", default=math.inf)
        kw.update(_housing(t.table("housing")))
    else:
        orders, radial, axial = read_support_file(_support_path(t), t.file, t.key("file"))
        top_order = orders[-1]
        order = kw.setdefault("max_order", top_order)
        if order > top_order:
            raise ConfigError(t.file, t.key("max_order"), t.raw("max_order"),
                              f"the FE file gives orders up to {top_order} only")
        kw.update(orders=orders, radial_stiffness=radial, axial_stiffness=axial)
    kw.setdefault("max_order", DEFAULT_RING_MAX_ORDER)
    return RingSupport(**kw)


def _given_section(t: Table) -> tuple:
    """(area, centroid radius, I_in, I_out, J) [SI] of a section given whole."""
    missing = [k for k in _SECTION_KEYS if not t.has(k)]
    if missing:
        raise ConfigError(t.file, t.key(missing[0]), None,
                          "missing: a given section needs all of " + ", ".join(_SECTION_KEYS))
    values = {k: t.get(k, bounds="positive") for k in _SECTION_KEYS}
    values["centroid_diameter"] /= 2.0
    return tuple(values[k] for k in _SECTION_KEYS)


def _housing(t: Table) -> dict:
    """The housing's section (given, or a rectangle), material and ground [SI]."""
    given = [k for k in _SECTION_KEYS if t.has(k)]
    rectangle = [k for k in _RECTANGLE_KEYS if t.has(k)]
    if given and rectangle:
        raise ConfigError(t.file, t.key(rectangle[0]), t.raw(rectangle[0]),
                          "give the housing's section either by its properties (" + ", ".join(_SECTION_KEYS)
                          + ") or as a rectangle (" + ", ".join(_RECTANGLE_KEYS) + "), not both")
    if rectangle:
        missing = [k for k in _RECTANGLE_KEYS if k not in rectangle]
        if missing:
            raise ConfigError(t.file, t.key(missing[0]), None,
                              "missing: a rectangular housing section needs " + ", ".join(_RECTANGLE_KEYS))
        di, do, b = (t.get(k, bounds="positive") for k in _RECTANGLE_KEYS)
        if not do > di:
            raise ConfigError(t.file, t.key("outer_diameter"), t.raw("outer_diameter"),
                              "must exceed housing.inner_diameter")
        s = section_from_envelope(di / 2.0, do / 2.0, b)
        section = (s.area, s.centroid_radius, s.i_in_plane, s.i_out_of_plane, s.torsion_constant)
    else:
        section = _given_section(t)
    out = {"housing_section": section,
           "ground_radial": t.get("ground_radial_stiffness"), "ground_axial": t.get("ground_axial_stiffness")}
    if t.has("material"):
        from rvcore.bearing.geometry import Material

        m = t.table("material")
        out["housing_material"] = Material(m.get("density"), m.get("youngs_modulus"), m.get("poisson_ratio"))
    return out


def _support_path(t: Table) -> Path:
    name = t.get("file", default=None)
    if name is None:
        raise ConfigError(t.file, t.key("file"), None,
                          "missing: support = \"fe_file\" reads the support's stiffness per order from a file")
    path = Path(name).expanduser()
    if not path.is_absolute() and t.file not in (None, "<input>"):
        path = Path(str(t.file)).parent / path
    return path


def read_support_file(path, file="<input>", key: str | None = None) -> tuple:
    """The support's stiffness per order from an FE support file (module docstring).

    Parameters
    ----------
    path : str or Path
        The CSV file.
    file, key :
        The bearing file and key that name it, for the message when it cannot be read.

    Returns
    -------
    orders : tuple of int
        ``0, 1, …, N`` [-].
    radial, axial : tuple of float
        ``K_k^support`` [N m⁻¹] (``inf`` where a compliance is 0).

    Raises
    ------
    ConfigError
        Naming the file, the line and the column, with the reason.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(file, key, str(path), f"cannot read the FE support file ({exc.__class__.__name__}: "
                                                f"{getattr(exc, 'strerror', None) or exc})") from None
    lines = [(n, line) for n, line in enumerate(text.splitlines(), 1)
             if line.strip() and not line.lstrip().startswith("#")]
    rows = [(n, [c.strip() for c in r]) for (n, _), r in zip(lines, csv.reader(line for _, line in lines))]
    if len(rows) < 3:
        raise ConfigError(path, None, None, "needs a line of column names, a line of units and at least one "
                                            "order (docs/inputs.md)")
    (_, names), (unit_line, units) = rows[0], rows[1]
    columns = next((c for c in SUPPORT_COLUMNS if set(names) == {"order", c[0], c[1]}), None)
    if columns is None or len(names) != 3:
        raise ConfigError(path, "line 1", ",".join(names), "the columns must be order and either "
                          + " or ".join(f"{c[0]}, {c[1]}" for c in SUPPORT_COLUMNS))
    if len(units) != 3:
        raise ConfigError(path, f"line {unit_line}", ",".join(units), "the units line needs one unit per column")
    col = {name: i for i, name in enumerate(names)}
    kind = columns[2]
    scale = {}
    for c in columns[:2]:
        scale[c] = parse_quantity(f"1 {units[col[c]]}", kind, file=path, key=f"line {unit_line}, {c}")
    if units[col["order"]] not in ("", "1", "dimensionless"):
        raise ConfigError(path, f"line {unit_line}, order", units[col["order"]], "an order has no unit (leave it "
                                                                                 "empty)")
    orders, radial, axial = [], [], []
    for n, r in rows[2:]:
        if len(r) != 3:
            raise ConfigError(path, f"line {n}", ",".join(r), "needs one value per column (3)")
        try:
            k = int(r[col["order"]])
        except ValueError:
            raise ConfigError(path, f"line {n}, order", r[col["order"]], "must be an integer") from None
        if k != len(orders):
            raise ConfigError(path, f"line {n}, order", k, f"the orders must run 0, 1, 2, … in order (expected "
                                                           f"{len(orders)})")
        if k > MAX_RING_ORDER:
            raise ConfigError(path, f"line {n}, order", k, f"at most {MAX_RING_ORDER}")
        orders.append(k)
        for c, out in zip(columns[:2], (radial, axial)):
            try:
                v = float(r[col[c]])
            except ValueError:
                v = math.nan
            if not math.isfinite(v) or v < 0.0:
                raise ConfigError(path, f"line {n}, {c}", r[col[c]], "must be a finite number >= 0")
            v *= scale[c]
            out.append((math.inf if v == 0.0 else 1.0 / v) if kind == "compliance" else v)
    if len(orders) < 3:
        raise ConfigError(path, None, None, f"{len(orders)} orders: give k = 0, 1 and 2 at least (the support "
                                            "holds the ring's rigid-body orders; 2 is its ovalisation)")
    for c, values in zip(columns[:2], (radial, axial)):
        held = (1,) if c.startswith("radial") else (0, 1)
        for k in held:
            if values[k] == 0.0:
                raise ConfigError(path, f"order {k}, {c}", 0, "must be > 0: the ring's own stiffness is 0 at "
                                                              "this order (a rigid-body motion): the support "
                                                              "must hold it")
    return tuple(orders), tuple(radial), tuple(axial)


def check_ring_supports(bearing, file) -> None:
    """The flexible rings' modes built once (:func:`rvcore.rings.flexible.bearing_rings`): a
    section the grooves cut through, a support that leaves an order without stiffness, is
    said now, about the ring's table, not mid-run."""
    from rvcore.rings.flexible import bearing_rings

    for name in ("inner", "outer"):
        spec = getattr(bearing, f"{name}_ring_support")
        if spec is None:
            continue
        try:
            bearing_rings(_only(bearing, name))
        except ValueError as exc:
            raise ConfigError(file, f"{name}_ring.flexible", None, str(exc)) from None


def _only(bearing, name: str):
    """``bearing`` with only ring ``name`` flexible."""
    import dataclasses

    other = "outer" if name == "inner" else "inner"
    return dataclasses.replace(bearing, **{f"{other}_ring_support": None})
