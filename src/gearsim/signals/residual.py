r"""Mesh residual of a whole record: the record without its mean and mesh harmonics.

The residual signal of Zakrajsek, Townsend & Decker (1993) removes the shaft and mesh
orders from a time-synchronous average; :func:`mesh_residual` removes the mean and every
mesh harmonic ``n f_m`` from the record itself, so that a disturbance that repeats once
per revolution (the engagement of a cracked tooth) stays visible in every revolution
instead of being averaged.

The record is resampled to ``M`` equal angle steps per revolution of the shaft of
frequency ``f_r`` over the ``R`` whole revolutions it holds
(:func:`gearsim.signals.tsa.angular_resample`), so that mesh harmonic ``n`` falls
exactly on bin ``n Z R`` (``Z = f_m / f_r`` teeth) of the ``R M``-point DFT and the
sidebands ``n f_m +- k f_r`` on the bins ``R`` apart. The mean and the mesh-harmonic bins
are set to zero (:func:`gearsim.signals.tsa.remove_orders`) and the result is resampled
back to the sample times with the same cubic spline
(:func:`gearsim.signals.tsa.cubic_resample`).

References
----------
.. [Z93] J. J. Zakrajsek, D. P. Townsend, H. J. Decker, "An analysis of gear fault
   detection methods as applied to pitting fatigue failure data", NASA TM-105950, 1993.
.. [M87] P. D. McFadden, "A revised model for the extraction of periodic waveforms by
   time domain averaging", *Mech. Syst. Signal Process.* 1 (1987) 83-95.
"""

from __future__ import annotations

import numpy as np

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs, check_positive
from gearsim.signals.tsa import (
    angular_resample,
    cubic_resample,
    order_mask,
    remove_orders,
    revolution_times_from_speed,
)

__all__ = ["mesh_residual", "residual_samples_per_rev"]


def residual_samples_per_rev(fs: float, shaft_frequency: float, teeth: int) -> int:
    """Angle samples per revolution used by :func:`mesh_residual`.

    The smallest power of two that is at least the number of time samples per
    revolution ``fs / f_r`` (no down-sampling) and at least ``8 Z`` (eight samples per
    mesh period, so that the mesh orders lie well below the Nyquist order).

    Parameters
    ----------
    fs : float
        Sampling rate [Hz].
    shaft_frequency : float
        ``f_r`` [Hz].
    teeth : int
        ``Z``.

    Returns
    -------
    int
        ``M``.
    """
    return 1 << int(np.ceil(np.log2(max(8 * teeth, fs / shaft_frequency))))


def mesh_residual(
    x: np.ndarray, fs: float, *, mesh_frequency: float, shaft_frequency: float
) -> np.ndarray:
    """The record with its mean and every mesh harmonic ``n f_m`` removed.

    See the module docstring for the method. Samples after the last whole revolution of
    the shaft are set to zero. A record of ``N`` samples spans ``N / fs`` seconds, so a
    revolution that ends within one sample interval after the last sample counts as
    whole.

    Parameters
    ----------
    x : array_like
        Record (any units), sampled at ``fs`` from time 0 at constant shaft speed.
    fs : float
        Sampling rate [Hz].
    mesh_frequency : float
        ``f_m`` [Hz]; ``f_m / f_r`` must be a whole number of teeth.
    shaft_frequency : float
        ``f_r`` of the shaft whose revolutions define the resampling [Hz].

    Returns
    -------
    ndarray
        Residual (units of ``x``), same length as ``x``.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal, a frequency is not > 0, ``f_m / f_r`` is not a
        whole number, or the record is shorter than one revolution.

    References
    ----------
    Zakrajsek, Townsend & Decker (1993), residual signal (here of the record, without
    removing shaft orders); McFadden (1987) for the angular resampling.
    """
    a = as_signal(x)
    fs = check_fs(fs)
    f_m = check_positive("mesh_frequency", mesh_frequency)
    f_r = check_positive("shaft_frequency", shaft_frequency)
    z = f_m / f_r
    if abs(z - round(z)) > 1e-6 * z:
        raise InputError("mesh_frequency / shaft_frequency", z, "must be a whole number of teeth")
    z = int(round(z))
    pulses = revolution_times_from_speed(a.size / fs, shaft_frequency=f_r)
    revs = pulses.size - 1
    if revs < 1:
        raise InputError("record duration", f"{a.size / fs:.4g} s",
                         f"must cover one revolution ({1 / f_r:.4g} s)")
    m = residual_samples_per_rev(fs, f_r, z)
    rows = angular_resample(a, fs, pulses=pulses, pulses_per_rev=1, samples_per_rev=m)
    mask = order_mask(revs * m, teeth=z, shaft_harmonics=0, sideband_orders=0,
                      revolutions=revs)
    res = remove_orders(rows.ravel(), mask)
    out = np.zeros_like(a)
    t = np.arange(a.size) / fs
    inside = t <= (revs * m - 1) / (m * f_r)
    out[inside] = cubic_resample(res, m * f_r, t[inside])
    return out
