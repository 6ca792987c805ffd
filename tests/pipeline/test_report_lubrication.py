"""The report's lubrication section (issue 40) on a hand-made metrics set: the regimes it
counts from λ's published bounds (boundary < 1 ≤ mixed < 3 ≤ full film), the lives side by
side, the figure written."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from pipeline.report.lubrication import section_lubrication
from pipeline.report.render import Image, Para, Table


class _Ctx:
    """What the section reads of a report context: the metrics and where figures go."""

    def __init__(self, metrics, folder: Path):
        self.metrics, self.folder, self.figures = metrics, folder, []

    def figure_path(self, name):
        (self.folder / "figures").mkdir(parents=True, exist_ok=True)
        p = self.folder / "figures" / name
        self.figures.append(p)
        return p


def _metrics():
    speed = xr.DataArray([120.0, 390.0, 660.0], dims="speed", attrs={"units": "degree s-1"})
    load = xr.DataArray([20e3, 40e3], dims="radial_load", attrs={"units": "N"})
    lam = np.array([[0.5, 0.45], [2.0, 1.9], [4.0, 3.8]])
    l10 = np.full((3, 2), 5e8)
    a = np.array([[0.3, 0.3], [2.0, 2.0], [10.0, 10.0]])
    data = {"film_parameter_steady": lam, "film_thickness_min_steady": lam * 0.186e-6,
            "kappa_steady": np.array([[0.34] * 2, [0.9] * 2, [1.4] * 2]), "a_iso_steady": a,
            "basic_rating_life_L10": l10, "reference_rating_life_L10r": 0.7 * l10,
            "modified_rating_life_L_nm": a * l10}
    return xr.Dataset({k: (("speed", "radial_load"), v) for k, v in data.items()},
                      coords={"speed": speed, "radial_load": load})


def test_the_section_counts_regimes_and_puts_the_lives_side_by_side(tmp_path):
    blocks = section_lubrication(_Ctx(_metrics(), tmp_path))
    text = " ".join(b.text for b in blocks if isinstance(b, Para))
    # λ: 0.5, 0.45 boundary; 2.0, 1.9 mixed; 4.0, 3.8 full film
    assert "2 of the 6 cases run in boundary lubrication" in text and "2 mixed" in text
    assert "2 in full film" in text and "±30 %" in text and "upper bounds" in text
    table = next(b for b in blocks if isinstance(b, Table))
    assert table.header[1:4] == ["L10 [10⁶ rev]", "L10r [10⁶ rev]", "L_nm [10⁶ rev]"]
    # at 660 °/s: L_nm = a_ISO·L10 = 10 × 500 = 5000 (10⁶ rev)
    assert table.rows[2][0] == "660" and table.rows[2][3] == "5000"
    image = next(b for b in blocks if isinstance(b, Image))
    assert (tmp_path / image.path).is_file() and (tmp_path / image.path).stat().st_size > 1000


def test_an_older_sweep_without_lubrication_outputs_says_so(tmp_path):
    blocks = section_lubrication(_Ctx(_metrics().drop_vars(["film_parameter_steady", "film_thickness_min_steady",
                                                            "kappa_steady"]), tmp_path))
    assert "holds no lubrication outputs" in blocks[1].text


def _cycle_metrics():
    """_metrics() with the film along the cycle over (speed, radial_load, phase) and the
    cycle's lives: λ's phase means 0.5 (start-up), 2.0 (steady), 3.5 (deceleration) at every
    case, smallest λ 0.05, 1.5 and 1.0."""
    ds = _metrics()
    shape = (3, 2, 3)
    lam_mean = np.broadcast_to(np.array([0.5, 2.0, 3.5]), shape)
    lam_min = np.broadcast_to(np.array([0.05, 1.5, 1.0]), shape)
    dims = ("speed", "radial_load", "phase")
    ds = ds.assign({"film_parameter_mean": (dims, lam_mean.copy()), "film_parameter_min": (dims, lam_min.copy()),
                    "film_thickness_minimum_mean": (dims, lam_mean * 0.186e-6),
                    "kappa_mean": (dims, np.full(shape, 0.8)), "kappa_min": (dims, np.full(shape, 0.0)),
                    "rating_life_L10r": (("speed", "radial_load"), np.full((3, 2), 4e8)),
                    "rating_life_L_nm": (("speed", "radial_load"), np.full((3, 2), 2e8)),
                    "a_iso_cycle": (("speed", "radial_load"), np.full((3, 2), 0.5)),
                    "kappa_below_scope_fraction": (("speed", "radial_load"), np.full((3, 2), 0.01))})
    return ds.assign_coords(phase=np.arange(3, dtype=np.int8))


def test_each_phase_gets_its_regime_from_lambda(tmp_path):
    """The regime table: a phase's regime from its mean λ by the published bounds (0.5
    boundary, 2.0 mixed, 3.5 full film), its worst from its smallest λ (0.05 boundary, 1.5
    and 1.0 mixed); the cycle's lives appended to the lives' table; both figures written."""
    blocks = section_lubrication(_Ctx(_cycle_metrics(), tmp_path))
    tables = [b for b in blocks if isinstance(b, Table)]
    regimes = next(t for t in tables if "regime" in t.header)
    got = {(r[0], r[1]): (r[4], r[6]) for r in regimes.rows}
    assert got[("120", "startup")] == ("boundary", "boundary")
    assert got[("390", "steady")] == ("mixed", "mixed")
    assert got[("660", "deceleration")] == ("full film", "mixed")
    lives = next(t for t in tables if "L10 [10⁶ rev]" in t.header)
    assert lives.header[6:8] == ["cycle L10r [10⁶ rev]", "cycle L_nm [10⁶ rev]"]
    assert lives.rows[0][6:8] == ["400", "200"]
    images = [b for b in blocks if isinstance(b, Image)]
    assert len(images) == 2 and all((tmp_path / i.path).stat().st_size > 1000 for i in images)
