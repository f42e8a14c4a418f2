"""Mesh harmonics ``n f_m`` and their sideband families ``n f_m +- k f_r``.

A tooth-root crack modulates the meshing once per revolution of the cracked gear, which
puts sidebands spaced by that gear's shaft frequency around every mesh harmonic (seed,
sec. 3.2 and Figure 7). The seed tells the flanks apart by the level and the regularity of
those sidebands near 1 f_m and 2 f_m; this module measures both:

* sideband energy ratio, SER (Hanna et al. 2011): the sum of the amplitudes of the first
  ``K`` sidebands on both sides divided by the amplitude of the mesh harmonic;
* uniformity: coefficient of variation of the ``2K`` sideband amplitudes (0 for a perfectly
  even family) and spectral flatness of their powers (Wiener entropy; 1 for an even family,
  towards 0 for a family dominated by a few lines; Gray & Markel 1974).

References
----------
.. [Ha11] J. Hanna, C. Hatch, M. Kalb, A. Weiss, H. Luo, "Detection of wind turbine gear
   tooth defects using sideband energy ratio", China Wind Power 2011 (GE Bently Nevada).
.. [GM74] A. H. Gray, J. D. Markel, "A spectral-flatness measure for studying the
   autocorrelation method of linear prediction of speech analysis", *IEEE Trans. ASSP*
   22 (1974) 207-217.
.. [R11] R. B. Randall, *Vibration-based Condition Monitoring*, Wiley, 2011, sec. 3.6.

Two measures of the band around a mesh harmonic complete these: the off-tone fraction
(the share of the band power that is not in the mesh line, i.e. how far sidebands widen
the band) and the sideband spacing (the most common distance between the strongest
lines, which names the shaft that modulates the mesh).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from gearsim.errors import InputError
from gearsim.signals._checks import (
    check_below_nyquist,
    check_int,
    check_positive,
    check_resolution,
)
from gearsim.signals.spectrum import WINDOWS, Spectrum, Tone, tone

__all__ = [
    "SEARCH_FRACTION",
    "SidebandFamily",
    "check_sideband_request",
    "mesh_harmonics",
    "sideband_families",
    "sideband_energy_ratio",
    "coefficient_of_variation",
    "spectral_flatness",
    "off_tone_fraction",
    "sideband_spacing",
]

#: A line is looked for within +- SEARCH_FRACTION x (line spacing) of its nominal
#: frequency: wide enough for a speed error of a quarter of a shaft order, narrow enough
#: never to reach the neighbouring line (which sits one full spacing away).
SEARCH_FRACTION = 0.25


@dataclass(frozen=True)
class SidebandFamily:
    """Sidebands ``n f_m + k f_r`` (``k = -K..-1, 1..K``) of one shaft around one harmonic.

    Built by :func:`sideband_families`.

    Parameters
    ----------
    order : int
        Mesh harmonic ``n``.
    shaft : str
        Shaft label.
    shaft_frequency : float
        ``f_r`` (Hz).
    mesh : Tone
        Estimated tone at ``n f_m``.
    k : ndarray of int
        Signed sideband numbers.
    frequency : ndarray
        Nominal sideband frequencies (Hz).
    amplitude : ndarray
        Estimated sideband amplitudes (signal units).
    isolated : ndarray of bool
        False where another requested line (mesh harmonic or another shaft's sideband) lies
        within the resolution of the window, so the amplitude mixes two lines.
    ser : float
        Sideband energy ratio (:func:`sideband_energy_ratio`, dimensionless); NaN when
        the mesh tone has zero amplitude.
    cv : float
        Coefficient of variation of the sideband amplitudes
        (:func:`coefficient_of_variation`, dimensionless).
    flatness : float
        Spectral flatness of the sideband powers (:func:`spectral_flatness`), in (0, 1];
        NaN if a sideband amplitude is zero.
    """

    order: int
    shaft: str
    shaft_frequency: float
    mesh: Tone
    k: np.ndarray
    frequency: np.ndarray
    amplitude: np.ndarray
    isolated: np.ndarray
    ser: float
    cv: float
    flatness: float

    def to_dict(self) -> dict:
        """JSON-serialisable summary.

        Returns
        -------
        dict
            The fields, arrays as lists, the mesh tone flattened to
            ``mesh_frequency_hz`` and ``mesh_amplitude``; frequencies in Hz.
        """
        return {
            "order": self.order,
            "shaft": self.shaft,
            "shaft_frequency_hz": self.shaft_frequency,
            "mesh_frequency_hz": self.mesh.frequency,
            "mesh_amplitude": self.mesh.amplitude,
            "k": self.k.tolist(),
            "frequency_hz": self.frequency.tolist(),
            "amplitude": self.amplitude.tolist(),
            "isolated": self.isolated.tolist(),
            "ser": self.ser,
            "cv": self.cv,
            "flatness": self.flatness,
        }


def sideband_energy_ratio(mesh_amplitude: float, sideband_amplitudes: np.ndarray) -> float:
    r"""Sideband energy ratio :math:`\mathrm{SER} = \sum_{k=1}^{K}(A_{-k}+A_{+k}) / A_{n f_m}`.

    Dimensionless; Hanna et al. (2011) use ``K = 6`` and report SER < 1 for healthy gears.

    Parameters
    ----------
    mesh_amplitude : float
        Amplitude of the mesh harmonic :math:`A_{n f_m}` (signal units), > 0.
    sideband_amplitudes : array_like
        Amplitudes of the sidebands :math:`A_{\pm k}`, ``k = 1..K`` (same units); all of
        them are summed.

    Returns
    -------
    float
        SER (dimensionless).

    Raises
    ------
    InputError
        If ``mesh_amplitude`` is not > 0.

    References
    ----------
    Hanna, Hatch, Kalb, Weiss & Luo (2011), Detection of wind turbine gear tooth defects
    using sideband energy ratio, China Wind Power 2011.

    Examples
    --------
    >>> sideband_energy_ratio(2.0, [0.1, 0.2, 0.3, 0.4])
    0.5
    """
    if not (math.isfinite(mesh_amplitude) and mesh_amplitude > 0.0):
        raise InputError("mesh_amplitude", mesh_amplitude, "must be a finite number > 0 "
                         "to form the SER")
    amps = np.asarray(sideband_amplitudes, dtype=float)
    if amps.size and not (np.all(np.isfinite(amps)) and np.all(amps >= 0.0)):
        raise InputError("sideband_amplitudes", amps.tolist(), "must be finite and >= 0 "
                         "(amplitudes)")
    return float(np.sum(amps) / mesh_amplitude)


def coefficient_of_variation(amplitudes: np.ndarray) -> float:
    r"""Coefficient of variation :math:`\sigma(A)/\bar A` of amplitudes (population std).

    A measure of the uniformity of a sideband family: 0 for perfectly even sidebands,
    larger for a family whose lines fluctuate (seed, sec. 3.2).

    Parameters
    ----------
    amplitudes : array_like
        Sideband amplitudes (any units, all the same).

    Returns
    -------
    float
        CV (dimensionless); NaN when the mean amplitude is not > 0.

    Examples
    --------
    >>> coefficient_of_variation([2.0, 2.0, 2.0]), coefficient_of_variation([1.0, 3.0])
    (0.0, 0.5)
    """
    a = np.asarray(amplitudes, dtype=np.float64)
    m = a.mean()
    return float(a.std() / m) if m > 0 else float("nan")


def spectral_flatness(amplitudes: np.ndarray) -> float:
    r"""Spectral flatness :math:`\exp(\overline{\ln P}) / \bar P` of powers ``P = A^2``.

    Gray & Markel (1974); 1 for equal lines, near 0 when a few lines dominate.

    Parameters
    ----------
    amplitudes : array_like
        Line amplitudes ``A`` (any units); the powers are ``A**2``.

    Returns
    -------
    float
        Ratio of geometric to arithmetic mean power, in (0, 1] (dimensionless); NaN for
        an empty input or when a line has zero amplitude.

    References
    ----------
    Gray & Markel (1974), *IEEE Trans. ASSP* 22, 207-217.

    Examples
    --------
    Powers 1 and 4: geometric mean 2, arithmetic mean 2.5.

    >>> spectral_flatness([1.0, 1.0, 1.0]), spectral_flatness([1.0, 2.0])
    (1.0, 0.8)
    """
    p = np.asarray(amplitudes, dtype=np.float64) ** 2
    if p.size == 0 or np.any(p <= 0.0):
        return float("nan")
    return float(np.exp(np.mean(np.log(p))) / np.mean(p))


def check_sideband_request(
    n_samples: int,
    fs: float,
    *,
    mesh_frequency: float,
    shafts: Mapping[str, float],
    orders: Sequence[int],
    n_sidebands: int,
    window: str,
) -> None:
    """Refuse requests above Nyquist or finer than the record's frequency resolution.

    The highest line ``max(orders) f_m + n_sidebands max(f_r)`` must lie below ``fs/2``,
    and the record must last at least ``2 L / f_r`` for every shaft (``L`` = main-lobe half
    width of the window in bins, :data:`gearsim.signals.spectrum.WINDOWS`), so that
    adjacent sidebands do not share a main lobe.

    Parameters
    ----------
    n_samples : int
        Record length (samples).
    fs : float
        Sampling rate (Hz).
    mesh_frequency : float
        Fundamental mesh frequency ``f_m`` (Hz), > 0.
    shafts : mapping of str to float
        Shaft label to shaft frequency ``f_r`` (Hz), at least one, each > 0.
    orders : sequence of int
        Mesh harmonics ``n`` requested, each an integer >= 1.
    n_sidebands : int
        ``K``, sidebands per side, >= 1.
    window : str
        Window name, one of :data:`gearsim.signals.spectrum.WINDOWS`.

    Raises
    ------
    InputError
        If an argument is out of range, the highest line is not below ``fs/2``, or the
        record (``n_samples / fs`` s) is shorter than ``2 L / f_r`` for some shaft.

    Examples
    --------
    >>> check_sideband_request(1000, 1000.0, mesh_frequency=100.0, shafts={"in": 10.0},
    ...                        orders=[5], n_sidebands=1, window="hann")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    gearsim.errors.InputError: fs = 1000 Hz: must exceed 2 x 510 Hz = 1020 Hz to cover ...
    """
    check_positive("mesh_frequency", mesh_frequency)
    if window not in WINDOWS:
        raise InputError("window", window, f"must be one of {sorted(WINDOWS)}")
    if not shafts:
        raise InputError("shafts", "{}", "must name at least one shaft frequency")
    for name, f in shafts.items():
        check_positive(f"shafts[{name!r}]", f)
    if not orders or any(int(n) != n or n < 1 for n in orders):
        raise InputError("orders", list(orders), "must be a non-empty list of integers >= 1")
    if int(n_sidebands) != n_sidebands or n_sidebands < 1:
        raise InputError("n_sidebands", n_sidebands, "must be an integer >= 1")
    f_top = max(orders) * mesh_frequency + n_sidebands * max(shafts.values())
    check_below_nyquist(
        fs, f_top, f"mesh order {max(orders)} with {n_sidebands} sidebands ({f_top:g} Hz)"
    )
    check_resolution(
        n_samples, fs, {f"shaft {k}": v for k, v in shafts.items()},
        bins_needed=2 * WINDOWS[window], window=window,
    )


def _family_lines(mesh_frequency: float, shafts: Mapping[str, float], orders: Sequence[int],
                  n_sidebands: int) -> list[float]:
    """Every line of one mesh (Hz): its harmonics, then their sidebands of each shaft."""
    k = np.concatenate([np.arange(-n_sidebands, 0), np.arange(1, n_sidebands + 1)])
    lines = [n * mesh_frequency for n in orders]
    for n in orders:
        for fr in shafts.values():
            lines.extend(n * mesh_frequency + k * fr)
    return lines


def mesh_harmonics(
    spec: Spectrum, *, mesh_frequency: float, orders: Sequence[int], search: float,
    avoid: Sequence[float] = (),
) -> list[Tone]:
    """Tones at ``n f_m`` for each ``n`` in ``orders`` (search half width in Hz).

    Each is estimated by :func:`gearsim.signals.spectrum.tone` (largest bin within
    ``+- search`` of ``n f_m``, short of the main lobe of any line of ``avoid``,
    scalloping-corrected).

    Parameters
    ----------
    spec : Spectrum
        Amplitude spectrum of the signal.
    mesh_frequency : float
        Fundamental mesh frequency ``f_m`` (Hz).
    orders : sequence of int
        Mesh harmonics ``n``; ``n f_m`` must not exceed ``fs/2``.
    search : float
        Half width of the search band around each harmonic (Hz), > 0.
    avoid : sequence of float, optional
        Frequencies (Hz) of known lines of other meshes, never taken for a harmonic.

    Returns
    -------
    list of Tone
        One per order, in the order given (frequency in Hz, amplitude in signal units).

    Raises
    ------
    InputError
        If ``search`` is not > 0 or a harmonic lies outside ``[0, fs/2]``.

    Examples
    --------
    >>> import numpy as np
    >>> from gearsim.signals.spectrum import amplitude_spectrum
    >>> t = np.arange(1000) / 1000.0
    >>> spec = amplitude_spectrum(3.0 * np.cos(2 * np.pi * 100.0 * t), 1000.0)
    >>> mesh_harmonics(spec, mesh_frequency=100.0, orders=[1], search=2.5)
    [Tone(frequency=100.0, amplitude=3.0)]
    """
    return [tone(spec, n * mesh_frequency, search=search, avoid=avoid) for n in orders]


def sideband_families(
    spec: Spectrum,
    *,
    mesh_frequency: float,
    shafts: Mapping[str, float],
    orders: Sequence[int],
    n_sidebands: int,
    other_lines: Sequence[float] = (),
) -> list[SidebandFamily]:
    """Measure the sideband family of every shaft around every mesh harmonic.

    Each line is estimated by :func:`gearsim.signals.spectrum.tone` within
    ``+- SEARCH_FRACTION * f_r`` of its nominal frequency (mesh harmonics within
    ``+- SEARCH_FRACTION * min f_r``), never reaching into the main lobe of a line of
    ``other_lines`` (a line of another stage 1.2 Hz away was taken for the mesh harmonic
    in a record of 0.25 Hz bins).

    Parameters
    ----------
    spec : Spectrum
        Amplitude spectrum of the signal.
    mesh_frequency : float
        Fundamental mesh frequency ``f_m`` (Hz).
    shafts : mapping of str to float
        Shaft label to shaft frequency ``f_r`` (Hz).
    orders : sequence of int
        Mesh harmonics ``n`` to examine.
    n_sidebands : int
        ``K``, sidebands per side.
    other_lines : sequence of float, optional
        Frequencies (Hz) of lines of other meshes (e.g. the other stages of a compound
        train): never taken for a line of this mesh, and a sideband within the
        resolution of one is flagged not ``isolated``.

    Returns
    -------
    list of SidebandFamily
        Ordered by harmonic, then by shaft in the order given.

    Raises
    ------
    InputError
        If the request fails :func:`check_sideband_request` (arguments, Nyquist, record
        length).
    """
    check_sideband_request(
        spec.n_samples, spec.fs, mesh_frequency=mesh_frequency, shafts=shafts,
        orders=orders, n_sidebands=n_sidebands, window=spec.window,
    )
    k = np.concatenate([np.arange(-n_sidebands, 0), np.arange(1, n_sidebands + 1)])
    f_min = min(shafts.values())
    resolution = 2 * spec.lobe_bins * spec.df
    # Every requested line, to flag sidebands that coincide with another family's line.
    others = np.asarray(other_lines, dtype=float)
    all_lines_arr = np.sort(np.concatenate([
        _family_lines(mesh_frequency, shafts, orders, n_sidebands), others]))
    out: list[SidebandFamily] = []
    for n in orders:
        mesh = tone(spec, n * mesh_frequency, search=SEARCH_FRACTION * f_min, avoid=others)
        for name, fr in shafts.items():
            freq = n * mesh_frequency + k * fr
            amps = np.array([tone(spec, f, search=SEARCH_FRACTION * fr, avoid=others).amplitude
                             for f in freq])
            # Count lines within the resolution; the line itself is always one of them.
            lo = np.searchsorted(all_lines_arr, freq - resolution, side="left")
            hi = np.searchsorted(all_lines_arr, freq + resolution, side="right")
            near = hi - lo
            # Identical lines from the same family appear once; a duplicate means overlap.
            isolated = near <= 1
            out.append(
                SidebandFamily(
                    order=int(n), shaft=str(name), shaft_frequency=float(fr), mesh=mesh, k=k,
                    frequency=freq, amplitude=amps, isolated=isolated,
                    ser=sideband_energy_ratio(mesh.amplitude, amps) if mesh.amplitude > 0
                    else float("nan"),
                    cv=coefficient_of_variation(amps), flatness=spectral_flatness(amps),
                )
            )
    return out


def off_tone_fraction(
    spec: Spectrum, *, center: float, line_half_width: float, band_half_width: float
) -> float:
    r"""Fraction of the band power around a tone that lies outside the tone's line.

    .. math:: \eta = 1 - \frac{\sum_{|f_k - f_c| \le w_l} A_k^2}
                               {\sum_{|f_k - f_c| \le w_b} A_k^2}

    with ``A_k`` the amplitude spectrum. For a mesh harmonic ``f_c = n f_m`` with
    ``w_l = f_r / 2`` and ``w_b = f_m / 2`` it is the share of the band power carried by
    sidebands and noise: 0 for a pure tone whose window main lobe fits in ``+- w_l``
    (a record of whole revolutions puts the line on a bin; the Hann lobe spans +- 2
    bins), growing as sidebands widen the band (seed Figure 8).

    Parameters
    ----------
    spec : Spectrum
        Amplitude spectrum (signal units).
    center : float
        Frequency of the tone ``f_c`` [Hz].
    line_half_width : float
        ``w_l`` [Hz], half width counted as the line.
    band_half_width : float
        ``w_b`` [Hz], half width of the band; at least ``line_half_width``.

    Returns
    -------
    float
        ``eta`` in [0, 1] (dimensionless); NaN if the band holds no power.

    Raises
    ------
    InputError
        If ``center`` or a half width is not > 0, or ``band_half_width < line_half_width``.

    References
    ----------
    Randall (2011), sec. 3.6 (sidebands around the mesh harmonics).
    """
    check_positive("center", center)
    w_l = check_positive("line_half_width", line_half_width)
    w_b = check_positive("band_half_width", band_half_width)
    if w_b < w_l:
        raise InputError("band_half_width", w_b, f"must be >= line_half_width = {w_l:g} Hz")
    dist = np.abs(spec.frequency - center)
    p = spec.amplitude**2
    total = float(np.sum(p[dist <= w_b]))
    if total <= 0:
        return float("nan")
    return float(1.0 - np.sum(p[dist <= w_l]) / total)


def sideband_spacing(
    spec: Spectrum, *, center: float, shaft_frequency: float, n_sidebands: int = 6
) -> float:
    """Most common spacing of the strongest spectral lines around a tone.

    Within ``center +- (K + 0.5) f_r`` the ``2 K`` largest local maxima of the amplitude
    spectrum other than the tone itself (its main lobe, ``+- (L + 0.5)`` bins with ``L``
    the window's main-lobe half width) are sorted by frequency; the distances between
    neighbours on the same side of the tone are rounded to whole bins and the most
    common one (the smallest on a tie) is returned. For a family ``center +- k f_s``
    it is ``f_s`` to within one bin, exactly ``f_s`` when the lines fall on bins; a few
    stray lines (e.g. of another shaft) do not move it. ``f_r`` only sets the search
    band: the result is measured, not assumed.

    Parameters
    ----------
    spec : Spectrum
        Amplitude spectrum.
    center : float
        Frequency of the tone, e.g. ``n f_m`` [Hz].
    shaft_frequency : float
        Expected sideband spacing ``f_r`` [Hz] (sets the band searched).
    n_sidebands : int
        ``K``, sidebands per side searched.

    Returns
    -------
    float
        Spacing [Hz]; NaN if no two lines lie on one side of the tone.

    Raises
    ------
    InputError
        If ``center`` or ``shaft_frequency`` is not > 0, or ``n_sidebands`` is not an
        integer >= 1.

    References
    ----------
    Randall (2011), sec. 3.6: sideband spacing identifies the modulating shaft.
    """
    from scipy.signal import find_peaks

    check_positive("center", center)
    f_r = check_positive("shaft_frequency", shaft_frequency)
    k_max = check_int("n_sidebands", n_sidebands, minimum=1)
    df = spec.df
    sel = np.flatnonzero(np.abs(spec.frequency - center) <= (k_max + 0.5) * f_r)
    amp = spec.amplitude[sel]
    freq = spec.frequency[sel]
    idx, _ = find_peaks(amp)
    idx = idx[np.abs(freq[idx] - center) > (spec.lobe_bins + 0.5) * df]  # not the tone
    if idx.size < 2:
        return float("nan")
    top = idx[np.argsort(amp[idx])[::-1][: 2 * k_max]]
    f = np.sort(freq[top])
    same_side = np.sign(f[1:] - center) == np.sign(f[:-1] - center)
    steps = np.round(np.diff(f)[same_side] / df).astype(int)
    if steps.size == 0:
        return float("nan")
    values, counts = np.unique(steps, return_counts=True)
    return float(values[np.argmax(counts)] * df)  # argmax takes the smallest on a tie
