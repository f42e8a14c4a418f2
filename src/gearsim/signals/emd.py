"""Empirical mode decomposition (PyEMD) and selection of intrinsic mode functions.

The seed (sec. 4) decomposes its measured accelerations by EMD and keeps "appropriate
signal components" before its time- and frequency-domain comparison. Two selection rules
are offered:

* correlation: keep IMFs whose correlation coefficient with the raw signal reaches a
  threshold; the default rule is that of Ayenu-Prah & Attoh-Okine (2010),
  ``th = max(rho) / (10 max(rho) - 3)``;
* kurtosis: keep IMFs whose kurtosis exceeds a threshold (3 = Gaussian), i.e. the
  impulsive components that carry tooth impacts (cf. the kurtosis-based selection used
  in gear and bearing diagnostics, Randall 2011 sec. 3.7).

The decomposition is PyEMD's EMD algorithm (Huang et al. 1998; Laszuk, PyEMD), run by
``pyemd_rs`` (package ``pyemd-rs``, a Rust port of ``PyEMD.EMD``) when installed and the
envelopes are cubic splines, else by ``PyEMD.EMD``; both give the same IMFs to round-off
(see :func:`emd`). A record can be cut before decomposing (``start``/``stop`` in seconds,
samples or shaft revolutions, :func:`segment_slice`) and the number of IMFs capped
(``max_imf``). Measured by ``benchmarks/bench_emd.py`` (1 s of a 50 kHz synthetic gear
signal with noise, 2 shared cores): ``pyemd_rs`` takes 1.2 s of CPU against 1.7 s for
``PyEMD.EMD`` (1.4x; 1.0-2.4x in wall time on the loaded machine) with the same IMFs.
The settings and packages that are faster still (PyEMD ``FIXE=10`` 8x, the ``emd``
package's ``sift`` 8x) change the IMFs beyond the agreement tolerance (normalised RMS
difference of IMF 2 of 3.7 and 4.7, and a different correlation selection), as do
PyEMD's ``MAX_ITERATION=50``, ``FIXE_H``, parabolic extrema and pchip splines (the last
three also slower); PyEMD's numba ``JitEMD`` agrees but is 2.5x slower after a 40-90 s
compilation. Sifting the first IMFs takes most of the time, so ``max_imf`` saves
little; the decomposed length (``start``/``stop``) is what bounds the cost.

References
----------
.. [Hu98] N. E. Huang et al., "The empirical mode decomposition and the Hilbert spectrum
   for nonlinear and non-stationary time series analysis", *Proc. R. Soc. Lond. A* 454
   (1998) 903-995.
.. [AA10] A. Ayenu-Prah, N. Attoh-Okine, "A criterion for selecting relevant intrinsic
   mode functions in empirical mode decomposition", *Adv. Adapt. Data Anal.* 2 (2010) 1-24.
.. [L17] D. Laszuk, PyEMD: Python implementation of Empirical Mode Decomposition,
   https://github.com/laszukdawid/PyEMD (package ``EMD-signal``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from gearsim.errors import InputError
from gearsim.signals._checks import as_signal
from gearsim.signals.timedomain import kurtosis

__all__ = ["EMD_ENGINES", "SEGMENT_UNITS", "Decomposition", "Selection", "emd", "imf_correlations",
           "imf_kurtoses", "segment_slice", "select_imfs"]


@dataclass(frozen=True)
class Decomposition:
    """IMFs (rows, highest frequency first) and residue of a signal (signal units).

    Built by :func:`emd`; the IMFs and the residue add up to the signal.

    Parameters
    ----------
    imfs : ndarray, shape (n_imfs, n_samples)
        Intrinsic mode functions, one per row, highest frequency first (signal units).
    residue : ndarray, shape (n_samples,)
        What remains after the last IMF, the slow trend (signal units).
    start : int, default 0
        Index, in the record given to :func:`emd`, of the first decomposed sample (the
        IMFs cover samples ``start .. start + n_samples - 1``).
    engine : str, default "pyemd"
        Engine that computed the IMFs, ``"pyemd"`` or ``"pyemd-rs"``.
    """

    imfs: np.ndarray
    residue: np.ndarray
    start: int = 0
    engine: str = "pyemd"

    @property
    def n_imfs(self) -> int:
        """Number of IMFs."""
        return int(self.imfs.shape[0])


@dataclass(frozen=True)
class Selection:
    """Chosen IMFs and their sum (built by :func:`select_imfs`).

    Parameters
    ----------
    indices : tuple of int
        Selected IMF rows.
    scores : ndarray, shape (n_imfs,)
        Score of every IMF (dimensionless): absolute correlation coefficient with the
        signal, or kurtosis.
    threshold : float
        Threshold applied to ``scores`` (the value used, also when it was computed by
        the Ayenu-Prah rule).
    method : str
        ``"correlation"`` or ``"kurtosis"``.
    signal : ndarray
        Sum of the selected IMFs (signal units; zeros if none passed).
    """

    indices: tuple[int, ...]
    scores: np.ndarray
    threshold: float
    method: str
    signal: np.ndarray


#: Units accepted for ``start``/``stop`` of :func:`segment_slice` and :func:`emd`.
SEGMENT_UNITS = ("s", "samples", "rev")

#: Decomposition engines of :func:`emd`.
EMD_ENGINES = ("auto", "pyemd", "pyemd-rs")

_SPLINES = ("cubic", "akima", "pchip", "cubic_hermite", "slinear", "quadratic", "linear")

#: PyEMD's default stopping thresholds (``PyEMD.EMD.__init__``), passed to ``pyemd_rs``
#: so that both engines stop sifting and decomposing at the same points (``pyemd_rs``
#: 0.1.4 defaults ``total_power_thresh`` to 0.05, PyEMD to 0.005).
_PYEMD_STOP = {"max_iteration": 1000, "svar_thresh": 0.001, "energy_ratio_thresh": 0.2,
               "std_thresh": 0.2, "range_thresh": 0.001, "total_power_thresh": 0.005}


def _bound(name: str, value: float | None, unit: str, fs: float | None,
           shaft_frequency: float | None) -> int | None:
    """Sample index of a segment bound given in ``unit`` (None stays None)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(name, value, "must be a number or None")
    v = float(value)
    if not np.isfinite(v) or v < 0:
        raise InputError(name, value, "must be a finite number >= 0")
    if unit == "samples":
        if v != int(v):
            raise InputError(name, value, "must be a whole number of samples")
        return int(v)
    if fs is None:
        raise InputError("fs", fs, f"is needed for {name} in unit {unit!r}")
    fs = float(fs)
    if not np.isfinite(fs) or fs <= 0:
        raise InputError("fs", fs, "must be a finite number > 0 [Hz]")
    if unit == "s":
        return int(round(v * fs))
    if shaft_frequency is None:
        raise InputError("shaft_frequency", shaft_frequency, f"is needed for {name} in revolutions")
    f_r = float(shaft_frequency)
    if not np.isfinite(f_r) or f_r <= 0:
        raise InputError("shaft_frequency", shaft_frequency, "must be a finite number > 0 [Hz]")
    return int(round(v / f_r * fs))


