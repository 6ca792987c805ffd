"""Least-squares fits: recovery of known lines and planes, interval coverage, NaN handling."""
from __future__ import annotations

import math

import cf_units
import numpy as np
import pytest
import xarray as xr
from scipy import stats

from pipeline.analysis import (LINE_STATS, PLANE_STATS, fit_metrics, fit_statistic, line_band, linear_fit,
                               plane_fit)
from pipeline.io import phase_coordinate
from pipeline.schema.units import compose_units

SPEEDS = np.array([120.0, 255.0, 390.0, 525.0, 660.0])  # degree s-1
LOADS = np.array([20e3, 30e3, 40e3])  # N


def _metrics(values, name="radial_displacement_mean", extra=None):
    """A metrics-like dataset over (speed, radial_load, phase[, extra dims])."""
    dims = ("speed", "radial_load", "phase") + tuple(extra or ())
    coords = {"speed": ("speed", SPEEDS, {"units": "degree s-1", "long_name": "steady inner-ring speed"}),
              "radial_load": ("radial_load", LOADS, {"units": "N", "long_name": "steady radial load"}),
              "phase": phase_coordinate()}
    return xr.Dataset({name: (dims, values, {"units": "m", "long_name": "time mean of delta_r"})},
                      coords=coords)


def test_exact_line_is_recovered():
    x = np.array([1.0, 2.0, 4.0, 7.0])
    f = linear_fit(x, 0.25 - 3e-6 * x)
    assert f["slope"] == pytest.approx(-3e-6, rel=1e-9)
    assert f["intercept"] == pytest.approx(0.25, rel=1e-12)
    assert f["rsquared"] == pytest.approx(1.0)
    assert f["n"] == 4
    # no residual: the interval collapses onto the slope (to rounding)
    assert f["slope_ci95_upper"] - f["slope_ci95_lower"] < 1e-9 * 3e-6


def test_standard_errors_match_the_textbook_formulas():
    rng = np.random.default_rng(3)
    x = np.linspace(0.0, 10.0, 8)
    y = 1.0 + 0.5 * x + rng.normal(0.0, 0.3, x.size)
    f = linear_fit(x, y)
    n = x.size
    sxx = ((x - x.mean()) ** 2).sum()
    b = ((x - x.mean()) * (y - y.mean())).sum() / sxx
    a = y.mean() - b * x.mean()
    s2 = ((y - a - b * x) ** 2).sum() / (n - 2)
    assert f["slope"] == pytest.approx(b, rel=1e-12)
    assert f["slope_stderr"] == pytest.approx(math.sqrt(s2 / sxx), rel=1e-10)
    assert f["intercept_stderr"] == pytest.approx(math.sqrt(s2 * (1 / n + x.mean() ** 2 / sxx)), rel=1e-10)
    t = stats.t.ppf(0.975, n - 2)
    assert f["slope_ci95_upper"] - f["slope"] == pytest.approx(t * math.sqrt(s2 / sxx), rel=1e-10)
    assert f["rsquared"] == pytest.approx(np.corrcoef(x, y)[0, 1] ** 2, rel=1e-12)
    # The band of the mean response at x̄ is t·s/√n; away from x̄ it widens.
    yl, lo, hi = line_band(f, np.array([x.mean(), x.max()]))
    assert yl[0] == pytest.approx(y.mean(), rel=1e-12)
    assert (hi[0] - lo[0]) / 2 == pytest.approx(t * math.sqrt(s2 / n), rel=1e-10)
    assert hi[1] - lo[1] > hi[0] - lo[0]


def test_line_intervals_cover_true_slopes_about_95_percent():
    """100 noisy replicates per (load, phase): the 95 % intervals hold the true values >= 85 times."""
    rng = np.random.default_rng(12345)
    slope = np.array([-5e-11, 2e-11, 8e-11])[:, None] * np.array([1.0, 2.0, -1.0])[None, :]  # (load, phase)
    intercept = 5e-5
    sigma = 3e-9
    reps = 100
    y = (intercept + slope[None, :, :, None] * SPEEDS[:, None, None, None]
         + sigma * rng.standard_normal((SPEEDS.size, LOADS.size, 3, reps)))
    fits = fit_metrics(_metrics(y, extra=("replicate",)))
    lo = fit_statistic(fits, "radial_displacement_mean", "speed", "slope_ci95_lower")
    hi = fit_statistic(fits, "radial_displacement_mean", "speed", "slope_ci95_upper")
    assert lo.dims == ("radial_load", "phase", "replicate")
    covered = ((lo.values <= slope[..., None]) & (slope[..., None] <= hi.values)).sum(axis=-1)
    assert covered.min() >= 85, covered
    ilo = fit_statistic(fits, "radial_displacement_mean", "speed", "intercept_ci95_lower").values
    ihi = fit_statistic(fits, "radial_displacement_mean", "speed", "intercept_ci95_upper").values
    assert ((ilo <= intercept) & (intercept <= ihi)).sum(axis=-1).min() >= 85
    n = fit_statistic(fits, "radial_displacement_mean", "speed", "n")
    assert np.all(n.values == SPEEDS.size)


