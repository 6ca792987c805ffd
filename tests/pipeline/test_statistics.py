"""Tolerance statistics (issue 43): ``[statistics]`` draws, percentiles, Sobol' indices, resuming.

The expectations are computed here: the Ishigami function's and a linear model's Sobol'
indices from their variance decompositions, a normal distribution's percentiles from its
quantile function, the class limits from ISO 492's table.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from scipy.stats import norm

from pipeline.analysis.statistics import percentiles, saltelli, sobol_table, statistics_dataset
from pipeline.errors import ConfigError
from pipeline.io import read_status, status_counts
from pipeline.run import run_sweep
from pipeline.schema import read_sweep_file
from pipeline.schema.statistics import sample_names, unit_design
from rvcore.standards.iso492 import K_EA, K_IA
from tests.pipeline.synthetic import synthetic_result
from tests.pipeline.test_sweep import Counting, case_files
from tests.schema.test_sweepfile import make_sweep

ONE_POINT = """
[axes]
speed = ["120 deg/s"]
radial_load = ["30 kN"]

[fixed]
axial_load = "10 kN"
"imperfections.tolerance_class" = "5"
"""


def statistics_table(**kw) -> str:
    lines = ["", "[statistics]"]
    for k, v in kw.items():
        lines.append(f"{k} = {v!r}".replace("'", '"').replace("True", "true").replace("False", "false"))
    return "\n".join(lines) + "\n"


def as_metrics(outputs: dict, names: tuple) -> xr.Dataset:
    """Outputs ``{sample: (n,) array}`` laid out as ``metrics.nc`` lays out a sweep with a
    Saltelli design: one grid point, a ``phase`` axis, ``draw`` and the ``sample`` category
    coordinate as the combined file writes it (int8 flags, meanings sorted by name)."""
    order = sorted(names)
    n = len(next(iter(outputs.values())))
    y = np.stack([outputs[s] for s in order], axis=-1)                 # (draw, sample)
    y = np.broadcast_to(y[None, None, None], (1, 1, 3, n, len(order))).copy()
    da = xr.DataArray(y, dims=("speed", "radial_load", "phase", "draw", "sample"),
                      attrs={"units": "m", "long_name": "range of delta_r"})
    return xr.Dataset({"radial_displacement_range": da}, coords={
        "speed": ("speed", [120.0], {"units": "degree s-1", "long_name": "speed"}),
        "radial_load": ("radial_load", [30e3], {"units": "N", "long_name": "load"}),
        "phase": ("phase", np.arange(3, dtype=np.int8), {"long_name": "phase", "flag_values": np.arange(3, dtype=np.int8),
                                                         "flag_meanings": "startup steady deceleration"}),
        "draw": ("draw", np.arange(n, dtype=float), {"units": "1", "long_name": "draw"}),
        "sample": ("sample", np.arange(len(order), dtype=np.int8),
                   {"long_name": "sample", "flag_values": np.arange(len(order), dtype=np.int8),
                    "flag_meanings": " ".join(order)})})


# --------------------------------------------------------------------------- Sobol' indices


def ishigami(x, a=7.0, b=0.1):
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def test_ishigami_indices_through_the_sweeps_design_and_index_code():
    """The Ishigami function on the sweep's Saltelli design (unit_design), laid out as
    metrics.nc, through statistics_dataset: the analytic indices lie in the intervals."""
    a, b = 7.0, 0.1
    v1 = 0.5 * (1 + b * math.pi ** 4 / 5) ** 2
    v2 = a ** 2 / 8
    v13 = 8 * b ** 2 * math.pi ** 8 / 225
    v = v1 + v2 + v13                     # = a²/8 + bπ⁴/5 + b²π⁸/18 + 1/2
    assert v == pytest.approx(a ** 2 / 8 + b * math.pi ** 4 / 5 + b ** 2 * math.pi ** 8 / 18 + 0.5)
    first = np.array([v1, v2, 0.0]) / v
    total = np.array([v1 + v13, v2, v13]) / v
    inputs = ("x1", "x2", "x3")
    design = unit_design("sobol", 1024, 7, {k: [i] for i, k in enumerate(inputs)}, sensitivity=True)
    outputs = {s: ishigami(-math.pi + 2 * math.pi * u) for s, u in design.items()}
    ds = statistics_dataset(as_metrics(outputs, tuple(design)))
    got = ds.sel(phase=1).isel(speed=0, radial_load=0)
    order = [str(x) for x in got["tolerance_input"].values]
    idx = [order.index(k) for k in inputs]
    for kind, truth in (("first_order", first), ("total_order", total)):
        name = f"sobol_{kind}_radial_displacement_range"
        est = got[name].values[idx]
        lo, hi = got[f"{name}_ci_low"].values[idx], got[f"{name}_ci_high"].values[idx]
        assert np.all(lo <= truth) and np.all(truth <= hi), (kind, lo, truth, hi)
        assert np.all(hi - lo < 0.25)                         # intervals narrow enough to mean something
        assert np.abs(est - truth).max() < 0.1
    for var in ds.variables.values():           # CF: units and long_name (a flag coordinate: its meanings)
        assert "long_name" in var.attrs and ("units" in var.attrs or "flag_meanings" in var.attrs)


def test_linear_model_indices_and_group_of_columns():
    """y = 3 x1 + Σ x_balls (a group of four columns, one input): S_i = c_i² Var x_i / V."""
    groups = {"one": [0], "balls": [1, 2, 3, 4]}
    design = unit_design("sobol", 512, 3, groups, sensitivity=True)
    assert set(design) == {"A", "B", "AB_one", "AB_balls"}
    np.testing.assert_array_equal(design["AB_balls"][:, 0], design["A"][:, 0])
    np.testing.assert_array_equal(design["AB_balls"][:, 1:], design["B"][:, 1:])
    outputs = {s: 3 * u[:, 0] + u[:, 1:].sum(axis=1) for s, u in design.items()}
    f_a, f_b, f_ab, inputs = saltelli(as_metrics(outputs, tuple(design))["radial_displacement_range"]
                                      .isel(speed=0, radial_load=0, phase=0), ["one", "balls"])
    res = sobol_table(f_a, f_b, f_ab)
    v = (9 + 4) / 12                      # Var U(0, 1) = 1/12
    truth = np.array([9 / 12, 4 / 12]) / v
    for kind in ("first_order", "total_order"):   # additive: first order = total
        assert np.all(res[f"{kind}_low"][0] <= truth) and np.all(truth <= res[f"{kind}_high"][0])


# --------------------------------------------------------------------------- percentiles


@pytest.mark.parametrize("method", ["sobol", "lhs"])
def test_percentiles_of_a_known_distribution_are_recovered(method):
    """Normal(2, 0.5) drawn through the design: the 5th, 50th and 95th percentiles
    (μ + σ Φ⁻¹(q)) within the bootstrap intervals, which are narrow."""
    u = unit_design(method, 1024, 11, {"x": [0]}, sensitivity=False)["A"][:, 0]
    x = 2.0 + 0.5 * norm.ppf(u)
    est, lo, hi = percentiles(x[None, :])
    truth = 2.0 + 0.5 * norm.ppf([0.05, 0.5, 0.95])
    assert np.all(lo[0] <= truth) and np.all(truth <= hi[0]), (lo, truth, hi)
    np.testing.assert_allclose(est[0], truth, atol=0.05)
    assert np.all(hi[0] - lo[0] < 0.2)
    # fewer than MIN_DRAWS finite draws: no percentile
    short = np.full((1, 10), np.nan)
    short[0, :5] = 1.0
    assert np.isnan(percentiles(short)[0]).all()


# --------------------------------------------------------------------------- the sweep file


def test_draws_become_cases_with_explicit_values_within_the_class(tmp_path):
    n = 8
    s = read_sweep_file(make_sweep(tmp_path, ONE_POINT + statistics_table(method="sobol", draws=n, seed=3)))
    assert len(s.cases) == n and s.axes[-1].key == "draw"
    bore, od = s.bearing.bore, s.bearing.outer_diameter
    e_i_max = K_IA["5"][np.searchsorted([10, 18, 30, 50, 80, 120, 180, 250, 315, 400, 500, 630],
                                        bore * 1e3 - 1e-9)] / 2
    e_o_max = K_EA["5"][np.searchsorted([18, 30, 50, 80, 120, 150, 180, 250, 315, 400, 500, 630],
                                        od * 1e3 - 1e-9)] / 2
    imps = [c.bearing.rows[0].imperfections for c in s.cases]
    e_i = np.array([m.inner_eccentricity for m in imps])
    assert np.all((0 <= e_i) & (e_i <= e_i_max)) and np.ptp(e_i) > 0.5 * e_i_max
    assert all(0 <= m.outer_eccentricity <= e_o_max for m in imps)
    assert all(0 <= m.inner_eccentricity_angle < 2 * math.pi for m in imps)
    balls = np.array([m.ball_diameter_deviation for m in imps])
    assert balls.shape == (n, s.bearing.rows[0].ball_count)
    assert np.abs(balls).max() <= 0.5e-6 / 2                  # class 5's G10: V_DwL 0.5 µm
    for c, m in zip(s.cases, imps):                           # the draw is in the hashed configuration
        assert repr(m.inner_eccentricity) in c.configuration
    assert len({c.case_id for c in s.cases}) == n


def test_more_sobol_draws_keep_the_first_ones_and_lhs_redraws(tmp_path):
    # the sequence itself: prefix-stable for a fixed seed, with and without Saltelli's design
    for sens in (False, True):
        small = unit_design("sobol", 8, 5, {"a": [0], "b": [1, 2]}, sens)
        large = unit_design("sobol", 32, 5, {"a": [0], "b": [1, 2]}, sens)
        for k in small:
            np.testing.assert_array_equal(small[k], large[k][:8])
    ids = {}
    for name, method, n in (("s4", "sobol", 4), ("s8", "sobol", 8), ("l4", "lhs", 4), ("l8", "lhs", 8)):
        s = read_sweep_file(make_sweep(tmp_path, ONE_POINT + statistics_table(method=method, draws=n, seed=1,
                                                                              sensitivity=method == "sobol"),
                                       f"{name}.toml"))
        ids[name] = [c.case_id for c in s.cases]
    # class 5 draws 9 inputs here (both eccentricities and their high points, both axial runouts
    # and their high points, the balls): Saltelli's design has N·(9 + 2) cases
    assert set(ids["s4"]) < set(ids["s8"]) and len(ids["s8"]) == 2 * len(ids["s4"]) == 8 * (9 + 2)
    assert not set(ids["l4"]) & set(ids["l8"])                # a Latin hypercube is stratified for its N


def test_a_killed_statistics_sweep_loses_no_draw_and_more_draws_compute_only_new_ones(tmp_path):
    grid = ONE_POINT.replace('speed = ["120 deg/s"]', 'speed = ["120 deg/s", "660 deg/s"]')
    path4 = make_sweep(tmp_path, grid + statistics_table(method="sobol", draws=4, seed=2), "a.toml")
    out = tmp_path / "out"
    first = Counting(interrupt_after=3)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(path4, out, serial=True, case_fn=first, progress=False)
    assert len(case_files(out)) == 3
    assert status_counts(read_status(out)) == {"ok": 3, "failed": 0, "not_run": 5}
    second = Counting()
    assert run_sweep(path4, out, serial=True, case_fn=second, progress=False).ok
    assert len(second.calls) == 5                             # the three finished draws kept
    path8 = make_sweep(tmp_path, grid + statistics_table(method="sobol", draws=8, seed=2), "a.toml")
    third = Counting()
    result = run_sweep(path8, out, serial=True, case_fn=third, progress=False)
    assert result.ok and len(third.calls) == 8 and len(result.reused) == 8
    with xr.open_dataset(out / "sweep.nc") as ds:
        assert ds.sizes["draw"] == 8 and ds["radial_displacement_range"].notnull().all()


def linear_case(bearing, profile, op, settings, sensors=()):
    """Synthetic, with δ_r's start-up range 2 e_i + e_o + 1 µm (a linear model of two inputs)."""
    r = synthetic_result(op.speed, op.radial_load, op.axial_load, n=47)
    imp = bearing.rows[0].imperfections
    r.phase_metrics["radial_displacement_range"] = r.phase_metrics["radial_displacement_range"] * 0 + (
        2 * imp.inner_eccentricity + imp.outer_eccentricity + 1e-6)
    return r