def segment_slice(
    n_samples: int,
    *,
    start: float | None = None,
    stop: float | None = None,
    unit: Literal["s", "samples", "rev"] = "s",
    fs: float | None = None,
    shaft_frequency: float | None = None,
) -> slice:
    """Samples ``[start, stop)`` of a record of ``n_samples``, bounds in s, samples or revolutions.

    Bounds in seconds or revolutions are rounded to the nearest sample: sample ``i`` is
    at time ``i / fs``, and revolution ``r`` of the reference shaft starts at
    ``r / shaft_frequency`` (revolution 0 at the first sample).

    Parameters
    ----------
    n_samples : int
        Length of the record (samples).
    start : float, optional
        First sample of the segment, in ``unit``; default the start of the record.
    stop : float, optional
        End of the segment (excluded), in ``unit``; default the end of the record.
    unit : {"s", "samples", "rev"}
        Unit of ``start`` and ``stop``: seconds from the first sample (needs ``fs``),
        sample indices, or revolutions of the reference shaft (needs ``fs`` and
        ``shaft_frequency``).
    fs : float, optional
        Sampling rate [Hz], for ``unit`` "s" and "rev".
    shaft_frequency : float, optional
        Reference shaft frequency [Hz], for ``unit`` "rev".

    Returns
    -------
    slice
        ``slice(i0, i1)`` with ``0 <= i0 < i1 <= n_samples`` and ``i1 - i0 >= 2``.

    Raises
    ------
    InputError
        If ``unit`` is unknown, a bound is negative, not finite or (samples) not whole,
        ``fs``/``shaft_frequency`` is missing or not positive when needed, ``stop`` lies
        beyond the record, or the segment holds fewer than 2 samples.

    Examples
    --------
    >>> segment_slice(50_000, start=0.1, stop=0.3, fs=50_000.0)
    slice(5000, 15000, None)
    >>> segment_slice(1000, start=10, unit="samples")
    slice(10, 1000, None)
    """
    if unit not in SEGMENT_UNITS:
        raise InputError("unit", unit, f"must be one of {list(SEGMENT_UNITS)}")
    n = int(n_samples)
    i0 = _bound("start", start, unit, fs, shaft_frequency)
    i1 = _bound("stop", stop, unit, fs, shaft_frequency)
    i0 = 0 if i0 is None else i0
    i1 = n if i1 is None else i1
    if i1 > n:
        raise InputError("stop", stop, f"lies beyond the record ({n} samples, {unit!r})")
    if i1 - i0 < 2:
        raise InputError("segment", f"[{start}, {stop}) {unit}",
                         f"must hold at least 2 samples (got samples {i0}..{i1})")
    return slice(i0, i1)


