"""Tolerance tables of the standards that set a bearing's imperfections, SI.

- ISO 492 (*Rolling bearings — Radial bearings — Geometrical product specifications
  (GPS) and tolerance values*): the radial runout of the assembled bearing's inner ring,
  ``K_ia``, over its bore ``d``, and of its outer ring, ``K_ea``, over its outside
  diameter ``D``, per tolerance class (Normal, 6, 5, 4); the axial runouts of the
  assembled bearing's rings against their raceways, ``S_ia`` and ``S_ea``, and of the
  inner ring's face against its bore, ``S_d``, where ISO 492 gives them (classes 5, 4
  and 2 only), as total indicator readings.
- ISO 3290-1 (*Rolling bearings — Balls — Steel balls*): per ball grade, the variation of
  a ball's diameter ``V_Dws`` and the diameter variation of a lot ``V_DwL``.

Sources, value by value (the standards' own texts were not at hand). One catalogue
reproduces every class's table and agrees with each value below row by row: NSK's *Rolling
Bearings* (CAT. No. E1102e), Table 8.2 "Tolerances for Radial Bearings (excluding Tapered
Roller Bearings)", pages A60–A63 (read in a text copy of the catalogue), to a 400 mm bore for
class 5 and to 250 mm (bore) and 400 mm (outside diameter) for class 4; NTN's *Ball and
Roller Bearings* (CAT. No. 2203/E, Table 6.4) and ZKL's *Rolling Bearings* (Table 13, class
P4) give the same class 4 values. The sources read first, value by value:

- ``K_ia``, Normal: the bearing maker SRS's reproduction of ISO 492 ("Dimensional and
  running accuracy of deep groove ball bearings, normal tolerance class") for d up to
  250 mm; 250–630 mm from the ISO 492 table as bearing makers' catalogues (NSK, NTN)
  reproduce it, 60 µm at 315–400 mm as the project's issue read it there; every row to
  630 mm as the bearing maker GBB reproduces ISO 492's Normal class for its self-aligning
  (radial) bearings (gbbco.cn, "Tolerances", Table 1, column Kia).
- ``K_ia``, classes 6, 5, 4 up to d = 50 mm: the Chinese bearing maker YCTOO's
  reproduction of ISO 492 ("Tolerance of inner ring (ISO)"). Classes 6 and 5 above
  50 mm: NTN's catalogue *Ball and Roller Bearings* ("Bearing Tolerances", tolerance of
  radial bearings, inner rings, column Kia; read in its yumpu.com reproduction), which
  splits 120–180 mm at 150 mm with the same value on both sides: class 6 every row to
  630 mm (10, 13, 18, 20, 25, 30, 35, 40 µm from 50 mm on; 30 µm at 315–400 mm, as the
  issue read it), class 5 to 315 mm. Class 4 above 50 mm: NSK's Table 8.2 (above),
  column K_ia, class 4. Class 5 at 400–630 mm: the bearing dealer NodesHK's reproduction of ISO 492:2014's
  class 5 table (below, the axial runouts' source), column tKia: 17 and 19 µm (20 µm
  had once been carried for 500–630 mm without a source, issue 39); its rows up to
  400 mm agree with the values above. Class 4 is tabulated to d = 250 mm only: ISO 492
  gives it no value above (NSK's and NTN's tables show a dash there).
- ``K_ea``, Normal: SRS's table (D 18–400 mm) and, converted from inches, Consolidated
  Bearings' ISO/ABMA table (D 6–630 mm; 0.0028 in = 71 µm at 315–400 mm).
- ``K_ea``, class 6: Consolidated Bearings' table, every row (in inches, converted).
- ``K_ea``, class 5: NodesHK's class 5 table (below), column tKea, every row; class 4:
  NSK's Table 8.2, column K_ea, class 4, to D = 400 mm (no value above). 20 and 13 µm at
  315–400 mm as the issue read them.
- the axial runouts ``S_d`` (the inner ring's reference face with its bore), ``S_ia``
  and ``S_ea`` (the assembled bearing's inner and outer ring faces against their
  raceways), class 5, every row: the bearing dealer NodesHK's reproduction of ISO
  492:2014's class 5 tables ("P5 class tolerances for radial bearings", nodeshk.com,
  tech/bearing-data/P5-tolerances-radial.html, columns tSd, tSia, tSea; its tKia and
  tKea columns agree with the class-5 K_ia, K_ea above row by row). ISO 492 gives
  ``S_d``, ``S_ia``, ``S_ea`` for classes 5, 4 and 2 only: the Normal and class 6 tables
  reproduced by SRS, Consolidated Bearings and YCTOO carry no such column, and the
  Swiss maker WIB's table lists ``S_d`` as "-" for P0 and P6 (wib-bearings.com,
  "Tolerances"). Class 4: NSK's Table 8.2, columns S_d, S_ia (to d = 250 mm) and S_ea (to
  D = 400 mm), class 4; NTN's, ZKL's and, to an 80 mm bore, the maker manv.in's class 4
  tables agree (one catalogue, UBC's, reads 11 µm for S_ea at 250–315 mm where the three read 10),
  and WIB's ``S_d`` of 3 µm for d ≤ 18 mm. S_ia and S_ea apply to ball bearings only
  (NSK's footnote 5, NTN's 2).
  The table's footnote 3 on ``S_ia``/``S_ea`` was not in the reproduction read.
- ``V_Dws``, ``V_DwL``: ISO 3290-1 Table 1 as catalogues of ball makers reproduce it;
  G10's 0.25 and 0.5 µm as the issue gives them.
- the nominal ball diameters a grade is made up to (:data:`BALL_GRADE_MAX_DIAMETER`):
  ISO 3290's grade table as the ball maker Mingzhu (en.mzzcgq.com, "ISO 3290" grade table
  with nominal sizes) reproduces it: G3 and G5 up to 12.7 mm, G10 and G16 up to 25.4 mm,
  G20 up to 38.1 mm; the coarser grades' limits were not at hand.

Check the values against a copy of the standard before a result is quoted against a
tolerance class: every source above is a reproduction.
"""
from __future__ import annotations

