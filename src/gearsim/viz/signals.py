"""Figures of the signal analysis: time trace, spectrum, zooms around n f_m, spectrogram.

Each function draws one figure of an :class:`gearsim.signals.analysis.Analysis` (or a
:class:`gearsim.signals.compare.SidebandComparison`) in the house style and returns it;
:func:`figures` returns the standard set by name, :func:`plot` one of them by kind. The
core calls them through ``Analysis.plot`` and ``Analysis.figures``; files are written
with :func:`gearsim.viz.save` / :func:`gearsim.viz.save_all`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from gearsim.errors import InputError
from gearsim.viz.style import figure_and_axes, figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from gearsim.signals.analysis import Analysis
    from gearsim.signals.compare import SidebandComparison

__all__ = [
    "plot_time",
    "plot_spectrum",
    "plot_zooms",
    "plot_spectrogram",
    "plot_tsa",
    "plot_comparison",
    "figures",
    "plot",
    "KINDS",
]

_SHAFT_COLORS = ("tab:red", "tab:green", "tab:purple", "tab:brown", "tab:pink")


def _ylabel(units: str | None) -> str:
    return f"Amplitude [{units}]" if units else "Amplitude [signal units]"


def _envelope(t: np.ndarray, x: np.ndarray, n_bins: int) -> tuple[np.ndarray, np.ndarray]:
    """Min/max per bin so a long record draws fast without hiding impacts."""
    if x.size <= 2 * n_bins:
        return t, x
    m = x.size // n_bins
    xs = x[: m * n_bins].reshape(n_bins, m)
    ts = t[: m * n_bins].reshape(n_bins, m)[:, 0]
    tt = np.repeat(ts, 2)
    xx = np.column_stack([xs.min(axis=1), xs.max(axis=1)]).ravel()
    return tt, xx


@styled
def plot_time(a: Analysis, *, units: str | None = None, revolutions: float = 4.0,
              fig: Figure | None = None) -> Figure:
    """Time trace: whole record (min/max envelope) and a close view with impacts marked.

    Parameters
    ----------
    a : gearsim.signals.analysis.Analysis
        Result of :func:`gearsim.signals.analysis.analyze`.
    units : str, optional
        Units of the signal, shown on the axes.
    revolutions : float
        Length of the close view in revolutions of shaft 1.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (two panels); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig = figure_or_new(fig, 10, 6)
    ax1, ax2 = fig.subplots(2, 1)
    x = a.signal - (a.stats.mean if a.stats.mean_removed else 0.0)
    t = np.arange(x.size) / a.fs
    te, xe = _envelope(t, x, 4000)
    label = "signal - mean" if a.stats.mean_removed else "signal"
    ax1.plot(te, xe, lw=0.6, color="tab:blue", label=label)
    idx = np.clip(np.round(a.impacts.times * a.fs).astype(int), 0, x.size - 1)
    ax1.plot(a.impacts.times, x[idx], "v", color="tab:red", ms=5,
             label=f"impacts ({a.impacts.count})")
    ax1.axhline(a.impacts.threshold, color="tab:red", ls=":", lw=1, label="impact threshold")
    ax1.axhline(-a.impacts.threshold, color="tab:red", ls=":", lw=1)
    ax1.set_xlabel("Time [s]")
    ax1.set_ylabel(_ylabel(units))
    ax1.set_title(f"Time record: RMS {a.stats.rms:.4g}, kurtosis {a.stats.kurtosis:.3g}")
    ax1.legend(loc="upper right")
    t1 = 1.0 / a.kinematics.reference_frequency
    t0 = a.impacts.times[0] - 0.5 * t1 if a.impacts.count else 0.0
    t0 = max(0.0, t0)
    sel = (t >= t0) & (t <= t0 + revolutions * t1)
    ax2.plot(t[sel], x[sel], lw=0.8, color="tab:blue", label="signal")
    isel = (a.impacts.times >= t0) & (a.impacts.times <= t0 + revolutions * t1)
    for ti in a.impacts.times[isel]:
        ax2.axvline(ti, color="tab:red", ls="--", lw=1)
    if isel.any():
        ax2.axvline(a.impacts.times[isel][0], color="tab:red", ls="--", lw=1, label="impact")
    period = a.impacts.period
    txt = f"T1 = 1/f_r1 = {t1 * 1e3:.2f} ms"
    if np.isfinite(period):
        txt += f"; measured impact period {period * 1e3:.2f} ms"
    ax2.set_title(txt)
    ax2.set_xlabel("Time [s]")
    ax2.set_ylabel(_ylabel(units))
    ax2.legend(loc="upper right")
    return fig


