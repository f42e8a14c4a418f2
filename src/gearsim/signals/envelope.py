"""Squared-envelope spectrum of a band of the signal.

Envelope analysis (Randall & Antoni 2011): band-pass the signal around a
resonance that repetitive impacts excite, form the analytic signal of the band, and take
the spectrum of its squared magnitude, the *squared envelope*. The repetition frequency of
the impacts and its harmonics appear as lines; the squared envelope (rather than the
envelope) is used because its spectrum has no spurious components from the square root
(Randall & Antoni 2011; Ho & Randall 2000).

The band-pass is done by masking the FFT of the whole record (an ideal rectangular filter,
as in Randall & Antoni's band-pass before demodulation), the analytic signal by
:func:`scipy.signal.hilbert`, the amplitude spectrum by
:func:`gearsim.signals.spectrum.amplitude_spectrum` (windowed, amplitude-corrected). The
band is chosen by the analyst or by the fast kurtogram
(:func:`gearsim.signals.kurtogram.fast_kurtogram`).

References
----------
.. [RA11] R. B. Randall, J. Antoni, "Rolling element bearing diagnostics -- A tutorial",
   *Mechanical Systems and Signal Processing* 25 (2011) 485-520.
.. [HR00] D. Ho, R. B. Randall, "Optimisation of bearing diagnostic techniques using
   simulated and actual bearing fault signals", *Mechanical Systems and Signal
   Processing* 14 (2000) 763-788.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.fft
from scipy.signal import hilbert

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs
from gearsim.signals.spectrum import WINDOWS, Spectrum, amplitude_spectrum

__all__ = ["EnvelopeSpectrum", "band_pass", "squared_envelope", "envelope_spectrum"]


@dataclass(frozen=True)
class EnvelopeSpectrum(Spectrum):
    """Amplitude spectrum of the squared envelope (built by :func:`envelope_spectrum`).

    A :class:`~gearsim.signals.spectrum.Spectrum` (its amplitudes in units of the signal
    squared) that also names the band demodulated.

    Parameters
    ----------
    frequency, amplitude, window, fs, n_samples
        As in :class:`~gearsim.signals.spectrum.Spectrum`.
    band : tuple of float
        Band ``(low, high)`` (Hz) of the signal that was demodulated (keyword only).
    """

    band: tuple[float, float] = field(kw_only=True)

    def plot(self, *, f_max: float | None = None, harmonics_of: float | None = None, ax=None):
        """Draw the envelope spectrum (see :func:`gearsim.viz.toolbox.plot_envelope_spectrum`).

        Parameters
        ----------
        f_max : float, optional
            Upper end of the frequency axis (Hz); default the band width.
        harmonics_of : float, optional
            Frequency (Hz) whose harmonics are marked, e.g. a fault frequency.
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from gearsim.viz.toolbox import plot_envelope_spectrum

        return plot_envelope_spectrum(self, f_max=f_max, harmonics_of=harmonics_of, ax=ax)


def _check_band(band: object, fs: float, n: int) -> tuple[float, float]:
    """``band`` as ``(low, high)`` Hz inside ``[0, fs/2]`` holding at least two bins."""
    nyq = 0.5 * fs
    if band is None:
        return 0.0, nyq
    try:
        lo, hi = (float(b) for b in band)  # type: ignore[union-attr]
    except (TypeError, ValueError):
        raise InputError("band", band, "must be a pair (low, high) of frequencies in Hz") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo < hi <= nyq):
        raise InputError("band", (lo, hi), f"must satisfy 0 <= low < high <= fs/2 = {nyq:g} Hz")
    df = fs / n
    if (hi - lo) < 2.0 * df:
        raise InputError(
            "band", (lo, hi),
            f"must be at least 2 bins wide ({2 * df:g} Hz for {n} samples at {fs:g} Hz)",
        )
    return lo, hi


def band_pass(x: np.ndarray, fs: float, band: tuple[float, float]) -> np.ndarray:
    r"""Ideal band-pass by FFT masking: keep the bins with ``low <= f_k <= high``.

    .. math:: x_b = \mathcal{F}^{-1}\{X(f_k)\,\mathbf{1}[f_l \le |f_k| \le f_h]\}

    over the whole record (circular; Randall & Antoni 2011). Uses
    ``scipy.fft.rfft``/``irfft``.

    Parameters
    ----------
    x : array_like
        Signal (any units).
    fs : float
        Sampling rate (Hz).
    band : tuple of float
        ``(low, high)`` (Hz), ``0 <= low < high <= fs/2``, at least two bins wide.

    Returns
    -------
    ndarray
        Band-passed signal, same length and units as ``x``.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal, ``fs`` is not > 0, or the band is out of range.

    Examples
    --------
    Two tones; the band keeps the one at 100 Hz:

    >>> import numpy as np
    >>> t = np.arange(1000) / 1000.0
    >>> x = np.cos(2 * np.pi * 100 * t) + np.cos(2 * np.pi * 300 * t)
    >>> xb = band_pass(x, 1000.0, (50.0, 150.0))
    >>> bool(np.allclose(xb, np.cos(2 * np.pi * 100 * t)))
    True

    References
    ----------
    Randall & Antoni (2011).
    """
    a = as_signal(x)
    fs = check_fs(fs)
    lo, hi = _check_band(band, fs, a.size)
    spec = scipy.fft.rfft(a)
    f = np.arange(spec.size) * (fs / a.size)
    spec[(f < lo) | (f > hi)] = 0.0
    return scipy.fft.irfft(spec, a.size)