def test_a_sensitivity_sweep_reports_the_linear_models_indices(tmp_path):
    """Through the whole path: sweep file -> Saltelli cases -> sweep.nc -> metrics -> indices."""
    body = ONE_POINT + statistics_table(method="sobol", draws=8, seed=4, sensitivity=True,
                                        inputs=["inner_eccentricity", "outer_eccentricity"])
    s = read_sweep_file(make_sweep(tmp_path, body))
    assert len(s.cases) == 8 * 4
    run_sweep(s, tmp_path / "out", serial=True, case_fn=linear_case, progress=False)
    from pipeline.analysis import open_results, phase_metrics

    ds = statistics_dataset(phase_metrics(open_results(tmp_path / "out")))
    lim_i = max(c.bearing.rows[0].imperfections.inner_eccentricity for c in s.cases)
    lim_o = max(c.bearing.rows[0].imperfections.outer_eccentricity for c in s.cases)
    bore, od = s.bearing.bore, s.bearing.outer_diameter
    from rvcore.standards.iso492 import inner_runout, outer_runout
    E_i, E_o = inner_runout(bore, "5") / 2, outer_runout(od, "5") / 2
    assert lim_i <= E_i and lim_o <= E_o
    truth_first = np.array([4 * E_i ** 2, E_o ** 2]) / (4 * E_i ** 2 + E_o ** 2)
    got = ds.isel(speed=0, radial_load=0).sel(phase=0)
    order = [str(x) for x in got["tolerance_input"].values]
    idx = [order.index("inner_eccentricity"), order.index("outer_eccentricity")]
    name = "sobol_total_order_radial_displacement_range"
    lo, hi = got[f"{name}_ci_low"].values[idx], got[f"{name}_ci_high"].values[idx]
    assert np.all(lo <= truth_first + 1e-12) and np.all(truth_first <= hi + 1e-12), (lo, truth_first, hi)
    assert got["radial_displacement_range_percentile"].notnull().all()


