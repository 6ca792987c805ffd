"""Amplitude spectra of a case's steady phase and the bearing's kinematic frequencies, SI.

A rig engineer compares a displacement's spectrum with the frequencies the bearing's
kinematics sets: the shaft's, the cage's, the ball-pass frequencies of both races, the
ball spin and their harmonics. Imperfections put vibration at these (docs/model.md §12); a
perfect bearing under radial load shows only the outer ball pass, its varying compliance.

Two estimates, for two uses:

- the spectrum (:func:`amplitude_spectrum`): a Hann-windowed FFT, to see where the lines
  are. A tone at a bin centre reads its amplitude; between bins the window's scalloping
  reads it low, by up to 15 % at half a bin (1 − sinc-shaped loss of the Hann window).
- the tone amplitudes at the kinematic frequencies (:func:`tone_amplitudes`): the
  frequencies are known, so each amplitude is a least-squares fit of a sinusoid at that
  frequency (Hann-weighted, with a constant), exact for a clean tone wherever it falls
  between bins. These are the ``*_kinematic_amplitude`` outputs (since MODEL_VERSION 13;
  before, the largest FFT value within one bin, 7–15 % low between bins).
"""
from __future__ import annotations

import math

import numpy as np

#: The kinematic frequencies, in the order of the ``kinematic`` dimension: each one and
#: its second harmonic.
KINEMATIC = ("shaft", "cage", "outer_ball_pass", "inner_ball_pass", "ball_spin")
KINEMATIC_NAMES = KINEMATIC + tuple(f"{k}_2x" for k in KINEMATIC)


def kinematic_frequencies(ball_count: int, ball_diameter: float, pitch_diameter: float,
                          contact_angle: float, speed: float) -> np.ndarray:
    """The bearing's kinematic frequencies [Hz] in :data:`KINEMATIC_NAMES` order.

    Parameters
    ----------
    ball_count : int
    ball_diameter, pitch_diameter : float
        ``D``, ``d_m`` [m].
    contact_angle : float
        α [rad].
    speed : float
        Inner-ring speed, the outer ring fixed [rad s^-1].

    Notes
    -----
    Rolling without slip, γ = D·cos α / d_m, ``f_i = ω/2π``:

    .. math:: f_c = \\tfrac{1}{2} f_i (1 - γ), \\quad f_{o} = Z f_c, \\quad
              f_{in} = Z (f_i - f_c), \\quad f_b = \\frac{d_m}{2D} f_i (1 - γ^2)

    (``f_b`` the ball's spin relative to the cage), then twice each.
    """
    f_i = abs(speed) / (2.0 * math.pi)
    gamma = ball_diameter * math.cos(contact_angle) / pitch_diameter
    f_c = 0.5 * f_i * (1.0 - gamma)
    base = np.array([f_i, f_c, ball_count * f_c, ball_count * (f_i - f_c),
                     pitch_diameter / (2.0 * ball_diameter) * f_i * (1.0 - gamma * gamma)])
    return np.concatenate([base, 2.0 * base])


def amplitude_spectrum(signal, sample_interval: float):
    """Single-sided amplitude spectrum of ``signal`` (mean removed, Hann window).

    Parameters
    ----------
    signal : array_like
        Samples, last axis time [any unit].
    sample_interval : float
        [s]

    Returns
    -------
    frequency : ndarray
        [Hz], bins ``k/(n·Δt)``.
    amplitude : ndarray
        [the signal's unit]: a sinusoid of amplitude A at a bin's frequency reads A;
        between bins it reads less, down to about 0.85 A at half a bin.

    Notes
    -----
    ``A_k = 2·|Σ w_n x_n e^{−2πikn/N}| / Σ w_n`` with the Hann window ``w``: the window's
    coherent gain divided out, so a tone at a bin centre peaks at its amplitude; a tone
    between bins leaks over ±1 bin and its peak reads low (the Hann window's scalloping
    loss, 1.42 dB = 15 % at half a bin). Read a tone's amplitude at a known frequency
    from :func:`tone_amplitudes`.
    """
    x = np.asarray(signal, dtype=np.float64)
    n = x.shape[-1]
    if n < 4:
        return np.zeros(0), np.zeros(x.shape[:-1] + (0,))
    w = np.hanning(n)
    x = x - x.mean(axis=-1, keepdims=True)
    amp = 2.0 * np.abs(np.fft.rfft(x * w, axis=-1)) / w.sum()
    return np.fft.rfftfreq(n, sample_interval), amp


