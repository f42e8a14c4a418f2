r"""Shaft speed from the signal: tacho pulses, tacholess estimation, given-speed check.

A :class:`SpeedProfile` holds the shaft angle :math:`\theta(t)` [rev] and the
instantaneous shaft frequency :math:`f(t) = d\theta/dt` [Hz] on a time grid. It comes
from one of three sources:

* ``"tacho"`` -- :func:`speed_from_tacho`: the angle is known exactly at each tacho pulse
  (pulse ``i`` at ``i / P`` revolutions for ``P`` equally spaced pulses per revolution)
  and interpolated between pulses by a cubic spline of time against angle, so that a
  run-up is followed within a pulse interval (a linear interpolation, i.e. constant
  speed within each interval, leaves an angle error of :math:`a T^2 / 8` rev for an
  acceleration ``a`` [Hz/s] over an interval ``T``);
* ``"estimate"`` -- :func:`estimate_speed`: tacholess, from a harmonic of known order
  ``q`` of the vibration (``q = Z`` for the mesh tone of a ``Z``-tooth gear on the
  shaft), in two steps (Urbanek, Barszcz & Antoni 2013):

  1. *ridge*: the STFT magnitude of the record (Hann window of ``2 / f_lo`` s, i.e. two
     periods of the slowest searched speed, so that shaft sidebands at ``+-f`` fall
     outside the main lobe) is searched in the band ``[q f_lo, q f_hi]``; the ridge is
     the path through the frames that maximises the summed log-magnitude with a jump
     of at most ``MAX_SLEW x q f_hi`` Hz per second between frames (dynamic
     programming), refined by parabolic interpolation of the log-magnitude;
  2. *phase demodulation*: the analytic signal (Hilbert transform) is shifted down by
     the phase of the ridge (heterodyne), low-pass filtered around zero (zero-phase
     Kaiser-window FIR, the band ``+-bandwidth / 2`` around the ridge) and its phase
     unwrapped (twice, the second time around the phase of the first pass): the
     phase of the harmonic is :math:`\Phi(t) = 2\pi q \theta(t)`, so
     :math:`\theta = \Phi / (2\pi q)` and :math:`f = \dot\Phi / (2\pi q)` (Bonnardot et
     al. 2005; Combet & Gelman 2007; instantaneous frequency of the analytic signal,
     Boashash 1992).

  The origin of an estimated angle is the start of the record: a harmonic of order
  ``q`` fixes the shaft angle only modulo ``1 / q`` revolution. The ridge and the
  demodulation filter need records of many periods; they are for a speed that varies.
* ``"given"`` -- :meth:`SpeedProfile.constant`: a known constant speed.

**Constant speed from short records** (:func:`estimate_constant_speed`): every line
the shaft causes (its harmonics, the mesh harmonics :math:`k Z f_r`, their sidebands
:math:`k Z f_r \pm m f_r`) lies at a multiple of :math:`f_r`. The lines of the whitened
Welch spectrum are sifted through the harmonic comb of every speed of the range
(harmonic sieve, Duifhuis, Willems & Sluyter 1982; harmonic sum, Schroeder 1968; Hermes
1988), each scored by the likelihood ratio (G) of its count of lines against the
Poisson mean of randomly placed lines on its comb: a sub-multiple :math:`f_r / k`
holds the same lines on a denser comb, a multiple or a rational :math:`Z f_r / m` the
mesh lines without the sidebands, so the best score is the shaft speed. Weighted least
squares of line frequency against harmonic number on the whole record's periodogram
refine it (the error falls with the record length and the harmonic number); the
sideband spacing around the strongest mesh line and the power cepstrum's rahmonic at
:math:`1/f_r` check it (Randall 2011, sec. 3.5-3.6); the dominant mesh family
(tooth count) comes with it, labelled an estimate.

:func:`check_given_speed` compares a given constant speed with the speed of the
harmonics of a known order in the data. Computed order tracking and the tracked TSA are
in :mod:`gearsim.signals.ordertrack`.

References
----------
.. [B05] F. Bonnardot, M. El Badaoui, R. B. Randall, J. Danière, F. Guillet, "Use of the
   acceleration signal of a gearbox in order to perform angular resampling (with
   limited speed fluctuation)", *Mech. Syst. Signal Process.* 19 (2005) 766-785.
.. [C07] F. Combet, L. Gelman, "An automated methodology for performing time
   synchronous averaging of a gearbox signal without speed sensor", *Mech. Syst.
   Signal Process.* 21 (2007) 2590-2606.
.. [U13] J. Urbanek, T. Barszcz, J. Antoni, "A two-step procedure for estimation of
   instantaneous rotational speed with large fluctuations", *Mech. Syst. Signal
   Process.* 38 (2013) 96-102.
.. [B92] B. Boashash, "Estimating and interpreting the instantaneous frequency of a
   signal -- Part 1: Fundamentals", *Proc. IEEE* 80 (1992) 520-538.
.. [K74] J. F. Kaiser, "Nonrecursive digital filter design using the I0-sinh window
   function", Proc. IEEE Int. Symp. Circuits and Systems, 1974, 20-23.
.. [M87] P. D. McFadden, "A revised model for the extraction of periodic waveforms by
   time domain averaging", *Mech. Syst. Signal Process.* 1 (1987) 83-95.
.. [dB78] C. de Boor, *A Practical Guide to Splines*, Springer, 1978.
.. [F97] K. R. Fyfe, E. D. S. Munck, "Analysis of computed order tracking", *Mech. Syst.
   Signal Process.* 11 (1997) 187-205.
.. [S68] M. R. Schroeder, *J. Acoust. Soc. Am.* 43 (1968) 829-834 (product spectrum).
.. [D82] H. Duifhuis, L. F. Willems, R. J. Sluyter, *J. Acoust. Soc. Am.* 71 (1982)
   1568-1580 (harmonic sieve).
.. [H88] D. J. Hermes, *J. Acoust. Soc. Am.* 83 (1988) 257-264 (subharmonic summation).
.. [W67] P. D. Welch, *IEEE Trans. Audio Electroacoust.* 15 (1967) 70-73.
.. [R11] R. B. Randall, *Vibration-based Condition Monitoring*, Wiley, 2011.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.fft
from numpy.lib.stride_tricks import sliding_window_view
from scipy.integrate import cumulative_trapezoid
from scipy.interpolate import CubicSpline
from scipy.signal import ShortTimeFFT, find_peaks, firwin, hilbert, kaiserord, oaconvolve, welch
from scipy.signal.windows import hann
from scipy.special import gammainccinv, gammaincinv

from gearsim.errors import InputError
from gearsim.signals._checks import (
    as_signal,
    check_below_nyquist,
    check_fs,
    check_int,
    check_positive,
)
from gearsim.signals._stft import stft as _stft
from gearsim.signals.periodicity import periodogram
from gearsim.signals.tsa import pulse_times

__all__ = [
    "SOURCES",
    "MIN_PULSES",
    "MAX_INTERVAL_RATIO",
    "ROUGH_FACTOR",
    "STFT_PERIODS",
    "MAX_SLEW",
    "DEMOD_PASSES",
    "STOPBAND_DB",
    "GIVEN_SPEED_TOLERANCE",
    "MIN_PERIODS",
    "SEGMENT_PERIODS",
    "MIN_HARMONICS",
    "MAX_ORDER",
    "LINE_FALSE_ALARM",
    "LINE_TOLERANCE",
    "EXPLAINED",
    "TEETH_RANGE",
    "CEPSTRUM_Z",
    "MIN_CONFIDENCE",
    "SpeedProfile",
    "SpeedEstimate",
    "speed_from_tacho",
    "estimate_speed",
    "check_speed_search",
    "estimate_constant_speed",
    "check_given_speed",
]

#: Sources of a speed profile.
SOURCES = ("tacho", "estimate", "given")
#: Fewest tacho pulses accepted: the cubic spline of time against angle needs four
#: knots for its not-a-knot ends.
MIN_PULSES = 4
#: Largest ratio of consecutive tacho pulse intervals. A missing pulse doubles an
#: interval and an extra one splits it (one of the three ratios around it is then
#: < 1/1.5 or > 1.5); a run-up changes the interval by a few per cent per pulse.
MAX_INTERVAL_RATIO = 1.5
#: A rough speed ``f0`` searches ``[f0 / ROUGH_FACTOR, f0 x ROUGH_FACTOR]``.
ROUGH_FACTOR = 1.25
#: STFT window length in periods of the lowest searched shaft speed: the Hann main
#: lobe (+-2 bins) is then +-f_lo wide, so shaft sidebands stay outside it.
STFT_PERIODS = 2.0
#: Largest rate of change of the ridge per second, as a fraction of the top of the
#: searched band (2: the speed may double within half a second).
MAX_SLEW = 2.0
#: Phase-demodulation passes: the first heterodynes by the STFT ridge (off the harmonic
#: by up to about one STFT bin where the speed changes fast), the second by the phase
#: of the first pass, so that the harmonic sits at the centre of the pass band.
DEMOD_PASSES = 2
#: Stopband attenuation [dB] of the demodulation low-pass (Kaiser-window FIR).
STOPBAND_DB = 60.0
#: Relative disagreement above which :func:`check_given_speed` warns (0.2 %): at the
#: mesh order ``Z = 20`` over 100 revolutions it drifts the mesh phase by 4 cycles.
GIVEN_SPEED_TOLERANCE = 0.002
#: Shortest record of a constant-speed search, in periods of the lowest searched speed:
#: the Hann main lobe is +-2 bins, so 8 periods resolve lines half that speed apart (the
#: sidebands of a shaft turning at half the speed).
MIN_PERIODS = 8.0
#: Welch segment length in periods of the lowest searched speed, when the record holds
#: more: lines 1/16 of that speed apart are resolved, and averaging steadies the floor.
SEGMENT_PERIODS = 16.0
#: Harmonics of the top searched speed that must lie below the Nyquist frequency.
MIN_HARMONICS = 3
#: Highest harmonic of a searched speed that is sifted (mesh harmonics 1-3 of gears up
#: to 60 teeth and beyond; it bounds the sieve's work).
MAX_ORDER = 200
#: Probability that noise exceeds the height a line must have above the local noise
#: mean (gamma law of the average of the Welch segments; exponential for a periodogram,
#: where the height is ln(1000) = 6.9): a few false lines per spectrum, placed at random.
LINE_FALSE_ALARM = 1e-3
#: Largest distance of a line from a comb tooth [Welch bins]: the parabolic
#: interpolation of a Hann peak is off by < 0.1 bin, the rest is room for noise.
LINE_TOLERANCE = 0.3
#: Share of the best family's line power the dominant mesh family (the largest tooth
#: count) must hold: every divisor of a tooth count holds as much, plus stray lines
#: (on the SpectraQuest records a line at order 16 holds 7-12 % beside a 32-tooth mesh).
EXPLAINED = 0.8
#: Tooth counts considered for the dominant mesh family (as ``estimate_teeth``).
TEETH_RANGE = (10, 199)
#: Robust z-score of the power cepstrum at ``1 / f_r`` that confirms the speed: the
#: median + 3 x 1.48 MAD of the searched quefrencies is exceeded by 0.13 % of Gaussian noise.
CEPSTRUM_Z = 3.0
#: Confidence below which the analysis tiers do not use a searched speed: half of it
#: is the two cross-checks, so both failing, or a margin under 0.7 Np, fall below.
MIN_CONFIDENCE = 0.5

_HOP_FRACTION = 8  # STFT hop = window / 8
_BLOCK = 256  # STFT frames per block
_ZERO_PAD = 4  # FFT length = 4 x window (finer frequency grid for the ridge)
_FLOOR_BLOCK = 4.0  # noise-floor blocks [multiples of the top searched speed]
_SIDEBANDS = 6  # sidebands per side sifted around the strongest mesh line
_MAX_GRID = 1 << 20  # most speeds on the sieve's grid


@dataclass(frozen=True, eq=False)
class SpeedProfile:
    r"""Shaft angle and instantaneous frequency on a time grid.

    Parameters
    ----------
    time : ndarray, shape (K,)
        Time grid [s], strictly increasing, ``K >= 2``.
    frequency : ndarray, shape (K,)
        Instantaneous shaft frequency [Hz] at ``time``, > 0.
    angle : ndarray, shape (K,)
        Cumulative shaft angle [rev] at ``time``, strictly increasing.
    source : str
        ``"tacho"``, ``"estimate"`` or ``"given"`` (:data:`SOURCES`).
    edge : float
        Duration [s] at each end of the profile affected by the start-up of the
        estimation filter (``"estimate"`` only; 0 otherwise).

    Raises
    ------
    InputError
        If the arrays differ in shape, have fewer than 2 points or non-finite values,
        time or angle do not increase strictly, a frequency is not > 0, the source is
        unknown or ``edge`` is negative.

    References
    ----------
    Fyfe & Munck (1997): the angle-time relation behind computed order tracking.
    """

    time: np.ndarray
    frequency: np.ndarray
    angle: np.ndarray
    source: str
    edge: float = 0.0

    def __post_init__(self) -> None:
        arrays = {}
        for name in ("time", "frequency", "angle"):
            arr = np.array(getattr(self, name), dtype=np.float64)
            if arr.ndim != 1 or arr.size < 2:
                raise InputError(name, arr.shape, "must be a 1-D array of >= 2 values")
            if not np.all(np.isfinite(arr)):
                raise InputError(name, "non-finite", "must be finite")
            arr.setflags(write=False)
            arrays[name] = arr
        if not arrays["time"].size == arrays["frequency"].size == arrays["angle"].size:
            raise InputError("frequency/angle", arrays["frequency"].size,
                             f"must have the length of time ({arrays['time'].size})")
        for name in ("time", "angle"):
            if np.any(np.diff(arrays[name]) <= 0.0):
                raise InputError(name, "not increasing", "must increase strictly")
        if np.any(arrays["frequency"] <= 0.0):
            raise InputError("frequency", float(arrays["frequency"].min()), "must be > 0 Hz")
        if self.source not in SOURCES:
            raise InputError("source", self.source, f"must be one of {SOURCES}")
        edge = float(self.edge)
        if not (math.isfinite(edge) and edge >= 0.0):
            raise InputError("edge", self.edge, "must be a finite duration >= 0 s")
        for name, arr in arrays.items():
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "edge", edge)

    @classmethod
    def constant(cls, shaft_frequency: float, duration: float) -> SpeedProfile:
        """Profile of a known constant speed, angle 0 at ``t = 0`` (source ``"given"``).

        Parameters
        ----------
        shaft_frequency : float
            Shaft frequency [Hz], > 0.
        duration : float
            End of the time grid [s], > 0.

        Returns
        -------
        SpeedProfile
            Two grid points, ``t = 0`` and ``t = duration``.

        Raises
        ------
        InputError
            If a value is not finite and > 0.

        References
        ----------
        McFadden (1987), sec. 2: constant-speed angle ``f t``.
        """
        f = check_positive("shaft_frequency", shaft_frequency)
        d = check_positive("duration", duration)
        return cls(time=np.array([0.0, d]), frequency=np.array([f, f]),
                   angle=np.array([0.0, f * d]), source="given")

    @property
    def mean_frequency(self) -> float:
        """Mean shaft frequency [Hz]: angle travelled over the time span.

        Returns
        -------
        float
            ``(angle[-1] - angle[0]) / (time[-1] - time[0])`` [Hz].

        References
        ----------
        McFadden (1987), sec. 2: mean speed over the averaged revolutions.
        """
        return float((self.angle[-1] - self.angle[0]) / (self.time[-1] - self.time[0]))

    @cached_property
    def _time_of_angle(self) -> CubicSpline:
        return CubicSpline(self.angle, self.time)

    @cached_property
    def _angle_of_time(self) -> CubicSpline:
        return CubicSpline(self.time, self.angle)

    def angle_at(self, times: np.ndarray) -> np.ndarray:
        """Shaft angle [rev] at the given times (cubic spline through the grid).

        Parameters
        ----------
        times : array_like
            Times [s] within ``[time[0], time[-1]]``.

        Returns
        -------
        ndarray
            Angle [rev], shape of ``times``.

        Raises
        ------
        InputError
            If a time lies outside the profile.

        References
        ----------
        C. de Boor, *A Practical Guide to Splines*, Springer, 1978, ch. IV.
        """
        return self._angle_of_time(_inside("times", times, self.time[0], self.time[-1], "s"))

    def times_at(self, angles: np.ndarray) -> np.ndarray:
        """Times [s] at which the shaft reaches the given angles.

        The time is a cubic spline (not-a-knot) of the angle through the grid points,
        exact at the grid (the tacho pulses for a tacho profile). This is the relation
        computed order tracking samples at equal angle steps (Fyfe & Munck 1997).

        Parameters
        ----------
        angles : array_like
            Angles [rev] within ``[angle[0], angle[-1]]``.

        Returns
        -------
        ndarray
            Times [s], shape of ``angles``.

        Raises
        ------
        InputError
            If an angle lies outside the profile.

        References
        ----------
        Fyfe & Munck (1997); de Boor (1978), ch. IV.
        """
        return self._time_of_angle(_inside("angles", angles, self.angle[0], self.angle[-1], "rev"))

    def frequency_at(self, times: np.ndarray) -> np.ndarray:
        """Instantaneous shaft frequency [Hz] at the given times (linear interpolation).

        Parameters
        ----------
        times : array_like
            Times [s] within ``[time[0], time[-1]]``.

        Returns
        -------
        ndarray
            Frequency [Hz], shape of ``times``.

        Raises
        ------
        InputError
            If a time lies outside the profile.

        References
        ----------
        Boashash (1992): instantaneous frequency as the derivative of the phase.
        """
        t = _inside("times", times, self.time[0], self.time[-1], "s")
        return np.interp(t, self.time, self.frequency)

    def revolution_times(self) -> np.ndarray:
        """Times [s] at which the angle passes a whole number of revolutions.

        Returns
        -------
        ndarray
            Times of the angles ``k = ceil(angle[0]) .. floor(angle[-1])`` (one per
            revolution; usable as ``pulses`` with ``pulses_per_rev = 1`` in
            :func:`gearsim.signals.tsa.tsa`).

        References
        ----------
        McFadden (1987), sec. 2: once-per-revolution reference.
        """
        k0 = math.ceil(self.angle[0] - 1e-9)
        k1 = math.floor(self.angle[-1] + 1e-9)
        ks = np.arange(k0, k1 + 1, dtype=np.float64)
        ks = np.clip(ks, self.angle[0], self.angle[-1])
        return self._time_of_angle(ks)


def _inside(name: str, values: np.ndarray, lo: float, hi: float, unit: str) -> np.ndarray:
    """``values`` as a float array, refused unless within ``[lo, hi]`` (with round-off slack)."""
    v = np.asarray(values, dtype=np.float64)
    slack = 1e-9 * max(abs(lo), abs(hi), 1.0)
    if v.size and (v.min() < lo - slack or v.max() > hi + slack):
        raise InputError(name, f"[{v.min():g}, {v.max():g}] {unit}",
                         f"must lie within the profile [{lo:g}, {hi:g}] {unit}")
    return v


def speed_from_tacho(
    tacho: np.ndarray,
    fs: float,
    *,
    pulses_per_rev: int = 1,
    threshold: float | None = None,
) -> SpeedProfile:
    r"""Speed profile from a tacho signal with any number of pulses per revolution.

    The rising edges are found by :func:`gearsim.signals.tsa.pulse_times` (linear
    interpolation of the threshold crossing). Pulse ``i`` is at angle ``i / P`` rev
    (equally spaced pulses, the first at angle 0); the time is a cubic spline of the
    angle through the pulses and the frequency at each pulse is
    :math:`1 / (dt/d\theta)` of that spline.

    Parameters
    ----------
    tacho : array_like
        Tacho signal (any units), sampled with the vibration.
    fs : float
        Sampling rate [Hz].
    pulses_per_rev : int
        Pulses per shaft revolution ``P`` (>= 1).
    threshold : float or None
        Crossing level (tacho units); ``None``: the midpoint of the tacho's range.

    Returns
    -------
    SpeedProfile
        Time grid = pulse times [s], angle [rev], frequency [Hz], source ``"tacho"``.

    Raises
    ------
    InputError
        Naming ``tacho`` if it is empty, not finite, constant, has fewer than
        ``max(MIN_PULSES, P + 1)`` pulses (too sparse), or irregular pulse intervals
        (consecutive intervals differing by more than :data:`MAX_INTERVAL_RATIO`:
        missing or extra pulses, wrong threshold); naming ``fs``, ``pulses_per_rev``
        or ``threshold`` if those are out of range.

    References
    ----------
    McFadden (1987), sec. 2; Fyfe & Munck (1997): angle from tacho pulses and
    interpolation of the pulse times.

    Examples
    --------
    >>> import numpy as np
    >>> fs = 1000.0
    >>> t = np.arange(2000) / fs
    >>> p = speed_from_tacho(np.sin(2 * np.pi * 5.0 * t), fs)
    >>> round(p.mean_frequency, 6), p.source
    (5.0, 'tacho')
    """
    a = as_signal(tacho, name="tacho")
    fs = check_fs(fs)
    ppr = check_int("pulses_per_rev", pulses_per_rev, minimum=1)
    p = pulse_times(a, fs, threshold=threshold)
    need = max(MIN_PULSES, ppr + 1)
    if p.size < need:
        raise InputError(
            "tacho", f"{p.size} pulses",
            f"too sparse: must hold at least {need} pulses (one revolution of "
            f"{ppr} pulses and {MIN_PULSES} for the angle spline)",
        )
    d = np.diff(p)
    ratio = d[1:] / d[:-1]
    bad = np.flatnonzero((ratio > MAX_INTERVAL_RATIO) | (ratio < 1.0 / MAX_INTERVAL_RATIO))
    if bad.size:
        i = int(bad[0]) + 1
        raise InputError(
            "tacho", f"pulse interval {d[i]:.4g} s after {d[i - 1]:.4g} s at t = {p[i]:.4g} s",
            f"irregular: consecutive pulse intervals must differ by less than a factor "
            f"{MAX_INTERVAL_RATIO:g} (missing or extra pulses? check threshold and "
            "pulses_per_rev)",
        )
    angle = np.arange(p.size) / ppr
    dt_dtheta = CubicSpline(angle, p)(angle, 1)
    if np.any(dt_dtheta <= 0.0):
        raise InputError("tacho", "non-monotonic angle", "the pulse spline must increase "
                         "(pulse intervals change too fast)")
    return SpeedProfile(time=p, frequency=1.0 / dt_dtheta, angle=angle, source="tacho")


def _search_band(rough: float | None, search: tuple[float, float] | None) -> tuple[float, float]:
    if (rough is None) == (search is None):
        raise InputError("rough/search", "both" if rough is not None else "neither",
                         "give exactly one of a rough speed or a search range")
    if rough is not None:
        f0 = check_positive("rough", rough)
        return f0 / ROUGH_FACTOR, f0 * ROUGH_FACTOR
    try:
        lo, hi = (float(v) for v in search)  # type: ignore[union-attr]
    except (TypeError, ValueError):
        raise InputError("search", search, "must be a pair (lo, hi) of speeds in Hz") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi):
        raise InputError("search", search, "must satisfy 0 < lo < hi (Hz)")
    return lo, hi


def _ridge(a: np.ndarray, fs: float, f_lo: float, f_hi: float,
           window_s: float) -> tuple[np.ndarray, np.ndarray, float]:
    """STFT ridge in ``[f_lo, f_hi]`` [Hz]: frame times [s], ridge frequencies [Hz] and the
    median over frames of the ridge's power over the band's median power [-]."""
    nperseg = max(16, int(round(window_s * fs)))
    hop = max(1, nperseg // _HOP_FRACTION)
    mfft = scipy.fft.next_fast_len(_ZERO_PAD * nperseg)
    stft = ShortTimeFFT(hann(nperseg, sym=False), hop, fs, mfft=mfft, scale_to="magnitude")
    f = stft.f
    band = np.flatnonzero((f >= f_lo) & (f <= f_hi))
    # frames whose centre lies inside the record
    p_all = np.arange(stft.p_min, stft.p_max(a.size))
    centres = p_all * hop / fs
    p_in = p_all[(centres >= 0.0) & (centres <= (a.size - 1) / fs)]
    if band.size < 3 or p_in.size < 1:
        raise InputError("search", f"[{f_lo:g}, {f_hi:g}] Hz at the harmonic",
                         "too narrow for the STFT (needs >= 3 frequency bins)")
    lo_i = max(int(band[0]) - 1, 0)
    hi_i = min(int(band[-1]) + 1, f.size - 1)
    # only the rows of the band are kept, computed in blocks of frames (memory)
    blocks = [
        np.abs(_stft(stft, a, int(b0), int(min(b0 + _BLOCK, p_in[-1] + 1))))[lo_i:hi_i + 1]
        for b0 in range(int(p_in[0]), int(p_in[-1]) + 1, _BLOCK)
    ]
    mag = np.concatenate(blocks, axis=1)
    t_frames = p_in * hop / fs
    logm = np.log(mag + 1e-300 + 1e-12 * mag.max())
    sel = slice(band[0] - lo_i, band[-1] - lo_i + 1)
    score_map = logm[sel]  # (bins in band, frames)
    nb, nf = score_map.shape
    df = f[1] - f[0]
    jump = max(1, math.ceil(MAX_SLEW * f_hi * (hop / fs) / df))
    score = score_map[:, 0].copy()
    back = np.zeros((nb, nf), dtype=np.int64)
    rows = np.arange(nb)
    for k in range(1, nf):
        win = sliding_window_view(np.pad(score, jump, constant_values=-np.inf), 2 * jump + 1)
        arg = win.argmax(axis=1)
        back[:, k] = rows + arg - jump
        score = win[rows, arg] + score_map[:, k]
    path = np.empty(nf, dtype=np.int64)
    path[-1] = int(np.argmax(score))
    for k in range(nf - 1, 0, -1):
        path[k - 1] = back[path[k], k]
    # parabolic interpolation on the log-magnitude (indices into logm)
    i = path + sel.start
    cols = np.arange(nf)
    y0 = logm[np.clip(i - 1, 0, logm.shape[0] - 1), cols]
    y1 = logm[i, cols]
    y2 = logm[np.clip(i + 1, 0, logm.shape[0] - 1), cols]
    den = y0 - 2.0 * y1 + y2
    with np.errstate(invalid="ignore", divide="ignore"):
        delta = np.where(den < 0.0, 0.5 * (y0 - y2) / den, 0.0)
    delta = np.clip(delta, -0.5, 0.5)
    band_mag = mag[sel]
    snr = float(np.median((band_mag[path, cols] / np.median(band_mag, axis=0)) ** 2))
    return t_frames, f[lo_i + i] + delta * df, snr


def tracking_samples(fs: float, bandwidth: float) -> int:
    """Shortest record :func:`estimate_speed` tracks with ``bandwidth`` [samples].

    Parameters
    ----------
    fs : float
        Sampling rate [Hz].
    bandwidth : float
        Full width of the demodulation band [Hz] (:func:`estimate_speed`).

    Returns
    -------
    int
        Twice the length of the demodulation low-pass (Kaiser FIR, -6 dB at
        ``bandwidth / 2``, :data:`STOPBAND_DB` stopband).
    """
    return 2 * _lowpass(0.5 * bandwidth, fs).size


def _lowpass(cutoff: float, fs: float) -> np.ndarray:
    """Odd-length Kaiser-window FIR low-pass, -6 dB at ``cutoff``, transition ``cutoff``."""
    numtaps, beta = kaiserord(STOPBAND_DB, cutoff / (0.5 * fs))
    numtaps |= 1
    return firwin(numtaps, cutoff, window=("kaiser", beta), fs=fs)


def estimate_speed(
    x: np.ndarray,
    fs: float,
    *,
    order: float,
    rough: float | None = None,
    search: tuple[float, float] | None = None,
    bandwidth: float | None = None,
    min_ridge_snr: float | None = None,
) -> SpeedProfile:
    r"""Tacholess instantaneous shaft speed from a harmonic of known order.

    Two steps (module docstring; Urbanek et al. 2013): the STFT ridge of the harmonic
    in the band ``[q f_lo, q f_hi]``, then phase demodulation of the band
    ``+-bandwidth / 2`` tracked around that ridge: heterodyne of the analytic signal by
    the ridge phase, zero-phase Kaiser FIR low-pass (-6 dB at ``bandwidth / 2``,
    transition as wide, :data:`STOPBAND_DB` stopband), unwrapped phase
    :math:`\Phi = 2 \pi q \theta`. The ridge frequency is smoothed by the same
    low-pass before it is integrated into the reference phase (parts of the reference
    above the pass band would pass unchanged into the estimate), and a second pass
    (:data:`DEMOD_PASSES`) heterodynes by the phase of the first, so that the harmonic
    sits at the centre of the pass band. The derivative of :math:`\Phi` gives the
    frequency on the sample grid. The filter's half length (``edge``) at each end of the record is less
    reliable.

    Parameters
    ----------
    x : array_like
        Vibration record (any units).
    fs : float
        Sampling rate [Hz].
    order : float
        Order ``q`` of the tracked harmonic with respect to the shaft (the tooth count
        ``Z`` of a gear on the shaft for its mesh tone, 1 for the shaft tone), > 0.
    rough : float, optional
        Rough shaft speed ``f0`` [Hz]; searches ``[f0 / 1.25, 1.25 f0]``
        (:data:`ROUGH_FACTOR`).
    search : tuple of float, optional
        Shaft speed range ``(f_lo, f_hi)`` [Hz] covering the whole record. Give exactly
        one of ``rough`` and ``search``.
    bandwidth : float, optional
        Full width [Hz] of the band kept around the harmonic; default ``f_lo`` (shaft
        sidebands at ``+-f >= +-f_lo`` then fall in the stopband, which starts at
        ``0.75 bandwidth``). It must hold the harmonic's frequency modulation left
        around the ridge; a narrower band lowers the noise but lengthens the filter
        (``edge`` grows as ``1 / bandwidth``), a wider one shortens it but lets
        neighbours in.
    min_ridge_snr : float, optional
        Least median, over the STFT frames, of the ridge's power over the median power
        of the searched band [-]: below it the harmonic is refused as noise (white noise
        alone gives about 5 in a band of 257 bins). Default: not checked.

    Returns
    -------
    SpeedProfile
        On the sample grid ``k / fs`` [s]: frequency [Hz], angle [rev] from 0 at
        ``t = 0``, source ``"estimate"``, ``edge`` = half the filter length [s].

    Raises
    ------
    InputError
        If ``x``, ``fs``, ``order``, ``rough``, ``search``, ``bandwidth`` or
        ``min_ridge_snr`` is out of
        range (``q f_hi`` must lie below Nyquist, the band must stay above 0 Hz), the
        record is shorter than twice the demodulation filter, or the harmonic is too
        weak to track (its demodulated phase does not increase).

    Notes
    -----
    The ridge follows the strongest continuous path in the searched band. When the
    range is wider than a factor 2 (a run-up), other harmonics of the same tone
    (orders ``q / 2``, ``2 q``, ...) can lie in the band at the same time; the tracked
    harmonic must then be the strongest of them (usually the first mesh harmonic), or
    the ridge may move to a stronger one. A search range narrower than a factor 2
    (``rough``) cannot hold two harmonics of one tone.

    References
    ----------
    Bonnardot, El Badaoui, Randall, Danière & Guillet (2005), *MSSP* 19:766-785
    (angular resampling from the phase of a gear harmonic); Combet & Gelman (2007),
    *MSSP* 21:2590-2606 (phase demodulation of the mesh harmonic); Urbanek, Barszcz &
    Antoni (2013), *MSSP* 38:96-102 (STFT ridge, then phase demodulation); Boashash
    (1992), *Proc. IEEE* 80:520-538 (instantaneous frequency); Kaiser (1974).

    Examples
    --------
    >>> import numpy as np
    >>> fs = 5000.0
    >>> t = np.arange(int(3 * fs)) / fs
    >>> x = np.cos(2 * np.pi * 20 * (12.0 * t + 0.5 * t**2))  # 12 -> 15 Hz, 20 teeth
    >>> p = estimate_speed(x, fs, order=20, search=(10.0, 18.0))
    >>> mid = p.time.size // 2
    >>> round(float(p.frequency[mid]), 3)  # true 12 + 1.5 = 13.5 Hz
    13.5
    """
    a = as_signal(x, name="x", min_length=16)
    fs = check_fs(fs)
    q = check_positive("order", order)
    lo, hi = _search_band(rough, search)
    check_below_nyquist(fs, q * hi, f"harmonic order {q:g} at the top of the search range")
    bw = lo if bandwidth is None else check_positive("bandwidth", bandwidth)
    if min_ridge_snr is not None:
        min_ridge_snr = check_positive("min_ridge_snr", min_ridge_snr)
    if not 0.75 * bw < q * lo:
        raise InputError("bandwidth", bw, f"must be < {q * lo / 0.75:g} Hz so that the band "
                         f"stays above 0 Hz (harmonic at >= {q * lo:g} Hz)")
    taps = _lowpass(0.5 * bw, fs)
    if a.size < 2 * taps.size:  # tracking_samples
        raise InputError(
            "x.length", f"{a.size} samples ({a.size / fs:.4g} s)",
            f"must be >= {2 * taps.size} samples ({2 * taps.size / fs:.4g} s), twice the "
            f"demodulation filter for bandwidth {bw:g} Hz (a wider bandwidth shortens it)",
        )
    t_frames, f_frames, snr = _ridge(a, fs, q * lo, q * hi, STFT_PERIODS / lo)
    if min_ridge_snr is not None and not snr >= min_ridge_snr:
        got, need = (10.0 * math.log10(max(v, 1e-30)) for v in (snr, min_ridge_snr))
        raise InputError("x", f"ridge of order {q:g} {got:.3g} dB over the band's median",
                         f"must stand {need:.3g} dB over it to be tracked: the harmonic does "
                         "not stand out of the noise")
    t = np.arange(a.size) / fs
    # the reference must be smooth: components of its phase above the pass band would
    # pass unchanged into the estimate (estimate = LP(true phase) + HP(reference phase))
    half = taps.size // 2
    f_ridge = oaconvolve(np.pad(np.interp(t, t_frames, f_frames), half, mode="edge"), taps,
                         mode="valid")
    phi_ridge = 2.0 * np.pi * cumulative_trapezoid(f_ridge, dx=1.0 / fs, initial=0.0)
    analytic = hilbert(a)
    phase = phi_ridge
    for _ in range(DEMOD_PASSES):
        z = oaconvolve(analytic * np.exp(-1j * phase), taps, mode="same")
        phase = phase + np.unwrap(np.angle(z))
    if np.any(np.diff(phase) <= 0.0):
        k = int(np.flatnonzero(np.diff(phase) <= 0.0)[0])
        raise InputError(
            "x", f"phase of order {q:g} decreasing at t = {t[k]:.4g} s",
            "the harmonic is too weak to track there (check order, search range and "
            "bandwidth)",
        )
    freq = np.gradient(phase, 1.0 / fs) / (2.0 * np.pi * q)
    angle = (phase - phase[0]) / (2.0 * np.pi * q)
    return SpeedProfile(time=t, frequency=freq, angle=angle, source="estimate",
                        edge=(taps.size // 2) / fs)


@dataclass(frozen=True)
class SpeedEstimate:
    """Constant shaft speed from the record's lines (built by :func:`estimate_constant_speed`).

    Parameters
    ----------
    frequency : float
        Shaft frequency [Hz].
    confidence : float
        Figure of merit in [0, 1], not a probability: ``(1 - exp(-margin)) (2 + n) / 4``,
        ``n`` the checks that agree (sidebands, cepstrum), halved when ``|drift|`` exceeds
        :data:`GIVEN_SPEED_TOLERANCE` (the speed is not constant).
    margin : float
        G statistic [Np] of this speed's comb beyond that of the best speed of the range
        that is neither a multiple nor a sub-multiple of it.
    lines : int
        Lines of the record's periodogram in the final fit.
    order : int
        Harmonic number of the strongest line.
    teeth : int or None
        Dominant mesh family: the largest ``Z`` in :data:`TEETH_RANGE` whose multiples
        hold :data:`EXPLAINED` of the line power of the best ``Z`` (None: no such line).
    teeth_confidence : float
        ``1 - P' / P``: ``P`` that family's line power, ``P'`` the largest power of a
        family neither a multiple nor a divisor of it on lines outside it.
    sideband_spacing : float
        Spacing [Hz] of the lines around the family's strongest line (NaN if none).
    sidebands_agree : bool
        The spacing is a multiple of ``frequency``.
    cepstrum_z : float
        Robust z-score of the cepstrum at ``1 / frequency`` among the searched
        quefrencies (agrees from :data:`CEPSTRUM_Z`).
    drift : float
        ``(f_2 - f_1) / frequency`` of fresh estimates on the first and the last piece
        of ``2 MIN_PERIODS`` periods of ``lo`` (NaN for shorter records or unsure pieces).
    search : tuple of float
        The searched range ``(lo, hi)`` [Hz].
    estimate : bool
        Always True: the value is inferred from the signal.
    """

    frequency: float
    confidence: float
    margin: float
    lines: int
    order: int
    teeth: int | None
    teeth_confidence: float
    sideband_spacing: float
    sidebands_agree: bool
    cepstrum_z: float
    drift: float
    search: tuple[float, float]
    estimate: bool = True

    def to_dict(self) -> dict:
        """JSON-ready dict (NaN as None).

        Returns
        -------
        dict
            Field name to value.
        """
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                for k, v in self.__dict__.items()} | {"search": list(self.search)}


def check_speed_search(n_samples: int, fs: float | None, search: tuple[float, float], *,
                       name: str = "search") -> tuple[float, float]:
    """Refuse, before any work, a constant-speed search the record cannot resolve.

    Parameters
    ----------
    n_samples : int
        Record length [samples].
    fs : float or None
        Sampling rate [Hz]; None checks the range alone.
    search : tuple of float
        Shaft speed range ``(lo, hi)`` [Hz].
    name : str
        Parameter name used in the error (e.g. ``"speed_search"``).

    Returns
    -------
    tuple of float
        ``(lo, hi)`` [Hz].

    Raises
    ------
    InputError
        If not ``0 < lo < hi``, :data:`MIN_HARMONICS` harmonics of ``hi`` pass Nyquist,
        or the record is shorter than :data:`MIN_PERIODS` periods of ``lo``, naming the
        range or the length that would work.

    References
    ----------
    Harris (1978), *Proc. IEEE* 66:51-83: the Hann main lobe (+-2 bins) sets the
    resolution of neighbouring lines.
    """
    try:
        lo, hi = _search_band(None, search)
    except InputError as exc:
        raise InputError(name, exc.value, exc.limit) from None
    if fs is None:
        return lo, hi
    fs = check_fs(fs)
    top = 0.5 * fs / MIN_HARMONICS
    if hi >= top:
        raise InputError(name, f"{lo:g}-{hi:g} Hz", f"must end below {top:.4g} Hz ({MIN_HARMONICS} "
                         f"harmonics of the top speed below the Nyquist frequency of fs = {fs:g} Hz)")
    need = math.ceil(MIN_PERIODS * fs / lo)
    if n_samples < need:
        raise InputError(
            name, f"{lo:g}-{hi:g} Hz on a record of {n_samples} samples ({n_samples / fs:.4g} s)",
            f"speeds down to {lo:g} Hz need >= {need} samples ({need / fs:.4g} s, "
            f"{MIN_PERIODS:g} periods): search above {MIN_PERIODS * fs / n_samples:.4g} Hz "
            "or give a longer record")
    return lo, hi


def _whiten(power: np.ndarray, df: float, width: float, k: int = 1) -> np.ndarray:
    """Power over the local noise mean: medians of ``width`` Hz blocks (interpolated)
    divided by the median of the mean-1 gamma law of an average of ``k`` periodograms."""
    b = min(max(16, int(width / df)), power.size)
    nb = power.size // b
    med = np.median(power[: nb * b].reshape(nb, b), axis=1) / (gammaincinv(k, 0.5) / k)
    floor = np.interp(np.arange(power.size), (np.arange(nb) + 0.5) * b, med)
    return np.maximum(power, 1e-300) / np.maximum(floor, 1e-300)


def _lines(pw: np.ndarray, df: float, f_top: float, k: int = 1):
    """Peaks of the whitened spectrum ``pw`` (average of ``k``) below ``f_top`` that noise
    exceeds with probability :data:`LINE_FALSE_ALARM`: frequencies [Hz] (parabolic
    interpolation of the log), whitened powers and weights ``min(1, ln(power / threshold))``
    (the false lines of noise lie just above the threshold)."""
    thr = gammainccinv(k, LINE_FALSE_ALARM) / k
    idx = find_peaks(pw[: int(f_top / df)], height=thr)[0]
    y0, y1, y2 = np.log(pw[idx - 1]), np.log(pw[idx]), np.log(pw[idx + 1])
    den = y0 - 2.0 * y1 + y2
    d = np.clip(np.where(den < 0.0, 0.5 * (y0 - y2) / np.where(den < 0.0, den, -1.0), 0.0),
                -0.5, 0.5)
    return (idx + d) * df, pw[idx], np.minimum(1.0, y1 - math.log(thr))


def _sieve(nu: np.ndarray, w: np.ndarray, lo: float, hi: float,
           tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Speeds on a grid over [lo, hi] and their score: the likelihood-ratio (G) statistic
    ``c ln(c / m) - (c - m)`` of the (weighted) count ``c`` of lines within ``tol`` of
    harmonics 1..MAX_ORDER against the Poisson mean ``m = 2 tol N / f`` that chance puts
    on the comb (``N`` the weighted count of the lines within its reach). Interval sums
    on a difference array; the work is bounded by MAX_ORDER per line."""
    order = np.argsort(nu)
    nu, w = nu[order], w[order]
    step = max(tol * lo / (2.0 * nu[-1]), (hi - lo) / _MAX_GRID)
    m = int((hi - lo) / step) + 1
    h0 = np.maximum(np.ceil((nu - tol) / hi), 1).astype(np.int64)
    h1 = np.minimum(np.floor((nu + tol) / lo).astype(np.int64), MAX_ORDER)
    cnt = np.maximum(h1 - h0 + 1, 0)
    li = np.repeat(np.arange(nu.size), cnt)
    h = np.repeat(h0, cnt) + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    a = np.clip(np.floor(((nu[li] - tol) / h - lo) / step + 0.5), 0, m).astype(np.int64)
    b = np.clip(np.floor(((nu[li] + tol) / h - lo) / step + 0.5) + 1, 0, m).astype(np.int64)
    grid = lo + step * np.arange(m)
    c = np.cumsum(np.bincount(a, w[li], m + 1) - np.bincount(b, w[li], m + 1))[:-1]
    reach = np.searchsorted(nu, MAX_ORDER * grid + tol, side="right")
    mean = 2.0 * tol * np.r_[0.0, np.cumsum(w)][reach] / grid
    with np.errstate(divide="ignore", invalid="ignore"):
        g = c * np.log(np.maximum(c, mean) / mean) - (c - mean)
    return grid, np.where(c > mean, g, 0.0)