@styled
def plot_spectrum(a: Analysis, *, units: str | None = None, ax: Axes | None = None) -> Figure:
    """Amplitude spectrum up to just above the highest mesh harmonic, with n f_m and sidebands.

    Parameters
    ----------
    a : gearsim.signals.analysis.Analysis
        Result of :func:`gearsim.signals.analysis.analyze`.
    units : str, optional
        Units of the signal, shown on the axes.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig, ax = figure_and_axes(ax, 10, 4.5)
    spec = a.spectrum
    f_m = a.kinematics.mesh_frequency
    top = (max(a.orders) + 0.5) * f_m
    sel = spec.frequency <= top
    ax.plot(spec.frequency[sel], spec.amplitude[sel], lw=0.7, color="tab:blue",
            label=f"amplitude spectrum ({spec.window})")
    for n, h in zip(a.orders, a.harmonics, strict=True):
        ax.plot(h.frequency, h.amplitude, "o", color="black", ms=5,
                label="mesh harmonics n f_m" if n == a.orders[0] else None)
        ax.annotate(f"{n} f_m", (h.frequency, h.amplitude), textcoords="offset points",
                    xytext=(4, 6), fontsize=9)
    shafts = list(a.kinematics.shafts)
    for fam in a.families:
        c = _SHAFT_COLORS[shafts.index(fam.shaft) % len(_SHAFT_COLORS)]
        ax.plot(fam.frequency, fam.amplitude, "x", color=c, ms=4,
                label=f"sidebands +-k f_r ({fam.shaft}, {fam.shaft_frequency:.4g} Hz)"
                if fam.order == a.orders[0] else None)
    ax.set_yscale("log")
    shown = spec.amplitude[sel]
    positive = shown[shown > 0]
    if positive.size:
        ax.set_ylim(max(positive.min(), positive.max() * 1e-8), positive.max() * 300)
    ax.set_xlim(0, top)
    ax.set_xlabel("Frequency [Hz]")
    ax.set_ylabel(_ylabel(units))
    ax.set_title(f"Spectrum, f_m = {f_m:.5g} Hz, resolution {spec.df:.3g} Hz")
    ax.legend(loc="upper center", ncols=2, fontsize=8)
    return fig


@styled
def plot_zooms(a: Analysis, *, units: str | None = None, fig: Figure | None = None) -> Figure:
    """Zoomed spectra around each n f_m (seed Figure 7) with sideband families marked.

    Parameters
    ----------
    a : gearsim.signals.analysis.Analysis
        Result of :func:`gearsim.signals.analysis.analyze`.
    units : str, optional
        Units of the signal, shown on the axes.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (one panel per mesh harmonic); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    orders = a.orders
    ncol = 2 if len(orders) > 1 else 1
    nrow = int(np.ceil(len(orders) / ncol))
    fig = figure_or_new(fig, 10, 3.2 * nrow)
    axes = np.atleast_1d(fig.subplots(nrow, ncol)).ravel()
    spec = a.spectrum
    f_m = a.kinematics.mesh_frequency
    f_r1 = a.kinematics.reference_frequency
    k_max = a.options["n_sidebands"]
    shafts = list(a.kinematics.shafts)
    for ax, n, h in zip(axes, orders, a.harmonics, strict=False):
        half = (k_max + 1.5) * f_r1
        sel = np.abs(spec.frequency - n * f_m) <= half
        ax.plot(spec.frequency[sel], spec.amplitude[sel], lw=0.8, color="tab:blue",
                label="spectrum")
        ax.plot(h.frequency, h.amplitude, "o", color="black", ms=5, label=f"{n} f_m")
        for fam in a.families:
            if fam.order != n:
                continue
            c = _SHAFT_COLORS[shafts.index(fam.shaft) % len(_SHAFT_COLORS)]
            ax.plot(fam.frequency, fam.amplitude, "x", color=c, ms=6,
                    label=f"{fam.shaft} SER {fam.ser:.3g}, CV {fam.cv:.2g}")
        ax.set_xlim(n * f_m - half, n * f_m + half)
        ax.set_yscale("log")
        shown = spec.amplitude[sel]
        positive = shown[shown > 0]
        if positive.size:
            # Head room above the highest line so the legend never hides it.
            ax.set_ylim(positive.min() * 0.5, positive.max() * 300)
        ax.set_xlabel("Frequency [Hz]")
        ax.set_ylabel(_ylabel(units))
        ax.set_title(f"Around {n} f_m = {n * f_m:.5g} Hz")
        ax.legend(loc="upper center", ncols=2, fontsize=8)
    for ax in axes[len(orders):]:
        ax.set_visible(False)
    return fig


