"""Short-time Fourier transform, band energy over time and band width around ``n f_m``.

The seed (sec. 3.3, Figure 8) reads its time-frequency maps in two directions: along
time, the energy near ``n f_m`` pulses once per revolution of the cracked gear; along
frequency, the bright band around ``n f_m`` widens when a crack is present. Band energy
over time and band width quantify the two.

References
----------
.. [AR77] J. B. Allen, L. R. Rabiner, "A unified approach to short-time Fourier analysis
   and synthesis", *Proc. IEEE* 65 (1977) 1558-1564.
.. [SciPy] ``scipy.signal.ShortTimeFFT`` (SciPy >= 1.12), used for the transform itself.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import ShortTimeFFT, get_window

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs, check_positive
from gearsim.signals._stft import stft as _stft

__all__ = ["Spectrogram", "spectrogram", "band_energy", "band_width", "modulation_index"]


@dataclass(frozen=True)
class Spectrogram:
    """Power spectral density over time (built by :func:`spectrogram`).

    Parameters
    ----------
    time : ndarray, shape (n_time,)
        Frame centre times (s).
    frequency : ndarray, shape (n_freq,)
        Frequencies (Hz), spacing ``fs / nperseg``.
    psd : ndarray, shape (n_freq, n_time)
        One-sided power spectral density (signal units squared per Hz).
    nperseg : int
        Frame length (samples).
    hop : int
        Step between frames (samples).
    window : str
        Window name (``scipy.signal.get_window``).
    fs : float
        Sampling rate (Hz).
    """

    time: np.ndarray
    frequency: np.ndarray
    psd: np.ndarray
    nperseg: int
    hop: int
    window: str
    fs: float

    @property
    def df(self) -> float:
        """Frequency resolution (bin width, Hz)."""
        return self.fs / self.nperseg


def spectrogram(
    x: np.ndarray, fs: float, *, nperseg: int, hop: int, window: str = "hann"
) -> Spectrogram:
    r"""One-sided PSD spectrogram :math:`S(t_j, f_k) = |X_j(f_k)|^2` with PSD scaling.

    Computed by ``scipy.signal.ShortTimeFFT(win, hop, fs, fft_mode="onesided2X",
    scale_to="psd")`` (Allen & Rabiner 1977): frames of ``nperseg`` samples every ``hop``
    samples; only frames that lie wholly inside the record are kept (no zero-padded edge
    frames, whose energy would be biased low).

    Parameters
    ----------
    x : array_like
        Signal (any units).
    fs : float
        Sampling rate (Hz).
    nperseg : int
        Frame length (samples); frequency resolution ``fs / nperseg``.
    hop : int
        Frame step (samples), 1 <= hop <= nperseg.
    window : str
        Window name for ``scipy.signal.get_window``.

    Returns
    -------
    Spectrogram
        Frame times (s), frequencies (Hz) and PSD (signal units squared per Hz).

    Raises
    ------
    InputError
        If ``x`` is not a valid signal, ``fs`` is not > 0, ``nperseg`` or ``hop`` is out
        of range, the window is unknown, or no frame fits wholly in the record.
    """
    a = as_signal(x)
    fs = check_fs(fs)
    if int(nperseg) != nperseg or not 2 <= nperseg <= a.size:
        raise InputError("nperseg", nperseg, f"must be an integer in [2, {a.size}] (record length)")
    if int(hop) != hop or not 1 <= hop <= nperseg:
        raise InputError("hop", hop, f"must be an integer in [1, {nperseg}] (nperseg)")
    nperseg, hop = int(nperseg), int(hop)
    try:
        win = get_window(window, nperseg, fftbins=True)
    except ValueError as exc:
        raise InputError("window", window, f"must be a scipy window name ({exc})") from None
    stft = ShortTimeFFT(win, hop, fs, fft_mode="onesided2X", scale_to="psd")
    p0 = stft.lower_border_end[1]
    p1 = stft.upper_border_begin(a.size)[1]
    if p1 <= p0:
        raise InputError("nperseg", nperseg, f"leaves no full frame in {a.size} samples")
    z = _stft(stft, a, p0, p1)  # = stft.stft(a, p0=p0, p1=p1), all frames in one FFT call
    psd = z.real**2 + z.imag**2
    return Spectrogram(
        time=stft.t(a.size, p0=p0, p1=p1), frequency=stft.f, psd=psd, nperseg=nperseg,
        hop=hop, window=window, fs=fs,
    )


def band_energy(spec: Spectrogram, *, center: float, half_width: float) -> np.ndarray:
    r"""Power in ``center +- half_width`` per frame, :math:`E(t_j) = \sum_k S(t_j,f_k)\,\Delta f`.

    Parameters
    ----------
    spec : Spectrogram
        PSD spectrogram (:func:`spectrogram`).
    center : float
        Band centre (Hz).
    half_width : float
        Band half width (Hz), > 0; the band must hold at least one bin.

    Returns
    -------
    ndarray, shape (n_time,)
        Mean-square value in the band for each frame (signal units squared).

    Raises
    ------
    InputError
        If ``half_width`` is not > 0 or the band holds no frequency bin.
    """
    check_positive("half_width", half_width)
    sel = np.abs(spec.frequency - center) <= half_width
    if not sel.any():
        raise InputError(
            "half_width", f"{half_width:g} Hz",
            f"holds no bin around {center:g} Hz (bin width {spec.df:g} Hz)",
        )
    return spec.psd[sel].sum(axis=0) * spec.df


def band_width(
    frequency: np.ndarray,
    power: np.ndarray,
    *,
    center: float,
    half_window: float,
    fraction: float,
) -> float:
    r"""Width :math:`2w` of the narrowest band ``center +- w`` holding ``fraction`` of the power.

    The reference power is the total within ``center +- half_window``. With the bins
    sorted by distance :math:`|f_k - f_c|`, :math:`w` is the distance of the first bin at
    which the cumulative power reaches ``fraction`` of the reference (a symmetric
    occupied-bandwidth measure, cf. the 99 % occupied bandwidth of ITU-R SM.328).

    Parameters
    ----------
    frequency : ndarray
        Bin frequencies (Hz).
    power : ndarray
        Power per bin (any units, e.g. PSD or squared amplitude).
    center, half_window : float
        Band centre and reference half width (Hz).
    fraction : float
        In (0, 1).

    Returns
    -------
    float
        Band width ``2 w`` (Hz).

    Raises
    ------
    InputError
        If ``half_window`` is not > 0, ``fraction`` is not in (0, 1), or the reference band
        holds fewer than two bins.
    """
    check_positive("half_window", half_window)
    if not 0.0 < fraction < 1.0:
        raise InputError("fraction", fraction, "must lie in (0, 1)")
    f = np.asarray(frequency, dtype=np.float64)
    p = np.asarray(power, dtype=np.float64)
    dist = np.abs(f - center)
    sel = dist <= half_window
    if sel.sum() < 2:
        raise InputError(
            "half_window", f"{half_window:g} Hz", f"holds < 2 bins around {center:g} Hz"
        )
    order = np.argsort(dist[sel], kind="stable")
    d_sorted = dist[sel][order]
    cum = np.cumsum(p[sel][order])
    total = cum[-1]
    if total <= 0.0:
        return float("nan")
    i = int(np.searchsorted(cum, fraction * total, side="left"))
    return float(2.0 * d_sorted[min(i, d_sorted.size - 1)])


def modulation_index(series: np.ndarray, times: np.ndarray, *, frequency: float) -> float:
    r"""Relative modulation of a series at one frequency, :math:`|c_f| / \bar e`.

    .. math:: c_f = \frac{2}{J} \sum_j (e_j - \bar e)\, e^{-2\pi i f t_j}

    i.e. the amplitude of the Fourier component of the band-energy series ``e(t_j)`` at
    ``frequency`` (Hz) relative to its mean: 0 for a steady band, about 1 or more when the
    band energy pulses once per revolution (seed Figure 8, time direction).

    Parameters
    ----------
    series : array_like
        Values ``e_j``, e.g. the band energy per frame from :func:`band_energy` (any
        units; the result is relative to their mean).
    times : array_like
        Times ``t_j`` of the values (s), same shape as ``series``, at least two.
    frequency : float
        Frequency ``f`` of the modulation looked for (Hz), > 0, e.g. the shaft frequency
        of the cracked gear.

    Returns
    -------
    float
        :math:`|c_f| / \bar e` (dimensionless); NaN when the mean is not > 0. Exact for a
        sinusoidal modulation sampled evenly over whole periods of ``f``.

    Raises
    ------
    InputError
        If ``frequency`` is not > 0, or ``series`` and ``times`` differ in shape or hold
        fewer than two values.

    Examples
    --------
    A series :math:`1 + 0.5\cos(2\pi f t)` over four whole periods:

    >>> import numpy as np
    >>> t = np.arange(40) * 0.01
    >>> e = 1.0 + 0.5 * np.cos(2 * np.pi * 10.0 * t)
    >>> round(modulation_index(e, t, frequency=10.0), 6)
    0.5
    """
    check_positive("frequency", frequency)
    e = np.asarray(series, dtype=np.float64)
    t = np.asarray(times, dtype=np.float64)
    if e.shape != t.shape or e.size < 2:
        raise InputError("series", e.shape, f"must match times {t.shape} with >= 2 values")
    mean = e.mean()
    if mean <= 0.0:
        return float("nan")
    c = 2.0 / e.size * np.sum((e - mean) * np.exp(-2j * np.pi * frequency * t))
    return float(np.abs(c) / mean)
