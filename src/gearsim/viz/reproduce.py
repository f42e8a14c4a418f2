"""Figures of ``gearsim reproduce``: equivalents of the seed's Figures 3 and 5-8.

All figures use matplotlib's object-oriented API with the Agg canvas (no GUI), SI units
on the axes (forces in kN, stiffness in GN/m), a legend on every panel with more than
one curve, and fonts of at least 9 pt at the saved size.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gearsim.viz.style import figure_and_axes, figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from gearsim.studies.reproduction import Reproduction

__all__ = ["plot_all", "plot_stiffness", "plot_time", "plot_spectrum", "plot_zooms",
           "plot_stft", "plot_sensitivity", "plot_fault_magnitudes", "CAPTIONS"]

#: Colours of the cases, the same in every figure.
COLORS = {"healthy": "black", "working": "tab:red", "non-working": "tab:blue",
          "working-open": "tab:orange", "non-working-open": "tab:cyan", "open": "tab:orange"}
NAMES = {"healthy": "healthy", "working": "working-flank crack",
         "non-working": "non-working-flank crack", "working-open": "working, open closure",
         "non-working-open": "non-working, open closure", "open": "open closure (either flank)"}


_REP = """    rep : gearsim.studies.reproduce.Reproduction
        Results of :func:`gearsim.studies.reproduce.reproduce`."""
_ROUTE = """    route : {"PE", "FE"}
        Stiffness route of the dynamic runs shown."""
_RETURNS = """    Returns
    -------
    matplotlib.figure.Figure
        The figure."""


def _doc(func):
    """Fill the shared parameter descriptions into ``func.__doc__``."""
    if func.__doc__:  # None under python -OO
        func.__doc__ = func.__doc__.format(rep=_REP, route=_ROUTE, returns=_RETURNS)
    return func


@styled
@_doc
def plot_stiffness(rep: Reproduction, *, fig: Figure | None = None) -> Figure:
    """Seed Figure 3: mesh stiffness healthy and cracked, PE and FE; FE vs PE tooth check.

    Parameters
    ----------
{rep}
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (one panel; two more per row of FE checks and of the FE
        gear pair); default a new one.