@styled
def plot_spectrogram(
    a: Analysis, *, units: str | None = None, revolutions: float | None = 8.0,
    fig: Figure | None = None,
) -> Figure:
    """STFT power spectral density (dB) with n f_m marked, and band energy over time.

    Parameters
    ----------
    a : gearsim.signals.analysis.Analysis
        Result of :func:`gearsim.signals.analysis.analyze`.
    units : str, optional
        Units of the signal, shown on the axes.
    revolutions : float or None
        Limits the time axis to that many revolutions of shaft 1 so the
        once-per-revolution pulsation (seed Figure 8) stays visible; ``None`` shows the
        whole record.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (two panels and a colour bar); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig = figure_or_new(fig, 10, 7)
    ax1, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=(3, 1.3))
    sg = a.stft
    f_m = a.kinematics.mesh_frequency
    top = (max(a.orders) + 0.5) * f_m
    fsel = sg.frequency <= top
    tsel = np.ones(sg.time.size, dtype=bool)
    if revolutions is not None:
        tsel = sg.time <= sg.time[0] + revolutions / a.kinematics.reference_frequency
    p = sg.psd[fsel][:, tsel]
    floor = np.max(p) * 1e-12 if np.max(p) > 0 else 1e-300
    db = 10 * np.log10(np.maximum(p, floor))
    vmax = float(np.max(db))
    mesh = ax1.pcolormesh(sg.time[tsel], sg.frequency[fsel], db, shading="nearest", cmap="viridis",
                          vmin=vmax - 60, vmax=vmax, rasterized=True)
    cb = fig.colorbar(mesh, ax=ax1)
    unit2 = f"({units})²/Hz" if units else "(signal units)²/Hz"
    cb.set_label(f"PSD [dB re 1 {unit2}]")
    for n in a.orders:
        ax1.axhline(n * f_m, color="white", ls="--", lw=0.8)
        ax1.text(sg.time[0], n * f_m, f" {n} f_m", color="white", va="bottom", fontsize=9)
    ax1.set_ylabel("Frequency [Hz]")
    ax1.set_title(f"STFT: frame {sg.nperseg / sg.fs * 1e3:.3g} ms, resolution {sg.df:.3g} Hz")
    for n in a.orders:
        ax2.plot(sg.time[tsel], a.band_energy[n][tsel], lw=0.9, label=f"{n} f_m +- f_m/2")
    ax2.set_xlabel("Time [s]")
    ax2.set_ylabel(f"Band power [({units})²]" if units else "Band power [(signal units)²]")
    ax2.set_yscale("log")
    lo, hi = ax2.get_ylim()
    ax2.set_ylim(lo, hi * 30)  # head room for the legend
    ax2.legend(loc="upper center", ncols=min(4, len(a.orders)), fontsize=8)
    return fig


@styled
def plot_tsa(a: Analysis, *, units: str | None = None, fig: Figure | None = None) -> Figure:
    """Time-synchronous average and its difference signal over one revolution.

    Parameters
    ----------
    a : gearsim.signals.analysis.Analysis
        Result of :func:`gearsim.signals.analysis.analyze`.
    units : str, optional
        Units of the signal, shown on the axes.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (two panels); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig = figure_or_new(fig, 10, 5.5)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    m = a.tsa.samples_per_rev
    ang = np.arange(m) * 360.0 / m
    ax1.plot(ang, a.tsa.average, lw=0.8, color="tab:blue",
             label=f"TSA, {a.tsa.n_averages} revolutions")
    ax1.set_ylabel(_ylabel(units))
    ax1.set_title(f"Shaft 1 at {a.tsa.shaft_frequency:.4g} Hz: FM0 {a.indicators.fm0:.3g}")
    ax1.legend(loc="upper right")
    ax2.plot(ang, a.difference, lw=0.8, color="tab:orange", label="difference signal")
    ax2.plot(ang, a.residual, lw=0.6, color="tab:gray", alpha=0.8, label="residual signal")
    ind = a.indicators
    ax2.set_title(f"FM4 {ind.fm4:.3g}, NA4 {ind.na4:.3g}, M6A {ind.m6a:.3g}, M8A {ind.m8a:.3g}")
    ax2.set_xlabel("Shaft angle [deg]")
    ax2.set_ylabel(_ylabel(units))
    ax2.legend(loc="upper right")
    return fig