def _peaks(score: np.ndarray) -> tuple[int, np.ndarray]:
    """Index of the best score and of every local maximum (plateaus at their centre)."""
    pk = find_peaks(np.r_[-np.inf, score, -np.inf])[0] - 1
    return int(pk[np.argmax(score[pk])]), pk


def _fit(nu: np.ndarray, w: np.ndarray, f: float, half,
         keep: np.ndarray | None = None) -> tuple[float, np.ndarray]:
    """Weighted least squares of ``nu = h f`` over the strongest line within ``half(h)``
    of each harmonic ``h`` (of those in ``keep``): the speed [Hz] and harmonics used."""
    h = np.rint(nu / f)
    ok = (h >= 1) & (np.abs(nu - h * f) <= half(h))
    idx = np.flatnonzero(ok if keep is None else ok & np.isin(h, keep))
    idx = idx[np.argsort(-w[idx], kind="stable")]
    idx = idx[np.unique(h[idx], return_index=True)[1]]
    if idx.size == 0:
        return f, idx
    hh, ww = h[idx], w[idx]
    return float(np.sum(ww * hh * nu[idx]) / np.sum(ww * hh * hh)), hh


def _record_lines(a: np.ndarray, fs: float, width: float, f_top: float):
    """Lines (frequency [Hz], whitened power) of a record's periodogram, and its bin [Hz]."""
    df = fs / a.size
    return *_lines(_whiten(periodogram(a), df, width), df, f_top)[:2], df