{returns}
    """
    has_fe = bool(rep.fe_checks)
    has_pair = bool(rep.fe_pair)
    rows = 1 + has_fe + has_pair
    fig = figure_or_new(fig, 12, 4.5 + 4.0 * (rows - 1))
    gs = fig.add_gridspec(rows, 2)
    ax0 = fig.add_subplot(gs[0, :])
    if has_fe:
        ax1 = fig.add_subplot(gs[1, 0])
        ax2 = fig.add_subplot(gs[1, 1])
    z = rep.train.gears[0].teeth
    span = 360.0 / z * 5  # five base pitches either side of the cracked tooth
    pe = rep.stiffness["PE"]
    drop = pe["healthy"]["k"] - pe["working"]["k"]
    centre = float(pe["working"]["theta_deg"][int(np.argmax(drop))])
    for route, curves in rep.stiffness.items():
        ls = "-" if route == "PE" else "--"
        for label in ("healthy", "working", "non-working", "working-open"):
            c = curves[label]
            th = (c["theta_deg"] - centre + 180.0) % 360.0 - 180.0
            o = np.argsort(th)
            th, k = th[o], c["k"][o]
            sel = np.abs(th) <= span
            ax0.plot(th[sel], k[sel] / 1e9, ls, color=COLORS[label], lw=1.3,
                     label=f"{route}: {NAMES[label]}")
    ax0.set_xlabel("rotation of the input gear from the largest stiffness loss [deg]")
    ax0.set_ylabel("mesh stiffness, mesh I [GN/m]")
    ax0.set_title(f"(a) Time-varying mesh stiffness around the cracked tooth, crack "
                  f"{rep.options.depth * 1e3:.3g} mm at 45 deg")
    ax0.legend(ncols=2, loc="lower left")
    if has_fe:
        b = rep.train.gears[0].face_width
        for crack, chk in rep.fe_checks.items():
            label = {"none": "healthy"}.get(crack, crack)
            roll = np.degrees(chk.roll_angle)
            ax1.plot(roll, chk.k_pe * b / 1e9, "-", color=COLORS[label], label=f"PE, {label}")
            ax1.plot(roll, chk.k_fe * b / 1e9, "o", color=COLORS[label], ms=5,
                     label=f"FE, {label}")
        ax1.set_xlabel("roll angle of the contact point on the input tooth [deg]")
        ax1.set_ylabel(f"tooth stiffness, b = {b * 1e3:.4g} mm [GN/m]")
        ax1.set_title("(b) Single input tooth: potential energy (lines) vs FE (points)")
        ax1.legend(ncols=2, fontsize=8)
        names = ["max", "min", "mean"]
        seed = [6.7, 5.6, 6.3]
        width = 0.2
        xs = np.arange(3)
        ax2.bar(xs - 1.5 * width, seed, width, color="grey", label="seed |error|")
        for i, (crack, chk) in enumerate(rep.fe_checks.items()):
            d = chk.differences()
            label = {"none": "healthy"}.get(crack, crack)
            ax2.bar(xs + (i - 0.5) * width, [abs(d[n]) for n in names], width,
                    color=COLORS[label], label=f"ours, {label}")
        ax2.axhline(10.0, color="k", ls=":", lw=1, label="10 % (seed's bound)")
        ax2.set_xticks(xs, [f"{n} stiffness" for n in names])
        ax2.set_ylabel("|k_PE - k_FE| / k_FE [%]")
        ax2.set_title("(c) PE vs FE differences (seed Figure 3b)")
        ax2.legend(fontsize=8)
    if has_pair:
        _plot_fe_pair(rep, fig.add_subplot(gs[rows - 1, 0]), fig.add_subplot(gs[rows - 1, 1]))
    return fig


_PAIR_CURVES = {"pe": ("-", "PE, seed options"),
                "pe_line": ("--", "PE tooth + line contact + coupling"),
                "fe_tooth": (":", "FE tooth + line contact + coupling"),
                "accurate": ("--", "gearsim default (calibrated)")}
#: The model curves drawn against the FE pair: the seed's and gearsim's default.
_DRAWN = ("pe", "accurate")


def _plot_fe_pair(rep: Reproduction, ax_k, ax_bar) -> None:
    """(d) FE gear pair TVMS of the mesh-I section against the model curves; (e) bars."""
    chk0 = next(iter(rep.fe_pair.values()))
    for crack, chk in rep.fe_pair.items():
        label = {"none": "healthy"}.get(crack, crack)
        color = COLORS[label]
        ax_k.plot(chk.cycles, chk.k_fe / 1e9, "o", color=color, ms=3.5,
                  label=f"FE gear pair, {label}")
        for curve in _DRAWN:
            ls, name = _PAIR_CURVES[curve]
            ax_k.plot(chk.cycles, chk.curves[curve] / 1e9, ls, color=color, lw=1.1,
                      label=f"{name}, {label}" if crack == "none" else None)
    ax_k.set_xlabel("mesh cycles (cracked tooth enters at the second)")
    ax_k.set_ylabel(f"mesh stiffness, section of mesh {chk0.mesh} [GN/m]")
    ax_k.set_title(f"(d) FE gear pair vs PE, {chk0.torque:.4g} N m (seed Figure 3a)")
    ax_k.legend(fontsize=7, ncols=2)
    names = ["max", "min", "mean"]
    xs = np.arange(3)
    n = 1 + len(_DRAWN) * len(rep.fe_pair)
    width = 0.8 / n
    ax_bar.bar(xs - 0.4 + 0.5 * width, [6.7, 5.6, 6.3], width, color="grey",
               label="seed |error|")
    j = 1
    for curve, hatch in zip(_DRAWN, ("", "//"), strict=True):
        for crack, chk in rep.fe_pair.items():
            label = {"none": "healthy"}.get(crack, crack)
            d = chk.differences(curve)
            ax_bar.bar(xs - 0.4 + (j + 0.5) * width, [d[m] for m in names], width,
                       color=COLORS[label], hatch=hatch, edgecolor="k", lw=0.3,
                       label=f"{_PAIR_CURVES[curve][1]}, {label}")
            j += 1
    ax_bar.axhline(0.0, color="k", lw=0.8)
    ax_bar.set_xticks(xs, [f"{m} stiffness" for m in names])
    ax_bar.set_ylabel("(k_model - k_FE pair) / k_FE pair [%]")
    ax_bar.set_title("(e) Differences to the FE gear pair (seed Figure 3b)")
    ax_bar.legend(fontsize=6)


def _impacts(rep: Reproduction, key: str) -> np.ndarray:
    m = rep.metrics.get(key)
    return np.asarray(m.impact_times) if m is not None else np.empty(0)


@styled
@_doc
def plot_time(rep: Reproduction, route: str = "PE", *, fig: Figure | None = None) -> Figure:
    """Seed Figure 5: dynamic load of mesh I over three revolutions, a zoom at an impact,
    and the fault signal (cracked minus healthy load) of both flanks.

    Parameters
    ----------
{rep}
{route}
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (four rows of two panels); default a new one.

