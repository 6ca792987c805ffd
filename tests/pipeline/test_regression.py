"""REGRESSION TEST, labelled as such: pinned case ids and pinned reduced-case metrics.

These numbers were copied from the code's own output (commit 0acd675 and its layout
move, MODEL_VERSION 3): they prove nothing about physics. They exist so that a change
that alters results fails here, which forces a deliberate decision: either the change
was meant to keep results (then it is a bug), or it was meant to change them (then bump
``MODEL_VERSION`` in ``pipeline/schema/sweepfile.py``, which changes every case id, and
re-pin both tables below from a fresh run).

The case: the smoke sweep's corner at 660 deg/s and 40 kN, 10 kN axial (the reduced
12-ball test bearing on the study's cycle scaled by 0.1), about 5 s of computing.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.run import run_one_case
from pipeline.schema import MODEL_VERSION, load_sweep
from pipeline.schema.shipped import shipped_file

PINNED_MODEL_VERSION = 3

#: (speed [deg/s], radial load [kN]) -> case id of the smoke sweep.
PINNED_CASE_IDS = {
    (120, 20): "f51417ac939b86d6",
    (120, 40): "0b91ba594f27866f",
    (660, 20): "894c42781663e009",
    (660, 40): "c48d5dc8df1cbb8d",
}

#: per phase (start-up, steady, deceleration), SI: m, m, 1.
PINNED_METRICS = {
    "radial_displacement_range": [1.6280345279643283e-06, 9.301738487308548e-07, 2.948584250892525e-07],
    "radial_displacement_mean": [0.00014765283807655712, 0.00014736134343360934, 0.0001472301792263076],
    "axial_displacement_range": [4.481158133539859e-06, 2.1980465871456216e-06, 2.6419096341356244e-07],
    "axial_displacement_mean": [7.294980359767013e-05, 7.308439260811971e-05, 7.304954380622623e-05],
    "cage_slip": [0.012713860877918703, 0.0012651192103720899, 0.0030143769271389065],
}

#: Round-off may differ between CPUs and compilers; a change of the model moves these
#: metrics by far more than this.
RTOL = 1e-6


def _smoke_cases():
    sweep = load_sweep(shipped_file("smoke.toml"))
    return {(round(math.degrees(c.point["speed"])), round(c.point["radial_load"] / 1e3)): c
            for c in sweep.cases}


def test_model_version_is_the_pinned_one():
    assert MODEL_VERSION == PINNED_MODEL_VERSION, (
        "MODEL_VERSION changed: re-pin the case ids and metrics in this file from a fresh run")


def test_pinned_case_ids():
    ids = {k: c.case_id for k, c in _smoke_cases().items()}
    assert ids == PINNED_CASE_IDS, (
        "the case ids changed: the hashed configuration or MODEL_VERSION changed")


def test_pinned_reduced_case_metrics():
    ds = run_one_case(_smoke_cases()[(660, 40)])
    for name, pinned in PINNED_METRICS.items():
        np.testing.assert_allclose(
            ds[name].values, pinned, rtol=RTOL, atol=0,
            err_msg=f"{name} moved: a result changed; bump MODEL_VERSION if that was meant")