def estimate_constant_speed(x: np.ndarray, fs: float, *,
                            search: tuple[float, float]) -> SpeedEstimate:
    r"""Constant shaft speed in a range from the record's lines: harmonic sieve, refined.

    Method in the module docstring. Lines: peaks of the Welch spectrum (Hann segments of
    :data:`SEGMENT_PERIODS` periods of ``lo``) over the local median, which noise exceeds
    with probability :data:`LINE_FALSE_ALARM` (a line counts ``min(1, ln(height /
    threshold))``: false lines barely pass). Sieve tolerance :data:`LINE_TOLERANCE`
    bins; least squares first on the Welch lines, then twice on the same harmonics in
    the record's periodogram. Checks: the spacing of the lines around the strongest line
    of the dominant family, sifted the same way, is a multiple of the speed; the
    cepstrum of the whitened Welch spectrum at ``1 / f_r`` reaches :data:`CEPSTRUM_Z`.

    Parameters
    ----------
    x : array_like
        Vibration record (any units), at least :data:`MIN_PERIODS` periods of ``lo``.
    fs : float
        Sampling rate [Hz].
    search : tuple of float
        Shaft speed range ``(lo, hi)`` [Hz]; :data:`MIN_HARMONICS` harmonics of ``hi``
        must lie below Nyquist. A range holding two shafts' speeds returns the one whose
        comb explains more lines (with a low confidence when they are close).

    Returns
    -------
    SpeedEstimate
        Speed [Hz], confidence, dominant mesh family (``teeth``), checks, ``drift``;
        ``estimate=True``.

    Raises
    ------
    InputError
        If ``x``, ``fs`` or ``search`` is invalid or unresolvable
        (:func:`check_speed_search`), or no line of the spectrum lies at a harmonic of
        a speed in the range.

    References
    ----------
    Schroeder (1968), *JASA* 43:829-834 (harmonic product/sum spectrum); Duifhuis,
    Willems & Sluyter (1982), *JASA* 71:1568-1580 (harmonic sieve); Hermes (1988), *JASA*
    83:257-264 (subharmonic summation); Welch (1967); Randall (2011), sec. 3.5-3.6
    (cepstrum and sideband spacing of gear signals).

    Examples
    --------
    >>> import numpy as np
    >>> fs, f_r = 8000.0, 24.3
    >>> t = np.arange(int(fs)) / fs  # 1 s, a 31-tooth mesh modulated by its shaft
    >>> x = (1 + 0.3 * np.cos(2 * np.pi * f_r * t)) * np.cos(2 * np.pi * 31 * f_r * t)
    >>> x += np.random.default_rng(0).normal(size=t.size)
    >>> est = estimate_constant_speed(x, fs, search=(15.0, 40.0))
    >>> round(est.frequency, 2), est.teeth, est.estimate
    (24.3, 31, True)
    """
    a = as_signal(x, name="x", min_length=16)
    lo, hi = check_speed_search(a.size, fs, search)
    fs = float(fs)
    a = a - a.mean()
    f_top, width = min(0.5 * fs, MAX_ORDER * hi), _FLOOR_BLOCK * hi
    nper = min(a.size, round(SEGMENT_PERIODS * fs / lo))
    fw, pw = welch(a, fs, window="hann", nperseg=nper)
    dfw, k_avg = float(fw[1]), a.size // nper
    pw = _whiten(pw, dfw, width, k_avg)
    nu, p, wt = _lines(pw, dfw, f_top, k_avg)
    tol = LINE_TOLERANCE * dfw
    if nu.size == 0:
        raise InputError("x", "no spectral line", f"no line stands out of the noise below "
                         f"{f_top:g} Hz: no speed to estimate")
    grid, score = _sieve(nu, wt, lo, hi, tol)
    best, pk = _peaks(score)
    f0 = float(grid[best])
    g = grid[pk]
    k1, k2 = np.maximum(np.rint(g / f0), 1), np.maximum(np.rint(f0 / g), 1)
    unrelated = (np.abs(g - k1 * f0) > 2 * tol) & (np.abs(g - f0 / k2) > 2 * tol)
    margin = float(score[best] - (score[pk][unrelated].max() if unrelated.any() else 0.0))
    # refinement: Welch lines on the comb (twice), then the record's lines at their harmonics
    f = f0
    for _ in range(2):
        f, h = _fit(nu, p, f, lambda h: tol + 0 * h)
    hn = np.rint(nu / f)
    on = (hn >= 1) & (np.abs(nu - hn * f) <= tol)
    if h.size == 0 or not on.any():
        raise InputError("x", f"{nu.size} spectral lines", f"none lies at a harmonic of a "
                         f"speed in [{lo:g}, {hi:g}] Hz: no speed to estimate")
    rn, rw, df = _record_lines(a, fs, width, f_top)
    sigma = tol / h.max()  # uncertainty of the Welch fit
    for half in (lambda k: np.maximum(1.5 * df, 3 * k * sigma), lambda k: 0.5 * df + 0 * k):
        f, used = _fit(rn, rw, f, half, h)
    # the dominant mesh family among the Welch lines on the comb (line power)
    hn, pn, nn = hn[on].astype(np.int64), p[on], nu[on]
    zs = np.arange(TEETH_RANGE[0], TEETH_RANGE[1] + 1)
    div = hn[None, :] % zs[:, None] == 0
    fam = div @ pn
    teeth, teeth_conf, centre = None, 0.0, nn[np.argmax(pn)]
    if fam.max() > 0:
        teeth = int(zs[fam >= EXPLAINED * fam.max()].max())
        mine = hn % teeth == 0
        other = (teeth % zs != 0) & (zs % teeth != 0)
        rest = (div[other] & ~mine).astype(float) @ pn  # other families' power off this one
        teeth_conf = float(1.0 - rest.max(initial=0.0) / fam[zs == teeth][0])
        centre = nn[mine][np.argmax(pn[mine])]
    # checks: sideband spacing around that line, cepstral rahmonic at 1 / f
    d = np.abs(nu - centre)
    near = (d > 2 * tol) & (d <= (_SIDEBANDS + 0.5) * f)
    spacing = math.nan
    if near.any():
        sg, ss = _sieve(d[near], wt[near], lo, hi, tol)
        spacing = float(sg[_peaks(ss)[0]])
    m = round(spacing / f) if math.isfinite(spacing) else 0
    sb_ok = bool(m >= 1 and abs(spacing - m * f) <= 2 * tol)
    c = scipy.fft.irfft(np.log(pw))
    band = c[int(fs / hi):int(math.ceil(fs / lo)) + 1]
    med = float(np.median(band))
    mad = 1.4826 * float(np.median(np.abs(band - med)))
    i = int(round(fs / f))
    cz = float((c[i - 1:i + 2].max() - med) / mad) if mad > 0 else 0.0
    drift, n = math.nan, 2 * math.ceil(MIN_PERIODS * fs / lo)
    if a.size >= 2 * n:  # fresh estimates on the first and the last piece
        try:
            ends = [estimate_constant_speed(piece, fs, search=(lo, hi)) for piece in (a[:n], a[-n:])]
        except InputError:
            ends = []
        if ends and min(e.confidence for e in ends) >= MIN_CONFIDENCE:
            drift = (ends[1].frequency - ends[0].frequency) / f
    n_ok = int(sb_ok) + int(cz >= CEPSTRUM_Z)
    steady = 0.5 if abs(drift) > GIVEN_SPEED_TOLERANCE else 1.0
    return SpeedEstimate(
        frequency=f, confidence=steady * (1.0 - math.exp(-max(margin, 0.0))) * (2 + n_ok) / 4,
        margin=margin, lines=int(used.size), order=int(hn[np.argmax(pn)]),
        teeth=teeth, teeth_confidence=max(teeth_conf, 0.0), sideband_spacing=spacing,
        sidebands_agree=sb_ok, cepstrum_z=cz, drift=float(drift), search=(lo, hi))


