"""metrics.nc from a synthetic sweep, and the reference-fit file of the study.

``build_synthetic_sweep`` (also used by ``test_report``) labels
``tests.pipeline.synthetic.synthetic_result`` with ``pipeline.io.case.case_dataset`` and combines the
cases into a ``sweep.nc`` laid out as the sweep writes it.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from pipeline.io import case_dataset, write_case
from pipeline.errors import ConfigError
from pipeline.io import CaseState, write_status
from pipeline.analysis import default_reference_path, load_reference_fits
from pipeline.analysis import open_results, phase_metrics, write_metrics
from rvcore.profile import PHASES
from tests.pipeline.synthetic import synthetic_result

#: A resolved configuration as the sweep stores it (pipeline.schema.sweepfile: SI numbers, the
#: dataclass field names of rvcore.bearing.geometry, the profile's phases as [name, start, end]).
SYNTHETIC_CONFIG = """\
model_version = 1
name = "synthetic"
case_ids = ["a", "b", "c", "d", "e", "f", "g", "h", "i"]

[axes]
speed = [2.0943951023931953, 6.806784082777885, 11.519173063162574]
radial_load = [20000.0, 30000.0, 40000.0]

[fixed]
axial_load = 10000.0

[bearing]
name = "study-table2"
bore = 0.32
outer_diameter = 0.383
width = 0.03
allow_ball_overlap = true
assumptions = ["rows[0].radial_clearance", "rows[0].outer_groove.arcs"]

[[bearing.rows]]
ball_count = 51
ball_diameter = 0.023
pitch_diameter = 0.3515
radial_clearance = 0.0

[[bearing.rows.outer_arcs]]
curvature_ratio = 0.53
contact_angle = 0.2617993877991494

[bearing.ball_material]
density = 7800.0
youngs_modulus = 208000000000.0
poisson_ratio = 0.3

[profile]
name = "study"
phases = [["startup", 0.3, 0.8], ["steady", 0.8, 3.8], ["deceleration", 3.8, 4.3]]
duration = 4.6
"""

#: The same bearing written as a bearing file would (unit strings), with no phase table.
FILE_STYLE_CONFIG = """\
name = "synthetic-file-style"

[bearing]
name = "study-table2"

[bearing.envelope]
bore = "320 mm"
outer_diameter = "383 mm"

[[bearing.rows]]
pitch_diameter = "351.5 mm"

[bearing.rows.balls]
count = 51
diameter = "23 mm"

[bearing.material]
density = "7800 kg/m^3"

