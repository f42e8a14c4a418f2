r"""Estimates of a record's missing metadata: sampling rate and tooth count.

When a file has lost its sampling rate or the gear's tooth count, the periodicities of the
signal still carry them, given the shaft speed. Both functions return dataclasses with
``estimate=True`` and the evidence (the line used, its significance, how well it matches)
so that a report can never show the result as a measured value.

**The line series rule.** Gear signals are harmonic series (the mesh harmonics
:math:`n Z f_r`; the shaft harmonics :math:`h f_r` of the squared envelope). The strongest
line of a series need not be its fundamental. The strongest line (frequency
:math:`\nu_0`) is taken as harmonic ``d`` of the series, and the largest ``d`` in
``1..harmonics`` whose candidate fundamental :math:`\nu_0 / d` is itself a significant
line (:func:`~gearsim.signals.periodicity.line_significance`, p-value below ``alpha``)
and strong enough (:data:`MIN_FUNDAMENTAL_POWER`) is kept: the lowest member of the
series present in the spectrum. The rule serves :func:`estimate_teeth`; the sampling rate
is chosen by whole combs instead (:func:`estimate_fs`): on a real gearbox record the
lines of the other shafts pass the rule for many ``d`` (the SpectraQuest records gave
2, 4, 8 and 10.7 times their rate from the mesh, 0.34 to 10 times from the envelope).

References
----------
.. [G83] T. Grandke, "Interpolation algorithms for discrete Fourier transforms of weighted
   signals", *IEEE Trans. Instrum. Meas.* 32 (1983) 350-355.
.. [R11] R. B. Randall, *Vibration-based Condition Monitoring*, Wiley, 2011, sec. 2.2
   (gear mesh harmonics) and 5.5 (envelope analysis).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
from scipy.ndimage import median_filter

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal, check_fs, check_int, check_positive, check_probability
from gearsim.signals.envelope import squared_envelope
from gearsim.signals.periodicity import line_significance, periodogram
from gearsim.signals.spectrum import amplitude_spectrum, tone

__all__ = ["FsEstimate", "TeethEstimate", "estimate_fs", "estimate_teeth"]

#: Bins excluded at the bottom of a periodogram (the Hann window's leakage of the mean).
_LOW_BINS = 3


@dataclass(frozen=True)
class FsEstimate:
    """Estimated sampling rate and the evidence for it (built by :func:`estimate_fs`).

    Parameters
    ----------
    fs : float
        Estimated sampling rate (Hz).
    method : str
        ``"mesh"`` (mesh line of the spectrum, ``teeth`` given), ``"envelope"`` (shaft
        line of the squared envelope) or ``"envelope+order"`` (shaft line, then refined by
        the record's strongest line at integer shaft order ``order``).
    cycles_per_sample : float
        Frequency of the line that gave ``fs``, in cycles per sample.
    order : int
        Shaft order of that line: ``teeth`` (mesh), 1 (envelope) or the integer order of
        the record's strongest line (envelope+order).
    divisor : int
        ``d``: the line that refined the rate was harmonic ``d`` of the fundamental (mesh:
        the strongest mesh harmonic of the comb kept; envelope: the strongest shaft
        harmonic of the squared envelope on the comb kept).
    snr : float
        Line-to-floor power ratio of the fundamental (mesh) or of that harmonic
        (envelope), linear.
    p_value : float
        False-alarm probability of that line.
    relative_resolution : float
        Half a bin relative to the measured line, ``1 / (2 N nu_0)``: a bound on the
        relative error without interpolation (the interpolated error is usually well
        below it).
    shaft_frequency : float
        The known shaft frequency used (Hz).
    estimate : bool
        Always True: the value is inferred, not measured.
    score : float or None
        Comb score of the rate kept (mean line evidence, log10 of line to floor in
        [0, 3], on the comb minus off it).
    runner_up : float or None
        The best score of any other candidate rate (None if there was none).
    """

    fs: float
    method: str
    cycles_per_sample: float
    order: int
    divisor: int
    snr: float
    p_value: float
    relative_resolution: float
    shaft_frequency: float
    estimate: bool = field(default=True)
    score: float | None = None
    runner_up: float | None = None

    def to_dict(self) -> dict:
        """JSON-serialisable dict.

        Returns
        -------
        dict
            Field name to value, for every field.
        """
        return dict(self.__dict__)


@dataclass(frozen=True)
class TeethEstimate:
    """Estimated tooth count and the evidence for it (built by :func:`estimate_teeth`).

    Parameters
    ----------
    teeth : int
        Estimated tooth count ``Z``.
    dominant_frequency : float
        Interpolated frequency of the strongest line (Hz).
    order : float
        ``dominant_frequency / shaft_frequency`` (shaft orders).
    harmonic : int
        Mesh harmonic ``d`` the dominant line was taken for (``order ~ d Z``).
    integrality : float
        ``1 - 2 |order/d - Z|`` in [0, 1]: 1 when the order is exactly a multiple of
        ``Z``, 0 half-way between two counts.
    snr : float
        Line-to-floor power ratio of the line at ``Z f_r`` (linear).
    p_value : float
        False-alarm probability of that line.
    confidence : float
        ``integrality * (1 - p_value)`` in [0, 1]; a figure of merit, not a probability.
    alternatives : tuple of dict
        Every harmonic hypothesis ``d = 1..harmonics`` tried: ``teeth``, ``harmonic``,
        ``integrality``, ``snr``, ``p_value`` (hypotheses outside ``candidates`` omitted).
    shaft_frequency : float
        The known shaft frequency used (Hz).
    estimate : bool
        Always True: the value is inferred, not counted.
    """

    teeth: int
    dominant_frequency: float
    order: float
    harmonic: int
    integrality: float
    snr: float
    p_value: float
    confidence: float
    alternatives: tuple
    shaft_frequency: float
    estimate: bool = field(default=True)

    def to_dict(self) -> dict:
        """JSON-serialisable dict.

        Returns
        -------
        dict
            Field name to value, ``alternatives`` as a list of dicts.
        """
        d = dict(self.__dict__)
        d["alternatives"] = [dict(a) for a in self.alternatives]
        return d


#: Smallest power of a candidate fundamental relative to the dominant line (amplitude
#: 10 %). A mesh fundamental 20 dB or more below its own harmonic is not what gears
#: produce, while impacts and modulation put significant lines at every shaft order
#: (e.g. order 13 of a 39-tooth gear with once-per-revolution impacts, 39 dB below the
#: mesh tone): without this bound such a line would be taken for the fundamental.
MIN_FUNDAMENTAL_POWER = 0.01


def _strong_enough(power: np.ndarray, k: float, k0: float) -> bool:
    """Whether the line near bin ``k`` has at least MIN_FUNDAMENTAL_POWER of bin ``k0``'s."""
    i = int(round(k))
    lo, hi = max(0, i - 1), min(power.size, i + 2)
    j0 = int(round(k0))
    top = float(power[max(0, j0 - 1):min(power.size, j0 + 2)].max())
    return lo < hi and float(power[lo:hi].max()) >= MIN_FUNDAMENTAL_POWER * top


#: Sideband orders ``|m| <= COMB_SIDEBANDS`` around each mesh harmonic in the comb test.
COMB_SIDEBANDS = 3
#: Strongest lines of the record each taken, in turn, for every comb line ``n Z + m``.
COMB_SOURCE_LINES = 5
#: Line evidence counts from this multiple of the local floor (mean noise power): a noise
#: bin exceeds it with probability exp(-5) = 0.7 %, so empty comb positions add ~0.
COMB_FLOOR = 5.0
#: A line: at least this multiple of the local floor (10 dB).
COMB_LINE = 10.0
#: Fewest periodogram bins per shaft order for a candidate rate (finer combs cannot put
#: their off-comb positions clear of their lines).
COMB_MIN_BINS = 8
#: Shifts (fractions of a shaft order) of the off-comb positions: half a shaft order
#: refutes a rate 2, 4, ... times too high or too low, a third 3 or 6 times.
COMB_SHIFTS = (1 / 2, 1 / 3, 2 / 3)
#: Candidate rates closer than this (relative) are one hypothesis (the record's speed
#: wander and the line used move a rate by up to about 1e-3; the nearest distinct
#: hypotheses, mesh harmonic h with or without a sideband, differ by 1/(h Z)).
COMB_SAME = 1e-3
#: A rate is kept only if no other candidate scores more than this fraction of its score.
COMB_DECISIVE = 2 / 3
#: The envelope rate is refined by the record's strongest line only when it lies within
#: this many shaft orders of an integer order (its uncertainty included): the lines of a
#: gearbox's other shafts lie at fractions of an order (SpectraQuest: multiples of 0.1).
ORDER_TOLERANCE = 0.05
#: The envelope comb kept must keep more than ``1 / COMB_COMPLETE`` times the mean line
#: evidence of any copy of it displaced by a fraction of an order.
COMB_COMPLETE = 1 / 3
#: Fewest lines (:data:`COMB_LINE`) on an envelope comb: one line does not set its order.
COMB_MIN_LINES = 3


def _fs_bounds(fs_range):
    """``(low, high)`` of ``fs_range`` checked, or None."""
    if fs_range is None:
        return None
    try:
        lo_fs, hi_fs = (check_positive("fs_range", v) for v in fs_range)
    except TypeError:
        raise InputError("fs_range", fs_range, "must be a pair (low, high) in Hz") from None
    if lo_fs >= hi_fs:
        raise InputError("fs_range", fs_range, "must satisfy low < high")
    return lo_fs, hi_fs


def _at(evidence: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """Evidence at fractional bins ``pos``: the largest of the bins within one bin of each
    (a line smeared by the speed's wander peaks a bin away from its nominal position)."""
    k = np.round(pos).astype(int)
    return np.maximum(np.maximum(evidence[k - 1], evidence[k]), evidence[k + 1])


def _comb_score(evidence: np.ndarray, orders: np.ndarray, step: float) -> float:
    """Mean line evidence at shaft ``orders`` (``step`` bins per order) minus the largest
    mean on the same comb shifted by a fraction of an order (:data:`COMB_SHIFTS`); -inf if
    no position is inside the spectrum. Each position reads the two bins around it."""
    pos = orders * step
    pos = pos[(pos > _LOW_BINS) & (pos + step < evidence.size - 2)]
    if not pos.size:
        return -np.inf
    return float(_at(evidence, pos).mean()
                 - max(_at(evidence, pos + f * step).mean() for f in COMB_SHIFTS))


def _mesh_orders(evidence: np.ndarray, step: float, teeth: int) -> np.ndarray | None:
    """The mesh comb's shaft orders ``n Z + m`` (``|m| <=`` :data:`COMB_SIDEBANDS`, ``n`` up
    to the highest mesh harmonic that is a line); None if the mesh fundamental is none."""
    mesh = np.arange(1, int((evidence.size - 1) / (step * teeth)) + 1) * teeth * step
    mesh = mesh[mesh < evidence.size - 2]
    line = np.log10(COMB_LINE / COMB_FLOOR)
    if not mesh.size or _at(evidence, mesh[:1])[0] < line:
        return None
    return (np.arange(1, np.flatnonzero(_at(evidence, mesh) >= line)[-1] + 2)[:, None] * teeth
            + np.arange(-COMB_SIDEBANDS, COMB_SIDEBANDS + 1)[None, :]).ravel()


def _shaft_orders(evidence: np.ndarray, step: float, _teeth: object = None) -> np.ndarray | None:
    """Every shaft order ``1, 2, ...`` of the spectrum; None if fewer than
    :data:`COMB_MIN_LINES` of them are lines (:data:`COMB_LINE`)."""
    orders = np.arange(1, int((evidence.size - 3) / step) + 1)
    pos = orders * step
    on = _at(evidence, pos[(pos > _LOW_BINS) & (pos + 1 < evidence.size)])
    lines = np.count_nonzero(on >= np.log10(COMB_LINE / COMB_FLOOR))
    return orders if lines >= COMB_MIN_LINES else None


def _incomplete(evidence: np.ndarray, step: float) -> str | None:
    """Why the shaft comb of ``step`` bins per order cannot be the rate, or None: displaced
    by any whole number of bins (3 or more from its teeth, so that no position reads a
    tooth's bins) it keeps
    more than :data:`COMB_COMPLETE` of its mean line evidence (lines off the comb: a finer
    comb, a higher rate, holds them)."""
    pos = np.arange(1, int((evidence.size - 3) / step) + 1) * step
    pos = pos[(pos > _LOW_BINS) & (pos + step < evidence.size - 2)]
    on = _at(evidence, pos)
    shifts = np.arange(3, step - 3 + 1e-9)  # windows of three bins clear of the teeth's
    off = _at(evidence, pos[None, :] + shifts[:, None]).mean(axis=1)
    j = int(np.argmax(off))
    if off[j] <= COMB_COMPLETE * on.mean():
        return None
    return (f"leaves lines off its comb: displaced by {shifts[j] / step:.3f} of an order it "
            f"keeps {off[j] / on.mean():.0%} of its line evidence")


def _comb_fit(sig, f_r, line_orders, comb_orders, teeth, bounds, where, refute=None):
    """The decision shared by the comb methods of :func:`estimate_fs`.

    Each of the :data:`COMB_SOURCE_LINES` strongest lines of ``sig``'s periodogram,
    taken for every shaft order ``q`` in ``line_orders(nu)``, gives a candidate shaft
    frequency ``nu / q`` (cycles per sample); each is scored by :func:`_comb_score` on
    ``comb_orders(evidence, step, teeth)`` (dropped when that is None). ``refute(evidence,
    step)``, if given, returns why a candidate cannot be the rate (None if it can); the
    best candidate it admits is kept, unless a refuted one scored better. Returns the
    periodogram, the line evidence, the Hann amplitude spectrum, the shaft frequency kept
    (cycles/sample), its score and the runner-up's; raises ``sampling rate = not
    estimated`` or ``ambiguous`` (the candidates named, ``where`` saying what was fitted).
    """
    n = sig.size
    power = periodogram(sig)
    floor = median_filter(power, size=101, mode="nearest") / np.log(2)
    # line evidence: log10 of a local maximum over COMB_FLOOR times the local floor, in
    # [0, 3]; 0 off the maxima (a strong line's neighbours are its leakage, not lines)
    evidence = np.clip(np.log10(power / np.maximum(COMB_FLOOR * floor, 1e-300)), 0, 3)
    evidence[1:-1] *= (power[1:-1] >= power[:-2]) & (power[1:-1] >= power[2:])
    k = np.arange(_LOW_BINS + 2, power.size - 3)
    peak = ((power[k] >= power[k - 1]) & (power[k] > power[k + 1])
            & (power[k] >= power[k - 2]) & (power[k] > power[k + 2]))
    peaks = k[peak][np.argsort(power[k[peak]])[::-1][:COMB_SOURCE_LINES]]
    spec = amplitude_spectrum(sig, 1.0, window="hann")
    cands: list[tuple[float, float]] = []  # (score, shaft frequency in cycles/sample)
    for p in peaks:
        nu_p = tone(spec, p / n, search=1.0 / n).frequency
        for q in line_orders(nu_p * n):
            spacing = nu_p / q
            if spacing * n < COMB_MIN_BINS or (
                    bounds is not None and not bounds[0] <= f_r / spacing <= bounds[1]):
                continue
            orders = comb_orders(evidence, spacing * n, teeth)
            if orders is not None:
                cands.append((_comb_score(evidence, orders, spacing * n), spacing))
    kept: list[tuple[float, float]] = []  # the best of each hypothesis, best first
    for c in sorted((c for c in cands if np.isfinite(c[0])), reverse=True):
        if all(abs(c[1] / k[1] - 1) > COMB_SAME for k in kept):
            kept.append(c)
    why: dict[int, str | None] = {}  # refute's verdict on the candidates that matter
    win = None
    for i, c in enumerate(kept):
        if win is not None and c[0] <= COMB_DECISIVE * kept[win][0]:
            break
        why[i] = refute(evidence, c[1] * n) if refute is not None else None
        if why[i] is None and win is None:
            win = i
    if win is None or kept[win][0] <= 0:
        first = f": the best, {f_r / kept[0][1] / 1e3:.4g} kHz, {why[0]}" if why.get(0) else ""
        raise InputError("sampling rate", "not estimated",
                         f"no candidate rate puts the record's lines on {where}{first}: give "
                         "the rate (--fs)")
    best, spacing = kept[win]
    rivals = [kept[i] for i in why if i > win and why[i] is None]
    if win or rivals:
        shown = ", ".join(f"{f_r / c[1] / 1e3:.4g} kHz (score {c[0]:.2f})"
                          for c in [kept[win], *rivals[:3]])
        better = (f"; {f_r / kept[0][1] / 1e3:.4g} kHz scores better ({kept[0][0]:.2f}) but "
                  f"{why[0]}" if win else "")
        raise InputError("sampling rate", "ambiguous",
                         f"the record's lines fit {where} about as well at several rates: "
                         f"{shown}{better}; give the rate (--fs)")
    return power, evidence, spec, spacing, best, float(kept[1][0]) if len(kept) > 1 else None


def _mesh_comb_fs(a, f_r, teeth, harmonics, bounds, alpha):
    """The mesh method of :func:`estimate_fs`: candidates, comb scores, decision."""
    n = a.size
    where = f"the comb of {teeth} teeth at {f_r:g} Hz (mesh harmonics and their shaft sidebands)"
    power, _, spec, spacing, best, runner_up = _comb_fit(
        a, f_r, lambda _k: [h * teeth + m for h in range(1, harmonics + 1)
                            for m in range(-COMB_SIDEBANDS, COMB_SIDEBANDS + 1)],
        _mesh_orders, teeth, bounds, where)
    # refine by the strongest mesh harmonic on the chosen comb (interpolated)
    hs = np.arange(1, int(0.5 / (spacing * teeth)) + 1)
    hs = hs[hs * teeth * spacing * n < power.size - 2]
    d = int(hs[np.argmax([power[int(round(h * teeth * spacing * n))] for h in hs])])
    nu_d = tone(spec, d * teeth * spacing, search=1.0 / n).frequency
    test = line_significance(power, nu_d / d * n, search_bins=1)
    if test.p_value >= alpha:
        raise InputError("sampling rate", "not estimated",
                         f"the mesh fundamental of the best fit of {where}, at "
                         f"{f_r / spacing / 1e3:.4g} kHz, is not significant (p = "
                         f"{test.p_value:.2g}): give the rate (--fs)")
    return FsEstimate(
        fs=float(d * teeth * f_r / nu_d), method="mesh", cycles_per_sample=float(nu_d / d),
        order=teeth, divisor=d, snr=test.snr, p_value=test.p_value,
        relative_resolution=float(0.5 / (n * nu_d)), shaft_frequency=f_r,
        score=best, runner_up=runner_up,
    )


def _envelope_comb_fs(a, f_r, bounds, alpha):
    """The envelope methods of :func:`estimate_fs`: candidates, comb scores, decision,
    refinement by the strongest comb line and then by the record's strongest line."""
    n = a.size
    where = (f"the shaft orders of {f_r:g} Hz in the squared envelope (no tooth count: "
             "--teeth scores the mesh comb instead)")
    sig = squared_envelope(a - a.mean(), 1.0)
    power, _, spec, spacing, best, runner_up = _comb_fit(
        sig, f_r, lambda k: range(1, int(k / COMB_MIN_BINS) + 1), _shaft_orders, None,
        bounds, where, _incomplete)
    # refine by the strongest line on the chosen comb (interpolated)
    hs = np.arange(1, int((power.size - 3) / (spacing * n)) + 1)
    d = int(hs[np.argmax(_at(power, hs * spacing * n))])
    nu_d = tone(spec, d * spacing, search=1.0 / n).frequency
    test = line_significance(power, nu_d * n, search_bins=1)
    if test.p_value >= alpha:
        raise InputError("sampling rate", "not estimated",
                         f"the strongest line of the best fit of {where}, at "
                         f"{f_r / spacing / 1e3:.4g} kHz, is not significant (p = "
                         f"{test.p_value:.2g}): give the rate (--fs)")
    method, order, nu, resolution = "envelope", 1, nu_d / d, 0.5 / (n * nu_d)
    # then by the strongest line of the record when it lies at an integer order q (a
    # line of another shaft lies at a fraction of an order: ORDER_TOLERANCE)
    raw_peak = int(np.argmax(periodogram(a)[_LOW_BINS:])) + _LOW_BINS
    nu_raw = tone(amplitude_spectrum(a, 1.0, window="hann"), raw_peak / n,
                  search=1.0 / n).frequency
    q = nu_raw / nu
    q_int = int(round(q))
    if q_int >= 2 and abs(q - q_int) + q * resolution < ORDER_TOLERANCE:
        method, order, nu, resolution = "envelope+order", q_int, nu_raw, 0.5 / (n * nu_raw)
    return FsEstimate(
        fs=float(order * f_r / nu), method=method, cycles_per_sample=float(nu), order=order,
        divisor=d, snr=test.snr, p_value=test.p_value, relative_resolution=float(resolution),
        shaft_frequency=f_r, score=best, runner_up=runner_up,
    )


def estimate_fs(
    x: np.ndarray,
    *,
    shaft_frequency: float,
    teeth: int | None = None,
    harmonics: int = 10,
    fs_range: tuple[float, float] | None = None,
    alpha: float = 1e-3,
) -> FsEstimate:
    r"""Estimate the sampling rate from a known shaft speed and the record's periodicity.

    With ``teeth`` ("mesh"): a line at :math:`\nu` cycles per sample taken for comb line
    :math:`q = nZ + m` (mesh harmonic ``n``, shaft sideband ``m``) gives the rate
    :math:`f_s = q f_r / \nu`. Every such rate is a candidate, for each of the
    :data:`COMB_SOURCE_LINES` strongest lines, ``n = 1..harmonics`` and
    :math:`|m| \le` :data:`COMB_SIDEBANDS`; a candidate whose mesh fundamental is no line
    (:data:`COMB_LINE` times the local floor) is dropped. Each is scored by its whole
    comb, the mesh harmonics up to the highest that is a line and their shaft sidebands:
    the mean line evidence (:math:`\log_{10}` of a local maximum of the periodogram
    within a bin of the position over :data:`COMB_FLOOR` times the local median floor,
    clipped to [0, 3]) on the comb minus the largest mean on the comb shifted by a half
    or a third of a shaft order (a rate k times too high puts half its comb between the
    record's lines, one k times too low leaves lines on the shifted comb). The best
    candidate is kept only when no other scores more than :data:`COMB_DECISIVE` of it;
    otherwise the rate is refused, naming the candidates. The rate kept is refined by
    its strongest mesh harmonic ``d`` (interpolated): :math:`\hat f_s = d Z f_r /
    \nu_d`.

    Without ("envelope"): the same candidates and scores on the squared envelope's
    periodogram, for the comb of every shaft order: a line at :math:`\nu` taken for
    shaft harmonic ``q`` (any ``q`` leaving :data:`COMB_MIN_BINS` bins per order) gives
    :math:`f_s = q f_r / \nu`; a comb holding fewer than :data:`COMB_MIN_LINES` lines is
    dropped. A rate k times too high puts the record's lines on every k-th order of its
    comb (a lower mean); one k times too low leaves lines between its teeth, which the
    shifts of a half or a third of an order see only for k = 2 or 3, so a candidate is
    also refuted when its comb displaced by any whole number of bins (3 or more from its
    teeth) keeps more than :data:`COMB_COMPLETE` of its mean evidence. The best
    candidate not refuted is kept if no refuted candidate scores better (a denser comb
    that leaves lines out against a finer one that holds them: two readings) and no
    other scores more than :data:`COMB_DECISIVE` of it; it is refined by its strongest
    harmonic ``d`` in the envelope (:math:`\hat f_s = d f_r / \nu_d`) and then, when the
    record's strongest line lies within :data:`ORDER_TOLERANCE` of an integer order
    ``q``, by that line (:math:`\hat f_s = q f_r / \nu_0`, "envelope+order"). On a
    gearbox whose pairs repeat after several revolutions (SpectraQuest 32/80: every 5)
    the lines of the other shafts make a comb 5 times finer fit as well, and the rate is
    refused: give ``teeth`` or ``fs_range``.

    Parameters
    ----------
    x : array_like
        Record (any units), at least 64 samples; it must hold many revolutions (the
        relative resolution is ``1 / (2 N nu)``).
    shaft_frequency : float
        Known shaft frequency ``f_r`` (Hz) of the gear of ``teeth`` teeth.
    teeth : int, optional
        Tooth count ``Z`` of that gear; enables the (more precise) mesh method.
    harmonics : int, default 10
        Mesh method: largest mesh harmonic a line may be taken for, >= 1 (the envelope
        method takes a line for any shaft harmonic).
    fs_range : tuple of float, optional
        ``(low, high)`` bounds (Hz) on the sampling rate, if known: only candidates
        inside are scored.
    alpha : float, default 1e-3
        Significance level for the line that refines the rate kept (mesh: the mesh
        fundamental; envelope: the strongest envelope harmonic on the comb).

    Returns
    -------
    FsEstimate
        ``fs`` (Hz) with ``estimate=True``, the line used and its significance.

    Raises
    ------
    InputError
        If an argument is out of range, the record is too short for a noise floor beside
        the line, no candidate rate fits the comb (``sampling rate = not estimated``) or
        several fit it about equally (``sampling rate = ambiguous``, the candidates
        named).

    References
    ----------
    Grandke (1983) for the line frequency; Randall (2011), sec. 2.2 and 5.5.
    """
    a = as_signal(x, min_length=64)
    f_r = check_positive("shaft_frequency", shaft_frequency)
    harmonics = check_int("harmonics", harmonics, minimum=1)
    alpha = check_probability("alpha", alpha)
    if teeth is not None:
        return _mesh_comb_fs(a, f_r, check_int("teeth", teeth, minimum=1), harmonics,
                             _fs_bounds(fs_range), alpha)
    return _envelope_comb_fs(a, f_r, _fs_bounds(fs_range), alpha)


def estimate_teeth(
    x: np.ndarray,
    fs: float,
    *,
    shaft_frequency: float,
    candidates: Iterable[int] = range(10, 200),
    harmonics: int = 3,
    alpha: float = 1e-3,
) -> TeethEstimate:
    r"""Estimate a gear's tooth count from the dominant tone and the known shaft speed.

    The strongest line at or above ``(min(candidates) - 1/2) f_r`` is taken for mesh
    harmonic ``d`` of :math:`Z f_r`; ``q = f_0 / f_r`` (interpolated) and :math:`Z =
    \mathrm{round}(q/d)`. Among the hypotheses ``d = 1..harmonics`` whose ``Z`` is a
    candidate, lies within a quarter order of ``q/d`` and has a significant line at
    :math:`Z f_r` (p < ``alpha``), the smallest ``Z`` (largest ``d``) is kept (the series
    rule of the module docstring); if none, ``d = 1``.

    Parameters
    ----------
    x : array_like
        Record (any units), at least 4 revolutions long.
    fs : float
        Sampling rate (Hz).
    shaft_frequency : float
        Shaft frequency ``f_r`` (Hz) of the gear whose teeth are counted.
    candidates : iterable of int, default range(10, 200)
        Admissible tooth counts.
    harmonics : int, default 3
        Largest mesh harmonic the dominant line may be, >= 1.
    alpha : float, default 1e-3
        Significance level for the line at ``Z f_r``.

    Returns
    -------
    TeethEstimate
        ``teeth`` with ``estimate=True``, the dominant line, ``confidence`` =
        integrality x (1 - p) and the alternatives tried.

    Raises
    ------
    InputError
        If an argument is out of range, the record holds fewer than 4 revolutions,
        ``min(candidates) f_r`` is not below Nyquist, or no hypothesis gives a candidate.

    References
    ----------
    Grandke (1983); Randall (2011), sec. 2.2.
    """
    a = as_signal(x, min_length=64)
    fs = check_fs(fs)
    f_r = check_positive("shaft_frequency", shaft_frequency)
    harmonics = check_int("harmonics", harmonics, minimum=1)
    alpha = check_probability("alpha", alpha)
    cands = sorted({check_int("candidates[]", c, minimum=1) for c in candidates})
    if not cands:
        raise InputError("candidates", "[]", "must hold at least one tooth count")
    n = a.size
    revs = n * f_r / fs
    if revs < 4:
        raise InputError("record length", f"{revs:.3g} revolutions",
                         "must hold >= 4 revolutions to resolve shaft orders to 1/4")
    df = fs / n
    power = periodogram(a)
    k_lo = max(_LOW_BINS, int(np.floor((cands[0] - 0.5) * f_r / df)))
    k_hi = power.size - 1 - _LOW_BINS
    if k_lo >= k_hi:
        raise InputError("candidates", cands[0],
                         f"the lowest mesh frequency {cands[0] * f_r:g} Hz must lie below "
                         f"Nyquist {0.5 * fs:g} Hz")
    k0 = k_lo + int(np.argmax(power[k_lo : k_hi + 1]))
    f0 = tone(amplitude_spectrum(a, fs, window="hann"), k0 * df, search=df).frequency
    q = f0 / f_r
    tried = []
    for d in range(1, harmonics + 1):
        z = int(round(q / d))
        if z not in cands:
            continue
        integ = max(0.0, 1.0 - 2.0 * abs(q / d - z))
        try:
            test = line_significance(power, z * f_r / df, search_bins=1)
        except InputError:
            continue
        tried.append({"teeth": z, "harmonic": d, "integrality": float(integ),
                      "snr": test.snr, "p_value": test.p_value,
                      "strong": d == 1 or _strong_enough(power, z * f_r / df, k0)})
    if not tried:
        raise InputError("candidates", f"{cands[0]}..{cands[-1]}",
                         f"no candidate explains the dominant line at {f0:g} Hz "
                         f"(order {q:.3f}) as a mesh harmonic 1..{harmonics}")
    good = [t for t in tried if t["p_value"] < alpha and t["integrality"] >= 0.5
            and t["strong"]]
    pick = max(good, key=lambda t: t["harmonic"]) if good else tried[0]
    return TeethEstimate(
        teeth=pick["teeth"], dominant_frequency=float(f0), order=float(q),
        harmonic=pick["harmonic"], integrality=pick["integrality"], snr=pick["snr"],
        p_value=pick["p_value"], confidence=float(pick["integrality"] * (1 - pick["p_value"])),
        alternatives=tuple(tried), shaft_frequency=f_r,
    )