def test_load_axis_fit_at_each_speed():
    y = (1e-5 + 2e-9 * LOADS[None, :, None] - 1e-8 * SPEEDS[:, None, None]) * np.ones((1, 1, 3))
    fits = fit_metrics(_metrics(y))
    s = fit_statistic(fits, "radial_displacement_mean", "radial_load", "slope")
    assert s.dims == ("speed", "phase")
    np.testing.assert_allclose(s.values, 2e-9, rtol=1e-9)
    i = fit_statistic(fits, "radial_displacement_mean", "radial_load", "intercept")
    np.testing.assert_allclose(i.values, (1e-5 - 1e-8 * SPEEDS)[:, None] * np.ones(3), rtol=1e-9)
    assert fits["displacement_vs_radial_load_slope"].attrs["units"] == "m N-1"
    assert fits["displacement_vs_speed_slope"].attrs["units"] == "m s degree-1"


def test_plane_recovers_known_interaction():
    gx, gy = np.meshgrid(SPEEDS, LOADS, indexing="ij")
    a, b, c, d = 2e-5, -4e-8, 1.5e-9, 3e-12
    z = a + b * gx + c * gy + d * gx * gy
    f = plane_fit(gx, gy, z)
    assert f["n"] == gx.size
    for key, true in (("intercept", a), ("speed", b), ("radial_load", c), ("interaction", d)):
        assert f[key] == pytest.approx(true, rel=1e-7, abs=1e-12 * abs(true) + 1e-30), key
    assert f["rsquared"] == pytest.approx(1.0)
    # Noisy: the interaction's 95 % interval covers d in >= 85 of 100 replicates.
    rng = np.random.default_rng(7)
    hits = 0
    for _ in range(100):
        zn = z + 2e-7 * rng.standard_normal(z.shape)
        g = plane_fit(gx, gy, zn)
        hits += g["interaction_ci95_lower"] <= d <= g["interaction_ci95_upper"]
    assert hits >= 85


def test_plane_in_dataset_and_units():
    gx, gy = np.meshgrid(SPEEDS, LOADS, indexing="ij")
    d = -2e-12
    z = (1e-5 + 1e-8 * gx + d * gx * gy)[:, :, None] * np.ones(3)
    fits = fit_metrics(_metrics(z))
    got = fit_statistic(fits, "radial_displacement_mean", "plane", "interaction")
    assert got.dims == ("phase",)
    np.testing.assert_allclose(got.values, d, rtol=1e-7)
    units = fits["displacement_plane_interaction"].attrs["units"]
    assert cf_units.Unit(units) == cf_units.Unit("m") / (cf_units.Unit("degree s-1") * cf_units.Unit("N"))


def test_composed_units_are_udunits():
    for u in (compose_units("m", "degree s-1"), compose_units("m", "N"), compose_units("1", "degree s-1"),
              compose_units("Pa", "degree s-1", "N"), compose_units("m", "degree s-1", power=2)):
        cf_units.Unit(u)  # raises on an invalid string
    assert cf_units.Unit(compose_units("m", "degree s-1", power=2)) == cf_units.Unit("m2 s degree-1")


def test_nan_points_are_skipped_and_counted():
    x = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    y = 3.0 + 2.0 * x
    y[[1, 3]] = np.nan
    f = linear_fit(x, y)
    assert f["n"] == 3
    assert f["slope"] == pytest.approx(2.0) and f["intercept"] == pytest.approx(3.0)
    y[0] = np.nan
    f = linear_fit(x, y)
    assert f["n"] == 2
    assert all(math.isnan(f[k]) for k in LINE_STATS if k != "n")
    f = linear_fit(np.full(4, 2.0), np.arange(4.0))  # one distinct x: no line
    assert f["n"] == 4 and math.isnan(f["slope"])
    f = linear_fit(x, np.full(5, np.nan))
    assert f["n"] == 0 and math.isnan(f["rsquared"])


