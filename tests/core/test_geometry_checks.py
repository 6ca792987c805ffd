"""rvcore.bearing.checks: each check fires exactly where the geometry, worked out here from
the dimensions, says the bearing cannot be built, and says so by its kind (no caller
reads the message text)."""
from __future__ import annotations

import dataclasses
import math

from rvcore.bearing.checks import BALL_OVERLAP, Problem, bearing_problems, cage_problems, geometry_problems, pair_problems
from rvcore.statics.preload import mirrored_rows

from .physics_cases import STUDY_D, STUDY_DM, STUDY_WIDTH, section_bearing


def _kinds(problems) -> list:
    return [p.kind for p in problems]


def _with_cage(bearing, **changes):
    row = bearing.rows[0]
    return dataclasses.replace(bearing, rows=(dataclasses.replace(row, cage=dataclasses.replace(row.cage, **changes)),))


def test_the_section_with_12_balls_is_buildable():
    assert bearing_problems(section_bearing(12)) == []


def test_the_studys_51_balls_are_recognised_as_ball_overlap_by_kind():
    # neighbouring centres are d_m·sin(π/Z) apart: 351.5 mm · sin(π/51) < 23 mm
    assert STUDY_DM * math.sin(math.pi / 51) < STUDY_D
    problems = bearing_problems(section_bearing(51))
    assert _kinds(problems) == [BALL_OVERLAP]
    (p,) = problems
    assert isinstance(p, Problem) and p.key == "rows[0].balls.count" and p.value == 51
    # the largest count that fits is no overlap at all
    z_fit = max(z for z in range(3, 60) if STUDY_DM * math.sin(math.pi / z) >= STUDY_D)
    assert BALL_OVERLAP not in _kinds(geometry_problems(section_bearing(z_fit)))
    assert BALL_OVERLAP in _kinds(geometry_problems(section_bearing(z_fit + 1)))


def test_only_the_overlap_has_the_overlap_kind():
    b = section_bearing(51)
    b = dataclasses.replace(b, bore=0.3515 - 0.023)   # balls now reach the bore too: d_m − D ≤ bore
    kinds = _kinds(geometry_problems(b))
    assert kinds.count(BALL_OVERLAP) == 1 and "balls_reach_bore" in kinds


def test_cage_width_against_the_bearing_and_its_pockets():
    b = section_bearing(12)
    pocket = STUDY_D + b.rows[0].cage.pocket_clearance
    assert _kinds(cage_problems(_with_cage(b, width=STUDY_WIDTH + 1e-4))) == ["cage_width"]
    assert _kinds(cage_problems(_with_cage(b, width=pocket))) == ["cage_pockets"]       # w ≤ D + c_p
    assert cage_problems(_with_cage(b, width=pocket + 1e-4)) == []


def test_an_outer_land_needs_room_below_the_groove_bottom():
    b = section_bearing(12)
    cage = b.rows[0].cage
    room = (STUDY_DM + STUDY_D) - cage.outer_diameter    # the land bore d_o + 2·c_land must stay below d_m + D
    assert _kinds(cage_problems(_with_cage(b, land_clearance=room / 2))) == ["cage_land"]
    assert cage_problems(_with_cage(b, land_clearance=room / 2 * 0.99)) == []
    assert cage_problems(_with_cage(b, land_clearance=room, guidance="ball")) == []


def test_a_pairs_rows_must_clear_each_other_and_fit_the_width():
    b = section_bearing(12)
    row, cage_w = b.rows[0], b.rows[0].cage.width

    def pair(spacing, width):
        return dataclasses.replace(b, rows=mirrored_rows(row, "back-to-back", spacing), arrangement="back-to-back",
                                   width=width)

    wide = 1.0
    assert _kinds(pair_problems(pair(0.9 * STUDY_D, wide))) == ["pair_balls"]
    assert _kinds(pair_problems(pair(0.5 * (STUDY_D + cage_w), wide))) == ["pair_cages"]   # D ≤ s < w
    s = 1.1 * cage_w
    assert pair_problems(pair(s, s + max(STUDY_D, cage_w))) == []
    assert _kinds(pair_problems(pair(s, 0.99 * (s + max(STUDY_D, cage_w))))) == ["pair_width"]
    assert pair_problems(b) == []   # not a pair