{returns}
    """
    fig = figure_or_new(fig, 12, 11.5)
    axes = fig.subplots(4, 2, width_ratios=(2.2, 1))
    h = rep.runs[f"{route}/healthy"]
    t = np.arange(h.force.size) / h.fs
    span = 3 * rep.t1
    first = _impacts(rep, f"{route}/working")
    later = first[first > 0.5 * rep.t1]
    t_imp = later[0] if later.size else 1.5 * rep.t1
    start = max(0.0, t_imp - 0.5 * rep.t1)
    sel = (t >= start) & (t <= start + span)
    zoom = np.abs(t - t_imp) <= 4 / rep.f_m
    for row, label in enumerate(("healthy", "working", "non-working")):
        run = rep.runs[f"{route}/{label}"]
        ax, az = axes[row]
        for a_, s in ((ax, sel), (az, zoom)):
            if label != "healthy":
                a_.plot(t[s] * 1e3, h.force[s] / 1e3, color="grey", lw=0.8, alpha=0.8,
                        label="healthy")
            a_.plot(t[s] * 1e3, run.force[s] / 1e3, color=COLORS[label], lw=0.9,
                    label=NAMES[label])
        imp = _impacts(rep, f"{route}/{label}")
        shown = imp[(imp >= start) & (imp <= start + span)]
        if shown.size:
            m = rep.metrics[f"{route}/{label}"]
            w = max(1, int(2 * run.fs / rep.f_m))
            top = [run.force[max(0, int(ti * run.fs) - w): int(ti * run.fs) + w + 1].max()
                   for ti in shown]
            ax.plot(shown * 1e3, np.array(top) / 1e3 + 0.05 * np.ptp(run.force[sel]) / 1e3,
                    "v", color="k", ms=8,
                    label=f"impact (period {m.impact_period * 1e3:.4g} ms)")
        ax.set_title(f"{NAMES[label]}: {route} route")
        ax.set_ylabel("mesh I load [kN]")
        az.set_title("zoom: +- 4 mesh periods at an impact")
        ax.legend(loc="upper right", ncols=3, fontsize=8)
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, hi + 0.35 * (hi - lo))
        if label != "healthy":
            az.legend(loc="upper right", fontsize=8)
            lo, hi = az.get_ylim()
            az.set_ylim(lo, hi + 0.3 * (hi - lo))
    ax, az = axes[3]
    for label in ("working", "non-working"):
        e = rep.metrics[f"{route}/{label}"].residual
        for a_, s in ((ax, sel), (az, zoom)):
            a_.plot(t[s] * 1e3, e[s], color=COLORS[label], lw=0.9, label=NAMES[label])
    ax.set_title("fault residual: cracked minus healthy load, mesh harmonics removed "
                 "(impact detector)")
    ax.set_ylabel("fault residual [N]")
    az.set_title("fault residual, zoom")
    ax.legend(loc="upper right", fontsize=8)
    for a_ in axes[-1]:
        a_.set_xlabel("time [ms]")
    return fig


@styled
@_doc
def plot_spectrum(rep: Reproduction, route: str = "PE", *, ax: Axes | None = None) -> Figure:
    """Seed Figure 6: amplitude spectra of the dynamic load up to 4.5 f_m.

    Parameters
    ----------
{rep}
{route}
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

