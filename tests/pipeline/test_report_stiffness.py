"""Stiffness at the operating point in ``metrics.nc`` and the report; the statics at the
extreme operating points stored in ``statics.nc`` when a sweep runs, and the load
distribution the report draws from them, for one row and for a pair of rows, and the
report of a folder without them; a bearing of two rows through the whole report (per-row
cage slip).

The stiffness values of the synthetic sweep are made up here (a known function of the
load): the tests check that they are carried and plotted, not their physics, which
``tests/core/test_pair_statics.py`` tests. The physics checked here is computed in the
test: the centrifugal load of a ball from the geometry, and the equilibrium of the stored
contact forces and rows' forces with the applied loads.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pipeline.analysis import STIFFNESS, open_results, phase_metrics
from pipeline.io import encoding_for
from pipeline.report import build_report
from pipeline.run import run_sweep
from tests.pipeline.test_report import section_of, synthetic_sweep, table_rows

REPO = Path(__file__).resolve().parents[2]

#: The stored study configuration's row (tests.pipeline.test_report.STUDY_CONFIG).
STUDY_D, STUDY_DM, STUDY_RHO = 0.023, 0.3515, 7800.0


def made_up_stiffness(speed_deg, load):
    """Synthetic stiffness values [N m-1, N m-1, N m rad-1] of a grid point."""
    return 1e9 * (1.0 + load / 1e5), 4e8 * (1.0 + load / 2e5), 3e6 * (1.0 + load / 4e5)


def add_stiffness(directory: Path) -> dict:
    """Add the three stiffness scalars to ``sweep.nc`` as the case files will carry them
    (NaN where the case failed); return the values written."""
    path = directory / "sweep.nc"
    with xr.open_dataset(path, engine="netcdf4") as ds:
        sweep = ds.load()
    failed = sweep["case_status"].values != 0
    written = {}
    for k, name in enumerate(STIFFNESS):
        v = np.array([[made_up_stiffness(s, f)[k] for f in sweep["radial_load"].values]
                      for s in sweep["speed"].values])
        v[failed] = np.nan
        units, long_name = STIFFNESS[name]
        sweep[name] = (("speed", "radial_load"), v, {"units": units, "long_name": long_name})
        written[name] = v
    sweep.to_netcdf(path, engine="netcdf4", encoding=encoding_for(sweep))
    return written


@pytest.fixture(scope="module")
def stiff(tmp_path_factory):
    d = synthetic_sweep(tmp_path_factory.mktemp("stiff"))  # 3x3, 390 °/s at 20 kN failed
    written = add_stiffness(d)
    files = build_report(d)
    return d, written, files, files.markdown.read_text(), files.html.read_text()


def test_metrics_nc_carries_the_stiffness_with_units(stiff):
    d, written, *_ = stiff
    with xr.open_dataset(d / "metrics.nc") as m:
        for name, (units, _) in STIFFNESS.items():
            assert m[name].dims == ("speed", "radial_load"), name
            assert m[name].attrs["units"] == units and m[name].attrs["long_name"]
            np.testing.assert_array_equal(m[name].values, written[name])
        assert m["tilting_stiffness"].attrs["units"] == "N m rad-1"
        assert "stiffness" in m.attrs["comment"]


def test_metrics_nc_with_stiffness_is_cf(stiff, tmp_path):
    from compliance_checker.runner import CheckSuite

    from tests.pipeline.test_cf import cf_problems

    suite = CheckSuite()
    suite.load_all_available_checkers()
    assert cf_problems(suite, stiff[0] / "metrics.nc") == []


def test_older_sweep_without_stiffness_is_reported_without(tmp_path):
    d = synthetic_sweep(tmp_path)
    metrics = phase_metrics(open_results(d))
    assert not any(n in metrics for n in STIFFNESS)
    md = build_report(d).markdown.read_text()
    text = section_of(md, "## Stiffness at the operating point")
    assert "holds no stiffness" in text
    assert "## Load distribution" in md   # from the stored statics, whatever the version of the cases


def test_stiffness_section_and_figure(stiff):
    d, _, files, md, html = stiff
    text = section_of(md, "## Stiffness at the operating point")
    assert "quasi-static" in text and "N/µm" in text and "N m/mrad" in text
    assert "](figures/stiffness.png)" in md and 'src="figures/stiffness.png"' in html
    png = d / "report" / "figures" / "stiffness.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png in files.figures
    # the centrifugal load of a ball at the highest speed, from the geometry: F = m_b (d_m/2) ω_c²
    alpha = math.radians(15.0)
    m_b = STUDY_RHO * math.pi * STUDY_D ** 3 / 6.0
    w_c = math.radians(660.0) / 2.0 * (1.0 - STUDY_D * math.cos(alpha) / STUDY_DM)
    f_c = m_b * STUDY_DM / 2.0 * w_c ** 2
    assert f_c < 1.0  # the argument of the section: below a newton
    assert f"at most {f_c:.3g} N" in text
    assert "660 °/s" in text


def _rows_table(md: str) -> list:
    return table_rows(section_of(md, "## Load distribution").split("Each row's share")[1])


def test_load_distribution_single_row(stiff):
    d, _, files, md, html = stiff
    text = section_of(md, "## Load distribution")
    assert "](figures/load_distribution.png)" in md
    assert (d / "report" / "figures" / "load_distribution.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = _rows_table(md)[1:]
    # one load axis (radial load 20-40 kN): its two ends, one row each
    assert len(rows) == 2
    assert all(r[1].startswith("row 0") for r in rows)
    for r, load in zip(rows, (20.0, 40.0)):
        # the slowest finished case at each end of the load axis
        assert r[0].startswith(f"120 °/s, {load:g} kN radial")
        # the row carries the applied loads (the ring's weight, some 0.2 kN, aside)
        assert float(r[2]) == pytest.approx(load, rel=0.02)
        assert float(r[3]) == pytest.approx(10.0, rel=0.02)
    assert "stored in `statics.nc`" in text


# --------------------------------------------------------------------------- a pair of rows


def _pair_files(folder: Path, speeds, loads) -> Path:
    """A sweep of the real core on a back-to-back pair of two 8-ball rows of the test section."""
    src = (REPO / "sweeps" / "bearings" / "reduced-test.toml").read_text()
    head, row = src.split("[[rows]]", 1)
    head = head.replace('width = "30 mm"', 'width = "60 mm"').replace('name = "reduced-test"', 'name = "pair"')
    row = row.replace("count = 12", "count = 8")
    first = "[[rows]]" + row.replace('axial_position = "0 mm"', 'axial_position = "-15 mm"')
    second = ("[[rows]]" + row.replace('axial_position = "0 mm"', 'axial_position = "15 mm"')
              .replace('contact_angle = "15 deg"', 'contact_angle = "-15 deg"'))
    (folder / "pair.toml").write_text(head + first + "\n" + second)
    sweep = folder / "pair-sweep.toml"
    sweep.write_text(f"""\
