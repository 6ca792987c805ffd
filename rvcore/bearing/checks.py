"""The geometry checks: what makes a bearing unbuildable, found on the dataclasses of
:mod:`rvcore.bearing.geometry` before any work starts.

Each check returns :class:`Problem` records: a ``kind`` a caller can act on (the ball
overlap of docs/model.md §10 is ``"ball_overlap"``, which a bearing file may accept as a
warning), the dotted key a bearing file would use, the value and the reason with its
numbers. Nothing here reads files or raises: the schema (:mod:`pipeline.schema.bearingfile`)
turns the first problem into its one-line error.
"""
from __future__ import annotations

from dataclasses import dataclass

from .geometry import Bearing, min_pitch_diameter
from .imperfections import Imperfections

__all__ = ["Problem", "BALL_OVERLAP", "geometry_problems", "cage_problems", "tolerance_class_problems",
           "pair_problems", "bearing_problems"]

#: The kind of the one problem a bearing file may turn into a warning (``allow_ball_overlap``).
BALL_OVERLAP = "ball_overlap"


@dataclass(frozen=True)
class Problem:
    """One reason a bearing cannot be built.

    Parameters
    ----------
    kind : str
        What is wrong, one word a caller can test (``"ball_overlap"``, ``"cage_width"``, ...).
    key : str
        Dotted path of the offending value as a bearing file nests it (``rows[0].balls.count``).
    value : object
        The offending value, SI [unit of the key].
    reason : str
        One sentence with the numbers, for the engineer.
    """

    kind: str
    key: str
    value: object
    reason: str


def _mm(x: float) -> str:
    return f"{x * 1e3:.4g} mm"


