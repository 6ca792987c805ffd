"""What the quick run (`make smoke`) must show: every fit and the whole study comparison.

The smoke sweep is run once per session (``conftest.smoke_run``).
"""
from __future__ import annotations

import re

import numpy as np
import xarray as xr

#: The study's one-dimensional sweeps: speed at 30 kN, radial load at 120 deg/s.
STUDY_LOAD, STUDY_SPEED = 30e3, 120.0


def test_smoke_report_was_written(smoke_run):
    assert smoke_run.sweep_code == 0, smoke_run.sweep_printed
    assert smoke_run.report_code == 0, smoke_run.report_printed


def test_smoke_fits_are_finite_along_the_study_lines(smoke_run):
    """Slopes, their intervals and n along both study lines, checked against a fit done
    here with numpy on metrics.nc (three points: a residual, so a standard error)."""
    with xr.open_dataset(smoke_run.out / "fits.nc") as f, \
            xr.open_dataset(smoke_run.out / "metrics.nc") as m:
        names = f["displacement_metric"].attrs["flag_meanings"].split()
        for axis, other, at, dim in (("speed", "radial_load", STUDY_LOAD, "speed"),
                                     ("radial_load", "speed", STUDY_SPEED, "radial_load")):
            prefix = f"displacement_vs_{axis}"
            line = f.sel({other: at})
            for k, name in enumerate(names):
                for ph in range(3):
                    sel = line.isel(displacement_metric=k).sel(phase=ph)
                    slope = float(sel[f"{prefix}_slope"])
                    lo, hi = float(sel[f"{prefix}_slope_ci95_lower"]), float(sel[f"{prefix}_slope_ci95_upper"])
                    assert int(sel[f"{prefix}_n"]) == 3
                    assert np.isfinite([slope, lo, hi]).all(), (prefix, name, ph)
                    assert lo < slope < hi
                    y = m[name].sel({other: at, "phase": ph})
                    expected = np.polyfit(y[dim].values, y.values, 1)[0]
                    np.testing.assert_allclose(slope, expected, rtol=1e-9, atol=0)


def test_smoke_report_compares_all_twelve_study_fits(smoke_run):
    text = (smoke_run.out / "report" / "report.md").read_text()
    counts = re.findall(r"(\d+) of (\d+) slope signs agree with the study", text)
    assert counts and all(total == "12" for _, total in counts)
    # each of the 12 table rows has its 3 points
    rows = [line for line in text.splitlines() if re.match(r"\| Table [34], row \d", line)]
    assert len(rows) == 12
    assert all(line.rstrip(" |").split("|")[-2].strip() == "3" for line in rows)


def test_the_report_says_what_was_run_under_its_title(smoke_run):
    """Bearing, profile, grid, integrator and model version, from the sweep file itself."""
    from pipeline.schema import MODEL_VERSION, read_sweep_file
    from tests.conftest import REPO

    sweep = read_sweep_file(REPO / "sweeps" / "smoke.toml")
    lines = (smoke_run.out / "report" / "report.md").read_text().splitlines()
    assert lines[0] == "# Sweep report: smoke"
    header = next(line for line in lines[1:] if line.strip())
    assert header.startswith("**Run:**")
    for text in (f"bearing {sweep.bearing.name}", f"profile {sweep.profile.name}",
                 f"({sweep.profile.duration:g} s cycle)", f"= {len(sweep.cases)} cases",
                 f"integrator {sweep.settings.method.upper()}", f"model version {MODEL_VERSION}"):
        assert text in header, (text, header)
