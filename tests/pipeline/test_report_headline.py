"""The report's first screen and its figures (issue 39, items 17-18): the headline states the
worst design numbers with where they occur and their verdict against the user's targets; a
bad target is one line before any work; range bands are never negative; the time histories'
y-limits leave out the settling from t = 0; lines identical at every speed are drawn as one;
a run on another bearing or cycle than the study's says so.

The synthetic sweep's designer outputs are made up (``tests/pipeline/test_report_designer.py``:
a known function of the grid point); every expected worst value, location and verdict is
computed here from those functions, not read from the report's code.
"""
from __future__ import annotations

import math
import subprocess
import sys
import tomllib
from pathlib import Path
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest
import xarray as xr

from pipeline.analysis import linear_fit, line_band
from pipeline.report import build_report
from pipeline.report.build import load_context
from rvcore.profile import PHASES
from tests.pipeline.test_report import section_of, synthetic_sweep, table_rows
from tests.pipeline.test_report_designer import fmt_g3, add_designer_outputs, made_up
from tests.pipeline.test_report_stiffness import made_up_stiffness, add_stiffness

REPO = Path(__file__).resolve().parents[2]

#: The synthetic grid (tests/pipeline/test_metrics.py): 3 x 3, 390 °/s at 20 kN failed.
SPEEDS = (120.0, 390.0, 660.0)
LOADS = (20e3, 30e3, 40e3)
FAILED = {(390.0, 20e3)}


def _points():
    return [(s, f) for s in SPEEDS for f in LOADS if (s, f) not in FAILED]


def _worst(value, how):
    """``(worst value, [(speed, load), ...] where it is)`` of ``value(speed, load)`` over the
    finished points, ties within 1e-9 relative."""
    vals = {p: value(*p) for p in _points()}
    w = (min if how == "min" else max)(vals.values())
    return w, [p for p, v in vals.items() if math.isclose(v, w, rel_tol=1e-9)]


def _s0(s, f):        # the smallest over the phases of the made-up safety factor
    return float(np.min(made_up("static_safety_factor_min", s, f)))


def _s0_phase(s, f):  # the phase it falls in
    return PHASES[int(np.argmin(made_up("static_safety_factor_min", s, f)))]


def _life(s, f):      # L10r of the duty cycle [Mrev]
    return float(made_up("rating_life_L10r", s, f)) / 1e6


def _torque(s, f):    # peak start-up drive torque [N m]
    return float(made_up("inner_ring_drive_torque_peak", s, f)[PHASES.index("startup")])


def _k_r(s, f):       # radial stiffness [N/µm]
    return made_up_stiffness(s, f)[0] / 1e6


@pytest.fixture(scope="module")
def headline(tmp_path_factory):
    d = synthetic_sweep(tmp_path_factory.mktemp("headline"))
    add_stiffness(d)
    add_designer_outputs(d)
    s0, _ = _worst(_s0, "min")
    life, _ = _worst(_life, "min")
    torque, _ = _worst(_torque, "max")
    k_r, _ = _worst(_k_r, "min")
    # s0 misses its target by 10 %; life, torque and k_r meet theirs by 10 %
    targets = {"safety": 1.1 * s0, "life_mrev": 0.9 * life, "startup_torque": 1.1 * torque,
               "radial_stiffness": 0.9 * k_r}
    files = build_report(d, targets=targets)
    md = files.markdown.read_text()
    return d, targets, md, files.html.read_text()


def _row(md: str, quantity: str) -> list:
    rows = table_rows(section_of(md, "## Headline"))
    return next(r for r in rows if r[0].startswith(quantity))


def test_the_report_opens_on_the_headline(headline):
    _, _, md, html = headline
    sections = [ln for ln in md.splitlines() if ln.startswith("## ")]
    assert sections[:2] == ["## Headline", "## Summary per operating point"]
    # the definitions follow the numbers: the summary's definitions paragraph comes after its table
    summary = section_of(md, "## Summary per operating point")
    assert summary.index("| speed [°/s]") < summary.index("**What the columns are.**")
    assert html.index("<h2>Headline</h2>") < html.index("<h2>What the designer's numbers are</h2>")


