"""The designer's outputs of a dynamic case, against values derived here.

A pure axial load on an angular-contact row at rest loads every ball alike, so the ball
load, the contact angle and the peak pressure follow from textbook relations without any
load-distribution integral:

- both grooves' centres lie on the load line through the centred ball, ``A = (f_i + f_o − 1)·D``
  apart (zero clearance, rvcore.bearing.geometry's arc layout). A ring moved axially keeps their
  radial distance ``A·cos α₀``, so under the total approach ``δ`` of a ball
  ``cos α = A·cos α₀ / (A + δ)`` (Harris, Rolling Bearing Analysis, §7 "thrust load");
- the two Hertz contacts act in series: ``Q = K_n·δ^1.5`` with
  ``K_n = (K_i^(-2/3) + K_o^(-2/3))^(-3/2)``;
- the ring is in equilibrium when ``F_a = Z·Q·sin α``;
- the peak pressure of a contact is ``p_max = 3Q/(2πab)``, ``a, b ∝ Q^(1/3)`` (Hertz),
  so the load giving 4200 MPa at the more highly stressed race contact is
  ``Q* = (4200 MPa / c)³`` with ``c = p_max/Q^(1/3)`` of that contact.

The Hertz constants (``K``, ``a/Q^(1/3)``, ``b/Q^(1/3)``) are taken from rvcore.hertz,
which tests/core/test_hertz.py checks against published values; the load, the angle and
the safety factor are computed here.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings
from rvcore.profile import OperatingPoint

from .physics_cases import axial_point, constant_profile, section_bearing

ISO76 = 4200e6   # ISO 76, ball bearings: the contact stress of the basic static load rating [Pa]


def test_static_safety_factor_is_one_where_the_peak_pressure_is_4200_mpa():
    """ω = 0, the axial load held at the value giving p_max = 4200 MPa at the more
    stressed race contacts: S0 = 1 within 0.5 % in the series and the phase metric, the contact angles
    are the loaded angle of the geometry, and nothing slides or drives."""
    bearing = section_bearing(8, alpha=math.radians(25.0))
    f_a, q, alpha = axial_point(bearing, ISO76)
    res = run_case(bearing, constant_profile(0.0, 0.003), OperatingPoint(0.0, 0.0, f_a),
                   SolverSettings(output_rate=1e4, gravity=False))
    s0 = res.series["static_safety_factor"]
    assert np.all(np.abs(s0 - 1.0) < 0.005)
    np.testing.assert_allclose(res.phase_metrics["static_safety_factor_min"], 1.0, rtol=0.005)
    assert np.all(res.series["max_outer_contact_load"] == pytest.approx(q, rel=0.015))
    for name in ("min_contact_angle", "max_contact_angle"):
        np.testing.assert_allclose(res.series[name], alpha, rtol=0.005)
    # at rest nothing slides, so no friction power and no drive torque beyond round-off
    assert np.max(res.series["max_race_sliding_speed"]) < 1e-6
    assert np.max(np.abs(res.series["inner_ring_drive_torque"])) < 1e-6 * q * bearing.rows[0].pitch_diameter


def test_static_safety_factor_is_the_load_ratio():
    """ISO 76 defines s0 = C0/P0, a ratio of loads. At the pressure 4200 MPa / 2 the ball
    load is an eighth of that at 4200 MPa (p_max ∝ Q^(1/3)), so s0 = 8, not 2."""
    bearing = section_bearing(8, alpha=math.radians(25.0))
    f_a1, q1, _ = axial_point(bearing, ISO76)
    f_a, q, _ = axial_point(bearing, ISO76 / 2.0)
    assert q1 / q == pytest.approx(8.0, rel=1e-12)   # the load ratio, from Hertz in this test
    res = run_case(bearing, constant_profile(0.0, 0.002), OperatingPoint(0.0, 0.0, f_a),
                   SolverSettings(output_rate=1e4, gravity=False))
    np.testing.assert_allclose(res.series["static_safety_factor"], q1 / q, rtol=0.005)


def test_life_sums_of_equal_ball_loads():
    """Turning slowly (30 °/s) under the same pure axial load: every ball carries Q on both
    races, so per revolution A_i = (1/Z)·ΣQ³ = Q³ and A_o = ((1/Z)·ΣQ^(10/3))^(9/10) = Q³,
    and the revolutions are ω·t/2π (the contract of rvcore.standards.iso16281)."""
    bearing = section_bearing(8, alpha=math.radians(25.0))
    f_a, q, _ = axial_point(bearing, ISO76 / 2.0)
    omega, t_end = math.radians(30.0), 0.006
    res = run_case(bearing, constant_profile(0.0, t_end), OperatingPoint(omega, 0.0, f_a),
                   SolverSettings(output_rate=1e4, gravity=False))
    sums = res.life_sums
    rev = omega * t_end / (2.0 * math.pi)
    assert sums["revolutions"][-1] == pytest.approx(rev, rel=1e-6)
    np.testing.assert_allclose(sums["revolutions"][:3].sum(), rev, rtol=1e-6)
    assert sums["inner"][-1, 0] == pytest.approx(rev * q**3, rel=0.03)
    assert sums["outer"][-1, 0] == pytest.approx(rev * q**3, rel=0.03)


def test_case_file_labels_every_new_output():
    """Every designer series and phase metric reaches the case dataset with units and a
    long name, and the NaN conventions hold (no inf)."""
    from pipeline.io.case import PHASE_METRICS, SERIES, case_dataset

    bearing = section_bearing(6)
    res = run_case(bearing, constant_profile(0.0005, 0.003), OperatingPoint(math.radians(120.0), 5e3, 2e3),
                   SolverSettings(output_rate=2e3))
    ds = case_dataset(res, speed=math.radians(120.0), radial_load=5e3, axial_load=2e3)
    series = ("inner_ring_drive_torque", "friction_power", "max_pocket_force", "cage_land_force",
              "max_race_sliding_speed", "max_race_pv", "min_contact_angle", "max_contact_angle",
              "static_safety_factor")
    metrics = ("inner_ring_drive_torque_peak", "inner_ring_drive_torque_mean", "friction_power_mean",
               "friction_energy", "max_pocket_force_peak", "cage_land_force_peak", "max_race_sliding_speed_peak",
               "max_race_pv_peak", "contact_angle_min", "contact_angle_max", "static_safety_factor_min",
               "static_safety_factor_min_time")
    for name in series:
        assert name in SERIES and ds[name].dims == ("elapsed_time",)
    for name in metrics:
        assert name in PHASE_METRICS and ds[name].dims == ("phase",)
    for name in series + metrics:
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]
        assert not np.any(np.isinf(ds[name].values))
    # the extremes over a phase bound the series sampled in it (not the drive torque's
    # peak, which is band-limited while the series is the instantaneous torque: it is
    # bounded by the phase mean's magnitude instead, within the filter's lag, here short
    # against the phases)
    t = ds["elapsed_time"].values
    for k in range(3):
        inside = (t >= ds["phase_start"].values[k]) & (t < ds["phase_end"].values[k])
        assert ds["inner_ring_drive_torque_peak"].values[k] >= 0.99 * abs(ds["inner_ring_drive_torque_mean"].values[k])
        assert ds["static_safety_factor_min"].values[k] <= np.nanmin(ds["static_safety_factor"].values[inside])


def test_duty_cycle_life_reaches_the_case_file():
    """The case file holds the duty-cycle life:
    the scalars, the cycle's damage as the test computes it from the run's accumulated
    sums, and the damage per phase, whose sum over phases that cover the cycle is the
    cycle's damage."""
    pytest.importorskip("rvcore.standards.iso16281")
    from pipeline.io.case import case_dataset

    bearing = section_bearing(6)
    op = OperatingPoint(math.radians(120.0), 5e3, 2e3)
    res = run_case(bearing, constant_profile(0.0005, 0.003), op, SolverSettings(output_rate=2e3))
    ds = case_dataset(res, speed=op.speed, radial_load=5e3, axial_load=2e3)
    for name in ("rating_life_L10r", "rating_life_cycles", "fatigue_damage_cycle"):
        assert ds[name].dims == () and ds[name].attrs["units"] == "1" and ds[name].attrs["long_name"]
    assert ds["fatigue_damage"].dims == ("phase",)
    # the cycle's damage written here from the run's accumulated sums (Palmgren–Miner per
    # ring, D_k = Σ dN·Q_e^3 / (10^6·Q_c^3), rings combined as ISO/TS 16281 eq. (29))
    from rvcore.standards.iso16281 import bearing_contact_ratings

    q_ci, q_ce = bearing_contact_ratings(bearing)
    d_i = res.life_sums["inner"][-1, 0] / (1e6 * q_ci ** 3)
    d_e = res.life_sums["outer"][-1, 0] / (1e6 * q_ce ** 3)
    assert float(ds["fatigue_damage_cycle"]) == pytest.approx((d_i ** (10 / 9) + d_e ** (10 / 9)) ** 0.9, rel=1e-9)
    assert float(ds["fatigue_damage"].sum()) == pytest.approx(float(ds["fatigue_damage_cycle"]), rel=1e-6)
