"""``statics.nc``: the quasi-static load distribution at the sweep's extreme operating points.

When a sweep finishes, :mod:`pipeline.run.corners` solves the statics at the steady
operating point of the finished cases at the corners of the sweep's loads and hands them
here as plain arrays, one :class:`CornerStatics` per corner; this module alone decides the
file's names, dimensions, units and long names. The report reads the file and computes
nothing.

Layout (CF-1.8, SI):

- dimension ``corner``: one extreme operating point each, with the string coordinate
  ``case_id`` (its file ``cases/<case_id>.nc``);
- dimensions ``ball`` (every ball of every row, in order), ``arc`` (a row's raceway arcs,
  inner first) and ``row``; a corner whose bearing has fewer balls, arcs or rows than
  another is padded with NaN (and ``-1`` in the integer variables);
- the variables of :data:`STATICS_VARIABLES`; where a bearing's rings are flexible
  (docs/model.md §16), those of :data:`FLEXIBLE_VARIABLES` too: the variables above are
  then the flexible rings', and each compared number has its rigid rings' value beside it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from .. import __version__
from .case import REFERENCES
from .files import history_line, write_atomic
from .netcdf import combined_encoding

#: The file's name in a results folder.
STATICS_FILE = "statics.nc"

#: name -> (dims, units, long_name) of every variable of ``statics.nc``.
STATICS_VARIABLES = {
    "speed": (("corner",), "rad s-1", "steady inner-ring speed of the case"),
    "radial_load": (("corner",), "N", "radial load the profile applies in the middle of its steady phase"),
    "axial_load": (("corner",), "N", "axial load the profile applies in the middle of its steady phase"),
    "moment": (("corner",), "N m", "tilting moment the profile applies in the middle of its steady phase, "
                                   "about the axis normal to the radial load"),
    "load_angle": (("corner",), "rad", "direction of the radial load from +x"),
    "preload": (("corner",), "N", "axial preload of the pair of rows (0 without one)"),
    "solved": (("corner",), "1", "1 where the statics found an equilibrium, 0 where they did not"),
    "radial_displacement": (("corner",), "m", "inner-ring displacement along the radial load at the equilibrium"),
    "axial_displacement": (("corner",), "m", "inner-ring axial displacement at the equilibrium"),
    "max_contact_load": (("corner",), "N", "largest ball-race normal force at the equilibrium"),
    "max_contact_pressure": (("corner",), "Pa", "largest Hertz contact pressure at the equilibrium"),
    "ball_azimuth": (("corner", "ball"), "rad", "azimuth of each ball from +x"),
    "ball_row": (("corner", "ball"), "1", "row of each ball (-1: no such ball in this corner's bearing)"),
    "ball_load": (("corner", "ball", "arc"), "N", "normal force of each ball on each raceway arc of its row "
                                                  "(0 where unloaded)"),
    "contact_angle": (("corner", "ball", "arc"), "rad", "contact angle of each ball on each raceway arc of its "
                                                       "row, from the bearing's radial plane (NaN where unloaded)"),
    "arc_ring": (("corner", "arc"), "1", "ring of each arc column: 0 inner, 1 outer (-1: no such arc)"),
    "row_radial_load": (("corner", "row"), "N", "radial force each row applies to the inner ring "
                                                "(magnitude in the radial plane)"),
    "row_axial_load": (("corner", "row"), "N", "axial force each row applies to the inner ring (magnitude)"),
    "row_axial_position": (("corner", "row"), "m", "axial position of each row's ball centres"),
    "row_contact_angle": (("corner", "row"), "rad", "nominal contact angle of each row"),
}


def _flexible_variables() -> dict:
    """The variables of a sweep whose bearing has flexible rings (docs/model.md §16): the
    compared numbers (:data:`rvcore.statics.flexible.HEADLINE`) with the flexible rings and,
    beside each, with rigid rings (``_rigid``), and each ring's deformation
    (:data:`rvcore.statics.flexible.DEFORMATION`)."""
    from rvcore.statics.flexible import DEFORMATION, HEADLINE

    out = {"flexible_rings": (("corner",), "1", "1 where the bearing's rings are flexible in their supports (the "
                                                "other variables then are the flexible rings'), 0 where rigid"),
           "ball_load_rigid": (("corner", "ball", "arc"), "N", "normal force of each ball on each raceway arc "
                                                              "with rigid rings at the same loads")}
    for name, (units, what) in HEADLINE.items():
        if name in ("max_contact_load", "max_contact_pressure"):
            out[f"{name}_rigid"] = ((("corner",), units, f"{what}, rigid rings at the same loads"))
            continue
        out[name] = (("corner",), units, f"{what} at the equilibrium")
        out[f"{name}_rigid"] = (("corner",), units, f"{what}, rigid rings at the same loads")
    for ring in ("inner", "outer"):
        for name, (units, what) in DEFORMATION.items():
            out[f"{ring}_ring_{name}"] = (("corner",), units, f"{ring} ring: {what} (NaN where rigid)")
    return out


#: name -> (dims, units, long_name) of the variables a sweep with flexible rings adds.
FLEXIBLE_VARIABLES = _flexible_variables()

#: Integer variables and their dtype; padding is -1 (no such ball or arc).
_INTEGER = {"solved": np.int8, "ball_row": np.int16, "arc_ring": np.int8, "flexible_rings": np.int8}


@dataclass
class CornerStatics:
    """The statics of one extreme case, SI: the values of :data:`STATICS_VARIABLES` by name.

    ``values`` holds a float for each ``("corner",)`` variable and an array for the others
    (``ball``, ``(ball, arc)``, ``arc`` or ``row``); without an equilibrium only the
    operating point and ``solved = 0``, and ``error`` says why.
    """

    case_id: str
    values: dict = field(default_factory=dict)
    error: str = ""


def _padded(corners: list, name: str, dims: tuple) -> np.ndarray:
    """Variable ``name`` of every corner, padded to the largest extent of each dimension
    (NaN, or -1 for an integer variable), so that bearings of different sizes share a file."""
    integer = _INTEGER.get(name)
    fill, dtype = (-1, integer) if integer is not None else (np.nan, np.float64)
    if len(dims) == 1:
        return np.array([c.values.get(name, fill) for c in corners], dtype=dtype)
    arrays = {i: np.asarray(c.values[name]) for i, c in enumerate(corners) if name in c.values}
    shape = tuple(max((a.shape[k] for a in arrays.values()), default=0) for k in range(len(dims) - 1))
    out = np.full((len(corners), *shape), fill, dtype=dtype)
    for i, a in arrays.items():
        out[(i, *(slice(0, n) for n in a.shape))] = a
    return out


def statics_dataset(corners: list, *, gravity: bool, tilt: str, sweep_name: str = "") -> xr.Dataset:
    """``statics.nc``'s dataset of the extreme cases' statics.

    Parameters
    ----------
    corners : list of CornerStatics
        One per extreme case, in the order they are shown.
    gravity : bool
        Whether the ring's weight was part of the equilibrium.
    tilt : str
        How the inner ring's tilts were held: "free" or "held".
    sweep_name : str
        The sweep's name, for the title.
    """
    ds = xr.Dataset(coords={
        "corner": ("corner", np.arange(len(corners), dtype=np.int32),
                   {"units": "1", "long_name": "extreme operating point of the sweep (corner of its loads)"}),
        "case_id": ("corner", np.array([c.case_id for c in corners], dtype=object),
                    {"long_name": "id of the case at this corner (its file is cases/<case_id>.nc)"}),
    })
    variables = dict(STATICS_VARIABLES)
    if any(c.values.get("flexible_rings") for c in corners):
        variables.update(FLEXIBLE_VARIABLES)
    for name, (dims, units, long_name) in variables.items():
        ds[name] = (dims, _padded(corners, name, dims), {"units": units, "long_name": long_name})
    ds["solved"].attrs.update(flag_values=np.array([0, 1], dtype=np.int8), flag_meanings="no_equilibrium equilibrium")
    ds["arc_ring"].attrs.update(valid_min=np.int8(0), valid_max=np.int8(1))
    errors = [f"{c.case_id}: {c.error}" for c in corners if c.error]
    ds.attrs = {
        "Conventions": "CF-1.8",
        "title": f"Quasi-static load distribution at the extreme operating points of sweep '{sweep_name}'",
        "source": f"rv-bearing-sweep {__version__}: rvcore.statics.operating.steady_statics at each case's steady "
                  "operating point (the bearing's rings, rigid unless flexible_rings says otherwise, with rigid "
                  "rings beside; Hertz at every contact, balls in equilibrium)",
        "history": history_line(f"pipeline.run.corners: statics of {len(corners)} extreme case"
                                f"{'s' if len(corners) != 1 else ''}"),
        "references": REFERENCES,
        "ring_weight": "included" if gravity else "left out",
        "inner_ring_tilt": tilt,
        "statics_errors": " | ".join(errors),
    }
    return ds


def write_statics(ds: xr.Dataset, directory) -> Path:
    """Write ``ds`` as ``<directory>/statics.nc`` atomically."""
    enc = combined_encoding(ds, ("corner",))
    enc.pop("case_id", None)   # a string coordinate: no fill value or compression to set
    for e in enc.values():     # every corner without an equilibrium leaves a dimension empty
        if 0 in e.get("chunksizes", (1,)):
            del e["chunksizes"]
    return write_atomic(ds, Path(directory) / STATICS_FILE, encoding=enc)