def check_given_speed(
    x: np.ndarray,
    fs: float,
    given_hz: float,
    *,
    order: float,
    tolerance: float = GIVEN_SPEED_TOLERANCE,
    label: str = "given speed {hz} Hz",
) -> str | None:
    """Warning text when a given constant shaft speed disagrees with the data.

    The strongest line within half a shaft order of order ``order`` of ``given_hz`` is
    taken for that harmonic; the speed is then fitted by weighted least squares to the
    lines at the multiples of that order (within 1.5 bins; parabolic peak interpolation,
    as :func:`estimate_constant_speed`) and compared with ``given_hz``.

    Parameters
    ----------
    x : array_like
        Vibration record (any units).
    fs : float
        Sampling rate [Hz].
    given_hz : float
        Given constant shaft speed [Hz].
    order : float
        Order of the harmonic used for the estimate (tooth count for the mesh tone).
    tolerance : float
        Largest accepted relative disagreement (default 0.002 = 0.2 %,
        :data:`GIVEN_SPEED_TOLERANCE`).
    label : str
        How the warning names the speed, ``{hz}`` standing for it (``"config speed {hz} Hz
        (the operating speed of --config two-stage-reducer)"`` for a configuration's).

    Returns
    -------
    str or None
        One line naming the given and estimated speeds and their relative difference,
        or ``None`` when they agree within ``tolerance``.

    Raises
    ------
    InputError
        If an argument is out of range, the record holds fewer than
        :data:`MIN_PERIODS` periods of ``given_hz``, or no line lies near the harmonic.

    References
    ----------
    Combet & Gelman (2007): a mean-speed error smears the synchronous average;
    Randall (2011), sec. 3.6 (mesh harmonics and their sidebands).

    Examples
    --------
    >>> import numpy as np
    >>> fs = 5000.0
    >>> t = np.arange(int(3 * fs)) / fs
    >>> x = np.cos(2 * np.pi * 20 * 15.0 * t)
    >>> check_given_speed(x, fs, 15.0, order=20) is None
    True
    >>> print(check_given_speed(x, fs, 15.1, order=20))  # doctest: +ELLIPSIS
    given speed 15.1 Hz disagrees with the speed estimated from order 20 ... (-0.66... %, ...)
    """
    a = as_signal(x, name="x", min_length=16)
    fs = check_fs(fs)
    given = check_positive("given_hz", given_hz)
    q = check_positive("order", order)
    tol = check_positive("tolerance", tolerance)
    check_below_nyquist(fs, q * given, f"harmonic order {q:g} of the given speed")
    if a.size < MIN_PERIODS * fs / given:
        raise InputError("x.length", f"{a.size} samples ({a.size / fs:.4g} s)",
                         f"must hold >= {MIN_PERIODS:g} periods of {given:g} Hz")
    nu, w, df = _record_lines(a - a.mean(), fs, _FLOOR_BLOCK * given, 0.5 * fs)
    f_q, h = _fit(nu, w, q * given, lambda h: np.where(h == 1, 0.5 * given, 0.0))
    if h.size == 0:
        raise InputError("x", f"no line near order {q:g} of {given:g} Hz",
                         "the harmonic is too weak to check the speed against")
    f_est = _fit(nu, w, f_q, lambda h: 1.5 * df + 0 * h)[0] / q
    dev = f_est / given - 1.0
    if abs(dev) <= tol:
        return None
    return (f"{label.format(hz=f'{given:g}')} disagrees with the speed estimated from order "
            f"{float(order):g} of the signal, {f_est:.6g} Hz ({100 * dev:+.3f} %, tolerance "
            f"{100 * tol:g} %)")
