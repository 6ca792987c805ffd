"""A sweep's expansion shares work between its cases (:class:`pipeline.schema.caseids.IdentityMemo`,
the configuration text written on first use): every case's id and configuration text must be
what the straightforward computation gives, case by case, for every shipped sweep and the
test sweep makers."""
from __future__ import annotations

import dataclasses
import pickle
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from pipeline.schema import read_sweep_file
from pipeline.schema.caseids import IdentityMemo, hash_id, plain
from pipeline.schema.sweepfile import case_configuration
from tests.schema.test_sweepfile import GRID, make_sweep

REPO = Path(__file__).resolve().parents[2]
SHIPPED = sorted((REPO / "sweeps").glob("*.toml"))
#: Cases checked per sweep, spread over the whole list (the statistics sweeps have thousands).
SAMPLE = 40


def _sample(cases) -> list:
    """At most :data:`SAMPLE` cases, evenly spread, the first and the last included."""
    if len(cases) <= SAMPLE:
        return list(cases)
    return [cases[int(i)] for i in np.unique(np.linspace(0, len(cases) - 1, SAMPLE).round())]


def _check_cases(cases) -> None:
    """Each case's id and configuration text against the configuration computed afresh for its
    own objects; also after a round trip through pickle (how a dask worker receives it)."""
    for spec in cases:
        conf = case_configuration(spec.bearing, spec.profile, spec.operating_point, spec.settings, spec.sensors)
        assert spec.case_id == hash_id(conf)
        back = pickle.loads(pickle.dumps(spec))          # before the text was ever written
        text = tomli_w.dumps(conf)
        assert spec.configuration == text
        assert back.configuration == text and back.case_id == spec.case_id
        again = pickle.loads(pickle.dumps(spec))         # after: the written text travels
        assert again.configuration == text


def _reference_plain(obj):
    """:func:`pipeline.schema.caseids.plain` written the plain way (dataclasses.fields on
    every object, no lookups kept): the form the case ids were pinned with."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _reference_plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)
                if getattr(obj, f.name) is not None}
    if isinstance(obj, dict):
        return {str(k): _reference_plain(v) for k, v in obj.items() if v is not None}
    if isinstance(obj, (list, tuple)):
        return [_reference_plain(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    return obj


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_every_shipped_sweeps_cases_have_the_ids_and_texts_of_their_own_values(path):
    sweep = read_sweep_file(path)
    assert sweep.cases
    _check_cases(_sample(sweep.cases))
    first = sweep.cases[0]
    assert plain(first.bearing) == _reference_plain(first.bearing)
    assert plain(first.profile) == _reference_plain(first.profile)
    assert plain(first.settings) == _reference_plain(first.settings)


def test_a_statistics_sweeps_draws_keep_their_own_bearings():
    """Each draw is another bearing object: its hashed part is its own, not the first draw's."""
    sweep = read_sweep_file(REPO / "sweeps" / "study-statistics.toml")
    cases = _sample(sweep.cases)
    bearings = {id(c.bearing) for c in cases}
    assert len(bearings) > 1
    hashed = {repr(c.resolved["bearing"]) for c in cases}
    assert len(hashed) > 1                     # the draws differ, and so do their hashed parts
    _check_cases(cases)


def test_the_test_sweep_makers_grid_list_ensemble_and_bearing_axes(tmp_path):
    bodies = {
        "grid": GRID,
        "list": '[[cases]]\nspeed = "120 deg/s"\nradial_load = "20 kN"\naxial_load = "10 kN"\n'
                '"friction.mu_static" = 0.08\n'
                '[[cases]]\nspeed = "660 deg/s"\nradial_load = "40 kN"\naxial_load = "10 kN"\n'
                '"friction.mu_static" = 0.12\n',
        "ensemble": GRID + "\n",
        "axes": '[axes]\nspeed = ["120 deg/s", "660 deg/s"]\n"friction.mu_static" = [0.08, 0.12]\n'
                '"solver.method" = ["rk4", "imex"]\n"profile.speed.fraction[2]" = [0.9, 1.0]\n'
                '[fixed]\nradial_load = "30 kN"\naxial_load = "10 kN"\n',
    }
    for name, body in bodies.items():
        folder = tmp_path / name
        folder.mkdir()
        header = 'bearing = "bearings/reduced-test.toml"\nprofile = "profiles/short.toml"\n'
        if name == "ensemble":
            header += "realizations = 3\nseed = 4\n"
        sweep = read_sweep_file(make_sweep(folder, body, header=header))
        assert len({c.case_id for c in sweep.cases}) == len(sweep.cases) > 1
        _check_cases(sweep.cases)
    from tests.pipeline.test_report import study_grid_sweep

    _check_cases(study_grid_sweep().cases)


def test_the_memo_computes_once_per_object_and_never_by_value():
    calls = []

    def compute(obj):
        calls.append(obj)
        return [len(calls)]

    memo = IdentityMemo()
    a, b = [1.0], [1.0]                        # equal values, two objects
    assert memo.get(a, "x", compute) == [1]
    assert memo.get(a, "x", compute) == [1]    # the same object: not computed again
    assert memo.get(b, "x", compute) == [2]    # an equal but other object: its own entry
    assert memo.get(a, "y", compute) == [3]    # another quantity of the same object
    assert calls == [a, b, a]
