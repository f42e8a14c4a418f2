r"""Narrow-band amplitude and phase demodulation of a mesh harmonic (McFadden 1986).

A gear's meshing vibration is a carrier at the mesh harmonic :math:`n f_m` (``f_m = Z
f_r``) modulated in amplitude and phase by the load each tooth carries. A cracked tooth
is less stiff during its own mesh period only, so once per revolution it perturbs both
modulations over about one tooth period. McFadden (1986) isolated one mesh harmonic with
its sidebands (the band :math:`n f_m \pm (k + 1/2) f_r`, ``k`` sideband orders), formed
the analytic signal of that band and read

* the amplitude envelope :math:`a(t) = |z(t)|`;
* the phase :math:`\varphi(t) = \arg z(t)` unwrapped, minus the linear carrier phase
  :math:`2\pi n f_m t + \varphi_0`.

Here the band-pass and the Hilbert transform are one step: the DFT of the record is kept
on the positive-frequency bins of the band (times two) and zeroed elsewhere, and the
inverse DFT is :math:`z`. On a time-synchronous average (one revolution, exactly
periodic) this is exact; on a record it is circular, so the first and last few
``1/bandwidth`` seconds are distorted by the wrap-around.

McFadden plotted the phase itself and found the crack as a local step of it; much
later work (e.g. the "FM derivative" of Samuel & Pines 2005) uses its derivative, the
instantaneous-frequency deviation. :meth:`Demodulation.phase_kurtosis` gives the
kurtosis of the phase (default, as McFadden) or, with ``derivative=True``, of its
derivative.

References
----------
.. [M86] P. D. McFadden, "Detecting fatigue cracks in gears by amplitude and phase
   demodulation of the meshing vibration", *J. Vib. Acoust. Stress Reliab. Des.* 108
   (1986) 165-170.
.. [SP05] P. D. Samuel, D. J. Pines, "A review of vibration-based techniques for
   helicopter transmission diagnostics", *J. Sound Vib.* 282 (2005) 475-508, sec. 4.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs, check_int, check_positive
from gearsim.signals.timedomain import kurtosis
from gearsim.signals.tsa import TSA

__all__ = ["Demodulation", "analytic_band", "demodulate", "demodulate_tsa"]

_CARRIERS = ("fit", "center")


@dataclass(frozen=True)
class Demodulation:
    """Amplitude envelope and phase of one narrow band (built by :func:`demodulate`).

    Parameters
    ----------
    time : ndarray
        Sample times ``j / fs`` (s).
    amplitude : ndarray
        Amplitude envelope ``|z|`` (units of the signal).
    phase : ndarray
        Unwrapped phase of ``z`` minus the linear carrier phase and its mean (rad).
    carrier_frequency : float
        Carrier frequency removed from the phase (Hz): fitted or the band centre.
    band : tuple of float
        ``(low, high)`` pass band (Hz).
    fs : float
        Sampling rate (Hz).
    """

    time: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    carrier_frequency: float
    band: tuple[float, float]
    fs: float

    def frequency_deviation(self) -> np.ndarray:
        r"""Instantaneous-frequency deviation :math:`\dot\varphi / 2\pi` (Hz).

        Returns
        -------
        ndarray
            Central differences of the phase (``numpy.gradient``, one-sided at the ends)
            times ``fs / 2 pi``, in Hz.
        """
        return np.gradient(self.phase) * (self.fs / (2.0 * np.pi))

    def amplitude_kurtosis(self) -> float:
        """Pearson kurtosis of the amplitude envelope (dimensionless; 3 for Gaussian).

        Returns
        -------
        float
            :func:`gearsim.signals.timedomain.kurtosis` of :attr:`amplitude`.
        """
        return kurtosis(self.amplitude)

    def phase_kurtosis(self, *, derivative: bool = False) -> float:
        """Pearson kurtosis of the phase, or of its derivative (dimensionless).

        Parameters
        ----------
        derivative : bool, default False
            False: kurtosis of the demodulated phase (McFadden 1986 read the phase);
            True: of the instantaneous-frequency deviation
            (:meth:`frequency_deviation`).

        Returns
        -------
        float
            Kurtosis (3 for a Gaussian phase noise; a local phase step of one tooth
            raises it).
        """
        return kurtosis(self.frequency_deviation() if derivative else self.phase)


def analytic_band(x: np.ndarray, fs: float, *, low: float, high: float) -> np.ndarray:
    r"""Analytic signal of the band ``[low, high]`` by DFT masking.

    :math:`z = \mathrm{IDFT}(2 X_k)` over the bins ``k`` with ``low <= k fs/N <= high``
    (all ``0 < k < N/2``), zero elsewhere: an ideal band-pass and the Hilbert transform
    in one step (as ``scipy.signal.hilbert`` does for the whole band).

    Parameters
    ----------
    x : array_like
        Signal (any units).
    fs : float
        Sampling rate (Hz).
    low, high : float
        Band edges (Hz), ``0 < low < high < fs/2``.

    Returns
    -------
    ndarray of complex
        Analytic signal of the band (units of ``x``); its real part is the band-passed
        record.

    Raises
    ------
    InputError
        If ``x`` or ``fs`` is invalid or the band is not inside ``(0, fs/2)``, or holds no
        DFT bin.

    References
    ----------
    McFadden (1986); Randall (2011), *Vibration-based Condition Monitoring*, sec. 3.3.2.

    Examples
    --------
    A tone in the band comes back as the complex exponential:

    >>> import numpy as np
    >>> t = np.arange(256) / 256.0
    >>> z = analytic_band(np.cos(2 * np.pi * 20 * t), 256.0, low=15.0, high=25.0)
    >>> bool(np.allclose(z, np.exp(2j * np.pi * 20 * t)))
    True
    """
    a = as_signal(x)
    fs = check_fs(fs)
    low, high = float(low), float(high)
    if not (0.0 < low < high < 0.5 * fs):
        raise InputError("band", f"({low:g}, {high:g}) Hz",
                         f"must satisfy 0 < low < high < fs/2 = {0.5 * fs:g} Hz")
    n = a.size
    spec = scipy.fft.fft(a)
    f = np.arange(n) * (fs / n)
    keep = (f >= low) & (f <= high) & (np.arange(n) < (n + 1) // 2) & (np.arange(n) > 0)
    if not keep.any():
        raise InputError("band", f"({low:g}, {high:g}) Hz",
                         f"holds no DFT bin (bin width {fs / n:g} Hz): widen it or use a longer "
                         "record")
    out = np.zeros(n, dtype=complex)
    out[keep] = 2.0 * spec[keep]
    return scipy.fft.ifft(out)


def demodulate(
    x: np.ndarray, fs: float, *, center: float, bandwidth: float, carrier: str = "fit"
) -> Demodulation:
    r"""Amplitude and phase demodulation of the band ``center +- bandwidth/2`` (McFadden 1986).

    For a mesh harmonic ``n f_m`` with ``k`` sideband orders of the shaft at ``f_r``:
    ``center = n f_m``, ``bandwidth = (2k + 1) f_r`` (band edges half-way between
    sidebands).

    Parameters
    ----------
    x : array_like
        Signal (any units): a record, or a time-synchronous average (then ``fs`` is
        ``samples_per_rev * shaft_frequency``; see :func:`demodulate_tsa`).
    fs : float
        Sampling rate (Hz).
    center : float
        Centre of the band (Hz), the carrier ``n f_m``.
    bandwidth : float
        Full width of the band (Hz), > 0; the band must lie inside ``(0, fs/2)``.
    carrier : {"fit", "center"}, default "fit"
        Linear phase removed: ``"fit"`` the least-squares line through the unwrapped
        phase (robust to a slightly wrong ``center`` on a record), ``"center"`` exactly
        ``2 pi center t`` (right for a TSA, where the carrier is exact).

    Returns
    -------
    Demodulation
        Times (s), amplitude envelope (units of ``x``), phase (rad, zero mean), the
        carrier frequency removed (Hz) and the band (Hz).

    Raises
    ------
    InputError
        If ``x`` or ``fs`` is invalid, ``center`` or ``bandwidth`` is not > 0, the band
        leaves ``(0, fs/2)`` or holds no bin, ``carrier`` is unknown, or the band is
        empty of signal (zero amplitude somewhere makes the phase undefined).

    References
    ----------
    McFadden (1986).

    Examples
    --------
    :math:`(1 + 0.2\cos\Omega t)\cos(\omega t + 0.3\sin\Omega t)` gives back the
    modulations (all lines inside the band, the record periodic):

    >>> import numpy as np
    >>> t = np.arange(512) / 512.0
    >>> m = 2 * np.pi * 4 * t
    >>> x = (1 + 0.2 * np.cos(m)) * np.cos(2 * np.pi * 100 * t + 0.3 * np.sin(m))
    >>> d = demodulate(x, 512.0, center=100.0, bandwidth=40.0, carrier="center")
    >>> bool(np.allclose(d.amplitude, 1 + 0.2 * np.cos(m)))
    True
    >>> bool(np.allclose(d.phase, 0.3 * np.sin(m)))
    True
    """
    a = as_signal(x)
    fs = check_fs(fs)
    center = check_positive("center", center)
    bandwidth = check_positive("bandwidth", bandwidth)
    if carrier not in _CARRIERS:
        raise InputError("carrier", carrier, f"must be one of {list(_CARRIERS)}")
    low, high = center - 0.5 * bandwidth, center + 0.5 * bandwidth
    z = analytic_band(a, fs, low=low, high=high)
    amp = np.abs(z)
    scale = float(np.max(np.abs(a - a.mean())))
    if amp.max() <= 1e-9 * scale or not np.all(amp > 1e-12 * amp.max()):
        raise InputError("signal", "no carrier in the band",
                         f"the band ({low:g}, {high:g}) Hz must hold the carrier: the envelope "
                         "vanishes, so the phase is undefined")
    t = np.arange(a.size) / fs
    phi = np.unwrap(np.angle(z))
    if carrier == "fit":
        slope, _ = np.polyfit(t, phi, 1)
        f_c = float(slope / (2.0 * np.pi))
    else:
        f_c = center
    res = phi - 2.0 * np.pi * f_c * t
    res -= res.mean()
    return Demodulation(time=t, amplitude=amp, phase=res, carrier_frequency=f_c,
                        band=(low, high), fs=fs)


def demodulate_tsa(t: TSA, *, teeth: int, harmonic: int = 1, sidebands: int) -> Demodulation:
    r"""McFadden's demodulation of mesh harmonic ``n`` of a time-synchronous average.

    Band: shaft orders ``n Z +- (k + 1/2)`` (``k = sidebands``), i.e. ``center = n Z
    f_r``, ``bandwidth = (2k + 1) f_r`` at the TSA's sampling rate ``M f_r``; the carrier
    phase removed is exactly ``2 pi n Z`` per revolution (``carrier="center"``). Time runs
    over one revolution, ``time[j] = j / (M f_r)``.

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z`` of that gear.
    harmonic : int, default 1
        Mesh harmonic ``n`` demodulated (McFadden used the dominant one).
    sidebands : int
        ``k``, sideband orders kept on each side, ``1 <= k < Z`` (``k`` about ``Z/2``
        keeps all the modulation of one tooth period without the next harmonic's
        sidebands when ``k < Z/2``).

    Returns
    -------
    Demodulation
        Amplitude (units of the TSA) and phase (rad) over one revolution.

    Raises
    ------
    InputError
        If a count is out of range or the band ``(n Z + k + 1/2)`` reaches the Nyquist
        order ``M/2``.

    References
    ----------
    McFadden (1986); McFadden (1987) for the TSA.

    Examples
    --------
    A 20-tooth mesh with a 0.3 rad phase modulation at order 2:

    >>> import numpy as np
    >>> j = np.arange(256) / 256.0
    >>> avg = np.cos(2 * np.pi * 20 * j + 0.3 * np.cos(2 * np.pi * 2 * j))
    >>> d = demodulate_tsa(TSA(avg, 1, 10.0), teeth=20, sidebands=9)
    >>> round(float(d.phase.max()), 3), round(d.carrier_frequency, 6)
    (0.3, 200.0)
    """
    teeth = check_int("teeth", teeth, minimum=1)
    harmonic = check_int("harmonic", harmonic, minimum=1)
    sidebands = check_int("sidebands", sidebands, minimum=1)
    if sidebands >= teeth:
        raise InputError("sidebands", sidebands,
                         f"must be < teeth = {teeth} (the band would hold the next mesh order)")
    m = t.samples_per_rev
    top = harmonic * teeth + sidebands + 0.5
    if top >= 0.5 * m:
        raise InputError("samples_per_rev", m,
                         f"must exceed 2 x {top:g} orders to hold the band of mesh harmonic "
                         f"{harmonic} with {sidebands} sidebands")
    f_r = float(t.shaft_frequency)
    return demodulate(t.average, m * f_r, center=harmonic * teeth * f_r,
                      bandwidth=(2 * sidebands + 1) * f_r, carrier="center")
