"""Real cepstrum, cepstral peak (a period) and cepstral pre-whitening.

The real cepstrum is the inverse Fourier transform of the log amplitude spectrum
(Bogert, Healy & Tukey 1963; Randall 2017). A family of lines spaced ``Delta f`` (the
harmonics of a shaft, or the sidebands of a once-per-revolution modulation around the
mesh harmonics) adds a periodic ripple to the log spectrum and so a peak (a *rahmonic*)
at the quefrency ``1 / Delta f``: :func:`cepstral_peak` finds it.

Cepstral pre-whitening (Sawalhi & Randall 2011; Borghesani et al. 2013) sets the real
cepstrum to zero at every quefrency except zero, i.e. divides the spectrum by its
magnitude and keeps the phase. The result has a flat amplitude spectrum: the discrete
tones of the gears and the resonances of the transfer path are removed, while impulsive
events, whose energy is spread over all frequencies at consistent phase, remain.

The transforms are ``scipy.fft.rfft``/``irfft`` and ``scipy.fft.fft``/``ifft``; SciPy has
no cepstrum routine of its own.

References
----------
.. [BHT63] B. P. Bogert, M. J. R. Healy, J. W. Tukey, "The quefrency alanysis of time
   series for echoes: cepstrum, pseudo-autocovariance, cross-cepstrum and saphe
   cracking", in M. Rosenblatt (ed.), *Proc. Symp. on Time Series Analysis*, Wiley,
   1963, 209-243.
.. [R17] R. B. Randall, "A history of cepstrum analysis and its application to
   mechanical problems", *Mechanical Systems and Signal Processing* 97 (2017) 3-19.
.. [SR11] N. Sawalhi, R. B. Randall, "Signal pre-whitening using cepstrum editing
   (liftering) to enhance fault detection in rolling element bearings", *Proc. 24th Int.
   Congress on Condition Monitoring and Diagnostics Engineering Management (COMADEM
   2011)*, Stavanger, 2011, 330-336.
.. [B13] P. Borghesani, P. Pennacchi, R. B. Randall, N. Sawalhi, R. Ricci, "Application
   of cepstrum pre-whitening for the diagnosis of bearing faults under variable speed
   conditions", *Mechanical Systems and Signal Processing* 36 (2013) 370-384.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import scipy.fft

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs

__all__ = ["CepstralPeak", "FLOOR", "real_cepstrum", "cepstral_peak", "prewhiten"]

#: Relative floor of the amplitude spectrum before the logarithm and the division of the
#: pre-whitening: bins below ``FLOOR * max|X|`` (e.g. exact zeros of a synthetic record)
#: are raised to it (cepstrum) or set to zero (pre-whitening) instead of giving
#: ``log 0`` or ``0 / 0``. 1e-12 is 240 dB below the largest line, below double
#: round-off of any physical record.
FLOOR = 1e-12


class CepstralPeak(NamedTuple):
    """Largest cepstral value in a quefrency range (built by :func:`cepstral_peak`).

    Parameters
    ----------
    quefrency : float
        Quefrency of the peak (s), on the sample grid ``k / fs``: the period of the
        family of lines.
    value : float
        Real cepstrum at the peak (dimensionless, natural-log units).
    index : int
        Sample index ``k`` of the peak.
    """

    quefrency: float
    value: float
    index: int


def real_cepstrum(x: np.ndarray, fs: float) -> tuple[np.ndarray, np.ndarray]:
    r"""Real cepstrum :math:`c(\tau_k) = \mathcal{F}^{-1}\{\ln|X(f)|\}`, ``tau_k = k / fs``.

    The whole record is transformed (no window, no zero padding); amplitudes below
    :data:`FLOOR` times the largest are raised to it before the logarithm. For a real
    record the cepstrum is even, :math:`c(\tau_k) = c(\tau_{N-k})`; the non-negative
    half ``k = 0 .. N//2`` is returned.

    Parameters
    ----------
    x : array_like
        Signal (any units).
    fs : float
        Sampling rate (Hz).

    Returns
    -------
    quefrency : ndarray, shape (N//2 + 1,)
        Quefrencies ``k / fs`` (s).
    c : ndarray, shape (N//2 + 1,)
        Real cepstrum (dimensionless; natural logarithm of the amplitude).

    Raises
    ------
    InputError
        If ``x`` is not a valid signal of at least 4 samples, ``fs`` is not > 0, or
        ``x`` is zero everywhere (no logarithm).

    Examples
    --------
    A signal and its echo of gain ``a`` after ``d`` samples,
    :math:`x_n + a x_{n-d}`, has :math:`\ln|X| = \ln|X_0| + \ln|1 + a e^{-2\pi i f d}|`,
    whose cepstrum holds :math:`a/2` at quefrency ``d`` (the series
    :math:`\ln(1+a z) = a z - a^2 z^2/2 + \dots`, halved by the real part). For a
    (circular) unit impulse with an echo of 0.5 after 10 samples:

    >>> import numpy as np
    >>> x = np.zeros(256); x[0] = 1.0; x[10] = 0.5
    >>> q, c = real_cepstrum(x, 1000.0)
    >>> round(float(q[10]), 3), round(float(c[10]), 6)
    (0.01, 0.25)

    References
    ----------
    Bogert, Healy & Tukey (1963); Randall (2017).
    """
    a = as_signal(x, min_length=4)
    fs = check_fs(fs)
    mag = np.abs(scipy.fft.rfft(a))
    top = float(mag.max())
    if top == 0.0:
        raise InputError("x", "all zeros", "must not vanish everywhere (log of zero spectrum)")
    logmag = np.log(np.maximum(mag, FLOOR * top))
    c = scipy.fft.irfft(logmag, a.size)
    half = a.size // 2 + 1
    return np.arange(half) / fs, c[:half]


def cepstral_peak(
    quefrency: np.ndarray, c: np.ndarray, *, search: tuple[float, float]
) -> CepstralPeak:
    """Largest value of the cepstrum with quefrency in ``search = (lo, hi)`` (s).

    The maximum over the samples ``lo <= tau_k <= hi`` of the (real) cepstrum, on the
    quefrency grid of :func:`real_cepstrum` (resolution ``1 / fs``). The search range
    should hold the expected period (e.g. one shaft revolution) and exclude its
    sub-multiples, whose rahmonics (e.g. of the mesh period) also peak.

    Parameters
    ----------
    quefrency : array_like
        Quefrencies (s), increasing, as returned by :func:`real_cepstrum`.
    c : array_like
        Cepstrum at those quefrencies (same shape).
    search : tuple of float
        ``(lo, hi)`` (s), ``0 <= lo < hi``; must hold at least one quefrency.

    Returns
    -------
    CepstralPeak
        Quefrency (s), value and sample index of the peak.

    Raises
    ------
    InputError
        If the arrays differ in shape or the search range is invalid or holds no sample.

    Examples
    --------
    >>> import numpy as np
    >>> q = np.arange(100) / 1000.0
    >>> c = np.zeros(100); c[40] = 0.3; c[5] = 1.0
    >>> cepstral_peak(q, c, search=(0.02, 0.06))
    CepstralPeak(quefrency=0.04, value=0.3, index=40)

    References
    ----------
    Randall (2017).
    """
    q = np.asarray(quefrency, dtype=np.float64)
    cc = np.asarray(c, dtype=np.float64)
    if q.ndim != 1 or q.shape != cc.shape:
        raise InputError("c", cc.shape, f"must be one-dimensional and match quefrency {q.shape}")
    try:
        lo, hi = (float(s) for s in search)
    except (TypeError, ValueError):
        raise InputError("search", search, "must be a pair (lo, hi) of quefrencies in s") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo < hi):
        raise InputError("search", (lo, hi), "must satisfy 0 <= lo < hi (s)")
    idx = np.flatnonzero((q >= lo) & (q <= hi))
    if idx.size == 0:
        raise InputError("search", (lo, hi), "holds no quefrency of the cepstrum")
    k = int(idx[np.argmax(cc[idx])])
    return CepstralPeak(quefrency=float(q[k]), value=float(cc[k]), index=k)


def prewhiten(x: np.ndarray) -> np.ndarray:
    r"""Cepstral pre-whitening: unit amplitude spectrum, phase kept.

    .. math:: y = \mathcal{F}^{-1}\left\{ \frac{X(f)}{|X(f)|} \right\}
       \cdot \frac{\mathrm{rms}(x)}{\mathrm{rms}(\mathcal{F}^{-1}\{X/|X|\})}

    Setting the real cepstrum to zero at all non-zero quefrencies (the log amplitude to a
    constant) and transforming back with the original phase is exactly this division
    (Sawalhi & Randall 2011; Borghesani et al. 2013). The constant is chosen so
    that ``y`` has the RMS of ``x`` (only a scale; the flat spectrum is what matters).
    Bins with ``|X| <`` :data:`FLOOR` ``* max|X|`` are set to zero.

    Parameters
    ----------
    x : array_like
        Signal (any units).

    Returns
    -------
    ndarray
        Pre-whitened signal, same length and RMS (units) as ``x``.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal of at least 4 samples or is zero everywhere.

    Examples
    --------
    A unit impulse already has a flat spectrum and zero phase: it is unchanged.

    >>> import numpy as np
    >>> x = np.zeros(64); x[5] = 1.0
    >>> bool(np.allclose(prewhiten(x), x))
    True

    References
    ----------
    Sawalhi & Randall (2011); Borghesani et al. (2013).
    """
    a = as_signal(x, min_length=4)
    spec = scipy.fft.rfft(a)
    mag = np.abs(spec)
    top = float(mag.max())
    if top == 0.0:
        raise InputError("x", "all zeros", "must not vanish everywhere (no phase to keep)")
    keep = mag >= FLOOR * top
    unit = np.zeros_like(spec)
    unit[keep] = spec[keep] / mag[keep]
    y = scipy.fft.irfft(unit, a.size)
    ry = float(np.sqrt(np.mean(y * y)))
    rx = float(np.sqrt(np.mean(a * a)))
    return y * (rx / ry) if ry > 0.0 else y
