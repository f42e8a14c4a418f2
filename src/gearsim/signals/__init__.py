"""Signal analysis of simulated and measured gear vibration.

Modules, one concept each:

* :mod:`~gearsim.signals.timedomain` -- RMS, peak, crest factor, kurtosis, impacts;
* :mod:`~gearsim.signals.spectrum` -- amplitude-corrected spectrum and tone estimation;
* :mod:`~gearsim.signals.sidebands` -- mesh harmonics, sideband families, SER, uniformity,
  off-tone fraction and sideband spacing;
* :mod:`~gearsim.signals.timefreq` -- STFT spectrogram, band energy and band width;
* :mod:`~gearsim.signals.tsa` -- angular resampling, order removal, time-synchronous
  averaging, FM0, FM4, NA4, M6A, M8A;
* :mod:`~gearsim.signals.residual` -- mesh residual of a whole record;
* :mod:`~gearsim.signals.emd` -- empirical mode decomposition and IMF selection;
* :mod:`~gearsim.signals.compare` -- simulated-versus-measured sidebands (seed Table 2);
* :mod:`~gearsim.signals.settings` -- the options of :func:`analyze`;
* :mod:`~gearsim.signals.speed` -- speed from a tacho or from the signal (tacholess);
* :mod:`~gearsim.signals.ordertrack` -- computed order tracking, order spectrum, TSA on
  the tracked angle with its quality figure;
* :mod:`~gearsim.signals.envelope` -- squared-envelope spectrum;
* :mod:`~gearsim.signals.kurtogram` -- spectral kurtosis and the fast kurtogram;
* :mod:`~gearsim.signals.cepstrum` -- real cepstrum and cepstral pre-whitening;
* :mod:`~gearsim.signals.demodulation` -- narrow-band amplitude and phase demodulation;
* :mod:`~gearsim.signals.indicators` -- NB4, energy ratio, sideband index and level factor;
* :mod:`~gearsim.signals.periodicity` -- periodicity verdict for impacts;
* :mod:`~gearsim.signals.estimate` -- estimates of fs and tooth counts (labelled as such);
* :mod:`~gearsim.signals.analysis` -- the full gear analysis of one record;
* :mod:`~gearsim.signals.tiers` -- every tier a record's inputs allow, and what was skipped;
* :mod:`~gearsim.signals.planetary` -- planetary stage frequencies (Willis), fault
  frequencies and the fixed-sensor sideband rule (McFadden & Smith 1985).

Names are imported on first use (PEP 562), so ``import gearsim.signals`` does not load
scipy.signal until a function needs it. ``gearsim.signals.analyze`` is the function; its
module is :mod:`gearsim.signals.analysis` (import module constants with
``from gearsim.signals.analysis import IMPACT_FACTOR``).
The functions ``tsa.tsa`` and ``emd.emd`` are not re-exported, so that
``gearsim.signals.tsa`` and ``gearsim.signals.emd`` stay the modules.

Readers of measured files are in :mod:`gearsim.io.measured`, figures in
:mod:`gearsim.viz.signals`. Equations and sources: ``docs/signals.md``.
"""

from __future__ import annotations

import importlib
from typing import Any