def test_the_report_writes_statistics_nc_and_its_section(tmp_path):
    """rvsweep report on a sensitivity sweep: statistics.nc (CF: units and long_name on every
    variable) and the report's section with the Sobol' table and the box plots."""
    grid = ONE_POINT.replace('speed = ["120 deg/s"]', 'speed = ["120 deg/s", "660 deg/s"]')
    body = grid + statistics_table(method="sobol", draws=8, seed=4, sensitivity=True,
                                   inputs=["inner_eccentricity", "outer_eccentricity"])
    out = tmp_path / "out"
    run_sweep(make_sweep(tmp_path, body), out, serial=True, case_fn=linear_case, progress=False)
    from pipeline.report import build_report

    files = build_report(out)
    with xr.open_dataset(out / "statistics.nc") as ds:
        for var in ds.variables.values():
            assert "long_name" in var.attrs and ("units" in var.attrs or "flag_meanings" in var.attrs), var.name
        assert ds["radial_displacement_range_percentile"].sizes["percentile"] == 3
        assert "sobol_total_order_radial_displacement_range_ci_high" in ds
    text = files.markdown.read_text()
    section = text.split("## Tolerance statistics")[1].split("\n## ")[0]
    assert "| output | inner_eccentricity | outer_eccentricity |" in section
    assert "radial displacement range, start-up" in section
    assert (out / "report" / "figures" / "statistics_speed.png").is_file()


