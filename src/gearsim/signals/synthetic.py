r"""Synthetic gear vibration with known content, for tests, benchmarks and examples.

.. math::

   x(t) = \sum_n A_n \cos(2\pi n f_m t)
        + \sum_n \sum_{k \ne 0} B_{n,k} \cos(2\pi (n f_m + k f_r) t + \psi_{n,k})
        + \sum_i I\, e^{-(t - t_i)/\tau} \sin(2\pi f_c (t - t_i))\, H(t - t_i)
        + \sigma\, \varepsilon(t)

with ``t_i = t_0 + i / f_r`` one impact per revolution (a tooth-root crack excites the
structure once per revolution of its gear: seed sec. 3.1; McFadden & Smith 1985 for the
decaying-resonance impact model), ``H`` the unit step and ``epsilon`` white Gaussian noise.

References
----------
.. [MS85] P. D. McFadden, J. D. Smith, "A signal processing technique for detecting local
   defects in a gear from the signal average of the vibration", *Proc. IMechE C* 199
   (1985) 287-292.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from gearsim.errors import InputError
from gearsim.signals._checks import check_fs, check_positive

__all__ = ["ImpactSpec", "gear_signal"]


@dataclass(frozen=True)
class ImpactSpec:
    """Once-per-revolution decaying resonance burst.

    Burst ``I exp(-(t - t_i)/tau) sin(2 pi f_c (t - t_i))`` for ``t >= t_i``, with
    ``t_i = t_0 + i / f_r`` (see :func:`gear_signal`).

    Parameters
    ----------
    amplitude : float
        ``I`` (signal units).
    decay : float
        ``tau`` (s), > 0; each burst is cut after ``10 tau``.
    carrier : float
        ``f_c`` (Hz), the excited resonance.
    first : float
        Time of the first impact ``t_0`` (s), >= 0.
    """

    amplitude: float
    decay: float
    carrier: float
    first: float


def gear_signal(
    *,
    fs: float,
    duration: float,
    shaft_frequency: float,
    teeth: int,
    mesh_amplitudes: Mapping[int, float],
    sidebands: Mapping[tuple[int, int], float] | None = None,
    sideband_shaft_frequency: float | None = None,
    impacts: ImpactSpec | None = None,
    noise: float = 0.0,
    offset: float = 0.0,
    seed: int = 0,
) -> np.ndarray:
    """Synthetic gear signal (see module docstring for the equation).

    Parameters
    ----------
    fs, duration : float
        Sampling rate (Hz) and duration (s).
    shaft_frequency : float
        ``f_r`` of the reference shaft (Hz); ``f_m = teeth * f_r``.
    teeth : int
        Teeth of the reference gear.
    mesh_amplitudes : mapping int -> float
        ``A_n`` for each mesh harmonic ``n``.
    sidebands : mapping (n, k) -> float, optional
        ``B_{n,k}`` with ``k`` signed, spaced by ``sideband_shaft_frequency``.
    sideband_shaft_frequency : float, optional
        Sideband spacing (Hz); the reference shaft frequency if omitted.
    impacts : ImpactSpec, optional
        Once-per-revolution impacts of the reference shaft.
    noise : float
        Standard deviation of the additive white Gaussian noise (signal units).
    offset : float
        Constant added (e.g. the static mesh force).
    seed : int
        Seed of ``numpy.random.default_rng`` for the noise and sideband phases.

    Returns
    -------
    ndarray
        ``round(fs * duration)`` samples.

    Raises
    ------
    InputError
        If ``fs``, ``duration``, a shaft frequency or ``impacts.decay`` is not > 0, or
        ``teeth`` is not an integer >= 1.
    """
    fs = check_fs(fs)
    duration = check_positive("duration", duration)
    f_r = check_positive("shaft_frequency", shaft_frequency)
    f_sb = f_r if sideband_shaft_frequency is None else check_positive(
        "sideband_shaft_frequency", sideband_shaft_frequency)
    if int(teeth) != teeth or teeth < 1:
        raise InputError("teeth", teeth, "must be an integer >= 1")
    rng = np.random.default_rng(seed)
    n = int(round(fs * duration))
    t = np.arange(n) / fs
    f_m = teeth * f_r
    x = np.full(n, float(offset))
    for order, amp in mesh_amplitudes.items():
        x += amp * np.cos(2 * np.pi * order * f_m * t)
    for (order, k), amp in (sidebands or {}).items():
        phase = rng.uniform(0.0, 2 * np.pi)
        x += amp * np.cos(2 * np.pi * (order * f_m + k * f_sb) * t + phase)
    if impacts is not None:
        tau = check_positive("impacts.decay", impacts.decay)
        length = min(n, int(np.ceil(10 * tau * fs)))
        tt = np.arange(length) / fs
        t_i = impacts.first
        while t_i < duration:
            i0 = int(np.ceil(t_i * fs))
            # Burst sampled at its exact (sub-sample) start time.
            dt = i0 / fs - t_i
            seg = impacts.amplitude * np.exp(-(tt + dt) / tau) * np.sin(
                2 * np.pi * impacts.carrier * (tt + dt))
            m = min(length, n - i0)
            x[i0 : i0 + m] += seg[:m]
            t_i += 1.0 / f_r
    if noise > 0.0:
        x += noise * rng.standard_normal(n)
    return x