def test_headline_states_each_worst_value_where_and_its_verdict(headline):
    _, targets, md, html = headline
    s0, at = _worst(_s0, "min")
    row = _row(md, "smallest static safety factor")
    assert row[1] == fmt_g3(s0)
    (s, f), = at
    assert row[2] == f"{s:g} °/s, {f / 1e3:g} kN"
    assert row[3].startswith({"startup": "start-up"}.get(_s0_phase(s, f), _s0_phase(s, f)))
    assert row[4] == f"≥ {targets['safety']:.4g}"
    assert row[5] == "✗ FAIL"                               # 10 % short of its target

    life, at = _worst(_life, "min")
    row = _row(md, "shortest rating life L10r")
    (s, f), = at
    assert row[1] == f"{fmt_g3(life)} Mrev" and row[2] == f"{s:g} °/s, {f / 1e3:g} kN"
    assert row[5] == "✓ pass"

    torque, at = _worst(_torque, "max")
    row = _row(md, "largest start-up drive torque")
    (s, f), = at
    assert row[1] == f"{fmt_g3(torque)} N m" and row[2] == f"{s:g} °/s, {f / 1e3:g} kN"
    assert row[3] == "start-up phase" and row[4] == f"≤ {targets['startup_torque']:.4g} N m"
    assert row[5] == "✓ pass"

    # the stiffness is the same at every speed: the smallest is at the lightest load, at every
    # speed that finished there (390 °/s failed at 20 kN)
    k_r, at = _worst(_k_r, "min")
    row = _row(md, "smallest radial stiffness")
    assert {f for _, f in at} == {LOADS[0]} and len(at) == 2
    assert row[1] == f"{fmt_g3(k_r)} N/µm" and row[2] == f"every speed with a result, {LOADS[0] / 1e3:g} kN"
    assert row[5] == "✓ pass"

    # no target: said so, no mark; L_nm of the cycle, its worst point as L10r's
    assert _row(md, "smallest axial stiffness")[5] == "no target set"
    l_nm, at = _worst(lambda s, f: float(made_up("rating_life_L_nm", s, f)) / 1e6, "min")
    row = _row(md, "shortest modified rating life L_nm")
    (s, f), = at
    assert row[1] == f"{fmt_g3(l_nm)} Mrev" and row[2] == f"{s:g} °/s, {f / 1e3:g} kN"
    assert row[5] == "no target set"
    assert "**3 of 4 targets met**: missed: smallest static safety factor s₀." in md
    assert '<td class="fail">✗ FAIL</td>' in html and '<td class="pass">✓ pass</td>' in html


def test_without_targets_no_verdict_is_invented(tmp_path):
    d = synthetic_sweep(tmp_path / "plain")
    add_designer_outputs(d)
    md = build_report(d).markdown.read_text()
    rows = table_rows(section_of(md, "## Headline"))[1:]
    assert rows and all(r[5] in ("no target set", "—") for r in rows)
    assert "No target set" in section_of(md, "## Headline")


@pytest.mark.parametrize("flag, value, reason", [
    ("--target-s0", "abc", "not a number"),
    ("--target-s0", "-2", "positive"),
    ("--target-life", "nan", "positive finite"),
    ("--target-torque", "20 kg", "N*m"),
    ("--target-radial-stiffness", "500 N", "N/m"),
])
def test_a_bad_target_is_one_line_before_any_work(tmp_path, capsys, flag, value, reason):
    """Through the command line's own entry point (in-process: a subprocess per case costs
    an interpreter start); the one-line, exit-code and traceback checks of a real process are
    the last case, run once as a subprocess."""
    from pipeline.cli import main

    d = tmp_path / "nosweep"      # no sweep at all: the target is checked first
    d.mkdir()
    assert main(["report", str(d), flag, value]) != 0
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert flag in lines[0] and repr(value) in lines[0] and reason in lines[0]
    assert not (d / "report").exists() and not (d / "metrics.nc").exists()


def test_a_bad_target_in_a_real_process_is_one_line_and_no_traceback(tmp_path):
    d = tmp_path / "nosweep"
    d.mkdir()
    r = subprocess.run([sys.executable, "-m", "pipeline.cli", "report", str(d), "--target-s0", "0"],
                       capture_output=True, text=True, cwd=REPO, timeout=120)
    assert r.returncode != 0
    assert r.stderr.strip().splitlines() == [
        f"rvsweep report: error: command line: --target-s0 = '0': a target must be a positive finite number"]
    assert "Traceback" not in r.stderr and not (d / "report").exists()


# --------------------------------------------------------------------------- figures


def test_range_bands_are_never_negative():
    """A range fit whose 95 % band crosses zero: the band drawn is cut at zero, the axis starts
    at zero; the same fit of a mean (which may be negative) is drawn uncut."""
    from matplotlib.figure import Figure

    import pipeline.report.figures as figures

    x = np.array([120.0, 390.0, 660.0])
    y = np.array([0.2e-6, 3.0e-6, 0.4e-6])          # scattered: a wide band
    fit = linear_fit(x, y)
    _, raw_lo, _ = line_band(fit, np.linspace(120, 660, 50))
    assert raw_lo.min() < 0                          # the statistics alone would go below zero
    ctx = SimpleNamespace(metrics=xr.Dataset(coords={"speed": x}))
    for name, cut in (("radial_displacement_range", True), ("radial_displacement_mean", False)):
        ax = Figure().subplots()
        ax.plot(x, y * 1e6, "o")
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(figures, "fit_at", lambda *a, **k: fit)
            figures._fit_line(ax, ctx, name, "speed", "radial_load", 30e3, "startup")
        band = [c for c in ax.collections if isinstance(c, matplotlib.collections.PolyCollection)][0]
        ys = np.concatenate([p.vertices[:, 1] for p in band.get_paths()])
        if cut:
            assert ys.min() >= 0.0 and ax.get_ylim()[0] >= 0.0
            assert all(ln.get_ydata().min() >= 0.0 for ln in ax.get_lines())
        else:
            assert ys.min() < 0.0


