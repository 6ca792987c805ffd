"""The real smoke sweep, run once per test session and shared by the tests that read it.

``rvsweep sweep sweeps/smoke.toml --serial`` then ``rvsweep report``: 9 real cases of the
reduced bearing (about 20 s serial once numba has compiled). Serial, so the default run
starts no cluster for it; the same sweep on a local cluster is compared with a serial
run in ``tests/pipeline/test_sweep.py`` (marked slow).

``make test`` spreads the tests over processes (pytest-xdist, ``--dist loadgroup``): every
test that reads the smoke run is put in one group, so one process runs the sweep once.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def pytest_configure(config):
    """A netCDF file that a test or the code leaves open is an error (pyproject.toml's
    ``filterwarnings``): xarray warns when the garbage collector closes it, and HDF5 can
    crash closing a file inside a collection (the suite's worker crashes of 2026-11-28)."""
    import xarray as xr

    xr.set_options(warn_for_unclosed_files=True)


@dataclass
class SmokeRun:
    out: Path            # results/smoke/ of the run
    sweep_code: int
    sweep_printed: str
    report_code: int
    report_printed: str


def pytest_collection_modifyitems(config, items):
    for item in items:
        if "smoke_run" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.xdist_group("smoke"))


@pytest.fixture(scope="session")
def smoke_run(tmp_path_factory) -> SmokeRun:
    import contextlib
    import io

    from pipeline.cli import main

    root = tmp_path_factory.mktemp("smoke")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["sweep", str(REPO / "sweeps" / "smoke.toml"), "--out", str(root),
                     "--serial", "--no-progress"])
    report_printed = io.StringIO()
    with contextlib.redirect_stdout(report_printed):
        report_code = main(["report", str(root / "smoke")])
    return SmokeRun(root / "smoke", code, printed.getvalue(), report_code, report_printed.getvalue())