[profile]
name = "study"
"""

CAVEAT = ("rows[0].balls.count = 51: 51 balls of 23 mm need a pitch diameter of at least "
          "373.6 mm; this bearing's is 351.5 mm (accepted with allow_ball_overlap)")
FAILED_REASON = "SimulationError: integration blew up at t = 1.234 s (ball 7)"


def build_synthetic_sweep(directory, speeds_deg=(120.0, 390.0, 660.0), loads=(20e3, 30e3, 40e3),
                          missing=((390.0, 20e3),), caveat: str = CAVEAT, with_sweep_nc: bool = True,
                          config: str = SYNTHETIC_CONFIG, flat_status: bool = False) -> Path:
    """Write ``sweep.nc``, ``status.json`` and ``cases/*.nc`` of a synthetic sweep.

    ``missing`` cases are failed: NaN in ``sweep.nc``, absent from ``cases/``, and
    ``status.json`` gives the reason (in the sweep's layout, or the flat
    ``{id: {state, reason, axis values}}`` one with ``flat_status``).
    """
    directory = Path(directory)
    (directory / "cases").mkdir(parents=True, exist_ok=True)
    cases, status = [], {}
    for s in speeds_deg:
        for f in loads:
            cid = f"case-{s:g}-{f / 1e3:g}"
            failed = (s, f) in missing
            status[cid] = CaseState(cid, len(status), {"speed": math.radians(s), "radial_load": f,
                                                      "axial_load": 10e3},
                                    state="failed" if failed else "ok",
                                    reason=FAILED_REASON if failed else "",
                                    traceback="Traceback ..." if failed else "")
            ds = case_dataset(synthetic_result(math.radians(s), f), speed=math.radians(s),
                              radial_load=f, axial_load=10e3, configuration=config,
                              configuration_hash="abc123", bearing_name="study-table2",
                              profile_name="study", caveats=(caveat,) if caveat else (),
                              assumptions=("rows[0].radial_clearance", "rows[0].outer_groove.arcs"))
            if not failed:
                write_case(ds, directory / "cases" / f"{cid}.nc")
            cases.append(ds.expand_dims(["speed", "radial_load"]))
    sweep = xr.combine_by_coords(cases, combine_attrs="override")
    status_flags = np.zeros((len(speeds_deg), len(loads)), dtype=np.int8)
    for (s, f) in missing:
        i = int(np.argmin(np.abs(sweep["speed"].values - s)))
        j = int(np.argmin(np.abs(sweep["radial_load"].values - f)))
        status_flags[i, j] = 1
        for name, var in sweep.data_vars.items():
            if var.dtype.kind == "f" and {"speed", "radial_load"} <= set(var.dims):
                sweep[name][{"speed": i, "radial_load": j}] = np.nan
    sweep["case_status"] = (("speed", "radial_load"), status_flags,
                            {"long_name": "state of the case", "flag_values": np.array([0, 1, 2], np.int8),
                             "flag_meanings": "ok failed not_run"})
    if with_sweep_nc:
        from pipeline.io import encoding_for

        sweep.to_netcdf(directory / "sweep.nc", engine="netcdf4", encoding=encoding_for(sweep))
    write_status(directory, status)  # the one layout, written by the pipeline's own writer
    return directory


@pytest.fixture(scope="module")
def sweep_dir(tmp_path_factory):
    return build_synthetic_sweep(tmp_path_factory.mktemp("sweep"))


@pytest.fixture(scope="module")
def metrics_file(sweep_dir):
    path = sweep_dir / "metrics.nc"
    write_metrics(phase_metrics(open_results(sweep_dir)), path)
    return path


def test_metrics_dims_units_and_flags(metrics_file):
    with xr.open_dataset(metrics_file) as m:
        for name in ("radial_displacement_range", "radial_displacement_mean", "radial_displacement_std",
                     "axial_displacement_range", "axial_displacement_mean", "axial_displacement_std"):
            assert m[name].dims == ("speed", "radial_load", "phase")
            assert m[name].attrs["units"] == "m"
            assert m[name].attrs["long_name"]
        assert m["cage_slip"].attrs["units"] == "1"
        assert m["peak_contact_pressure"].attrs["units"] == "Pa"
        assert m["epicyclic_cage_speed"].attrs["units"] == "rad s-1"
        assert m["speed"].attrs["units"] == "degree s-1"
        assert m["radial_load"].attrs["units"] == "N"
        assert m["phase"].dtype == np.int8
        assert list(m["phase"].attrs["flag_values"]) == [0, 1, 2]
        assert m["phase"].attrs["flag_meanings"].split() == list(PHASES)
        assert m["case_status"].dims == ("speed", "radial_load")
        assert m.attrs["Conventions"] == "CF-1.8"
        assert m.attrs["configuration"] == SYNTHETIC_CONFIG
    with netCDF4.Dataset(metrics_file) as nc:
        for c in ("speed", "radial_load", "phase"):
            assert "_FillValue" not in nc.variables[c].ncattrs()
        assert nc.variables["radial_displacement_range"].dtype == np.float64


#: The study cycle's phase windows [s] as the core applies them (start <= t < end).
WINDOWS = [(0.3, 0.8), (0.8, 3.8), (3.8, 4.3)]


def _series(speed_deg: float, load: float, t: np.ndarray, rng) -> tuple:
    """δ_r and δ_a built here: an oscillation whose amplitude and offset depend on the
    operating point, a drift and noise (nothing like the synthetic cases' profile shape)."""
    w = 2.0 * np.pi * (0.7 + speed_deg / 400.0)
    dr = 1e-9 * load * (1.0 + 0.3 * np.sin(w * t)) + 2e-7 * t + 3e-8 * rng.standard_normal(t.size)
    da = -4e-9 * speed_deg * np.cos(1.7 * w * t) ** 3 + 1e-6 + 1e-8 * rng.standard_normal(t.size)
    return dr, da


def _core_phase_metrics(t, dr, da) -> dict:
    """The core's own phase accumulators fed the series sample by sample, then read out."""
    from rvcore.recording.plan import SL_DA, SL_DR, build_plan, new_accumulators, reduce_step
    from rvcore.dynamics.rhs import new_diagnostics
    from rvcore.recording.results import read_phase_metrics

    plan = build_plan(1, 0)
    acc = new_accumulators(plan, len(WINDOWS))
    diag, _ = new_diagnostics(1, 1)
    for ti, r, a in zip(t, dr, da):
        diag[SL_DR], diag[SL_DA] = r, a
        for k, (start, end) in enumerate(WINDOWS):
            if start <= ti < end:
                reduce_step(acc[k], plan.reductions, diag, ti, 0, 0.0)
    with np.errstate(all="ignore"):
        return read_phase_metrics(acc, plan, np.array(WINDOWS), 0.01)


def test_metrics_match_values_computed_here_from_the_time_series(tmp_path):
    """metrics.nc (through the core's accumulators, the case files, the combiner and
    phase_metrics) holds the range, mean, std and extreme times of δ_r and δ_a computed
    here with numpy over each phase window of series built in this test."""
    from rvcore.recording.results import CaseResult

    rng = np.random.default_rng(11)
    t = np.round(np.arange(0.0, 4.6 + 1e-9, 0.01), 10)
    (tmp_path / "cases").mkdir()
    built = {}
    for s in (120.0, 660.0):
        for f in (20e3, 40e3):
            dr, da = _series(s, f, t, rng)
            built[(s, f)] = (dr, da)
            result = CaseResult(time=t, series={"radial_displacement": dr, "axial_displacement": da},
                                phase_metrics=_core_phase_metrics(t, dr, da), final_state=np.zeros(1))
            ds = case_dataset(result, speed=math.radians(s), radial_load=f, axial_load=10e3)
            write_case(ds, tmp_path / "cases" / f"case-{s:g}-{f:g}.nc")
    write_metrics(phase_metrics(open_results(tmp_path)), tmp_path / "metrics.nc")
    with xr.open_dataset(tmp_path / "metrics.nc") as m:
        assert m["radial_displacement_range"].dims == ("speed", "radial_load", "phase")
        assert (m["case_status"] == 0).all()
        for (s, f), series in built.items():
            got = m.sel(speed=s, radial_load=f)
            for name, x in zip(("radial_displacement", "axial_displacement"), series):
                for k, (start, end) in enumerate(WINDOWS):
                    mask = (t >= start) & (t < end)
                    w, tw = x[mask], t[mask]
                    g = got.sel(phase=k)
                    assert mask.sum() > 10
                    assert g[f"{name}_range"].item() == w.max() - w.min()
                    assert g[f"{name}_mean"].item() == pytest.approx(w.mean(), rel=1e-12, abs=1e-20)
                    assert g[f"{name}_std"].item() == pytest.approx(w.std(), rel=1e-9)
                    assert g[f"{name}_min_time"].item() == tw[np.argmin(w)]
                    assert g[f"{name}_max_time"].item() == tw[np.argmax(w)]


def test_missing_cases_are_nan_and_flagged(metrics_file):
    with xr.open_dataset(metrics_file) as m:
        miss = m.sel(speed=390.0, radial_load=20e3, method="nearest")
        assert np.all(np.isnan(miss["radial_displacement_range"].values))
        assert miss["case_status"].item() == 1
        assert int((m["case_status"] == 0).sum()) == 8
        # The cage slip is 1 - mean cage speed / epicyclic speed, so the epicyclic speed
        # the slip was measured against is mean / (1 - slip).
        steady = m.sel(phase=1)
        np.testing.assert_allclose(steady["epicyclic_cage_speed"] * (1 - steady["cage_slip"]),
                                   steady["cage_speed_mean"], rtol=1e-12)


def test_metrics_from_case_files_when_no_sweep_nc(tmp_path):
    d = build_synthetic_sweep(tmp_path, speeds_deg=(120.0, 660.0), loads=(20e3, 40e3),
                              missing=((660.0, 20e3),), with_sweep_nc=False)
    m = phase_metrics(open_results(d))
    assert m["radial_displacement_range"].dims == ("speed", "radial_load", "phase")
    assert m.sizes["speed"] == 2 and m.sizes["radial_load"] == 2
    at = {"speed": 660.0, "method": "nearest"}
    assert np.isnan(m["radial_displacement_mean"].sel(radial_load=20e3, **at)).all()
    assert m["case_status"].sel(radial_load=20e3, **at).item() == 1  # failed, as status.json records
    assert np.isfinite(m["radial_displacement_mean"].sel(radial_load=40e3, **at)).all()


def test_metrics_and_fits_pass_cf_checker(metrics_file, tmp_path):
    from compliance_checker.runner import CheckSuite, ComplianceChecker

    from pipeline.analysis import fit_metrics, write_fits

    with xr.open_dataset(metrics_file) as m:
        write_fits(fit_metrics(m.load()), tmp_path / "fits.nc")
    CheckSuite.load_all_available_checkers()
    for path in (metrics_file, tmp_path / "fits.nc"):
        ok, errors = ComplianceChecker.run_checker(str(path), ["cf:1.8"], 0, "normal",
                                                   output_filename=str(tmp_path / "cf.json"),
                                                   output_format="json")
        report = json.loads((tmp_path / "cf.json").read_text())
        high = report["cf:1.8"]["high_priorities"]
        failed = [r for r in high if r["value"][0] < r["value"][1]]
        assert not errors
        assert ok, f"{path.name}: {failed}"


# --------------------------------------------------------------------------- the study's fits

#: The study's table rows in order: (phase, displacement, metric).
ROWS = [("startup", "radial", "range"), ("deceleration", "radial", "range"), ("steady", "radial", "mean"),
        ("startup", "axial", "range"), ("deceleration", "axial", "range"), ("steady", "axial", "mean")]


def test_study_fits_file_holds_the_twelve_rows():
    fits = load_reference_fits(default_reference_path())
    assert len(fits) == 12
    for table, axis, fixed_axis, fixed in (("Table 3", "speed", "radial_load", 30e3),
                                           ("Table 4", "radial_load", "speed", math.radians(120.0))):
        rows = [f for f in fits if f.table == table]
        assert sorted(f.row for f in rows) == [1, 2, 3, 4, 5, 6]
        for f in rows:
            assert (f.phase, f.displacement, f.metric) == ROWS[f.row - 1]
            assert f.axis == axis and f.fixed_axis == fixed_axis
            assert f.fixed_value == pytest.approx(fixed)
            assert f.label.startswith(f"{table}, row {f.row}: ")
            assert f.source
    labels = [f.label for f in fits]
    assert len(set(labels)) == 12


def test_study_fits_file_is_consistent():
    """Every fit of the shipped study file loads, names its source, converts to our units
    (m per degree s-1, m per N; intercept in m) and back, and its labels match its rows."""
    fits = load_reference_fits(default_reference_path())
    assert len(fits) == 12 and {f.table for f in fits} == {"Table 3", "Table 4"}
    names = {"range": "Variation Range", "mean": "Mean"}
    for f in fits:
        assert f"{f.table}, row {f.row}" in f.source   # each fit names where it comes from
        assert f.label.startswith(f"{f.table}, row {f.row}: ")
        assert f.variable in ("radial_displacement_range", "radial_displacement_mean",
                              "axial_displacement_range", "axial_displacement_mean")
        unit = "mm/(deg/s)" if f.table == "Table 3" else "mm/N"
        assert f.slope_units == unit and f.intercept_units == "mm"
        # mm -> m is 1e-3 exactly; deg/s is the coordinate unit of speed, N of the load
        assert f.slope_in_coordinate_units() == pytest.approx(f.slope * 1e-3, rel=1e-12)
        assert f.intercept_si() == pytest.approx(f.intercept * 1e-3, rel=1e-12)
        back = f.to_reference_units(f.slope_in_coordinate_units(), f.intercept_si())
        assert back == pytest.approx((f.slope, f.intercept), rel=1e-12)
        assert f.fixed_coordinate == pytest.approx(30e3 if f.table == "Table 3" else 120.0, rel=1e-12)
        assert f.displacement.capitalize() in f.label and names[f.metric] in f.label
        assert math.isfinite(f.slope) and f.slope != 0.0 and f.intercept > 0.0
    for table in ("Table 3", "Table 4"):   # the same rows in both tables, in the same order
        rows = sorted((f for f in fits if f.table == table), key=lambda f: f.row)
        assert [(f.phase, f.displacement, f.metric) for f in rows] == ROWS


def test_reference_file_errors_name_file_and_key(tmp_path):
    good = default_reference_path().read_text()
    bad = tmp_path / "rig.toml"
    bad.write_text(good.replace('remarks = "Decreases with speed"', 'remark = "typo"'))
    with pytest.raises(ConfigError) as exc:
        load_reference_fits(bad)
    assert str(bad) in str(exc.value) and "fits[2].remark" in str(exc.value)
    bad.write_text(good.replace('slope_units = "mm/N"', 'slope_units = "mm/s"', 1))
    with pytest.raises(ConfigError) as exc:
        load_reference_fits(bad)
    assert "fits[6].slope_units" in str(exc.value) and "'mm/s'" in str(exc.value)


def test_extra_sweep_dimension_is_kept(tmp_path):
    """An extra sweep axis (here the axial load) stays a dimension of metrics.nc."""
    cases = []
    for s in (120.0, 660.0):
        for f in (20e3, 40e3):
            for a in (5e3, 10e3):
                ds = case_dataset(synthetic_result(math.radians(s), f, a), speed=math.radians(s),
                                  radial_load=f, axial_load=a)
                cases.append(ds.expand_dims(["speed", "radial_load", "axial_load"]))
    m = phase_metrics(xr.combine_by_coords(cases, combine_attrs="override"))
    assert m["axial_displacement_mean"].dims == ("speed", "radial_load", "axial_load", "phase")
    assert m["case_status"].dims == ("speed", "radial_load", "axial_load")
    # the synthetic steady δ_a grows by 1e-9 m per N of axial load
    steady = m["axial_displacement_mean"].sel(phase=1)
    np.testing.assert_allclose(steady.sel(axial_load=10e3) - steady.sel(axial_load=5e3), 5e-6, rtol=1e-9)
