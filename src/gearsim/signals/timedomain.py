"""Time-domain statistics and periodic-impact detection.

The statistics are the classical overall indicators of vibration condition monitoring
(Randall 2011, ch. 5): RMS, peak, crest factor and kurtosis. A tooth-root crack produces
one impact per revolution of the cracked gear, so the period between impacts should equal
``T1 = 1 / f_r1`` (seed, section 3.1).

References
----------
.. [R11] R. B. Randall, *Vibration-based Condition Monitoring*, Wiley, 2011, sec. 5.2.
.. [Seed] H. Shi, W. Li, W. Zhou, "Dynamic response analysis of tooth root crack failure in
   helical idler gear system under different working flank conditions", *Actuators* 14
   (2025) 292, sec. 3.1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs, check_positive

__all__ = [
    "TimeStats",
    "Impacts",
    "rms",
    "peak",
    "crest_factor",
    "kurtosis",
    "time_stats",
    "impact_threshold",
    "detect_impacts",
    "ratios_to_baseline",
    "window_peak",
]


def rms(x: np.ndarray) -> float:
    r"""Root mean square :math:`\sqrt{\frac1N\sum_i x_i^2}` (units of ``x``).

    The mean is not removed: pass ``x - x.mean()`` for the RMS of the dynamic part
    (as :func:`time_stats` does with ``remove_mean=True``).

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units).

    Returns
    -------
    float
        RMS in units of ``x``.

    Raises
    ------
    InputError
        If ``x`` is not 1-D, has fewer than two samples or holds NaN/inf.

    References
    ----------
    Randall (2011), eq. 5.1.

    Examples
    --------
    A sine of amplitude :math:`A` over whole periods has RMS :math:`A/\sqrt2`:

    >>> import numpy as np
    >>> t = np.arange(1000) / 1000.0
    >>> round(rms(2.0 * np.sin(2 * np.pi * 10 * t)), 6)
    1.414214
    """
    a = as_signal(x)
    return float(np.sqrt(np.mean(a * a)))


def peak(x: np.ndarray) -> float:
    r"""Peak value :math:`\max_i |x_i|` (units of ``x``).

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units).

    Returns
    -------
    float
        Largest absolute sample, in units of ``x``.

    Raises
    ------
    InputError
        If ``x`` is not 1-D, has fewer than two samples or holds NaN/inf.

    References
    ----------
    Randall (2011), sec. 5.2.

    Examples
    --------
    >>> peak([1.0, -3.0, 2.0])
    3.0
    """
    return float(np.max(np.abs(as_signal(x))))


def crest_factor(x: np.ndarray) -> float:
    r"""Crest factor :math:`\max|x| / \mathrm{RMS}(x)` (dimensionless).

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units). The mean is not removed.

    Returns
    -------
    float
        Peak over RMS; :math:`\sqrt2` for a sine, larger for an impulsive signal.

    Raises
    ------
    InputError
        If ``x`` is not 1-D, has fewer than two samples, holds NaN/inf, or is all zeros
        (RMS = 0).

    References
    ----------
    Randall (2011), sec. 5.2.1.

    Examples
    --------
    A sine sampled at its crest has crest factor :math:`\sqrt2`:

    >>> import numpy as np
    >>> t = np.arange(1000) / 1000.0
    >>> round(crest_factor(2.0 * np.sin(2 * np.pi * 10 * t)), 6)
    1.414214
    """
    a = as_signal(x)
    r = float(np.sqrt(np.mean(a * a)))
    if r == 0.0:
        raise InputError("signal", "all zeros", "crest factor needs a signal with RMS > 0")
    return float(np.max(np.abs(a))) / r


def kurtosis(x: np.ndarray) -> float:
    r"""Pearson kurtosis :math:`N\sum(x_i-\bar x)^4 / (\sum(x_i-\bar x)^2)^2` (dimensionless).

    Equals 3 for Gaussian noise and ``scipy.stats.kurtosis(x, fisher=False)`` (biased
    moments).

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units); its mean is removed.

    Returns
    -------
    float
        Normalised fourth central moment: 1.5 for a sine, 3 for Gaussian noise, larger
        for an impulsive signal.

    Raises
    ------
    InputError
        If ``x`` is not 1-D, has fewer than two samples, holds NaN/inf, or is constant
        (zero variance).

    References
    ----------
    Randall (2011), sec. 5.2.1; Stewart (1977) uses the same normalised fourth moment
    for FM4.

    Examples
    --------
    A sine over whole periods: :math:`\overline{\sin^4} / (\overline{\sin^2})^2 =
    (3/8) / (1/2)^2 = 1.5`:

    >>> import numpy as np
    >>> t = np.arange(1000) / 1000.0
    >>> round(kurtosis(np.sin(2 * np.pi * 10 * t)), 6)
    1.5
    """
    a = as_signal(x)
    d = a - a.mean()
    m2 = np.mean(d * d)
    if m2 == 0.0:
        raise InputError("signal", "constant", "kurtosis needs a signal with non-zero variance")
    d2 = d * d
    return float(np.mean(d2 * d2) / (m2 * m2))


@dataclass(frozen=True)
class TimeStats:
    """Overall time-domain statistics of one signal (built by :func:`time_stats`).

    Parameters
    ----------
    rms : float
        Root mean square (:func:`rms`), in units of the signal (of the signal minus its
        mean if ``mean_removed``).
    peak : float
        Peak absolute value (:func:`peak`), in units of the signal (after mean removal if
        ``mean_removed``).
    crest_factor : float
        ``peak / rms`` (dimensionless).
    kurtosis : float
        Pearson kurtosis of the signal (:func:`kurtosis`; dimensionless, always about
        the mean).
    mean : float
        Mean of the raw signal (units of the signal).
    mean_removed : bool
        Whether ``rms``, ``peak`` and ``crest_factor`` refer to the signal minus its mean.
    """

    rms: float
    peak: float
    crest_factor: float
    kurtosis: float
    mean: float
    mean_removed: bool


def time_stats(x: np.ndarray, *, remove_mean: bool) -> TimeStats:
    """Compute :class:`TimeStats`; ``remove_mean`` selects AC (True) or raw (False) RMS/peak.

    A mesh force carries the static load as its mean; the seed's RMS comparison concerns
    the dynamic part, so :func:`gearsim.signals.analysis.analyze` passes ``remove_mean=True``.

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units).
    remove_mean : bool
        If True, RMS, peak and crest factor are those of ``x - mean(x)``; if False, of
        ``x`` as given. Kurtosis is always taken about the mean.

    Returns
    -------
    TimeStats
        The statistics, with ``mean`` and ``mean_removed`` recorded.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal, or is constant (crest factor or kurtosis
        undefined).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(1000) / 1000.0
    >>> s = time_stats(3.0 + 2.0 * np.sin(2 * np.pi * 10 * t), remove_mean=True)
    >>> round(s.mean, 6), round(s.rms, 6), round(s.peak, 6), round(s.kurtosis, 6)
    (3.0, 1.414214, 2.0, 1.5)
    """
    a = as_signal(x)
    mu = float(a.mean())
    b = a - mu if remove_mean else a
    return TimeStats(
        rms=rms(b), peak=peak(b), crest_factor=crest_factor(b), kurtosis=kurtosis(a),
        mean=mu, mean_removed=bool(remove_mean),
    )


@dataclass(frozen=True)
class Impacts:
    """Impacts found in a signal and their period (built by :func:`detect_impacts`).

    Parameters
    ----------
    times : ndarray
        Impact times (s), refined by parabolic interpolation of the peak.
    amplitudes : ndarray
        Peak of ``|x - mean|`` at each impact (units of the signal).
    period : float
        Least-squares period between impacts (s); NaN when fewer than two impacts.
    period_std : float
        Standard deviation of the successive intervals divided by their cycle count (s).
    threshold : float
        Detection threshold on ``|x - mean|`` (units of the signal).
    """

    times: np.ndarray
    amplitudes: np.ndarray
    period: float
    period_std: float
    threshold: float

    @property
    def count(self) -> int:
        """Number of impacts."""
        return int(self.times.size)


def impact_threshold(x: np.ndarray, fs: float, *, window: float, factor: float) -> float:
    r"""Robust impact threshold :math:`c \cdot \mathrm{median}_j \max_{i \in W_j} |x_i - \bar x|`.

    The record is cut into windows ``W_j`` of ``window`` seconds (one mesh period is the
    natural choice: every window then holds one meshing cycle); the median of the window
    peaks is the level of normal meshing, and an impact must exceed it by ``factor``.

    Parameters
    ----------
    x : array_like
        Signal (any units).
    fs : float
        Sampling rate (Hz).
    window : float
        Window length (s), at least two samples.
    factor : float
        Multiple of the median window peak, > 1.

    Returns
    -------
    float
        Threshold in units of ``x``.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal, ``fs``, ``window`` or ``factor`` is not > 0, or the
        window spans fewer than 2 samples or more than the record.
    """
    a = as_signal(x)
    fs = check_fs(fs)
    window = check_positive("window", window)
    factor = check_positive("factor", factor)
    n = int(round(window * fs))
    if n < 2 or n > a.size:
        raise InputError(
            "window", f"{window:g} s", f"must span 2..{a.size} samples at fs={fs:g} Hz"
        )
    d = np.abs(a - a.mean())
    m = a.size // n
    peaks = d[: m * n].reshape(m, n).max(axis=1)
    return float(factor * np.median(peaks))


def detect_impacts(
    x: np.ndarray, fs: float, *, min_separation: float, threshold: float
) -> Impacts:
    r"""Find impacts as peaks of :math:`|x - \bar x|` above ``threshold``.

    Peaks closer than ``min_separation`` are merged (the highest is kept, as in
    ``scipy.signal.find_peaks(distance=...)``). Each peak time is refined by a parabola
    through the peak sample and its two neighbours. The period is the slope of a
    least-squares line through the impact times against their cycle numbers
    ``round((t_i - t_0) / median(diff t))``, so a missed impact does not bias it.

    Parameters
    ----------
    x : array_like
        Signal (any units).
    fs : float
        Sampling rate (Hz).
    min_separation : float
        Minimum time between impacts (s); half the expected period is a good choice.
    threshold : float
        Minimum peak of ``|x - mean|`` (units of ``x``); see :func:`impact_threshold`.

    Returns
    -------
    Impacts
        Impact times (s), amplitudes (units of ``x``), period and its scatter (s).

    Raises
    ------
    InputError
        If ``x`` is not a valid signal or ``fs``, ``min_separation`` or ``threshold`` is
        not > 0.
    """
    a = as_signal(x)
    fs = check_fs(fs)
    min_separation = check_positive("min_separation", min_separation)
    threshold = check_positive("threshold", threshold)
    d = np.abs(a - a.mean())
    distance = max(1, int(round(min_separation * fs)))
    from scipy.signal import find_peaks  # heavy: only the impact detector needs it

    idx, _ = find_peaks(d, height=threshold, distance=distance)
    # Parabolic refinement of the peak position (sub-sample timing).
    t = idx.astype(np.float64)
    amp = d[idx] if idx.size else np.empty(0)
    inner = (idx > 0) & (idx < a.size - 1)
    if inner.any():
        i = idx[inner]
        ym, y0, yp = d[i - 1], d[i], d[i + 1]
        den = ym - 2.0 * y0 + yp
        with np.errstate(divide="ignore", invalid="ignore"):
            delta = np.where(den != 0.0, 0.5 * (ym - yp) / den, 0.0)
        delta = np.clip(delta, -0.5, 0.5)
        t[inner] = i + delta
        amp = amp.copy()
        amp[inner] = y0 - 0.25 * (ym - yp) * delta
    times = t / fs
    period, period_std = float("nan"), float("nan")
    if times.size >= 2:
        step = float(np.median(np.diff(times)))
        cycles = np.round((times - times[0]) / step)
        if np.unique(cycles).size >= 2:
            slope, _ = np.polyfit(cycles, times, 1)
            period = float(slope)
            dc = np.diff(cycles)
            ok = dc > 0
            intervals = np.diff(times)[ok] / dc[ok]
            period_std = float(np.std(intervals)) if intervals.size > 1 else 0.0
    return Impacts(
        times=times, amplitudes=np.asarray(amp, dtype=np.float64), period=period,
        period_std=period_std, threshold=float(threshold),
    )


def ratios_to_baseline(current: TimeStats, baseline: TimeStats) -> dict[str, float]:
    """Ratios current / baseline of RMS, peak, crest factor and kurtosis (dimensionless).

    The seed reports these as percentages of the healthy system (e.g. RMS 132.4 %).

    Parameters
    ----------
    current : TimeStats
        Statistics of the signal under test (e.g. the cracked system).
    baseline : TimeStats
        Statistics of the reference signal (e.g. the healthy system), computed with the
        same ``remove_mean`` setting.

    Returns
    -------
    dict of str to float
        Keys ``"rms"``, ``"peak"``, ``"crest_factor"``, ``"kurtosis"``; values
        ``current / baseline`` (1.0 = unchanged; multiply by 100 for percent).

    Raises
    ------
    InputError
        If the two were computed with different ``mean_removed``, or a baseline value is
        zero.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(1000) / 1000.0
    >>> x = np.sin(2 * np.pi * 10 * t)
    >>> r = ratios_to_baseline(time_stats(1.5 * x, remove_mean=True),
    ...                        time_stats(x, remove_mean=True))
    >>> {k: round(v, 6) for k, v in r.items()}
    {'rms': 1.5, 'peak': 1.5, 'crest_factor': 1.0, 'kurtosis': 1.0}
    """
    if current.mean_removed != baseline.mean_removed:
        raise InputError(
            "baseline.mean_removed", baseline.mean_removed,
            f"must equal the current signal's setting ({current.mean_removed})",
        )
    out: dict[str, float] = {}
    for name in ("rms", "peak", "crest_factor", "kurtosis"):
        b = getattr(baseline, name)
        if b == 0.0:
            raise InputError(f"baseline.{name}", 0.0, "must be non-zero to form a ratio")
        out[name] = getattr(current, name) / b
    return out


def window_peak(x: np.ndarray, fs: float, centres: np.ndarray, half_width: float) -> np.ndarray:
    r"""Peak :math:`\max |x_i|` in a window around each given time.

    The window around ``c`` holds the samples ``j`` with ``|j - round(c fs)| <= h``,
    ``h = max(1, round(half_width fs))``, clipped to the record. A window with at most
    ``h`` samples inside the record (less than about half a window) gives NaN, so that
    a peak is never taken from a sliver of a window at the record's ends.

    Parameters
    ----------
    x : array_like
        Signal (any units), e.g. a load fluctuation ``x - mean(x)``.
    fs : float
        Sampling rate [Hz].
    centres : array_like
        Window centres [s], e.g. impact times.
    half_width : float
        Half width of the window [s].

    Returns
    -------
    ndarray
        Peak per centre (units of ``x``), NaN where the window lies mostly outside.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal or ``fs`` or ``half_width`` is not > 0.

    References
    ----------
    Randall (2011), sec. 5.2.1 (peak value); applied per impact window as in the
    seed's impact amplitudes (sec. 3.2).
    """
    a = as_signal(x)
    fs = check_fs(fs)
    half_width = check_positive("half_width", half_width)
    c = np.atleast_1d(np.asarray(centres, dtype=np.float64))
    n = a.size
    out = np.full(c.size, np.nan)
    h = max(1, int(round(half_width * fs)))
    for i, ci in enumerate(c):
        j = int(round(ci * fs))
        lo, hi = max(0, j - h), min(n, j + h + 1)
        if hi - lo > h:  # at least half a window inside the record
            out[i] = np.max(np.abs(a[lo:hi]))
    return out


# --- Shape statistics (skewness and the peak/level factors) -----------------------------

__all__ += ["skewness", "impulse_factor", "shape_factor", "clearance_factor"]


def skewness(x: np.ndarray) -> float:
    r"""Skewness :math:`\sqrt N \sum(x_i-\bar x)^3 / (\sum(x_i-\bar x)^2)^{3/2}` (dimensionless).

    The normalised third central moment with biased (``1/N``) moments, equal to
    ``scipy.stats.skew(x, bias=True)``. Zero for a symmetric distribution (a sine, Gaussian
    noise); impacts of one sign make it depart from zero.

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units); its mean is removed.

    Returns
    -------
    float
        Skewness (dimensionless).

    Raises
    ------
    InputError
        If ``x`` is not a valid signal or is constant (zero variance).

    References
    ----------
    Randall (2011), sec. 5.2.1; A. K. S. Jardine, D. Lin, D. Banjevic, "A review on
    machinery diagnostics and prognostics implementing condition-based maintenance",
    *Mech. Syst. Signal Process.* 20 (2006) 1483-1510, sec. 3.1.

    Examples
    --------
    The values 0, 0, 3 have mean 1, deviations -1, -1, 2: :math:`m_3 = 6/3 = 2`,
    :math:`m_2 = 6/3 = 2`, skewness :math:`2 / 2^{3/2} = 1/\sqrt2`:

    >>> round(skewness([0.0, 0.0, 3.0]), 6)
    0.707107
    """
    a = as_signal(x)
    d = a - a.mean()
    m2 = np.mean(d * d)
    if m2 == 0.0:
        raise InputError("signal", "constant", "skewness needs a signal with non-zero variance")
    return float(np.mean(d * d * d) / m2**1.5)


def _mean_abs(a: np.ndarray, what: str) -> float:
    m = float(np.mean(np.abs(a)))
    if m == 0.0:
        raise InputError("signal", "all zeros", f"{what} needs a signal with mean |x| > 0")
    return m


def impulse_factor(x: np.ndarray) -> float:
    r"""Impulse factor :math:`\max|x| / \overline{|x|}` (dimensionless).

    The peak over the mean absolute value (the mean is not removed, as in :func:`rms`).
    :math:`\pi/2` for a sine over whole periods; large for an impulsive signal.

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units).

    Returns
    -------
    float
        Impulse factor (dimensionless, >= 1).

    Raises
    ------
    InputError
        If ``x`` is not a valid signal or is all zeros.

    References
    ----------
    Jardine, Lin & Banjevic (2006), sec. 3.1; Y. Lei, M. J. Zuo, "Gear crack level
    identification based on weighted K nearest neighbor classification algorithm",
    *Mech. Syst. Signal Process.* 23 (2009) 1535-1547, Table 1 (features F5-F7).

    Examples
    --------
    For a sine :math:`\overline{|\sin|} = 2/\pi`, so the factor is :math:`\pi/2`:

    >>> import numpy as np
    >>> t = (np.arange(200_000) + 0.5) / 200_000  # one period, midpoint samples
    >>> round(impulse_factor(np.sin(2 * np.pi * t)), 6), round(np.pi / 2, 6)
    (1.570796, 1.570796)
    """
    a = as_signal(x)
    return float(np.max(np.abs(a))) / _mean_abs(a, "impulse factor")


def shape_factor(x: np.ndarray) -> float:
    r"""Shape factor :math:`\mathrm{RMS}(x) / \overline{|x|}` (dimensionless).

    The mean is not removed. :math:`\pi / (2\sqrt2) \approx 1.1107` for a sine,
    :math:`\sqrt{\pi/2} \approx 1.2533` for zero-mean Gaussian noise.

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units).

    Returns
    -------
    float
        Shape factor (dimensionless, >= 1).

    Raises
    ------
    InputError
        If ``x`` is not a valid signal or is all zeros.

    References
    ----------
    Jardine, Lin & Banjevic (2006), sec. 3.1; Lei & Zuo (2009), Table 1.

    Examples
    --------
    For a sine, :math:`(1/\sqrt2) / (2/\pi) = \pi / (2\sqrt2)`:

    >>> import numpy as np
    >>> t = (np.arange(200_000) + 0.5) / 200_000  # one period, midpoint samples
    >>> round(shape_factor(np.sin(2 * np.pi * t)), 6), round(float(np.pi / (2 * np.sqrt(2))), 6)
    (1.110721, 1.110721)
    """
    a = as_signal(x)
    return float(np.sqrt(np.mean(a * a))) / _mean_abs(a, "shape factor")


def clearance_factor(x: np.ndarray) -> float:
    r"""Clearance (margin) factor :math:`\max|x| / \big(\overline{\sqrt{|x|}}\big)^2` (dimensionless).

    The mean is not removed. For a sine of unit amplitude,
    :math:`\overline{\sqrt{|\sin|}} = \frac{2}{\pi}\int_0^{\pi/2}\sqrt{\sin\theta}\,d\theta
    = \frac{2}{\pi}\,\frac{\sqrt\pi\,\Gamma(3/4)}{2\,\Gamma(5/4)} \approx 0.762760`, so the
    factor is about 1.718796.

    Parameters
    ----------
    x : array_like
        Signal, 1-D, at least two finite samples (any units).

    Returns
    -------
    float
        Clearance factor (dimensionless, >= 1).

    Raises
    ------
    InputError
        If ``x`` is not a valid signal or is all zeros.

    References
    ----------
    Jardine, Lin & Banjevic (2006), sec. 3.1; Lei & Zuo (2009), Table 1 (F8).

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.special import gamma
    >>> t = (np.arange(200_000) + 0.5) / 200_000  # one period, midpoint samples
    >>> m = (2 / np.pi) * np.sqrt(np.pi) * gamma(0.75) / (2 * gamma(1.25))
    >>> round(clearance_factor(np.sin(2 * np.pi * t)), 5), round(float(1 / m**2), 5)
    (1.7188, 1.7188)
    """
    a = as_signal(x)
    _mean_abs(a, "clearance factor")
    return float(np.max(np.abs(a))) / float(np.mean(np.sqrt(np.abs(a)))) ** 2
