"""A bearing of two rows reports every row: cage speeds and cage slips over a ``row`` axis.

The pair: two copies of the reduced 8-ball section, placed at z = ±s with mirrored
grooves (contact angles +α and −α: back to back), under a pure radial load. The pair is
symmetric under z → −z, so both cages must turn alike; and each must turn near its own
epicyclic speed ω_c = ½(1 − (D/d_m)·cos α)·ω_i, computed here from the geometry.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from pipeline.io import case_dataset
from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings
from rvcore.bearing.geometry import Arc
from rvcore.profile import OperatingPoint
from tests.core.physics_cases import STUDY_D, STUDY_DM, constant_profile, section_bearing

SPEED = math.radians(660.0)
ALPHA = math.radians(15.0)


def _pair():
    single = section_bearing(8, alpha=ALPHA)
    row = single.rows[0]
    spacing = 1.2 * STUDY_D
    mirrored = dataclasses.replace(
        row, axial_position=+spacing / 2,
        inner_arcs=tuple(Arc(a.curvature_ratio, -a.contact_angle) for a in row.inner_arcs),
        outer_arcs=tuple(Arc(a.curvature_ratio, -a.contact_angle) for a in row.outer_arcs))
    first = dataclasses.replace(row, axial_position=-spacing / 2)
    return dataclasses.replace(single, rows=(first, mirrored), width=2 * single.width)


def test_two_rows_are_reported_in_full():
    bearing = _pair()
    res = run_case(bearing, constant_profile(0.005, 0.04), OperatingPoint(SPEED, 8e3, 0.0),
                   SolverSettings(output_rate=1e4, gravity=False))
    ds = case_dataset(res, speed=SPEED, radial_load=8e3, axial_load=0.0)
    assert ds["cage_speed"].dims == ("elapsed_time", "row") and ds.sizes["row"] == 2
    for name in ("cage_speed_mean", "epicyclic_cage_speed", "cage_slip", "cage_slip_nominal"):
        assert ds[name].dims == ("phase", "row"), name
    assert ds["row"].attrs["long_name"] and ds["row"].attrs["units"] == "1"

    # both cages turn, alike (mirror symmetry), near their own epicyclic speed
    late = ds["cage_speed"].isel(elapsed_time=slice(-100, None)).mean("elapsed_time").values
    epicyclic = 0.5 * (1.0 - STUDY_D / STUDY_DM * math.cos(ALPHA)) * SPEED
    np.testing.assert_allclose(late, epicyclic, rtol=0.05)
    assert abs(late[0] - late[1]) < 1e-3 * epicyclic
    steady = ds["epicyclic_cage_speed"].sel(phase=1).values
    np.testing.assert_allclose(steady, epicyclic, rtol=0.02)


def test_a_single_row_keeps_its_dimensions():
    res = run_case(section_bearing(8), constant_profile(0.005, 0.01), OperatingPoint(SPEED, 8e3, 2e3),
                   SolverSettings(output_rate=1e4))
    ds = case_dataset(res, speed=SPEED, radial_load=8e3, axial_load=2e3)
    assert ds["cage_speed"].dims == ("elapsed_time",) and "row" not in ds.dims
    assert ds["cage_slip"].dims == ("phase",)
