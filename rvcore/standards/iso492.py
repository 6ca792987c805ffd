"""Tolerance tables of the standards that set a bearing's imperfections, SI.

- ISO 492 (*Rolling bearings — Radial bearings — Geometrical product specifications
  (GPS) and tolerance values*): the radial runout of the assembled bearing's inner ring,
  ``K_ia``, over its bore ``d``, and of its outer ring, ``K_ea``, over its outside
  diameter ``D``, per tolerance class (Normal, 6, 5, 4).
- ISO 3290-1 (*Rolling bearings — Balls — Steel balls*): per ball grade, the variation of
  a ball's diameter ``V_Dws`` and the diameter variation of a lot ``V_DwL``.

Sources, value by value (the standards' own texts were not at hand):

- ``K_ia``, Normal: the bearing maker SRS's reproduction of ISO 492 ("Dimensional and
  running accuracy of deep groove ball bearings, normal tolerance class") for d up to
  250 mm; 250–630 mm from the ISO 492 table as bearing makers' catalogues (NSK, NTN)
  reproduce it, 60 µm at 315–400 mm as the project's issue read it there.
- ``K_ia``, classes 6, 5, 4 up to d = 50 mm: the Chinese bearing maker YCTOO's
  reproduction of ISO 492 ("Tolerance of inner ring (ISO)"); above, the same makers'
  catalogue tables as remembered, class 6 at 315–400 mm (30 µm) as the issue read it.
  Class 4 is tabulated here to d = 250 mm only.
- ``K_ea``, Normal: SRS's table (D 18–400 mm) and, converted from inches, Consolidated
  Bearings' ISO/ABMA table (D 6–630 mm; 0.0028 in = 71 µm at 315–400 mm).
- ``K_ea``, class 6: Consolidated Bearings' table, every row (in inches, converted).
- ``K_ea``, classes 5 and 4: catalogue tables as remembered; 20 and 13 µm at
  315–400 mm as the issue read them.
- ``V_Dws``, ``V_DwL``: ISO 3290-1 Table 1 as catalogues of ball makers reproduce it;
  G10's 0.25 and 0.5 µm as the issue gives them.

Rows marked "as remembered" are the ones to check against a copy of the standard before a
result is quoted against a tolerance class.
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
    "5": np.array([4, 4, 4, 5, 5, 6, 8, 10, 13, 15, 17, 20]) * 1e-6,
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


class ToleranceError(ValueError):
    """The tables carry no value for this class and size (said why)."""


def _lookup(limits, values, size: float, what: str, tolerance_class: str) -> float:
    k = int(np.searchsorted(limits, size - 1e-12))
    if k >= limits.size or not np.isfinite(values[k]):
        raise ToleranceError(f"ISO 492 {what} of class {tolerance_class} is not tabulated here for "
                             f"{size * 1e3:.4g} mm")
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


def ball_lot_variation(grade: str) -> float:
    """ISO 3290-1 ``V_DwL`` of ball grade ``grade`` [m]: the spread of the mean diameters of
    the balls of one lot, which is what a bearing's balls differ by."""
    if grade not in BALL_GRADES:
        raise ToleranceError(f"ball grade {grade!r} is not one of {', '.join(BALL_GRADES)}")
    return BALL_GRADES[grade][1]