def _engine(engine: str, spline_kind: str) -> str:
    """Engine actually used: "pyemd-rs" or "pyemd"."""
    if engine not in EMD_ENGINES:
        raise InputError("engine", engine, f"must be one of {list(EMD_ENGINES)}")
    if engine == "pyemd":
        return "pyemd"
    if spline_kind != "cubic":
        if engine == "pyemd-rs":
            raise InputError("spline_kind", spline_kind, "engine 'pyemd-rs' supports 'cubic' only")
        return "pyemd"
    try:
        import pyemd_rs  # noqa: F401
    except ImportError as exc:
        if engine == "pyemd-rs":
            raise InputError("engine", engine, "package pyemd-rs is not installed") from exc
        return "pyemd"
    return "pyemd-rs"


def emd(
    x: np.ndarray,
    *,
    max_imf: int = -1,
    spline_kind: str = "cubic",
    start: float | None = None,
    stop: float | None = None,
    unit: Literal["s", "samples", "rev"] = "s",
    fs: float | None = None,
    shaft_frequency: float | None = None,
    engine: Literal["auto", "pyemd", "pyemd-rs"] = "auto",
) -> Decomposition:
    """Decompose ``x``, or a segment of it, by EMD (Huang et al. 1998; PyEMD's algorithm).

    Two engines run the same algorithm (PyEMD's ``EMD``: simple extrema, mirrored
    ends with ``nbsym=2``, cubic-spline envelopes, PyEMD's default stopping thresholds):
    ``pyemd_rs`` (Rust, package ``pyemd-rs``) and ``PyEMD.EMD`` itself. Their IMFs agree
    to round-off (normalised RMS difference of the first three IMFs < 1e-11 on the
    benchmark signal; ``benchmarks/bench_emd.py`` and the tests require < 1e-6);
    ``pyemd_rs`` needs about 1.4x less CPU time. The time grows with the number of
    samples times the number of sifting iterations, most of them spent on the first
    IMFs: cutting the record (``start``/``stop``) bounds it, capping the IMFs
    (``max_imf``) saves little.

    Parameters
    ----------
    x : array_like
        Signal (the whole record).
    max_imf : int
        Maximum number of IMFs (``-1``, default: until the residue is monotonic). The
        first ``max_imf`` IMFs are the same as without the cap; what the cap leaves is in
        the residue.
    spline_kind : str
        Envelope interpolation ("cubic", "akima", "pchip", "cubic_hermite", "slinear",
        "quadratic", "linear"); only "cubic" runs on ``pyemd_rs``, the others on PyEMD.
    start : float, optional
        Start of the segment to decompose, in ``unit`` (default: start of the record).
    stop : float, optional
        End of the segment (excluded), in ``unit`` (default: end of the record).
    unit : {"s", "samples", "rev"}
        Unit of ``start``/``stop``: seconds (needs ``fs``), samples, or revolutions of the
        reference shaft (needs ``fs`` and ``shaft_frequency``); see :func:`segment_slice`.
    fs : float, optional
        Sampling rate [Hz], needed for ``unit`` "s" and "rev" when a bound is given.
    shaft_frequency : float, optional
        Reference shaft frequency [Hz], needed for ``unit`` "rev".
    engine : {"auto", "pyemd", "pyemd-rs"}
        ``"auto"`` (default): ``pyemd_rs`` for cubic splines when installed, else PyEMD;
        ``"pyemd"``: always ``PyEMD.EMD``; ``"pyemd-rs"``: always ``pyemd_rs``.

    Returns
    -------
    Decomposition
        IMFs (highest frequency first) and residue of the segment, in units of ``x``;
        ``start`` is the index of the segment's first sample in ``x``.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal, ``max_imf`` is neither -1 nor an integer >= 1,
        ``spline_kind`` or ``engine`` is not supported (or "pyemd-rs" is asked for
        without cubic splines or without the package), or the segment is invalid (see
        :func:`segment_slice`).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(5000) / 5000.0
    >>> x = np.sin(2 * np.pi * 400 * t) + 0.3 * np.sin(2 * np.pi * 20 * t)
    >>> dec = emd(x, max_imf=2, start=0.2, stop=0.8, fs=5000.0)
    >>> dec.imfs.shape, dec.start
    ((2, 3000), 1000)
    """
    a = as_signal(x)
    if isinstance(max_imf, bool) or int(max_imf) != max_imf or (max_imf < 1 and max_imf != -1):
        raise InputError("max_imf", max_imf, "must be -1 (no limit) or an integer >= 1")
    if spline_kind not in _SPLINES:
        raise InputError("spline_kind", spline_kind, f"must be one of {list(_SPLINES)}")
    which = _engine(engine, spline_kind)
    seg = segment_slice(a.size, start=start, stop=stop, unit=unit, fs=fs,
                        shaft_frequency=shaft_frequency)
    s = np.ascontiguousarray(a[seg])
    if which == "pyemd-rs":
        from pyemd_rs import emd as rs_emd

        imfs, residue = rs_emd(s, max_imf=None if max_imf == -1 else int(max_imf), **_PYEMD_STOP)
    else:
        from PyEMD import EMD  # imported here: PyEMD is only needed for this step

        dec = EMD(spline_kind=spline_kind)
        dec.emd(s, max_imf=int(max_imf))
        imfs, residue = dec.get_imfs_and_residue()
    imfs = np.asarray(imfs, dtype=np.float64).reshape(-1, s.size)
    return Decomposition(imfs=imfs, residue=np.asarray(residue, dtype=np.float64),
                         start=int(seg.start), engine=which)


