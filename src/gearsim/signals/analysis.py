"""One call that runs every signal analysis of gearsim on one vibration record.

:func:`analyze` takes a signal, its sampling rate, the tooth counts of the gear train and
the speed (known, or from a tacho channel), and returns an :class:`Analysis`: time-domain
statistics and impacts, mesh harmonics and sideband families of every shaft, the STFT with
band energy and band width around each mesh harmonic, the time-synchronous average with
FM0/FM4/NA4/M6A/M8A and, optionally, an EMD selection. ``Analysis.to_dict()`` is the
JSON summary; ``Analysis.plot(kind)`` and ``Analysis.figures()`` draw the figures (matplotlib,
imported lazily).

Train convention: ``teeth[0]`` is the gear on the reference shaft (the shaft whose speed
is given or whose tacho is recorded, assumed to carry the gear under watch, as the cracked
input gear of the seed); ``teeth[1:]`` are the other gears in mesh order. With a single
mesh frequency ``f_m = f_r1 Z_1`` shared by all meshes of a simple (idler) train, shaft
``j`` turns at ``f_m / Z_j``.

A compound (multi-stage parallel-shaft) train is given as ``stages`` instead: stage ``k``
is a pair ``(z_k^d, z_k^n)`` of driving and driven teeth whose driving gear sits on the
driven shaft of stage ``k - 1`` (stage 1's on the reference shaft). Shaft 1 turns at
``f_r1``, shaft ``k + 1`` at ``f_{k+1} = f_k z_k^d / z_k^n`` and stage ``k`` meshes at
``f_{m,k} = f_k z_k^d``, modulated by its two shafts ``k`` and ``k + 1``. Every stage
gets its own mesh harmonics, sideband families (of its two shafts) and STFT bands; the
time domain, the impacts and the TSA with its condition indicators stay on the reference
shaft with the reference gear's teeth ``z_1^d``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gearsim._version import __version__
from gearsim.errors import InputError
from gearsim.signals._checks import (
    as_signal,
    check_fs,
    check_positive,
    check_resolution,
    check_speed_source,
    check_teeth,
)
from gearsim.signals.emd import Selection, emd, select_imfs
from gearsim.signals.settings import (
    BAND_FRACTION,
    IMPACT_FACTOR,
    STFT_FRAMES_PER_REV,
    AnalysisSettings,
)
from gearsim.signals.sidebands import (
    SEARCH_FRACTION,
    SidebandFamily,
    _family_lines,
    check_sideband_request,
    mesh_harmonics,
    sideband_families,
)
from gearsim.signals.spectrum import WINDOWS, Spectrum, Tone, amplitude_spectrum
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

__all__ = [
    "BAND_FRACTION",
    "IMPACT_FACTOR",
    "STFT_FRAMES_PER_REV",
    "Analysis",
    "Kinematics",
    "MeshStage",
    "StageLines",
    "analyze",
    "check_stages",
    "kinematics",
]


@dataclass(frozen=True)
class MeshStage:
    """One mesh of a compound train, as the signal analysis sees it.

    Parameters
    ----------
    index : int
        Stage number, 1 for the mesh of the reference shaft.
    teeth : tuple of int
        ``(z_d, z_n)``: teeth of the driving gear (on the driving shaft) and of the
        driven gear.
    mesh_frequency : float
        ``f_{m,k} = f_k z_d`` (Hz), ``f_k`` the driving shaft's frequency.
    shafts : tuple of str
        Labels of the driving and the driven shaft (``"shaft{k}"``, ``"shaft{k+1}"``),
        keys of :attr:`Kinematics.shafts`.
    """

    index: int
    teeth: tuple[int, int]
    mesh_frequency: float
    shafts: tuple[str, str]

    def to_dict(self) -> dict[str, Any]:
        """JSON-serialisable summary.

        Returns
        -------
        dict of str to Any
            ``stage``, ``teeth`` (driving, driven), ``mesh_frequency_hz`` (Hz) and
            ``shafts`` (driving, driven labels).
        """
        return {"stage": self.index, "teeth": list(self.teeth),
                "mesh_frequency_hz": self.mesh_frequency, "shafts": list(self.shafts)}


@dataclass(frozen=True)
class Kinematics:
    """Tooth counts and frequencies of a train, as the signal analysis sees it.

    Not the physical train (:class:`gearsim.system.GearTrain`): only what is needed to
    place the spectral lines. A simple train (:func:`kinematics` with ``teeth``) has one
    mesh frequency and no ``stages``; a compound train (with ``stages``) one
    :class:`MeshStage` per mesh.

    Parameters
    ----------
    teeth : tuple of int
        Tooth counts, reference gear first (a compound train: the stages' pairs in order,
        ``(z_1^d, z_1^n, z_2^d, z_2^n, ...)``).
    mesh_frequency : float
        ``f_m = f_r1 Z_1`` (Hz): the mesh of the reference gear (stage 1).
    shafts : dict
        Shaft label (``"shaft1"``, ...) to shaft frequency (Hz): ``f_m / Z_j`` for a
        simple train, ``f_{k+1} = f_k z_k^d / z_k^n`` for a compound one.
    stages : tuple of MeshStage
        The meshes of a compound train in power-flow order; empty for a simple train.
    """

    teeth: tuple[int, ...]
    mesh_frequency: float
    shafts: dict[str, float]
    stages: tuple[MeshStage, ...] = ()

    @property
    def reference_frequency(self) -> float:
        """Frequency of the reference shaft ``f_r1`` (Hz)."""
        return self.shafts["shaft1"]

    @property
    def compound(self) -> bool:
        """True for a train given by stages (one mesh frequency per stage)."""
        return bool(self.stages)


def check_stages(stages: object, *, name: str = "stages") -> tuple[tuple[int, int], ...]:
    """The stages of a compound train as pairs of integers, each checked >= 1.

    Parameters
    ----------
    stages : sequence of (int, int)
        ``(driving teeth, driven teeth)`` of each stage, in power-flow order.
    name : str
        Name used in the error message.

    Returns
    -------
    tuple of (int, int)
        The stages.

    Raises
    ------
    InputError
        If ``stages`` is not a non-empty sequence of pairs of integers in
        [1, ``MAX_TEETH``].
    """
    from gearsim.signals._checks import MAX_TEETH, check_int

    rule = "must be a non-empty list of (driving teeth, driven teeth) pairs"
    if isinstance(stages, (str, bytes)):
        raise InputError(name, stages, rule)
    try:
        items = list(stages)  # type: ignore[call-overload]
    except TypeError:
        raise InputError(name, stages, rule) from None
    if not items:
        raise InputError(name, items, rule)
    out = []
    for k, pair in enumerate(items):
        try:
            zs = list(pair)
        except TypeError:
            zs = []
        if len(zs) != 2 or isinstance(pair, (str, bytes)):
            raise InputError(f"{name}[{k}]", pair, "must be a pair (driving teeth, driven teeth)")
        out.append((check_int(f"{name}[{k}][0]", zs[0], minimum=1, maximum=MAX_TEETH),
                    check_int(f"{name}[{k}][1]", zs[1], minimum=1, maximum=MAX_TEETH)))
    return tuple(out)


def kinematics(
    *,
    shaft_frequency: float,
    teeth: Sequence[int] | None = None,
    stages: Sequence[tuple[int, int]] | None = None,
) -> Kinematics:
    """Frequencies of a train from its reference shaft speed and tooth counts.

    Simple train (``teeth``): one mesh frequency ``f_m = f_r1 Z_1`` and shaft ``j`` at
    ``f_m / Z_j``. Compound train (``stages``): shaft 1 at ``f_1 = f_r1``, shaft ``k + 1``
    at ``f_{k+1} = f_k z_k^d / z_k^n`` and stage ``k`` meshing at ``f_{m,k} = f_k z_k^d``.

    Parameters
    ----------
    shaft_frequency : float
        Frequency of the reference shaft ``f_r1`` [Hz].
    teeth : sequence of int, optional
        Simple train: tooth counts, reference gear first, then the other gears in mesh
        order.
    stages : sequence of (int, int), optional
        Compound train: ``(driving teeth, driven teeth)`` of each stage in power-flow
        order, the driving gear of stage ``k`` on the driven shaft of stage ``k - 1``
        (stage 1's on the reference shaft). Give exactly one of ``teeth`` and ``stages``.

    Returns
    -------
    Kinematics
        Mesh frequency or frequencies [Hz] and shaft frequencies [Hz].

    Raises
    ------
    InputError
        If ``shaft_frequency`` is not > 0, not exactly one of ``teeth`` and ``stages`` is
        given, or a tooth count is not an integer >= 1 (or none is given).

    Examples
    --------
    >>> kin = kinematics(shaft_frequency=30.0, stages=((32, 80), (48, 64)))
    >>> [round(f, 9) for f in kin.shafts.values()], [s.mesh_frequency for s in kin.stages]
    ([30.0, 12.0, 9.0], [960.0, 576.0])
    """
    f_r = check_positive("shaft_frequency", shaft_frequency)
    if (teeth is None) == (stages is None):
        raise InputError("teeth/stages", "both" if teeth is not None else "neither",
                         "give exactly one: teeth for a simple train, stages for a "
                         "compound one")
    if stages is None:
        zs = check_teeth(teeth)
        f_m = f_r * zs[0]
        shafts = {f"shaft{j + 1}": f_m / z for j, z in enumerate(zs)}
        shafts["shaft1"] = f_r
        return Kinematics(teeth=zs, mesh_frequency=f_m, shafts=shafts)
    pairs = check_stages(stages)
    shafts = {"shaft1": f_r}
    out: list[MeshStage] = []
    f_k = f_r
    for k, (z_d, z_n) in enumerate(pairs, start=1):
        f_next = f_k * z_d / z_n
        out.append(MeshStage(index=k, teeth=(z_d, z_n), mesh_frequency=f_k * z_d,
                             shafts=(f"shaft{k}", f"shaft{k + 1}")))
        shafts[f"shaft{k + 1}"] = f_next
        f_k = f_next
    return Kinematics(teeth=tuple(z for p in pairs for z in p),
                      mesh_frequency=out[0].mesh_frequency, shafts=shafts, stages=tuple(out))


@dataclass(frozen=True)
class StageLines:
    """The lines of one stage of a compound train (built by :func:`analyze`).

    Parameters
    ----------
    stage : MeshStage
        The stage: teeth, mesh frequency ``f_{m,k}`` (Hz), its two shafts.
    harmonics : list of Tone
        Mesh harmonics ``n f_{m,k}``, one per analysed order (Hz, signal units).
    families : list of SidebandFamily
        Sideband family of each of the stage's two shafts around every harmonic.
    band_energy : dict of int to ndarray
        Order ``n`` to the mean-square value in ``n f_{m,k} +- f_{m,k}/2`` per STFT
        frame (signal units squared).
    band_width_spectrum : dict of int to float
        Order to the occupied band width (Hz) from the amplitude spectrum.
    band_width_stft : dict of int to float
        Order to the occupied band width (Hz) from the time-averaged STFT PSD.
    band_modulation : dict of int to float
        Order to the relative modulation of the band energy at the driving shaft's
        frequency (dimensionless).
    """

    stage: MeshStage
    harmonics: list[Tone]
    families: list[SidebandFamily]
    band_energy: dict[int, np.ndarray]
    band_width_spectrum: dict[int, float]
    band_width_stft: dict[int, float]
    band_modulation: dict[int, float]


def _finite(v: float) -> float | None:
    return float(v) if v is not None and math.isfinite(v) else None


@dataclass(frozen=True)
class Analysis:
    """Everything :func:`analyze` computed. Arrays are kept for plotting; see ``to_dict``.

    Parameters
    ----------
    signal : ndarray
        The record analysed (units of the input; the sum of the selected IMFs when EMD
        was used).
    fs : float
        Sampling rate (Hz).
    kinematics : Kinematics
        Tooth counts, mesh frequency and shaft frequencies (Hz).
    stats : TimeStats
        RMS, peak, crest factor and kurtosis (:func:`~gearsim.signals.timedomain.time_stats`).
    impacts : Impacts
        Impacts and their period (s) (:func:`~gearsim.signals.timedomain.detect_impacts`).
    spectrum : Spectrum
        Amplitude spectrum of the record.
    harmonics : list of Tone
        Mesh harmonics ``n f_m``, one per analysed order.
    families : list of SidebandFamily
        Sideband family of every shaft around every mesh harmonic, with SER, CV and
        flatness.
    stft : Spectrogram
        Short-time PSD (signal units squared per Hz).
    band_energy : dict of int to ndarray
        Mesh order ``n`` to the mean-square value in ``n f_m +- f_m/2`` per STFT frame
        (signal units squared).
    band_width_spectrum : dict of int to float
        Mesh order to the occupied band width (Hz) from the amplitude spectrum.
    band_width_stft : dict of int to float
        Mesh order to the occupied band width (Hz) from the time-averaged STFT PSD.
    band_modulation : dict of int to float
        Mesh order to the relative modulation of the band energy at ``f_r1``
        (:func:`~gearsim.signals.timefreq.modulation_index`, dimensionless).
    tsa : TSA
        Time-synchronous average of the reference shaft.
    indicators : Indicators
        FM0, FM4, NA4, M6A, M8A (dimensionless).
    difference : ndarray
        Difference signal of the TSA (signal units).
    residual : ndarray
        Residual signal of the TSA (signal units).
    options : dict of str to Any
        The options used (settings, speed source, search fraction), as recorded in the
        JSON summary.
    timings : dict of str to float
        Wall-clock time of each stage (s).
    baseline_stats : TimeStats or None
        Statistics of the baseline record, if one was given.
    ratios : dict of str to float or None
        Ratios current / baseline of the time-domain statistics, if a baseline was given.
    emd_selection : Selection or None
        The IMF selection, if EMD was used.
    stages : tuple of StageLines
        A compound train: the lines of every stage (stage 1's are the ``harmonics``,
        ``families`` and bands above); empty for a simple train.
    """

    signal: np.ndarray
    fs: float
    kinematics: Kinematics
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
    stages: tuple[StageLines, ...] = ()

    @property
    def orders(self) -> tuple[int, ...]:
        """Mesh harmonics analysed."""
        return tuple(self.options["orders"])

    def to_dict(self) -> dict[str, Any]:
        """JSON-serialisable summary (no long arrays except impact times).

        Returns
        -------
        dict of str to Any
            Version, record, train, options, time domain, impacts, mesh harmonics,
            sidebands, time-frequency bands, TSA indicators and timings; frequencies in
            Hz and times in s (keys ending ``_hz``, ``_s``), amplitudes in signal units.
            Baseline statistics and ratios, and the EMD selection, when present. A
            compound train adds ``train["stages"]`` (teeth, mesh frequency and shafts of
            each stage) and ``stages``: each stage's mesh harmonics, sideband families
            and STFT bands (modulation at the stage's driving shaft).
        """
        t1 = 1.0 / self.kinematics.reference_frequency
        lines = _lines_dict(self, self.orders, "modulation_at_fr1")
        out: dict[str, Any] = {
            "gearsim_version": __version__,
            "fs_hz": self.fs,
            "n_samples": int(self.signal.size),
            "duration_s": self.signal.size / self.fs,
            "train": {
                "teeth": list(self.kinematics.teeth),
                "mesh_frequency_hz": self.kinematics.mesh_frequency,
                "shaft_frequencies_hz": dict(self.kinematics.shafts),
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
            "mesh_harmonics": lines["mesh_harmonics"],
            "sidebands": lines["sidebands"],
            "time_frequency": {
                "nperseg": self.stft.nperseg,
                "hop": self.stft.hop,
                "frequency_resolution_hz": self.stft.df,
                "bands": lines["bands"],
            },
            "tsa": self.indicators.to_dict()
            | {"shaft_frequency_hz": self.tsa.shaft_frequency},
            "timings_s": dict(self.timings),
        }
        if self.baseline_stats is not None:
            out["baseline_time_domain"] = dict(self.baseline_stats.__dict__)
            out["ratios_to_baseline"] = dict(self.ratios or {})
        if self.kinematics.stages:
            out["train"]["stages"] = [st.to_dict() for st in self.kinematics.stages]
            out["stages"] = [
                sl.stage.to_dict()
                | {"shaft_frequencies_hz": {k: self.kinematics.shafts[k] for k in sl.stage.shafts}}
                | _lines_dict(sl, self.orders, "modulation_at_driving_shaft")
                for sl in self.stages]
        if self.emd_selection is not None:
            s = self.emd_selection
            out["emd"] = {
                "method": s.method, "threshold": s.threshold, "selected": list(s.indices),
                "scores": s.scores.tolist(), "n_imfs": int(s.scores.size),
            }
        return out

    def plot(self, kind: str = "spectrum", *, ax=None, fig=None, units: str | None = None):
        """One figure of the analysis (see :func:`gearsim.viz.signals.plot`).

        Parameters
        ----------
        kind : {"time", "spectrum", "zooms", "spectrogram", "tsa"}
            Which figure.
        ax : matplotlib.axes.Axes, optional
            Axes to draw into (single-panel kind ``"spectrum"``).
        fig : matplotlib.figure.Figure, optional
            Figure to draw into (multi-panel kinds).
        units : str, optional
            Units of the signal, shown on the axes.

        Returns
        -------
        matplotlib.figure.Figure
            The figure; write it with :func:`gearsim.viz.save`.
        """
        from gearsim.viz.signals import plot

        return plot(self, kind, ax=ax, fig=fig, units=units)

    def figures(self, *, units: str | None = None) -> dict:
        """The standard figures by file stem (see :func:`gearsim.viz.signals.figures`).

        Parameters
        ----------
        units : str, optional
            Units of the signal, shown on the axes.

        Returns
        -------
        dict of str to matplotlib.figure.Figure
            Figures ready for :func:`gearsim.viz.save_all`.
        """
        from gearsim.viz.signals import figures

        return figures(self, units=units)


def _lines_dict(lines: Analysis | StageLines, orders: Sequence[int],
                modulation: str) -> dict[str, list]:
    """JSON rows of the mesh harmonics, sideband families and STFT bands of the reference
    mesh (an :class:`Analysis`) or of one stage (a :class:`StageLines`), which hold them
    under the same names; ``modulation`` is the key of the band's modulation."""

    def cv(e: np.ndarray) -> float | None:
        m = float(np.mean(e))
        return _finite(float(np.std(e)) / m) if m > 0 else None

    return {
        "mesh_harmonics": [
            {"order": n, "frequency_hz": h.frequency, "amplitude": h.amplitude}
            for n, h in zip(orders, lines.harmonics, strict=True)
        ],
        "sidebands": [f.to_dict() for f in lines.families],
        "bands": [
            {
                "order": n,
                "energy_mean": float(np.mean(lines.band_energy[n])),
                "energy_cv": cv(lines.band_energy[n]),
                modulation: _finite(lines.band_modulation[n]),
                "width_spectrum_hz": _finite(lines.band_width_spectrum[n]),
                "width_stft_hz": _finite(lines.band_width_stft[n]),
            }
            for n in orders
        ],
    }


def _samples_per_rev(fs: float, f_r: float) -> int:
    """Power of two at least the number of samples per revolution (no down-sampling)."""
    return int(2 ** math.ceil(math.log2(fs / f_r)))


def analyze(
    x: np.ndarray,
    fs: float,
    *,
    teeth: Sequence[int] | None = None,
    stages: Sequence[tuple[int, int]] | None = None,
    shaft_frequency: float | None = None,
    tacho: np.ndarray | None = None,
    baseline: np.ndarray | None = None,
    baseline_tacho: np.ndarray | None = None,
    settings: AnalysisSettings | None = None,
    **overrides: Any,
) -> Analysis:
    """Run the time, frequency, time-frequency and TSA analyses on one record.

    Parameters
    ----------
    x : array_like
        Signal (any units, e.g. N for a mesh force or m/s^2 for an acceleration).
    fs : float
        Sampling rate [Hz].
    teeth : sequence of int, optional
        Simple train: tooth counts, reference gear first (see module docstring).
    stages : sequence of (int, int), optional
        Compound train: ``(driving teeth, driven teeth)`` of each stage in power-flow
        order, stage 1's driving gear on the reference shaft (see module docstring and
        :func:`kinematics`). Every stage's mesh harmonics, sideband families (of its two
        shafts) and STFT bands are analysed; the time domain, impacts, TSA and condition
        indicators stay on the reference shaft with stage 1's driving teeth. Give exactly
        one of ``teeth`` and ``stages``.
    shaft_frequency : float, optional
        Reference shaft frequency [Hz]; give this or ``tacho``.
    tacho : array_like, optional
        Tacho signal of the reference shaft, same sampling as ``x``.
    baseline : array_like, optional
        Healthy record (same fs) for ratios and NA4's run-average variance.
    baseline_tacho : array_like, optional
        Tacho of the baseline when ``tacho`` is used (else the known speed is reused).
    settings : AnalysisSettings, optional
        Analysis options (orders, sidebands, window, impact factor, band fraction, STFT
        frames, TSA orders, EMD, tacho pulses per revolution); default
        ``AnalysisSettings()``.
    **overrides
        Any field of :class:`AnalysisSettings` by keyword (e.g. ``orders=(1, 2)``),
        replacing the value in ``settings``; validated by :class:`AnalysisSettings`.

    Returns
    -------
    Analysis
        Every result, with the options used; ``Analysis.to_dict()`` for JSON.

    Raises
    ------
    InputError
        If an input or option is invalid: not exactly one of ``shaft_frequency`` and
        ``tacho`` or of ``teeth`` and ``stages``, a tacho of another length or with less
        than one revolution, a line above Nyquist, a record too short to resolve the
        sidebands (of every stage's shafts) or shorter than two revolutions, or an EMD
        threshold that selects no IMF.

    References
    ----------
    Measures and sources: :mod:`gearsim.signals.timedomain` (Randall 2011),
    :mod:`gearsim.signals.sidebands` (Hanna et al. 2011), :mod:`gearsim.signals.timefreq`,
    :mod:`gearsim.signals.tsa` (Stewart 1977; Zakrajsek et al. 1993).
    """
    timings: dict[str, float] = {}
    t_start = time.perf_counter()
    opt = _settings(settings, overrides)
    a = as_signal(x)
    fs = check_fs(fs)
    shaft_frequency = check_speed_source(shaft_frequency, tacho)
    ppr = opt.pulses_per_rev
    pulses = None
    if tacho is not None:
        tach = as_signal(tacho, name="tacho")
        if tach.size != a.size:
            raise InputError("tacho.length", tach.size, f"must equal the signal length {a.size}")
        pulses = pulse_times(tach, fs)
        n_rev = (pulses.size - 1) // ppr
        if n_rev < 1:
            raise InputError("tacho", f"{pulses.size} pulses",
                             f"must hold at least {ppr + 1} pulses (one revolution)")
        shaft_frequency = n_rev / (pulses[n_rev * ppr] - pulses[0])
    kin = kinematics(shaft_frequency=shaft_frequency, teeth=teeth, stages=stages)
    orders = opt.orders
    f_m = kin.mesh_frequency
    # the shafts whose sidebands are measured around each mesh frequency: every shaft of
    # a simple train; of a compound train, the two shafts of each stage
    stage_shafts = [{k: kin.shafts[k] for k in st.shafts} for st in kin.stages]
    # the slowest shaft of every stage sets the record length, named at once
    check_resolution(a.size, fs, {f"shaft {k}": v for k, v in kin.shafts.items()},
                     bins_needed=2 * WINDOWS[opt.window], window=opt.window)
    for mesh_f, shafts in ([(st.mesh_frequency, sh) for st, sh in zip(kin.stages, stage_shafts,
                                                                       strict=True)]
                           or [(f_m, kin.shafts)]):
        check_sideband_request(
            a.size, fs, mesh_frequency=mesh_f, shafts=shafts, orders=orders,
            n_sidebands=opt.n_sidebands, window=opt.window,
        )
    f_r1 = kin.reference_frequency
    if a.size / fs < 2.0 / f_r1:
        raise InputError("record duration", f"{a.size / fs:.4g} s",
                         f"must cover >= 2 revolutions of shaft1 ({2.0 / f_r1:.4g} s) for TSA")
    options: dict[str, Any] = {
        "orders": list(orders), "n_sidebands": opt.n_sidebands, "window": opt.window,
        "remove_mean": opt.remove_mean, "impact_factor": opt.impact_factor,
        "band_fraction": opt.band_fraction, "stft_frames_per_rev": opt.stft_frames_per_rev,
        "shaft_harmonics": opt.shaft_harmonics, "sideband_orders": opt.sideband_orders,
        "speed_source": "tacho" if tacho is not None else "known",
        "pulses_per_rev": ppr if tacho is not None else None,
        "tacho_threshold": "midpoint of tacho range" if tacho is not None else None,
        "emd_method": opt.emd_method,
        "emd_threshold": opt.emd_threshold if opt.emd_method else None,
        "search_fraction": SEARCH_FRACTION,
    }
    timings["checks"] = time.perf_counter() - t_start

    selection = None
    if opt.emd_method is not None:
        t0 = time.perf_counter()
        dec = emd(a, max_imf=opt.emd_max_imf)
        selection = select_imfs(a, dec, method=opt.emd_method, threshold=opt.emd_threshold)
        if not selection.indices:
            raise InputError("analysis.emd_threshold", opt.emd_threshold,
                             f"selects no IMF (max score {float(selection.scores.max()):.3g})")
        a = selection.signal
        timings["emd"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    stats = time_stats(a, remove_mean=opt.remove_mean)
    thr = impact_threshold(a, fs, window=1.0 / f_m, factor=opt.impact_factor)
    impacts = detect_impacts(a, fs, min_separation=0.5 / f_r1, threshold=thr)
    timings["time_domain"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    spec = amplitude_spectrum(a, fs, window=opt.window)
    stage_spec: list[tuple[list[Tone], list[SidebandFamily]]] = []
    if kin.stages:
        stage_spec = _stage_spectrum(kin, stage_shafts, spec, orders, opt.n_sidebands)
        harmonics, fams = stage_spec[0]
    else:
        harmonics = mesh_harmonics(spec, mesh_frequency=f_m, orders=orders,
                                   search=SEARCH_FRACTION * min(kin.shafts.values()))
        fams = sideband_families(spec, mesh_frequency=f_m, shafts=kin.shafts,
                                 orders=orders, n_sidebands=opt.n_sidebands)
    timings["spectrum"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    # The static part (e.g. the mean mesh force) would swamp the lowest bins; the STFT
    # analyses the dynamic part when remove_mean is set.
    dynamic = a - stats.mean if opt.remove_mean else a
    sg, first = _stft_bands(dynamic, fs, spec, f_m, f_r1, orders, opt, 0)
    energies, bw_spec, bw_stft, mod_peak = first
    stage_out = []
    for k, st in enumerate(kin.stages):  # stage 1 is the reference gear's mesh: `first`
        b = first if k == 0 else _stft_bands(dynamic, fs, spec, st.mesh_frequency,
                                             kin.shafts[st.shafts[0]], orders, opt, k)[1]
        stage_out.append(StageLines(stage=st, harmonics=stage_spec[k][0],
                                    families=stage_spec[k][1], band_energy=b[0],
                                    band_width_spectrum=b[1], band_width_stft=b[2],
                                    band_modulation=b[3]))
    timings["time_frequency"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    m = _samples_per_rev(fs, f_r1)
    if pulses is not None:
        t_avg = tsa(a, fs, samples_per_rev=m, pulses=pulses, pulses_per_rev=ppr)
    else:
        t_avg = tsa(a, fs, samples_per_rev=m, shaft_frequency=f_r1)

    history: list[np.ndarray] = []
    base_stats = None
    ratios = None
    if baseline is not None:
        b = as_signal(baseline, name="baseline")
        base_stats = time_stats(b, remove_mean=opt.remove_mean)
        ratios = ratios_to_baseline(stats, base_stats)
        if tacho is not None and baseline_tacho is not None:
            bp = pulse_times(as_signal(baseline_tacho, name="baseline_tacho"), fs)
            b_avg = tsa(b, fs, samples_per_rev=m, pulses=bp, pulses_per_rev=ppr)
        else:
            b_avg = tsa(b, fs, samples_per_rev=m, shaft_frequency=f_r1)
        _, _, b_res = condition_indicators(b_avg, teeth=kin.teeth[0],
                                           shaft_harmonics=opt.shaft_harmonics,
                                           sideband_orders=opt.sideband_orders)
        history.append(b_res)
    ind, diff, resid = condition_indicators(
        t_avg, teeth=kin.teeth[0], shaft_harmonics=opt.shaft_harmonics,
        sideband_orders=opt.sideband_orders, history=history,
    )
    timings["tsa"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_start

    return Analysis(
        signal=a, fs=fs, kinematics=kin, stats=stats, impacts=impacts, spectrum=spec,
        harmonics=harmonics, families=fams, stft=sg, band_energy=energies,
        band_width_spectrum=bw_spec, band_width_stft=bw_stft,
        band_modulation=mod_peak, tsa=t_avg, indicators=ind, difference=diff,
        residual=resid, options=options, timings=timings, baseline_stats=base_stats,
        ratios=ratios, emd_selection=selection, stages=tuple(stage_out),
    )


def _stage_spectrum(kin: Kinematics, shafts: list[dict[str, float]], spec: Spectrum,
                    orders: Sequence[int], n_sidebands: int,
                    ) -> list[tuple[list[Tone], list[SidebandFamily]]]:
    """Mesh harmonics and sideband families (of its two shafts, ``shafts[k]``) of every
    stage; the lines of the other stages (their requested lines and every mesh harmonic
    below Nyquist) are never taken for one of this stage's, and one within the
    resolution makes a sideband not ``isolated``."""
    out = []
    for st, sh in zip(kin.stages, shafts, strict=True):
        others = [line for o, osh in zip(kin.stages, shafts, strict=True) if o is not st
                  for line in _family_lines(o.mesh_frequency, osh, orders, n_sidebands)
                  + list(o.mesh_frequency * np.arange(1, 0.5 * spec.fs // o.mesh_frequency
                                                      + 1))]
        out.append((
            mesh_harmonics(spec, mesh_frequency=st.mesh_frequency, orders=orders,
                           search=SEARCH_FRACTION * min(sh.values()), avoid=others),
            sideband_families(spec, mesh_frequency=st.mesh_frequency, shafts=sh,
                              orders=orders, n_sidebands=n_sidebands, other_lines=others),
        ))
    return out


def _stft_bands(dynamic: np.ndarray, fs: float, spec: Spectrum, mesh_frequency: float,
                f_drive: float, orders: Sequence[int], opt, k: int,
                ) -> tuple[Spectrogram, tuple[dict, dict, dict, dict]]:
    """STFT of stage ``k`` (index from 0) and, per order n, around n f_m (half width
    f_m / 2): the STFT band energy, the band widths of the spectrum and of the mean STFT
    PSD, and the band energy's modulation at its driving shaft's frequency ``f_drive``.

    The STFT has ``opt.stft_frames_per_rev`` frames per revolution of the driving shaft,
    half overlapping: a further stage of a compound train is analysed as its own gear
    pair would be, its band around n f_m resolved however slow the stage (frames sized by
    the input shaft hold under two bins around a slow stage's mesh)."""
    nperseg = max(8, int(round(fs / (opt.stft_frames_per_rev * f_drive))))
    if nperseg > dynamic.size:
        frame = "a frame" if k == 0 else f"stage {k + 1}'s frame"
        why = "" if k == 0 else (f" (a revolution of its driving shaft, {f_drive:.4g} Hz, "
                                 f"over {opt.stft_frames_per_rev})")
        raise InputError("analysis.stft_frames_per_rev", opt.stft_frames_per_rev,
                         f"gives {frame} of {nperseg} samples{why}, longer than the record")
    sg = spectrogram(dynamic, fs, nperseg=nperseg, hop=max(1, nperseg // 2), window="hann")
    mean_psd = sg.psd.mean(axis=1)
    half = 0.5 * mesh_frequency
    energy, width_spec, width_stft, modulation = {}, {}, {}, {}
    for n in orders:
        centre = n * mesh_frequency
        energy[n] = band_energy(sg, center=centre, half_width=half)
        width_spec[n] = band_width(spec.frequency, spec.amplitude**2, center=centre,
                                   half_window=half, fraction=opt.band_fraction)
        width_stft[n] = band_width(sg.frequency, mean_psd, center=centre, half_window=half,
                                   fraction=opt.band_fraction)
        modulation[n] = modulation_index(energy[n], sg.time, frequency=f_drive)
    return sg, (energy, width_spec, width_stft, modulation)


def _settings(settings: AnalysisSettings | None, overrides: dict[str, Any]) -> AnalysisSettings:
    """``settings`` (default ``AnalysisSettings()``) with the keyword ``overrides`` applied."""
    base = AnalysisSettings() if settings is None else settings
    if not isinstance(base, AnalysisSettings):
        raise InputError("settings", type(base).__name__, "must be an AnalysisSettings")
    allowed = [f.name for f in dataclasses.fields(AnalysisSettings)]
    for key in overrides:
        if key not in allowed:
            raise InputError(key, overrides[key],
                             f"is not an analysis option; allowed: {', '.join(allowed)}")
    return dataclasses.replace(base, **overrides) if overrides else base
