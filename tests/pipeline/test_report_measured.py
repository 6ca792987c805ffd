"""Measured traces in a sweep folder: ``rvsweep compare --sweep`` stores them in ``measured/``;
``rvsweep report`` puts them in ``metrics.nc`` beside the simulated cases, their fits in
``fits.nc`` beside ours, and a section of overlays in the report.

The sweep is synthetic (tests/pipeline/test_report.py); the traces are its own case files'
series times a known gain, written by the test. Every expectation is computed here from
those series (numpy ranges over the windows, numpy's least-squares line), not from the
code's output.
"""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pipeline.analysis import fit_statistic
from pipeline.cli import main
from pipeline.report import build_report
from rvcore.profile import study_profile
from tests.pipeline.test_compare import NAMES, write_trace
from tests.pipeline.test_report import synthetic_sweep

REPO = Path(__file__).resolve().parents[2]
#: Two reports and three comparisons: about 45 s of CPU (the default run keeps the measured
#: group's and fits' own tests in test_compare.py).
pytestmark = pytest.mark.slow
GAIN = 1.2
SPEEDS = (120.0, 390.0, 660.0)
WINDOWS = np.array([(a, b) for _, a, b in study_profile().phases])


def _case_series(d, speed):
    with xr.open_dataset(d / "cases" / f"case-{speed:g}-30.nc") as ds:
        return ds["elapsed_time"].values, {n: ds[n].values.copy() for n in NAMES}


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """A 3x3 synthetic sweep, a copy without traces, and three traces at 30 kN (120, 390,
    660 °/s), each GAIN times its case, compared with --sweep."""
    root = tmp_path_factory.mktemp("measured")
    d = synthetic_sweep(root / "sweep")
    bare = root / "bare"
    shutil.copytree(d, bare)
    for s in SPEEDS:
        t, series = _case_series(d, s)
        traces = root / f"trace{s:g}"
        traces.mkdir()
        toml = write_trace(traces, "csv", t, {n: GAIN * x for n, x in series.items()},
                           extra=f'profile = "{REPO / "sweeps/profiles/study.toml"}"\n'
                                 f'speed = "{s:g} deg/s"\nradial_load = "30 kN"\naxial_load = "10 kN"')
        toml.write_text(toml.read_text().replace('name = "test-csv"', f'name = "rig {s:g}"'))
        assert main(["compare", str(toml), "--sweep", str(d), "--out", str(traces / "out")]) == 0
    build_report(d)
    build_report(bare)
    return d, bare


def test_compare_stores_each_trace_in_the_sweeps_measured_folder(folder):
    d, _ = folder
    assert sorted(p.name for p in (d / "measured").glob("*.nc")) == ["rig-120.nc", "rig-390.nc", "rig-660.nc"]
    with xr.open_dataset(d / "measured" / "rig-660.nc") as ds:
        assert ds.attrs["case"].endswith("case-660-30.nc")
        assert float(ds["speed"]) == pytest.approx(660.0) and ds["speed"].attrs["units"] == "degree s-1"
        t, series = _case_series(d, 660.0)
        np.testing.assert_allclose(ds["radial_displacement_simulated"].values, series["radial_displacement"][:ds.sizes["elapsed_time"]])
        np.testing.assert_allclose(ds["radial_displacement"].values,
                                   GAIN * series["radial_displacement"][:ds.sizes["elapsed_time"]], rtol=1e-9, atol=1e-15)


def test_measured_cases_sit_in_metrics_nc_with_their_ranges(folder):
    d, _ = folder
    with xr.open_dataset(d / "metrics.nc") as m:
        meanings = m["measured_case"].attrs["flag_meanings"].split()
        assert meanings == ["rig_120", "rig_390", "rig_660"]
        np.testing.assert_allclose(m["measured_case_speed"].values, SPEEDS)
        for k, s in enumerate(SPEEDS):
            t, series = _case_series(d, s)
            for n in NAMES:
                want = [GAIN * np.ptp(series[n][(t >= a) & (t < b)]) for a, b in WINDOWS]
                np.testing.assert_allclose(m[f"measured_{n}_range"].values[k], want, rtol=1e-9, atol=1e-15)
                assert m[f"measured_{n}_range"].attrs["units"] == "m"
                # the same metric, simulated, at the same grid point: the measured is GAIN times it
                sim = m[f"{n}_range"].sel(speed=s, radial_load=30e3).values
                np.testing.assert_allclose(m[f"measured_{n}_range"].values[k], GAIN * sim, rtol=1e-9, atol=1e-15)
        for name, v in m.variables.items():
            if str(name).startswith("measured_") and "flag_values" not in v.attrs:
                assert v.attrs.get("units") is not None and v.attrs.get("long_name"), name


