"""One call that runs every signal analysis of gearsim on one vibration record.

:func:`analyze` takes a signal, its sampling rate, the tooth counts of the gear train and
the speed (known, or from a tacho channel), and returns an :class:`Analysis`: time-domain
statistics and impacts, mesh harmonics and sideband families of every shaft, the STFT with
band energy and band width around each mesh harmonic, the time-synchronous average with
FM0/FM4/NA4/M6A/M8A and, optionally, an EMD selection. ``Analysis.to_dict()`` is the
JSON summary; ``Analysis.plot(directory)`` draws the figures (matplotlib, lazily).

Train convention: ``teeth[0]`` is the gear on the reference shaft (the shaft whose speed
is given or whose tacho is recorded, assumed to carry the gear under watch, as the cracked
input gear of the seed); ``teeth[1:]`` are the other gears in mesh order. With a single
mesh frequency ``f_m = f_r1 Z_1`` shared by all meshes of a simple (idler) train, shaft
``j`` turns at ``f_m / Z_j``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs, check_positive
from gearsim.signals.emd import Selection, emd, select_imfs
from gearsim.signals.sidebands import (
    SEARCH_FRACTION,
    SidebandFamily,
    check_sideband_request,
    mesh_harmonics,
    sideband_families,
)
from gearsim.signals.spectrum import Spectrum, Tone, amplitude_spectrum
from gearsim.signals.timedomain import (
    Impacts,
    TimeStats,
    detect_impacts,
    impact_threshold,
    ratios_to_baseline,
    time_stats,
)
from gearsim.signals.timefreq import (
    Spectrogram,
    band_energy,
    band_width,
    modulation_index,
    spectrogram,
)
from gearsim.signals.tsa import TSA, Indicators, condition_indicators, pulse_times, tsa

__all__ = ["IMPACT_FACTOR", "GearTrain", "Analysis", "analyze", "gear_train"]

#: An impact must exceed the median per-mesh-period peak by this factor. The seed's
#: cracked-gear impacts reach about 2x the healthy level (209.8 %, 203.1 %) while normal
#: meshing peaks scatter by a few per cent, so 1.5 sits between the two with margin.
IMPACT_FACTOR = 1.5

#: Fraction of the power around n f_m that defines the band width (90 %: the main lobe
#: and the first sidebands of a healthy mesh tone, but not its far leakage).
BAND_FRACTION = 0.9

#: STFT frames per revolution of the reference shaft: four frames resolve the once-per-
#: revolution pulsation of the band energy (seed Figure 8) with frequency resolution
#: 4 f_r, still far finer than the mesh-harmonic spacing f_m = Z f_r for Z >= 12.
STFT_FRAMES_PER_REV = 4


@dataclass(frozen=True)
class GearTrain:
    """Frequencies of a simple train (Hz).

    Attributes
    ----------
    teeth : tuple of int
        Tooth counts, reference gear first.
    mesh_frequency : float
        ``f_m = f_r1 Z_1`` (Hz).
    shafts : dict
        Shaft label (``"shaft1"``, ...) to shaft frequency ``f_m / Z_j`` (Hz).
    """

    teeth: tuple[int, ...]
    mesh_frequency: float
    shafts: dict[str, float]

    @property
    def reference_frequency(self) -> float:
        """Frequency of the reference shaft ``f_r1`` (Hz)."""
        return self.shafts["shaft1"]


def gear_train(*, shaft_frequency: float, teeth: Sequence[int]) -> GearTrain:
    """Build :class:`GearTrain` from the reference shaft frequency (Hz) and tooth counts."""
    f_r = check_positive("shaft_frequency", shaft_frequency)
    if not teeth:
        raise InputError("teeth", list(teeth), "must list at least the reference gear's teeth")
    for j, z in enumerate(teeth):
        if int(z) != z or z < 1:
            raise InputError(f"teeth[{j}]", z, "must be an integer >= 1")
    zs = tuple(int(z) for z in teeth)
    f_m = f_r * zs[0]
    shafts = {f"shaft{j + 1}": f_m / z for j, z in enumerate(zs)}
    shafts["shaft1"] = f_r
    return GearTrain(teeth=zs, mesh_frequency=f_m, shafts=shafts)


def _finite(v: float) -> float | None:
    return float(v) if v is not None and math.isfinite(v) else None


@dataclass(frozen=True)
class Analysis:
    """Everything :func:`analyze` computed. Arrays are kept for plotting; see ``to_dict``."""

    signal: np.ndarray
    fs: float
    train: GearTrain
    stats: TimeStats
    impacts: Impacts
    spectrum: Spectrum
    harmonics: list[Tone]
    families: list[SidebandFamily]
    stft: Spectrogram
    band_energy: dict[int, np.ndarray]
    band_width_spectrum: dict[int, float]
    band_width_stft: dict[int, float]
    band_modulation: dict[int, float]
    tsa: TSA
    indicators: Indicators
    difference: np.ndarray
    residual: np.ndarray
    options: dict[str, Any]
    timings: dict[str, float]
    baseline_stats: TimeStats | None = None
    ratios: dict[str, float] | None = None
    emd_selection: Selection | None = None

    @property
    def orders(self) -> tuple[int, ...]:
        """Mesh harmonics analysed."""
        return tuple(self.options["orders"])

    def to_dict(self) -> dict[str, Any]:
        """JSON-serialisable summary (no long arrays except impact times)."""
        import gearsim

        t1 = 1.0 / self.train.reference_frequency
        out: dict[str, Any] = {
            "gearsim_version": gearsim.__version__,
            "fs_hz": self.fs,
            "n_samples": int(self.signal.size),
            "duration_s": self.signal.size / self.fs,
            "train": {
                "teeth": list(self.train.teeth),
                "mesh_frequency_hz": self.train.mesh_frequency,
                "shaft_frequencies_hz": dict(self.train.shafts),
            },
            "options": self.options,
            "time_domain": dict(self.stats.__dict__),
            "impacts": {
                "count": self.impacts.count,
                "threshold": self.impacts.threshold,
                "period_s": _finite(self.impacts.period),
                "period_std_s": _finite(self.impacts.period_std),
                "expected_period_s": t1,
                "period_ratio_to_T1": _finite(self.impacts.period / t1),
                "mean_amplitude": _finite(float(np.mean(self.impacts.amplitudes)))
                if self.impacts.count else None,
                "times_s": self.impacts.times.tolist(),
            },
            "mesh_harmonics": [
                {"order": n, "frequency_hz": h.frequency, "amplitude": h.amplitude}
                for n, h in zip(self.orders, self.harmonics, strict=True)
            ],
            "sidebands": [f.to_dict() for f in self.families],
            "time_frequency": {
                "nperseg": self.stft.nperseg,
                "hop": self.stft.hop,
                "frequency_resolution_hz": self.stft.df,
                "bands": [
                    {
                        "order": n,
                        "energy_mean": float(np.mean(self.band_energy[n])),
                        "energy_cv": _finite(
                            float(np.std(self.band_energy[n]) / np.mean(self.band_energy[n]))
                        ) if np.mean(self.band_energy[n]) > 0 else None,
                        "modulation_at_fr1": _finite(self.band_modulation[n]),
                        "width_spectrum_hz": _finite(self.band_width_spectrum[n]),
                        "width_stft_hz": _finite(self.band_width_stft[n]),
                    }
                    for n in self.orders
                ],
            },
            "tsa": self.indicators.to_dict()
            | {"shaft_frequency_hz": self.tsa.shaft_frequency},
            "timings_s": dict(self.timings),
        }
        if self.baseline_stats is not None:
            out["baseline_time_domain"] = dict(self.baseline_stats.__dict__)
            out["ratios_to_baseline"] = dict(self.ratios or {})
        if self.emd_selection is not None:
            s = self.emd_selection
            out["emd"] = {
                "method": s.method, "threshold": s.threshold, "selected": list(s.indices),
                "scores": s.scores.tolist(), "n_imfs": int(s.scores.size),
            }
        return out

    def plot(self, directory: str, *, fmt: str = "png", units: str | None = None) -> list[str]:
        """Write the standard figures to ``directory`` (see :mod:`gearsim.viz.signals`)."""
        from gearsim.viz.signals import plot_analysis

        return plot_analysis(self, directory, fmt=fmt, units=units)


def _samples_per_rev(fs: float, f_r: float) -> int:
    """Power of two at least the number of samples per revolution (no down-sampling)."""
    return int(2 ** math.ceil(math.log2(fs / f_r)))


def analyze(
    x: np.ndarray,
    fs: float,
    *,
    teeth: Sequence[int],
    shaft_frequency: float | None = None,
    tacho: np.ndarray | None = None,
    pulses_per_rev: int = 1,
    baseline: np.ndarray | None = None,
    baseline_tacho: np.ndarray | None = None,
    orders: Sequence[int] = (1, 2, 3, 4),
    n_sidebands: int = 6,
    window: str = "hann",
    remove_mean: bool = True,
    impact_factor: float = IMPACT_FACTOR,
    band_fraction: float = BAND_FRACTION,
    stft_frames_per_rev: int = STFT_FRAMES_PER_REV,
    shaft_harmonics: int = 2,
    sideband_orders: int = 1,
    emd_method: Literal["correlation", "kurtosis"] | None = None,
    emd_threshold: float | str = "ayenu-prah",
    emd_max_imf: int = -1,
) -> Analysis:
    """Run the time, frequency, time-frequency and TSA analyses on one record.

    Parameters
    ----------
    x : array_like
        Signal (any units, e.g. N for a mesh force or m/s^2 for an acceleration).
    fs : float
        Sampling rate (Hz).
    teeth : sequence of int
        Tooth counts, reference gear first (see module docstring).
    shaft_frequency : float, optional
        Reference shaft frequency (Hz); give this or ``tacho``.
    tacho : array_like, optional
        Tacho signal of the reference shaft, same sampling as ``x``.
    pulses_per_rev : int
        Tacho pulses per revolution.
    baseline : array_like, optional
        Healthy record (same fs) for ratios and NA4's run-average variance.
    baseline_tacho : array_like, optional
        Tacho of the baseline when ``tacho`` is used (else the known speed is reused).
    orders : sequence of int
        Mesh harmonics ``n`` examined (seed: 1..4).
    n_sidebands : int
        Sidebands per side ``K`` (Hanna et al. 2011 use 6 for SER).
    window : {"hann", "flattop", "boxcar"}
        Window of the amplitude spectrum.
    remove_mean : bool
        RMS and peak of the signal minus its mean (the dynamic part) if True.
    impact_factor : float
        See :data:`IMPACT_FACTOR`.
    band_fraction : float
        See :data:`BAND_FRACTION`.
    stft_frames_per_rev : int
        See :data:`STFT_FRAMES_PER_REV`; hop is half a frame.
    shaft_harmonics, sideband_orders : int
        Orders removed for the residual/difference signals (Zakrajsek et al. 1993:
        shaft orders 1..2 in practice, mesh sidebands +-1).
    emd_method : {"correlation", "kurtosis"} or None
        If given, decompose by EMD first and analyse the sum of the selected IMFs (seed
        sec. 4).
    emd_threshold : float or "ayenu-prah"
        Selection threshold (see :func:`gearsim.signals.emd.select_imfs`).
    emd_max_imf : int
        Maximum number of IMFs (-1: no limit).

    Returns
    -------
    Analysis
    """
    timings: dict[str, float] = {}
    t_start = time.perf_counter()
    a = as_signal(x)
    fs = check_fs(fs)
    if (shaft_frequency is None) == (tacho is None):
        raise InputError(
            "shaft_frequency/tacho", "both" if tacho is not None else "neither",
            "give exactly one of a known shaft speed or a tacho channel",
        )
    pulses = None
    if tacho is not None:
        tach = as_signal(tacho, name="tacho")
        if tach.size != a.size:
            raise InputError("tacho.length", tach.size, f"must equal the signal length {a.size}")
        pulses = pulse_times(tach, fs)
        n_rev = (pulses.size - 1) // int(pulses_per_rev)
        if n_rev < 1:
            raise InputError("tacho", f"{pulses.size} pulses",
                             f"must hold at least {pulses_per_rev + 1} pulses (one revolution)")
        shaft_frequency = n_rev / (pulses[n_rev * pulses_per_rev] - pulses[0])
    train = gear_train(shaft_frequency=shaft_frequency, teeth=teeth)
    orders = tuple(int(n) for n in orders)
    check_sideband_request(
        a.size, fs, mesh_frequency=train.mesh_frequency, shafts=train.shafts, orders=orders,
        n_sidebands=n_sidebands, window=window,
    )
    f_r1 = train.reference_frequency
    if a.size / fs < 2.0 / f_r1:
        raise InputError("record duration", f"{a.size / fs:.4g} s",
                         f"must cover >= 2 revolutions of shaft1 ({2.0 / f_r1:.4g} s) for TSA")
    options: dict[str, Any] = {
        "orders": list(orders), "n_sidebands": int(n_sidebands), "window": window,
        "remove_mean": bool(remove_mean), "impact_factor": float(impact_factor),
        "band_fraction": float(band_fraction), "stft_frames_per_rev": int(stft_frames_per_rev),
        "shaft_harmonics": int(shaft_harmonics), "sideband_orders": int(sideband_orders),
        "speed_source": "tacho" if tacho is not None else "known",
        "pulses_per_rev": int(pulses_per_rev) if tacho is not None else None,
        "tacho_threshold": "midpoint of tacho range" if tacho is not None else None,
        "emd_method": emd_method,
        "emd_threshold": emd_threshold if emd_method else None,
        "search_fraction": SEARCH_FRACTION,
    }
    timings["checks"] = time.perf_counter() - t_start

    selection = None
    if emd_method is not None:
        t0 = time.perf_counter()
        dec = emd(a, max_imf=emd_max_imf)
        selection = select_imfs(a, dec, method=emd_method, threshold=emd_threshold)
        if not selection.indices:
            raise InputError("emd_threshold", emd_threshold,
                             f"selects no IMF (max score {float(selection.scores.max()):.3g})")
        a = selection.signal
        timings["emd"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    stats = time_stats(a, remove_mean=remove_mean)
    thr = impact_threshold(a, fs, window=1.0 / train.mesh_frequency, factor=impact_factor)
    impacts = detect_impacts(a, fs, min_separation=0.5 / f_r1, threshold=thr)
    timings["time_domain"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    spec = amplitude_spectrum(a, fs, window=window)
    harmonics = mesh_harmonics(spec, mesh_frequency=train.mesh_frequency, orders=orders,
                               search=SEARCH_FRACTION * min(train.shafts.values()))
    fams = sideband_families(spec, mesh_frequency=train.mesh_frequency, shafts=train.shafts,
                             orders=orders, n_sidebands=n_sidebands)
    half = 0.5 * train.mesh_frequency
    bw_spec = {
        n: band_width(spec.frequency, spec.amplitude**2, center=n * train.mesh_frequency,
                      half_window=half, fraction=band_fraction)
        for n in orders
    }
    timings["spectrum"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    nperseg = max(8, int(round(fs / (stft_frames_per_rev * f_r1))))
    if nperseg > a.size:
        raise InputError("stft_frames_per_rev", stft_frames_per_rev,
                         f"gives a frame of {nperseg} samples, longer than the record")
    hop = max(1, nperseg // 2)
    # The static part (e.g. the mean mesh force) would swamp the lowest bins; the STFT
    # analyses the dynamic part when remove_mean is set.
    sg = spectrogram(a - stats.mean if remove_mean else a, fs, nperseg=nperseg, hop=hop,
                     window="hann")
    mean_psd = sg.psd.mean(axis=1)
    energies, bw_stft, mod_peak = {}, {}, {}
    for n in orders:
        e = band_energy(sg, center=n * train.mesh_frequency, half_width=half)
        energies[n] = e
        bw_stft[n] = band_width(sg.frequency, mean_psd, center=n * train.mesh_frequency,
                                half_window=half, fraction=band_fraction)
        mod_peak[n] = modulation_index(e, sg.time, frequency=f_r1)
    timings["time_frequency"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    m = _samples_per_rev(fs, f_r1)
    if pulses is not None:
        t_avg = tsa(a, fs, samples_per_rev=m, pulses=pulses, pulses_per_rev=pulses_per_rev)
    else:
        t_avg = tsa(a, fs, samples_per_rev=m, shaft_frequency=f_r1)

    history: list[np.ndarray] = []
    base_stats = None
    ratios = None
    if baseline is not None:
        b = as_signal(baseline, name="baseline")
        base_stats = time_stats(b, remove_mean=remove_mean)
        ratios = ratios_to_baseline(stats, base_stats)
        if tacho is not None and baseline_tacho is not None:
            bp = pulse_times(as_signal(baseline_tacho, name="baseline_tacho"), fs)
            b_avg = tsa(b, fs, samples_per_rev=m, pulses=bp, pulses_per_rev=pulses_per_rev)
        else:
            b_avg = tsa(b, fs, samples_per_rev=m, shaft_frequency=f_r1)
        _, _, b_res = condition_indicators(b_avg, teeth=train.teeth[0],
                                           shaft_harmonics=shaft_harmonics,
                                           sideband_orders=sideband_orders)
        history.append(b_res)
    ind, diff, resid = condition_indicators(
        t_avg, teeth=train.teeth[0], shaft_harmonics=shaft_harmonics,
        sideband_orders=sideband_orders, history=history,
    )
    timings["tsa"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_start

    return Analysis(
        signal=a, fs=fs, train=train, stats=stats, impacts=impacts, spectrum=spec,
        harmonics=harmonics, families=fams, stft=sg, band_energy=energies,
        band_width_spectrum=bw_spec, band_width_stft=bw_stft,
        band_modulation=mod_peak, tsa=t_avg, indicators=ind, difference=diff,
        residual=resid, options=options, timings=timings, baseline_stats=base_stats,
        ratios=ratios, emd_selection=selection,
    )
