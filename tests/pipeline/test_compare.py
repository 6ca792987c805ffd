"""``rvsweep compare``: measured traces the test makes from a simulated case, read back.

The simulated case is synthetic (tests/pipeline/synthetic.py: δ_r and δ_a follow the study
profile's loads and speed; no dynamics). Each expectation is computed here from the
series the test wrote (numpy ranges, means and standard deviations, the noise's bound, the
Sprague–Geers definitions), not taken from the code's output.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pipeline.analysis.compare import compare, phase_metrics_of, sprague_geers
from pipeline.cli import main
from pipeline.io.case import case_dataset, write_case
from pipeline.schema.tracefile import load_trace
from rvcore.profile import study_profile
from tests.pipeline.synthetic import synthetic_result

NAMES = ("radial_displacement", "axial_displacement")
PHASE_WINDOWS = np.array([(s, e) for _, s, e in study_profile().phases])
REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    """A synthetic 660 °/s, 30 kN case written as a case file, with its phase windows."""
    r = synthetic_result(math.radians(660), 30e3)
    ds = case_dataset(r, speed=math.radians(660), radial_load=30e3, axial_load=10e3)
    ds["phase_start"] = ("phase", PHASE_WINDOWS[:, 0], {"units": "s", "long_name": "start of the phase window"})
    ds["phase_end"] = ("phase", PHASE_WINDOWS[:, 1], {"units": "s", "long_name": "end of the phase window"})
    path = tmp_path_factory.mktemp("case") / "case.nc"
    write_case(ds, path)
    return path, r.time, {n: r.series[n] for n in NAMES}


def _write_mat73(path, columns):
    """A MAT 7.3 file: HDF5 behind MATLAB's 512-byte header (what MATLAB's -v7.3 writes)."""
    import h5py

    with h5py.File(path, "w", userblock_size=512) as f:
        for k, v in columns.items():
            f[k] = v.reshape(1, -1)
    head = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created by: test_compare HDF5 schema 1.00 ."
    with open(path, "r+b") as fh:
        fh.write(head.ljust(116) + b"\0" * 8 + b"\x00\x02" + b"IM")


def write_trace(folder, fmt, t, series, *, unit="um", scale=1e6, extra="", time_unit="s", with_time=True,
                more=None, tail=""):
    """Write ``series`` [m] (over ``t`` [s]) in ``fmt`` and a trace TOML describing it;
    ``more``: further columns as written, ``tail``: TOML appended."""
    cols = {"dr": series["radial_displacement"] * scale, "da": -series["axial_displacement"] * scale,
            **(more or {})}
    if with_time:
        cols = {"time": np.asarray(t) * (1e3 if time_unit == "ms" else 1.0), **cols}
    ext = {"csv": "csv", "tdms": "tdms", "hdf5": "h5", "mat": "mat", "mat73": "mat"}[fmt]
    data = folder / f"trace-{fmt}.{ext}"
    if fmt == "csv":
        with data.open("w") as fh:
            fh.write(",".join(cols) + "\n")
            for row in zip(*cols.values()):
                fh.write(",".join(repr(float(v)) for v in row) + "\n")
    elif fmt == "tdms":
        from nptdms import ChannelObject, TdmsWriter

        with TdmsWriter(data) as w:
            w.write_segment([ChannelObject("rig", k, v) for k, v in cols.items()])
    elif fmt == "hdf5":
        import h5py

        with h5py.File(data, "w") as f:
            for k, v in cols.items():
                f[f"lasers/{k}"] = v
        cols = {f"lasers/{k}": v for k, v in cols.items()}
    elif fmt == "mat":
        import scipy.io

        scipy.io.savemat(data, cols)
    else:
        _write_mat73(data, cols)
    pre = "lasers/" if fmt == "hdf5" else ""
    time = f'{{ channel = "{pre}time", unit = "{time_unit}" }}' if with_time else '{ rate = "100 Hz" }'
    toml = folder / f"trace-{fmt}.toml"
    toml.write_text(f"""[trace]
name = "test-{fmt}"
file = "{data.name}"
format = "{'mat' if fmt == 'mat73' else fmt}"
time = {time}
{extra}
[[trace.channel]]
name = "{pre}dr"
unit = "{unit}"
measures = "radial_displacement"
position = "outer ring, on the load line"

