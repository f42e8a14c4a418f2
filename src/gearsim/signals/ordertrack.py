r"""Computed order tracking for varying speed and the time-synchronous average on it.

Given a :class:`~gearsim.signals.speed.SpeedProfile` (tacho, tacholess estimate or a
given constant speed), the record is resampled at ``M`` equal angle steps per
revolution over the whole revolutions the profile and the record share: the times of
the angles ``k0 + j / M`` come from the profile's time-angle spline, and the signal at
those times from :func:`gearsim.signals.tsa.cubic_resample` (Potter 1990; Fyfe & Munck
1997). In the angle domain a shaft order is a fixed "frequency" however the speed
varies, so the order spectrum has sharp lines and the revolutions can be averaged.

Quality of the tracked TSA. For ``R`` revolutions ``y_r`` of ``M`` samples, let
:math:`Y_r(Z)` be the DFT of revolution ``r`` at the mesh order ``Z``. The TSA keeps
the coherent mean :math:`|\frac1R\sum_r Y_r(Z)|`; the order spectrum of the tracked
record averaged over revolutions (Bartlett, one-revolution segments) has the mesh-order
amplitude :math:`\sqrt{\frac1R\sum_r |Y_r(Z)|^2}`, which does not depend on the phase
of the mesh tone from one revolution to the next. The quality

.. math:: Q = \frac{|\frac1R \sum_r Y_r(Z)|}{\sqrt{\frac1R \sum_r |Y_r(Z)|^2}}

is the share of the spectral mesh-order amplitude the average keeps: 1 when the mesh
tone repeats with the same phase every tracked revolution, about :math:`1/\sqrt R` when
its phase drifts at random (wrong speed). (The single DFT of the whole ``R``-revolution
record at order ``Z`` equals the TSA's by construction, so it cannot serve as the
reference.) Uncorrelated noise of power :math:`\sigma^2` per DFT bin lowers ``Q`` by the
factor :math:`(1 + \sigma^2/A^2)^{-1/2}` for a mesh amplitude ``A``.

References
----------
.. [P90] R. Potter, "A new order tracking method for rotating machinery", *Sound and
   Vibration* 24 (9) (1990) 30-34.
.. [F97] K. R. Fyfe, E. D. S. Munck, "Analysis of computed order tracking", *Mech. Syst.
   Signal Process.* 11 (1997) 187-205.
.. [M87] P. D. McFadden, "A revised model for the extraction of periodic waveforms by
   time domain averaging", *Mech. Syst. Signal Process.* 1 (1987) 83-95.
.. [B05] F. Bonnardot, M. El Badaoui, R. B. Randall, J. Danière, F. Guillet, "Use of the
   acceleration signal of a gearbox in order to perform angular resampling (with
   limited speed fluctuation)", *Mech. Syst. Signal Process.* 19 (2005) 766-785.
.. [C07] F. Combet, L. Gelman, "An automated methodology for performing time
   synchronous averaging of a gearbox signal without speed sensor", *Mech. Syst.
   Signal Process.* 21 (2007) 2590-2606.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs, check_int
from gearsim.signals.speed import SpeedProfile
from gearsim.signals.tsa import TSA, _order_amplitudes, cubic_resample

__all__ = ["order_track", "order_spectrum", "tracked_tsa", "default_samples_per_rev"]


def _check_profile(profile: object) -> SpeedProfile:
    if not isinstance(profile, SpeedProfile):
        raise InputError("profile", type(profile).__name__, "must be a SpeedProfile")
    return profile


def _revolutions(a: np.ndarray, fs: float, profile: SpeedProfile) -> tuple[int, int]:
    """First and last whole revolution (angles k0 < k1) inside record and profile."""
    t_lo = max(float(profile.time[0]), 0.0)
    t_hi = min(float(profile.time[-1]), (a.size - 1) / fs)
    if not t_hi > t_lo:
        raise InputError("profile", f"[{profile.time[0]:g}, {profile.time[-1]:g}] s",
                         f"must overlap the record [0, {(a.size - 1) / fs:g}] s")
    th_lo, th_hi = profile.angle_at(np.array([t_lo, t_hi]))
    k0 = math.ceil(th_lo - 1e-9)
    k1 = math.floor(th_hi + 1e-9)
    if k1 - k0 < 1:
        raise InputError("profile", f"{th_hi - th_lo:.4g} rev inside the record",
                         "must span at least one whole revolution")
    return k0, k1


def default_samples_per_rev(fs: float, profile: SpeedProfile, *, teeth: int = 1) -> int:
    """Samples per revolution that do not undersample the record anywhere.

    Parameters
    ----------
    fs : float
        Sampling rate of the record [Hz].
    profile : SpeedProfile
        Speed profile of the shaft.
    teeth : int
        Highest order that must be held is ``2 teeth`` (twice the mesh order).

    Returns
    -------
    int
        The smallest power of two >= ``max(fs / f_min, 4 teeth)``, ``f_min`` the lowest
        shaft frequency [Hz] of the profile (outside its ``edge``): the angle sampling is then at least as
        dense as the time sampling at every speed, so resampling adds no aliasing.

    Raises
    ------
    InputError
        If ``fs`` is not > 0, ``profile`` is not a SpeedProfile or ``teeth`` < 1.

    References
    ----------
    Fyfe & Munck (1997): angle-domain sampling rate and aliasing in computed order
    tracking.
    """
    fs = check_fs(fs)
    profile = _check_profile(profile)
    teeth = check_int("teeth", teeth, minimum=1)
    inner = (profile.time >= profile.time[0] + profile.edge) & (
        profile.time <= profile.time[-1] - profile.edge)
    f_min = float(profile.frequency[inner].min() if inner.any() else profile.frequency.min())
    need = max(fs / f_min, 4.0 * teeth)
    return int(2 ** math.ceil(math.log2(need)))


def order_track(
    x: np.ndarray, fs: float, profile: SpeedProfile, *, samples_per_rev: int
) -> tuple[np.ndarray, np.ndarray]:
    """Resample a record at equal shaft-angle steps (computed order tracking).

    Parameters
    ----------
    x : array_like
        Record (any units), sampled at ``fs``.
    fs : float
        Sampling rate [Hz].
    profile : SpeedProfile
        Shaft angle against time (:func:`~gearsim.signals.speed.speed_from_tacho`,
        :func:`~gearsim.signals.speed.estimate_speed` or
        :meth:`~gearsim.signals.speed.SpeedProfile.constant`).
    samples_per_rev : int
        ``M`` samples per revolution (>= 4); :func:`default_samples_per_rev` avoids
        undersampling.

    Returns
    -------
    x_angle : ndarray, shape (R M,)
        Record at the angles (units of ``x``), ``R`` whole revolutions.
    angle : ndarray, shape (R M,)
        Shaft angles [rev], ``k0 + j / M``, ``k0`` the first whole revolution of the
        profile inside the record.

    Raises
    ------
    InputError
        If ``x`` or ``fs`` is invalid, ``samples_per_rev < 4``, or the profile does not
        span a whole revolution inside the record.

    References
    ----------
    Potter (1990); Fyfe & Munck (1997).
    """
    a = as_signal(x, name="x", min_length=4)
    fs = check_fs(fs)
    profile = _check_profile(profile)
    m = check_int("samples_per_rev", samples_per_rev, minimum=4)
    k0, k1 = _revolutions(a, fs, profile)
    angle = k0 + np.arange((k1 - k0) * m) / m
    times = np.clip(profile.times_at(angle), 0.0, (a.size - 1) / fs)
    return cubic_resample(a, fs, times), angle


def order_spectrum(
    x: np.ndarray, fs: float, profile: SpeedProfile, *, samples_per_rev: int
) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude spectrum against shaft order of the order-tracked record.

    The DFT (rectangular window) of the ``R`` whole revolutions of
    :func:`order_track`: bin ``b`` is order ``b / R``, so every integer order falls on a
    bin and a tone ``A cos(2 pi o theta)`` of integer order ``o`` reads ``A``.

    Parameters
    ----------
    x : array_like
        Record (any units).
    fs : float
        Sampling rate [Hz].
    profile : SpeedProfile
        Shaft angle against time.
    samples_per_rev : int
        ``M`` samples per revolution (>= 4); the orders reach ``M / 2``.

    Returns
    -------
    orders : ndarray
        Shaft orders ``b / R`` (dimensionless), ``b = 0 .. R M / 2``.
    amplitude : ndarray
        Peak amplitude per order (units of ``x``): ``2 |X_b| / (R M)``, halved at order
        0 and at the Nyquist order.

    Raises
    ------
    InputError
        As :func:`order_track`.

    References
    ----------
    Potter (1990); Fyfe & Munck (1997).
    """
    y, angle = order_track(x, fs, profile, samples_per_rev=samples_per_rev)
    n_rev = y.size // int(samples_per_rev)
    return np.arange(y.size // 2 + 1) / n_rev, _order_amplitudes(y)


def tracked_tsa(
    x: np.ndarray,
    fs: float,
    profile: SpeedProfile,
    *,
    teeth: int,
    samples_per_rev: int | None = None,
) -> tuple[TSA, float]:
    """Time-synchronous average on the tracked angle, with the share of the mesh it keeps.

    Parameters
    ----------
    x : array_like
        Record (any units).
    fs : float
        Sampling rate [Hz].
    profile : SpeedProfile
        Angle of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z`` of that gear: the mesh order used for the quality.
    samples_per_rev : int, optional
        ``M``, > ``2 Z``; default :func:`default_samples_per_rev`.

    Returns
    -------
    TSA
        Average of the ``R`` tracked revolutions (units of ``x``), ``n_averages = R``,
        ``shaft_frequency`` = mean over them [Hz].
    quality : float
        :math:`Q \\in [0, 1]` (module docstring): coherent over power-averaged
        mesh-order amplitude; the share of the spectral mesh amplitude the average
        keeps.

    Raises
    ------
    InputError
        As :func:`order_track`; if ``teeth`` is not an integer in ``[1, M/2)``; or if
        the record has no mesh-order content (zero amplitude at order ``Z``).

    References
    ----------
    McFadden (1987) (averaging); Fyfe & Munck (1997) (tracking); Bonnardot et al.
    (2005) and Combet & Gelman (2007) (averaging on an angle estimated from the mesh
    phase).
    """
    teeth = check_int("teeth", teeth, minimum=1)
    if samples_per_rev is None:
        samples_per_rev = default_samples_per_rev(fs, profile, teeth=teeth)
    m = check_int("samples_per_rev", samples_per_rev, minimum=4)
    if not 2 * teeth < m:
        raise InputError("samples_per_rev", m, f"must exceed 2 x teeth = {2 * teeth}")
    y, angle = order_track(x, fs, profile, samples_per_rev=m)
    rows = y.reshape(-1, m)
    n_rev = rows.shape[0]
    y_z = scipy.fft.rfft(rows, axis=1)[:, teeth]
    power = math.sqrt(float(np.mean(np.abs(y_z) ** 2)))
    if power == 0.0:
        raise InputError("x", "no mesh-order content", f"order {teeth} has zero amplitude")
    quality = float(abs(np.mean(y_z)) / power)
    t0, t1 = profile.times_at(np.array([angle[0], angle[0] + n_rev]))
    avg = TSA(average=rows.mean(axis=0), n_averages=n_rev,
              shaft_frequency=float(n_rev / (t1 - t0)))
    return avg, quality
