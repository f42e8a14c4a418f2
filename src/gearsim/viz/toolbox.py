"""Figures of the analyst's toolbox: envelope spectrum, kurtogram, cepstrum.

Each function draws one result of :mod:`gearsim.signals.envelope`,
:mod:`gearsim.signals.kurtogram` or :mod:`gearsim.signals.cepstrum` into one panel in
the house style and returns the figure; nothing is written (see :func:`gearsim.viz.save`).
The result objects hand off here: ``EnvelopeSpectrum.plot()``, ``Kurtogram.plot()``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gearsim.errors import InputError
from gearsim.viz.style import figure_and_axes, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from gearsim.signals.envelope import EnvelopeSpectrum
    from gearsim.signals.kurtogram import Kurtogram

__all__ = ["plot_envelope_spectrum", "plot_kurtogram", "plot_cepstrum"]


@styled
def plot_envelope_spectrum(
    es: EnvelopeSpectrum,
    *,
    f_max: float | None = None,
    harmonics_of: float | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Squared-envelope spectrum, optionally with the harmonics of a frequency marked.

    Parameters
    ----------
    es : gearsim.signals.envelope.EnvelopeSpectrum
        Result of :func:`gearsim.signals.envelope.envelope_spectrum`.
    f_max : float, optional
        Upper end of the frequency axis (Hz), > 0; default the width of the demodulated
        band (the squared envelope holds nothing above it).
    harmonics_of : float, optional
        Frequency (Hz), > 0, whose harmonics up to ``f_max`` are marked by dashed lines
        (e.g. an expected fault frequency).
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    lo, hi = es.band
    top = (hi - lo) if f_max is None else float(f_max)
    if not top > 0.0:
        raise InputError("f_max", f_max, "must be > 0 Hz")
    fig, ax = figure_and_axes(ax, 9, 4)
    sel = es.frequency <= top
    ax.plot(es.frequency[sel], es.amplitude[sel], lw=0.8, color="tab:blue",
            label="squared envelope")
    if harmonics_of is not None:
        if not float(harmonics_of) > 0.0:
            raise InputError("harmonics_of", harmonics_of, "must be > 0 Hz")
        ks = np.arange(1, int(top // harmonics_of) + 1)
        for j, k in enumerate(ks):
            ax.axvline(k * harmonics_of, color="tab:red", ls="--", lw=0.8, alpha=0.7,
                       label=f"k x {harmonics_of:.4g} Hz" if j == 0 else None)
    ax.set_xlim(0.0, top)
    ax.set_xlabel("Frequency [Hz]")
    ax.set_ylabel("Amplitude [signal units$^2$]")
    ax.set_title(f"Squared-envelope spectrum, band {lo:.4g}-{hi:.4g} Hz")
    ax.legend(loc="upper right")
    return fig


@styled
def plot_kurtogram(k: Kurtogram, *, ax: Axes | None = None) -> Figure:
    """Kurtogram: kurtosis over level (rows) and frequency (columns), best band marked.

    Parameters
    ----------
    k : gearsim.signals.kurtogram.Kurtogram
        Result of :func:`gearsim.signals.kurtogram.fast_kurtogram`.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig, ax = figure_and_axes(ax, 9, 5)
    rows = np.arange(k.levels.size + 1) - 0.5
    mesh = ax.pcolormesh(k.frequency_edges, rows, k.kurtosis, cmap="viridis", shading="flat")
    fig.colorbar(mesh, ax=ax, label="Kurtosis [-]")
    r = int(np.argmin(np.abs(k.levels - k.best.level)))
    lo, hi = k.best.band
    ax.plot([lo, hi, hi, lo, lo], [r - 0.5, r - 0.5, r + 0.5, r + 0.5, r - 0.5],
            color="tab:red", lw=1.5)
    ax.set_yticks(np.arange(k.levels.size))
    ax.set_yticklabels([f"{lv:.1f}" for lv in k.levels])
    ax.set_ylim(k.levels.size - 0.5, -0.5)
    ax.grid(False)
    ax.set_xlabel("Frequency [Hz]")
    ax.set_ylabel("Level")
    b = k.best
    ax.set_title(f"Kurtogram: max {b.kurtosis:.3g} at level {b.level:.1f}, "
                 f"centre {b.center:.5g} Hz, bandwidth {b.bandwidth:.4g} Hz")
    return fig


@styled
def plot_cepstrum(
    quefrency: np.ndarray,
    c: np.ndarray,
    *,
    q_max: float | None = None,
    peak: float | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Real cepstrum over quefrency, optionally with a period marked.

    Parameters
    ----------
    quefrency : array_like
        Quefrencies (s), from :func:`gearsim.signals.cepstrum.real_cepstrum`.
    c : array_like
        Real cepstrum (dimensionless), same shape.
    q_max : float, optional
        Upper end of the quefrency axis (s), > 0; default the last quefrency.
    peak : float, optional
        Quefrency (s) to mark with its rahmonics, e.g. the shaft period found by
        :func:`gearsim.signals.cepstrum.cepstral_peak`.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    q = np.asarray(quefrency, dtype=np.float64)
    cc = np.asarray(c, dtype=np.float64)
    if q.shape != cc.shape or q.ndim != 1 or q.size < 2:
        raise InputError("c", cc.shape, f"must be one-dimensional and match quefrency {q.shape}")
    top = float(q[-1]) if q_max is None else float(q_max)
    if not top > 0.0:
        raise InputError("q_max", q_max, "must be > 0 s")
    fig, ax = figure_and_axes(ax, 9, 4)
    sel = (q > 0.0) & (q <= top)  # c(0) is the mean log amplitude: off the scale
    ax.plot(q[sel] * 1e3, cc[sel], lw=0.8, color="tab:blue", label="real cepstrum")
    if peak is not None:
        if not float(peak) > 0.0:
            raise InputError("peak", peak, "must be > 0 s")
        for j, m in enumerate(range(1, int(top // peak) + 1)):
            ax.axvline(m * peak * 1e3, color="tab:red", ls="--", lw=0.8, alpha=0.7,
                       label=f"rahmonics of {peak * 1e3:.4g} ms" if j == 0 else None)
    ax.set_xlim(0.0, top * 1e3)
    ax.set_xlabel("Quefrency [ms]")
    ax.set_ylabel("Cepstrum [-]")
    ax.set_title("Real cepstrum")
    ax.legend(loc="upper right")
    return fig