# --------------------------------------------------------------------------- bad tables

BAD = [
    ("method = \"mc\"\ndraws = 4\nseed = 1", "statistics.method", "must be one of sobol, lhs"),
    ("draws = 4\nseed = 1\ncolour = 1", "statistics.colour", "unknown key"),
    ("seed = 1", "statistics.draws", "missing"),
    ("draws = 6\nseed = 1", "statistics.draws", "powers of 2: give 4 or 8"),
    ("draws = 1\nseed = 1", "statistics.draws", "from 2 to"),
    ("draws = \"64\"\nseed = 1", "statistics.draws", "whole number"),
    ("draws = 4", "statistics.seed", "missing"),
    ("draws = 4\nseed = -1", "statistics.seed", "at least 0"),
    ("method = \"lhs\"\ndraws = 5\nseed = 1\nsensitivity = true", "statistics.sensitivity", "method = \"sobol\""),
    ("draws = 4\nseed = 1\nsensitivity = \"yes\"", "statistics.sensitivity", "true or false"),
    ("draws = 4\nseed = 1\ninputs = [\"roundness\"]", "statistics.inputs[0]", "unknown input"),
    ("draws = 4\nseed = 1\ninputs = [\"inner_eccentricity\", \"inner_eccentricity\"]", "statistics.inputs[1]",
     "listed twice"),
    ("draws = 4\nseed = 1\ninputs = [\"outer_waviness\"]", "statistics.inputs[0]", "no outer waviness"),
    ("draws = 4\nseed = 1\ninputs = []", "statistics.inputs", "list of input names"),
    ("draws = 4\nseed = 1\nsensitivity = true\ninputs = [\"inner_eccentricity\"]", "statistics.sensitivity",
     "at least two inputs"),
]


