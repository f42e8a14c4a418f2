r"""Further gear condition indicators: NB4, energy ratio, sideband index and level factor.

Complements FM0, FM4, NA4, M6A and M8A of :mod:`~gearsim.signals.tsa`. Definitions, with
``M`` samples per revolution of a time-synchronous average (TSA), ``A_o`` the amplitude
of shaft order ``o`` (:meth:`gearsim.signals.tsa.TSA.order_amplitudes`) and ``Z`` the
tooth count:

* **NB4** (Zakrajsek, Handschuh & Decker 1994): NA4 applied to the envelope of the signal
  band-passed about the mesh frequency,

  .. math:: \mathrm{NB4} = \frac{N\sum_i (s_{iM} - \bar s_M)^4}
     {\left[\frac1M\sum_{j=1}^{M}\sum_i (s_{ij} - \bar s_j)^2\right]^2},

  ``s_j`` the envelope of record ``j`` (the current one last); damage that changes the
  load on a few teeth makes the envelope spiky.
* **Energy ratio** (Swansson 1980): :math:`\mathrm{ER} = \mathrm{RMS}(d) /
  \mathrm{RMS}(y_r)`, ``d`` the difference signal and ``y_r`` the regular signal
  (:func:`~gearsim.signals.tsa.difference_signal`,
  :func:`~gearsim.signals.tsa.regular_signal`); heavy distributed wear moves energy
  from the regular meshing into the difference.
* **Sideband index**: :math:`\mathrm{SI} = (A_{nZ-1} + A_{nZ+1}) / 2`, the mean of the two
  first-order sidebands of mesh harmonic ``n`` (``n = 1`` in the sources), in signal
  units.
* **Sideband level factor**: :math:`\mathrm{SLF} = (A_{nZ-1} + A_{nZ+1}) / \sigma_{TSA}`,
  the sum of the two first-order sidebands over the standard deviation (RMS about the
  mean) of the TSA, dimensionless.

SI and SLF are given in these forms by Lebold et al. (2000), the review that fixes the
pre-processing of each indicator; the 1990s NASA reports (Zakrajsek et al. 1993, 1994;
Decker 2002) use the same first-order sidebands about the fundamental mesh order.

References
----------
.. [Z94] J. J. Zakrajsek, R. F. Handschuh, H. J. Decker, "Application of fault detection
   techniques to spiral bevel gear fatigue data", NASA TM-106467, 1994 (NB4).
.. [Z93] J. J. Zakrajsek, D. P. Townsend, H. J. Decker, "An analysis of gear fault
   detection methods as applied to pitting fatigue failure data", NASA TM-105950, 1993
   (NA4, whose normalisation NB4 takes over).
.. [S80] N. S. Swansson, "Application of vibration signal analysis techniques to signal
   monitoring", Conf. on Friction and Wear in Engineering, Institution of Engineers,
   Australia, 1980, 262-267 (energy ratio).
.. [L00] M. Lebold, K. McClintic, R. Campbell, C. Byington, K. Maynard, "Review of
   vibration analysis methods for gearbox diagnostics and prognostics", Proc. 54th
   Meeting of the Society for Machinery Failure Prevention Technology, 2000, 623-634.
.. [D02] H. J. Decker, "Crack detection for aerospace quality spur gears", NASA
   TM-2002-211492, 2002.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from gearsim.errors import InputError
from gearsim.signals._checks import check_int
from gearsim.signals.tsa import TSA, _history_kurtosis, difference_signal, regular_signal

__all__ = ["nb4", "energy_ratio", "sideband_index", "sideband_level_factor"]


def nb4(envelopes: Sequence[np.ndarray]) -> float:
    r"""NB4: kurtosis of the current envelope normalised by the run-average envelope variance.

    .. math:: \mathrm{NB4} = \frac{N\sum_i (s_{iM} - \bar s_M)^4}
       {\left[\frac1M\sum_{j=1}^{M}\sum_i (s_{ij} - \bar s_j)^2\right]^2}

    The envelopes ``s_j`` are those of the signal (its TSA in the source) band-passed
    about the mesh frequency, e.g. ``demodulate_tsa(t, teeth=Z, sidebands=k).amplitude``
    (:mod:`~gearsim.signals.demodulation`). With one record NB4 is the kurtosis of the
    envelope.

    Parameters
    ----------
    envelopes : sequence of array_like
        Envelopes of records ``1..M``, oldest first, the current record last; 1-D, of
        equal length, any (common) units.

    Returns
    -------
    float
        NB4 (dimensionless); about 3 when the envelope fluctuates like Gaussian noise.

    Raises
    ------
    InputError
        If ``envelopes`` is empty, an envelope is not a valid signal, the lengths differ,
        or the average variance is zero.

    References
    ----------
    Zakrajsek, Handschuh & Decker (1994), NASA TM-106467; Lebold et al. (2000).

    Examples
    --------
    Envelope :math:`1 + 0.5\cos`: fluctuation variance 0.125, kurtosis 1.5. With a
    baseline envelope :math:`1 + \cos` (variance 0.5) the average variance is 0.3125 and
    NB4 :math:`= (3/8)(0.5)^4 / 0.3125^2 = 0.24`:

    >>> import numpy as np
    >>> c = np.cos(2 * np.pi * 5 * np.arange(64) / 64)
    >>> round(nb4([1 + 0.5 * c]), 6), round(nb4([1 + c, 1 + 0.5 * c]), 6)
    (1.5, 0.24)
    """
    return _history_kurtosis(envelopes, "envelopes", "envelope", "NB4 needs an envelope")


def energy_ratio(
    t: TSA, *, teeth: int, shaft_harmonics: int, sideband_orders: int = 1
) -> float:
    r"""Energy ratio :math:`\mathrm{ER} = \mathrm{RMS}(d) / \mathrm{RMS}(y_r)` (Swansson 1980).

    ``y_r``: the regular signal (shaft orders ``1..H``, mesh orders ``n Z`` and sidebands
    ``n Z +- 1..S``, mean excluded); ``d = TSA - mean - y_r`` the difference signal.

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z`` of that gear, ``2 Z < M``.
    shaft_harmonics : int
        ``H``: shaft orders ``1..H`` counted as regular (0: none).
    sideband_orders : int, default 1
        ``S``: sidebands ``n Z +- 1..S`` counted as regular.

    Returns
    -------
    float
        ER (dimensionless); small for a healthy gear, it grows towards 1 and beyond as
        heavy wear spreads energy off the mesh orders.

    Raises
    ------
    InputError
        If an order argument is out of range, or the regular signal is zero (below
        1e-12 of the TSA's standard deviation: round-off).

    References
    ----------
    Swansson (1980); Lebold et al. (2000).

    Examples
    --------
    Mesh order 10 (amplitude 2), shaft order 1 (0.5) and an extra order 5 (0.1):
    :math:`\mathrm{ER} = (0.1/\sqrt2) / \sqrt{(2^2 + 0.5^2)/2} = 0.1/\sqrt{4.25}`:

    >>> import numpy as np
    >>> j = np.arange(64)
    >>> avg = (2 * np.cos(2 * np.pi * 10 * j / 64) + 0.5 * np.cos(2 * np.pi * j / 64)
    ...        + 0.1 * np.cos(2 * np.pi * 5 * j / 64))
    >>> round(energy_ratio(TSA(avg, 1, 1.0), teeth=10, shaft_harmonics=2), 6)
    0.048507
    """
    d = difference_signal(t, teeth=teeth, shaft_harmonics=shaft_harmonics,
                          sideband_orders=sideband_orders)
    r = regular_signal(t, teeth=teeth, shaft_harmonics=shaft_harmonics,
                       sideband_orders=sideband_orders)
    rms_r = float(np.sqrt(np.mean(r * r)))
    if rms_r <= 1e-12 * float(np.std(t.average)) or rms_r == 0.0:
        raise InputError("regular signal", "zero", "the energy ratio needs mesh or shaft orders "
                         "in the TSA (regular-signal RMS > 0)")
    return float(np.sqrt(np.mean(d * d))) / rms_r


def _first_sidebands(t: TSA, teeth: int, harmonic: int) -> tuple[float, float]:
    teeth = check_int("teeth", teeth, minimum=2)
    harmonic = check_int("harmonic", harmonic, minimum=1)
    amps = t.order_amplitudes()
    top = harmonic * teeth + 1
    if top >= amps.size - 1:
        raise InputError("samples_per_rev", t.samples_per_rev,
                         f"must exceed 2 x {top} to hold the sideband order {top} below Nyquist")
    return float(amps[top - 2]), float(amps[top])


def sideband_index(t: TSA, *, teeth: int, harmonic: int = 1) -> float:
    r"""Sideband index :math:`\mathrm{SI} = (A_{nZ-1} + A_{nZ+1}) / 2` (signal units).

    The mean amplitude of the two first-order sidebands of mesh harmonic ``n`` in the
    TSA's order spectrum (exact order bins, no window).

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z``, >= 2.
    harmonic : int, default 1
        Mesh harmonic ``n`` (1, the fundamental, in the sources).

    Returns
    -------
    float
        SI in units of the TSA.

    Raises
    ------
    InputError
        If ``teeth`` or ``harmonic`` is out of range, or the order ``n Z + 1`` is not below
        the Nyquist order ``M/2``.

    References
    ----------
    Lebold et al. (2000); Decker (2002).

    Examples
    --------
    Sidebands 0.3 (order 9) and 0.1 (order 11) about mesh order 10:

    >>> import numpy as np
    >>> j = np.arange(64) / 64
    >>> avg = (np.cos(2 * np.pi * 10 * j) + 0.3 * np.cos(2 * np.pi * 9 * j)
    ...        + 0.1 * np.sin(2 * np.pi * 11 * j))
    >>> round(sideband_index(TSA(avg, 1, 1.0), teeth=10), 6)
    0.2
    """
    lower, upper = _first_sidebands(t, teeth, harmonic)
    return 0.5 * (lower + upper)


def sideband_level_factor(t: TSA, *, teeth: int, harmonic: int = 1) -> float:
    r"""Sideband level factor :math:`\mathrm{SLF} = (A_{nZ-1} + A_{nZ+1}) / \sigma_{TSA}`.

    The sum of the two first-order sideband amplitudes of mesh harmonic ``n`` over the
    standard deviation of the TSA (its RMS about the mean; equal to its RMS when the mean
    is zero).

    Parameters
    ----------
    t : TSA
        Time-synchronous average of the shaft carrying the gear.
    teeth : int
        Tooth count ``Z``, >= 2.
    harmonic : int, default 1
        Mesh harmonic ``n`` (1 in the sources).

    Returns
    -------
    float
        SLF (dimensionless).

    Raises
    ------
    InputError
        If ``teeth`` or ``harmonic`` is out of range, the order ``n Z + 1`` is not below
        Nyquist, or the TSA is constant.

    References
    ----------
    Lebold et al. (2000).

    Examples
    --------
    As for :func:`sideband_index`: sum 0.4, :math:`\sigma = \sqrt{(1 + 0.09 + 0.01)/2}`:

    >>> import numpy as np
    >>> j = np.arange(64) / 64
    >>> avg = (np.cos(2 * np.pi * 10 * j) + 0.3 * np.cos(2 * np.pi * 9 * j)
    ...        + 0.1 * np.sin(2 * np.pi * 11 * j))
    >>> round(sideband_level_factor(TSA(avg, 1, 1.0), teeth=10), 6)
    0.53936
    """
    lower, upper = _first_sidebands(t, teeth, harmonic)
    sd = float(np.std(t.average))
    if sd == 0.0:
        raise InputError("TSA", "constant", "the sideband level factor needs a TSA with "
                         "non-zero standard deviation")
    return (lower + upper) / sd
