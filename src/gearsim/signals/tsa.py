r"""Time-synchronous averaging and the gear condition indicators built on it.

The signal is resampled to ``M`` points per revolution of the shaft of interest (from a
known constant speed or from tacho pulses, by cubic-spline interpolation at the times of
equal angle increments) and averaged over ``N`` revolutions. Components synchronous with
the shaft add coherently; non-synchronous ones (other shafts, noise) shrink by
:math:`1/\sqrt N` in amplitude for uncorrelated noise (McFadden 1987).

Derived signals (Zakrajsek, Townsend & Decker 1993; Decker 2002), in shaft orders ``o``
of the average (``o`` = bin of the ``M``-point DFT of the TSA):

* regular signal: orders ``1..H`` (shaft and harmonics), mesh orders ``n Z`` and their
  sidebands ``n Z +- s, s = 1..S`` (``S = 1`` in the sources);
* difference signal ``d = TSA - regular``;
* residual signal ``r = TSA - (shaft orders 1..H and mesh orders n Z)``.

Indicators (moments about the mean, ``N_s`` samples):

* FM0 = (max TSA - min TSA) / sum_n A(n Z)  (Stewart 1977);
* FM4 = N_s sum d^4 / (sum d^2)^2  (Stewart 1977);
* M6A = N_s^2 sum d^6 / (sum d^2)^3,  M8A = N_s^3 sum d^8 / (sum d^2)^4  (Martin 1989);
* NA4 = N_s sum r_M^4 / [ (1/M) sum_j sum_i r_ij^2 ]^2 over the run history
  j = 1..M (Zakrajsek et al. 1993).

References
----------
.. [S77] R. M. Stewart, "Some useful data analysis techniques for gearbox diagnostics",
   Report MHM/R/10/77, Machine Health Monitoring Group, ISVR, Univ. Southampton, 1977.
.. [M87] P. D. McFadden, "A revised model for the extraction of periodic waveforms by
   time domain averaging", *Mech. Syst. Signal Process.* 1 (1987) 83-95.
.. [M89] H. R. Martin, "Statistical moment analysis as a means of surface damage detection",
   Proc. 7th Int. Modal Analysis Conf., 1989, 1016-1021.
.. [Z93] J. J. Zakrajsek, D. P. Townsend, H. J. Decker, "An analysis of gear fault detection
   methods as applied to pitting fatigue failure data", NASA TM-105950, 1993.
.. [D02] H. J. Decker, "Crack detection for aerospace quality spur gears", NASA
   TM-2002-211492, 2002.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.fft
from scipy.interpolate import CubicSpline

from gearsim.errors import InputError
from gearsim.signals._checks import (
    as_signal,
    check_fs,
    check_int,
    check_positive,
    check_speed_source,
)

__all__ = [
    "TSA",
    "Indicators",
    "pulse_times",
    "revolution_times_from_speed",
    "cubic_resample",
    "angular_resample",
    "order_mask",
    "remove_orders",
    "tsa",
    "regular_signal",
    "difference_signal",
    "residual_signal",
    "fm0",
    "fm4",
    "m6a",
    "m8a",
    "na4",
    "condition_indicators",
]


def _order_amplitudes(y: np.ndarray) -> np.ndarray:
    """Peak amplitude per DFT bin of ``y`` (rectangular window), halved at 0 and Nyquist."""
    a = np.abs(scipy.fft.rfft(y)) * (2.0 / y.size)
    a[0] *= 0.5
    if y.size % 2 == 0:
        a[-1] *= 0.5
    return a


@dataclass(frozen=True)
class TSA:
    """Time-synchronous average over one revolution (built by :func:`tsa`).

    Parameters
    ----------
    average : ndarray, shape (M,)
        Averaged revolution (signal units), sample ``j`` at shaft angle ``2 pi j / M``.
    n_averages : int
        Number of revolutions averaged, ``N``.
    shaft_frequency : float
        Mean shaft frequency over the averaged revolutions (Hz).
    """

    average: np.ndarray
    n_averages: int
    shaft_frequency: float

    @property
    def samples_per_rev(self) -> int:
        """Number of samples per revolution ``M`` (length of ``average``)."""
        return int(self.average.size)

    def order_amplitudes(self) -> np.ndarray:
        """Peak amplitude per shaft order ``0..M/2`` (signal units, DFT of the average).

        Returns
        -------
        ndarray, shape (M // 2 + 1,)
            Entry ``o`` is the amplitude of shaft order ``o``: ``2 |Y_o| / M`` for
            ``0 < o < M/2``, ``|Y_o| / M`` for the mean (``o = 0``) and, for even ``M``,
            the Nyquist order. A tone ``A cos(2 pi o j / M)`` gives exactly ``A``.

        Examples
        --------
        >>> import numpy as np
        >>> j = np.arange(64)
        >>> t = TSA(average=3.0 * np.cos(2 * np.pi * 10 * j / 64), n_averages=1,
        ...         shaft_frequency=1.0)
        >>> round(float(t.order_amplitudes()[10]), 6)
        3.0
        """
        return _order_amplitudes(self.average)


def pulse_times(tacho: np.ndarray, fs: float, *, threshold: float | None = None) -> np.ndarray:
    """Times (s) of the rising edges of a tacho signal, by linear interpolation of the crossing.

    Parameters
    ----------
    tacho : array_like
        Tacho (once- or N-per-revolution pulse) signal.
    fs : float
        Sampling rate (Hz).
    threshold : float or None
        Crossing level (signal units); ``None`` takes the midpoint of the signal's range.
        This is a documented choice, not a silent default: it is reported by the caller.

    Returns
    -------
    ndarray
        Rising-edge times (s).

    Raises
    ------
    InputError
        If the tacho is not a valid signal or is constant, ``fs`` is not > 0, or
        ``threshold`` lies outside the tacho's range.
    """
    a = as_signal(tacho, name="tacho")
    fs = check_fs(fs)
    lo, hi = float(a.min()), float(a.max())
    if hi == lo:
        raise InputError("tacho", "constant", "must contain pulses (min == max)")
    level = 0.5 * (lo + hi) if threshold is None else float(threshold)
    if not lo < level < hi:
        raise InputError("threshold", level, f"must lie inside the tacho range ({lo:g}, {hi:g})")
    below = a[:-1] < level
    i = np.flatnonzero(below & (a[1:] >= level))
    frac = (level - a[i]) / (a[i + 1] - a[i])
    return (i + frac) / fs


def revolution_times_from_speed(duration: float, *, shaft_frequency: float) -> np.ndarray:
    """Start times of whole revolutions at constant speed.

    Parameters
    ----------
    duration : float
        Time span the revolutions must fit in [s].
    shaft_frequency : float
        Constant shaft frequency ``f_r`` [Hz].

    Returns
    -------
    ndarray
        ``k / f_r`` [s] for ``k = 0..R``, ``R = floor(duration f_r)`` whole revolutions
        (a relative slack of 1e-9 revolutions absorbs rounding of ``duration``).

    Raises
    ------
    InputError
        If ``duration`` or ``shaft_frequency`` is not > 0.
    """
    duration = check_positive("duration", duration)
    f_r = check_positive("shaft_frequency", shaft_frequency)
    n = int(np.floor(duration * f_r + 1e-9))
    return np.arange(n + 1) / f_r


def cubic_resample(x: np.ndarray, fs: float, times: np.ndarray) -> np.ndarray:
    """Values of the cubic interpolating spline through the samples at the given times.

    The spline passes through ``x[k]`` at ``t_k = k / fs`` with not-a-knot end
    conditions (de Boor 1978, ch. IV), so its error is fourth order in ``1 / fs`` up to
    the ends of the record: ``(5/384) (omega / fs)^4 A`` for a tone of amplitude ``A``
    and angular frequency ``omega`` (Hall & Meyer 1976). Times up to one sample interval
    past the last sample are extrapolated with the last cubic piece. This is the one
    interpolation of the package's resampling (angular resampling and its inverse).

    Parameters
    ----------
    x : array_like
        Samples (any units), at least 4.
    fs : float
        Sampling rate of ``x`` [Hz].
    times : array_like
        Times [s] at which to evaluate the spline, in ``[0, len(x) / fs]``.

    Returns
    -------
    ndarray
        Interpolated values (units of ``x``), shape of ``times``.

    Raises
    ------
    InputError
        If ``x`` has fewer than 4 samples or is not finite, ``fs`` is not > 0, or a time
        lies outside the record.

    References
    ----------
    C. de Boor, *A Practical Guide to Splines*, Springer, 1978, ch. IV-V.
    C. A. Hall, W. W. Meyer, "Optimal error bounds for cubic spline interpolation",
    *J. Approx. Theory* 16 (1976) 105-122.
    """
    a = as_signal(x, min_length=4)
    fs = check_fs(fs)
    t = np.asarray(times, dtype=np.float64)
    span = a.size / fs
    if t.size and (t.min() < -1e-12 * span or t.max() > span * (1 + 1e-12)):
        raise InputError("times", f"[{t.min():g}, {t.max():g}] s",
                         f"must lie within the record [0, {span:g}] s")
    return CubicSpline(np.arange(a.size) / fs, a)(t)


def angular_resample(
    x: np.ndarray,
    fs: float,
    *,
    pulses: np.ndarray,
    pulses_per_rev: int,
    samples_per_rev: int,
) -> np.ndarray:
    r"""Resample ``x`` at ``samples_per_rev`` equal angle steps per revolution.

    The shaft angle is known at each pulse (pulse ``i`` at ``i / pulses_per_rev``
    revolutions) and taken as linear in time between pulses (constant speed within a pulse
    interval). The signal is evaluated at the resulting times by :func:`cubic_resample`
    (cubic spline through the samples, not-a-knot ends).

    Parameters
    ----------
    x : array_like
        Signal.
    fs : float
        Sampling rate (Hz).
    pulses : array_like
        Pulse times (s), increasing; whole revolutions between the first and last pulse are
        used. They must lie within ``[0, len(x) / fs]``: a record of ``n`` samples spans
        ``n`` sample intervals, so a revolution may end one interval after the last
        sample (its last angle sample is then extrapolated by less than one interval).
    pulses_per_rev : int
        Pulses per shaft revolution.
    samples_per_rev : int
        ``M``.

    Returns
    -------
    ndarray, shape (N, M)
        One row per revolution.

    Raises
    ------
    InputError
        If ``x`` or ``fs`` is invalid, a count is out of range, or the pulses are not
        increasing, span less than one revolution or lie outside the record.

    References
    ----------
    McFadden (1987), sec. 2 (resampling at equal angle increments).
    """
    a = as_signal(x)
    fs = check_fs(fs)
    p = np.asarray(pulses, dtype=np.float64)
    pulses_per_rev = check_int("pulses_per_rev", pulses_per_rev, minimum=1)
    samples_per_rev = check_int("samples_per_rev", samples_per_rev, minimum=4)
    if p.ndim != 1 or np.any(np.diff(p) <= 0):
        raise InputError("pulses", "not increasing", "pulse times must increase strictly")
    n_rev = (p.size - 1) // int(pulses_per_rev)
    if n_rev < 1:
        raise InputError(
            "pulses", f"{p.size} pulses",
            f"must span at least one revolution ({pulses_per_rev + 1} pulses)",
        )
    t_end = a.size / fs
    if p[0] < 0.0 or p[n_rev * pulses_per_rev] > t_end * (1 + 1e-12):
        raise InputError("pulses", f"[{p[0]:g}, {p[-1]:g}] s", f"must lie within [0, {t_end:g}] s")
    m = samples_per_rev
    angle_pulses = np.arange(p.size) / pulses_per_rev  # revolutions
    theta = np.arange(n_rev * m) / m
    t = np.interp(theta, angle_pulses, p)
    return cubic_resample(a, fs, t).reshape(n_rev, m)


def tsa(
    x: np.ndarray,
    fs: float,
    *,
    samples_per_rev: int,
    shaft_frequency: float | None = None,
    pulses: np.ndarray | None = None,
    pulses_per_rev: int = 1,
) -> TSA:
    r"""Time-synchronous average :math:`\bar y_j = \frac1N \sum_{r=0}^{N-1} y(r, j)`.

    Give either ``shaft_frequency`` (constant known speed, revolutions start at t = 0) or
    ``pulses`` (tacho pulse times, see :func:`pulse_times`).

    Parameters
    ----------
    x : array_like
        Signal.
    fs : float
        Sampling rate (Hz).
    samples_per_rev : int
        ``M``; at least twice the highest shaft order of interest.
    shaft_frequency : float, optional
        Shaft frequency (Hz) for the known-speed case.
    pulses : array_like, optional
        Tacho pulse times (s).
    pulses_per_rev : int
        Pulses per revolution (tacho case).

    Returns
    -------
    TSA
        The averaged revolution (units of ``x``), the number of revolutions and the
        mean shaft frequency (Hz).

    Raises
    ------
    InputError
        If ``x`` or ``fs`` is invalid, not exactly one of ``shaft_frequency`` and
        ``pulses`` is given, ``samples_per_rev < 4``, or the pulses are not increasing,
        span less than one revolution or lie outside the record.

    References
    ----------
    McFadden (1987); Stewart (1977).
    """
    a = as_signal(x)
    fs = check_fs(fs)
    f_r = check_speed_source(shaft_frequency, pulses, names=("shaft_frequency", "pulses"))
    if f_r is not None:
        pulses = revolution_times_from_speed((a.size - 1) / fs, shaft_frequency=f_r)
        pulses_per_rev = 1
    rows = angular_resample(
        a, fs, pulses=pulses, pulses_per_rev=pulses_per_rev, samples_per_rev=samples_per_rev
    )
    n_rev = rows.shape[0]
    p = np.asarray(pulses, dtype=np.float64)
    f_mean = n_rev / (p[n_rev * pulses_per_rev] - p[0])
    return TSA(average=rows.mean(axis=0), n_averages=n_rev, shaft_frequency=float(f_mean))


def order_mask(
    n: int, *, teeth: int, shaft_harmonics: int, sideband_orders: int, revolutions: int = 1
) -> np.ndarray:
    """Mask of the DFT bins of the shaft and mesh orders to remove from an angle record.

    For ``n`` samples over ``R`` whole revolutions (equal angle steps), bin ``b`` of the
    ``n``-point DFT is shaft order ``b / R``. The mask selects the mean (bin 0), the shaft
    orders ``1..H``, every mesh order ``q Z`` and its sidebands ``q Z +- s, s = 1..S``
    below the Nyquist order.

    Parameters
    ----------
    n : int
        Length of the angle record (``R M`` samples).
    teeth : int
        Tooth count ``Z`` of the gear on the shaft (the mesh order).
    shaft_harmonics : int
        ``H`` (0: none).
    sideband_orders : int
        ``S`` (0: the mesh orders only).
    revolutions : int
        ``R``; 1 for a time-synchronous average.

    Returns
    -------
    ndarray of bool, shape (n // 2 + 1,)
        True at the bins to remove (for :func:`remove_orders`).

    Raises
    ------
    InputError
        If a count is not an integer of its range, or the mesh order ``Z R`` is not below
        the Nyquist bin ``n // 2``.

    References
    ----------
    Zakrajsek et al. (1993): regular, difference and residual signals.
    """
    teeth = check_int("teeth", teeth, minimum=1)
    shaft_harmonics = check_int("shaft_harmonics", shaft_harmonics, minimum=0)
    sideband_orders = check_int("sideband_orders", sideband_orders, minimum=0)
    r = check_int("revolutions", revolutions, minimum=1)
    n_bins = n // 2 + 1
    if teeth * r >= n_bins:
        raise InputError(
            "samples_per_rev", n // r,
            f"must exceed 2 x teeth = {2 * teeth} to hold the mesh order",
        )
    mask = np.zeros(n_bins, dtype=bool)
    mask[0] = True
    mask[r : min(shaft_harmonics * r, n_bins - 1) + 1 : r] = True
    for centre in range(teeth * r, n_bins, teeth * r):
        for s in range(-sideband_orders, sideband_orders + 1):
            if 0 <= centre + s * r < n_bins:
                mask[centre + s * r] = True
    return mask


def remove_orders(x: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Set the DFT bins selected by ``mask`` to zero and transform back.

    Parameters
    ----------
    x : ndarray
        Angle record (units of the signal), a whole number of revolutions.
    mask : ndarray of bool
        From :func:`order_mask`, length ``len(x) // 2 + 1``.

    Returns
    -------
    ndarray
        ``x`` without the selected orders (same units and length).

    References
    ----------
    Zakrajsek et al. (1993).
    """
    spec = scipy.fft.rfft(x)
    spec[mask] = 0.0
    return scipy.fft.irfft(spec, n=x.size)


def regular_signal(
    t: TSA, *, teeth: int, shaft_harmonics: int, sideband_orders: int = 1
) -> np.ndarray:
    """Regular meshing signal: TSA restricted to shaft orders 1..H, mesh orders and sidebands.

    The mean is not kept. ``TSA - regular`` is :func:`difference_signal`.

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z`` of that gear (mesh order), ``2 Z < M``.
    shaft_harmonics : int
        ``H``: shaft orders ``1..H`` kept (0: none).
    sideband_orders : int, default 1
        ``S``: sidebands ``n Z +- 1..S`` kept around every mesh order (1 in Zakrajsek
        et al. 1993).

    Returns
    -------
    ndarray, shape (M,)
        Regular signal, in units of the TSA.

    Raises
    ------
    InputError
        If ``teeth``, ``shaft_harmonics`` or ``sideband_orders`` is not an integer of
        the allowed range, or ``M <= 2 Z`` (the mesh order is above Nyquist).

    References
    ----------
    Zakrajsek et al. (1993), sec. "Difference signal"; Decker (2002).
    """
    m = t.samples_per_rev
    keep = order_mask(m, teeth=teeth, shaft_harmonics=shaft_harmonics,
                       sideband_orders=sideband_orders)
    keep[0] = False
    return remove_orders(t.average, ~keep)


def difference_signal(
    t: TSA, *, teeth: int, shaft_harmonics: int, sideband_orders: int = 1
) -> np.ndarray:
    """Difference signal ``d = TSA - regular`` (zero mean; Zakrajsek et al. 1993).

    The TSA without its mean, shaft orders ``1..H``, mesh orders ``n Z`` and their
    sidebands ``n Z +- 1..S`` (see :func:`regular_signal`); what is left is the part of
    the average not explained by normal meshing, whose moments FM4, M6A and M8A measure.

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z`` of that gear (mesh order), ``2 Z < M``.
    shaft_harmonics : int
        ``H``: shaft orders ``1..H`` removed (0: none).
    sideband_orders : int, default 1
        ``S``: sidebands ``n Z +- 1..S`` removed around every mesh order (1 in Zakrajsek
        et al. 1993).

    Returns
    -------
    ndarray, shape (M,)
        Difference signal, in units of the TSA.

    Raises
    ------
    InputError
        If ``teeth``, ``shaft_harmonics`` or ``sideband_orders`` is not an integer of
        the allowed range, or ``M <= 2 Z``.

    References
    ----------
    Zakrajsek et al. (1993); Decker (2002).

    Examples
    --------
    Mesh order 10, shaft order 1 and an extra order 5: only order 5 remains.

    >>> import numpy as np
    >>> j = np.arange(64)
    >>> extra = 0.1 * np.cos(2 * np.pi * 5 * j / 64)
    >>> avg = 2 * np.cos(2 * np.pi * 10 * j / 64) + 0.5 * np.cos(2 * np.pi * j / 64) + extra
    >>> d = difference_signal(TSA(avg, 1, 1.0), teeth=10, shaft_harmonics=2)
    >>> bool(np.allclose(d, extra))
    True
    """
    mask = order_mask(t.samples_per_rev, teeth=teeth, shaft_harmonics=shaft_harmonics,
                       sideband_orders=sideband_orders)
    return remove_orders(t.average, mask)


def residual_signal(t: TSA, *, teeth: int, shaft_harmonics: int) -> np.ndarray:
    """Residual ``r = TSA - (shaft orders 1..H + mesh orders n Z)`` (Zakrajsek et al. 1993).

    Unlike :func:`difference_signal` the mesh sidebands are kept, so that the sideband
    growth of a developing fault counts in NA4 (:func:`na4`). The mean is removed too.

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z`` of that gear (mesh order), ``2 Z < M``.
    shaft_harmonics : int
        ``H``: shaft orders ``1..H`` removed (0: none).

    Returns
    -------
    ndarray, shape (M,)
        Residual signal, in units of the TSA.

    Raises
    ------
    InputError
        If ``teeth`` or ``shaft_harmonics`` is not an integer of the allowed range, or
        ``M <= 2 Z``.

    References
    ----------
    Zakrajsek et al. (1993); Decker (2002).
    """
    mask = order_mask(t.samples_per_rev, teeth=teeth, shaft_harmonics=shaft_harmonics,
                       sideband_orders=0)
    return remove_orders(t.average, mask)


def _moment_ratio(d: np.ndarray, power: int, name: str) -> float:
    a = as_signal(d, name=name)
    c = a - a.mean()
    m2 = np.mean(c * c)
    if m2 == 0.0:
        raise InputError(name, "zero variance", f"{name} needs a signal with non-zero variance")
    # the ratio of the centred signal scaled to unit variance: the same number, without
    # the underflow of m2**4 (a healthy simulated difference signal is ~1e-40)
    return float(np.mean((c / np.sqrt(m2)) ** power))


def fm0(t: TSA, *, teeth: int) -> float:
    r"""FM0 = :math:`(\max \bar y - \min \bar y) / \sum_n A_{nZ}` (dimensionless; Stewart 1977).

    ``A_{nZ}``: amplitudes of all mesh orders ``n Z`` up to ``M/2`` in the TSA
    (:meth:`TSA.order_amplitudes`). The peak-to-peak of the average grows with a local
    fault (a tooth crack adds a once-per-revolution transient) while the mesh harmonics
    hardly change, so FM0 rises; general wear raises both and leaves it about constant.

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z`` of that gear, ``1 <= Z <= M/2``.

    Returns
    -------
    float
        FM0 (dimensionless); 2 for a TSA that is one pure mesh tone.

    Raises
    ------
    InputError
        If ``teeth`` is not an integer in ``[1, M/2]``, or every mesh-order amplitude is
        zero.

    References
    ----------
    Stewart (1977); reviewed in Zakrajsek et al. (1993).

    Examples
    --------
    A pure mesh tone :math:`A\cos(2\pi Z j/M)` has peak-to-peak :math:`2A` and one mesh
    amplitude :math:`A`:

    >>> import numpy as np
    >>> j = np.arange(64)
    >>> round(fm0(TSA(np.cos(2 * np.pi * 10 * j / 64), 1, 1.0), teeth=10), 6)
    2.0
    """
    amps = t.order_amplitudes()
    if int(teeth) != teeth or not 1 <= teeth < amps.size:
        raise InputError("teeth", teeth, f"must be an integer in [1, {amps.size - 1}] (M/2)")
    s = float(amps[teeth::teeth].sum())
    if s == 0.0:
        raise InputError("tsa", "no mesh harmonics", "FM0 needs non-zero mesh-order amplitudes")
    return float((t.average.max() - t.average.min()) / s)


def fm4(d: np.ndarray) -> float:
    r"""FM4 = :math:`N\sum(d_i-\bar d)^4 / [\sum(d_i-\bar d)^2]^2` of the difference signal.

    About 3 for a healthy gear (Gaussian difference signal); a localised fault (crack,
    pit) puts one or a few peaks into the difference signal and raises it.

    Parameters
    ----------
    d : array_like
        Difference signal (:func:`difference_signal`), 1-D, any units; its mean is
        removed.

    Returns
    -------
    float
        FM4 (dimensionless): 3 for Gaussian noise, 1.5 for a pure tone.

    Raises
    ------
    InputError
        If ``d`` is not a valid signal or has zero variance.

    References
    ----------
    Stewart (1977); reviewed in Zakrajsek et al. (1993).

    Examples
    --------
    A difference signal that is one pure tone (no Gaussian part):

    >>> import numpy as np
    >>> j = np.arange(64)
    >>> round(fm4(0.1 * np.cos(2 * np.pi * 5 * j / 64)), 6)
    1.5
    """
    return _moment_ratio(d, 4, "difference")


def m6a(d: np.ndarray) -> float:
    r"""M6A = :math:`N^2\sum(d_i-\bar d)^6 / [\sum(d_i-\bar d)^2]^3` (Martin 1989).

    Normalised sixth moment of the difference signal, more sensitive than FM4 to a few
    large peaks (surface damage); 15 for Gaussian noise.

    Parameters
    ----------
    d : array_like
        Difference signal (:func:`difference_signal`), 1-D, any units; its mean is
        removed.

    Returns
    -------
    float
        M6A (dimensionless): 15 for Gaussian noise, 2.5 for a pure tone.

    Raises
    ------
    InputError
        If ``d`` is not a valid signal or has zero variance.

    References
    ----------
    Martin (1989); reviewed in Zakrajsek et al. (1993).

    Examples
    --------
    For a tone, :math:`\overline{\cos^6} / (\overline{\cos^2})^3 = (5/16) / (1/8)`:

    >>> import numpy as np
    >>> j = np.arange(64)
    >>> round(m6a(np.cos(2 * np.pi * 5 * j / 64)), 6)
    2.5
    """
    return _moment_ratio(d, 6, "difference")


def m8a(d: np.ndarray) -> float:
    r"""M8A = :math:`N^3\sum(d_i-\bar d)^8 / [\sum(d_i-\bar d)^2]^4` (Martin 1989).

    Normalised eighth moment of the difference signal; 105 for Gaussian noise.

    Parameters
    ----------
    d : array_like
        Difference signal (:func:`difference_signal`), 1-D, any units; its mean is
        removed.

    Returns
    -------
    float
        M8A (dimensionless): 105 for Gaussian noise, 4.375 for a pure tone.

    Raises
    ------
    InputError
        If ``d`` is not a valid signal or has zero variance.

    References
    ----------
    Martin (1989); reviewed in Zakrajsek et al. (1993).

    Examples
    --------
    For a tone, :math:`\overline{\cos^8} / (\overline{\cos^2})^4 = (35/128) / (1/16)`:

    >>> import numpy as np
    >>> j = np.arange(64)
    >>> round(m8a(np.cos(2 * np.pi * 5 * j / 64)), 6)
    4.375
    """
    return _moment_ratio(d, 8, "difference")


def _history_kurtosis(records: Sequence[np.ndarray], name: str, what: str, needs: str) -> float:
    """Kurtosis of the last record over the squared run-average variance (NA4, NB4).

    ``name`` names the argument (``"residuals"``), ``what`` one record (``"residual"``)
    and ``needs`` starts the zero-variance message (``"NA4 needs a residual"``).
    """
    rs = [as_signal(r, name=f"{name}[{j}]") for j, r in enumerate(records)]
    if not rs:
        raise InputError(name, "[]", f"must hold at least the current {what}")
    n = rs[-1].size
    for j, r in enumerate(rs):
        if r.size != n:
            raise InputError(f"{name}[{j}].length", r.size, f"must equal {n} (current record)")
    var = np.mean([np.mean((r - r.mean()) ** 2) for r in rs])
    if var == 0.0:
        raise InputError(name, "zero variance", f"{needs} with variance > 0")
    c = rs[-1] - rs[-1].mean()
    return float(np.mean(c**4) / var**2)


def na4(residuals: Sequence[np.ndarray]) -> float:
    r"""NA4 of the last residual normalised by the run-average residual variance.

    .. math:: \mathrm{NA4}(M) = \frac{N \sum_i (r_{iM}-\bar r_M)^4}
              {\left[\frac1M \sum_{j=1}^{M} \sum_i (r_{ij}-\bar r_j)^2\right]^2}

    with ``r_j`` the residual of record ``j`` (``j = M`` current, earlier ones the history,
    e.g. the healthy baseline), all of the same length ``N`` (Zakrajsek et al. 1993).
    With one record it equals the kurtosis of the residual. Normalising by the run
    average rather than the current variance lets NA4 keep growing as damage spreads
    (about 3 for a healthy gear).

    Parameters
    ----------
    residuals : sequence of array_like
        Residual signals (:func:`residual_signal`) of records ``1..M``, oldest first, the
        current record last; all 1-D, of equal length, any (common) units.

    Returns
    -------
    float
        NA4 (dimensionless).

    Raises
    ------
    InputError
        If ``residuals`` is empty, a residual is not a valid signal, the lengths differ,
        or the average variance is zero.

    References
    ----------
    Zakrajsek, Townsend & Decker (1993), NASA TM-105950.

    Examples
    --------
    One record: the kurtosis of the residual (1.5 for a tone). A baseline with twice
    the amplitude makes the average variance :math:`2.5\sigma^2`, so NA4 =
    :math:`1.5 / 2.5^2 = 0.24`:

    >>> import numpy as np
    >>> r = np.cos(2 * np.pi * 5 * np.arange(64) / 64)
    >>> round(na4([r]), 6), round(na4([2 * r, r]), 6)
    (1.5, 0.24)
    """
    return _history_kurtosis(residuals, "residuals", "residual", "NA4 needs a residual")


@dataclass(frozen=True)
class Indicators:
    """TSA-based condition indicators (all dimensionless), from :func:`condition_indicators`.

    Parameters
    ----------
    fm0 : float
        FM0, peak-to-peak of the TSA over the sum of mesh-order amplitudes
        (:func:`fm0`; Stewart 1977).
    fm4 : float
        FM4, kurtosis of the difference signal (:func:`fm4`; Stewart 1977); 3 healthy.
    na4 : float
        NA4, kurtosis of the residual normalised by the run-average variance
        (:func:`na4`; Zakrajsek et al. 1993); 3 healthy.
    m6a : float
        M6A, normalised sixth moment of the difference signal (:func:`m6a`; Martin
        1989); 15 for Gaussian noise.
    m8a : float
        M8A, normalised eighth moment of the difference signal (:func:`m8a`; Martin
        1989); 105 for Gaussian noise.
    n_averages : int
        Number of revolutions averaged in the TSA.
    samples_per_rev : int
        Samples per revolution ``M`` of the TSA.
    shaft_harmonics : int
        ``H``, shaft orders ``1..H`` removed for the difference and residual signals.
    sideband_orders : int
        ``S``, mesh sidebands ``n Z +- 1..S`` removed for the difference signal.
    """

    fm0: float
    fm4: float
    na4: float
    m6a: float
    m8a: float
    n_averages: int
    samples_per_rev: int
    shaft_harmonics: int
    sideband_orders: int

    def to_dict(self) -> dict:
        """JSON-serialisable dict.

        Returns
        -------
        dict
            Field name to value, for every field.
        """
        return dict(self.__dict__)


def condition_indicators(
    t: TSA,
    *,
    teeth: int,
    shaft_harmonics: int,
    sideband_orders: int,
    history: Sequence[np.ndarray] = (),
) -> tuple[Indicators, np.ndarray, np.ndarray]:
    """FM0, FM4, NA4, M6A and M8A of one TSA.

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear of ``teeth`` teeth.
    teeth : int
        Tooth count ``Z`` of that gear (mesh order).
    shaft_harmonics : int
        ``H``: shaft orders 1..H removed for the residual and difference signals.
    sideband_orders : int
        ``S``: sidebands ``n Z +- 1..S`` removed for the difference signal (1 in Zakrajsek
        et al. 1993).
    history : sequence of ndarray
        Earlier residual signals (same length) for NA4's run-average variance, e.g. the
        residual of a healthy baseline; empty for a single record.

    Returns
    -------
    indicators : Indicators
        FM0, FM4, NA4, M6A, M8A (dimensionless) and the settings used.
    difference : ndarray, shape (M,)
        Difference signal (:func:`difference_signal`), units of the TSA.
    residual : ndarray, shape (M,)
        Residual signal (:func:`residual_signal`), units of the TSA.

    Raises
    ------
    InputError
        If an order argument is out of range, the difference or residual signal has
        zero variance, the history residuals differ in length, or the TSA has no mesh
        harmonic (FM0).

    Examples
    --------
    Mesh order 10 and an extra tone at order 5 (the "fault"): the difference and
    residual signals are that tone, so FM4 = NA4 = 1.5.

    >>> import numpy as np
    >>> j = np.arange(64)
    >>> avg = 2 * np.cos(2 * np.pi * 10 * j / 64) + 0.1 * np.cos(2 * np.pi * 5 * j / 64)
    >>> ind, d, r = condition_indicators(TSA(avg, 1, 1.0), teeth=10, shaft_harmonics=2,
    ...                                  sideband_orders=1)
    >>> round(ind.fm4, 6), round(ind.na4, 6), round(ind.m6a, 6), round(ind.m8a, 6)
    (1.5, 1.5, 2.5, 4.375)
    """
    d = difference_signal(t, teeth=teeth, shaft_harmonics=shaft_harmonics,
                          sideband_orders=sideband_orders)
    r = residual_signal(t, teeth=teeth, shaft_harmonics=shaft_harmonics)
    ind = Indicators(
        fm0=fm0(t, teeth=teeth), fm4=fm4(d), na4=na4([*history, r]), m6a=m6a(d), m8a=m8a(d),
        n_averages=t.n_averages, samples_per_rev=t.samples_per_rev,
        shaft_harmonics=int(shaft_harmonics), sideband_orders=int(sideband_orders),
    )
    return ind, d, r
