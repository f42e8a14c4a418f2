"""All frames of a ``scipy.signal.ShortTimeFFT`` in one FFT call.

``ShortTimeFFT.stft`` transforms its frames one at a time in a Python loop (about
1000 FFT calls for a 100 000-sample record at the speed estimate's hop); :func:`stft`
gives the same values (same windowed frames, same zero padding and phase shift, same
``scipy.fft.rfft`` per frame) from one vectorised call over the stacked frames.
"""

from __future__ import annotations

import numpy as np
import scipy.fft
from numpy.lib.stride_tricks import sliding_window_view

__all__ = ["stft"]


def stft(sft, x: np.ndarray, p0: int, p1: int) -> np.ndarray:
    """``sft.stft(x, p0=p0, p1=p1)`` for a real 1-D ``x``, computed in one FFT call.

    Parameters
    ----------
    sft : scipy.signal.ShortTimeFFT
        The transform (``fft_mode`` ``"onesided"`` or ``"onesided2X"``).
    x : ndarray
        Real 1-D signal.
    p0, p1 : int
        First and one-past-last frame index (``sft.stft`` semantics; frames reaching
        outside the record are zero-padded, ``padding="zeros"``).

    Returns
    -------
    ndarray, shape (sft.f_pts, p1 - p0)
        Complex STFT values, one column per frame.

    Raises
    ------
    ValueError
        For a complex or multi-dimensional ``x`` or another ``fft_mode`` (use
        ``sft.stft``).
    """
    if x.ndim != 1 or np.iscomplexobj(x) or sft.fft_mode not in ("onesided", "onesided2X"):
        raise ValueError("stft: real 1-D x and a one-sided fft_mode only")
    m, hop, mfft = sft.m_num, sft.hop, sft.mfft
    n, n1 = x.size, (p1 - p0) * hop
    k0 = p0 * hop - sft.m_num_mid  # first sample of frame p0 (as ShortTimeFFT._x_slices)
    k1 = k0 + n1 + m
    x1 = np.pad(x[max(k0, 0):min(k1, n)], (-min(k0, 0), max(k1 - n, 0)))
    seg = sliding_window_view(x1, m)[0:n1:hop] * sft.win.conj()
    if sft.phase_shift is not None:  # (ShortTimeFFT keeps mfft >= m)
        # frames zero-padded to mfft, then rolled left by s (ShortTimeFFT._fft_func),
        # written in place: samples s.. first, zeros, samples ..s last
        s = (sft.phase_shift + sft.m_num_mid) % m
        buf = np.zeros((seg.shape[0], mfft), dtype=seg.dtype)
        buf[:, :m - s] = seg[:, s:]
        buf[:, mfft - s:] = seg[:, :s]
        seg = buf
    z = scipy.fft.rfft(seg, n=mfft, axis=-1)
    if sft.fft_mode == "onesided2X":
        fac = np.sqrt(2) if sft.scaling == "psd" else 2
        z[..., 1:-1 if mfft % 2 == 0 else None] *= fac
    return z.T
