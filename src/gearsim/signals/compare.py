r"""Simulated-versus-measured comparison of sideband amplitudes (seed Table 2).

The seed takes the measured value as the standard and reports, near 1 f_m and 2 f_m,
the error of the simulated sideband amplitude,
:math:`e = |A_\mathrm{sim} - A_\mathrm{meas}| / A_\mathrm{meas} \times 100\,\%`.
It does not say how one number per harmonic is formed from a family of sidebands; this
module reports the error of every sideband and of the family mean amplitude (the number
to set beside Table 2).

A simulated mesh force (N) and a measured acceleration (m/s^2) are not comparable in
absolute terms, so by default every amplitude is first divided by the amplitude of its
own mesh harmonic (relative sideband level, dimensionless); ``normalize="none"`` compares
absolute amplitudes of signals of the same quantity.

References
----------
.. [Seed] Shi, Li & Zhou, *Actuators* 14 (2025) 292, sec. 4 and Table 2.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs, check_positive
from gearsim.signals.sidebands import sideband_families
from gearsim.signals.spectrum import amplitude_spectrum

__all__ = ["SidebandComparison", "compare_sidebands", "percentage_error"]


def percentage_error(simulated: np.ndarray, measured: np.ndarray) -> np.ndarray:
    r"""Relative error :math:`100\,|s - m| / |m|` (%), measured taken as the standard.

    This is the error measure of the seed's Table 2 (sec. 4).

    Parameters
    ----------
    simulated : array_like
        Simulated values ``s`` (any units, the same as ``measured``).
    measured : array_like
        Measured values ``m``, the reference; broadcast against ``simulated``.

    Returns
    -------
    ndarray
        Error (%), NaN where ``m == 0``.

    Examples
    --------
    >>> percentage_error([110.0, 90.0, 1.0], [100.0, 100.0, 0.0])
    array([10., 10., nan])
    """
    s = np.asarray(simulated, dtype=np.float64)
    m = np.asarray(measured, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(m != 0.0, 100.0 * np.abs(s - m) / np.abs(m), np.nan)


@dataclass(frozen=True)
class SidebandComparison:
    """Sideband amplitudes of two signals near each mesh harmonic and their errors.

    Built by :func:`compare_sidebands`.

    Parameters
    ----------
    orders : tuple of int
        Mesh harmonics compared.
    k : ndarray of int, shape (2K,)
        Signed sideband numbers ``-K..-1, 1..K``.
    simulated : ndarray, shape (n_orders, 2K)
        Sideband amplitudes of the simulated signal: dimensionless (relative to the mesh
        harmonic) if ``normalize == "mesh"``, otherwise in the signal's units.
    measured : ndarray, shape (n_orders, 2K)
        The same for the measured signal.
    error_percent : ndarray, shape (n_orders, 2K)
        Per-sideband error (%, :func:`percentage_error`; NaN where the measured
        amplitude is zero).
    mean_error_percent : ndarray, shape (n_orders,)
        Error of the family mean amplitude (%).
    normalize : str
        ``"mesh"`` or ``"none"``.
    shaft : str
        Shaft whose sidebands are compared.
    """

    orders: tuple[int, ...]
    k: np.ndarray
    simulated: np.ndarray
    measured: np.ndarray
    error_percent: np.ndarray
    mean_error_percent: np.ndarray
    normalize: str
    shaft: str

    def to_dict(self) -> dict:
        """JSON-serialisable table.

        Returns
        -------
        dict
            ``shaft``, ``normalize`` and ``orders``: one row per harmonic with ``k``,
            both amplitude lists, the per-sideband errors (None where not finite), both
            family means and their error.
        """
        rows = []
        for i, n in enumerate(self.orders):
            rows.append({
                "order": n,
                "k": self.k.tolist(),
                "simulated": self.simulated[i].tolist(),
                "measured": self.measured[i].tolist(),
                "error_percent": [None if not np.isfinite(e) else float(e)
                                  for e in self.error_percent[i]],
                "simulated_mean": float(self.simulated[i].mean()),
                "measured_mean": float(self.measured[i].mean()),
                "mean_error_percent": float(self.mean_error_percent[i]),
            })
        return {"shaft": self.shaft, "normalize": self.normalize, "orders": rows}


def compare_sidebands(
    simulated: np.ndarray,
    fs_simulated: float,
    measured: np.ndarray,
    fs_measured: float,
    *,
    mesh_frequency: float,
    shaft_frequency: float,
    orders: Sequence[int] = (1, 2),
    n_sidebands: int,
    window: str = "hann",
    normalize: Literal["mesh", "none"] = "mesh",
    shaft: str = "faulty",
) -> SidebandComparison:
    """Compare sideband amplitudes near ``n f_m`` of a simulated and a measured signal.

    Parameters
    ----------
    simulated : array_like
        Simulated signal (e.g. mesh force, N).
    fs_simulated : float
        Sampling rate of ``simulated`` (Hz).
    measured : array_like
        Measured signal (e.g. acceleration, m/s^2), the reference of the errors.
    fs_measured : float
        Sampling rate of ``measured`` (Hz).
    mesh_frequency : float
        ``f_m`` (Hz), the same operating point for both.
    shaft_frequency : float
        ``f_r`` of the faulty gear's shaft (Hz): the sideband spacing compared.
    orders : sequence of int
        Mesh harmonics; (1, 2) as in the seed's Table 2.
    n_sidebands : int
        Sidebands per side.
    window : str
        Spectrum window (see :data:`gearsim.signals.spectrum.WINDOWS`).
    normalize : {"mesh", "none"}
        Divide amplitudes by the mesh-harmonic amplitude of the same signal, or not.
    shaft : str
        Label of the shaft in the output.

    Returns
    -------
    SidebandComparison
        Amplitudes of both signals and the errors of the simulated ones.

    Raises
    ------
    InputError
        If ``normalize`` is not ``"mesh"`` or ``"none"``, a signal or sampling rate is
        invalid, the request fails :func:`gearsim.signals.sidebands.check_sideband_request`
        for either signal (Nyquist, record length), or, with ``normalize="mesh"``, a mesh
        harmonic has zero amplitude.
    """
    if normalize not in ("mesh", "none"):
        raise InputError("normalize", normalize, "must be 'mesh' or 'none'")
    check_positive("shaft_frequency", shaft_frequency)
    fams = {}
    inputs = (("simulated", simulated, fs_simulated), ("measured", measured, fs_measured))
    for label, x, fs in inputs:
        a = as_signal(x, name=label)
        fs = check_fs(fs)
        spec = amplitude_spectrum(a, fs, window=window)
        fams[label] = sideband_families(
            spec, mesh_frequency=mesh_frequency, shafts={shaft: shaft_frequency},
            orders=orders, n_sidebands=n_sidebands,
        )
    tables = {}
    for label, fl in fams.items():
        rows = []
        for fam in fl:
            amp = fam.amplitude
            if normalize == "mesh":
                if not fam.mesh.amplitude > 0:
                    raise InputError(f"{label} mesh amplitude", fam.mesh.amplitude,
                                     f"must be > 0 at order {fam.order} to normalise")
                amp = amp / fam.mesh.amplitude
            rows.append(amp)
        tables[label] = np.vstack(rows)
    sim, meas = tables["simulated"], tables["measured"]
    return SidebandComparison(
        orders=tuple(int(n) for n in orders), k=fams["simulated"][0].k, simulated=sim,
        measured=meas, error_percent=percentage_error(sim, meas),
        mean_error_percent=percentage_error(sim.mean(axis=1), meas.mean(axis=1)),
        normalize=normalize, shaft=shaft,
    )