{returns}
    """
    fig, ax = figure_and_axes(ax, 12, 5)
    top = 4.5 * rep.f_m
    for label, lw in (("healthy", 1.6), ("working", 0.9), ("non-working", 0.9)):
        s = rep.runs[f"{route}/{label}"].analysis.spectrum
        sel = (s.frequency >= 0.5 / rep.t1) & (s.frequency <= top)  # no mean (0 Hz)
        ax.semilogy(s.frequency[sel], s.amplitude[sel], color=COLORS[label], lw=lw,
                    label=NAMES[label], alpha=0.85)
    for n in range(1, 5):
        ax.axvline(n * rep.f_m, color="k", ls=":", lw=0.8)
        ax.text(n * rep.f_m, 1.0, f" {n} f_m", transform=ax.get_xaxis_transform(),
                va="top", fontsize=10)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("amplitude of mesh I load [N]")
    ax.set_title(f"Spectrum of the dynamic load ({route} route, Hann window, "
                 f"{rep.options.revolutions} input revolutions)")
    lo, hi = ax.get_ylim()
    ax.set_ylim(max(lo, hi * 1e-9), hi * 5)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return fig


@styled
@_doc
def plot_zooms(rep: Reproduction, route: str = "PE", *, fig: Figure | None = None) -> Figure:
    """Seed Figure 7: spectra around n f_m (n = 1..4) with the sidebands n f_m +- k f_r1.

    Parameters
    ----------
{rep}
{route}
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (four panels); default a new one.

{returns}
    """
    fig = figure_or_new(fig, 12, 8)
    axes = fig.subplots(2, 2).ravel()
    f_r1 = 1.0 / rep.t1
    k_max = 6
    half = (k_max + 1.5) * f_r1
    for ax, n in zip(axes, range(1, 5), strict=True):
        ymin = np.inf
        for label in ("working", "non-working", "healthy"):
            s = rep.runs[f"{route}/{label}"].analysis.spectrum
            sel = np.abs(s.frequency - n * rep.f_m) <= half
            amp = np.maximum(s.amplitude[sel], 1e-6)
            ax.semilogy(s.frequency[sel], amp, color=COLORS[label],
                        lw=1.6 if label == "healthy" else 1.0,
                        label=NAMES[label], drawstyle="steps-mid")
            ymin = min(ymin, float(np.min(amp)))
        for k in range(-k_max, k_max + 1):
            if k:
                ax.axvline(n * rep.f_m + k * f_r1, color="grey", ls=":", lw=0.7)
        ax.set_xlim(n * rep.f_m - half, n * rep.f_m + half)
        lo, hi = ax.get_ylim()
        ax.set_ylim(max(lo, 1e-3), hi * 50)
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("amplitude [N]")
        ax.set_title(f"around {n} f_m = {n * rep.f_m:.5g} Hz (dotted: {n} f_m +- k f_r1)")
        ax.legend(loc="upper left", fontsize=8)
    return fig


@styled
@_doc
def plot_stft(rep: Reproduction, route: str = "PE", *, fig: Figure | None = None) -> Figure:
    """Seed Figure 8: STFT spectrograms with the n f_m bands, and band energy over time.

    Parameters
    ----------
{rep}
{route}
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (four panels and a colour bar); default a new one.