def imf_correlations(x: np.ndarray, imfs: np.ndarray) -> np.ndarray:
    r"""Pearson correlation coefficient of each IMF with ``x`` (dimensionless).

    .. math:: \rho_c = \frac{\sum_i (c_i - \bar c)(x_i - \bar x)}
              {\sqrt{\sum_i (c_i - \bar c)^2 \sum_i (x_i - \bar x)^2}}

    the score of the correlation selection rule (Ayenu-Prah & Attoh-Okine 2010).

    Parameters
    ----------
    x : array_like
        Signal that was decomposed, 1-D (any units).
    imfs : array_like, shape (n_imfs, n_samples) or (n_samples,)
        IMFs, one per row, of the same length as ``x``.

    Returns
    -------
    ndarray, shape (n_imfs,)
        Correlation coefficients in [-1, 1]; 0 for a constant IMF or a constant ``x``.

    Raises
    ------
    InputError
        If ``x`` is not a valid signal or the rows of ``imfs`` differ in length from it.

    References
    ----------
    Ayenu-Prah & Attoh-Okine (2010), *Adv. Adapt. Data Anal.* 2, 1-24.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.sin(2 * np.pi * 10 * np.arange(1000) / 1000.0)
    >>> imf_correlations(x, np.vstack([x, -2.0 * x])).round(6)
    array([ 1., -1.])
    """
    a = as_signal(x)
    m = np.atleast_2d(np.asarray(imfs, dtype=np.float64))
    if m.shape[1] != a.size:
        raise InputError("imfs.shape", m.shape, f"rows must have {a.size} samples (signal length)")
    ac = a - a.mean()
    mc = m - m.mean(axis=1, keepdims=True)
    den = np.sqrt(np.sum(mc * mc, axis=1) * np.sum(ac * ac))
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = np.where(den > 0, mc @ ac / den, 0.0)
    return rho