def test_plane_needs_five_points_and_two_distinct_values_per_axis():
    gx, gy = np.meshgrid(SPEEDS[:2], LOADS[:2], indexing="ij")
    f = plane_fit(gx, gy, gx + gy)
    assert f["n"] == 4 and all(math.isnan(f[k]) for k in PLANE_STATS if k != "n")
    gx, gy = np.meshgrid(SPEEDS[:1], LOADS, indexing="ij")
    gx = np.concatenate([gx, gx])
    gy = np.concatenate([gy, gy + 1.0])
    f = plane_fit(gx, gy, gy * 2.0)  # a single speed: rank deficient
    assert f["n"] == 6 and math.isnan(f["interaction"])


def test_dataset_fit_with_missing_cases():
    y = (1e-5 + 2e-9 * LOADS[None, :, None] + 0.0 * SPEEDS[:, None, None]) * np.ones((1, 1, 3))
    y[0, 0, :] = np.nan  # a failed case
    y[1, 0, :] = np.nan
    y[2, 0, :] = np.nan  # at 20 kN only two speeds remain
    fits = fit_metrics(_metrics(y))
    n = fit_statistic(fits, "radial_displacement_mean", "speed", "n")
    assert n.sel(radial_load=20e3).values.tolist() == [2, 2, 2]
    assert np.isnan(fit_statistic(fits, "radial_displacement_mean", "speed", "slope").sel(radial_load=20e3)).all()
    assert n.sel(radial_load=30e3).values.tolist() == [5, 5, 5]
    ld = fit_statistic(fits, "radial_displacement_mean", "radial_load", "slope")
    assert np.isnan(ld.sel(speed=120.0)).all()  # two loads left
    np.testing.assert_allclose(ld.sel(speed=660.0).values, 2e-9, rtol=1e-9)
    assert fit_statistic(fits, "radial_displacement_mean", "plane", "n").values.tolist() == [12, 12, 12]


def test_level_sets_the_intervals_and_their_labels():
    """level=0.9: every interval is labelled 90 % and its half-width is t_{0.95, n-2} times
    the standard error (Student quantile and standard error computed here, by hand)."""
    rng = np.random.default_rng(7)
    slope, intercept = -2e-9, 1e-5
    values = (intercept + slope * SPEEDS[:, None, None] + 1e-8 * rng.standard_normal((5, 3, 3)))
    fits = fit_metrics(_metrics(values), level=0.9)
    for stat in ("slope_ci95_lower", "slope_ci95_upper", "intercept_ci95_lower", "intercept_ci95_upper"):
        long_name = fit_statistic(fits, "radial_displacement_mean", "speed", stat).attrs["long_name"]
        assert "90 % confidence interval" in long_name and "95 %" not in long_name
    for stat in ("interaction_ci95_lower", "interaction_ci95_upper"):
        long_name = fit_statistic(fits, "radial_displacement_mean", "plane", stat).attrs["long_name"]
        assert "90 % confidence interval" in long_name
    n = len(SPEEDS)
    t = stats.t.ppf(0.95, n - 2)
    x = SPEEDS
    sxx = float(((x - x.mean()) ** 2).sum())
    for j in range(3):
        for k in range(3):
            y = values[:, j, k]
            b = float(((x - x.mean()) * (y - y.mean())).sum() / sxx)
            a = float(y.mean() - b * x.mean())
            s2 = float(((y - a - b * x) ** 2).sum() / (n - 2))
            se_b = math.sqrt(s2 / sxx)
            se_a = math.sqrt(s2 * (1.0 / n + x.mean() ** 2 / sxx))
            at = {"radial_load": LOADS[j], "phase": k}
            got = {s: float(fit_statistic(fits, "radial_displacement_mean", "speed", s).sel(at))
                   for s in ("slope", "slope_ci95_lower", "slope_ci95_upper",
                             "intercept", "intercept_ci95_lower", "intercept_ci95_upper")}
            assert got["slope"] == pytest.approx(b, rel=1e-9)
            assert got["slope_ci95_upper"] - got["slope"] == pytest.approx(t * se_b, rel=1e-9)
            assert got["slope"] - got["slope_ci95_lower"] == pytest.approx(t * se_b, rel=1e-9)
            assert got["intercept_ci95_upper"] - got["intercept"] == pytest.approx(t * se_a, rel=1e-8)
    # the default level keeps its 95 % labels
    default = fit_metrics(_metrics(values))
    assert "95 % confidence interval" in fit_statistic(
        default, "radial_displacement_mean", "speed", "slope_ci95_lower").attrs["long_name"]