def squared_envelope(
    x: np.ndarray, fs: float, *, band: tuple[float, float] | None = None
) -> np.ndarray:
    r"""Squared envelope :math:`|x_b + i\,\mathcal{H}\{x_b\}|^2` of the band ``band``.

    ``x_b`` is ``x`` minus its mean, band-passed by :func:`band_pass` (the whole record
    when ``band`` is None); the analytic signal is :func:`scipy.signal.hilbert`. The mean
    is removed first: a sensor's bias ``c`` would add ``2 c x`` to the squared envelope,
    the raw spectrum of ``x`` scaled by the bias. For
    :math:`x = A\cos(2\pi f t)` inside the band the squared envelope is :math:`A^2`.

    Parameters
    ----------
    x : array_like
        Signal (any units).
    fs : float
        Sampling rate (Hz).
    band : tuple of float, optional
        ``(low, high)`` (Hz); default the whole band ``(0, fs/2)``.

    Returns
    -------
    ndarray
        Squared envelope (units of ``x`` squared), same length as ``x``.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal, ``fs`` is not > 0, or the band is out of range.

    Examples
    --------
    A tone of amplitude 2 on a bin has the constant squared envelope 4:

    >>> import numpy as np
    >>> t = np.arange(1000) / 1000.0
    >>> e = squared_envelope(2.0 * np.cos(2 * np.pi * 100 * t), 1000.0)
    >>> bool(np.allclose(e, 4.0))
    True

    References
    ----------
    Randall & Antoni (2011).
    """
    a = as_signal(x)
    fs = check_fs(fs)
    lo, hi = _check_band(band, fs, a.size)
    a = a - a.mean()
    xb = a if band is None else band_pass(a, fs, (lo, hi))
    z = hilbert(xb)
    return z.real**2 + z.imag**2


def envelope_spectrum(
    x: np.ndarray,
    fs: float,
    *,
    band: tuple[float, float] | None = None,
    window: str = "hann",
) -> EnvelopeSpectrum:
    r"""Squared-envelope spectrum of the band ``band`` of ``x``.

    .. math:: SES(f) = \left|\mathcal{F}\{ w\,(e - \bar e) \}\right|\ \text{(amplitude-
       corrected)}, \qquad e = |x_b + i\,\mathcal{H}\{x_b\}|^2

    Steps (Randall & Antoni 2011): mean removed, band-pass by FFT masking
    (:func:`band_pass`),
    analytic signal (:func:`scipy.signal.hilbert`), squared magnitude, mean removed,
    one-sided amplitude spectrum (:func:`gearsim.signals.spectrum.amplitude_spectrum`).
    Impacts repeating at ``f_r`` that excite a resonance inside the band show as lines at
    ``k f_r``.

    Parameters
    ----------
    x : array_like
        Signal (any units).
    fs : float
        Sampling rate (Hz).
    band : tuple of float, optional
        ``(low, high)`` (Hz) to demodulate, ``0 <= low < high <= fs/2``; default the whole
        band. :attr:`gearsim.signals.kurtogram.Kurtogram.band` gives the band of largest
        kurtosis.
    window : {"hann", "flattop", "boxcar"}
        Window of the amplitude spectrum of the squared envelope.

    Returns
    -------
    EnvelopeSpectrum
        Frequencies (Hz), amplitudes (units of ``x`` squared) and the band used.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal, ``fs`` is not > 0, the band is out of range or the
        window unknown.

    Examples
    --------
    A carrier of 200 Hz amplitude-modulated at 10 Hz,
    :math:`(1 + m\cos 2\pi f_m t)\cos 2\pi f_c t`, has the squared envelope
    :math:`1 + m^2/2 + 2m\cos 2\pi f_m t + (m^2/2)\cos 4\pi f_m t`: lines of amplitude
    :math:`2m` at 10 Hz and :math:`m^2/2` at 20 Hz.

    >>> import numpy as np
    >>> t = np.arange(2000) / 1000.0
    >>> x = (1 + 0.5 * np.cos(2 * np.pi * 10 * t)) * np.cos(2 * np.pi * 200 * t)
    >>> es = envelope_spectrum(x, 1000.0, band=(150.0, 250.0))
    >>> round(float(es.amplitude[20]), 6), round(float(es.amplitude[40]), 6)
    (1.0, 0.125)

    References
    ----------
    Randall & Antoni (2011).
    """
    a = as_signal(x)
    fs = check_fs(fs)
    if window not in WINDOWS:
        raise InputError("window", window, f"must be one of {sorted(WINDOWS)}")
    lo, hi = _check_band(band, fs, a.size)
    e = squared_envelope(a, fs, band=None if band is None else (lo, hi))
    spec = amplitude_spectrum(e - e.mean(), fs, window=window)
    return EnvelopeSpectrum(
        frequency=spec.frequency, amplitude=spec.amplitude, band=(lo, hi), window=window,
        fs=fs, n_samples=a.size,
    )