import numpy as np

#: ISO 492 tolerance classes carried here.
TOLERANCE_CLASSES = ("normal", "6", "5", "4")

#: Upper ends ("incl.") of ISO 492's nominal bore ranges for K_ia [m]; the first range
#: starts at 2.5 mm.
BORE_LIMITS = np.array([10, 18, 30, 50, 80, 120, 180, 250, 315, 400, 500, 630]) * 1e-3
#: K_ia per class over :data:`BORE_LIMITS` [m]; NaN where the class has no value.
K_IA = {
    "normal": np.array([10, 10, 13, 15, 20, 25, 30, 40, 50, 60, 65, 70]) * 1e-6,
    "6": np.array([6, 7, 8, 10, 10, 13, 18, 20, 25, 30, 35, 40]) * 1e-6,
    "5": np.array([4, 4, 4, 5, 5, 6, 8, 10, 13, 15, 17, 19]) * 1e-6,
    "4": np.array([2.5, 2.5, 3, 4, 4, 5, 6, 8, np.nan, np.nan, np.nan, np.nan]) * 1e-6,
}

#: Upper ends of ISO 492's nominal outside-diameter ranges for K_ea [m]; the first range
#: starts at 6 mm.
OD_LIMITS = np.array([18, 30, 50, 80, 120, 150, 180, 250, 315, 400, 500, 630]) * 1e-3
#: K_ea per class over :data:`OD_LIMITS` [m].
K_EA = {
    "normal": np.array([15, 15, 20, 25, 35, 40, 45, 50, 60, 70, 80, 100]) * 1e-6,
    "6": np.array([8, 9, 10, 13, 18, 20, 23, 25, 30, 35, 40, 50]) * 1e-6,
    "5": np.array([5, 6, 7, 8, 10, 11, 13, 15, 18, 20, 23, 25]) * 1e-6,
    "4": np.array([3, 4, 5, 5, 6, 7, 8, 10, 11, 13, np.nan, np.nan]) * 1e-6,
}

