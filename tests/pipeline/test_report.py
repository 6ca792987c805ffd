"""``rvsweep report`` on a small synthetic sweep: sections, figures, the 12-row table, caveats,
missing cases, the computed physics paragraph and reproducibility; on a synthetic
ensemble sweep with virtual sensors (sensor table and figures, ensemble captions, the
window-edge section, both cage-slip definitions); on a real (tiny) run of the core; and
the stored configuration read back into the core's dataclasses."""
from __future__ import annotations

import math
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import rvcore.simulation.run
import tests.pipeline.test_metrics as synthetic_sweeps
from pipeline.cli import main
from pipeline.analysis import default_reference_path, load_reference_fits
from pipeline.errors import ConfigError
from pipeline.report import build_report, ensemble_statistics, sensors
from pipeline.io import CaseState
from pipeline.run import run_sweep
from pipeline.run.corners import store_corner_statics
from pipeline.schema import read_sweep_file, stored_configuration, sweep_from_dict
from rvcore.profile import PHASES, study_profile
from tests.pipeline.synthetic import synthetic_result
from tests.pipeline.test_metrics import CAVEAT, FAILED_REASON, build_synthetic_sweep

REPO = Path(__file__).resolve().parents[2]



def study_grid_sweep(speeds_deg=(120.0, 390.0, 660.0), loads=(20e3, 30e3, 40e3)):
    """The study's sweep on a synthetic grid (default 3 x 3), without its ensemble and sensors (51
    balls of 23 mm on a 351.5 mm pitch circle, ball density 7800 kg/m^3, the assumptions marked)."""
    study = REPO / "sweeps" / "study.toml"
    raw = {k: v for k, v in tomllib.loads(study.read_text()).items()
           if k not in ("realizations", "seed", "sensors")}
    raw["axes"] = {"speed": [f"{s:g} deg/s" for s in speeds_deg], "radial_load": [f"{f / 1e3:g} kN" for f in loads]}
    return sweep_from_dict(raw, study)


def store_statics(directory, speeds_deg=(120.0, 390.0, 660.0), loads=(20e3, 30e3, 40e3),
                  missing=((390.0, 20e3),)):
    """``statics.nc`` as the runner writes it when a sweep finishes (:mod:`pipeline.run.corners`),
    for a synthetic sweep of the study's bearing: the study's sweep on the same grid, the
    ``missing`` points not finished."""
    sweep = study_grid_sweep(speeds_deg, loads)
    states = {}
    for i, spec in enumerate(sweep.cases):
        s, f = math.degrees(spec.point["speed"]), spec.point["radial_load"]
        failed = any(math.isclose(s, ms) and math.isclose(f, mf) for ms, mf in missing)
        states[spec.case_id] = CaseState(spec.case_id, i, spec.point, state="failed" if failed else "ok")
    return store_corner_statics(sweep, directory, states)


#: A real stored configuration (of :func:`study_grid_sweep`), as sweep.nc stores it.
STUDY_CONFIG = study_grid_sweep().configuration


def _with_windows(speed, radial_load, axial_load=10e3, **kw):
    """:func:`synthetic_result` with the study's phase windows as ``phase_start``/``phase_end``,
    as every real case writes them."""
    r = synthetic_result(speed, radial_load, axial_load, **kw)
    r.phase_metrics["phase_start"] = np.array([a for _, a, _ in study_profile().phases])
    r.phase_metrics["phase_end"] = np.array([b for _, _, b in study_profile().phases])
    return r


def synthetic_sweep(directory, windows: bool = True, **kw):
    """``build_synthetic_sweep`` with a real stored configuration and, with ``windows``, the
    phase windows in the data; with ``statics`` (default: with the study's configuration) the
    statics at the extreme cases stored as a run stores them (:func:`store_statics`)."""
    statics = kw.pop("statics", "config" not in kw)
    kw.setdefault("config", STUDY_CONFIG)
    with pytest.MonkeyPatch.context() as mp:
        if windows:
            mp.setattr(synthetic_sweeps, "synthetic_result", _with_windows)
        d = build_synthetic_sweep(directory, **kw)
    if statics:
        store_statics(d, **{k: kw[k] for k in ("speeds_deg", "loads", "missing") if k in kw})
    return d

