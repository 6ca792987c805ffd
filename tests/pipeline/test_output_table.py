"""The output table (rvcore.output_table) is the one home of every output: each of its rows
appears in a case file and, where it is a per-case quantity, in metrics.nc, with the
table's units and long_name; no data variable appears that the table lacks; and
docs/outputs.md lists exactly the table's rows."""
from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest
import xarray as xr

from rvcore.output_table import OUTPUTS, PHASE, SERIES, SPECTRUM

REPO = Path(__file__).resolve().parents[2]

#: Data variables of a file that are not outputs of a case: the grid's bookkeeping.
BOOKKEEPING = {"case_status"}
#: metrics.nc's ensemble statistics of the displacement metrics (over realizations).
ENSEMBLE_SUFFIXES = ("_ensemble_mean", "_ensemble_std", "_ensemble_stderr", "_ensemble_count")


@pytest.fixture(scope="module")
def sensor_sweep(tmp_path_factory):
    """A 2 × 1 sweep of the reduced bearing on the short cycle with two virtual sensors:
    every kind of output (series, phase, sensor, steady, duty cycle, spectrum) is written."""
    from pipeline.cli import main

    root = tmp_path_factory.mktemp("table")
    text = (REPO / "sweeps" / "smoke.toml").read_text()
    text = re.sub(r"\[axes\].*?\n\n", '[axes]\nspeed = ["120 deg/s", "660 deg/s"]\nradial_load = ["30 kN"]\n\n',
                  text, flags=re.S)
    text = text.replace('bearing = "bearings/', f'bearing = "{REPO}/sweeps/bearings/')
    text = text.replace('profile = "profiles/', f'profile = "{REPO}/sweeps/profiles/')
    text += ('\n[[sensors]]\nname = "radial_bore"\nposition = ["45 mm", "0 mm", "0 mm"]\ndirection = [1, 0, 0]\n'
             '\n[[sensors]]\nname = "axial_face"\nposition = ["56 mm", "0 mm", "6 mm"]\ndirection = [0, 0, 1]\n')
    path = root / "table.toml"
    path.write_text(text)
    with contextlib.redirect_stdout(io.StringIO()):
        code = main(["sweep", str(path), "--out", str(root / "out"), "--serial", "--no-progress"])
        assert code == 0
        assert main(["report", str(root / "out" / "smoke")]) == 0     # it writes metrics.nc
    return root / "out" / "smoke"


def _data_variables(path) -> dict:
    with xr.open_dataset(path) as ds:
        return {k: dict(v.attrs) for k, v in ds.data_vars.items()}


def test_every_row_is_in_a_case_file_with_its_units_and_nothing_else(sensor_sweep):
    case = _data_variables(next((sensor_sweep / "cases").glob("*.nc")))
    assert set(case) - BOOKKEEPING == {o.name for o in OUTPUTS}
    for o in OUTPUTS:
        assert case[o.name]["units"] == o.units, o.name
        assert case[o.name]["long_name"] == o.long_name, o.name


def test_every_per_case_row_is_in_metrics_nc_and_nothing_else(sensor_sweep):
    """metrics.nc holds the per-case quantities: every phase metric and scalar (the
    series and spectra are sweep.nc's), plus the ensemble statistics of the displacement
    metrics, which derive from the table's rows by name."""
    metrics = _data_variables(sensor_sweep / "metrics.nc")
    per_case = {o.name: o for o in OUTPUTS if o.kind not in (SERIES, SPECTRUM)}
    for name, o in per_case.items():
        assert name in metrics, name
        assert metrics[name]["units"] == o.units and metrics[name]["long_name"] == o.long_name, name
    for name in set(metrics) - BOOKKEEPING - set(per_case):
        base = next((name[:-len(s)] for s in ENSEMBLE_SUFFIXES if name.endswith(s)), None)
        assert base in per_case and per_case[base].kind == PHASE, f"metrics.nc: {name} is not in the output table"


def test_docs_outputs_lists_the_table():
    """docs/outputs.md's variable tables are the ones the output table writes
    (:func:`pipeline.io.case.variables_markdown`), and they name every row once."""
    from pipeline.io.case import variables_markdown

    text = (REPO / "docs" / "outputs.md").read_text()
    block = text.split("<!-- begin variables (generated) -->\n")[1].split("<!-- end variables -->")[0]
    assert block == variables_markdown(), ("docs/outputs.md is out of date: paste the output of python -c "
                                           "'from pipeline.io.case import variables_markdown as v; print(v())'")
    listed = re.findall(r"^\| `([a-zA-Z0-9_]+)` \|", block, flags=re.M)
    assert sorted(listed) == sorted(o.name for o in OUTPUTS)