#: The classes for which ISO 492 tabulates the axial runouts S_d, S_ia, S_ea (classes 5,
#: 4 and 2; class 2 is not carried here): Normal and 6 have none, left to the user.
AXIAL_RUNOUT_CLASSES = ("5", "4")

#: ISO 492 S_ia, the assembled bearing's inner ring face runout against its raceway, over
#: :data:`BORE_LIMITS` [m]; NaN: no value in ISO 492 for the class (module docstring).
S_IA = {
    "5": np.array([7, 7, 8, 8, 8, 9, 10, 13, 15, 20, 23, 25]) * 1e-6,
    "4": np.array([3, 3, 4, 4, 5, 5, 7, 8, np.nan, np.nan, np.nan, np.nan]) * 1e-6,
}
#: ISO 492 S_d, the inner ring's reference face runout with its bore, over
#: :data:`BORE_LIMITS` [m].
S_D = {
    "5": np.array([7, 7, 8, 8, 8, 9, 10, 11, 13, 15, 18, 20]) * 1e-6,
    "4": np.array([3, 3, 4, 4, 5, 5, 6, 7, np.nan, np.nan, np.nan, np.nan]) * 1e-6,
}
#: ISO 492 S_ea, the assembled bearing's outer ring face runout against its raceway, over
#: :data:`OD_LIMITS` [m].
S_EA = {
    "5": np.array([8, 8, 8, 10, 11, 13, 14, 15, 18, 20, 23, 25]) * 1e-6,
    "4": np.array([5, 5, 5, 5, 6, 7, 8, 10, 10, 13, np.nan, np.nan]) * 1e-6,
}

#: ISO 3290-1 ball grades: (V_Dws, V_DwL) [m].
BALL_GRADES = {
    "G3": (0.08e-6, 0.13e-6), "G5": (0.13e-6, 0.25e-6), "G10": (0.25e-6, 0.5e-6),
    "G16": (0.4e-6, 0.8e-6), "G20": (0.5e-6, 1.0e-6), "G24": (0.6e-6, 1.2e-6),
    "G28": (0.7e-6, 1.4e-6), "G40": (1.0e-6, 2.0e-6), "G60": (1.5e-6, 3.0e-6),
    "G100": (2.5e-6, 5.0e-6),
}

#: The ball grade a tolerance class implies when the bearing file names none. Not a
#: standard's rule (ISO 492 does not name ball grades): the grades bearing makers commonly
#: fit in each class, an assumption stated wherever it is used.
DEFAULT_BALL_GRADE = {"normal": "G20", "6": "G16", "5": "G10", "4": "G5"}

#: Largest nominal ball diameter each grade is made in [m], where a source gives it
#: (module docstring): G3, G5 to 1/2 in, G10, G16 to 1 in, G20 to 1 1/2 in.
BALL_GRADE_MAX_DIAMETER = {"G3": 12.7e-3, "G5": 12.7e-3, "G10": 25.4e-3, "G16": 25.4e-3, "G20": 38.1e-3}


class ToleranceError(ValueError):
    """The tables carry no value for this class and size (said why)."""