#: Public name -> module that defines it (imported on first access).
_LAZY: dict[str, str] = {
    "amplitude_spectrum": "gearsim.signals.spectrum",
    "Analysis": "gearsim.signals.analysis",
    "AnalysisSettings": "gearsim.signals.settings",
    "analyze": "gearsim.signals.analysis",
    "analyze_record": "gearsim.signals.tiers",
    "band_energy": "gearsim.signals.timefreq",
    "band_width": "gearsim.signals.timefreq",
    "cepstral_peak": "gearsim.signals.cepstrum",
    "check_given_speed": "gearsim.signals.speed",
    "clearance_factor": "gearsim.signals.timedomain",
    "compare_sidebands": "gearsim.signals.compare",
    "condition_indicators": "gearsim.signals.tsa",
    "crest_factor": "gearsim.signals.timedomain",
    "Decomposition": "gearsim.signals.emd",
    "demodulate": "gearsim.signals.demodulation",
    "demodulate_tsa": "gearsim.signals.demodulation",
    "Demodulation": "gearsim.signals.demodulation",
    "detect_impacts": "gearsim.signals.timedomain",
    "difference_signal": "gearsim.signals.tsa",
    "energy_ratio": "gearsim.signals.indicators",
    "envelope_spectrum": "gearsim.signals.envelope",
    "EnvelopeSpectrum": "gearsim.signals.envelope",
    "estimate_fs": "gearsim.signals.estimate",
    "estimate_speed": "gearsim.signals.speed",
    "estimate_teeth": "gearsim.signals.estimate",
    "fast_kurtogram": "gearsim.signals.kurtogram",
    "fm0": "gearsim.signals.tsa",
    "fm4": "gearsim.signals.tsa",
    "impact_periodicity": "gearsim.signals.periodicity",
    "impact_threshold": "gearsim.signals.timedomain",
    "Impacts": "gearsim.signals.timedomain",
    "impulse_factor": "gearsim.signals.timedomain",
    "Indicators": "gearsim.signals.tsa",
    "Kinematics": "gearsim.signals.analysis",
    "kinematics": "gearsim.signals.analysis",
    "Kurtogram": "gearsim.signals.kurtogram",
    "kurtosis": "gearsim.signals.timedomain",
    "m6a": "gearsim.signals.tsa",
    "m8a": "gearsim.signals.tsa",
    "mesh_harmonics": "gearsim.signals.sidebands",
    "mesh_residual": "gearsim.signals.residual",
    "na4": "gearsim.signals.tsa",
    "nb4": "gearsim.signals.indicators",
    "off_tone_fraction": "gearsim.signals.sidebands",
    "order_spectrum": "gearsim.signals.ordertrack",
    "order_track": "gearsim.signals.ordertrack",
    "peak": "gearsim.signals.timedomain",
    "percentage_error": "gearsim.signals.compare",
    "Periodicity": "gearsim.signals.periodicity",
    "prewhiten": "gearsim.signals.cepstrum",
    "pulse_times": "gearsim.signals.tsa",
    "ratios_to_baseline": "gearsim.signals.timedomain",
    "real_cepstrum": "gearsim.signals.cepstrum",
    "RecordAnalysis": "gearsim.signals.tiers",
    "residual_signal": "gearsim.signals.tsa",
    "rms": "gearsim.signals.timedomain",
    "select_imfs": "gearsim.signals.emd",
    "Selection": "gearsim.signals.emd",
    "shape_factor": "gearsim.signals.timedomain",
    "sideband_families": "gearsim.signals.sidebands",
    "sideband_index": "gearsim.signals.indicators",
    "sideband_level_factor": "gearsim.signals.indicators",
    "sideband_spacing": "gearsim.signals.sidebands",
    "SidebandComparison": "gearsim.signals.compare",
    "SidebandFamily": "gearsim.signals.sidebands",
    "skewness": "gearsim.signals.timedomain",
    "spectral_kurtosis": "gearsim.signals.kurtogram",
    "Spectrogram": "gearsim.signals.timefreq",
    "spectrogram": "gearsim.signals.timefreq",
    "Spectrum": "gearsim.signals.spectrum",
    "speed_from_tacho": "gearsim.signals.speed",
    "SpeedProfile": "gearsim.signals.speed",
    "time_stats": "gearsim.signals.timedomain",
    "TimeStats": "gearsim.signals.timedomain",
    "Tone": "gearsim.signals.spectrum",
    "tone": "gearsim.signals.spectrum",
    "tracked_tsa": "gearsim.signals.ordertrack",
    "TSA": "gearsim.signals.tsa",
    "window_peak": "gearsim.signals.timedomain",
    "zoom": "gearsim.signals.spectrum",
}

#: The public names are those of _LAZY.
__all__ = list(_LAZY)


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'gearsim.signals' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