{returns}
    """
    fig = figure_or_new(fig, 12, 11)
    axes = fig.subplots(4, 1, sharex=True, height_ratios=(2, 2, 2, 1.6))
    top = 4.5 * rep.f_m
    labels = ("healthy", "working", "non-working")
    sgs = {lab: rep.runs[f"{route}/{lab}"].analysis.stft for lab in labels}
    t_end = sgs["healthy"].time[0] + 8 * rep.t1
    vmax = max(float(np.max(sg.psd)) for sg in sgs.values())
    vmax_db = 10 * np.log10(vmax)
    mesh = None
    for ax, lab in zip(axes[:3], labels, strict=True):
        sg = sgs[lab]
        fs_ = sg.frequency <= top
        ts_ = sg.time <= t_end
        db = 10 * np.log10(np.maximum(sg.psd[fs_][:, ts_], vmax * 1e-12))
        mesh = ax.pcolormesh(sg.time[ts_] * 1e3, sg.frequency[fs_], db, shading="nearest",
                             cmap="viridis", vmin=vmax_db - 70, vmax=vmax_db, rasterized=True)
        for n in range(1, 5):
            ax.axhline(n * rep.f_m, color="white", ls="--", lw=0.8)
            ax.text(sg.time[0] * 1e3, n * rep.f_m, f" {n} f_m", color="white", va="bottom",
                    fontsize=9)
        ax.set_ylabel("frequency [Hz]")
        ax.set_title(f"{NAMES[lab]} (STFT frame {sg.nperseg / sg.fs * 1e3:.3g} ms, "
                     f"resolution {sg.df:.3g} Hz)")
        ax.grid(False)
    cb = fig.colorbar(mesh, ax=list(axes[:3]), shrink=0.9)
    cb.set_label("PSD [dB re 1 N^2/Hz]")
    ax = axes[3]
    for lab in labels:
        a = rep.runs[f"{route}/{lab}"].analysis
        sg = a.stft
        ts_ = sg.time <= t_end
        for n, ls in ((1, "-"), (2, "--")):
            e = a.band_energy[n][ts_]
            ax.plot(sg.time[ts_] * 1e3, 100 * (e / np.mean(a.band_energy[n]) - 1), ls,
                    color=COLORS[lab], lw=1.0, label=f"{n} f_m, {lab}")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("band power - mean [%]")
    ax.set_title("power in n f_m +- f_m/2 over time (periodic with T1 when cracked)")
    ax.legend(ncols=3, fontsize=8, loc="upper right")
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + 0.6 * (hi - lo))
    return fig


@styled
@_doc
def plot_sensitivity(rep: Reproduction, *, fig: Figure | None = None) -> Figure:
    """Crack-depth sensitivity: stiffness drop, impact amplitude, RMS, SER at 1 and 2 f_m.

    The seed's values (``rep.seed``) are drawn as dotted lines.

    Parameters
    ----------
{rep}
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (four panels); default a new one.

{returns}
    """
    ref = rep.seed
    fig = figure_or_new(fig, 12, 8)
    axes = fig.subplots(2, 2).ravel()
    rows = rep.sensitivity
    cases = sorted({r["case"] for r in rows}, key=["working", "non-working", "open"].index)

    def series(case: str, key: str):
        rr = [r for r in rows if r["case"] == case]
        d = np.array([r["depth_m"] * 1e3 for r in rr])
        v = np.array([np.nan if r[key] is None else r[key] for r in rr], dtype=float)
        return d, v

    panels = (
        ("tvms_max_local_drop_percent", "largest local drop of mesh-I stiffness [%]",
         "(a) stiffness loss", None),
        ("impact_percent", "impact amplitude [% of healthy]", "(b) impact amplitude",
         (100 * ref["impact_working"], 100 * ref["impact_non_working"])),
        ("rms_percent", "RMS of the dynamic load [% of healthy]", "(c) RMS",
         (100 * ref["rms_working"], 100 * ref["rms_non_working"])),
        ("ser_1fm", "sideband energy ratio SER [-]", "(d) SER at 1 f_m (solid), "
         "2 f_m (dashed)", None),
    )
    for ax, (key, ylabel, title, seed) in zip(axes, panels, strict=True):
        for case in cases:
            d, v = series(case, key)
            ax.plot(d, v, "o-", color=COLORS[case], label=NAMES[case])
            if key == "ser_1fm":
                d2, v2 = series(case, "ser_2fm")
                ax.plot(d2, v2, "s--", color=COLORS[case], alpha=0.7)
        if seed is not None:
            ax.axhline(seed[0], color=COLORS["working"], ls=":", lw=1.2,
                       label=f"seed, working: {seed[0]:.4g} %")
            ax.axhline(seed[1], color=COLORS["non-working"], ls=":", lw=1.2,
                       label=f"seed, non-working: {seed[1]:.4g} %")
        ax.axvline(rep.options.depth * 1e3, color="grey", lw=0.8, ls="-.",
                   label="reference depth")
        ax.set_xlabel("crack depth [mm] (45 deg, from the 30 deg tangent point)")
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.legend(fontsize=8)
    return fig


@styled
@_doc
def plot_fault_magnitudes(rep: Reproduction, *, fig: Figure | None = None) -> Figure:
    """Impact amplitude and RMS of every fault class against severity, beside the seed's.

    Parameters
    ----------
{rep}
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (two panels); default a new one.