def _lookup(limits, values, size: float, what: str, tolerance_class: str) -> float:
    """``values`` at ``size`` [m] over the ranges ending at ``limits``; refused beyond the
    class's last value, saying where its table ends: a class whose values stop before the
    ranges do (NaN after them) ends where ISO 492 gives it no more (class 4)."""
    k = int(np.searchsorted(limits, size - 1e-12))
    if k >= limits.size or not np.isfinite(values[k]):
        given = np.flatnonzero(np.isfinite(values))
        end = limits[given[-1]] * 1e3 if given.size else 0.0
        dimension = "a bore" if limits is BORE_LIMITS else "an outside diameter"
        why = (f"ISO 492 gives class {tolerance_class}'s {what} to {dimension} of {end:.0f} mm"
               if given.size and given[-1] < limits.size - 1 else f"the tables here end at {end:.0f} mm")
        raise ToleranceError(f"ISO 492 {what} of class {tolerance_class} is not tabulated here for "
                             f"{size * 1e3:.4g} mm ({why}); give the eccentricity itself")
    return float(values[k])


def inner_runout(bore: float, tolerance_class: str) -> float:
    """ISO 492 ``K_ia`` of an inner ring of bore ``bore`` [m] in ``tolerance_class`` [m]."""
    if tolerance_class not in K_IA:
        raise ToleranceError(f"tolerance class {tolerance_class!r} is not one of {', '.join(TOLERANCE_CLASSES)}")
    return _lookup(BORE_LIMITS, K_IA[tolerance_class], bore, "K_ia", tolerance_class)


def outer_runout(outer_diameter: float, tolerance_class: str) -> float:
    """ISO 492 ``K_ea`` of an outer ring of outside diameter ``outer_diameter`` [m] [m]."""
    if tolerance_class not in K_EA:
        raise ToleranceError(f"tolerance class {tolerance_class!r} is not one of {', '.join(TOLERANCE_CLASSES)}")
    return _lookup(OD_LIMITS, K_EA[tolerance_class], outer_diameter, "K_ea", tolerance_class)


def _axial(table, limits, size: float, what: str, tolerance_class: str):
    """An axial runout of ``table`` for ``size`` [m], None for a class without one."""
    if tolerance_class not in TOLERANCE_CLASSES:
        raise ToleranceError(f"tolerance class {tolerance_class!r} is not one of {', '.join(TOLERANCE_CLASSES)}")
    if tolerance_class not in AXIAL_RUNOUT_CLASSES:
        return None
    try:
        return _lookup(limits, table[tolerance_class], size, what, tolerance_class)
    except ToleranceError as exc:
        raise ToleranceError(str(exc).replace("give the eccentricity itself",
                                              "give the raceway's axial amplitude itself")) from None


def inner_axial_runout(bore: float, tolerance_class: str):
    """ISO 492 ``S_ia`` of an assembled bearing's inner ring of bore ``bore`` [m] in
    ``tolerance_class`` [m]: the total indicator reading of its face against its raceway
    over a revolution; None where ISO 492 gives none for the class (Normal, 6).

    Raises
    ------
    ToleranceError
        The class has no value for this bore in the tables (class 4 beyond 250 mm,
        class 5 beyond 630 mm).
    """
    return _axial(S_IA, BORE_LIMITS, bore, "S_ia", tolerance_class)


def outer_axial_runout(outer_diameter: float, tolerance_class: str):
    """ISO 492 ``S_ea`` of an assembled bearing's outer ring of outside diameter
    ``outer_diameter`` [m] in ``tolerance_class`` [m], as :func:`inner_axial_runout`."""
    return _axial(S_EA, OD_LIMITS, outer_diameter, "S_ea", tolerance_class)


def face_runout_with_bore(bore: float, tolerance_class: str):
    """ISO 492 ``S_d`` of an inner ring of bore ``bore`` [m] in ``tolerance_class`` [m]: its
    reference face's runout against its bore, as :func:`inner_axial_runout`. Not a
    raceway's runout (the model's rings have true faces): for a reader of the tables."""
    return _axial(S_D, BORE_LIMITS, bore, "S_d", tolerance_class)


