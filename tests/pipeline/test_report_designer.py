"""The report for the designer: the summary table per operating point first, the
designer figures, the configuration last in engineering units; ``metrics.nc`` carrying the
designer outputs.

The designer outputs of the synthetic sweep are made up here (a known function of the grid
point, put into ``sweep.nc`` as the case files carry them): the tests check that each
value reaches the right row and column in the right engineering unit, computed here from
the dataset's variables, not their physics (the core's tests check that).
"""
from __future__ import annotations

import csv
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pipeline.analysis import DESIGNER_METRICS, DESIGNER_SCALARS, REALIZATION
from pipeline.io import encoding_for
from pipeline.report import build_report
from pipeline.report.context import Context
from pipeline.report.summary import ABSENT, COLUMNS, section_summary
from pipeline.schema import sweep_from_dict
from rvcore.profile import PHASES
from tests.pipeline.test_report import section_of, table_rows, synthetic_sweep
from tests.pipeline.test_report_stiffness import add_stiffness

REPO = Path(__file__).resolve().parents[2]

#: The summary table's safety-factor column, as the report labels it.
SAFETY_COLUMN = next(c.header for c in COLUMNS if c.key == "safety")

#: Phase titles as the report writes them.
TITLE = {"startup": "start-up", "steady": "steady", "deceleration": "deceleration"}


def made_up(name: str, speed_deg: float, load: float) -> np.ndarray:
    """A synthetic value of designer output ``name`` at a grid point [SI]: shape (3,) per phase
    for a phase metric, () for a scalar. Distinct per phase so that a reduction over the
    phases is checkable; the safety factor is smallest in a phase that depends on the point."""
    x = speed_deg / 100.0 + load / 1e4                  # 1.2 ... 10.6, a different number per point
    per_phase = np.array([1.0, 2.0, 1.5])
    if name == "static_safety_factor_min":
        k = int(x) % 3                                  # the phase of the smallest: varies over the grid
        v = np.full(3, 5.0 / x)
        v[k] *= 0.5
        return v
    if name == "static_safety_factor_min_time":
        return np.array([0.5, 2.0, 4.0])
    if name in DESIGNER_SCALARS:
        return np.array(1e7 * x + {"rating_life_L10r": 1, "rating_life_cycles": 2, "fatigue_damage_cycle": 3,
                                   "reference_rating_life_L10r": 4, "basic_rating_life_L10": 5}.get(name, 6) * 1e5)
    scale = {"max_race_pv_peak": 1e7, "max_race_sliding_speed_peak": 0.01}.get(name, 10.0)
    return scale * x * per_phase


def add_designer_outputs(directory: Path, skip=()) -> xr.Dataset:
    """Add every designer output but ``skip`` to the synthetic ``sweep.nc`` (NaN where the
    case failed); return the sweep written."""
    path = directory / "sweep.nc"
    with xr.open_dataset(path, engine="netcdf4") as ds:
        sweep = ds.load()
    failed = sweep["case_status"].values != 0
    for name, (units, long_name) in {**DESIGNER_METRICS, **DESIGNER_SCALARS}.items():
        if name in skip:
            continue
        v = np.array([[made_up(name, s, f) for f in sweep["radial_load"].values] for s in sweep["speed"].values])
        v[failed] = np.nan
        dims = ("speed", "radial_load") + (("phase",) if name in DESIGNER_METRICS else ())
        sweep[name] = (dims, v, {"units": units, "long_name": long_name})
    sweep.to_netcdf(path, engine="netcdf4", encoding=encoding_for(sweep))
    return sweep


@pytest.fixture(scope="module")
def designer(tmp_path_factory):
    d = synthetic_sweep(tmp_path_factory.mktemp("designer"))   # 3x3, 390 °/s at 20 kN failed
    add_stiffness(d)
    sweep = add_designer_outputs(d)
    files = build_report(d)
    return d, sweep, files, files.markdown.read_text(), files.html.read_text()