[[trace.channel]]
name = "{pre}da"
unit = "{unit}"
measures = "axial_displacement"
position = "ring face"
sign = -1
""" + tail)
    return toml


def numpy_metrics(t, x, windows):
    """Range, mean and population std per window, by numpy."""
    out = {"range": [], "mean": [], "std": []}
    for a, b in windows:
        w = (t >= a) & (t < b)
        out["range"].append(np.ptp(x[w]))
        out["mean"].append(x[w].mean())
        out["std"].append(x[w].std())
    return {k: np.array(v) for k, v in out.items()}


# --------------------------------------------------------------------------- Sprague–Geers

def test_sprague_geers_of_a_scaled_and_of_a_quarter_period_shifted_signal():
    t = np.linspace(0.0, 1.0, 1000, endpoint=False)
    x = np.sin(2 * np.pi * 5 * t)
    for a in (0.8, 1.0, 1.25):
        m, p, c = sprague_geers(a * x, x)
        assert m == pytest.approx(a - 1.0, abs=1e-12)     # sqrt(a²Σx²/Σx²) − 1
        assert p == pytest.approx(0.0, abs=1e-6)
        assert c == pytest.approx(abs(a - 1.0), abs=1e-6)
    # sin and cos over whole periods are orthogonal: arccos(0)/π = 1/2; equal energy: M = 0
    m, p, _ = sprague_geers(np.cos(2 * np.pi * 5 * t), x)
    assert m == pytest.approx(0.0, abs=1e-12)
    assert p == pytest.approx(0.5, abs=1e-12)
    assert sprague_geers(-x, x)[1] == pytest.approx(1.0)


# ------------------------------------------------------------------------ metrics, same code

def test_phase_metrics_of_a_series_are_numpys_range_mean_and_std(case):
    _, t, series = case
    got = phase_metrics_of(t, series, PHASE_WINDOWS)
    for n in NAMES:
        want = numpy_metrics(t, series[n], PHASE_WINDOWS)
        for k in ("range", "mean", "std"):
            np.testing.assert_allclose(got[f"{n}_{k}"], want[k], rtol=1e-9, atol=1e-15)


# --------------------------------------------------------------------------- every format

@pytest.mark.parametrize("fmt", ["csv", "tdms", "hdf5", "mat", "mat73"])
def test_each_format_reads_back_the_simulated_case(case, tmp_path, fmt):
    path, t, series = case
    import xarray as xr

    trace = load_trace(write_trace(tmp_path, fmt, t, series))
    with xr.open_dataset(path) as ds:
        result = compare(trace, ds.load())
    dt = t[1] - t[0]
    assert abs(result["lag"]) < dt
    for n in NAMES:
        np.testing.assert_allclose(result["measured"][n], series[n][:result["measured"][n].size], rtol=1e-9, atol=1e-15)
        sg = result["sprague_geers"][n]
        assert np.all(np.abs(sg) < 1e-6), (n, sg)
        want = numpy_metrics(t, series[n], PHASE_WINDOWS)
        np.testing.assert_allclose(result["measured_metrics"][f"{n}_range"], want["range"], rtol=1e-6, atol=1e-13)


def test_a_resampled_shifted_noisy_trace_with_a_gain_error(case, tmp_path):
    """Rig at 333 Hz (the case samples at 100 Hz), starting 0.237 s before the cycle,
    uniform noise of ±20 nm and a gain of 1.1: the lag within one sample, each phase
    metric within what the noise and the resampling can move it."""
    import xarray as xr

    path, t, series = case
    dt = t[1] - t[0]
    lag, gain, eps = 0.237, 1.1, 20e-9
    rng = np.random.default_rng(7)
    tm = np.arange(0.0, t[-1] + 0.6, 1 / 333.0)
    meas = {n: gain * np.interp(tm - lag, t, series[n]) + rng.uniform(-eps, eps, tm.size) for n in NAMES}
    trace = load_trace(write_trace(tmp_path, "tdms", tm, meas))
    with xr.open_dataset(path) as ds:
        result = compare(trace, ds.load())
    assert abs(result["lag"] - lag) <= dt
    for n in NAMES:
        x = series[n]
        slope = np.max(np.abs(np.diff(x))) / dt
        # linear interpolation of a piecewise-linear series misses a knot by at most its
        # slope change over one interval; the lag's error moves every sample by slope·δ
        interp = np.max(np.abs(np.diff(x, 2)))
        shift = slope * abs(result["lag"] - lag)
        tol = gain * (interp + shift) + eps
        want = numpy_metrics(t, x, PHASE_WINDOWS)
        got = result["measured_metrics"]
        np.testing.assert_array_less(np.abs(got[f"{n}_range"] - gain * want["range"]), 2 * tol + 1e-15)
        np.testing.assert_array_less(np.abs(got[f"{n}_mean"] - gain * want["mean"]), tol + 1e-15)
        np.testing.assert_array_less(np.abs(got[f"{n}_std"] - gain * want["std"]), tol + 1e-15)


def test_the_sprague_geers_magnitude_error_of_a_gain_error(case, tmp_path):
    """Measured = a·simulated: the simulation's magnitude error is 1/a − 1 (SG's M with
    c the simulation and m the measurement), its phase error 0."""
    import xarray as xr

    path, t, series = case
    a = 1.1
    trace = load_trace(write_trace(tmp_path, "hdf5", t, {n: a * series[n] for n in NAMES}))
    with xr.open_dataset(path) as ds:
        result = compare(trace, ds.load())
    for n in NAMES:
        sg = result["sprague_geers"][n]
        np.testing.assert_allclose(sg[:, 0], 1 / a - 1, atol=1e-9)
        np.testing.assert_allclose(sg[:, 1], 0.0, atol=1e-6)
        d = result["simulated_metrics"][f"{n}_range"] - result["measured_metrics"][f"{n}_range"]
        np.testing.assert_allclose(d, (1 - a) * numpy_metrics(t, series[n], PHASE_WINDOWS)["range"], atol=1e-13)


# ------------------------------------------------------------------------------ the command

def test_the_command_writes_netcdf_and_json_with_units(case, tmp_path, capsys):
    import json

    import xarray as xr

    path, t, series = case
    toml = write_trace(tmp_path, "csv", t, series)
    out = tmp_path / "out"
    assert main(["compare", str(toml), "--case", str(path), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "lag" in printed and "radial_displacement" in printed
    with xr.open_dataset(out / "comparison.nc") as ds:
        for name, v in ds.data_vars.items():
            assert v.attrs.get("units") is not None and v.attrs.get("long_name"), name
        assert "radial_displacement_sprague_geers_combined" in ds
        assert "axial_displacement_range_difference" in ds
    summary = json.loads((out / "comparison.json").read_text())
    assert abs(summary["lag_s"]) < t[1] - t[0]
    from compliance_checker.runner import CheckSuite

    from tests.pipeline.test_cf import cf_problems

    suite = CheckSuite()
    suite.load_all_available_checkers()
    assert cf_problems(suite, out / "comparison.nc") == []


# ------------------------------------------------------------------------------- bad input

def _one_line_error(capsys, argv):
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2
    assert "Traceback" not in err
    assert len(err.strip().splitlines()) == 1, err
    return err


@pytest.mark.parametrize("edit, expect, duty", [
    (lambda s: s.replace('unit = "um"', 'unit = "N"', 1), "not a length", False),
    (lambda s: s.replace('format = "csv"', 'format = "xlsx"'), "unknown format", False),
    (lambda s: s.replace('file = "trace-csv.csv"', 'file = "nowhere.csv"'), "no such data file", False),
    (lambda s: s.replace('name = "dr"', 'name = "laser_9"'), "no such channel", False),
    (lambda s: s.replace('unit = "s" }', 'unit = "mm" }'), "not a time", False),
    (lambda s: s.replace('sign = -1', 'sign = 2'), "must be 1 or -1", False),
    (lambda s: s.replace('measures = "radial_displacement"', 'measures = "force"'), "unknown", False),
    # the duty cycle from channels ([trace.duty])
    (lambda s: s.replace('unit = "rpm"', 'unit = "N"'), "trace.duty.speed.unit = 'N': not a speed", True),
    (lambda s: s.replace('unit = "rpm"', 'unit = "Hz"'), "a frequency without an angle", True),
    (lambda s: s.replace('channel = "Fr", unit = "kN"', 'channel = "Fr", unit = "um"'),
     "trace.duty.radial_load.unit = 'um': not a force", True),
    (lambda s: s.replace('channel = "Fa", unit = "kN"', 'channel = "Fa"'), "every measured series carries its unit", True),
    (lambda s: s.replace('axial_load = { channel = "Fa", unit = "kN" }', ''), "trace.duty.axial_load", True),
    (lambda s: s.replace('channel = "Fr"', 'channel = "F_radial"'), "no such channel", True),
    (lambda s: s.replace('format = "csv"', 'format = "csv"\nprofile = "trace-csv.csv"'), "not both", True),
    (lambda s: s.replace("[trace.duty]", "[trace.duty]\ntolerance = 0.7"), "between 0 and 0.5", True),
    # a quantity held constant instead of a channel
    (lambda s: s.replace(FA, 'axial_load = 10'), "trace.duty.axial_load = 10: a constant takes its unit", True),
    (lambda s: s.replace(FA, 'axial_load = "10"'), "trace.duty.axial_load = '10': a constant takes its unit", True),
    (lambda s: s.replace(FA, 'axial_load = "10 um"'), "trace.duty.axial_load = '10 um': wrong units", True),
    (lambda s: s.replace(FA, 'axial_load = "Fa"'), "trace.duty.axial_load = 'Fa': not a constant", True),
    (lambda s: s.replace(FA, 'axial_load = "nan kN"'), "trace.duty.axial_load = 'nan kN': not a constant", True),
    (lambda s: s.replace(FA, 'axial_load = "1e400 kN"'), "trace.duty.axial_load = '1e400 kN': not a finite", True),
    (lambda s: s.replace(FA, 'axial_load = ["10 kN"]'), "trace.duty.axial_load: expected { channel", True),
    (lambda s: s.replace(FR, 'radial_load = "-5 kN"'), "trace.duty.radial_load = '-5 kN': must not be negative",
     True),
    (lambda s: s.replace(N, 'speed = "660 deg/s"'), "trace.duty.speed = '660 deg/s': a constant speed gives no "
                                                   "phases", True),
    (lambda s: s.replace(N, 'speed = "10 Hz"'), "trace.duty.speed = '10 Hz': not a speed: a frequency without",
     True),
    (lambda s: s.replace(N, 'speed = "10 kN"'), "trace.duty.speed = '10 kN': wrong units", True),
])
def test_bad_trace_files_give_one_line(case, tmp_path, capsys, edit, expect, duty):
    path, t, series = case
    more = study_channels(t, math.radians(660), 30e3, 10e3) if duty else None
    toml = write_trace(tmp_path, "csv", t, series, more=more, tail=DUTY_TAIL if duty else "")
    toml.write_text(edit(toml.read_text()))
    err = _one_line_error(capsys, ["compare", str(toml), "--case", str(path), "--out", str(tmp_path / "o")])
    assert expect in err and str(toml) in err


def test_a_time_base_that_goes_backwards(case, tmp_path, capsys):
    path, t, series = case
    tb = t.copy()
    tb[100], tb[101] = tb[101], tb[100]
    toml = write_trace(tmp_path, "csv", tb, series)
    err = _one_line_error(capsys, ["compare", str(toml), "--case", str(path), "--out", str(tmp_path / "o")])
    assert "goes backwards or stands still at sample 101" in err   # the 0-based index of 1.00 s after 1.01 s


def test_a_trace_shorter_than_the_cycle(case, tmp_path, capsys):
    path, t, series = case
    k = t.size // 2
    toml = write_trace(tmp_path, "mat", t[:k], {n: v[:k] for n, v in series.items()})
    err = _one_line_error(capsys, ["compare", str(toml), "--case", str(path), "--out", str(tmp_path / "o")])
    assert "shorter than the" in err


def test_a_file_the_library_cannot_read(case, tmp_path, capsys):
    path, t, series = case
    toml = write_trace(tmp_path, "hdf5", t, series)
    (tmp_path / "trace-hdf5.h5").write_bytes(b"not an HDF5 file at all")
    err = _one_line_error(capsys, ["compare", str(toml), "--case", str(path), "--out", str(tmp_path / "o")])
    assert "cannot read as HDF5" in err


def test_sweep_picks_the_case_at_the_traces_operating_point(case, tmp_path, capsys):
    """Two cases in a sweep folder, 120 and 660 °/s: the trace made from the 660 one and
    saying so is compared with it (Sprague–Geers errors 0), not with the other."""
    import json

    _, t, series = case
    sweep = tmp_path / "sweep"
    (sweep / "cases").mkdir(parents=True)
    for deg in (120, 660):
        r = synthetic_result(math.radians(deg), 30e3)
        ds = case_dataset(r, speed=math.radians(deg), radial_load=30e3, axial_load=10e3)
        write_case(ds, sweep / "cases" / f"case{deg}.nc")
    toml = write_trace(tmp_path, "csv", t, series,
                       extra='profile = "' + str(REPO / "sweeps/profiles/study.toml") + '"\n'
                             'speed = "660 deg/s"\nradial_load = "30 kN"')
    out = tmp_path / "out"
    assert main(["compare", str(toml), "--sweep", str(sweep), "--out", str(out)]) == 0
    summary = json.loads((out / "comparison.json").read_text())
    assert summary["case"].endswith("case660.nc")
    for n in NAMES:
        assert np.all(np.abs(summary["variables"][f"{n}_sprague_geers_combined"]) < 1e-6)


def test_the_shipped_example_reads_and_says_it_is_not_a_measurement():
    from pipeline.analysis.compare import read_trace

    trace = load_trace(REPO / "sweeps/traces/example.toml")
    data = read_trace(trace)
    assert "NOT A MEASUREMENT" in trace.file.read_text().splitlines()[0]
    assert np.all(np.diff(data["time"]) > 0)
    assert {c.measures for c in trace.channels} == set(NAMES)
    assert trace.profile is not None and trace.bearing is not None


def test_the_low_pass_removes_a_tone_above_its_cut_off(case, tmp_path):
    """A 1 µm tone at 230 Hz on a 1 kHz trace of the case, whose steady phase is flat: read
    at the case's 100 Hz unfiltered it aliases into a steady range of about 2 µm; a 20 Hz
    4th-order Butterworth, applied forwards and backwards, passes |H|² = 1/(1 + (230/20)^8)²
    of it, below 1e-16, so the steady range is the flat signal's 0 within the filter's own
    settling (bounded here by 1 % of the tone)."""
    import xarray as xr

    path, t, series = case
    tm = np.arange(0.0, t[-1] + 1e-9, 1e-3)
    tone = 1e-6 * np.sin(2 * np.pi * 230 * tm)
    meas = {n: np.interp(tm, t, series[n]) + tone for n in NAMES}
    assert np.ptp(series["radial_displacement"][(t >= 0.8) & (t < 3.8)]) == 0.0   # flat steady phase
    ranges = {}
    for low in ("", 'low_pass = "20 Hz"'):
        folder = tmp_path / (low and "lp" or "raw")
        folder.mkdir()
        trace = load_trace(write_trace(folder, "csv", tm, meas, extra=low))
        with xr.open_dataset(path) as ds:
            result = compare(trace, ds.load())
        ranges[bool(low)] = result["measured_metrics"]["radial_displacement_range"][1]
    assert ranges[False] > 1e-6
    assert ranges[True] < 1e-8


# ------------------------------------------------------------- the duty cycle from channels

DUTY_TAIL = """
[trace.duty]
speed = { channel = "n", unit = "rpm" }
radial_load = { channel = "Fr", unit = "kN" }
axial_load = { channel = "Fa", unit = "kN" }
"""


N, FR, FA = (line for line in DUTY_TAIL.splitlines() if "channel" in line)


def study_channels(t, speed, fr, fa, eps=(0.0, 0.0), seed=3):
    """The study cycle's speed [rpm] and loads [kN] at ``t``, by numpy from its breakpoints
    (docs/model.md §6: loads 0 -> 1 over 0-0.3 s, back to 0 over 4.3-4.6 s; speed 0 -> 1
    over 0.3-0.8 s, back over 3.8-4.3 s), with uniform noise of ±eps[0] rpm, ±eps[1] kN."""
    rng = np.random.default_rng(seed)
    load = np.interp(t, [0.0, 0.3, 4.3, 4.6], [0.0, 1.0, 1.0, 0.0])
    w = np.interp(t, [0.3, 0.8, 3.8, 4.3], [0.0, 1.0, 1.0, 0.0])
    rpm = speed * 60 / (2 * np.pi)
    return {"n": rpm * w + rng.uniform(-eps[0], eps[0], t.size),
            "Fr": fr / 1e3 * load + rng.uniform(-eps[1], eps[1], t.size),
            "Fa": fa / 1e3 * load + rng.uniform(-eps[1], eps[1], t.size)}


def test_breakpoints_keep_every_sample_within_the_tolerance():
    from pipeline.analysis.duty import breakpoints

    rng = np.random.default_rng(1)
    t = np.linspace(0.0, 1.0, 2001)
    x = np.sin(7 * t) + 0.01 * rng.standard_normal(t.size)
    for tol in (0.2, 0.05, 0.02):
        k = breakpoints(t, x, tol)
        assert k[0] == 0 and k[-1] == t.size - 1 and np.all(np.diff(k) > 0)
        assert np.max(np.abs(np.interp(t, t[k], x[k]) - x)) <= tol
    # a straight line needs only its ends; a trapezoid its four corners
    assert list(breakpoints(t, 3 * t + 1, 1e-9)) == [0, t.size - 1]
    trap = np.interp(t, [0.0, 0.25, 0.75, 1.0], [0.0, 1.0, 1.0, 0.0])
    assert list(breakpoints(t, trap, 1e-9)) == [0, 500, 1500, 2000]


@pytest.mark.parametrize("eps", [(0.0, 0.0), (0.5, 0.02)])
def test_the_duty_cycle_from_channels_is_the_study_cycle(eps):
    """Speed and load channels of the study cycle at 660 °/s, 30 kN + 10 kN, sampled at
    1 kHz, clean and with uniform noise: the phases within the time the ramp takes to
    cross the tolerance band and the noise (plus a sample), the operating point within
    the noise, and each table within half the tolerance of every sample."""
    from pipeline.analysis.duty import profile_from_channels

    speed, fr, fa, tol = math.radians(660), 30e3, 10e3, 0.02
    t = np.arange(0.0, 4.6 + 1e-9, 1e-3)
    ch = study_channels(t, speed, fr, fa, eps)
    rpm = 2 * np.pi / 60
    duty = {"speed": ch["n"] * rpm, "radial_load": ch["Fr"] * 1e3, "axial_load": ch["Fa"] * 1e3}
    profile, op = profile_from_channels(t, duty, tolerance=tol)
    slope = speed / 0.5                                    # the ramps' angular acceleration [rad s-2]
    band = (tol * speed + 2 * eps[0] * rpm) / slope + 1e-3
    for (name, a, b), (_, a0, b0) in zip(profile.phases, study_profile().phases):
        assert abs(a - a0) <= band and abs(b - b0) <= band, (name, a, b)
    assert op.speed == pytest.approx(speed, abs=eps[0] * rpm + 1e-12)
    assert op.radial_load == pytest.approx(fr, abs=eps[1] * 1e3 + 1e-9)
    assert op.axial_load == pytest.approx(fa, abs=eps[1] * 1e3 + 1e-9)
    for name, chan, steady in (("speed", profile.speed, op.speed), ("radial_load", profile.radial_load, op.radial_load),
                               ("axial_load", profile.axial_load, op.axial_load)):
        assert chan.relative and chan.interpolation == "linear"
        line = np.interp(t, chan.times, np.asarray(chan.values) * steady)
        scale = max(abs(steady), np.max(np.abs(duty[name])))
        assert np.max(np.abs(line - duty[name])) <= 0.5 * tol * scale * (1 + 1e-12), name
    assert profile.duration == pytest.approx(4.6)


def test_the_duty_profile_file_reads_back_as_the_same_profile(tmp_path):
    from pipeline.analysis.duty import profile_from_channels, profile_toml
    from pipeline.schema.profilefile import load_profile

    t = np.arange(0.0, 4.6 + 1e-9, 1e-3)
    ch = study_channels(t, math.radians(120), 20e3, 0.0, (0.1, 0.01))
    rpm = 2 * np.pi / 60
    duty = {"speed": ch["n"] * rpm, "radial_load": ch["Fr"] * 1e3, "axial_load": ch["Fa"] * 1e3}
    profile, _ = profile_from_channels(t, duty, tolerance=0.02, name="rig")
    path = tmp_path / "rig.toml"
    path.write_text(profile_toml(profile, "a header\nof two lines"))
    back = load_profile(path)
    assert back.phases == profile.phases and back.duration == profile.duration
    for a, b in ((back.speed, profile.speed), (back.radial_load, profile.radial_load),
                 (back.axial_load, profile.axial_load)):
        assert a.times == b.times and a.relative == b.relative
        np.testing.assert_allclose(a.values, b.values, rtol=1e-15, atol=1e-12)


def test_the_command_with_duty_channels_writes_the_profile(case, tmp_path, capsys):
    """A trace whose duty cycle comes from its channels (rpm, kN) and no profile file:
    compared with the case, its phases are the derived ones, and profile.toml is the cycle."""
    from pipeline.schema.profilefile import load_profile

    path, t, series = case
    more = study_channels(t, math.radians(660), 30e3, 10e3)
    toml = write_trace(tmp_path, "tdms", t, series, more=more, tail=DUTY_TAIL)
    out = tmp_path / "out"
    assert main(["compare", str(toml), "--case", str(path), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "--speed 660deg/s --radial-load 30kN --axial-load 10kN" in printed
    prof = load_profile(out / "profile.toml")
    dt = t[1] - t[0]
    band = 0.02 * 0.5 + dt             # the tolerance band of a 0.5 s ramp, and a sample
    for (_, a, b), (_, a0, b0) in zip(prof.phases, study_profile().phases):
        assert abs(a - a0) <= band and abs(b - b0) <= band
    import xarray as xr

    with xr.open_dataset(out / "comparison.nc") as ds:
        np.testing.assert_allclose(ds["phase_start"].values, [a for _, a, _ in prof.phases])
        assert float(ds["speed"]) == pytest.approx(660)
        assert np.all(np.abs(ds["radial_displacement_sprague_geers_combined"].values) < 1e-6)


@pytest.mark.parametrize("key, column, text, held", [
    ("axial_load", "Fa", "10 kN", 10e3),      # a dead weight the rig did not log
    ("axial_load", "Fa", "0 kN", 0.0),        # no axial load: no fraction to form
    ("radial_load", "Fr", "30 kN", 30e3),
])
def test_a_load_held_constant_is_the_channel_that_holds_it(case, tmp_path, capsys, key, column, text, held):
    """A trace with speed and load channels where one load is written as a constant in the
    trace file gives the profile and operating point of the same trace with a channel
    holding that constant over the whole record (in kN): the same phases, the constant as
    the operating point's load, each table within half the tolerance of the other's line;
    the written profile.toml, run at the printed operating point, holds the load at the
    constant over the whole record."""
    from pipeline.analysis.compare import read_trace
    from pipeline.analysis.duty import profile_from_channels
    from pipeline.schema.profilefile import load_profile
    from rvcore.profile import CH_AXIAL, CH_RADIAL, OperatingPoint

    path, t, series = case
    more = study_channels(t, math.radians(660), 30e3, 10e3, (0.3, 0.01))
    more[column] = np.full(t.size, held / 1e3)                      # the channel holding it [kN]
    line = {"axial_load": FA, "radial_load": FR}[key]
    got = {}
    for how, tail in (("channel", DUTY_TAIL), ("constant", DUTY_TAIL.replace(line, f'{key} = "{text}"'))):
        folder = tmp_path / how
        folder.mkdir()
        trace = load_trace(write_trace(folder, "csv", t, series, more=more, tail=tail))
        data = read_trace(trace)
        got[how] = profile_from_channels(data["time"], data["duty"], tolerance=trace.duty_tolerance)
    (p_ch, op_ch), (p_k, op_k) = got["channel"], got["constant"]
    assert p_k.phases == p_ch.phases and p_k.duration == p_ch.duration
    assert getattr(op_k, key) == held and getattr(op_ch, key) == pytest.approx(held, rel=1e-12, abs=1e-9)
    for n in ("speed", "radial_load", "axial_load"):
        a, b = getattr(p_k, n), getattr(p_ch, n)
        steady = getattr(op_k, n)
        assert getattr(op_ch, n) == pytest.approx(steady, rel=1e-12, abs=1e-9)
        assert a.relative == b.relative == (steady != 0.0)
        va, vb = (np.interp(t, c.times, np.asarray(c.values) * (steady if c.relative else 1.0)) for c in (a, b))
        scale = max(abs(steady), np.max(np.abs(vb)))
        assert np.max(np.abs(va - vb)) <= 0.5 * 0.02 * scale + 1e-12, n

    # the command: profile.toml holds the constant; resolved at the printed operating point
    # (as rvsweep simulate resolves it) the load is the constant at every time of the record
    toml = tmp_path / "constant" / "trace-csv.toml"
    out = tmp_path / "out"
    assert main(["compare", str(toml), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    flag = {"axial_load": "--axial-load", "radial_load": "--radial-load"}[key]
    assert f"{flag} {held / 1e3:g}kN" in printed
    text_file = (out / "profile.toml").read_text()
    assert f"{key} held at {text}" in text_file
    prof = load_profile(out / "profile.toml")
    other = 10e3 if key == "radial_load" else 30e3             # whatever the other load's steady value
    op = OperatingPoint(math.radians(660), held if key == "radial_load" else other,
                        held if key == "axial_load" else other)
    resolved = prof.resolve(op)
    c = CH_AXIAL if key == "axial_load" else CH_RADIAL
    for s in np.linspace(0.0, float(t[-1]), 7):
        assert resolved.value(c, float(s)) == held


def test_a_speed_that_never_comes_back_to_rest(case, tmp_path, capsys):
    path, t, series = case
    more = study_channels(t, math.radians(660), 30e3, 10e3)
    more["n"] = np.where(t > 3.8, more["n"].max(), more["n"])     # the rig never stops
    toml = write_trace(tmp_path, "csv", t, series, more=more, tail=DUTY_TAIL)
    err = _one_line_error(capsys, ["compare", str(toml), "--out", str(tmp_path / "o")])
    assert "trace.duty.speed.channel = 'n': the speed does not come back to rest" in err


# ------------------------------------------------- measured cases beside the simulated ones

def test_measured_group_and_fits_of_traces_at_three_speeds(tmp_path):
    """Traces of the synthetic case at 120, 390 and 660 °/s (30 kN), the 660 one twice with
    gains 1 and 1.1: the group holds each test's ranges (numpy's, over the windows), the
    fits' line against speed at 30 kN is numpy's least-squares line through the three
    operating points, the repeated point their average."""
    from pipeline.analysis import fit_statistic
    from pipeline.analysis.compare import comparison_dataset
    from pipeline.analysis.measured import measured_fits, measured_group

    tests = [(120.0, 1.0), (390.0, 1.0), (660.0, 1.0), (660.0, 1.1)]
    cases, want = [], []
    for k, (deg, gain) in enumerate(tests):
        r = synthetic_result(math.radians(deg), 30e3)
        series = {n: gain * r.series[n] for n in NAMES}
        folder = tmp_path / f"t{k}"
        folder.mkdir()
        trace = load_trace(write_trace(folder, "csv", r.time, series))
        result = compare(trace, None, phases=PHASE_WINDOWS)
        cases.append(comparison_dataset(trace, result, operating_point={
            "speed": math.radians(deg), "radial_load": 30e3, "axial_load": 10e3}))
        want.append({n: numpy_metrics(r.time, series[n], PHASE_WINDOWS)["range"] for n in NAMES})
    group = measured_group(cases)
    assert group.sizes["measured_case"] == 4
    np.testing.assert_allclose(group["measured_case_speed"].values, [d for d, _ in tests])
    for n in NAMES:
        np.testing.assert_allclose(group[f"measured_{n}_range"].values, [w[n] for w in want], rtol=1e-9, atol=1e-15)
    from pipeline.analysis.measured import points_on_line

    x, y = points_on_line(group, "radial_displacement_range", "speed", "radial_load", 30.2e3, 0)   # within 1 %
    np.testing.assert_allclose(x, [d for d, _ in tests])
    np.testing.assert_allclose(y, [w["radial_displacement"][0] for w in want], rtol=1e-9, atol=1e-15)
    assert points_on_line(group, "radial_displacement_range", "speed", "radial_load", 31e3, 0)[0].size == 0
    fits = measured_fits(group)
    for n in NAMES:
        for p in range(3):
            y = [want[0][n][p], want[1][n][p], 0.5 * (want[2][n][p] + want[3][n][p])]
            slope, intercept = np.polyfit([120.0, 390.0, 660.0], y, 1)
            got = fit_statistic(fits, f"{n}_range", "speed", "slope").sel(radial_load=30e3, phase=p)
            assert float(got) == pytest.approx(slope, rel=1e-9, abs=1e-20)
            got = fit_statistic(fits, f"{n}_range", "speed", "intercept").sel(radial_load=30e3, phase=p)
            assert float(got) == pytest.approx(intercept, rel=1e-9, abs=1e-15)


def test_the_shipped_duty_example_gives_the_short_profile_delayed_12_ms():
    """example.csv's speed and load channels are the short profile's (0.1 × the study's
    times) delayed 12 ms with ±0.3 rpm of noise: the phases within the tolerance band of a
    0.05 s ramp (2 % of 110 rpm, noise twice) and a sample, the operating point within the noise."""
    from pipeline.analysis.compare import read_trace
    from pipeline.analysis.duty import profile_from_channels
    from rvcore.profile import scaled_study_profile

    trace = load_trace(REPO / "sweeps/traces/example-duty.toml")
    data = read_trace(trace)
    profile, op = profile_from_channels(data["time"], data["duty"], tolerance=trace.duty_tolerance)
    band = (0.02 * 110 + 0.6) / (110 / 0.05) + 1e-3
    for (_, a, b), (_, a0, b0) in zip(profile.phases, scaled_study_profile(0.1).phases):
        assert abs(a - (a0 + 0.012)) <= band and abs(b - (b0 + 0.012)) <= band
    assert math.degrees(op.speed) == pytest.approx(660, abs=0.3 * 6)
    assert op.radial_load == pytest.approx(30e3, abs=50) and op.axial_load == pytest.approx(10e3, abs=50)