def axial_runout_limits(bore: float, outer_diameter: float, tolerance_class: str) -> tuple:
    """The class limits of the raceways' axial runout amplitudes ``(a_i, a_o)`` [m] a
    tolerance class allows a bearing of this bore and outside diameter: half of ``S_ia``
    and ``S_ea`` (a tilted plane's amplitude, :mod:`rvcore.bearing.imperfections`); None
    where the class has no value (Normal, 6: the user gives it).

    Raises
    ------
    ToleranceError
        As :func:`inner_axial_runout`.
    """
    s_i = inner_axial_runout(bore, tolerance_class)
    s_o = outer_axial_runout(outer_diameter, tolerance_class)
    return (None if s_i is None else s_i / 2, None if s_o is None else s_o / 2)


def ball_lot_variation(grade: str) -> float:
    """ISO 3290-1 ``V_DwL`` of ball grade ``grade`` [m]: the spread of the mean diameters of
    the balls of one lot, which is what a bearing's balls differ by."""
    if grade not in BALL_GRADES:
        raise ToleranceError(f"ball grade {grade!r} is not one of {', '.join(BALL_GRADES)}")
    return BALL_GRADES[grade][1]


def default_ball_grade(tolerance_class: str, ball_diameter: float) -> str:
    """The ball grade a tolerance class implies for balls of ``ball_diameter`` [m].

    Parameters
    ----------
    tolerance_class : str
        One of :data:`TOLERANCE_CLASSES`.
    ball_diameter : float
        Nominal ball diameter ``D_w`` [m].

    Returns
    -------
    str
        :data:`DEFAULT_BALL_GRADE`'s grade where ISO 3290 makes it in that size
        (:data:`BALL_GRADE_MAX_DIAMETER`), else the next coarser grade that is made in it
        (class 4's G5 is made to 12.7 mm only: a 23 mm ball takes G10).

    Raises
    ------
    ToleranceError
        No grade from the class's own onwards is known to be made in this size (one line:
        name ``imperfections.ball_grade`` in the bearing file).
    """
    if tolerance_class not in DEFAULT_BALL_GRADE:
        raise ToleranceError(f"tolerance class {tolerance_class!r} is not one of {', '.join(TOLERANCE_CLASSES)}")
    grades = list(BALL_GRADES)
    start = DEFAULT_BALL_GRADE[tolerance_class]
    for grade in grades[grades.index(start):]:
        limit = BALL_GRADE_MAX_DIAMETER.get(grade)
        if limit is None:
            break
        if ball_diameter <= limit + 1e-12:
            return grade
    raise ToleranceError(f"class {tolerance_class}'s default ball grade {start} is made up to "
                         f"{BALL_GRADE_MAX_DIAMETER[start] * 1e3:.4g} mm, and no coarser grade is known here to be "
                         f"made in {ball_diameter * 1e3:.4g} mm balls (ISO 3290); name imperfections.ball_grade")


def tolerance_problems(tolerance_class: str, bore: float, outer_diameter: float, ball_diameter: float, *,
                       inner_given: bool = False, outer_given: bool = False, grade_given: bool = False,
                       inner_axial_given: bool = False, outer_axial_given: bool = False) -> list:
    """What a tolerance class cannot give this bearing, as ``(key, value, reason)`` before
    any work starts: an ISO 492 runout without a row for its size (unless the
    eccentricity, or the raceway's axial amplitude, is given), a default ball grade not
    made in its ball size (unless a grade is named). Empty for no class."""
    if not tolerance_class:
        return []
    out = []
    checks = []
    if not inner_given:
        checks.append(lambda: inner_runout(bore, tolerance_class))
    if not outer_given:
        checks.append(lambda: outer_runout(outer_diameter, tolerance_class))
    if not inner_axial_given:
        checks.append(lambda: inner_axial_runout(bore, tolerance_class))
    if not outer_axial_given:
        checks.append(lambda: outer_axial_runout(outer_diameter, tolerance_class))
    if not grade_given:
        checks.append(lambda: default_ball_grade(tolerance_class, ball_diameter))
    for check in checks:
        try:
            check()
        except ToleranceError as exc:
            out.append(("imperfections.tolerance_class", tolerance_class, str(exc)))
    return out