@pytest.fixture
def report_context():
    """``load_context`` whose sweep file and figures are closed after the test: a netCDF file
    left to the garbage collector is closed inside a collection, where HDF5 can crash."""
    import matplotlib.pyplot as plt

    opened = []

    def load(directory):
        opened.append(load_context(directory))
        return opened[-1]

    yield load
    for ctx in opened:
        ctx.sweep.close()
    plt.close("all")


def test_time_history_ylimits_leave_out_the_settling(tmp_path, monkeypatch, report_context):
    """A 1 mm spike at t = 0 (the ring settling onto its balls) no longer sets the y-axis: the
    limits hold every sample inside the phase windows and end well short of the spike."""
    import pipeline.report.figures as figures

    d = synthetic_sweep(tmp_path / "th")
    ctx = report_context(d)
    t = ctx.sweep["elapsed_time"].values
    first = min(a for a, _ in ctx.windows.values())
    v = ctx.sweep["radial_displacement"].values.copy()
    v[..., t < 0.5 * first] = -1e-3                  # -1000 µm before the first window
    ctx.sweep["radial_displacement"] = (ctx.sweep["radial_displacement"].dims, v)
    captured = {}
    monkeypatch.setattr(figures, "save_figure", lambda fig, path: captured.setdefault("fig", fig))
    cases = [(120.0, 20e3), (660.0, 40e3)]
    notes = figures.figure_time_histories(ctx, ctx.windows, tmp_path / "th.png", cases)
    ax = captured["fig"].axes[0]
    lo, hi = ax.get_ylim()
    inside = np.zeros(t.shape, bool)
    for a, b in ctx.windows.values():
        inside |= (t >= a) & (t <= b)
    traces = [ctx.sweep["radial_displacement"].sel(speed=s, radial_load=f).values[inside] * 1e6 for s, f in cases]
    assert lo <= min(tr.min() for tr in traces) and hi >= max(tr.max() for tr in traces)
    span = max(tr.max() for tr in traces) - min(tr.min() for tr in traces)
    assert lo > -1000.0 and lo > min(tr.min() for tr in traces) - 0.2 * span - 1.0
    assert any("-1e+03" in n or "-1000" in n for n in notes), notes


def test_lines_identical_at_every_speed_are_drawn_as_one(tmp_path, monkeypatch, report_context):
    """The stiffness does not depend on the speed: against the load, one line per speed would lie
    on top of each other; it is one line, labelled as every speed's."""
    import pipeline.report.stiffness as stiffness

    d = synthetic_sweep(tmp_path / "st")
    add_stiffness(d)
    ctx = report_context(d)
    captured = {}
    monkeypatch.setattr(stiffness, "save_figure", lambda fig, path: captured.setdefault("fig", fig))
    notes = stiffness.figure_stiffness(ctx, ["speed", "radial_load"], tmp_path / "k.png")
    fig = captured["fig"]
    against_load = fig.axes[1]                       # first row (k_r), second column (against load)
    solid = [ln for ln in against_load.get_lines() if ln.get_linestyle() == "-"]
    assert len(solid) == 1
    assert "all 3" in solid[0].get_label() and "identical" in solid[0].get_label()
    assert "one line for all 3" in notes[1]
    # its suptitle fits: two lines, each shorter than the figure's width at 10 pt
    title = fig._suptitle.get_text()
    assert "\n" in title and max(len(x) for x in title.splitlines()) * 10 * 0.6 / 72 < fig.get_figwidth()


# --------------------------------------------------------------------------- a run that is not the study's


def _toml(path: Path) -> dict:
    return tomllib.loads(path.read_text())


def test_the_smoke_report_names_the_reduced_bearing_and_the_short_cycle(smoke_run):
    """Computed here from the shipped files: the smoke sweep's bearing and profile against the
    study sweep's."""
    smoke, study = _toml(REPO / "sweeps" / "smoke.toml"), _toml(REPO / "sweeps" / "study.toml")
    bearing = _toml(REPO / "sweeps" / smoke["bearing"])
    study_bearing = _toml(REPO / "sweeps" / study["bearing"])
    balls = sum(r["balls"]["count"] for r in bearing["rows"])
    study_balls = sum(r["balls"]["count"] for r in study_bearing["rows"])
    duration = float(_toml(REPO / "sweeps" / smoke["profile"])["duration"].split()[0])
    study_duration = float(_toml(REPO / "sweeps" / study["profile"])["duration"].split()[0])
    assert (balls, study_balls) == (12, 51) and study_duration / duration == pytest.approx(10.0)
    md = (smoke_run.out / "report" / "report.md").read_text()
    head = section_of(md, "## Headline")
    assert "Not the study's run" in head
    assert f"`{bearing['name']}`, {balls} balls" in head and f"`{study_bearing['name']}`: {study_balls} balls" in head
    assert f"{study_duration / duration:g} times shorter" in head
    assert f"{duration:g} s" in head and f"{study_duration:g} s" in head


def test_the_study_run_is_not_flagged(headline):
    """The synthetic sweep stores the study's own configuration: no such note."""
    _, _, md, _ = headline
    assert "Not the study's run" not in md