name = "pair"
bearing = "{folder / 'pair.toml'}"
profile = "{REPO / 'sweeps' / 'profiles' / 'short.toml'}"

[axes]
speed = {[f"{s} deg/s" for s in speeds]}
radial_load = {[f"{f} kN" for f in loads]}

[fixed]
axial_load = "2 kN"

[solver]
output_rate = "500 Hz"
end_time = "0.1 s"
""".replace("'", '"'))
    return sweep


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pair")
    result = run_sweep(_pair_files(folder, (120, 660), (10, 20)), folder / "out", serial=True, progress=False)
    assert result.ok
    files = build_report(result.out_dir)
    return result.out_dir, files, files.markdown.read_text()


def test_two_rows_report_renders_with_per_row_cage_slip(pair):
    out, files, md = pair
    with xr.open_dataset(out / "sweep.nc") as s:
        assert s["cage_slip"].dims == ("speed", "radial_load", "phase", "row")
        assert s["cage_speed"].dims == ("speed", "radial_load", "elapsed_time", "row")
    with xr.open_dataset(out / "metrics.nc") as m:
        assert m["cage_slip"].dims == ("speed", "radial_load", "phase", "row")
        assert m["row"].attrs["units"] == "1" and m["row"].attrs["long_name"]
    # the row is no sweep axis
    assert "Extra sweep dimensions" not in md
    slip = table_rows(section_of(md, "## Cage slip"))
    assert slip[0][3] == "row"
    assert {r[3] for r in slip[1:]} == {"0", "1"}
    for p in files.figures:
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_two_rows_load_distribution_balances_the_applied_loads(pair):
    out, files, md = pair
    text = section_of(md, "## Load distribution")
    assert "stored in `statics.nc`" in text
    rows = _rows_table(md)[1:]
    cases = {}
    for r in rows:
        cases.setdefault(r[0], []).append(r)
    assert len(cases) == 2                        # the radial load's two ends
    for label, rs in cases.items():
        assert [r[1].split(" (")[0] for r in rs] == ["row 0", "row 1"]
        assert "α = 15°" in rs[0][1] and "α = -15°" in rs[1][1]
        fr = float(re.search(r"([\d.]+) kN radial", label).group(1))
        # mirrored rows push the ring axially opposite ways: their axial loads differ by the
        # applied 2 kN; both carry the radial load the same way (no weight: the ring's is
        # along -y, normal to the load, and adds in quadrature, ~0.1 %)
        assert float(rs[0][3]) - float(rs[1][3]) == pytest.approx(2.0, abs=0.01)
        assert float(rs[0][2]) + float(rs[1][2]) == pytest.approx(fr, rel=0.01)


def test_statics_nc_holds_the_corners_with_units(pair):
    """The runner stores the statics at the corners of the load axis in ``statics.nc``, each
    variable with its units and long name, and the stored contacts balance the applied loads."""
    out, files, md = pair
    with xr.open_dataset(out / "statics.nc", engine="netcdf4") as ds:
        ds = ds.load()
    for name, var in {**ds.data_vars, "corner": ds["corner"]}.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    assert ds.attrs["Conventions"] == "CF-1.8"
    # the corners of the one varying load (10 and 20 kN radial), each the slowest of its load
    assert sorted(ds["radial_load"].values) == pytest.approx([10e3, 20e3])
    assert np.degrees(ds["speed"].values) == pytest.approx([120.0, 120.0])
    assert all((out / "cases" / f"{cid}.nc").is_file() for cid in ds["case_id"].values)
    assert (ds["solved"].values == 1).all()
    for c in range(ds.sizes["corner"]):
        corner = ds.isel(corner=c)
        inner = corner["arc_ring"].values == 0
        q = corner["ball_load"].values[:, inner]
        alpha = np.nan_to_num(corner["contact_angle"].values[:, inner])   # NaN where unloaded (q = 0)
        phi = corner["ball_azimuth"].values - float(corner["load_angle"])
        # the inner ring in equilibrium: its contacts' normal forces Q (cos α cos φ, sin α), summed,
        # carry the applied radial and axial loads (the ring's weight, 47 N here, acts normal to
        # the radial load and adds in quadrature)
        radial = float((q * np.cos(alpha) * np.cos(phi)[:, None]).sum())
        axial = float((q * np.sin(alpha)).sum())
        assert radial == pytest.approx(float(corner["radial_load"]), rel=1e-3)
        assert axial == pytest.approx(float(corner["axial_load"]), rel=1e-3)
        # and each row's stored force is its balls' share: the rows' axial loads differ by the applied load
        rows = corner["row_axial_load"].values
        assert rows[0] - rows[1] == pytest.approx(float(corner["axial_load"]), rel=1e-3)


def test_report_of_a_folder_without_stored_statics(tmp_path):
    """A results folder written before the statics were stored gives a report: the load
    distribution says they are not stored and how to get them, and nothing is solved."""
    d = synthetic_sweep(tmp_path, statics=False)
    add_stiffness(d)
    assert not (d / "statics.nc").exists()
    files = build_report(d)
    md = files.markdown.read_text()
    text = section_of(md, "## Load distribution")
    assert "not stored" in text and "`statics.nc`" in text and "rvsweep sweep" in text
    assert not any(p.name == "load_distribution.png" for p in files.figures)
    stiffness = section_of(md, "## Stiffness at the operating point")
    assert "at most" in stiffness and "contact loads of up to" not in stiffness
    assert "`statics.nc`:" not in section_of(md, "## Files")


def test_statics_nc_is_cf(stiff):
    from compliance_checker.runner import CheckSuite

    from tests.pipeline.test_cf import cf_problems

    suite = CheckSuite()
    suite.load_all_available_checkers()
    assert cf_problems(suite, stiff[0] / "statics.nc") == []


def test_statics_nc_pads_corners_of_other_sizes_and_the_report_trims_them(tmp_path):
    """Corners whose bearings differ in balls or rows (a sweep axis may change them) share one
    file, padded; a corner without equilibrium keeps its operating point and its reason; the
    report reads each back at its own size."""
    from pipeline.io.statics import CornerStatics, statics_dataset, write_statics
    from pipeline.report.loads import read_statics

    def corner(cid, n_balls, n_rows):
        return CornerStatics(cid, {
            "speed": 1.0, "radial_load": 1e4, "axial_load": 0.0, "moment": 0.0, "load_angle": 0.0, "preload": 0.0,
            "solved": 1, "max_contact_load": 2e3, "ball_azimuth": np.linspace(0.0, 6.0, n_balls),
            "ball_row": np.arange(n_balls) % n_rows, "ball_load": np.ones((n_balls, 2)),
            "contact_angle": np.zeros((n_balls, 2)), "arc_ring": np.array([0, 1]),
            "row_radial_load": np.full(n_rows, 1e4 / n_rows), "row_axial_load": np.zeros(n_rows),
            "row_axial_position": np.zeros(n_rows), "row_contact_angle": np.zeros(n_rows)})

    failed = CornerStatics("c", {"speed": 2.0, "radial_load": 2e4, "axial_load": 0.0, "moment": 0.0,
                                 "load_angle": 0.0, "preload": 0.0, "solved": 0}, "NoEquilibriumError: diverged")
    write_statics(statics_dataset([corner("a", 12, 1), corner("b", 16, 2), failed], gravity=True, tilt="free"),
                  tmp_path)
    with xr.open_dataset(tmp_path / "statics.nc") as ds:
        assert ds.sizes["ball"] == 16 and ds.sizes["row"] == 2
        assert (ds["ball_row"].values[0, 12:] == -1).all() and np.isnan(ds["ball_load"].values[0, 12:]).all()
    a, b, c = read_statics(tmp_path).corners
    assert a.azimuth.size == 12 and a.row_axial_position.size == 1 and a.ball_load.shape == (12, 2)
    assert b.azimuth.size == 16 and b.row_axial_position.size == 2
    assert not c.solved and c.error == "NoEquilibriumError: diverged" and c.radial_load == 2e4
