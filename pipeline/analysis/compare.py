"""Measured rig traces beside a simulated case (``rvsweep compare``).

A trace (:mod:`pipeline.schema.tracefile`) is read with the format's own library (CSV:
the csv module; TDMS: npTDMS; HDF5 and MAT 7.3: h5py; MAT before 7.3: scipy.io.loadmat),
converted to metres with its sign, resampled onto the simulated case's output interval,
optionally low-passed (a zero-phase Butterworth, scipy.signal) and aligned to the simulated
cycle by cross-correlation. Its phase metrics then come from the code that computes a
simulated case's: every sample goes through the core's phase reductions
(:func:`rvcore.recording.plan.reduce_step`, read back by
:func:`rvcore.recording.results.read_phase_metrics`), and its steady spectrum through
:func:`rvcore.recording.spectra.steady_spectra`. Agreement is given as Sprague–Geers
errors per channel and phase and as the difference of each phase metric. The duty cycle
comes from the trace's profile file or from its speed and load channels
(:mod:`pipeline.analysis.duty`); a comparison stored in a sweep folder joins its metrics
and fits (:mod:`pipeline.analysis.measured`). SI throughout.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import xarray as xr

from rvcore.profile import PHASES

from ..errors import ConfigError, UserError
from ..io import VARIABLES, history_line, phase_coordinate
from ..io.case import kinematic_coordinate
from ..schema.tracefile import DutyChannel

#: Phase metrics of a displacement compared (those the core's reductions give).
METRIC_KINDS = ("range", "mean", "std", "min_time", "max_time", "range_at_edge")
#: Sprague–Geers errors: name -> long name.
SG_ERRORS = {"magnitude": "Sprague-Geers magnitude error M", "phase": "Sprague-Geers phase error P",
             "combined": "Sprague-Geers combined error C"}


# ----------------------------------------------------------------------------- reading

def _fail(trace, key, value, reason):
    raise ConfigError(trace.source, key, value, reason)


def _column_csv(path: Path, names):
    with path.open(newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    rows = [r for r in rows if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise UserError(f"{path}: empty CSV file")
    header = [h.strip() for h in rows[0]]
    out = {}
    for n in names:
        if n not in header:
            out[n] = None
            continue
        j = header.index(n)
        try:
            out[n] = np.array([float(r[j]) for r in rows[1:]], dtype=np.float64)
        except (ValueError, IndexError) as exc:
            raise UserError(f"{path}: column {n!r} is not all numbers ({exc})") from None
    return out, header


def _columns_tdms(path: Path, wanted):
    from nptdms import TdmsFile

    tdms = TdmsFile.read(path)
    groups = {g.name: g for g in tdms.groups()}
    out, have = {}, []
    for (group, name) in wanted:
        g = groups.get(group) if group else (next(iter(groups.values())) if groups else None)
        have = [f"{gg}/{c.name}" for gg, grp in groups.items() for c in grp.channels()]
        if g is None or name not in [c.name for c in g.channels()]:
            out[(group, name)] = None
        else:
            out[(group, name)] = np.asarray(g[name][:], dtype=np.float64)
    return out, have


def _columns_hdf5(path: Path, names):
    import h5py

    out, have = {}, []
    with h5py.File(path, "r") as f:
        f.visit(lambda n: have.append(n) if isinstance(f[n], h5py.Dataset) else None)
        for n in names:
            out[n] = np.asarray(f[n][()], dtype=np.float64).ravel() if n in have else None
    return out, have


def _columns_mat(path: Path, names):
    import scipy.io

    try:
        data = scipy.io.loadmat(path, squeeze_me=True)
    except NotImplementedError:       # MAT 7.3 is HDF5
        return _columns_hdf5(path, names)
    have = [k for k in data if not k.startswith("__")]
    return {n: (np.asarray(data[n], dtype=np.float64).ravel() if n in have else None) for n in names}, have


def read_trace(trace) -> dict:
    """The trace's series, SI, with the time base checked.

    Returns
    -------
    dict
        ``time`` [s] from the first sample (strictly increasing) and, for each channel,
        its ``measures`` name -> samples [m], sign applied; with ``[trace.duty]``, ``duty``:
        ``speed`` [rad s-1], ``radial_load`` and ``axial_load`` [N] over the same samples
        (a load the trace file holds constant: its value, a float).

    Raises
    ------
    ConfigError, UserError
        A file the format's library cannot read, a missing channel, a time base that
        does not increase, series of unequal length or with non-finite values.
    """
    duty = [(key, d) for key, d in trace.duty.items() if isinstance(d, DutyChannel)]
    wanted = ([(c.group, c.name) for c in trace.channels] + [(d.group, d.name) for _, d in duty]
              + ([(trace.time_group, trace.time_channel)] if trace.time_channel else []))
    names = list(dict.fromkeys(n for _, n in wanted))
    try:
        if trace.format == "csv":
            cols, have = _column_csv(trace.file, names)
        elif trace.format == "tdms":
            got, have = _columns_tdms(trace.file, list(dict.fromkeys(wanted)))
            cols = {n: got[w] for w in wanted for n in [w[1]]}
        elif trace.format == "hdf5":
            cols, have = _columns_hdf5(trace.file, names)
        else:
            cols, have = _columns_mat(trace.file, names)
    except UserError:
        raise
    except Exception as exc:   # each library raises its own types for a file it cannot read
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise UserError(f"{trace.file}: cannot read as {trace.format.upper()} ({why})") from None
    checked = ([(f"trace.channel[{i}].name", c.name) for i, c in enumerate(trace.channels)]
               + [(f"trace.duty.{key}.channel", d.name) for key, d in duty])
    for key, name in checked:
        if cols[name] is None:
            _fail(trace, key, name, f"no such channel in {trace.file.name} (has: {', '.join(map(str, have[:12]))})")
    if trace.time_channel and cols[trace.time_channel] is None:
        _fail(trace, "trace.time.channel", trace.time_channel,
              f"no such channel in {trace.file.name} (has: {', '.join(map(str, have[:12]))})")
    n = len(cols[trace.channels[0].name])
    for key, name in checked:
        x = cols[name]
        if len(x) != n:
            _fail(trace, key, name, f"{len(x)} samples, the first channel has {n}")
        if not np.all(np.isfinite(x)):
            _fail(trace, key, name, f"non-finite sample at index {int(np.argmin(np.isfinite(x)))}")
    if n < 4:
        _fail(trace, "trace.file", str(trace.file.name), f"{n} samples: too few to compare")
    if trace.time_channel:
        t = cols[trace.time_channel] * trace.time_scale
        if len(t) != n:
            _fail(trace, "trace.time.channel", trace.time_channel, f"{len(t)} samples, the channels have {n}")
        d = np.diff(t)
        if not np.all(np.isfinite(t)) or np.any(d <= 0):
            k = int(np.argmax(~(d > 0)))
            _fail(trace, "trace.time.channel", trace.time_channel,
                  f"the time base goes backwards or stands still at sample {k + 1}, counted from 0 "
                  f"({t[k]:.6g} s, then {t[k + 1]:.6g} s)")
        t = t - t[0]
    else:
        t = np.arange(n) / trace.rate
    out = {"time": t}
    for c in trace.channels:
        out[c.measures] = c.sign * c.scale * cols[c.name]
    if trace.duty:
        out["duty"] = {key: (d.scale * cols[d.name] if isinstance(d, DutyChannel) else d.value)
                       for key, d in trace.duty.items()}
    return out


# -------------------------------------------------------------------------- conditioning

def resample(time, x, interval: float, *, low_pass: float = math.nan):
    """``x(time)`` on a uniform grid of ``interval`` [s] from ``time[0]``, optionally low-passed first.

    Parameters
    ----------
    time : ndarray
        Increasing sample times [s].
    x : ndarray
        Samples [m].
    interval : float
        The new sample interval [s] (the simulated case's output interval).
    low_pass : float
        Cut-off [Hz] of a 4th-order Butterworth applied forwards and backwards (zero
        phase, scipy.signal.sosfiltfilt) at the trace's own median rate; NaN: none.

    Notes
    -----
    Linear interpolation. A cut-off at or below the new Nyquist frequency 1/(2·interval)
    keeps the resampling free of aliasing.
    """
    t = np.asarray(time, dtype=np.float64)
    x = np.asarray(x, dtype=np.float64)
    if math.isfinite(low_pass):
        from scipy.signal import butter, sosfiltfilt

        fs = 1.0 / float(np.median(np.diff(t)))
        if low_pass < 0.5 * fs and x.size > 27:
            x = sosfiltfilt(butter(4, low_pass, fs=fs, output="sos"), x)
    grid = t[0] + interval * np.arange(int(math.floor((t[-1] - t[0]) / interval + 1e-9)) + 1)
    return grid, np.interp(grid, t, x)


def find_lag(simulated: dict, measured: dict, interval: float) -> float:
    """The lag [s] of the measured series behind the simulated ones, by cross-correlation.

    Both on the same uniform ``interval`` [s], times from their first samples; ``measured(t)
    ≈ simulated(t − lag)``.

    Notes
    -----
    At each lag k the correlation coefficient of the overlapping samples,

    .. math:: r(k) = \\frac{Σ ab − Σa Σb / n}{\\sqrt{(Σa^2 − (Σa)^2/n)(Σb^2 − (Σb)^2/n)}}

    over the n samples where ``a[i + k]`` (measured) and ``b[i]`` (simulated) overlap, the
    sums Σab from scipy.signal.correlate and the others from cumulative sums; only lags
    overlapping at least half the shorter series count. The raw correlation (without the
    per-overlap normalisation) is biased towards the lag of largest overlap for a cycle
    that starts and ends unloaded. ``r`` is summed over the channels; its peak is refined
    by a parabola through its three samples.
    """
    from scipy.signal import correlate, correlation_lags

    total, lags = None, None
    for name, a in measured.items():
        b = simulated[name]
        na, nb = a.size, b.size
        lags = correlation_lags(na, nb, mode="full")
        sab = correlate(a, b, mode="full", method="auto")
        ca = np.concatenate([[0.0], np.cumsum(a)])
        ca2 = np.concatenate([[0.0], np.cumsum(a * a)])
        cb = np.concatenate([[0.0], np.cumsum(b)])
        cb2 = np.concatenate([[0.0], np.cumsum(b * b)])
        b_lo = np.maximum(0, -lags)
        b_hi = np.minimum(nb, na - lags)
        n = (b_hi - b_lo).astype(float)
        a_lo, a_hi = b_lo + lags, b_hi + lags
        with np.errstate(invalid="ignore", divide="ignore"):
            sa, sa2 = ca[a_hi] - ca[a_lo], ca2[a_hi] - ca2[a_lo]
            sb, sb2 = cb[b_hi] - cb[b_lo], cb2[b_hi] - cb2[b_lo]
            num = sab - sa * sb / n
            den = np.sqrt(np.maximum(sa2 - sa * sa / n, 0.0) * np.maximum(sb2 - sb * sb / n, 0.0))
            r = np.where((n >= max(4.0, 0.5 * min(na, nb))) & (den > 0), num / den, np.nan)
        total = r if total is None else total + r
    if total is None or not np.any(np.isfinite(total)):
        return 0.0
    k = int(np.nanargmax(total))
    shift = 0.0
    if 0 < k < len(total) - 1 and np.isfinite(total[k - 1]) and np.isfinite(total[k + 1]):
        y0, y1, y2 = total[k - 1], total[k], total[k + 1]
        den = y0 - 2 * y1 + y2
        if den < 0:
            shift = 0.5 * (y0 - y2) / den
    return float((lags[k] + shift) * interval)


# ------------------------------------------------------------------------------ metrics

def phase_metrics_of(time, series: dict, phases) -> dict:
    """Phase metrics of displacement series by the core's own reductions.

    Parameters
    ----------
    time : ndarray
        Sample times [s], uniform.
    series : dict
        ``radial_displacement`` and/or ``axial_displacement`` [m] over ``time``.
    phases : ndarray
        ``(phase, 2)`` windows ``[start, end)`` [s].

    Returns
    -------
    dict
        ``<name>_<kind>`` over phase for each series given and each of
        :data:`METRIC_KINDS`; the edge tolerance is one sample interval.

    Notes
    -----
    Each sample is a step of the integrator's phase accumulators
    (:func:`rvcore.recording.plan.reduce_step`, Welford's mean and variance, extremes with
    their times), read back by :func:`rvcore.recording.results.read_phase_metrics`: a
    measured case's metrics are a simulated case's, computed from the samples.
    """
    from rvcore.output_table import N_ROW_SIGNALS, N_SIGNALS
    from rvcore.recording.plan import SL_DA, SL_DR, build_plan, in_window, new_accumulators, reduce_step
    from rvcore.recording.results import read_phase_metrics

    t = np.asarray(time, dtype=np.float64)
    phases = np.asarray(phases, dtype=np.float64)
    plan = build_plan(1, 0)
    acc = new_accumulators(plan, phases.shape[0])
    diag = np.zeros(N_SIGNALS + N_ROW_SIGNALS)
    dr = np.asarray(series.get("radial_displacement", np.zeros_like(t)), dtype=np.float64)
    da = np.asarray(series.get("axial_displacement", np.zeros_like(t)), dtype=np.float64)
    dt = float(np.median(np.diff(t)))
    n_ph = phases.shape[0]
    for j in range(t.size):
        diag[SL_DR], diag[SL_DA] = dr[j], da[j]
        for k in range(n_ph + 1):
            if in_window(phases, k, n_ph, t[j]):
                reduce_step(acc[k], plan.reductions, diag, t[j], 0, 0.5 * dt)
    every = read_phase_metrics(acc, plan, phases, dt)
    return {f"{name}_{kind}": np.asarray(every[f"{name}_{kind}"], dtype=np.float64)
            for name in series for kind in METRIC_KINDS if f"{name}_{kind}" in every}


def sprague_geers(computed, measured):
    """Sprague–Geers magnitude, phase and combined errors of ``computed`` against ``measured``.

    Parameters
    ----------
    computed, measured : ndarray
        The two series on the same samples [any one unit].

    Returns
    -------
    tuple of float
        ``(M, P, C)`` [1]; NaN where either series is all zero or fewer than 2 samples.

    Notes
    -----
    Sprague, M. A. and Geers, T. L. (2004), "A spectral-element method for modelling
    cavitation in transient fluid–structure interaction", Int. J. Numer. Meth. Engng 60,
    2467–2499 (the revised comprehensive error factors). With
    ``ψ_mm = Σ m²``, ``ψ_cc = Σ c²`` and ``ψ_mc = Σ m·c`` over uniform samples,

    .. math:: M = \\sqrt{ψ_{cc}/ψ_{mm}} − 1, \\quad
              P = \\frac{1}{π} \\arccos\\frac{ψ_{mc}}{\\sqrt{ψ_{mm} ψ_{cc}}}, \\quad
              C = \\sqrt{M^2 + P^2}

    so ``c = a·m`` gives ``M = a − 1`` and ``P = 0``: M is the simulation's relative
    magnitude error, P its phase error (0 in phase, 1 opposite).
    """
    c = np.asarray(computed, dtype=np.float64)
    m = np.asarray(measured, dtype=np.float64)
    if c.size < 2:
        return math.nan, math.nan, math.nan
    mm, cc, mc = float(np.dot(m, m)), float(np.dot(c, c)), float(np.dot(m, c))
    if mm == 0 or cc == 0:
        return math.nan, math.nan, math.nan
    mag = math.sqrt(cc / mm) - 1.0
    ph = math.acos(max(-1.0, min(1.0, mc / math.sqrt(mm * cc)))) / math.pi
    return mag, ph, math.hypot(mag, ph)


# ------------------------------------------------------------------------- the comparison

def simulated_case(path) -> xr.Dataset:
    """A case file, loaded; one line if it cannot be read or lacks the displacements."""
    path = Path(path)
    if not path.is_file():
        raise UserError(f"{path}: no such case file")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            ds = ds.load()
    except Exception as exc:  # netCDF4/HDF5 raise OSError, RuntimeError, ValueError
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise UserError(f"{path}: cannot read as NetCDF ({why})") from None
    for v in ("radial_displacement", "axial_displacement"):
        if v not in ds:
            raise UserError(f"{path}: not a case file (no '{v}')")
    return ds


def case_of_sweep(directory, speed: float, radial_load: float, source: str) -> Path:
    """The case file of a sweep folder nearest the trace's operating point (``speed``
    [rad s-1], ``radial_load`` [N]), the relative distance in each summed."""
    directory = Path(directory)
    files = sorted((directory / "cases").glob("*.nc"))
    if not files:
        raise UserError(f"{directory}: no cases/*.nc to compare with")
    if not (math.isfinite(speed) and math.isfinite(radial_load)):
        raise ConfigError(source, "trace.speed", None, "--sweep needs the trace's speed and radial_load "
                                                       "to pick the case")
    best, score = None, math.inf
    for f in files:
        with xr.open_dataset(f, engine="netcdf4") as ds:
            s = math.radians(float(ds["speed"])) if "speed" in ds.coords else math.nan
            r = float(ds["radial_load"]) if "radial_load" in ds.coords else math.nan
        d = abs(s - speed) / abs(speed or 1) + abs(r - radial_load) / abs(radial_load or 1)
        if d < score:
            best, score = f, d
    return best


def compare(trace, case: xr.Dataset | None = None, *, phases=None, cycle: float = math.nan,
            kinematic=None) -> dict:
    """Condition a trace, align it to a simulated case and compute both sides' metrics.

    Parameters
    ----------
    trace : pipeline.schema.tracefile.Trace
    case : xarray.Dataset or None
        A simulated case (:func:`simulated_case`); None: the trace's own metrics only, on
        its own time base and rate.
    phases : ndarray or None
        ``(phase, 2)`` windows [s] of the cycle; None: the case's ``phase_start``/``phase_end``.
    cycle : float
        The cycle's length [s] (the profile's duration); NaN: the case's last output time.
    kinematic : ndarray or None
        The bearing's kinematic frequencies [Hz]
        (:func:`rvcore.recording.spectra.kinematic_frequencies`) for the measured tone
        amplitudes; None: none.

    Returns
    -------
    dict
        ``time`` [s] (simulated frame), ``measured`` and ``simulated`` series on it [m],
        ``lag`` [s], ``interval`` [s], ``phases``, ``measured_metrics`` and
        ``simulated_metrics`` (:func:`phase_metrics_of`), ``sprague_geers``
        (name -> (phase, 3) array of M, P, C), ``spectra`` (measured steady spectra) and
        ``simulated_spectra`` (the simulated series' on the same samples, by the same code).

    Raises
    ------
    ConfigError
        A trace shorter than the cycle (before any conditioning).
    """
    from rvcore.recording.spectra import steady_spectra

    raw = read_trace(trace)
    names = [c.measures for c in trace.channels]
    if case is not None:
        ts = np.asarray(case["elapsed_time"].values, dtype=np.float64)
        if phases is None and "phase_start" in case and "phase_end" in case:
            phases = np.column_stack([case["phase_start"].values, case["phase_end"].values])
        if not math.isfinite(cycle):
            cycle = float(ts[-1] - ts[0])
    if phases is None:
        raise ConfigError(trace.source, "trace.profile", None,
                          "no phase windows: give the profile the rig ran (the case file holds none)")
    phases = np.asarray(phases, dtype=np.float64)
    if not math.isfinite(cycle):
        cycle = float(phases[-1, 1])
    span = float(raw["time"][-1])
    if span < cycle * (1 - 1e-9):
        _fail(trace, "trace.file", str(trace.file.name),
              f"the trace lasts {span:.6g} s, shorter than the {cycle:.6g} s cycle it must cover")
    if case is None:
        interval = float(np.median(np.diff(raw["time"])))
        t, meas = None, {}
        for n in names:
            t, meas[n] = resample(raw["time"], raw[n], interval, low_pass=trace.low_pass)
        sim, lag = None, 0.0
    else:
        interval = float(np.median(np.diff(ts)))
        grid_m, meas_u = None, {}
        for n in names:
            grid_m, meas_u[n] = resample(raw["time"], raw[n], interval, low_pass=trace.low_pass)
        sim_u = {n: np.interp(ts[0] + interval * np.arange(int((ts[-1] - ts[0]) / interval + 1e-9) + 1), ts,
                              np.asarray(case[n].values, dtype=np.float64)) for n in names}
        lag = find_lag(sim_u, meas_u, interval) + float(grid_m[0] - ts[0])
        t = ts
        # measured on the simulated samples: m(t + lag); outside the trace, NaN
        meas = {n: np.interp(t + lag, raw["time"][0] + interval * np.arange(meas_u[n].size), meas_u[n],
                             left=np.nan, right=np.nan) for n in names}
        keep = np.all([np.isfinite(v) for v in meas.values()], axis=0)
        t = t[keep]
        meas = {n: v[keep] for n, v in meas.items()}
        sim = {n: np.asarray(case[n].values, dtype=np.float64)[keep] for n in names}
        if t.size < 4 or t[-1] - t[0] < (phases[-1, 1] - phases[0, 0]) * 0.5:
            _fail(trace, "trace.file", str(trace.file.name),
                  f"aligned with a lag of {lag:.6g} s, the trace covers too little of the cycle")
    out = {"time": t, "measured": meas, "simulated": sim, "lag": lag, "interval": interval, "phases": phases,
           "measured_metrics": phase_metrics_of(t, meas, phases),
           "simulated_metrics": phase_metrics_of(t, sim, phases) if sim is not None else None}
    sg = {}
    if sim is not None:
        for n in names:
            rows = []
            for (a, b) in phases:
                w = (t >= a) & (t < b)
                rows.append(sprague_geers(sim[n][w], meas[n][w]))
            sg[n] = np.array(rows)
    out["sprague_geers"] = sg
    kinematic = np.zeros(0) if kinematic is None else np.asarray(kinematic, dtype=np.float64)
    out["kinematic"] = kinematic
    out["spectra"] = steady_spectra(t, meas, tuple(phases[1]), kinematic) if len(phases) > 1 else {}
    out["simulated_spectra"] = (steady_spectra(t, sim, tuple(phases[1]), kinematic)
                                if sim is not None and len(phases) > 1 else {})
    return out


def comparison_dataset(trace, result: dict, *, case_name: str = "", operating_point=None) -> xr.Dataset:
    """The comparison as CF NetCDF content: the measured phase metrics under the case
    files' names (so a measured case sits beside simulated ones), the simulated ones with
    ``_simulated``, their ``_difference`` (simulated − measured), the Sprague–Geers errors
    and the lag; the compared series over ``elapsed_time`` (the simulated frame) and the
    steady spectra, measured under the case files' names and simulated with
    ``_simulated``; the phase windows; the operating point (``speed`` [degree s-1],
    ``radial_load``, ``axial_load`` [N]) as scalar coordinates where known. Every variable
    has ``units`` and ``long_name``.

    Parameters
    ----------
    operating_point : dict or None
        ``speed`` [rad s-1], ``radial_load``, ``axial_load`` [N]; NaN or missing: unknown.
    """
    data = {}
    for name, values in result["measured_metrics"].items():
        _, units, long_name = VARIABLES[name]
        data[name] = ("phase", values, {"units": units, "long_name": f"measured: {long_name}"})
        sim = result["simulated_metrics"]
        if sim is not None:
            data[f"{name}_simulated"] = ("phase", sim[name], {"units": units, "long_name": f"simulated: {long_name}"})
            data[f"{name}_difference"] = ("phase", sim[name] - values,
                                          {"units": units, "long_name": f"simulated minus measured: {long_name}"})
    for name, arr in result["sprague_geers"].items():
        for k, (key, long_name) in enumerate(SG_ERRORS.items()):
            data[f"{name}_sprague_geers_{key}"] = ("phase", arr[:, k], {
                "units": "1", "long_name": f"{long_name} of the simulated {name} against the measured, per phase"})
    data["lag"] = ((), result["lag"], {"units": "s", "long_name": "lag of the measured trace behind the simulated "
                                                                   "cycle, by cross-correlation"})
    data["sample_interval"] = ((), result["interval"], {"units": "s", "long_name": "sample interval of the "
                                                                                   "compared series"})
    phases = np.asarray(result["phases"], dtype=np.float64)
    data["phase_start"] = ("phase", phases[:, 0], {"units": "s", "long_name": "start of the phase window"})
    data["phase_end"] = ("phase", phases[:, 1], {"units": "s", "long_name": "end of the phase window"})
    for n, x in result["measured"].items():
        _, units, long_name = VARIABLES[n]
        data[n] = ("elapsed_time", np.asarray(x, dtype=np.float64), {"units": units,
                                                                      "long_name": f"measured: {long_name}"})
        if result["simulated"] is not None:
            data[f"{n}_simulated"] = ("elapsed_time", np.asarray(result["simulated"][n], dtype=np.float64),
                                      {"units": units, "long_name": f"simulated: {long_name}"})
    coords = {"phase": phase_coordinate(),
              "elapsed_time": ("elapsed_time", np.asarray(result["time"], dtype=np.float64),
                               {"units": "s", "long_name": "simulated time from the start of the cycle "
                                                           "(the measured series shifted by the lag)"})}
    spectra = result["spectra"]
    if "frequency" in spectra:
        coords["frequency"] = ("frequency", spectra["frequency"], {"units": "Hz", "long_name":
                                                                   "frequency of the steady phase's spectra"})
        for who, sp in (("measured", spectra), ("simulated", result.get("simulated_spectra") or {})):
            tail = "" if who == "measured" else "_simulated"
            for n in ("radial_displacement", "axial_displacement"):
                if f"{n}_spectrum" in sp:
                    _, units, long_name = VARIABLES[f"{n}_spectrum"]
                    data[f"{n}_spectrum{tail}"] = ("frequency", sp[f"{n}_spectrum"],
                                                   {"units": units, "long_name": f"{who}: {long_name}"})
                if f"{n}_kinematic_amplitude" in sp and result["kinematic"].size:
                    _, units, long_name = VARIABLES[f"{n}_kinematic_amplitude"]
                    data[f"{n}_kinematic_amplitude{tail}"] = ("kinematic", sp[f"{n}_kinematic_amplitude"],
                                                              {"units": units, "long_name": f"{who}: {long_name}"})
        if result["kinematic"].size:
            coords["kinematic"] = kinematic_coordinate()
            data["kinematic_frequency"] = ("kinematic", result["kinematic"], {
                "units": "Hz", "long_name": "kinematic frequency of the bearing at the trace's speed"})
    op = dict(operating_point or {})
    for key, conv, units, long_name in (("speed", math.degrees, "degree s-1", "steady inner-ring speed"),
                                        ("radial_load", float, "N", "steady radial load"),
                                        ("axial_load", float, "N", "steady axial load")):
        v = op.get(key, math.nan)
        if v is not None and math.isfinite(v):
            coords[key] = ((), conv(v), {"units": units, "long_name": f"{long_name} of the measured test"})
    ds = xr.Dataset(data, coords=coords)
    ds.attrs = {"Conventions": "CF-1.8",
                "title": f"RV main-bearing rig trace '{trace.name}' beside the simulated case {case_name}".strip(),
                "source": f"measured: {trace.file.name} ({trace.format}); trace file {trace.source}",
                "history": history_line("pipeline.analysis.compare"),
                "references": "Sprague, M. A. and Geers, T. L. (2004), Int. J. Numer. Meth. Engng 60, 2467-2499",
                "trace": trace.name,
                "case": case_name,
                "comment": "; ".join(f"{c.measures}: channel {c.name!r} in {c.unit}, sign {c.sign:+g}, "
                                     f"position {c.position or 'not given'}" for c in trace.channels)}
    return ds


def table(result: dict) -> str:
    """The agreement as a plain-text table: per channel and phase, the ranges and means [µm]
    and the Sprague–Geers errors."""
    lines = [f"lag {result['lag']:.6g} s (measured behind simulated); sample interval {result['interval']:.6g} s",
             f"{'series':<22}{'phase':<14}{'range meas':>12}{'range sim':>12}{'mean meas':>12}{'mean sim':>12}"
             f"{'SG M':>9}{'SG P':>9}{'SG C':>9}", "(ranges and means in µm)"]
    mm, sm = result["measured_metrics"], result["simulated_metrics"]
    for name in result["measured"]:
        for k, ph in enumerate(PHASES[:len(result["phases"])]):
            def f(d, kind):
                return f"{d[f'{name}_{kind}'][k] * 1e6:12.4g}" if d is not None else f"{'-':>12}"
            sg = result["sprague_geers"].get(name)
            e = "".join(f"{v:9.3f}" for v in sg[k]) if sg is not None else f"{'-':>9}" * 3
            lines.append(f"{name:<22}{ph:<14}{f(mm, 'range')}{f(sm, 'range')}{f(mm, 'mean')}{f(sm, 'mean')}{e}")
    return "\n".join(lines)