def geometry_problems(bearing: Bearing) -> list:
    """The envelope, the balls on their pitch circle, the groove arcs and the cage ring.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
        The bearing, SI.

    Returns
    -------
    list of Problem
        Empty when it can be built. Ball overlap (``Z`` balls of ``D`` need
        ``d_m ≥ min_pitch_diameter(Z, D)``) is reported with kind :data:`BALL_OVERLAP`;
        whether it is an error is the caller's decision.
    """
    out = []
    if bearing.outer_diameter <= bearing.bore:
        out.append(Problem("envelope", "envelope.outer_diameter", bearing.outer_diameter,
                           f"must exceed the bore ({bearing.bore * 1e3:.4g} mm)"))
    if bearing.inner_ring.shoulder_diameter <= bearing.bore:
        out.append(Problem("shoulder", "inner_ring.shoulder_diameter", bearing.inner_ring.shoulder_diameter,
                           f"must exceed the bore ({bearing.bore * 1e3:.4g} mm)"))
    for i, row in enumerate(bearing.rows):
        d, dm, z = row.ball_diameter, row.pitch_diameter, row.ball_count
        need = min_pitch_diameter(z, d)
        if dm < need:
            out.append(Problem(BALL_OVERLAP, f"rows[{i}].balls.count", z,
                               f"{z} balls of {d * 1e3:.4g} mm need a pitch diameter of at least "
                               f"{need * 1e3:.1f} mm; this bearing's is {dm * 1e3:.1f} mm"))
        if dm - d <= bearing.bore:
            out.append(Problem("balls_reach_bore", f"rows[{i}].pitch_diameter", dm,
                               f"balls of {d * 1e3:.4g} mm on this pitch reach the bore "
                               f"({(dm - d) * 1e3:.1f} mm ≤ {bearing.bore * 1e3:.1f} mm)"))
        if dm + d >= bearing.outer_diameter:
            out.append(Problem("balls_reach_outer_diameter", f"rows[{i}].pitch_diameter", dm,
                               f"balls of {d * 1e3:.4g} mm on this pitch reach the outer diameter "
                               f"({(dm + d) * 1e3:.1f} mm ≥ {bearing.outer_diameter * 1e3:.1f} mm)"))
        for ring, arcs in (("inner", row.inner_arcs), ("outer", row.outer_arcs)):
            if not arcs:
                out.append(Problem("groove_arcs", f"rows[{i}].{ring}_groove.arcs", [], "needs at least one arc"))
            for k, arc in enumerate(arcs):
                if arc.curvature_ratio <= 0.5:
                    out.append(Problem("curvature_ratio", f"rows[{i}].{ring}_groove.arcs[{k}].curvature_ratio",
                                       arc.curvature_ratio,
                                       f"groove radius {arc.curvature_ratio * d * 1e3:.4g} mm is not larger "
                                       f"than the ball radius {d / 2 * 1e3:.4g} mm (f must exceed 0.5)"))
        c = row.cage
        if c.inner_diameter >= c.outer_diameter:
            out.append(Problem("cage_bore", f"rows[{i}].cage.inner_diameter", c.inner_diameter,
                               "must be smaller than the cage outer diameter"))
        if c.inner_diameter <= bearing.inner_ring.shoulder_diameter:
            out.append(Problem("cage_shoulder", f"rows[{i}].cage.inner_diameter", c.inner_diameter,
                               f"the cage ({c.inner_diameter * 1e3:.4g} mm) does not clear the inner-ring "
                               f"shoulder ({bearing.inner_ring.shoulder_diameter * 1e3:.4g} mm)"))
        if c.outer_diameter >= bearing.outer_diameter:
            out.append(Problem("cage_outer_diameter", f"rows[{i}].cage.outer_diameter", c.outer_diameter,
                               f"the cage ({c.outer_diameter * 1e3:.4g} mm) does not fit inside the outer "
                               f"ring ({bearing.outer_diameter * 1e3:.4g} mm)"))
        if not (c.inner_diameter < dm + d and c.outer_diameter > dm - d):
            out.append(Problem("cage_reach", f"rows[{i}].cage", (c.inner_diameter, c.outer_diameter),
                               f"the cage ring ({c.inner_diameter * 1e3:.4g}–{c.outer_diameter * 1e3:.4g} mm) "
                               f"does not reach the balls ({(dm - d) * 1e3:.4g}–{(dm + d) * 1e3:.4g} mm)"))
        if c.guidance not in ("outer-land", "ball"):
            out.append(Problem("cage_guidance", f"rows[{i}].cage.guidance", c.guidance,
                               "must be 'outer-land' or 'ball'"))
    return out


def tolerance_class_problems(bearing: Bearing) -> list:
    """What each row's ISO 492 tolerance class cannot give this bearing
    (:func:`rvcore.standards.iso492.tolerance_problems`: a runout without a sourced row for
    its size, a default ball grade not made in its ball size), kind ``"tolerance_class"``."""
    return [p for row in bearing.rows for p in _tolerance(bearing, row)]


def _tolerance(bearing: Bearing, row) -> list:
    from ..standards.iso492 import tolerance_problems

    imp = row.imperfections
    if not isinstance(imp, Imperfections):   # a realized or perfect row: nothing left to source (issue 39)
        return []
    return [Problem("tolerance_class", key, value, reason) for key, value, reason in
            tolerance_problems(imp.tolerance_class, bearing.bore, bearing.outer_diameter, row.ball_diameter,
                               inner_given=imp.inner_eccentricity is not None,
                               outer_given=imp.outer_eccentricity is not None,
                               grade_given=bool(imp.ball_grade or imp.ball_diameter_deviation),
                               inner_axial_given=imp.inner_axial_amplitude is not None,
                               outer_axial_given=imp.outer_axial_amplitude is not None)]


def cage_problems(bearing: Bearing) -> list:
    """The cage in its bearing, beyond :func:`geometry_problems`.

    - the cage is no wider than the bearing (kind ``"cage_width"``), and wider than its
      pockets, ``w > D + c_p`` (kind ``"cage_pockets"``), or the pockets would cut the
      cage ring in two;
    - an outer-land guided cage's land bore ``d_cage,o + 2·c_land`` lies below the outer
      groove's bottom ``d_m + D`` (kind ``"cage_land"``), so that the outer ring has a land
      there at all.
    """
    return [p for i in range(len(bearing.rows)) for p in _cage(bearing, i)]