@pytest.mark.parametrize("table,key,why", BAD, ids=[b[1] + ":" + b[2][:12] for b in BAD])
def test_bad_statistics_tables_give_one_line(tmp_path, table, key, why):
    with pytest.raises(ConfigError) as err:
        read_sweep_file(make_sweep(tmp_path, ONE_POINT + "\n[statistics]\n" + table + "\n"))
    line = str(err.value)
    assert "\n" not in line and key in line and why in line, line


def test_listed_cases_take_draws_and_a_perfect_bearing_has_none(tmp_path):
    cases = ("[[cases]]\nspeed = \"120 deg/s\"\nradial_load = \"30 kN\"\naxial_load = \"10 kN\"\n"
             "\"imperfections.tolerance_class\" = \"normal\"\n")
    s = read_sweep_file(make_sweep(tmp_path, cases + statistics_table(draws=4, seed=1), "c.toml"))
    assert len(s.cases) == 4 and s.axes[-1].key == "draw"
    perfect = ONE_POINT.replace('"imperfections.tolerance_class" = "5"\n', "")
    with pytest.raises(ConfigError, match="no tolerance to draw"):
        read_sweep_file(make_sweep(tmp_path, perfect + statistics_table(draws=4, seed=1), "p.toml"))
    with pytest.raises(ConfigError, match="no inner eccentricity to draw within"):
        read_sweep_file(make_sweep(tmp_path, perfect + statistics_table(draws=4, seed=1,
                                                                         inputs=["inner_eccentricity"]), "q.toml"))


