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
* :mod:`~gearsim.signals.analyze` -- everything above on one record.

The package exports :func:`analyze` (the function, which shadows the module of the same
name: import module constants with ``from gearsim.signals.analyze import IMPACT_FACTOR``).
The functions ``tsa.tsa`` and ``emd.emd`` are not re-exported, so that
``gearsim.signals.tsa`` and ``gearsim.signals.emd`` stay the modules.

Readers of measured files are in :mod:`gearsim.io.measured`, figures in
:mod:`gearsim.viz.signals`. Equations and sources: ``docs/signals.md``.
"""

from gearsim.signals.analyze import Analysis, Kinematics, analyze, kinematics
from gearsim.signals.compare import SidebandComparison, compare_sidebands, percentage_error
from gearsim.signals.emd import Decomposition, Selection, select_imfs
from gearsim.signals.residual import mesh_residual
from gearsim.signals.settings import AnalysisSettings
from gearsim.signals.sidebands import (
    SidebandFamily,
    mesh_harmonics,
    off_tone_fraction,
    sideband_families,
    sideband_spacing,
)
from gearsim.signals.spectrum import Spectrum, Tone, amplitude_spectrum, tone, zoom
from gearsim.signals.timedomain import (
    Impacts,
    TimeStats,
    crest_factor,
    detect_impacts,
    impact_threshold,
    kurtosis,
    peak,
    ratios_to_baseline,
    rms,
    time_stats,
    window_peak,
)
from gearsim.signals.timefreq import Spectrogram, band_energy, band_width, spectrogram
from gearsim.signals.tsa import (
    TSA,
    Indicators,
    condition_indicators,
    difference_signal,
    fm0,
    fm4,
    m6a,
    m8a,
    na4,
    pulse_times,
    residual_signal,
)

__all__ = [
    "TSA",
    "Analysis",
    "AnalysisSettings",
    "Decomposition",
    "Impacts",
    "Indicators",
    "Kinematics",
    "Selection",
    "SidebandComparison",
    "SidebandFamily",
    "Spectrogram",
    "Spectrum",
    "TimeStats",
    "Tone",
    "amplitude_spectrum",
    "analyze",
    "band_energy",
    "band_width",
    "compare_sidebands",
    "condition_indicators",
    "crest_factor",
    "detect_impacts",
    "difference_signal",
    "fm0",
    "fm4",
    "impact_threshold",
    "kinematics",
    "kurtosis",
    "m6a",
    "m8a",
    "mesh_harmonics",
    "mesh_residual",
    "na4",
    "off_tone_fraction",
    "peak",
    "percentage_error",
    "pulse_times",
    "ratios_to_baseline",
    "residual_signal",
    "rms",
    "select_imfs",
    "sideband_families",
    "sideband_spacing",
    "spectrogram",
    "time_stats",
    "tone",
    "window_peak",
    "zoom",
]
