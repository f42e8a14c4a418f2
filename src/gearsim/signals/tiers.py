"""Tiered analysis of one record: every quantity its inputs allow, and why not the others.

What a value needs decides the tier it belongs to:

==========  =====================================  ===========================================
tier        needs                                  gives
==========  =====================================  ===========================================
statistics  nothing                                RMS, peak, crest factor, kurtosis, skewness,
                                                   impulse, shape and clearance factors
spectrum    nothing (a sampling rate for Hz;       largest spectral lines, centroid, kurtogram
            without one, cycles per sample)        best band
shaft       a sampling rate and a shaft speed      shaft frequency, shaft-order amplitudes,
            (given, from a tacho channel, or       envelope spectrum at the shaft orders,
            estimated from the signal in a         cepstral shaft period, impact periodicity
            search range)
gear        sampling rate, speed and tooth counts  full gear analysis (:func:`~gearsim.signals.
            (or the stages of a compound train)    analyze.analyze`: mesh harmonics, sidebands,
                                                   STFT bands, TSA indicators; every stage's
                                                   mesh), TSA of every further gear, gear
                                                   indicators, demodulation
==========  =====================================  ===========================================

:func:`analyze_record` computes every tier its inputs allow and lists the others in
``skipped`` with the reason (a missing input, a record too short for the tier).
Nothing is an error that only prevents a tier: the call fails only
for an unusable signal (not 1-D, fewer than 2 samples, non-finite samples) or an invalid
option.

Provenance. The sampling rate, the speed and the tooth counts each carry a provenance:
``"file"`` (read from the record or its tacho channel), ``"given"`` (typed by the user),
``"config"`` (a gearbox configuration's kinematics: its nominal input speed, its teeth
and stages) or ``"estimate"`` (estimated from the signal); every tier records the provenance of what
it rests on (``rests_on``) and the text summary says it next to each tier.

Units: frequencies in Hz when the sampling rate is known, else in cycles per sample
(keys and the ``frequency_unit`` of the spectrum tier say which); speed in Hz (and rpm in
the text); amplitudes in the units of the signal.

Heavy imports (scipy, the toolbox modules) happen inside the tier that uses them, so a
statistics-only call costs numpy only.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gearsim.errors import InputError
from gearsim.io.measured import RUN_UP_TOL
from gearsim.signals import timedomain as td
from gearsim.signals._checks import as_signal

__all__ = [
    "MIN_REVOLUTIONS",
    "MIN_SPECTRUM_SAMPLES",
    "PROVENANCES",
    "RecordAnalysis",
    "analyze_record",
    "stage_features",
    "statistics",
]

#: Where a sampling rate, speed or tooth count came from.
PROVENANCES = ("file", "given", "config", "estimate")
#: Shortest record for the spectrum tier [samples].
MIN_SPECTRUM_SAMPLES = 16
#: Revolutions of the measured shaft the shaft tier needs (shaft orders resolved, TSA).
MIN_REVOLUTIONS = 2.0
#: Spectral lines reported by the spectrum tier.
N_LINES = 5
#: Shaft orders reported by the shaft tier.
SHAFT_ORDERS = (1, 2, 3)
#: Strongest lines reported from the order spectrum of a tracked record (local maxima
#: standing 6 dB above their neighbourhood's median, at most one per half order: the
#: mesh orders of every stage and their harmonics).
ORDER_LINES = 8

CPS = "cycles/sample"
#: A steady speed estimated from the signal (first and last pieces within
#: :data:`~gearsim.signals.speed.GIVEN_SPEED_TOLERANCE`) is still tracked, within this
#: fraction of the estimate on either side, and the record read in the order domain: a
#: wander of a few tenths of a percent spreads a mesh line over many bins (the
#: SpectraQuest record b30hz90: stage-1 mesh line 1.333 read in time, 2.150 in the order
#: domain, its 8 pieces read alone as steady records agree with the latter). 2 % holds the
#: wander and keeps the neighbouring lines of the strongest one out of the band.
STEADY_TRACK_SPAN = 0.02
#: Band of the phase demodulation of a steady estimated speed, as a fraction of the
#: slowest shaft's frequency (of the train the teeth or stages give, else the measured
#: shaft's): the filter's stopband starts at 0.75 of the band, so every shaft's first
#: sidebands (the gears' own modulation, what the gear tier looks for) stay out of the
#: tracked phase and only the slow wander of the speed is followed (Combet & Gelman 2007).
STEADY_TRACK_BAND = 0.5
#: Least median ridge-to-band power ratio of a speed tracked over the search range (a
#: run-up, or a record with no confident constant estimate): 16, 12 dB. White noise alone
#: gives 4.8 (the largest of a few neighbouring bins over the median), a steady 29.7 Hz
#: mesh line of 0.05 under noise of 0.3 9.6 (tracked, it wandered from 28.4 to 30.4 Hz
#: and halved another stage's line), 0.1 32; the SpectraQuest records 29-38 (mesh order
#: 32 over 20-40 Hz), a 10 -> 30 Hz run-up at -10 dB 147: below it the search's harmonic
#: does not stand out of the noise and is not tracked.
RIDGE_SNR = 16.0


def _f(v: Any) -> float | None:
    """A finite float or None."""
    try:
        v = float(v)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _fmt(v: Any, spec: str = ".4g") -> str:
    """``v`` formatted, or ``n/a`` for None."""
    return "n/a" if v is None else format(v, spec)


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _kurtosis(y: np.ndarray) -> float:
    """Kurtosis ``mean(d^4) / mean(d^2)^2`` of ``d = y - mean(y)``; NaN for a constant ``y``."""
    d = y - y.mean()
    v = float(np.mean(d * d))
    return float(np.mean(d**4) / v**2) if v > 0 else math.nan


def statistics(x: np.ndarray, *, remove_mean: bool = True) -> dict[str, float | None]:
    r"""Statistics that need nothing but the samples.

    With :math:`d = x - \bar x` (or :math:`d = x` if not ``remove_mean``) and moments
    :math:`m_k = \overline{(x - \bar x)^k}`: RMS :math:`\sqrt{\overline{d^2}}`, peak
    :math:`\max |d|`, crest factor peak/RMS, kurtosis :math:`m_4/m_2^2` (Pearson, 3 for
    Gaussian noise), skewness :math:`m_3/m_2^{3/2}`, impulse factor
    :math:`\max|d| / \overline{|d|}`, shape factor :math:`\mathrm{RMS} / \overline{|d|}`,
    clearance factor :math:`\max|d| / \overline{\sqrt{|d|}}^{\,2}` (Randall 2011, sec. 5.2;
    Lei et al. 2008), computed by :mod:`gearsim.signals.timedomain` (which loads no
    scipy). A ratio whose denominator is 0 (constant signal) is None.

    Parameters
    ----------
    x : array_like
        Signal (any units), 1-D, finite, at least 2 samples.
    remove_mean : bool
        RMS, peak and the factors of the signal minus its mean (the dynamic part).

    Returns
    -------
    dict
        ``n_samples``, ``mean``, ``std``, ``rms``, ``peak``, ``crest_factor``,
        ``kurtosis``, ``skewness``, ``impulse_factor``, ``shape_factor``,
        ``clearance_factor`` (amplitudes in signal units, factors dimensionless).

    Raises
    ------
    InputError
        If ``x`` is not a valid signal.
    """
    a = as_signal(x)
    mu = float(a.mean())
    d = a - mu if remove_mean else a

    def value(fn, signal: np.ndarray) -> float | None:
        try:  # a ratio whose denominator is 0 (constant signal) is None
            return fn(signal)
        except InputError:
            return None

    return {
        "n_samples": int(a.size), "mean": mu, "std": float(np.std(a)),
        "rms": td.rms(d), "peak": td.peak(d), "crest_factor": value(td.crest_factor, d),
        "kurtosis": value(td.kurtosis, a), "skewness": value(td.skewness, a),
        "impulse_factor": value(td.impulse_factor, d),
        "shape_factor": value(td.shape_factor, d),
        "clearance_factor": value(td.clearance_factor, d),
    }


@dataclass
class RecordAnalysis:
    """Everything :func:`analyze_record` computed on one record, tier by tier.

    Parameters
    ----------
    n_samples : int
        Length of the record.
    fs : float or None
        Sampling rate [Hz], None when unknown (frequencies in cycles per sample).
    fs_provenance : str or None
        ``"file"``, ``"given"`` or ``"estimate"``; None without a rate.
    speed : float or None
        Speed of the measured shaft [Hz] used by the shaft and gear tiers.
    speed_provenance : str or None
        ``"file"`` (tacho), ``"given"`` or ``"estimate"``.
    teeth : tuple of int or None
        Tooth counts, gear on the measured shaft first.
    teeth_provenance : str or None
        ``"given"``, ``"file"`` or ``"estimate"``.
    tiers : dict
        Tier name to its results (a dict with ``rests_on`` and the values).
    skipped : list of dict
        ``{"tier": ..., "reason": ...}`` for every tier (or part of one) not computed.
    source : dict
        Where the record came from (``file``, ``channel``, ``units``, ...), as given.
    units : str or None
        Units of the signal.
    analysis : object or None
        The :class:`~gearsim.signals.analysis.Analysis` of the gear tier (arrays for the
        figures), if computed.
    timings : dict
        Wall-clock time per tier [s].
    stages : tuple of (int, int) or None
        A compound train: ``(driving teeth, driven teeth)`` of each stage in power-flow
        order (:func:`gearsim.signals.analysis.kinematics`); ``teeth`` then lists the
        stages' pairs in order. None for a simple train.
    warnings : list of str
        What the tiers computed rests on and the record contradicts (a given speed the
        signal disagrees with: every tier still uses the speed given).
    """

    n_samples: int
    fs: float | None
    fs_provenance: str | None
    speed: float | None
    speed_provenance: str | None
    teeth: tuple[int, ...] | None
    teeth_provenance: str | None
    tiers: dict[str, dict] = field(default_factory=dict)
    skipped: list[dict] = field(default_factory=list)
    source: dict = field(default_factory=dict)
    units: str | None = None
    analysis: Any = None
    timings: dict[str, float] = field(default_factory=dict)
    stages: tuple[tuple[int, int], ...] | None = None
    warnings: list[str] = field(default_factory=list)

    @property
    def frequency_unit(self) -> str:
        """``"Hz"`` with a sampling rate, else ``"cycles/sample"``."""
        return "Hz" if self.fs is not None else CPS

    def features(self) -> dict[str, tuple[float | str | None, str]]:
        """Flat indicators of the record: name to ``(value, unit)``, for tables.

        Amplitudes are in ``signal`` units (the ``units`` of the record; the squared
        envelope's, ``envelope_order*``, in ``signal^2``); frequencies in
        Hz, or in cycles per sample when the name ends in ``_cps``. A compound train's
        gear tier gives stage 1's lines under the simple-train names and every further
        stage ``k`` as ``stage{k}_mesh_frequency_hz`` and the :func:`stage_features`.

        Returns
        -------
        dict of str to tuple
            Indicator name to (value or None, unit).
        """
        out: dict[str, tuple[Any, str]] = {}
        st = self.tiers.get("statistics", {})
        for k, u in (("rms", "signal"), ("peak", "signal"), ("crest_factor", "1"),
                     ("kurtosis", "1"), ("skewness", "1"), ("impulse_factor", "1"),
                     ("shape_factor", "1"), ("clearance_factor", "1")):
            if k in st:
                out[k] = (st[k], u)
        sp = self.tiers.get("spectrum")
        if sp:
            sfx, fu = ("hz", "Hz") if sp["frequency_unit"] == "Hz" else ("cps", CPS)
            if sp["lines"]:
                out[f"spectrum_peak_frequency_{sfx}"] = (sp["lines"][0]["frequency"], fu)
                out["spectrum_peak_amplitude"] = (sp["lines"][0]["amplitude"], "signal")
            out[f"spectral_centroid_{sfx}"] = (sp["centroid"], fu)
            kg = sp.get("kurtogram")
            if kg:
                out[f"kurtogram_center_{sfx}"] = (kg.get("center"), fu)
                out[f"kurtogram_bandwidth_{sfx}"] = (kg.get("bandwidth"), fu)
                out["kurtogram_kurtosis"] = (kg.get("kurtosis"), "1")
        sh = self.tiers.get("shaft")
        if sh:
            out["shaft_frequency_hz"] = (sh["shaft_frequency_hz"], "Hz")
            for row in sh["orders"]:
                out[f"shaft_order{row['order']}_amplitude"] = (row["amplitude"], "signal")
            for row in sh.get("envelope", {}).get("orders", []):
                out[f"envelope_order{row['order']}_amplitude"] = (row["amplitude"],
                                                                  "signal^2")
            cep = sh.get("cepstrum")
            if cep:
                out["cepstrum_period_ratio"] = (cep.get("period_ratio_to_T1"), "1")
            per = sh.get("periodicity")
            if per and "verdict" in per:
                out["periodicity_verdict"] = (per["verdict"], "")
        g = self.tiers.get("gear")
        if g:
            full = g["analysis"]
            out["mesh_frequency_hz"] = (full["train"]["mesh_frequency_hz"], "Hz")
            for h in full["mesh_harmonics"]:
                out[f"mesh{h['order']}_amplitude"] = (h["amplitude"], "signal")
            for fam in full["sidebands"]:
                out[f"ser_mesh{fam['order']}_{fam['shaft']}"] = (fam.get("ser"), "1")
            for k in ("fm0", "fm4", "na4", "m6a", "m8a"):
                out[k] = (full["tsa"].get(k), "1")
            out["impact_period_ratio"] = (full["impacts"].get("period_ratio_to_T1"), "1")
            for st in full.get("stages", [])[1:]:
                out[f"stage{st['stage']}_mesh_frequency_hz"] = (st["mesh_frequency_hz"], "Hz")
            out |= stage_features(full)
            for gear in g.get("gears", []):
                for k in ("fm0", "fm4", "m6a", "m8a"):
                    if gear.get(k) is not None:
                        out[f"{gear['shaft']}_{k}"] = (gear[k], "1")
            for k, v in (g.get("indicators") or {}).items():
                if isinstance(v, (int, float)) and not isinstance(v, bool):
                    out[k] = (v, "1")
            for k, v in (g.get("demodulation") or {}).items():
                if isinstance(v, (int, float)) and not isinstance(v, bool):
                    out[f"demodulation_{k}"] = (v, "1")
        pl = self.tiers.get("planetary")
        if pl:
            out["planet_pass_hz"] = (pl["frequencies"]["planet_pass"], "Hz")
            for sb in pl["sidebands"] or []:
                out[f"sideband_predicted_share_m{sb['harmonic']}"] = (sb["predicted_share"], "1")
            for name, line in ((pl["envelope"] or {}).get("lines") or {}).items():
                out[f"envelope_{name}_db"] = (line["to_floor_db"], "dB")
            sep = pl["separation"]
            if sep:
                for p in sep["planets"]:
                    out[f"planet{p['planet']}_fm4"] = (p["fm4"], "1")
                out["sun_fm4"] = (sep["sun"]["fm4"], "1")
        return {k: (_f(v) if not isinstance(v, str) else v, u) for k, (v, u) in out.items()}

    def to_dict(self) -> dict[str, Any]:
        """JSON-serialisable summary.

        Returns
        -------
        dict
            ``source``, ``n_samples``, ``fs_hz`` and its provenance, ``speed_hz``,
            ``speed_rpm`` and provenance, ``teeth`` and provenance (with ``stages``, the
            ``[driving, driven]`` teeth of each stage, for a compound train),
            ``frequency_unit``, ``tiers``, ``skipped``, ``warnings``, ``timings_s``.
        """
        return {
            "source": dict(self.source), "units": self.units, "n_samples": self.n_samples,
            "fs_hz": self.fs, "fs_provenance": self.fs_provenance,
            "duration_s": self.n_samples / self.fs if self.fs else None,
            "speed_hz": self.speed,
            "speed_rpm": 60.0 * self.speed if self.speed is not None else None,
            "speed_provenance": self.speed_provenance,
            "teeth": list(self.teeth) if self.teeth else None,
            "teeth_provenance": self.teeth_provenance,
            **({"stages": [list(p) for p in self.stages]} if self.stages else {}),
            "frequency_unit": self.frequency_unit,
            "tiers": self.tiers, "skipped": list(self.skipped),
            "warnings": list(self.warnings), "timings_s": dict(self.timings),
        }

    def text(self) -> str:
        """Text summary: what each value rests on, the values, and what was skipped.

        Returns
        -------
        str
            Several lines.
        """
        u = f" {self.units}" if self.units else ""
        src = self.source
        head = " ".join(str(src[k]) for k in ("file", "channel") if src.get(k) is not None)
        lines = [f"{head or 'record'}: {self.n_samples} samples"
                 + (f" ({self.n_samples / self.fs:.4g} s)" if self.fs else "")]
        rests = [f"fs {self.fs:g} Hz ({self.fs_provenance})" if self.fs
                 else "fs unknown (frequencies in cycles/sample)"]
        if self.speed is not None:
            span = self.tiers.get("shaft", {}).get("speed_range_hz")
            rests.append(f"speed {60 * self.speed:.6g} rpm = {self.speed:.6g} Hz "
                         f"({self.speed_provenance}" + (f"; mean of {span[0]:.5g} to "
                                                        f"{span[1]:.5g} Hz)" if span else ")"))
        if self.stages:
            rests.append("stages " + ", ".join(f"{d}/{n}" for d, n in self.stages)
                         + f" ({self.teeth_provenance})")
        elif self.teeth:
            rests.append(f"teeth {', '.join(map(str, self.teeth))} ({self.teeth_provenance})")
        lines.append("  rests on: " + "; ".join(rests))
        lines += [f"  WARNING: {w}" for w in self.warnings]
        d = src.get("dropped")
        if isinstance(d, dict):  # io.record.DroppedSamples.to_dict()
            lines.append(f"  dropped {d['count']} samples ({d['nonfinite']} non-finite) at "
                         f"the ends, file samples {d['first']}..{d['last']}: kept "
                         f"{d['kept'][0]}..{d['kept'][1] - 1}")
        st = self.tiers.get("statistics")
        if st:
            def g(k: str, fmt: str = ".4g") -> str:
                return "n/a" if st.get(k) is None else format(st[k], fmt)
            lines.append(f"  statistics (need nothing): RMS {g('rms', '.5g')}{u}  peak "
                         f"{g('peak', '.5g')}{u}  crest {g('crest_factor')}  kurtosis "
                         f"{g('kurtosis')}  skewness {g('skewness')}  impulse "
                         f"{g('impulse_factor')}  shape {g('shape_factor')}  clearance "
                         f"{g('clearance_factor')}")
        sp = self.tiers.get("spectrum")
        if sp:
            fu = sp["frequency_unit"]
            lines.append(f"  spectrum [{fu}; fs {sp['rests_on']['fs']}]: lines "
                         + ", ".join(f"{r['frequency']:.5g} ({r['amplitude']:.3g}{u})"
                                     for r in sp["lines"])
                         + f"; centroid {_fmt(sp['centroid'], '.5g')} {fu}")
            kg = sp.get("kurtogram")
            if kg:
                lines.append(f"    kurtogram best band: centre {_fmt(kg['center'], '.5g')} {fu}, "
                             f"width {_fmt(kg['bandwidth'])} {fu}, kurtosis "
                             f"{_fmt(kg['kurtosis'])}")
        sh = self.tiers.get("shaft")
        if sh:
            r = sh["rests_on"]
            lines.append(f"  shaft [speed {r['speed']}, fs {r['fs']}]: f_r "
                         f"{sh['shaft_frequency_hz']:.6g} Hz{_order_domain(sh)}; orders "
                         + ", ".join(f"{o['order']}x {o['amplitude']:.4g}{u}"
                                     for o in sh["orders"]))
            osp = sh.get("order_spectrum")
            if osp:
                lines.append("    order spectrum: " + ", ".join(
                    f"{o['order']:.4g}x {o['amplitude']:.4g}{u}" for o in osp["lines"]))
            env = sh.get("envelope")
            if env:
                u2 = f" ({self.units})^2" if self.units else ""  # squared envelope
                lines.append("    squared envelope at shaft orders: " + ", ".join(
                    f"{o['order']}x {o['amplitude']:.4g}{u2}" for o in env["orders"]))
            cep = sh.get("cepstrum")
            if cep and cep.get("period_s") is not None:
                lines.append(f"    cepstral shaft period {1e3 * cep['period_s']:.4g} ms "
                             f"({cep['period_ratio_to_T1']:.4f} x T1)")
            per = sh.get("periodicity")
            if per and "verdict" in per:
                lines.append(f"    impact periodicity: {per['verdict']}")
        g_ = self.tiers.get("gear")
        if g_:
            r = g_["rests_on"]
            full = g_["analysis"]
            stages = full.get("stages", [])
            first = (f" (stage 1, {stages[0]['teeth'][0]}/{stages[0]['teeth'][1]})"
                     if stages else "")
            lines.append(f"  gear [teeth {r['teeth']}, speed {r['speed']}, fs {r['fs']}]: "
                         f"f_m {full['train']['mesh_frequency_hz']:.6g} Hz{first}"
                         f"{_order_domain(g_)}")
            lines += _harmonic_lines(full["mesh_harmonics"], full["sidebands"], u, "    ")
            for st in stages[1:]:  # a compound train: a line per further stage
                lines.append(f"    gear stage {st['stage']} ({st['teeth'][0]}/"
                             f"{st['teeth'][1]}): f_m {st['mesh_frequency_hz']:.6g} Hz, "
                             "shafts " + ", ".join(f"{k} {v:.5g} Hz" for k, v in
                                                   st["shaft_frequencies_hz"].items()))
                lines += _harmonic_lines(st["mesh_harmonics"], st["sidebands"], u, "      ")
            t = full["tsa"]
            lines.append(f"    TSA ({t['n_averages']} revs): FM0 {t['fm0']:.4g}  FM4 "
                         f"{t['fm4']:.4g}  NA4 {t['na4']:.4g}  M6A {t['m6a']:.4g}  M8A "
                         f"{t['m8a']:.4g}")
            im = full["impacts"]
            lines.append(f"    impacts: {im['count']}; period "
                         + (f"{im['period_ratio_to_T1']:.4f} x T1"
                            if im.get("period_ratio_to_T1") is not None else "n/a"))
            if "ratios_to_baseline" in full:
                lines.append("    ratio to baseline: " + ", ".join(
                    f"{k} {100 * v:.1f} %" for k, v in full["ratios_to_baseline"].items()))
            for gear in g_.get("gears", []):
                if gear.get("fm4") is not None:
                    lines.append(f"    TSA {gear['shaft']} (Z {gear['teeth']}, "
                                 f"{gear['n_averages']} revs): FM0 {gear['fm0']:.4g}  "
                                 f"FM4 {gear['fm4']:.4g}")
            for name in ("indicators", "demodulation"):
                vals = {k: v for k, v in (g_.get(name) or {}).items()
                        if isinstance(v, float)}
                if vals:
                    lines.append(f"    {name}: " + "  ".join(f"{k} {v:.4g}"
                                                            for k, v in vals.items()))
        pl = self.tiers.get("planetary")
        if pl:
            fq = pl["frequencies"]
            lines.append(f"  planetary [stage {pl['rests_on']['stage']}, fs "
                         f"{pl['rests_on'].get('fs')}]: f_c {fq['carrier']:.5g} Hz, f_m "
                         f"{fq['mesh']:.6g} Hz, planet pass {fq['planet_pass']:.5g} Hz; "
                         f"fault frequencies sun {fq['sun_fault']:.5g}, planet "
                         f"{fq['planet_fault']:.5g}, ring {fq['ring_fault']:.5g} Hz")
            for sb in pl["sidebands"] or []:
                lines.append(f"    {sb['harmonic']} f_m: share of sideband power at the "
                             f"orders equal spacing allows {sb['predicted_share']:.4g}; "
                             f"largest order {sb['dominant_order']:+d} (predicted "
                             f"{sb['predicted_dominant_order']:+d})")
            env = pl["envelope"]
            if env and env["lines"]:
                lines.append("    envelope lines over the local floor: " + ", ".join(
                    f"{k} {v['to_floor_db']:.1f} dB" for k, v in env["lines"].items()
                    if v["to_floor_db"] is not None))
            sep = pl["separation"]
            if sep:
                top = sep["highest_fm4_planet"]
                lines.append(f"    separated averages ({sep['window']}): FM4 " + "  ".join(
                    f"planet-{p['planet']} {_fmt(p['fm4'], '.3g')}" for p in sep["planets"])
                    + f"  sun {_fmt(sep['sun']['fm4'], '.3g')}; highest "
                    + (f"planet-{top}" if top else "none (no FM4: a constant record)"))
        for s in self.skipped:
            lines.append(f"  skipped {s['tier']}: {s['reason']}")
        return "\n".join(lines)


def _harmonic_lines(harmonics: list[dict], sidebands: list[dict], u: str,
                    indent: str) -> list[str]:
    """Text lines of mesh harmonics (``to_dict`` rows) with the SER of each family."""
    lines = []
    for h in harmonics:
        fams = [f for f in sidebands if f["order"] == h["order"]]
        lines.append(f"{indent}{h['order']} f_m {h['frequency_hz']:.6g} Hz  A "
                     f"{h['amplitude']:.4g}{u}  SER " + "  ".join(
                         f"{f['shaft']} {_fmt(f['ser'], '.3g')}" for f in fams))
    return lines


def stage_features(summary: dict) -> dict[str, tuple[Any, str]]:
    """Features of the stages after the first of a compound-train analysis.

    Stage 1 of a compound train is the reference gear's mesh, whose features keep the
    simple-train names; every further stage ``k`` is named with the prefix
    ``stage{k}_``. One flattening for the batch table
    (:meth:`RecordAnalysis.features`) and the study features
    (:func:`gearsim.studies.sweep_case.features`).

    Parameters
    ----------
    summary : dict
        :meth:`gearsim.signals.analysis.Analysis.to_dict` of an analysis (a simple train
        has no ``stages`` and gives no feature).

    Returns
    -------
    dict of str to tuple
        Name to ``(value or None, unit)``: ``stage{k}_mesh_amplitude_o{n}`` (signal units),
        ``stage{k}_sb_{ser,cv,flatness}_o{n}_{shaft}`` of the stage's two shafts (1),
        ``stage{k}_band_energy_o{n}`` (mean-square value in the STFT band, signal units
        squared), ``stage{k}_band_cv_o{n}`` (1) and ``stage{k}_band_modulation_o{n}`` (1,
        modulation at the stage's driving shaft).
    """
    out: dict[str, tuple[Any, str]] = {}
    for st in summary.get("stages", []):
        if st["stage"] == 1:  # the simple-train names
            continue
        p = f"stage{st['stage']}_"
        for h in st["mesh_harmonics"]:
            out[f"{p}mesh_amplitude_o{h['order']}"] = (h["amplitude"], "signal")
        for f in st["sidebands"]:
            for k in ("ser", "cv", "flatness"):
                out[f"{p}sb_{k}_o{f['order']}_{f['shaft']}"] = (f[k], "1")
        for b in st["bands"]:
            out[f"{p}band_energy_o{b['order']}"] = (b["energy_mean"], "signal^2")
            out[f"{p}band_cv_o{b['order']}"] = (b["energy_cv"], "1")
            out[f"{p}band_modulation_o{b['order']}"] = (b["modulation_at_driving_shaft"], "1")
    return out


def _hann_amplitude(a: np.ndarray) -> np.ndarray:
    """One-sided amplitude spectrum (periodic Hann, mean removed), DC and Nyquist unhalved.

    Computed once per record and shared by the spectrum and shaft tiers.
    """
    n = a.size
    w = 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(n) / n)
    return np.abs(np.fft.rfft((a - a.mean()) * w)) * (2.0 / w.sum())


def _spectrum_tier(a: np.ndarray, fs: float | None,
                   amp: np.ndarray | None = None) -> dict[str, Any]:
    """Amplitude spectrum (periodic Hann, mean removed) by numpy; lines and centroid."""
    n = a.size
    rate = fs if fs is not None else 1.0
    amp = (_hann_amplitude(a) if amp is None else amp).copy()
    amp[0] *= 0.5
    if n % 2 == 0:
        amp[-1] *= 0.5
    freq = np.arange(amp.size) * (rate / n)
    inner = amp[1:-1]
    k = np.flatnonzero((inner > amp[:-2]) & (inner >= amp[2:])) + 1
    top = k[np.argsort(amp[k])[::-1][:N_LINES]]
    power = amp * amp
    centroid = float(np.sum(freq * power) / np.sum(power)) if power.sum() > 0 else math.nan
    return {
        "frequency_unit": "Hz" if fs is not None else CPS,
        "resolution": rate / n, "window": "hann (mean removed)",
        "lines": [{"frequency": float(freq[i]), "amplitude": float(amp[i])} for i in top],
        "centroid": _f(centroid),
    }


def _kurtogram(a: np.ndarray, fs: float | None, skipped: list) -> dict | None:
    from gearsim.signals.kurtogram import fast_kurtogram

    try:
        res = fast_kurtogram(a, fs if fs is not None else 1.0)
    except InputError as exc:
        skipped.append({"tier": "spectrum.kurtogram", "reason": _first_line(exc)})
        return None
    best = res.best
    return {"center": _f(best.center), "bandwidth": _f(best.bandwidth),
            "kurtosis": _f(best.kurtosis), "level": _f(best.level)}


def _resolve_speed(a, fs, speed, tacho, ppr, search, order, skipped, prov, warnings,
                   slowest=1.0, config=None):
    """(speed Hz, provenance, profile or None, SpeedEstimate or None, tracked); speed None
    with a skip reason when it cannot be had; ``tracked`` when the profile follows a speed
    estimated as steady (:data:`STEADY_TRACK_SPAN`: the record is read in the order
    domain). ``slowest``: the slowest shaft's frequency over the
    measured one's (:data:`STEADY_TRACK_BAND`); ``config``: the configuration a speed of
    provenance ``config`` came from, as written."""
    from gearsim.signals import speed as sp

    if speed is not None:
        # checked against the mesh order only: with no tooth count the shaft line (order 1)
        # may be absent from a healthy gear signal, and a missing line is no disagreement
        if order > 1:
            try:
                label = ("given speed {hz} Hz" if prov != "config" else "config speed "
                         "{hz} Hz (" + (f"the operating speed of --config {config}" if config
                                        else "the configuration's operating speed") + ")")
                warn = sp.check_given_speed(a, fs, float(speed), order=order, label=label)
            except InputError as exc:
                whose = {"config": "the configuration's", "file": "the file's"}.get(
                    prov, "the given")
                why = {"x.length": f"the check needs {sp.MIN_PERIODS:g} shaft revolutions, "
                                   f"{sp.MIN_PERIODS / speed:.4g} s at {speed:.4g} Hz, and the "
                                   f"record lasts {a.size / fs:.4g} s: a longer record would "
                                   "allow it",
                       "x": f"the record has no line near the mesh order {order:g} of that "
                            "speed to compare it with"}.get(exc.parameter, _first_line(exc))
                skipped.append({"tier": "shaft.speed_check", "reason": f"{whose} speed is not "
                                f"checked against the record: {why}"})
                warn = None
            if warn and prov == "config":  # the configuration's speed, not the user's
                warnings.append(f"{warn}; every tier uses it: give --shaft-rpm or "
                                "--speed-search")
            elif warn:  # every tier uses the speed given: a warning, not a skip
                warnings.append(f"{warn}; every tier uses the given speed")
        return float(speed), prov or "given", None, None, False
    if tacho is not None:
        tach = as_signal(tacho, name="tacho")
        if tach.size != a.size:
            raise InputError("tacho.length", tach.size, f"must equal the signal length {a.size}")
        try:
            prof = sp.speed_from_tacho(tach, fs, pulses_per_rev=ppr)
        except InputError as exc:
            skipped.append({"tier": "shaft", "reason": f"tacho unusable: {_first_line(exc)}"})
            return None, None, None, None, False
        return prof.mean_frequency, "file", prof, None, False
    if search is None:
        skipped.append({"tier": "shaft", "reason": "needs a shaft speed: give one (--shaft-rpm), "
                        "a tacho channel (--tacho) or a search range to estimate it "
                        "(--speed-search)"})
        return None, None, None, None, False
    # constant speed from the line families; where the first and last pieces of the record
    # disagree, the constant model holds on a short central piece, whose dominant line (or
    # the given tooth count's mesh line when no line family is found) is tracked by the
    # ridge and phase demodulation, if the record is long enough for them
    est = why = None
    varies = False
    try:
        est = sp.estimate_constant_speed(a, fs, search=search)
        varies = abs(est.drift) > sp.GIVEN_SPEED_TOLERANCE
        if varies:
            n = min(a.size, 2 * math.ceil(sp.MIN_PERIODS * fs / search[0]))
            est = sp.estimate_constant_speed(a[(a.size - n) // 2:][:n], fs, search=search)
    except InputError as exc:
        est, why = None, f"no constant-speed estimate: {_first_line(exc)}"
    if est is not None and est.confidence < sp.MIN_CONFIDENCE:
        why = (f"speed estimate {est.frequency:.6g} Hz has confidence {est.confidence:.2f} < "
               f"{sp.MIN_CONFIDENCE} (narrow --speed-search or give --shaft-rpm)")
        est = None
    if (varies and est is not None) or (est is None and order > 1):
        try:
            prof = sp.estimate_speed(a, fs, order=est.order if est else order, search=search,
                                     min_ridge_snr=RIDGE_SNR)
            return prof.mean_frequency, "estimate", prof, est, False
        except InputError as exc:
            skipped.append({"tier": "shaft.tracking", "reason": f"speed not tracked: "
                            f"{_first_line(exc)}"})
    if est is None:
        skipped.append({"tier": "shaft", "reason": why})
        return None, None, None, None, False
    # a steady speed's wander, followed within STEADY_TRACK_SPAN of the estimate on the
    # measured gear's mesh line (the highest order known to be strong: the narrowest band)
    q = order if order > 1 else est.teeth or est.order
    band = STEADY_TRACK_BAND * slowest * est.frequency
    need = sp.tracking_samples(fs, band)
    why = (f"the record ({a.size / fs:.4g} s) is shorter than the {need / fs:.4g} s its "
           "tracking filter needs" if a.size < need else None)
    if why is None:
        try:
            prof = sp.estimate_speed(a, fs, order=q,
                                     search=(est.frequency * (1.0 - STEADY_TRACK_SPAN),
                                             est.frequency * (1.0 + STEADY_TRACK_SPAN)),
                                     bandwidth=band)
        except InputError as exc:
            why = _first_line(exc)
    if why is not None:
        skipped.append({"tier": "shaft.tracking", "reason": "steady speed not tracked, lines "
                        f"read at the estimate: {why}"})
        return est.frequency, "estimate", None, est, False
    lo, hi = _per_revolution(prof, fs)
    if not ((1.0 - STEADY_TRACK_SPAN) * est.frequency <= lo <= hi
            <= (1.0 + STEADY_TRACK_SPAN) * est.frequency):
        skipped.append({"tier": "shaft.tracking", "reason": "steady speed not tracked, lines "
                        f"read at the estimate: the tracked speed ({lo:.5g} to {hi:.5g} Hz a "
                        f"revolution) leaves {100 * STEADY_TRACK_SPAN:g} % of the estimate "
                        f"{est.frequency:.6g} Hz: its line is too weak to follow"})
        return est.frequency, "estimate", None, est, False
    return est.frequency, "estimate", prof, est, True


def _order_domain(tier: dict) -> str:
    """The text's note of a tier read in the order domain (:func:`_at_mean_speed`)."""
    od = tier.get("order_domain")
    return (f" (order domain: resampled at equal angle steps of {od['mean_speed_hz']:.6g} Hz)"
            if od else "")


def _times_at(profile, fs: float):
    """Time [s] at shaft angles [rev] of ``profile``: a tacho's pulse times are quantised
    to the samples (uniform error of variance 1 / (12 fs^2)), so for a tacho the cubic
    smoothing spline of time against angle whose squared residuals sum to that variance
    times the pulses (Reinsch 1967), in place of the spline through every pulse; else the
    profile's own :meth:`~gearsim.signals.speed.SpeedProfile.times_at`."""
    if profile.source != "tacho":
        return profile.times_at
    from scipy.interpolate import UnivariateSpline

    return UnivariateSpline(profile.angle, profile.time, k=3,
                            s=profile.time.size / (12.0 * fs**2))


def _per_revolution(profile, fs: float) -> tuple[float, float]:
    """Lowest and highest speed [Hz] over a whole revolution of ``profile`` outside the
    tracking filter's edges (a tracked phase's derivative wobbles where its line fades:
    b30hz0 reaches 32.5 Hz for 0.04 s, a tenth of a tooth, at a steady 29.76 Hz); the
    profile's own range when fewer than two revolutions remain."""
    lo, hi = profile.angle_at(np.array([profile.time[0] + profile.edge,
                                        profile.time[-1] - profile.edge]))
    revs = np.arange(math.ceil(lo), math.floor(hi) + 1, dtype=float)
    f = (1.0 / np.diff(_times_at(profile, fs)(revs)) if revs.size > 2
         else np.asarray(profile.frequency, dtype=float))
    return float(f.min()), float(f.max())


def _at_mean_speed(a, fs, profile) -> tuple[np.ndarray, float] | None:
    """The record resampled at equal shaft-angle steps ``f / fs`` (computed order
    tracking, Fyfe & Munck 1997; Combet & Gelman 2007 for a tracked phase): the record
    the shaft would give at its mean speed ``f`` [Hz] over the whole revolutions of the
    profile's reliable part (its ``edge`` left out at each end), at the same ``fs``.
    Every line of a shaft order stands at order x ``f`` however the speed changed, and
    the TSA's revolutions are equal. Cubic interpolation of the samples
    (:func:`~gearsim.signals.tsa.cubic_resample`): relative error (5/384)(2 pi f' / fs)^4
    at a line of ``f'`` Hz, 7e-4 at 1 kHz and fs 12.8 kHz. None when the reliable part
    holds fewer than ``MIN_REVOLUTIONS`` whole revolutions."""
    from gearsim.signals.tsa import cubic_resample

    times_at = _times_at(profile, fs)
    t_lo = max(float(profile.time[0]) + profile.edge, 0.0)
    t_hi = min(float(profile.time[-1]) - profile.edge, (a.size - 1) / fs)
    lo, hi = profile.angle_at(np.array([t_lo, t_hi]))
    k0, k1 = math.ceil(lo), math.floor(hi)
    if k1 - k0 < MIN_REVOLUTIONS:  # the record's rule, on its reliable part
        return None
    f = (k1 - k0) / float(np.ptp(times_at(np.array([k0, k1], dtype=float))))
    angles = k0 + np.arange(int((k1 - k0) * fs / f)) * (f / fs)
    return cubic_resample(a, fs, np.clip(times_at(angles), 0.0, (a.size - 1) / fs)), f


def _order_lines(a, fs, profile) -> dict[str, Any]:
    """Strongest lines of the order spectrum of the order-tracked record (orders of the
    tracked shaft: every stage's mesh shows at its own order, z times its speed ratio)."""
    from scipy.ndimage import median_filter
    from scipy.signal import find_peaks

    from gearsim.signals.ordertrack import default_samples_per_rev, order_spectrum

    orders, amp = order_spectrum(a, fs, profile,
                                 samples_per_rev=default_samples_per_rev(fs, profile))
    floor = median_filter(amp, size=31, mode="nearest")
    # one line per half order: a line smeared by the tacho's angle error (it grows with
    # the order) splits into neighbouring maxima
    peaks, _ = find_peaks(amp, height=2.0 * floor, distance=max(1, int(0.5 / orders[1])))
    top = peaks[np.argsort(amp[peaks])[::-1][:ORDER_LINES]]
    return {"resolution_orders": float(orders[1]),
            "lines": [{"order": float(orders[i]), "amplitude": float(amp[i])} for i in top]}


def _other_orders(f_r, teeth, stages, top) -> list[float]:
    """Orders (Hz) up to ``top f_r`` of the train's shafts other than the reference one
    (shaft frequencies by :func:`~gearsim.signals.analysis.kinematics`); none without
    teeth or stages."""
    if not teeth:
        return []
    from gearsim.signals.analysis import kinematics

    kin = kinematics(shaft_frequency=f_r, stages=stages) if stages else \
        kinematics(shaft_frequency=f_r, teeth=teeth)
    return [m * f for f in kin.shafts.values() if abs(f - f_r) > 1e-9 * f_r
            for m in range(1, int(top * f_r / f) + 1)]


def _shaft_tier(a, fs, f_r, rests, skipped, profile=None, teeth=None,
                amp=None, stages=None, steady=None) -> dict[str, Any]:
    """The shaft tier; with ``steady`` = (record, speed) of :func:`_at_mean_speed` (a
    speed that varies) its lines (orders, envelope, cepstrum, periodicity) are read on
    the order-domain record at its mean speed, the order spectrum and tracked TSA on the
    record with its profile."""
    from gearsim.signals.cepstrum import real_cepstrum
    from gearsim.signals.envelope import envelope_spectrum
    from gearsim.signals.ordertrack import tracked_tsa
    from gearsim.signals.periodicity import impact_periodicity
    from gearsim.signals.spectrum import Spectrum, tone

    out: dict[str, Any] = {"rests_on": rests, "shaft_frequency_hz": f_r,
                           "shaft_rpm": 60.0 * f_r}
    if profile is not None:
        fr = np.asarray(profile.frequency, dtype=float)
        out["speed_range_hz"] = list(_per_revolution(profile, fs))
        try:
            t, q = tracked_tsa(a, fs, profile, teeth=int(teeth[0]) if teeth else 1)
            out["tracked_tsa"] = {"n_averages": int(t.n_averages),
                                  "samples_per_rev": int(t.samples_per_rev), "quality": _f(q)}
        except InputError as exc:
            skipped.append({"tier": "shaft.tracked_tsa", "reason": _first_line(exc)})
        try:
            out["order_spectrum"] = _order_lines(a, fs, profile)
        except InputError as exc:
            skipped.append({"tier": "shaft.order_spectrum", "reason": _first_line(exc)})
    spread = 0.0 if profile is None else float(np.max(np.abs(fr - f_r)))
    if steady is not None:
        a, f_r, amp, spread = steady[0], steady[1], None, 0.0
        out["order_domain"] = {"mean_speed_hz": f_r, "samples": int(a.size)}
    n = a.size
    if amp is None:
        amp = _hann_amplitude(a)
    # order k is read within the window's main lobe of k f_r, widened to the speed's own
    # spread (a tracked or tacho profile), never reaching into the main lobe of another
    # shaft's order (the train's other shafts, as the teeth or stages know them)
    avoid = _other_orders(f_r, teeth, stages, max(SHAFT_ORDERS) + 1.0)

    def read(spec) -> list[dict[str, Any]]:
        rows = []
        for k in SHAFT_ORDERS:
            if k * f_r >= 0.5 * fs:
                break
            t = tone(spec, k * f_r, search=max(spec.lobe_bins * spec.df, k * spread),
                     avoid=avoid)
            rows.append({"order": k, "frequency_hz": t.frequency, "amplitude": t.amplitude})
        return rows

    out["orders"] = read(Spectrum(np.arange(amp.size) * (fs / n), amp, "hann", fs, n))
    try:
        es = envelope_spectrum(a, fs)
        out["envelope"] = {"orders": read(es)}
    except (InputError, AttributeError, TypeError) as exc:
        skipped.append({"tier": "shaft.envelope", "reason": _first_line(exc)})
    try:
        q, v = real_cepstrum(a, fs)
        t1 = 1.0 / f_r
        sel = (q >= 0.8 * t1) & (q <= 1.2 * t1)
        if sel.any():
            j = np.flatnonzero(sel)[np.argmax(v[sel])]
            out["cepstrum"] = {"period_s": float(q[j]), "value": float(v[j]),
                               "period_ratio_to_T1": float(q[j] / t1)}
        else:
            skipped.append({"tier": "shaft.cepstrum",
                            "reason": "record shorter than 1.2 shaft periods"})
    except (InputError, TypeError, ValueError) as exc:
        skipped.append({"tier": "shaft.cepstrum", "reason": _first_line(exc)})
    try:
        res = impact_periodicity(a, fs, frequency=f_r)
        out["periodicity"] = {"verdict": str(res.verdict), "p_value": _f(res.p_value),
                              "alpha": _f(res.alpha), "frequency_hz": _f(res.frequency)}
    except (InputError, TypeError) as exc:
        skipped.append({"tier": "shaft.periodicity", "reason": _first_line(exc)})
    return out


def _gear_tier(a, fs, f_r, teeth, pulses_tacho, settings, rests, skipped,
               baseline, baseline_tacho, stages=None, profile=None) -> tuple[dict | None, Any]:
    """The gear tier: :func:`~gearsim.signals.analysis.analyze` of the simple train
    ``teeth`` or the compound train ``stages`` (every stage's mesh in one analysis),
    and the TSA of the gear on every further shaft. A compound analysis refused for a
    stage after the first (e.g. a record too short for the slowest shaft's sidebands)
    falls back to stage 1's pair, with the reason as the skipped tier ``gear.stages``.
    With a tacho (or a tracked phase, ``pulses_tacho``) and its ``profile``, a further
    shaft's revolutions start where the reference angle times the speed ratio passes a
    whole number (the tacho's smoothing spline, :func:`_times_at`), so that they follow
    a changing speed."""
    from gearsim.signals.analysis import analyze

    kw: dict[str, Any] = {"settings": settings}
    if pulses_tacho is not None:
        kw["tacho"] = pulses_tacho
        if baseline is not None:
            kw["baseline_tacho"] = baseline_tacho
    else:
        kw["shaft_frequency"] = f_r
    train = {"stages": stages} if stages else {"teeth": teeth}
    try:
        try:
            full = analyze(a, fs, baseline=baseline, **train, **kw)
        except InputError as exc:
            if not stages or exc.parameter.startswith(("analysis.", "settings")):
                raise
            full = analyze(a, fs, teeth=stages[0], baseline=baseline, **kw)
            skipped.append({"tier": "gear.stages", "reason": _first_line(exc)})
    except InputError as exc:
        if exc.parameter.startswith(("analysis.", "settings")):
            raise
        skipped.append({"tier": "gear", "reason": _first_line(exc)})
        return None, None
    out: dict[str, Any] = {"rests_on": rests, "analysis": full.to_dict()}
    # TSA of the gear on every further shaft, at its shaft frequency: a simple train's
    # gear j on shaft j; a compound train's driven gear of stage k on shaft k + 1
    from gearsim.signals.analysis import _samples_per_rev
    from gearsim.signals.tsa import condition_indicators, tsa

    gears = []
    kin = full.kinematics
    further = ([(st.shafts[1], st.teeth[1]) for st in kin.stages] if kin.compound else
               [(f"shaft{j}", z) for j, z in enumerate(kin.teeth[1:], start=2)])
    for label, z in further:
        f_j = kin.shafts[label]
        row: dict[str, Any] = {"shaft": label, "teeth": int(z), "shaft_frequency_hz": f_j}
        if a.size / fs < MIN_REVOLUTIONS / f_j:
            skipped.append({"tier": f"gear.tsa.{label}", "reason": f"record "
                            f"{a.size / fs:.4g} s shorter than {MIN_REVOLUTIONS:g} "
                            f"revolutions of {label} ({MIN_REVOLUTIONS / f_j:.4g} s)"})
            continue
        try:
            if pulses_tacho is not None and profile is not None:
                ratio = f_j / kin.reference_frequency
                k = np.arange(math.ceil(profile.angle[0] * ratio),
                              math.floor(profile.angle[-1] * ratio) + 1)
                t = tsa(a, fs, samples_per_rev=_samples_per_rev(fs, f_j),
                        pulses=_times_at(profile, fs)(k / ratio))
            else:
                t = tsa(a, fs, samples_per_rev=_samples_per_rev(fs, f_j), shaft_frequency=f_j)
            ind, _, _ = condition_indicators(t, teeth=int(z),
                                             shaft_harmonics=full.options["shaft_harmonics"],
                                             sideband_orders=full.options["sideband_orders"])
        except InputError as exc:
            skipped.append({"tier": f"gear.tsa.{label}", "reason": _first_line(exc)})
            continue
        row |= {"n_averages": ind.n_averages, "fm0": _f(ind.fm0), "fm4": _f(ind.fm4),
                "m6a": _f(ind.m6a), "m8a": _f(ind.m8a)}
        gears.append(row)
    out["gears"] = gears
    out["indicators"] = _gear_indicators(full, teeth, skipped)
    out["demodulation"] = _demodulation(a, fs, full, skipped)
    return out, full


def _gear_indicators(full, teeth, skipped) -> dict:
    from gearsim.signals import indicators as ind

    t, z, o = full.tsa, int(teeth[0]), full.options
    out: dict[str, Any] = {}
    for name, call in (
        ("energy_ratio", lambda: ind.energy_ratio(t, teeth=z, shaft_harmonics=o[
            "shaft_harmonics"], sideband_orders=o["sideband_orders"])),
        ("sideband_index", lambda: ind.sideband_index(t, teeth=z)),
        ("sideband_level_factor", lambda: ind.sideband_level_factor(t, teeth=z)),
    ):
        try:
            out[name] = _f(call())
        except InputError as exc:
            skipped.append({"tier": f"gear.indicators.{name}", "reason": _first_line(exc)})
    skipped.append({"tier": "gear.indicators.nb4", "reason": "NB4 needs the envelopes of a "
                    "run history (several records of one gear), not one record"})
    return out


def _demodulation(a, fs, full, skipped) -> dict | None:
    from gearsim.signals.demodulation import demodulate_tsa

    try:
        d = demodulate_tsa(full.tsa, teeth=full.kinematics.teeth[0], harmonic=1,
                           sidebands=max(1, full.options["sideband_orders"]))
    except InputError as exc:
        skipped.append({"tier": "gear.demodulation", "reason": _first_line(exc)})
        return None
    return {"amplitude_kurtosis": _f(_kurtosis(d.amplitude)),
            "phase_kurtosis": _f(_kurtosis(d.phase)), "carrier_frequency": _f(d.carrier_frequency)}


def _provenance(name: str, value: str | None) -> str | None:
    if value is not None and value not in PROVENANCES:
        raise InputError(f"{name}_provenance", value, f"must be one of {list(PROVENANCES)}")
    return value


#: Confidence an estimated tooth count needs before the gear tier uses it (the share of
#: the dominant line's evidence that points to one integer count, signals.estimate).
TEETH_CONFIDENCE = 0.9
#: Share of the line power by which the dominant mesh family found with a searched speed
#: must lead every unrelated family before the gear tier uses its tooth count.
TEETH_SHARE = 0.5


def analyze_record(
    x: np.ndarray,
    fs: float | None = None,
    *,
    speed: float | None = None,
    tacho: np.ndarray | None = None,
    pulses_per_rev: int = 1,
    speed_search: tuple[float, float] | None = None,
    teeth: Sequence[int] | None = None,
    stages: Sequence[tuple[int, int]] | None = None,
    settings: Any = None,
    baseline: np.ndarray | None = None,
    baseline_tacho: np.ndarray | None = None,
    fs_provenance: str | None = None,
    speed_provenance: str | None = None,
    teeth_provenance: str | None = None,
    source: dict | None = None,
    units: str | None = None,
    stage: Any = None,
) -> RecordAnalysis:
    """Every tier of analysis the inputs allow, with what was skipped and why.

    Parameters
    ----------
    x : array_like
        Signal (any units), 1-D, finite.
    fs : float, optional
        Sampling rate [Hz]; without it the spectrum is in cycles per sample and the
        shaft and gear tiers are skipped.
    speed : float, optional
        Speed of the measured shaft [Hz] (not rpm). At most one of ``speed``,
        ``tacho`` and ``speed_search``.
    tacho : array_like, optional
        Tacho of the measured shaft, same sampling and length as ``x``.
    pulses_per_rev : int
        Tacho pulses per revolution (>= 1).
    speed_search : tuple of float, optional
        ``(low, high)`` [Hz]: estimate the shaft speed from the signal in this range
        (:func:`gearsim.signals.speed.estimate_constant_speed`; tracked by
        :func:`~gearsim.signals.speed.estimate_speed` when it varies); provenance
        ``"estimate"``, with the dominant mesh family as an estimated tooth count when
        no ``teeth`` are given.
    teeth : sequence of int, optional
        Tooth counts, gear on the measured shaft first; enables the gear tier.
    stages : sequence of (int, int), optional
        A compound train instead of ``teeth``: ``(driving teeth, driven teeth)`` of each
        stage in power-flow order, stage 1's driving gear on the measured shaft
        (:func:`gearsim.signals.analysis.kinematics`). The gear tier analyses every
        stage's mesh in one :func:`~gearsim.signals.analysis.analyze` call and the TSA of
        each stage's driven gear on its shaft; ``teeth_provenance`` applies to them.
    settings : AnalysisSettings, optional
        Options of the gear tier (:class:`gearsim.signals.settings.AnalysisSettings`);
        ``remove_mean`` also applies to the statistics.
    baseline : array_like, optional
        Healthy record for the gear tier's ratios and NA4.
    baseline_tacho : array_like, optional
        Tacho of ``baseline``.
    fs_provenance, speed_provenance, teeth_provenance : str, optional
        ``"file"``, ``"given"`` or ``"estimate"`` (default ``"given"`` when the value is
        given; a tacho speed is ``"file"``, a searched speed ``"estimate"``).
    source : dict, optional
        Where the record came from (``file``, ``channel``, ...), copied to the output.
    units : str, optional
        Units of the signal.
    stage : StageSpec, optional
        A planetary stage with its carrier speed, ring held
        (:class:`gearsim.signals.planetary_tier.StageSpec`): adds the ``planetary`` tier
        (carrier-order sidebands, envelope fault lines, separated planet and sun
        averages); needs a sampling rate.

    Returns
    -------
    RecordAnalysis
        Tier results, ``skipped`` list, provenance; ``.to_dict()``, ``.text()``,
        ``.features()``.

    Raises
    ------
    InputError
        An unusable signal (fewer than 2 samples, non-finite), an invalid ``fs``,
        ``speed``, ``teeth`` or ``stages`` (or both given), ``pulses_per_rev``,
        ``speed_search`` (also one the record
        cannot resolve: too short, or too close to Nyquist) or provenance, more than one
        speed source, a tacho of another length, or invalid settings.
    """
    from gearsim.signals._checks import check_fs, check_int, check_positive, check_teeth

    t_start = time.perf_counter()
    a = as_signal(x)
    fs = check_fs(fs) if fs is not None else None
    given = [n for n, v in (("speed", speed), ("tacho", tacho), ("speed_search", speed_search))
             if v is not None]
    if len(given) > 1:
        raise InputError("/".join(given), "several", "give at most one speed source")
    if speed is not None:
        speed = check_positive("speed", speed)
    ppr = check_int("pulses_per_rev", pulses_per_rev, minimum=1)
    if speed_search is not None:  # refused before any work when the record cannot resolve it
        from gearsim.signals.speed import check_speed_search

        speed_search = check_speed_search(a.size, fs, speed_search, name="speed_search")
    pairs = None
    if stages is not None:
        from gearsim.signals.analysis import check_stages

        if teeth is not None:
            raise InputError("teeth/stages", "both", "give at most one: teeth for a simple "
                             "train, stages for a compound one")
        pairs = check_stages(stages)
        zs = tuple(z for p in pairs for z in p)  # the reference gear first, as teeth
    else:
        zs = check_teeth(teeth) if teeth is not None else None
    if settings is not None:
        from gearsim.signals.settings import AnalysisSettings

        if not isinstance(settings, AnalysisSettings):
            raise InputError("settings", type(settings).__name__, "must be an AnalysisSettings")
    remove_mean = getattr(settings, "remove_mean", True)
    prov_fs = _provenance("fs", fs_provenance) or ("given" if fs is not None else None)
    prov_teeth = _provenance("teeth", teeth_provenance) or ("given" if zs else None)
    _provenance("speed", speed_provenance)
    estimates: dict[str, Any] = {}
    early_skips: list[dict[str, str]] = []
    if fs is None and speed is not None and a.size >= MIN_SPECTRUM_SAMPLES:
        # the sampling rate from the known shaft speed and the record's dominant
        # periodicity (signals.estimate), labelled as an estimate everywhere
        from gearsim.signals.estimate import estimate_fs

        try:
            est = estimate_fs(a, shaft_frequency=float(speed), teeth=zs[0] if zs else None)
        except InputError as exc:
            early_skips.append({"tier": "estimate.fs", "reason": str(exc)})
        else:
            fs, prov_fs = float(est.fs), "estimate"
            estimates["fs"] = {"value_hz": est.fs, "method": est.method, "snr": est.snr,
                               "p_value": est.p_value, "comb_score": est.score,
                               "runner_up_score": est.runner_up, "estimate": True}

    rec = RecordAnalysis(n_samples=int(a.size), fs=fs, fs_provenance=prov_fs if fs else None,
                         speed=None, speed_provenance=None, teeth=zs,
                         teeth_provenance=prov_teeth, source=dict(source or {}), units=units,
                         stages=pairs)
    skipped = rec.skipped
    skipped.extend(early_skips)
    if estimates:
        rec.tiers["estimates"] = estimates
    t0 = time.perf_counter()
    rec.tiers["statistics"] = {"rests_on": {}, "remove_mean": bool(remove_mean),
                               **statistics(a, remove_mean=remove_mean)}
    rec.timings["statistics"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    amp = None  # the record's amplitude spectrum, shared by the spectrum and shaft tiers
    if a.size < MIN_SPECTRUM_SAMPLES:
        skipped.append({"tier": "spectrum", "reason": f"record of {a.size} samples is shorter "
                        f"than {MIN_SPECTRUM_SAMPLES}"})
    else:
        amp = _hann_amplitude(a)
        sp = _spectrum_tier(a, fs, amp)
        sp["rests_on"] = {"fs": prov_fs or "none (cycles/sample)"}
        if fs is None:
            skipped.append({"tier": "spectrum.Hz", "reason": "no sampling rate: frequencies "
                            "are in cycles/sample (give --fs)"})
        sp["kurtogram"] = _kurtogram(a, fs, skipped)
        rec.tiers["spectrum"] = sp
    rec.timings["spectrum"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    f_r = est_speed = pulses_tacho = steady = None
    if fs is None:
        for tier in ("shaft", "gear"):
            skipped.append({"tier": tier, "reason": "needs a sampling rate (give --fs, or a "
                            "file that stores it)"})
    else:
        order = zs[0] if zs else 1
        slowest = min([1.0, *_other_orders(1.0, zs, pairs, 1.0)])
        f_r, prov_speed, profile, est_speed, tracked = _resolve_speed(
            a, fs, speed, tacho, ppr, speed_search, order, skipped, speed_provenance,
            rec.warnings, slowest, (source or {}).get("config"))
        if est_speed is not None:
            rec.tiers.setdefault("estimates", {})["speed"] = est_speed.to_dict()
        if f_r is not None:
            rec.speed, rec.speed_provenance = f_r, prov_speed
            if tacho is not None:
                pulses_tacho = tacho
            rests = {"fs": prov_fs, "speed": prov_speed}
            if a.size / fs < MIN_REVOLUTIONS / f_r:
                reason = (f"record {a.size / fs:.4g} s is shorter than {MIN_REVOLUTIONS:g} "
                          f"revolutions of the measured shaft ({MIN_REVOLUTIONS / f_r:.4g} s)")
                skipped.append({"tier": "shaft", "reason": reason})
                skipped.append({"tier": "gear", "reason": reason})
                f_r = None
            else:
                fr = None if profile is None else profile.frequency
                if fr is not None and (tracked or np.ptp(fr) >
                                       RUN_UP_TOL * (fr.max() + fr.min()) / 2):
                    # a steady speed tracked, or one that changes (the run-up rule): the
                    # lines of the shaft and gear tiers read in the order domain, at the
                    # mean speed
                    steady = _at_mean_speed(a, fs, profile)
                    if steady is not None:  # the speed every line is read at
                        f_r = rec.speed = steady[1]
                    else:
                        skipped.append({"tier": "shaft.order_domain", "reason": "fewer "
                                        f"than {MIN_REVOLUTIONS:g} whole revolutions outside "
                                        "the tracking filter's edges: lines read at the mean "
                                        "speed"})
                rec.tiers["shaft"] = _shaft_tier(a, fs, f_r, rests, skipped, profile, zs,
                                                   amp, stages=pairs, steady=steady)
        else:
            skipped.append({"tier": "gear", "reason": "needs a shaft speed (see shaft)"})
    rec.timings["shaft"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    if f_r is not None and not zs and est_speed is not None and est_speed.teeth is not None:
        # the dominant mesh family found with the searched speed (labelled an estimate)
        if est_speed.teeth_confidence >= TEETH_SHARE:
            zs, prov_teeth = (est_speed.teeth,), "estimate"
            rec.teeth, rec.teeth_provenance = zs, prov_teeth
        else:
            skipped.append({"tier": "estimate.teeth", "reason": f"mesh family {est_speed.teeth} "
                            f"has confidence {est_speed.teeth_confidence:.2f} < {TEETH_SHARE} "
                            "(give --teeth)"})
    elif f_r is not None and not zs and fs is not None:
        # tooth count of the measured shaft's gear from the dominant tone (signals.estimate);
        # used only when the evidence is clear, and labelled as an estimate
        from gearsim.signals.estimate import estimate_teeth

        try:
            est_z = estimate_teeth(a, fs, shaft_frequency=f_r)
        except InputError as exc:
            skipped.append({"tier": "estimate.teeth", "reason": str(exc)})
        else:
            info = {"value": int(est_z.teeth), "confidence": est_z.confidence,
                    "snr": est_z.snr, "p_value": est_z.p_value, "estimate": True}
            rec.tiers.setdefault("estimates", {})["teeth"] = info
            if est_z.confidence >= TEETH_CONFIDENCE:
                zs, prov_teeth = (int(est_z.teeth),), "estimate"
                rec.teeth, rec.teeth_provenance = zs, prov_teeth
            else:
                skipped.append({"tier": "estimate.teeth", "reason": f"confidence "
                                f"{est_z.confidence:.2f} < {TEETH_CONFIDENCE} (give --teeth)"})
    if f_r is not None:
        a_g, f_g = steady or (a, f_r)
        if steady is not None:
            pulses_tacho = None  # the revolutions are equal in the order domain
        if not zs:
            skipped.append({"tier": "gear", "reason": "needs tooth counts (give --teeth)"})
        else:
            f_m = zs[0] * f_r
            if prov_teeth != "estimate" and f_m >= 0.5 * fs:
                # not a tier to skip: the inputs contradict each other (a wrong tooth
                # count, speed or rate), so the call is refused
                raise InputError("teeth", zs[0], f"mesh frequency {f_m:g} Hz (teeth x shaft "
                                 f"frequency {f_r:g} Hz) is at or above the Nyquist frequency "
                                 f"{0.5 * fs:g} Hz of fs = {fs:g} Hz: check the tooth count, "
                                 "the speed and the sampling rate")
            rests = {"fs": prov_fs, "speed": rec.speed_provenance, "teeth": prov_teeth}
            if ppr != 1 and settings is None:
                from gearsim.signals.settings import AnalysisSettings

                settings = AnalysisSettings(pulses_per_rev=ppr)
            elif ppr != 1:
                import dataclasses

                settings = dataclasses.replace(settings, pulses_per_rev=ppr)
            n_b = None if baseline is None else np.size(baseline)
            if n_b is not None and n_b / fs < MIN_REVOLUTIONS / f_r:  # the record's rule
                skipped.append({"tier": "gear.baseline", "reason": f"baseline {n_b / fs:.4g} "
                                f"s is shorter than {MIN_REVOLUTIONS:g} revolutions of the "
                                f"measured shaft ({MIN_REVOLUTIONS / f_r:.4g} s)"})
                baseline = baseline_tacho = None
            g, full = _gear_tier(a_g, fs, f_g, zs, pulses_tacho, settings, rests, skipped,
                                 baseline, baseline_tacho, stages=pairs, profile=profile)
            if g is not None and a_g is not a:
                full.options["speed_source"] = g["analysis"]["options"]["speed_source"] = (
                    f"{rec.speed_provenance} profile, record resampled at equal angle steps "
                    f"of its mean speed {f_g:.6g} Hz")
                g["order_domain"] = {"mean_speed_hz": f_g, "samples": int(a_g.size)}
            if g is not None:
                rec.tiers["gear"] = g
                rec.analysis = full
                if pairs and not full.kinematics.compound:  # stage 1 only (gear.stages)
                    rec.teeth, rec.stages = tuple(full.kinematics.teeth), None
    rec.timings["gear"] = time.perf_counter() - t0
    if stage is not None:
        t0 = time.perf_counter()
        if fs is None:
            skipped.append({"tier": "planetary", "reason": "needs a sampling rate (give --fs, "
                            "or a file that stores it)"})
        else:
            from gearsim.signals.planetary_tier import planetary_tier

            pt = planetary_tier(a, fs, stage, skipped)
            pt["rests_on"]["fs"] = prov_fs
            rec.tiers["planetary"] = pt
        rec.timings["planetary"] = time.perf_counter() - t0
    rec.timings["total"] = time.perf_counter() - t_start
    return rec