def imf_kurtoses(imfs: np.ndarray) -> np.ndarray:
    """Kurtosis (Pearson, Gaussian = 3) of each IMF.

    Uses :func:`gearsim.signals.timedomain.kurtosis`; IMFs above 3 are impulsive and
    carry tooth impacts (Randall 2011, sec. 3.7).

    Parameters
    ----------
    imfs : array_like, shape (n_imfs, n_samples) or (n_samples,)
        IMFs, one per row (any units).

    Returns
    -------
    ndarray, shape (n_imfs,)
        Kurtosis of each IMF (dimensionless).

    Raises
    ------
    InputError
        If an IMF is constant (zero variance), shorter than two samples or not finite.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(1000) / 1000.0
    >>> imf_kurtoses(np.vstack([np.sin(2 * np.pi * 10 * t), np.cos(2 * np.pi * 10 * t)])).round(6)
    array([1.5, 1.5])
    """
    m = np.atleast_2d(np.asarray(imfs, dtype=np.float64))
    return np.array([kurtosis(row) for row in m])


def select_imfs(
    x: np.ndarray,
    dec: Decomposition,
    *,
    method: Literal["correlation", "kurtosis"],
    threshold: float | Literal["ayenu-prah"],
) -> Selection:
    """Select IMFs by correlation with ``x`` or by kurtosis and sum them.

    Parameters
    ----------
    x : array_like
        Raw signal that was decomposed: the segment, or the whole record given to
        :func:`emd` (then cut to the decomposed samples ``dec.start ..``).
    dec : Decomposition
        Its EMD (:func:`emd`).
    method : {"correlation", "kurtosis"}
        Score of each IMF: ``|rho|`` with ``x``, or kurtosis.
    threshold : float or "ayenu-prah"
        Keep IMFs with score >= threshold. ``"ayenu-prah"`` (correlation only) uses
        ``min(max rho, max rho / (10 max rho - 3))`` (Ayenu-Prah & Attoh-Okine 2010); the
        ``min`` keeps at least the most correlated IMF when ``max rho < 0.4``, where the
        published rule would exceed every score.

    Returns
    -------
    Selection
        Indices, scores, the threshold used and the sum of the selected IMFs (zeros if
        none passes).

    Raises
    ------
    InputError
        If ``method`` is unknown, ``"ayenu-prah"`` is asked for with ``"kurtosis"``, the
        threshold is not finite, (kurtosis) an IMF is constant, or ``x`` is shorter than
        the decomposed segment.
    """
    n = dec.imfs.shape[1]
    x = np.asarray(x)
    if x.ndim == 1 and x.size != n and x.size >= dec.start + n:
        x = x[dec.start : dec.start + n]
    if method == "correlation":
        scores = np.abs(imf_correlations(x, dec.imfs))
        if threshold == "ayenu-prah":
            top = float(scores.max())
            den = 10.0 * top - 3.0
            th = min(top, top / den) if den > 0 else top
        else:
            th = float(threshold)
    elif method == "kurtosis":
        if threshold == "ayenu-prah":
            raise InputError(
                "threshold", threshold, "the Ayenu-Prah rule applies to correlation only"
            )
        scores = imf_kurtoses(dec.imfs)
        th = float(threshold)
    else:
        raise InputError("method", method, "must be 'correlation' or 'kurtosis'")
    if not np.isfinite(th):
        raise InputError("threshold", threshold, "must be a finite number")
    idx = tuple(int(i) for i in np.flatnonzero(scores >= th))
    sig = dec.imfs[list(idx)].sum(axis=0) if idx else np.zeros(dec.imfs.shape[1])
    return Selection(indices=idx, scores=scores, threshold=th, method=method, signal=sig)