#: The report's sections in their order: the headline first, the designer's summary, then the
#: cases and the figures, the study comparison, the files and the configuration as an appendix.
SECTIONS = ("# Sweep report", "## Headline", "## Summary per operating point", "## Cases", "## Time histories",
            "## Metrics against speed and load", "## Cage slip", "## Fits beside the study's (Tables 3 and 4)",
            "## Where our physics agrees with the study and where it does not", "## Files",
            "## Appendix: bearing, profile and parameters")


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    d = synthetic_sweep(tmp_path_factory.mktemp("rep"))  # 3x3, 390 °/s at 20 kN failed
    files = build_report(d)
    return d, files, (d / "report" / "report.md").read_text(), (d / "report" / "report.html").read_text()


def test_every_section_and_figure(built):
    d, files, md, html = built
    for s in SECTIONS:
        assert s in md
    headings = [ln for ln in md.splitlines() if ln.startswith("#")]
    at = [next(k for k, h in enumerate(headings) if h.startswith(s)) for s in SECTIONS]
    assert at == sorted(at)   # in this order
    sections = [h for h in headings if h.startswith("## ")]
    assert sections[:2] == ["## Headline", "## Summary per operating point"]
    assert sections[-1] == "## Appendix: bearing, profile and parameters"
    assert (d / "metrics.nc").exists() and (d / "fits.nc").exists()
    names = sorted(p.name for p in (d / "report" / "figures").glob("*.png"))
    expected = ["time_histories.png", "cage_slip_steady.png", "load_distribution.png"] + [f"metric_{p}_{x}_{m}.png" for p, x, m in (
        ("startup", "radial", "range"), ("deceleration", "radial", "range"), ("steady", "radial", "mean"),
        ("startup", "axial", "range"), ("deceleration", "axial", "range"), ("steady", "axial", "mean"))]
    assert names == sorted(expected)
    for name in names:
        data = (d / "report" / "figures" / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        assert b"Software" not in data and b"matplotlib" not in data  # no version metadata
        assert f"](figures/{name})" in md
        assert f'src="figures/{name}"' in html
    assert "<h2>Cases</h2>" in html and "<table>" in html
    # no sensors, no ensemble: none of their sections or wording
    assert "## Displacement sensors" not in md and "realization" not in md
    assert "δ_r and δ_a at the ring centre of the extreme cases" in md


def test_comparison_table_has_the_twelve_rows(built):
    _, _, md, html = built
    refs = load_reference_fits(default_reference_path())
    rows = [ln for ln in md.splitlines() if re.match(r"\| Table [34], row \d", ln)]
    assert len(rows) == 12
    for ref in refs:
        assert sum(ln.startswith(f"| {ref.label} |") for ln in rows) == 1
        assert f"<td>{ref.label}</td>" in html
    # Each row is fitted at the study's fixed value, which the grid holds.
    for ln in rows:
        cells = [c.strip() for c in ln.strip("|").split("|")]
        assert cells[1] == ("30 kN" if "Table 3" in ln else "120 °/s")


def test_comparison_values_in_study_units(built):
    """The synthetic steady δ_r is 2e-9 m/N·F_r − 1e-7 m/(rad/s)·ω: check the two mean-radial rows."""
    _, _, md, _ = built
    rows = {ln.split("|")[1].strip(): [c.strip() for c in ln.strip("|").split("|")]
            for ln in md.splitlines() if re.match(r"\| Table [34], row \d", ln)}
    t3 = rows["Table 3, row 3: Steady-State, Mean Radial Displacement"]
    slope_mm_per_deg_s = -1e-7 * 1e3 * math.pi / 180.0  # m per rad/s -> mm per °/s
    assert t3[4].startswith(f"{slope_mm_per_deg_s:.2e} [")
    assert t3[-1] == "yes"  # the study's slope is negative too
    t4 = rows["Table 4, row 3: Steady-State, Mean Radial Displacement"]
    assert t4[4].startswith(f"{2e-9 * 1e3:.2e} [")
    assert t4[-1] == "yes"
    assert t4[7] == "3"  # three loads at 120 °/s


def test_parameters_with_assumptions_marked(built):
    _, _, md, _ = built
    assert "bearing: **study-table2**" in md and "profile: **study**" in md
    rows = {r[0]: r[1:] for r in table_rows(section_of(md, "## Appendix: bearing, profile and parameters"))[1:]}
    # keys are the bearing file's own key paths, values in the schema's display units
    assert rows["`rows[0].radial_clearance`"][2] == "**assumed**"
    # a listed table (rows[0].outer_groove.arcs) marks every value in it
    assert rows["`rows[0].outer_groove.arcs[0].contact_angle`"][2] == "**assumed**"
    assert rows["`rows[0].balls.diameter`"][0] == "23 mm" and rows["`rows[0].balls.diameter`"][2] == ""
    assert rows["`rows[0].balls.count`"][0] == "51"
    assert rows["`material.density`"][0] == "7800 kg/m³"   # units as a reader writes them
    assert rows["`radial_load`"][0].endswith("kN")   # a sweep axis, in kN
    assert "case_ids" not in md


def test_caveat_is_prominent(built):
    _, _, md, html = built
    body = md.split("## Summary per operating point", 1)[0]  # before the first section
    assert "> **Geometry caveat.**" in body and CAVEAT in body
    assert '<div class="caveat">' in html


def test_missing_case_is_reported(built):
    _, files, md, _ = built
    assert files.missing == 1
    cases = md.split("## Cases", 1)[1].split("\n## ", 1)[0]
    assert "9 cases, 8 finished ok, 1 failed or missing" in cases
    row = next(ln for ln in cases.splitlines() if ln.startswith("| 390 °/s"))
    assert "| 20 kN |" in row and "| failed |" in row and FAILED_REASON in row and "excluded" in row


def test_physics_paragraph_numbers_are_computed(built):
    """F_c = m_b·(d_m/2)·ω_c² from the configuration and the synthetic cage speed."""
    _, _, md, _ = built
    text = md.split("## Where our physics agrees", 1)[1]
    m_b = 7800.0 * math.pi / 6.0 * 0.023**3  # configuration: D = 23 mm, rho = 7800 kg/m^3
    omega = math.radians(660.0)
    # synthetic steady phase: mean cage speed 0.468·ω, slip 0.005 against the epicyclic speed
    omega_c = 0.468 * omega / (1.0 - 0.005)
    f_c = m_b * (0.3515 / 2.0) * omega_c**2
    assert f"F_c = m_b·(d_m/2)·ω_c² = {f_c:.3g} N" in text
    q = 30e3 / 10.0  # synthetic max inner contact load: F_r/10 in the steady phase
    assert f"averages {q / 1e3:.3g} kN" in text
    assert f"{100 * f_c / q:.2g} %" in text
    # the study's mean axial displacement at 120 °/s against ours
    study = 1.996 + 7.9e-6 * 120.0
    assert f"{study:.4g} mm" in text
    ours_mm = (1e-9 * 10e3 + 5e-8 * math.radians(120.0)) * 1e3
    assert f"ours at the same point is {ours_mm:.3g} mm" in text


def test_report_is_reproducible_and_works_without_caveat(tmp_path):
    d = synthetic_sweep(tmp_path, speeds_deg=(120.0, 660.0), loads=(30e3, 40e3), missing=(), caveat="")
    build_report(d)
    first = {p.name: p.read_bytes() for p in (d / "report").rglob("*") if p.is_file()}
    build_report(d)
    second = {p.name: p.read_bytes() for p in (d / "report").rglob("*") if p.is_file()}
    assert first == second and len(first) == 12  # report.md, report.html, summary.csv and 9 figures
    assert not [p for p in (d / "report").rglob("*.tmp")]  # written atomically, nothing left over
    md = first["report.md"].decode()
    m_b = 7800.0 * math.pi / 6.0 * 0.023**3
    assert f"m_b = {m_b:.3g} kg" in md and "d_m/2 = 175.8 mm" in md
    assert "Geometry caveat" not in md
    assert "Every case of the grid finished." in md
    assert ("Phase windows from the sweep's `phase_start`/`phase_end`: start-up 0.3–0.8 s, steady 0.8–3.8 s, "
            "deceleration 3.8–4.3 s.") in md


def test_report_says_when_the_data_hold_no_phase_windows(tmp_path):
    """No guessing: without ``phase_start``/``phase_end`` the report says so and shades nothing."""
    d = synthetic_sweep(tmp_path, windows=False, speeds_deg=(120.0, 660.0), loads=(30e3, 40e3), missing=())
    md = build_report(d).markdown.read_text()
    assert "The data hold no phase windows (`phase_start`/`phase_end`)" in md
    assert "Phase windows from" not in md


def test_report_names_an_unreadable_configuration(tmp_path):
    """A configuration this version did not write: the report says why and leaves the table out."""
    d = synthetic_sweep(tmp_path, config='model_version = 1\nname = "old"\n', speeds_deg=(120.0, 660.0),
                        loads=(30e3, 40e3), missing=())
    md = build_report(d).markdown.read_text()
    text = section_of(md, "## Appendix: bearing, profile and parameters")
    assert "model_version = 1: written by another model version" in text
    assert "| key | value |" not in text
    assert "The centrifugal force on a ball could not be estimated" in md


def test_cli_on_a_partial_sweep_of_case_files(tmp_path, capsys):
    d = synthetic_sweep(tmp_path, speeds_deg=(120.0, 660.0), loads=(30e3, 40e3),
                        missing=((660.0, 40e3),), with_sweep_nc=False)
    assert main(["report", str(d)]) == 0
    out = capsys.readouterr().out
    assert "report.md" in out and "1 case(s) failed or missing" in out
    md = (d / "report" / "report.md").read_text()
    assert "4 cases, 3 finished ok, 1 failed or missing" in md
    row = next(ln for ln in section_of(md, "## Cases").splitlines() if ln.startswith("| 660 °/s | 40 kN |"))
    assert "| failed |" in row and FAILED_REASON in row


def test_cli_errors_are_one_line(tmp_path, capsys):
    assert main(["report", str(tmp_path / "nowhere")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "nowhere" in err
    (tmp_path / "empty").mkdir()
    assert main(["report", str(tmp_path / "empty")]) == 2
    assert "neither sweep.nc nor any cases" in capsys.readouterr().err
    bad = tmp_path / "rig.toml"
    bad.write_text("title = 'x'\nfoo = 1\n")
    d = synthetic_sweep(tmp_path / "s", speeds_deg=(120.0, 660.0), loads=(30e3, 40e3), missing=())
    assert main(["report", str(d), "--reference", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "rig.toml: foo" in err


# --------------------------------------------------------------------------- ensemble with sensors

#: A 3 x 3 grid, 2 realizations (seeds 0 and 1), two virtual sensors; run with ensemble_case.
ENSEMBLE_SWEEP = f"""\
name = "ens"
bearing = "{REPO / 'sweeps' / 'bearings' / 'reduced-test.toml'}"
profile = "{REPO / 'sweeps' / 'profiles' / 'short.toml'}"
realizations = 2

[axes]
speed = ["120 deg/s", "390 deg/s", "660 deg/s"]
radial_load = ["20 kN", "30 kN", "40 kN"]

[fixed]
axial_load = "10 kN"

[[sensors]]
name = "radial_bore"
position = ["160 mm", "0 mm", "0 mm"]
direction = [1, 0, 0]

[[sensors]]
name = "axial_face"
position = ["175.75 mm", "0 mm", "15 mm"]
direction = [0, 0, 1]
"""

ENSEMBLE_FAILED = "SimulationError: synthetic failure of seed 1 at 390 deg/s, 20 kN"


def ensemble_case(bearing, profile, op, settings, sensors=()):
    """:func:`tests.synthetic.synthetic_result` with the new phase metrics and sensor readings.

    Made-up but checkable: the seed adds 1e-7 m to the steady means and 0.001 to both
    cage slips (nominal = actual + 0.002); the start-up δ_r range is flagged at the window's
    edge for seed 0 at 660 deg/s, every steady range of sensor ``axial_face`` is flagged,
    nothing else; seed 1 at 390 deg/s, 20 kN fails.
    """
    seed = int(settings.seed)
    if seed == 1 and abs(op.speed - math.radians(390.0)) < 1e-6 and op.radial_load == 20e3:
        raise rvcore.simulation.run.SimulationError(ENSEMBLE_FAILED.removeprefix("SimulationError: "))
    r = synthetic_result(op.speed, op.radial_load, op.axial_load, n=47)
    t = r.time
    windows = [(a, b) for _, a, b in study_profile().phases]
    pm = r.phase_metrics
    pm["phase_start"] = np.array([a for a, _ in windows])
    pm["phase_end"] = np.array([b for _, b in windows])
    for name in ("radial_displacement", "axial_displacement"):
        pm[f"{name}_mean"] = pm[f"{name}_mean"] + 1e-7 * seed
        pm[f"{name}_min_time"] = pm["phase_start"].copy()
        pm[f"{name}_max_time"] = pm["phase_end"].copy()
        pm[f"{name}_range_at_edge"] = np.zeros(len(PHASES))
    if op.speed > 10.0 and seed == 0:
        pm["radial_displacement_range_at_edge"][0] = 1.0
    pm["cage_slip"] = pm["cage_slip"] + 0.001 * seed
    pm["cage_slip_nominal"] = pm["cage_slip"] + 0.002
    pm["epicyclic_cage_speed"] = pm["cage_speed_mean"] / (1.0 - pm["cage_slip"])
    rows = np.array([s.as_row() for s in sensors]).reshape(-1, 6)
    reading = (r.series["radial_displacement"][:, None] * rows[:, 3]
               + r.series["axial_displacement"][:, None] * rows[:, 5] + 1e-7 * seed)
    r.series["sensor_displacement"] = reading
    stats = {k: np.zeros((len(PHASES), len(sensors))) for k in ("range", "mean", "std", "min_time", "max_time")}
    for k, (a, b) in enumerate(windows):
        w = (t >= a) & (t < b)
        stats["range"][k] = np.ptp(reading[w], axis=0)
        stats["mean"][k] = reading[w].mean(axis=0)
        stats["std"][k] = reading[w].std(axis=0)
        stats["min_time"][k] = t[w][np.argmin(reading[w], axis=0)]
        stats["max_time"][k] = t[w][np.argmax(reading[w], axis=0)]
    edge = np.zeros((len(PHASES), len(sensors)))
    edge[PHASES.index("steady"), 1] = 1.0
    for k, v in stats.items():
        pm[f"sensor_displacement_{k}"] = v
    pm["sensor_displacement_range_at_edge"] = edge
    return r


@pytest.fixture(scope="module")
def ensemble(tmp_path_factory):
    """The synthetic ensemble sweep, run serially, and its report (built with warnings as errors)."""
    folder = tmp_path_factory.mktemp("ens")
    path = folder / "ens.toml"
    path.write_text(ENSEMBLE_SWEEP)
    run_sweep(path, folder / "out", serial=True, case_fn=ensemble_case, progress=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        files = build_report(folder / "out")
    return folder / "out", files, files.markdown.read_text(), files.html.read_text()


def section_of(md: str, heading: str) -> str:
    """The text under ``heading`` up to the next heading of any level."""
    return re.split(r"\n#{1,6} ", md.split(f"\n{heading}\n", 1)[1], maxsplit=1)[0]


def table_rows(text: str) -> list:
    """Rows of the first Markdown table in ``text`` as lists of cells (header first)."""
    lines = [ln for ln in text.splitlines() if ln.startswith("|") and not ln.startswith("|---")]
    return [[c.strip() for c in ln.strip("|").split("|")] for ln in lines]


def test_ensemble_sensor_table_and_figures(ensemble):
    d, files, md, html = ensemble
    text = section_of(md, "## Displacement sensors")
    assert table_rows(text) == [["sensor", "position [mm]", "direction"],
                            ["`radial_bore`", "(160, 0, 0)", "(1, 0, 0)"],
                            ["`axial_face`", "(175.75, 0, 15)", "(0, 0, 1)"]]
    assert "laser" in text and "tilt" in text
    names = sorted(p.name for p in files.figures)
    for name in ("sensor_time_histories.png", "sensor_startup_range.png", "sensor_deceleration_range.png",
                 "sensor_steady_mean.png", "cage_slip_steady.png", "time_histories.png"):
        assert name in names
        assert f"](figures/{name})" in md and f'src="figures/{name}"' in html
    # every sensor figure names its sensors with position and direction
    for ln in md.splitlines():
        if ln.startswith("The virtual sensors' readings") or ln.startswith("Readings of the virtual sensors"):
            assert "sensor `radial_bore` at (160, 0, 0) mm along (1, 0, 0)" in ln
            assert "sensor `axial_face` at (175.75, 0, 15) mm along (0, 0, 1)" in ln
    # the ring-centre figures say so
    headings = [ln for ln in md.splitlines() if ln.startswith("### ")]
    assert len(headings) == 9 and sum(h.endswith(", at the ring centre") for h in headings) == 6
    # phase windows from phase_start/phase_end, not from the configuration's (short) profile
    assert "Phase windows from the sweep's `phase_start`/`phase_end`: start-up 0.3–0.8 s, steady 0.8–3.8 s" in md
    with xr.open_dataset(files.metrics) as m:
        assert [s_.name for s_ in sensors(m)] == ["radial_bore", "axial_face"]


def test_ensemble_captions_give_n_and_error_bars(ensemble):
    d, files, md, _ = ensemble
    captions = [ln for ln in md.splitlines() if "Ensemble mean of" in ln]
    assert len(captions) == 9  # six at the ring centre, three of the sensors
    for c in captions:
        assert "Ensemble mean of N = 2 realizations (seeds 0, 1) per case with ±1 standard-error bars" in c
        assert "individual realizations as faint small points" in c and "weighted least-squares" in c
    assert "the first realization (seed 0) of N = 2" in section_of(md, "## Time histories")
    assert "× N = 2 realizations (seeds 0, 1): 9 grid points, 18 runs, 17 finished ok, 1 failed or missing" in md
    row = next(r for r in table_rows(section_of(md, "## Cases")) if r[0] == "390 °/s")
    assert row[1:5] == ["20 kN", "seed 1", "failed", ENSEMBLE_FAILED]
    assert files.missing == 1


def test_ensemble_statistics_match_metrics_nc(ensemble):
    _, files, _, _ = ensemble
    with xr.open_dataset(files.metrics) as m:
        for name in ("radial_displacement_mean", "sensor_displacement_range"):
            mean, se = ensemble_statistics(m[name])
            xr.testing.assert_allclose(mean, m[f"{name}_ensemble_mean"].drop_attrs())
            xr.testing.assert_allclose(se, m[f"{name}_ensemble_stderr"].drop_attrs())
        # the seed adds 1e-7 m to the steady mean: standard error 0.5e-7 m where both finished
        se = ensemble_statistics(m["radial_displacement_mean"])[1].sel(phase=1)
        assert int(se.isnull().sum()) == 1 and np.allclose(se.values[np.isfinite(se.values)], 0.5e-7)


def test_window_edge_section_lists_flagged_ranges(ensemble):
    _, _, md, html = ensemble
    text = section_of(md, "## Ranges cut off by the phase window")
    assert "cut off by the window and is a lower bound" in text
    rows = table_rows(text)
    assert rows[0][:3] == ["phase", "metric", "extreme at the window's edge"]
    flagged = {(r[0], r[1]): r for r in rows[1:]}
    assert set(flagged) == {("start-up", "range of δ_r at the ring centre"),
                            ("steady", "range of sensor `axial_face` at (175.75, 0, 15) mm along (0, 0, 1)")}
    r = flagged[("start-up", "range of δ_r at the ring centre")]
    assert r[2] == "3 of 17 runs (17.6 % of realizations), at 3 of 9 grid points"
    assert r[3] == "660 °/s, 20 kN (1 of 2); 660 °/s, 30 kN (1 of 2); 660 °/s, 40 kN (1 of 2)"
    r = flagged[("steady", "range of sensor `axial_face` at (175.75, 0, 15) mm along (0, 0, 1)")]
    assert r[2] == "17 of 17 runs (100 % of realizations), at 9 of 9 grid points"
    assert "No other range has an extreme at the edge of its window." in text
    # the figure holds one flagged realization: seed 0 at 660 °/s in the panel at 30 kN
    caption = section_of(md, "### start-up radial displacement variation range, at the ring centre")
    assert "Hollow markers (1 realization and the mean it belongs to)" in caption
    assert "No range drawn here has an extreme" in section_of(md, "### start-up sensor reading variation range")
    assert "<h2>Ranges cut off by the phase window</h2>" in html


def test_both_cage_slip_definitions(ensemble):
    _, _, md, _ = ensemble
    text = section_of(md, "## Cage slip")
    assert "`cage_slip` = 1 − ω̄_c/ω_epi" in text and "actual contact angles" in text
    assert re.search(r"`cage_slip_nominal` against the epicyclic speed at the nominal contact angle α = [\d.]+°", text)
    rows = table_rows(text)
    assert rows[0][3:5] == ["`cage_slip` (actual contact angles) [%]",
                            "`cage_slip_nominal` (nominal contact angle) [%]"]
    # 120 °/s, 20 kN, steady: slip 0.005 + 0.001·seed, nominal 0.002 more; mean ± standard error in %
    row = next(r for r in rows if r[:3] == ["120 °/s", "20 kN", "steady"])
    assert row[3:5] == ["0.55 ± 0.05", "0.75 ± 0.05"]
    assert "cage_slip_steady.png" in text
    files = section_of(md, "## Files")
    assert "`cage_slip`" in files and "`cage_slip_nominal`" in files


# --------------------------------------------------------------------------- the stored configuration


@pytest.mark.parametrize("name", ["study.toml", "smoke.toml"])
def test_stored_configuration_round_trips(name):
    sweep = read_sweep_file(REPO / "sweeps" / name)
    conf = stored_configuration(sweep.configuration)
    assert conf.bearing == sweep.bearing and conf.profile == sweep.profile
    assert conf.settings == sweep.settings and conf.sensors == sweep.sensors
    assert conf.name == sweep.name and conf.fixed == sweep.fixed
    assert conf.axes == {a.key: list(a.coords) for a in sweep.axes}
    assert isinstance(conf.bearing.rows[0].outer_arcs[0], type(sweep.bearing.rows[0].outer_arcs[0]))


def test_stored_configuration_round_trips_sensors():
    sweep_file = Path(__file__).parent / "ens.toml"
    try:
        sweep_file.write_text(ENSEMBLE_SWEEP)
        sweep = read_sweep_file(sweep_file)
    finally:
        sweep_file.unlink(missing_ok=True)
    conf = stored_configuration(sweep.configuration)
    assert conf.sensors == sweep.sensors and len(conf.sensors) == 2


@pytest.mark.parametrize("text, key, reason", [
    ("", None, "empty"),
    ("model_version = [", None, "not valid TOML"),
    ('model_version = 1\nname = "x"\n', "model_version", "another model version"),
    (STUDY_CONFIG.replace("ball_diameter = ", "ball_diametre = "), "bearing.rows[0].ball_diametre",
     "unknown field of Row"),
    (STUDY_CONFIG.replace("ball_count = ", "ball_count = 'x' #"), "bearing.rows[0].ball_count", "integer"),
    ("extra_key = 1\n" + STUDY_CONFIG, "extra_key", "unknown key"),
])
def test_stored_configuration_errors_name_key_and_reason(text, key, reason):
    with pytest.raises(ConfigError) as info:
        stored_configuration(text)
    assert info.value.key == key and reason in str(info.value)


# --------------------------------------------------------------------------- a real run


REAL_SWEEP = f"""\
name = "real"
bearing = "{REPO / 'sweeps' / 'bearings' / 'reduced-test.toml'}"
profile = "{REPO / 'sweeps' / 'profiles' / 'short.toml'}"

[axes]
speed = ["120 deg/s", "660 deg/s"]

[fixed]
radial_load = "20 kN"
axial_load = "10 kN"

[solver]
output_rate = "500 Hz"
end_time = "0.1 s"
"""


def test_report_of_a_real_run(tmp_path):
    """The real core on the 12-ball test bearing, 2 cases of a cut-short cycle, reported."""
    path = tmp_path / "real.toml"
    path.write_text(REAL_SWEEP)
    result = run_sweep(path, tmp_path / "out", serial=True, progress=False)
    assert result.ok
    files = build_report(result.out_dir)
    md, html = files.markdown.read_text(), files.html.read_text()
    for heading in (f"# Sweep report: {result.out_dir.name}", "## Appendix: bearing, profile and parameters", "## Cases", "## Time histories",
                    "## Metrics against speed and load", "## Fits beside the study's (Tables 3 and 4)",
                    "## Where our physics agrees with the study and where it does not", "## Files"):
        assert heading in md
    assert "Every case of the grid finished." in md
    assert "Phase windows from the sweep's `phase_start`/`phase_end`: start-up 0.03–0.08 s" in md
    names = {p.name for p in files.figures}
    assert "time_histories.png" in names and "metric_steady_radial_mean.png" in names
    for p in files.figures:
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert f"](figures/{p.name})" in md and f'src="figures/{p.name}"' in html
    table = table_rows(section_of(md, "## Appendix: bearing, profile and parameters"))
    values = {r[0]: r[1:] for r in table[1:]}
    assert values["`rows[0].balls.count`"][0] == "12"
    assert values["`rows[0].balls.diameter`"][0] == "23 mm"
    assert values["`rows[0].radial_clearance`"][2] == "**assumed**"
