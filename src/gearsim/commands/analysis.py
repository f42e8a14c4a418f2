"""CLI verbs ``analyze`` and ``compare``: signal analysis of measured or simulated records.

Units are converted here, once: shaft speed in rpm on the command line becomes Hz for the
API (:mod:`gearsim.signals`), which works in SI throughout.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from gearsim.commands._options import as_options
from gearsim.errors import InputError
from gearsim.io.jsonout import strict_json
from gearsim.io.measured import read_signal
from gearsim.io.targets import atomic_folder, check_output_folder
from gearsim.signals._checks import check_speed_source, check_teeth
from gearsim.signals.analyze import analyze as run
from gearsim.signals.compare import compare_sidebands
from gearsim.viz import check_plot_file, save, save_all
from gearsim.viz.signals import KINDS, plot_comparison

__all__ = ["register"]

#: Files ``analyze --plot DIR`` writes; an existing DIR may hold only these (it is
#: replaced as a whole).
FIGURE_FILES = frozenset(f"{stem}.png" for _, stem, _ in KINDS.values())


def _speed(shaft_rpm: float | None, tacho: str | None) -> None:
    check_speed_source(shaft_rpm, tacho, names=("--shaft-rpm", "--tacho"), unit="rpm")


def _teeth(teeth: list[int] | None) -> list[int]:
    if not teeth:
        raise InputError("--teeth", None, "must be given (teeth of the gear on the measured "
                                          "shaft first, then the other gears)")
    return list(check_teeth(teeth, name="--teeth"))


def _emd_threshold(method: str | None, threshold: str | None) -> float | str:
    if method is None:
        return "ayenu-prah"
    if method not in ("correlation", "kurtosis"):
        raise InputError("--emd", method, 'must be "correlation" or "kurtosis"')
    if threshold is None:
        return "ayenu-prah" if method == "correlation" else 3.0
    if threshold == "ayenu-prah":
        return threshold
    try:
        return float(threshold)
    except ValueError:
        raise InputError("--emd-threshold", threshold, 'must be a number or "ayenu-prah"') from None


def _summary_text(d: dict[str, Any], units: str | None) -> str:
    u = f" {units}" if units else ""
    td = d["time_domain"]
    im = d["impacts"]
    lines = [
        f"record: {d['n_samples']} samples at {d['fs_hz']:g} Hz ({d['duration_s']:.4g} s)",
        f"mesh frequency {d['train']['mesh_frequency_hz']:.6g} Hz; shafts "
        + ", ".join(f"{k} {v:.5g} Hz" for k, v in d["train"]["shaft_frequencies_hz"].items()),
        f"RMS {td['rms']:.5g}{u}  peak {td['peak']:.5g}{u}  crest {td['crest_factor']:.4g}  "
        f"kurtosis {td['kurtosis']:.4g}",
    ]
    period = im["period_s"]
    lines.append(
        f"impacts: {im['count']} above {im['threshold']:.4g}{u}; period "
        + (f"{period * 1e3:.4f} ms ({im['period_ratio_to_T1']:.4f} x T1)" if period else "n/a")
    )
    if "ratios_to_baseline" in d:
        r = d["ratios_to_baseline"]
        lines.append("ratio to baseline: "
                     + ", ".join(f"{k} {100 * v:.1f} %" for k, v in r.items()))
    lines.append("mesh harmonics and sidebands (SER, CV, flatness):")
    for h in d["mesh_harmonics"]:
        fams = [f for f in d["sidebands"] if f["order"] == h["order"]]
        lines.append(
            f"  {h['order']} f_m = {h['frequency_hz']:.6g} Hz  A {h['amplitude']:.4g}{u}  "
            + "  ".join(f"{f['shaft']}: {f['ser']:.3g}/{f['cv']:.3g}/{f['flatness']:.3g}"
                        for f in fams)
        )
    tf = d["time_frequency"]
    lines.append(f"STFT bands (frame {tf['nperseg']} samples): order, width spectrum/STFT [Hz], "
                 "modulation at f_r1")
    for b in tf["bands"]:
        ws, wt, m = b["width_spectrum_hz"], b["width_stft_hz"], b["modulation_at_fr1"]
        lines.append(f"  {b['order']}: {ws if ws is None else f'{ws:.4g}'} / "
                     f"{wt if wt is None else f'{wt:.4g}'}  {m if m is None else f'{m:.3g}'}")
    t = d["tsa"]
    lines.append(
        f"TSA ({t['n_averages']} revs, M {t['samples_per_rev']}): FM0 {t['fm0']:.4g}  "
        f"FM4 {t['fm4']:.4g}  NA4 {t['na4']:.4g}  M6A {t['m6a']:.4g}  M8A {t['m8a']:.4g}"
    )
    if "emd" in d:
        e = d["emd"]
        lines.append(f"EMD: {e['n_imfs']} IMFs, selected {e['selected']} by {e['method']} "
                     f">= {e['threshold']:.3g}")
    lines.append(f"time {d['timings_s']['total']:.3g} s")
    return "\n".join(lines)


def analyze(
    file: Annotated[Path, typer.Argument(help="CSV, WAV, MAT, TDMS, UFF or NetCDF record")],
    channel: Annotated[str | None, typer.Option(help="channel name (required if several)")] = None,
    fs: Annotated[float | None, typer.Option(help="sampling rate [Hz] if not in the file")] = None,
    shaft_rpm: Annotated[float | None, typer.Option(help="speed of the measured shaft [rpm]")]
    = None,
    teeth: Annotated[list[int] | None, typer.Option(
        help="teeth of the gear on the measured shaft, then of the other gears (repeat)")] = None,
    tacho: Annotated[str | None, typer.Option(help="tacho channel of the measured shaft")] = None,
    pulses_per_rev: Annotated[int, typer.Option(help="tacho pulses per revolution")] = 1,
    baseline: Annotated[Path | None, typer.Option(help="healthy record, same channel")] = None,
    plot: Annotated[str | None, typer.Option(
        help="folder for the figures (replaced as a whole)")] = None,
    json_: Annotated[bool, typer.Option("--json", help="print the JSON summary")] = False,
    max_order: Annotated[int, typer.Option(help="mesh harmonics 1..N")] = 4,
    sidebands: Annotated[int, typer.Option(help="sidebands per side (SER uses 6)")] = 6,
    window: Annotated[str, typer.Option(help="hann, flattop or boxcar")] = "hann",
    emd: Annotated[str | None, typer.Option(
        help="decompose by EMD first and keep IMFs by 'correlation' or 'kurtosis'")] = None,
    emd_threshold: Annotated[str | None, typer.Option(
        help="IMF threshold: number, or 'ayenu-prah' (correlation default); kurtosis "
             "default 3.0")] = None,
) -> None:
    """Time, frequency, time-frequency and TSA analysis of one vibration record."""
    if plot is not None:  # every output target is checked before any work
        plot = check_output_folder(plot, "--plot", owned=FIGURE_FILES.__contains__)
    _speed(shaft_rpm, tacho)
    zs = _teeth(teeth)
    if max_order < 1:
        raise InputError("--max-order", max_order, "must be >= 1")
    threshold = _emd_threshold(emd, emd_threshold)
    with as_options({"channel": "--channel", "fs": "--fs"}):
        sig = read_signal(file, channel=channel, fs=fs)
    tach = None
    if tacho is not None:
        with as_options({"channel": "--tacho", "fs": "--fs"}):
            tach = read_signal(file, channel=tacho, fs=fs).data
    base = base_tach = None
    if baseline is not None:
        b = read_signal(baseline, channel=sig.channel, fs=fs)
        if abs(b.fs - sig.fs) > 1e-9 * sig.fs:
            raise InputError("--baseline fs", b.fs, f"must equal the record's {sig.fs:g} Hz")
        base = b.data
        if tacho is not None:
            base_tach = read_signal(baseline, channel=tacho, fs=fs).data
    result = run(
        sig.data, sig.fs, teeth=zs,
        shaft_frequency=None if shaft_rpm is None else shaft_rpm / 60.0,
        tacho=tach, pulses_per_rev=pulses_per_rev, baseline=base, baseline_tacho=base_tach,
        orders=tuple(range(1, max_order + 1)), n_sidebands=sidebands, window=window,
        emd_method=emd, emd_threshold=threshold,
    )
    d = result.to_dict()
    d["source"] = {"file": sig.path, "channel": sig.channel, "format": sig.fmt,
                   "fs_source": sig.fs_source, "units": sig.units,
                   "baseline": str(baseline) if baseline is not None else None,
                   "shaft_rpm": shaft_rpm}
    if plot is not None:  # written into a temporary folder, then swapped in
        with atomic_folder(plot) as tmp:
            written = save_all(result.figures(units=sig.units), tmp)
        d["figures"] = [str(plot / p.name) for p in written]
    if json_:
        typer.echo(strict_json(d, indent=1))
    else:
        typer.echo(_summary_text(d, sig.units))
        if plot is not None:
            typer.echo(f"figures: {', '.join(d['figures'])}")


def compare(
    simulated: Annotated[Path, typer.Argument(help="simulated record (e.g. gearsim NetCDF)")],
    measured: Annotated[Path, typer.Argument(help="measured record")],
    shaft_rpm: Annotated[float | None, typer.Option(help="speed of the faulty gear's shaft [rpm]")]
    = None,
    teeth: Annotated[int | None, typer.Option(help="teeth of the faulty gear")] = None,
    channel_sim: Annotated[str | None, typer.Option(help="channel of the simulated file")] = None,
    channel_meas: Annotated[str | None, typer.Option(help="channel of the measured file")] = None,
    fs_sim: Annotated[float | None, typer.Option(help="fs of the simulated file [Hz]")] = None,
    fs_meas: Annotated[float | None, typer.Option(help="fs of the measured file [Hz]")] = None,
    max_order: Annotated[int, typer.Option(help="mesh harmonics 1..N (seed: 2)")] = 2,
    sidebands: Annotated[int, typer.Option(help="sidebands per side")] = 6,
    window: Annotated[str, typer.Option(help="hann, flattop or boxcar")] = "hann",
    normalize: Annotated[str, typer.Option(
        help="'mesh': amplitudes relative to n f_m of the same signal; 'none': absolute")]
    = "mesh",
    plot: Annotated[str | None, typer.Option(help="figure file (.png, .pdf, .svg)")] = None,
    json_: Annotated[bool, typer.Option("--json", help="print the JSON table")] = False,
) -> None:
    """Sideband amplitudes near n f_m, simulated versus measured, with % errors (seed Table 2)."""
    if plot is not None:  # every output target is checked before any work
        plot = check_plot_file(plot, "--plot")
    _speed(shaft_rpm, None)
    if teeth is None or teeth < 1:
        raise InputError("--teeth", teeth, "must be given as an integer >= 1")
    if max_order < 1:
        raise InputError("--max-order", max_order, "must be >= 1")
    s = read_signal(simulated, channel=channel_sim, fs=fs_sim)
    m = read_signal(measured, channel=channel_meas, fs=fs_meas)
    f_r = shaft_rpm / 60.0
    c = compare_sidebands(
        s.data, s.fs, m.data, m.fs, mesh_frequency=f_r * teeth, shaft_frequency=f_r,
        orders=tuple(range(1, max_order + 1)), n_sidebands=sidebands, window=window,
        normalize=normalize, shaft="shaft1",
    )
    d = c.to_dict() | {
        "mesh_frequency_hz": f_r * teeth, "shaft_frequency_hz": f_r,
        "simulated": {"file": s.path, "channel": s.channel, "fs_hz": s.fs},
        "measured": {"file": m.path, "channel": m.channel, "fs_hz": m.fs},
    }
    if plot is not None:
        d["figure"] = str(save(plot_comparison(c), plot, parameter="--plot"))
    if json_:
        typer.echo(strict_json(d, indent=1))
        return
    typer.echo(f"sidebands n f_m +- k f_r, f_m = {f_r * teeth:.6g} Hz, f_r = {f_r:.5g} Hz, "
               f"normalize = {normalize}; error = |sim - meas| / meas")
    typer.echo(f"{'order':>5} {'sim mean':>12} {'meas mean':>12} {'error %':>9}")
    for row in d["orders"]:
        typer.echo(f"{row['order']:>5} {row['simulated_mean']:>12.5g} {row['measured_mean']:>12.5g}"
                   f" {row['mean_error_percent']:>9.2f}")
    if plot is not None:
        typer.echo(f"figure: {plot}")


def register(app: typer.Typer) -> None:
    """Add ``analyze`` and ``compare`` to the ``gearsim`` application.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`).
    """
    app.command("analyze")(analyze)
    app.command("compare")(compare)