def fmt_g3(x: float) -> str:
    """``x`` to 3 significant digits as the table writes it: 1234 as 1230, 12300000 as 1.23×10⁷."""
    text = f"{x:.3g}"
    if "e+" in text and abs(x) < 1e6:
        return str(round(float(text)))
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    digits = dict(zip("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return f"{mantissa}×10" + "".join(digits[c] for c in str(int(exponent)))


def test_the_summary_table_follows_the_headline(designer):
    _, _, _, md, html = designer
    assert [ln for ln in md.splitlines() if ln.startswith("## ")][:2] == ["## Headline",
                                                                        "## Summary per operating point"]
    assert html.index("<h2>Summary per operating point</h2>") < html.index("<h2>Cases</h2>")
    text = section_of(md, "## Summary per operating point")
    assert "This sweep lacks" not in text            # every output present
    assert "Every grid point is shown" in text


def test_summary_rows_match_the_dataset(designer):
    """One row per grid point, in grid order; each cell is the dataset's variable at that
    point, reduced and converted to the header's unit here."""
    _, sweep, _, md, _ = designer
    rows = table_rows(section_of(md, "## Summary per operating point"))
    header, rows = rows[0], rows[1:]
    col = {h: k for k, h in enumerate(header)}
    assert header[:2] == ["speed [°/s]", "radial load [kN]"]
    speeds, loads = sweep["speed"].values, sweep["radial_load"].values
    assert [(r[0], r[1]) for r in rows] == [(f"{s:g} °/s", f"{f / 1e3:g} kN") for s in speeds for f in loads]
    for r in rows:
        s, f = float(r[0].split()[0]), float(r[1].split()[0]) * 1e3
        at = sweep.sel(speed=s, radial_load=f)
        if (s, f) == (390.0, 20e3):                   # the failed case: nothing known there
            assert set(r[2:]) == {ABSENT}
            continue
        phase = {n: at[n].values for n in DESIGNER_METRICS}
        k = int(np.argmin(phase["static_safety_factor_min"]))
        assert r[col[SAFETY_COLUMN]] == fmt_g3(phase["static_safety_factor_min"].min())
        assert r[col["s₀ smallest in"]] == f"{TITLE[PHASES[k]]}, {phase['static_safety_factor_min_time'][k]:.3g} s"
        assert r[col["L10r of the duty cycle [Mrev]"]] == fmt_g3(float(at["rating_life_L10r"]) / 1e6)
        assert r[col["L10r of the duty cycle [cycles]"]] == fmt_g3(float(at["rating_life_cycles"]))
        assert r[col["L10r at the steady point (statics) [Mrev]"]] == fmt_g3(float(at["reference_rating_life_L10r"]) / 1e6)
        assert r[col["L10 (ISO 281) at the steady point [Mrev]"]] == fmt_g3(float(at["basic_rating_life_L10"]) / 1e6)
        assert r[col["peak start-up drive torque [N m]"]] == fmt_g3(phase["inner_ring_drive_torque_peak"][0])
        assert r[col["peak ball-pocket force [N]"]] == fmt_g3(phase["max_pocket_force_peak"].max())
        assert r[col["peak cage-land force [N]"]] == fmt_g3(phase["cage_land_force_peak"].max())
        assert r[col["peak race sliding speed [m/s]"]] == fmt_g3(phase["max_race_sliding_speed_peak"].max())
        assert r[col["peak race pv [MPa m/s]"]] == fmt_g3(phase["max_race_pv_peak"].max() / 1e6)
        steady = PHASES.index("steady")
        assert r[col["steady δ_r mean [µm]"]] == fmt_g3(float(at["radial_displacement_mean"][steady]) * 1e6)
        assert r[col["steady δ_a mean [µm]"]] == fmt_g3(float(at["axial_displacement_mean"][steady]) * 1e6)
        assert r[col["radial stiffness [N/µm]"]] == fmt_g3(float(at["radial_stiffness"]) / 1e6)    # N/m -> N/µm
        assert r[col["axial stiffness [N/µm]"]] == fmt_g3(float(at["axial_stiffness"]) / 1e6)
        assert r[col["tilting stiffness [N m/mrad]"]] == fmt_g3(float(at["tilting_stiffness"]) / 1e3)  # per rad -> per mrad


def test_summary_csv_holds_every_point(designer):
    d, sweep, files, md, _ = designer
    with open(d / "report" / "summary.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    table = table_rows(section_of(md, "## Summary per operating point"))
    assert rows[0] == table[0]
    assert len(rows) - 1 == sweep.sizes["speed"] * sweep.sizes["radial_load"]
    for r, t in zip(rows[1:], table[1:]):
        life = float(sweep["rating_life_L10r"].sel(speed=float(r[0]), radial_load=float(r[1]) * 1e3))
        got = r[table[0].index("L10r of the duty cycle [Mrev]")]
        assert (got == "") if math.isnan(life) else math.isclose(float(got), life / 1e6, rel_tol=1e-5)
        # the CSV's empty cells are the table's dashes
        assert [c == "" for c in r[2:]] == [c == ABSENT for c in t[2:]]


def test_designer_figures(designer):
    d, _, files, md, html = designer
    text = md.split("\n## Designer outputs against speed and load\n", 1)[1].split("\n## ", 1)[0]
    for key in ("startup_torque", "safety", "life_mrev", "static_life"):
        assert f"](figures/designer_{key}.png)" in text and f'src="figures/designer_{key}.png"' in html
        assert (d / "report" / "figures" / f"designer_{key}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the figures come after the summary and before the study comparison
    assert md.index("## Summary per operating point") < md.index("## Designer outputs") < md.index("## Fits beside")


def test_metrics_nc_carries_the_designer_outputs(designer):
    from compliance_checker.runner import CheckSuite

    from tests.pipeline.test_cf import cf_problems

    d, sweep, files, _, _ = designer
    with xr.open_dataset(files.metrics) as m:
        for name, (units, _) in {**DESIGNER_METRICS, **DESIGNER_SCALARS}.items():
            assert m[name].attrs["units"] == units and m[name].attrs["long_name"]
            assert ("phase" in m[name].dims) == (name in DESIGNER_METRICS)
            np.testing.assert_array_equal(m[name].transpose("speed", "radial_load", ...).values,
                                          sweep[name].transpose("speed", "radial_load", ...).values)
    suite = CheckSuite()
    suite.load_all_available_checkers()
    assert cf_problems(suite, files.metrics) == []


def test_an_older_sweep_says_what_it_lacks(tmp_path):
    """Without the life outputs (an older sweep, or a core that does not write them yet): —,
    and the section names them."""
    d = synthetic_sweep(tmp_path, speeds_deg=(120.0, 660.0), loads=(30e3, 40e3), missing=())
    add_designer_outputs(d, skip=("rating_life_L10r", "rating_life_cycles"))
    md = build_report(d).markdown.read_text()
    text = section_of(md, "## Summary per operating point")
    assert "This sweep lacks `rating_life_L10r`, `rating_life_cycles`" in text
    rows = table_rows(text)
    for k in (rows[0].index("L10r of the duty cycle [Mrev]"), rows[0].index("L10r of the duty cycle [cycles]")):
        assert {r[k] for r in rows[1:]} == {ABSENT}
    assert {r[rows[0].index("L10r at the steady point (statics) [Mrev]")] for r in rows[1:]}.isdisjoint({ABSENT})
    assert "designer_life_mrev.png" not in md and "designer_static_life.png" in md


def _metrics_grid(speeds, loads, seeds=None) -> xr.Dataset:
    """A metrics.nc-like dataset with the designer outputs over (speed, radial_load[, realization])."""
    coords = {"speed": ("speed", np.asarray(speeds, float)), "radial_load": ("radial_load", np.asarray(loads, float)),
              "phase": ("phase", np.arange(3, dtype=np.int8))}
    data = {}
    for name in (*DESIGNER_METRICS, *DESIGNER_SCALARS):
        v = np.array([[made_up(name, s, f) for f in loads] for s in speeds])
        dims = ["speed", "radial_load"] + (["phase"] if name in DESIGNER_METRICS else [])
        if seeds is not None:
            v = np.stack([v * (1.0 + 0.1 * k) for k in range(len(seeds))], axis=-1)
            dims.append(REALIZATION)
        data[name] = (dims, v)
    if seeds is not None:
        coords[REALIZATION] = (REALIZATION, np.asarray(seeds))
    return xr.Dataset(data, coords=coords)


def _context(metrics: xr.Dataset, tmp_path: Path) -> Context:
    return Context(directory=tmp_path, sweep=xr.Dataset(), metrics=metrics, fits=xr.Dataset(), status={},
                   references=[], reference_path=tmp_path, outdir=tmp_path)


def test_study_grid_shows_corners_and_middle(tmp_path):
    """The study's 5 x 10 grid: the report shows the four corners and the middle point, the CSV all 50."""
    speeds = np.linspace(120.0, 660.0, 5)
    loads = np.linspace(20e3, 40e3, 10)
    ctx = _context(_metrics_grid(speeds, loads), tmp_path)
    blocks, path = section_summary(ctx), ctx.summary_path
    table = next(b for b in blocks if hasattr(b, "rows"))
    shown = [(r[0], r[1]) for r in table.rows]
    expected = [(i, j) for i, j in ((0, 0), (0, 9), (2, 5), (4, 0), (4, 9))]
    assert shown == [(f"{speeds[i]:.4g} °/s", f"{loads[j] / 1e3:.4g} kN") for i, j in expected]
    assert any("50 points" in getattr(b, "text", "") and "four corners and the middle" in b.text for b in blocks)
    with open(path, newline="") as fh:
        assert len(list(csv.reader(fh))) == 1 + 50


def test_ensemble_summary_is_the_mean_over_realizations(tmp_path):
    seeds = [0, 1, 2]
    m = _metrics_grid([120.0, 660.0], [20e3, 40e3], seeds)
    m["rating_life_L10r"][0, 0, 2] = np.nan          # a realization that did not finish: left out of its mean
    blocks = section_summary(_context(m, tmp_path))
    table = next(b for b in blocks if hasattr(b, "rows"))
    k = table.header.index("L10r of the duty cycle [Mrev]")
    lives = [made_up("rating_life_L10r", s, f) for s in (120.0, 660.0) for f in (20e3, 40e3)]
    means = [float(x) * (1.0 + 0.1) for x in lives]  # mean of factors 1, 1.1, 1.2
    means[0] = float(lives[0]) * 1.05                # mean of factors 1, 1.1
    assert [r[k] for r in table.rows] == [fmt_g3(x / 1e6) for x in means]
    # s₀: the minimum over the phases per realization, then the mean
    k = table.header.index(SAFETY_COLUMN)
    s0 = made_up("static_safety_factor_min", 120.0, 20e3).min() * 1.1
    assert table.rows[0][k] == fmt_g3(s0)
    assert table.rows[0][k + 1] in TITLE.values()    # an ensemble: the phase, no time


def test_appendix_in_engineering_units(tmp_path):
    """The configuration last, 120 °/s for a fixed sweep speed (never 2.094 rad/s), with units
    as a reader writes them."""
    study = REPO / "sweeps" / "study.toml"
    raw = {k: v for k, v in tomllib.loads(study.read_text()).items() if k not in ("realizations", "seed", "sensors")}
    raw["axes"] = {"radial_load": ["20 kN", "30 kN", "40 kN"]}
    raw["fixed"] = {**raw.get("fixed", {}), "speed": "120 deg/s"}
    config = sweep_from_dict(raw, study).configuration
    d = synthetic_sweep(tmp_path, speeds_deg=(120.0,), loads=(20e3, 30e3, 40e3), missing=(), config=config)
    md = build_report(d).markdown.read_text()
    assert [ln for ln in md.splitlines() if ln.startswith("## ")][-1] == "## Appendix: bearing, profile and parameters"
    rows = {r[0]: r[1:] for r in table_rows(section_of(md, "## Appendix: bearing, profile and parameters"))[1:]}
    assert rows["`speed`"][0] == "120 °/s" and rows["`speed`"][1].startswith("sweep fixed")
    assert rows["`radial_load`"][0] == "[20, 30, 40] kN"
    assert rows["`contact.damping`"][0].endswith(" N s/m")
    assert rows["`material.youngs_modulus`"][0].endswith(" GPa")
    assert rows["`rows[0].balls.diameter`"][0].endswith(" mm")
    assert rows["`contact.damping_depth`"][0].endswith(" µm")
    assert rows["`rows[0].radial_clearance`"][2] == "**assumed**"
    assert not [v for v, *_ in rows.values() if "e+" in v or "e-" in v]   # 1×10⁹, not 1e+09
    assert "2.094" not in md and "rad/s" not in md and "deg/s" not in md


def test_unloaded_life_is_infinite_and_undefined_safety_is_absent(tmp_path):
    """No load at a point: no Hertz pressure (s₀ NaN, "—") and an infinite life ("∞", "inf" in the CSV)."""
    m = _metrics_grid([120.0, 660.0], [20e3, 40e3])
    m["rating_life_L10r"][0, 0] = np.inf
    m["static_safety_factor_min"][0, 0, :] = np.nan
    ctx = _context(m, tmp_path)
    blocks, path = section_summary(ctx), ctx.summary_path
    table = next(b for b in blocks if hasattr(b, "rows"))
    row = table.rows[0]
    assert row[table.header.index("L10r of the duty cycle [Mrev]")] == "∞"
    k = table.header.index(SAFETY_COLUMN)
    assert row[k] == ABSENT and row[k + 1] == ABSENT
    with open(path, newline="") as fh:
        first = list(csv.reader(fh))[1]
    assert first[table.header.index("L10r of the duty cycle [Mrev]")] == "inf"


def test_report_warns_where_catalogue_ratings_are_reduced_or_refused():
    """The definitions section reads the stored bearing: the 6010 file (grooves 0.625 D_w)
    gets a warning naming ISO 76's reduced f0 and ISO 281's refused C_r; the study bearing
    (0.52/0.53) none; Palmgren's row is named for each."""
    import types

    from pipeline.report import definitions
    from pipeline.schema.bearingfile import load_bearing

    bearings = Path(__file__).resolve().parents[2] / "sweeps" / "bearings"
    open_ = types.SimpleNamespace(configuration=types.SimpleNamespace(
        bearing=load_bearing(bearings / "deep-groove-6010.toml")))
    study = types.SimpleNamespace(configuration=types.SimpleNamespace(
        bearing=load_bearing(bearings / "rv-main-study.toml")))
    blocks = definitions._rating_basis(open_)
    assert len(blocks) == 1
    text = blocks[0].text
    assert "reduced" in text and "not rated" in text and "0.625" in text
    assert definitions._rating_basis(study) == []
    assert "deep-groove row" in definitions._palmgren_basis(open_)
    assert "30-40 deg" in definitions._palmgren_basis(study)