{returns}
    """
    ref = rep.seed
    fig = figure_or_new(fig, 12, 4.5)
    axes = fig.subplots(1, 2)
    rows = rep.fault_magnitudes
    kinds = list(dict.fromkeys(r["fault"] for r in rows))
    markers = "osD^v<>phx*"
    for ax, key, title, seeds in (
            (axes[0], "impact_percent", "(a) impact amplitude near the damaged tooth",
             (ref["impact_working"], ref["impact_non_working"])),
            (axes[1], "rms_percent", "(b) RMS of the dynamic load",
             (ref["rms_working"],))):
        for i, kind in enumerate(kinds):
            rr = [r for r in rows if r["fault"] == kind]
            x = [r["severity"] for r in rr]
            y = [np.nan if r[key] is None else r[key] for r in rr]
            ax.plot(x, y, marker=markers[i % len(markers)], label=kind)
        for v in seeds:
            ax.axhline(100 * v, color="k", ls=":", lw=1.2)
        ax.text(0.02, 100 * max(seeds), " seed", va="bottom", fontsize=8,
                transform=ax.get_yaxis_transform())
        ax.set_xlabel("severity (fraction of the reference size, gearsim.model.variants)")
        ax.set_ylabel("% of healthy (same contact-mesh model)")
        ax.set_title(title)
    axes[0].legend(fontsize=8, ncol=2)
    return fig


#: Caption of each figure of the report, by file stem (the keys of :func:`plot_all`).
CAPTIONS: dict[str, str] = {
    "fig3_stiffness":
        "Equivalent of seed Figure 3: (a) mesh-I stiffness around the cracked input "
        "tooth, potential energy (solid) and FE tooth compliance (dashed; the FE working-flank "
        "crack opens, so its contact and open curves coincide); (b) tooth "
        "stiffness along the path of contact, PE lines and FE points; (c) PE-FE "
        "differences of the max, min and mean tooth stiffness beside the seed's; (d) the FE "
        "gear pair's mesh stiffness of the mesh-I transverse section against the PE curves "
        "and (e) the differences of their max, min and mean (seed Figure 3a/3b).",
    "fig5_time":
        "Equivalent of seed Figure 5: dynamic load of mesh I over three input "
        "revolutions (left; triangles: impacts found in the fault residual, bottom row) and a "
        "zoom at an impact (right); the healthy load is drawn in grey behind the cracked "
        "ones.",
    "fig6_spectrum":
        "Equivalent of seed Figure 6: amplitude spectra of the dynamic load.",
    "fig7_zooms":
        "Equivalent of seed Figure 7: spectra around n f_m, n = 1..4; dotted lines at the "
        "sideband positions n f_m +- k f_r1. The healthy load has only low lines off the "
        "f_r1 grid, three to four orders below the mesh tone (as the seed describes its "
        "Figure 7a); the cracked loads add the f_r1 families. Clipped at 1 mN.",
    "fig8_stft":
        "Equivalent of seed Figure 8: STFT of the dynamic load (same colour scale for "
        "the three cases) and the power near 1 f_m and 2 f_m over time.",
    "fig_sensitivity":
        "Crack-depth sensitivity (PE route): the seed does not state its crack size.",
    "fig_fault_magnitudes":
        "Which faults reach the seed's magnitudes: impact amplitude (a) and RMS (b) of the "
        "mesh-I load for every fault class on tooth 0 of the input gear against its "
        "severity, in % of the healthy train on the same contact-mesh model; dotted: the "
        "seed's values (impact 209.8 / 203.1 %, RMS 132.4 %).",
}


def plot_all(rep: Reproduction) -> dict[str, Figure]:
    """Every figure of the report, by file stem (captions in :data:`CAPTIONS`).

    Parameters
    ----------
    rep : gearsim.studies.reproduce.Reproduction
        Results of :func:`gearsim.studies.reproduce.reproduce`.

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``fig3_stiffness``, ``fig5_time``, ``fig6_spectrum``, ``fig7_zooms``,
        ``fig8_stft``, ``fig_sensitivity`` and (when computed) ``fig_fault_magnitudes``,
        ready for :func:`gearsim.viz.save_all`.
    """
    return {
        "fig3_stiffness": plot_stiffness(rep),
        "fig5_time": plot_time(rep),
        "fig6_spectrum": plot_spectrum(rep),
        "fig7_zooms": plot_zooms(rep),
        "fig8_stft": plot_stft(rep),
        "fig_sensitivity": plot_sensitivity(rep),
        **({"fig_fault_magnitudes": plot_fault_magnitudes(rep)} if rep.fault_magnitudes
           else {}),
    }
