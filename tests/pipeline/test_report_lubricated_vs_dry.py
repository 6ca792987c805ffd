"""``rvsweep report DIR --dry DIR2`` (issue 40): a lubricated sweep's cage slip, drive torque
and transient ranges beside a dry sweep's of the same grid, on two tiny synthetic sweeps
(2 speeds x 2 loads) whose lubricated values are the dry ones times known factors, so every
number the section prints is known here: the synthetic dry values
(tests/pipeline/synthetic.py) and those factors."""
from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

import tests.pipeline.test_metrics as synthetic_sweeps
from pipeline.cli import main
from pipeline.report import build_report
from pipeline.schema import sweep_from_dict
from rvcore.profile import study_profile
from tests.pipeline.synthetic import synthetic_result
from tests.pipeline.test_report import REPO, section_of, table_rows

SPEEDS, LOADS = (120.0, 660.0), (30e3, 40e3)
#: The lubricated sweep's values over the dry one's: cage slip, drive torque, δ_r ranges.
SLIP, TORQUE, RANGE = 2.0, 1.5, 0.8


def _configuration(law: str, speeds=SPEEDS):
    """The study sweep's stored configuration on the grid, with friction law ``law``."""
    raw = {k: v for k, v in tomllib.loads((REPO / "sweeps" / "study.toml").read_text()).items()
           if k not in ("realizations", "seed", "sensors")}
    raw["axes"] = {"speed": [f"{s:g} deg/s" for s in speeds], "radial_load": [f"{f / 1e3:g} kN" for f in LOADS]}
    if law != "coulomb_step":
        raw["fixed"] = dict(raw.get("fixed", {}), **{"friction.law": law,
                                                    "lubricant.kinematic_viscosity": "100 mm^2/s"})
    return sweep_from_dict(raw, REPO / "sweeps" / "study.toml").configuration


def _case(wet: bool):
    """synthetic_result with the phase windows and a drive torque (load/1000 N m in every phase);
    the lubricated case's cage slip, torque and δ_r ranges scaled by SLIP, TORQUE, RANGE."""
    def result(speed, radial_load, axial_load=10e3, **kw):
        r = synthetic_result(speed, radial_load, axial_load, **kw)
        m = r.phase_metrics
        m["phase_start"] = np.array([a for _, a, _ in study_profile().phases])
        m["phase_end"] = np.array([b for _, _, b in study_profile().phases])
        m["inner_ring_drive_torque_mean"] = np.full(3, radial_load / 1e3)
        if wet:
            m["cage_slip"] = m["cage_slip"] * SLIP
            m["inner_ring_drive_torque_mean"] = m["inner_ring_drive_torque_mean"] * TORQUE
            m["radial_displacement_range"] = m["radial_displacement_range"] * RANGE
        return r
    return result


def _sweep(directory, wet: bool, speeds=SPEEDS):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(synthetic_sweeps, "synthetic_result", _case(wet))
        return synthetic_sweeps.build_synthetic_sweep(
            directory, speeds_deg=speeds, loads=LOADS, missing=(),
            config=_configuration("ehl_bair_winer" if wet else "coulomb_step", speeds))


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    root = tmp_path_factory.mktemp("wetdry")
    return _sweep(root / "wet", True), _sweep(root / "dry", False)


def test_the_section_puts_each_point_beside_the_dry_one(pair):
    wet, dry = pair
    build_report(wet, dry=dry)
    text = section_of((wet / "report" / "report.md").read_text(), "## Lubricated against dry")
    assert "`ehl_bair_winer`" in text and "`coulomb_step`" in text and "Not a lubricated" not in text
    rows = {(r[0], r[1]): r[2:] for r in table_rows(text) if r[0] in ("120", "660")}
    assert set(rows) == {("120", "30"), ("120", "40"), ("660", "30"), ("660", "40")}
    # dry: synthetic cage slip 0.5 % steady, torque = load/1000; the lubricated ones x2 and x1.5
    cells = rows[("660", "40")]
    assert float(cells[0]) == pytest.approx(0.5 * SLIP) and float(cells[1]) == pytest.approx(0.5)
    assert float(cells[2]) == pytest.approx(40 * TORQUE) and float(cells[3]) == pytest.approx(40.0)
    # the δ_r ranges [µm]: the dry one is the synthetic series' range over the start-up, by itself
    ref = synthetic_result(math.radians(660.0), 40e3).phase_metrics["radial_displacement_range"] * 1e6
    for k in range(3):
        assert float(cells[5 + 2 * k]) == pytest.approx(ref[k], rel=1e-3)
        assert float(cells[4 + 2 * k]) == pytest.approx(RANGE * ref[k], rel=1e-3)
    # the medians over the grid of lubricated/dry are the factors
    assert "cage slip, steady [%]: lubricated/dry, median over the grid, 2" in text
    assert "drive torque, steady [N m]: lubricated/dry, median over the grid, 1.5" in text
    assert "δ_r range, start-up [µm]: lubricated/dry, median over the grid, 0.8" in text


def test_a_lubricated_sweep_without_dry_says_how_and_a_dry_one_shows_nothing(pair, tmp_path):
    wet, dry = pair
    build_report(wet)
    text = section_of((wet / "report" / "report.md").read_text(), "## Lubricated against dry")
    assert "--dry DRY_DIR" in text
    build_report(dry)
    assert "## Lubricated against dry" not in (dry / "report" / "report.md").read_text()


def test_a_dry_sweep_of_another_grid_or_no_folder_is_one_line_before_any_work(pair, tmp_path, capsys):
    wet, _ = pair
    other = _sweep(tmp_path / "other", False, speeds=(120.0, 390.0))
    (wet / "report" / "report.md").unlink(missing_ok=True)
    assert main(["report", str(wet), "--dry", str(other)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--dry" in err and "speed" in err and "same grid" in err
    assert not (wet / "report" / "report.md").exists()
    assert main(["report", str(wet), "--dry", str(tmp_path / "nowhere")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--dry" in err and "nowhere" in err