def test_a_new_tolerance_input_is_one_entry(tmp_path, monkeypatch):
    """An input added to INPUTS (as an axial runout will be) is drawn, named in the Saltelli
    design and bounded, with no other change."""
    from pipeline.schema import statistics as st

    limit = 2e-6
    monkeypatch.setitem(st.INPUTS, "toy_runout", st.ToleranceInput(
        "toy_runout", "a made-up input", lambda row: 1, lambda row, bearing, u: {"inner_eccentricity": u[0] * limit}))
    s = read_sweep_file(make_sweep(tmp_path, ONE_POINT + statistics_table(
        draws=4, seed=1, sensitivity=True, inputs=["toy_runout", "outer_eccentricity"])))
    names = ("A", "B", "AB_toy_runout", "AB_outer_eccentricity")
    assert [a.coords for a in s.axes if a.key == "sample"] == [names] and sample_names(s.statistics) == names
    e = [c.bearing.rows[0].imperfections.inner_eccentricity for c in s.cases]
    assert len(set(e)) == 8 and all(0 <= x <= limit for x in e)      # A's and B's four draws each


def test_check_says_what_changing_the_number_of_draws_does(tmp_path, capsys):
    from pipeline.cli import main

    for method, n, says in (("sobol", 4, "more draws keep these and add new cases"),
                            ("lhs", 5, "changing draws redraws every draw (all cases new)")):
        path = make_sweep(tmp_path, ONE_POINT + statistics_table(method=method, draws=n, seed=1), f"{method}.toml")
        assert main(["check", str(path)]) == 0
        out = capsys.readouterr().out
        assert f"statistics: {n} {method} draws a grid point (seed 1)" in out and says in out


def test_the_shipped_study_statistics_sweep_is_both_classes_on_the_studys_two_lines():
    from tests.schema.test_sweepfile import SWEEPS

    s = read_sweep_file(SWEEPS / "study-statistics.toml")
    n = s.statistics.draws
    assert s.statistics.method == "sobol" and n >= 64
    points = {(round(math.degrees(c.point["speed"])), c.point["radial_load"],
               c.point["imperfections.tolerance_class"]) for c in s.cases}
    speed_line = {(w, 30e3) for w in range(120, 661, 60)}          # Table 3: speed at 30 kN
    load_line = {(120, f * 1e3) for f in (20, 25, 30, 35, 40)}     # Table 4: load at 120 deg/s
    assert points == {(w, f, cls) for w, f in speed_line | load_line for cls in ("5", "normal")}
    assert len(s.cases) == len(points) * n
    assert all(c.operating_point.axial_load == 10e3 for c in s.cases)


def test_a_listed_case_sweep_reports_no_missing_case_for_the_points_it_did_not_ask_for(tmp_path):
    """[[cases]] at (120 °/s, 20 kN) and (660 °/s, 30 kN) combine onto a 2 × 2 grid: the two
    other points were asked for by nobody, so the report neither counts nor lists them as
    missing; a listed case that fails still is."""
    from pipeline.report import build_report
    from tests.pipeline.test_sweep import synthetic_case

    body = """
[fixed]
axial_load = "10 kN"

[[cases]]
speed = "120 deg/s"
radial_load = "20 kN"

[[cases]]
speed = "660 deg/s"
radial_load = "30 kN"
"""
    out = tmp_path / "out"
    run_sweep(read_sweep_file(make_sweep(tmp_path, body)), out, serial=True, case_fn=synthetic_case, progress=False)
    files = build_report(out)
    cases = files.markdown.read_text().split("## Cases")[1].split("\n## ")[0]
    assert files.missing == 0
    assert "2 of the grid's 4 speed and load points are not among them" in cases
    assert "2 cases, 2 finished ok, 0 failed or missing" in cases and "Missing or failed" not in cases

    def fails_at_660(bearing, profile, op, settings, sensors=()):
        if op.speed > 10:
            raise RuntimeError("made to fail (test)")
        return synthetic_case(bearing, profile, op, settings, sensors)

    out2 = tmp_path / "out2"
    run_sweep(read_sweep_file(make_sweep(tmp_path, body)), out2, serial=True, case_fn=fails_at_660,
              progress=False)
    files = build_report(out2)
    cases = files.markdown.read_text().split("## Cases")[1].split("\n## ")[0]
    assert files.missing == 1 and "2 cases, 1 finished ok, 1 failed or missing" in cases
    assert "made to fail (test)" in cases
