"""The start a sweep's speeds share (rvcore.simulation.shared_start): where it ends, and
that a case whose start was copied from another speed's is the same, bit for bit, as the
case computed alone.

Where the start ends is read off the profile's own speed breakpoints here (the study
cycle's inner ring stands still until 0.3 s: sweeps/profiles/study.toml).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rvcore.profile import Channel, OperatingPoint, Profile, scaled_study_profile, study_profile
from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings
from rvcore.simulation.shared_start import StartStore, shared_until, start_key

from .physics_cases import section_bearing

OP = OperatingPoint(math.radians(660.0), 30e3, 10e3)


def _first_turn(profile) -> float:
    """The last breakpoint of the speed channel before its first non-zero value [s]."""
    times, values = profile.speed.times, profile.speed.values
    k = next(i for i, v in enumerate(values) if v != 0.0)
    return float(times[k - 1])


def test_the_start_ends_on_the_output_grid_where_the_ring_starts_to_turn():
    profile = study_profile()
    turn = _first_turn(profile)
    assert turn == pytest.approx(0.3)
    resolved = profile.resolve(OP)
    assert shared_until(resolved, 0.0, 4.6, 1000.0) == pytest.approx(turn, abs=1e-12)
    # an output interval that does not divide the time: the last output time before it
    assert shared_until(resolved, 0.0, 4.6, 7.0) == pytest.approx(math.floor(turn * 7.0) / 7.0)
    # a run that ends before the ring turns, or starts after it, shares nothing
    assert shared_until(resolved, 0.0, 0.2, 1000.0) == 0.0
    assert shared_until(resolved, 0.5, 4.6, 1000.0) == 0.5
    # a case at zero speed never turns: nothing to share
    assert shared_until(profile.resolve(dataclasses.replace(OP, speed=0.0)), 0.0, 4.6, 1000.0) == 0.0


def test_a_profile_that_turns_from_the_start_shares_nothing():
    base = study_profile()
    turning = Profile(base.name, base.radial_load, base.axial_load,
                      Channel((0.0, 0.8), (0.1, 1.0)), base.phases, base.duration)
    assert shared_until(turning.resolve(OP), 0.0, 4.6, 1000.0) == 0.0


def test_the_key_reads_every_byte_and_number():
    a = np.arange(6.0)
    b = a.copy()
    b[3] = np.nextafter(b[3], 10.0)
    assert start_key("imex", (a,), (1.0,)) == start_key("imex", (a.copy(),), (1.0,))
    assert start_key("imex", (a,), (1.0,)) != start_key("imex", (b,), (1.0,))
    assert start_key("imex", (a,), (1.0,)) != start_key("imex", (a.reshape(2, 3),), (1.0,))
    assert start_key("imex", (a,), (1.0,)) != start_key("imex", (a,), (np.nextafter(1.0, 2.0),))
    assert start_key("imex", (a,), (1.0,)) != start_key("rk4", (a,), (1.0,))


def _same(a, b):
    """Every array of two case results equal, bit for bit (NaN where NaN)."""
    assert np.array_equal(a.time, b.time)
    assert a.series.keys() == b.series.keys()
    for name in a.series:
        assert np.array_equal(a.series[name], b.series[name], equal_nan=True), name
    assert a.phase_metrics.keys() == b.phase_metrics.keys()
    for name in a.phase_metrics:
        assert np.array_equal(np.asarray(a.phase_metrics[name]), np.asarray(b.phase_metrics[name]),
                              equal_nan=True), name
    assert np.array_equal(a.final_state, b.final_state)
    assert np.array_equal(a.ball_diag, b.ball_diag, equal_nan=True)
    for key in ("steps", "tangent_refreshes", "substepped_steps", "substeps_taken", "shared_start_end"):
        assert a.info[key] == b.info[key], key


def test_a_case_whose_start_was_copied_is_the_case_computed_alone(monkeypatch):
    """The 12-ball section on the study cycle scaled to 46 ms (the ring still until 3 ms),
    two seeds: the second speed of a load and seed takes the first's start, its initial
    state and the start's peak load from the store (no statics solved for them) and gives
    the same bits as computed alone; another load or seed computes its own."""
    import rvcore.simulation.run as driver

    solved = []
    real = driver.initial_state
    monkeypatch.setattr(driver, "initial_state", lambda *a, **k: solved.append(a[2]) or real(*a, **k))
    bearing = section_bearing()
    profile = scaled_study_profile(0.01)
    store = StartStore()
    slow = dataclasses.replace(OP, speed=math.radians(120.0))
    settings = SolverSettings(output_rate=1e4, seed=1)
    first = run_case(bearing, profile, OP, settings, starts=store)
    assert (store.hits, store.misses) == (0, 1) and len(solved) == 1
    assert first.info["shared_start_end"] == pytest.approx(0.003)
    shared = run_case(bearing, profile, slow, settings, starts=store)
    assert (store.hits, store.misses) == (1, 1) and len(solved) == 1
    _same(shared, run_case(bearing, profile, slow, settings, starts=None))
    assert len(solved) == 2
    # the two speeds' outputs agree up to the start's end, and part after it
    start = first.time < first.info["shared_start_end"] - 5e-5
    assert start.sum() == 30
    for name in first.series:
        assert np.array_equal(first.series[name][start], shared.series[name][start], equal_nan=True), name
    assert not np.array_equal(first.final_state, shared.final_state)
    # another seed or load: a start of its own
    run_case(bearing, profile, slow, dataclasses.replace(settings, seed=2), starts=store)
    run_case(bearing, profile, dataclasses.replace(slow, radial_load=20e3), settings, starts=store)
    assert (store.hits, store.misses) == (1, 3) and len(solved) == 4


def test_two_processes_share_a_start_through_a_folder(tmp_path):
    """Two stores (two workers) sharing a folder: the second takes the start the first
    computed from the folder, and its case is the case computed alone, bit for bit; a
    start file that does not read is computed again, and a store without the folder
    computes its own."""
    bearing = section_bearing()
    profile = scaled_study_profile(0.01)
    settings = SolverSettings(output_rate=1e4, seed=1)
    slow = dataclasses.replace(OP, speed=math.radians(120.0))
    first, second = StartStore(), StartStore()
    first.share(tmp_path)
    second.share(tmp_path)
    run_case(bearing, profile, OP, settings, starts=first)
    files = list(tmp_path.glob("*.npz"))
    assert len(files) == 1 and not list(tmp_path.glob(".*"))     # written whole, no temporary left
    shared = run_case(bearing, profile, slow, settings, starts=second)
    assert (second.hits, second.misses, second.shared) == (1, 0, 1)
    _same(shared, run_case(bearing, profile, slow, settings, starts=None))
    # a damaged file is no start: the third computes its own, and writes it whole again
    files[0].write_bytes(files[0].read_bytes()[:1000])
    third = StartStore()
    third.share(tmp_path)
    again = run_case(bearing, profile, slow, settings, starts=third)
    assert (third.hits, third.misses) == (0, 1)
    _same(again, shared)
    assert files[0].stat().st_size > 1000
    # a store without the folder does not look there
    alone = StartStore()
    run_case(bearing, profile, slow, settings, starts=alone)
    assert (alone.hits, alone.misses) == (0, 1)


def test_flexible_lubricated_rings_copy_their_start_bit_for_bit():
    """The same on the 12-ball section with the lubricated law and both rings flexible
    (their modes are states, their block of the IMEX scratch is carried over too)."""
    from .test_lubricated_law import lubricated
    from .test_ring_dynamics import rings_of

    bearing = lubricated(section_bearing(12))
    rings = rings_of(bearing, 1e11, damping_ratio=0.02)
    profile = scaled_study_profile(0.004)
    settings = SolverSettings(output_rate=1e4, seed=1)
    store = StartStore()
    run_case(bearing, profile, OP, settings, rings=rings, starts=store)
    slow = dataclasses.replace(OP, speed=math.radians(120.0))
    shared = run_case(bearing, profile, slow, settings, rings=rings, starts=store)
    assert (store.hits, store.misses) == (1, 1)
    _same(shared, run_case(bearing, profile, slow, settings, rings=rings, starts=None))


class _Fake:
    def __init__(self, v):
        self.v = v

    @property
    def nbytes(self):
        return self.v.nbytes

    def copy(self):
        return _Fake(self.v.copy())


def test_the_store_keeps_the_last_starts_and_hands_out_copies():
    store = StartStore(keep=2)
    for k in ("a", "b", "c"):
        store.put(k, _Fake(np.array([1.0])))
    assert store.get("a") is None and store.get("b") is not None
    got = store.get("c")
    got.v[0] = 5.0
    assert store.get("c").v[0] == 1.0


def test_the_store_keeps_no_more_bytes_than_its_budget_but_the_newest():
    store = StartStore(keep=10, budget=3 * 800)
    for k in "abcd":
        store.put(k, _Fake(np.zeros(100)))          # 800 bytes each
    assert [store.get(k) is not None for k in "abcd"] == [False, True, True, True]
    store.put("big", _Fake(np.zeros(1000)))         # over the budget alone: kept, the rest dropped
    assert store.get("big") is not None and store.get("d") is None