def tone_amplitudes(signal, sample_interval: float, targets) -> np.ndarray:
    """Amplitude of a sinusoid at each known frequency, by weighted least squares.

    Parameters
    ----------
    signal : array_like
        Samples, last axis time [any unit].
    sample_interval : float
        [s]
    targets : array_like
        The tone frequencies [Hz].

    Returns
    -------
    ndarray
        ``signal.shape[:-1] + (len(targets),)`` [the signal's unit]; NaN for a target at or
        above the Nyquist frequency, or with less than one period in the record.

    Notes
    -----
    At each target ``f`` the fit minimises

    .. math:: \\sum_n w_n \\left(x_n - c - a \\cos 2π f t_n - b \\sin 2π f t_n\\right)^2,
              \\qquad A = \\sqrt{a^2 + b^2}

    with the Hann window ``w`` as the weight (``t_n = n Δt``). For a record that is a
    constant plus one sinusoid at ``f`` the fit is exact whatever the weights, so ``A``
    is the tone's amplitude wherever ``f`` falls between the FFT's bins; the weight
    keeps the other tones' leakage into the fit at the Hann window's low side lobes.
    """
    x = np.asarray(signal, dtype=np.float64)
    n = x.shape[-1]
    targets = np.asarray(targets, dtype=np.float64)
    out = np.full(x.shape[:-1] + (targets.size,), np.nan)
    if n < 4:
        return out
    t = np.arange(n) * sample_interval
    duration = n * sample_interval
    sw = np.sqrt(np.hanning(n + 2)[1:-1])        # the weights' square roots, none zero
    flat = x.reshape(-1, n)
    for k, f in enumerate(targets):
        if not (math.isfinite(f) and f * duration >= 1.0 and f < 0.5 / sample_interval):
            continue
        phase = 2.0 * math.pi * f * t
        design = np.column_stack([np.ones(n), np.cos(phase), np.sin(phase)]) * sw[:, None]
        coef, *_ = np.linalg.lstsq(design, (flat * sw[None, :]).T, rcond=None)
        out[..., k] = np.hypot(coef[1], coef[2]).reshape(x.shape[:-1])
    return out


def amplitude_at(frequency: np.ndarray, amplitude: np.ndarray, targets) -> np.ndarray:
    """The largest amplitude within one bin of each target frequency (NaN beyond the
    spectrum), last axis over ``targets``: where a line is, not its amplitude (that reads
    low between bins, :func:`amplitude_spectrum`); the amplitudes are
    :func:`tone_amplitudes`."""
    out = np.full(amplitude.shape[:-1] + (len(targets),), np.nan)
    if frequency.size < 2:
        return out
    df = frequency[1] - frequency[0]
    for k, f in enumerate(targets):
        near = np.abs(frequency - f) <= df * (1.0 + 1e-9)
        if f <= frequency[-1] and near.any():
            out[..., k] = amplitude[..., near].max(axis=-1)
    return out


def steady_spectra(time, series: dict, window, kinematic: np.ndarray) -> dict:
    """Spectra of the steady window ``[start, end)`` of every displacement series.

    Parameters
    ----------
    time : ndarray
        Sample times [s], uniformly spaced in the window.
    series : dict
        ``radial_displacement``, ``axial_displacement`` over time and, with sensors,
        ``sensor_displacement`` over (time, sensor) [m].
    window : tuple of float
        The steady phase [s].
    kinematic : ndarray
        :func:`kinematic_frequencies` [Hz].

    Returns
    -------
    dict
        ``frequency`` [Hz]; for each series ``<name>_spectrum`` over frequency (then
        sensor; Hann FFT, :func:`amplitude_spectrum`) and ``<name>_kinematic_amplitude``
        over the kinematic frequencies (then sensor; least-squares tone fits,
        :func:`tone_amplitudes`) [m]; empty when the window holds fewer than 4 samples.
    """
    t = np.asarray(time, dtype=np.float64)
    inside = (t >= window[0]) & (t < window[1])
    if inside.sum() < 4:
        return {}
    dt = float(np.median(np.diff(t[inside])))
    out = {}
    for name in ("radial_displacement", "axial_displacement", "sensor_displacement"):
        if name not in series:
            continue
        x = np.asarray(series[name], dtype=np.float64)[inside]
        f, a = amplitude_spectrum(np.moveaxis(x, 0, -1), dt)     # (sensor,) + (frequency,)
        out["frequency"] = f
        out[f"{name}_spectrum"] = np.moveaxis(a, -1, 0)
        xs = np.moveaxis(x, 0, -1)
        out[f"{name}_kinematic_amplitude"] = np.moveaxis(tone_amplitudes(xs, dt, kinematic), -1, 0)
    return out