def test_measured_fits_sit_in_fits_nc_beside_ours(folder):
    """The measured ranges against speed at 30 kN: numpy's least-squares line through the
    three tests, and GAIN times our own fit's slope there."""
    d, _ = folder
    with xr.open_dataset(d / "metrics.nc") as m, xr.open_dataset(d / "fits.nc") as f:
        f = f.load()
        for n in NAMES:
            y = m[f"measured_{n}_range"].values[:, 0]          # start-up, the three speeds
            slope, intercept = np.polyfit(np.array(SPEEDS), y, 1)
            mf = f[[v for v in f.data_vars if str(v).startswith("measured_")]]
            mf = mf.rename({k: str(k).removeprefix("measured_") for k in mf.variables
                            if str(k).startswith("measured_")})
            meas = fit_statistic(mf, f"{n}_range", "speed", "slope")
            got = float(meas.sel(radial_load=30e3, phase=0))
            assert got == pytest.approx(slope, rel=1e-9, abs=1e-18)
            ours = float(fit_statistic(f, f"{n}_range", "speed", "slope").sel(radial_load=30e3, phase=0))
            assert got == pytest.approx(GAIN * ours, rel=1e-9, abs=1e-18)
        assert f["measured_displacement_vs_speed_n"].sel(measured_radial_load=30e3).values.min() == 3


def test_the_report_shows_the_traces_and_the_fits(folder):
    d, _ = folder
    md = (d / "report" / "report.md").read_text()
    assert "## Measured traces beside the model" in md
    section = md.split("## Measured traces beside the model")[1].split("\n## ")[0]
    for s in SPEEDS:
        for kind in ("traces", "spectra"):
            name = f"measured_rig_{s:g}_{kind}.png"
            assert (d / "report" / "figures" / name).read_bytes()[:4] == b"\x89PNG"
            assert f"](figures/{name})" in section
    # Sprague-Geers M of the simulation against GAIN times it: 1/GAIN − 1
    assert f"{1 / GAIN - 1:.3g}".lstrip("0") in section or f"{1 / GAIN - 1:.3g}" in section
    assert "measured slope" in section and "Table 3, row 1" in section
    assert "`measured/`: 3 rig trace(s)" in md.split("## Files")[1]


def test_a_sweep_without_traces_keeps_its_files_as_they_were(folder):
    d, bare = folder
    md = (bare / "report" / "report.md").read_text()
    assert "Measured traces" not in md
    with xr.open_dataset(bare / "metrics.nc") as a, xr.open_dataset(d / "metrics.nc") as b:
        assert set(b.variables) - set(a.variables) == {v for v in b.variables if str(v).startswith("measured_")}
        assert set(a.dims) == set(b.dims) - {"measured_case"}
        for v in a.data_vars:
            assert a[v].dims == b[v].dims
            np.testing.assert_array_equal(a[v].values, b[v].values)
    with xr.open_dataset(bare / "fits.nc") as a, xr.open_dataset(d / "fits.nc") as b:
        assert not any(str(v).startswith("measured_") for v in a.variables)
        for v in a.data_vars:
            np.testing.assert_array_equal(a[v].values, b[v].values)


def test_an_unreadable_measured_file_is_one_line(folder, tmp_path, capsys):
    d, bare = folder
    bad = tmp_path / "sweep"
    shutil.copytree(bare, bad)
    (bad / "measured").mkdir()
    (bad / "measured" / "rig.nc").write_bytes(b"not a netCDF file")
    assert main(["report", str(bad)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "measured/rig.nc: cannot read as NetCDF" in err


def test_the_files_with_measured_cases_pass_the_cf_checker(folder):
    from compliance_checker.runner import CheckSuite

    from tests.pipeline.test_cf import cf_problems

    d, _ = folder
    suite = CheckSuite()
    suite.load_all_available_checkers()
    # fits.nc with the measured fits passes too, but its check alone takes about 90 s here
    # (the checker's time grows with the square of the number of variables): left out.
    for name in ("metrics.nc", "measured/rig-660.nc"):
        assert cf_problems(suite, d / name) == [], name
