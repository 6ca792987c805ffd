"""Tone amplitudes at known frequencies (rvcore.recording.spectra, issue 39 item 14).

Facts asserted, each from a signal built here whose amplitude is known by construction:

- a sinusoid between FFT bins, and at exactly half a bin, reads its amplitude within 1 %
  from :func:`rvcore.recording.spectra.tone_amplitudes` (a least-squares fit at the known frequency),
  where the Hann FFT's peak reads it 7-15 % low (the window's scalloping loss, which the
  test computes from the Hann window's transform);
- two tones together, each read within 1 % at its own frequency;
- ``steady_spectra``'s ``*_kinematic_amplitude`` are those fits.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from rvcore.recording import spectra

DT = 1e-3          # 1 kHz sampling
N = 2000           # 2 s: bins 0.5 Hz apart
DF = 1.0 / (N * DT)


def _tone(freq, amp, phase=0.3, n=N, offset=2.5e-4):
    t = np.arange(n) * DT
    return offset + amp * np.sin(2 * math.pi * freq * t + phase)


def _hann_scalloping(delta):
    """Peak of a Hann-windowed tone ``delta`` bins off a bin centre, over its amplitude
    (large N): |W(δ)|/W(0) = |sinc(δ)/(1 − δ²)|."""
    return abs(np.sinc(delta) / (1.0 - delta ** 2))


@pytest.mark.parametrize("offset_bins", [0.0, 0.25, 0.37, 0.5])
def test_a_tone_between_bins_reads_its_amplitude_within_one_percent(offset_bins):
    """A 20.02 µm tone at bin 97 + offset: the fit reads 20.02 µm within 1 % wherever it
    falls; the FFT's peak reads the Hann window's scalloping, 15 % low at half a bin."""
    amp = 20.02e-6
    freq = (97 + offset_bins) * DF
    x = _tone(freq, amp)
    fit = spectra.tone_amplitudes(x, DT, [freq])[0]
    assert fit == pytest.approx(amp, rel=0.01)
    f, a = spectra.amplitude_spectrum(x, DT)
    fft_peak = spectra.amplitude_at(f, a, [freq])[0]
    assert fft_peak == pytest.approx(amp * _hann_scalloping(offset_bins), rel=0.01)
    if offset_bins == 0.5:
        assert fft_peak < 0.86 * amp        # what the issue found: 18.6 µm for 20.0 µm


def test_two_tones_are_each_read_at_their_own_frequency():
    """Two tones 7.3 bins apart, 10 µm and 3 µm, off-bin: each fit within 1 %."""
    f1, f2 = 41.3 * DF, 48.6 * DF
    x = _tone(f1, 10e-6) + _tone(f2, 3e-6, phase=1.1, offset=0.0)
    a1, a2 = spectra.tone_amplitudes(x, DT, [f1, f2])
    assert a1 == pytest.approx(10e-6, rel=0.01)
    assert a2 == pytest.approx(3e-6, rel=0.01)


def test_targets_beyond_nyquist_or_below_one_period_are_nan():
    x = _tone(10.0, 1e-6)
    out = spectra.tone_amplitudes(x, DT, [600.0, 0.2, 10.0])
    assert math.isnan(out[0]) and math.isnan(out[1]) and out[2] == pytest.approx(1e-6, rel=1e-6)


def test_steady_spectra_kinematic_amplitudes_are_the_fits():
    """``steady_spectra`` over a window: the radial tone at a kinematic frequency reads its
    amplitude within 1 %, over a (time, sensor) series too."""
    t = np.arange(3 * N) * DT
    kin = spectra.kinematic_frequencies(12, 23e-3, 351.5e-3, 0.0, 2 * math.pi * 1.7)
    f_target = kin[2]                                   # the outer ball pass
    radial = 1e-4 + 5e-6 * np.sin(2 * math.pi * f_target * t)
    sensor = np.column_stack([radial, 2 * radial])
    out = spectra.steady_spectra(t, {"radial_displacement": radial, "axial_displacement": 0 * t,
                                     "sensor_displacement": sensor}, (1.0, 3.0), kin)
    assert out["radial_displacement_kinematic_amplitude"][2] == pytest.approx(5e-6, rel=0.01)
    assert out["sensor_displacement_kinematic_amplitude"].shape == (kin.size, 2)
    assert out["sensor_displacement_kinematic_amplitude"][2, 1] == pytest.approx(10e-6, rel=0.01)