@styled
def plot_comparison(c: SidebandComparison, *, fig: Figure | None = None) -> Figure:
    """Simulated versus measured sideband amplitudes near each mesh harmonic (seed Table 2).

    Parameters
    ----------
    c : gearsim.signals.compare.SidebandComparison
        Result of :func:`gearsim.signals.compare.compare_sidebands`.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (one panel per mesh harmonic); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig = figure_or_new(fig, 10, 3.5 * len(c.orders))
    axes = np.atleast_1d(fig.subplots(len(c.orders), 1))
    w = 0.38
    for i, (ax, n) in enumerate(zip(axes, c.orders, strict=True)):
        pos = np.arange(c.k.size)
        ax.bar(pos - w / 2, c.measured[i], w, label="measured", color="tab:gray")
        ax.bar(pos + w / 2, c.simulated[i], w, label="simulated", color="tab:blue")
        ax.set_xticks(pos, [f"{k:+d}" for k in c.k])
        ax.set_xlabel(f"Sideband number k (n f_m + k f_r, {c.shaft})")
        ax.set_ylabel("Amplitude / A(n f_m)" if c.normalize == "mesh" else "Amplitude")
        ax.set_title(f"Near {n} f_m: error of mean sideband amplitude "
                     f"{c.mean_error_percent[i]:.3g} %")
        ax.legend(loc="upper right")
    return fig


#: Kinds of :func:`plot` -> (function, file stem in :func:`figures`, takes ``ax``).
KINDS: dict[str, tuple[Any, str, bool]] = {
    "time": (plot_time, "time", False),
    "spectrum": (plot_spectrum, "spectrum", True),
    "zooms": (plot_zooms, "zoom_mesh_harmonics", False),
    "spectrogram": (plot_spectrogram, "spectrogram", False),
    "tsa": (plot_tsa, "tsa", False),
}


def plot(a: Analysis, kind: str = "spectrum", *, ax: Axes | None = None,
         fig: Figure | None = None, units: str | None = None) -> Figure:
    """One figure of an analysis by kind (what ``Analysis.plot`` calls).

    Parameters
    ----------
    a : gearsim.signals.analysis.Analysis
        Result of :func:`gearsim.signals.analysis.analyze`.
    kind : {"time", "spectrum", "zooms", "spectrogram", "tsa"}
        Which figure.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into, for the single-panel kind ``"spectrum"``.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into, for the multi-panel kinds.
    units : str, optional
        Units of the signal, shown on the axes.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    Raises
    ------
    gearsim.errors.InputError
        If ``kind`` is unknown, or ``ax`` is given for a multi-panel kind.
    """
    if kind not in KINDS:
        raise InputError("kind", kind, f"must be one of {', '.join(KINDS)}")
    func, _, single = KINDS[kind]
    if single:
        if fig is not None:
            raise InputError("fig", "given", f'kind "{kind}" draws one panel: pass ax=')
        return func(a, units=units, ax=ax)
    if ax is not None:
        raise InputError("ax", "given", f'kind "{kind}" draws several panels: pass fig=')
    return func(a, units=units, fig=fig)


def figures(a: Analysis, *, units: str | None = None) -> dict[str, Figure]:
    """The standard figures of an analysis, by file stem (what ``Analysis.figures`` calls).

    Parameters
    ----------
    a : gearsim.signals.analysis.Analysis
        Result of :func:`gearsim.signals.analysis.analyze`.
    units : str, optional
        Units of the signal, shown on the axes.

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``time``, ``spectrum``, ``zoom_mesh_harmonics``, ``spectrogram`` and ``tsa``,
        ready for :func:`gearsim.viz.save_all`.
    """
    return {stem: func(a, units=units) for func, stem, _ in KINDS.values()}