def _cage(bearing: Bearing, i: int) -> list:
    out = []
    row = bearing.rows[i]
    c = row.cage
    if c.width > bearing.width:
        out.append(Problem("cage_width", f"rows[{i}].cage.width", c.width,
                           f"the cage ({c.width * 1e3:.4g} mm) is wider than the bearing "
                           f"({bearing.width * 1e3:.4g} mm)"))
    pocket = row.ball_diameter + c.pocket_clearance
    if c.width <= pocket:
        out.append(Problem("cage_pockets", f"rows[{i}].cage.width", c.width,
                           f"the cage ({c.width * 1e3:.4g} mm) is not wider than its pockets "
                           f"({pocket * 1e3:.4g} mm = ball diameter + pocket clearance), so they "
                           "would cut the ring in two"))
    if c.guidance == "outer-land":
        land = c.outer_diameter + 2.0 * c.land_clearance
        groove_bottom = row.pitch_diameter + row.ball_diameter
        if land >= groove_bottom:
            out.append(Problem("cage_land", f"rows[{i}].cage.outer_diameter", c.outer_diameter,
                               f"the cage does not fit inside the outer ring: its guiding land's bore "
                               f"({land * 1e3:.4g} mm = cage OD + 2 × land clearance "
                               f"{c.land_clearance * 1e3:.4g} mm) is not below the outer groove's "
                               f"bottom ({groove_bottom * 1e3:.4g} mm = d_m + D), so the outer ring "
                               "has no land there"))
    return out


def pair_problems(bearing: Bearing) -> list:
    """A pair's two rows overlap each other or stick out of the envelope.

    Notes
    -----
    With ``s`` the spacing of the rows' centre planes, ``D`` the ball diameter and ``w``
    the cage width: the balls need ``s ≥ D`` (kind ``"pair_balls"``), the cages ``s ≥ w``
    (kind ``"pair_cages"``), and both rows fit the width ``B`` when
    ``s + max(D, w) ≤ B`` (kind ``"pair_width"``). Empty for a bearing that is not a pair.
    """
    if not bearing.arrangement:
        return []
    out = []
    z = sorted(r.axial_position for r in bearing.rows)
    spacing = z[-1] - z[0]
    row = bearing.rows[0]
    d, cage = row.ball_diameter, row.cage.width
    if spacing < d:
        out.append(Problem("pair_balls", "pair.row_spacing", spacing,
                           f"the two rows' balls ({_mm(d)}) overlap at a spacing of {_mm(spacing)}: the spacing "
                           "must be at least the ball diameter"))
    elif spacing < cage:
        out.append(Problem("pair_cages", "pair.row_spacing", spacing,
                           f"the two rows' cages ({_mm(cage)} wide) overlap at a spacing of {_mm(spacing)}: the "
                           "spacing must be at least the cage width"))
    extent = spacing + max(d, cage)
    if extent > bearing.width:
        out.append(Problem("pair_width", "pair.row_spacing", spacing,
                           f"the two rows span {_mm(extent)} (spacing + the wider of ball and cage, "
                           f"{_mm(max(d, cage))}), more than the envelope width {_mm(bearing.width)}"))
    return out


def bearing_problems(bearing: Bearing) -> list:
    """Every check, in the order a bearing file's errors are reported: :func:`geometry_problems`,
    then row by row :func:`tolerance_class_problems` and :func:`cage_problems`, then
    :func:`pair_problems`."""
    out = geometry_problems(bearing)
    for i, row in enumerate(bearing.rows):
        out += _tolerance(bearing, row) + _cage(bearing, i)
    return out + pair_problems(bearing)
