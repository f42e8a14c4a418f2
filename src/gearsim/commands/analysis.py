"""CLI verbs ``analyze`` and ``compare``: signal analysis of measured or simulated records.

``analyze`` takes any number of files and glob patterns, analyses every vibration channel (or the
``--channel`` ones) tier by tier (:mod:`gearsim.signals.tiers`: statistics need nothing,
the spectrum a sampling rate, shaft orders a speed, gear quantities tooth counts), and
prints what each value rests on; ``--out`` writes the table (rows = file x channel) and
labels (``--labels``, ``--label-pattern``) add a separability report
(:mod:`gearsim.studies.batch`). Every problem of one call is reported in one message.

Units are converted here, once: shaft speed in rpm on the command line becomes Hz for the
API (:mod:`gearsim.signals`), which works in SI throughout. Heavy modules (scipy,
xarray, matplotlib, dask, scikit-learn) are imported only where a run needs them.
"""

from __future__ import annotations

import math
from contextlib import ExitStack
from pathlib import Path
from typing import Annotated, Any

import typer

from gearsim.commands._options import as_options
from gearsim.errors import InputError

__all__ = ["register"]

#: Most mesh harmonics ``--max-order`` may ask for (each is listed; the gear tier skips
#: those above Nyquist, and a million of them would only fill the memory).
MAX_ORDER = 1000
#: Files ``analyze --report DIR`` writes; an existing DIR may hold only these.
REPORT_FILES = frozenset({"separability.json", "separability.csv"})
#: Teeth by which ``--stage`` may miss z_r = z_s + 2 z_p (profile shifts of about +-1 close
#: a centre-distance gap of one module; a stage file checks the exact shifted geometry).
SHIFT_TEETH = 2
#: Lowest speed ``--speed-search`` may start at [Hz] (0.06 rpm; a slower shaft turns
#: too seldom to be heard in any record).
MIN_SEARCH_HZ = 1e-3


def _figure_files() -> frozenset[str]:
    """Files ``analyze --plot DIR`` writes; an existing DIR may hold only these."""
    from gearsim.viz.signals import KINDS

    return frozenset(f"{stem}.png" for _, stem, _ in KINDS.values())


def _speed(shaft_rpm: float | None, tacho: str | None) -> None:
    from gearsim.signals._checks import check_speed_source

    check_speed_source(shaft_rpm, tacho, names=("--shaft-rpm", "--tacho"), unit="rpm")
    if shaft_rpm is not None:
        _rpm("--shaft-rpm", shaft_rpm)


def _rpm(name: str, rpm: float) -> float:
    """A shaft speed option [rpm], finite, > 0 and within the operating speeds a gear
    train takes (:data:`gearsim.system.train.MIN_SPEED`, ``MAX_SPEED``), before any
    record is read; returned in Hz."""
    from gearsim.signals._checks import check_positive
    from gearsim.system.train import MAX_SPEED, MIN_SPEED

    check_positive(name, rpm)
    lo, hi = MIN_SPEED * 30.0 / math.pi, MAX_SPEED * 30.0 / math.pi
    if not lo <= rpm <= hi:
        raise InputError(name, rpm, f"must be in [{lo:.3g}, {hi:.0f}] rpm, the operating "
                         "speeds of a gear train")
    return rpm / 60.0


def _teeth(values: list[str] | None, extra: list[str], problems: list[str]) -> tuple[int, ...] | None:
    """Tooth counts from ``--teeth`` values (each an integer or a comma list) and the bare
    integers typer left among the files (``--teeth 32 80``)."""
    from gearsim.signals._checks import MAX_TEETH

    if not values:
        return None
    items = [t.strip() for v in [*values, *extra] for t in str(v).split(",") if t.strip()]
    if not items:
        problems.append(f"--teeth = {' '.join(map(repr, values))}: must list at least one tooth "
                        "count (e.g. --teeth 32 80 or --teeth 32,80)")
        return None
    try:
        zs = tuple(int(t) for t in items)
    except ValueError:
        problems.append(f"--teeth = {' '.join(items)}: must be integers in [1, {MAX_TEETH}] "
                        "(e.g. --teeth 32 80 or --teeth 32,80)")
        return None
    if any(not 1 <= z <= MAX_TEETH for z in zs):
        problems.append(f"--teeth = {' '.join(items)}: must be integers in [1, {MAX_TEETH}]")
        return None
    return zs


#: The form of ``--stages``, named in its refusals.
STAGES_FORM = ("DRIVING/DRIVEN teeth of each stage in power-flow order, stages separated by "
               "commas, stage 1's driving gear on the measured shaft (e.g. --stages "
               "32/80,48/64)")


def _stages(text: str | None, problems: list[str]) -> tuple[tuple[int, int], ...] | None:
    """``--stages 32/80,48/64`` to ``((32, 80), (48, 64))``: every stage two integer tooth
    counts in [1, MAX_TEETH] (a compound train, :func:`gearsim.signals.analysis.kinematics`)."""
    import re

    from gearsim.signals._checks import MAX_TEETH

    if text is None:
        return None
    pairs = []
    for k, item in enumerate(text.split(","), start=1):
        m = re.fullmatch(r"\s*([+-]?\d+)\s*/\s*([+-]?\d+)\s*", item)
        if m is None:
            why = (f"stage {k} ({item.strip()}): tooth counts must be integers in "
                   f"[1, {MAX_TEETH}]"
                   if item.count("/") == 1 and all(p.strip() for p in item.split("/"))
                   else f"stage {k} ({item.strip() or 'empty'}) is not DRIVING/DRIVEN")
            problems.append(f"--stages = {text}: {why}; give {STAGES_FORM}")
            return None
        z_d, z_n = int(m.group(1)), int(m.group(2))
        if min(z_d, z_n) < 1 or max(z_d, z_n) > MAX_TEETH:
            problems.append(f"--stages = {text}: stage {k} ({item.strip()}): tooth counts "
                            f"must be integers in [1, {MAX_TEETH}]; give {STAGES_FORM}")
            return None
        pairs.append((z_d, z_n))
    return tuple(pairs)


def _speed_search(text: str | None, problems: list[str], name: str = "--speed-search",
                  fs: float | None = None) -> tuple[float, float] | None:
    """``LO,HI`` with an optional unit to ``(lo, hi)`` in Hz: bare numbers are Hz (the unit
    of the API); ``Hz`` (``hertz``, ``1/s``) or ``rpm`` (``r/min``, ``rev/min``,
    ``revolutions_per_minute``, as pint spells them) after HI applies to both, after
    each to each: ``20,40``, ``20,40Hz``, ``1200,2400rpm``, ``20 Hz, 2400 rpm``. An HI
    that no record of the sampling rate ``fs`` (the option's; else the highest read)
    resolves is refused here, before any file is read, as written."""
    import re

    from gearsim.io.record import MAX_SAMPLING_RATE
    from gearsim.signals.speed import MIN_HARMONICS

    if text is None:
        return None
    units = {"hz": 1.0, "hertz": 1.0, "1/s": 1.0, "rpm": 1 / 60, "r/min": 1 / 60,
             "rev/min": 1 / 60, "revolutions_per_minute": 1 / 60}
    form = "must be LO,HI in Hz, or with a unit: 20,40Hz or 1200,2400rpm"
    parts = []
    for item in text.split(","):
        m = re.fullmatch(r"\s*(.*?)\s*(hz|hertz|1/s|rpm|r/min|rev/min|revolutions_per_minute)?\s*",
                         item, flags=re.IGNORECASE)
        try:
            parts.append((float(m.group(1)), m.group(2) and units[m.group(2).lower()]))
        except ValueError:
            parts = []
            break
    if len(parts) != 2:
        problems.append(f"{name} = {text}: {form}")
        return None
    (lo, u_lo), (hi, u_hi) = parts
    lo, hi = lo * (u_lo or u_hi or 1.0), hi * (u_hi or u_lo or 1.0)
    if not MIN_SEARCH_HZ <= lo < hi < float("inf"):  # LO 5e-324 Hz overflowed the estimator
        problems.append(f"{name} = {text}: must be {MIN_SEARCH_HZ:g} Hz <= LO < HI "
                        f"({lo:g}, {hi:g} Hz)")
        return None
    top = 0.5 * (fs or MAX_SAMPLING_RATE) / MIN_HARMONICS  # as check_speed_search's
    if hi >= top:
        problems.append(f"{name} = {text}: must end below {top:.4g} Hz ({MIN_HARMONICS} "
                        "harmonics of the top speed below the Nyquist frequency of "
                        + (f"fs = {fs:g} Hz)" if fs else "the highest sampling rate "
                           f"read, {MAX_SAMPLING_RATE:g} Hz)"))
        return None
    return lo, hi


def _stage(text: str | None, problems: list[str]) -> tuple[int, int, int, int] | None:
    """``ZS,ZP,ZR,N`` to four integers, checked as a stage file is where tooth counts
    suffice (:class:`~gearsim.geometry.planetary.PlanetaryStage`): 7 to MAX_TEETH teeth,
    coaxiality (within ``SHIFT_TEETH`` teeth, which profile shifts can absorb), equal
    spacing, and neighbouring planets clear at the standard addendum (tip radius
    (z_p + 2) m / 2 on centres (z_s + z_p) m / 2 apart: sin(pi / N) > (z_p + 2)/(z_s + z_p))."""
    from gearsim.geometry.gear import MAX_TEETH

    if text is None:
        return None
    try:
        vals = tuple(int(v) for v in text.split(","))
    except ValueError:
        vals = ()
    if len(vals) != 4 or min(vals) < 1:
        problems.append(f"--stage = {text}: must be ZS,ZP,ZR,N (sun, planet and ring teeth, "
                        "planets; integers >= 1, e.g. 21,39,99,3)")
        return None
    zs, zp, zr, n = vals
    clear = (zp + 2) / (zs + zp)
    why = (f"sun and planet need 7 to {MAX_TEETH} teeth, the ring at most {MAX_TEETH}"
           if min(zs, zp) < 7 or max(vals[:3]) > MAX_TEETH else
           f"not coaxial: z_r must be z_s + 2 z_p = {zs + 2 * zp} (within {SHIFT_TEETH} with "
           "profile shifts)" if abs(zr - zs - 2 * zp) > SHIFT_TEETH else
           f"equal spacing needs (z_s + z_r)/N integer: ({zs} + {zr})/{n} = {(zs + zr) / n:.6g}"
           if (zs + zr) % n else
           f"neighbouring planets collide: N must be < pi / asin((z_p + 2)/(z_s + z_p)) = "
           f"{math.pi / math.asin(clear):.4g} (standard addendum)"
           if n > 1 and not math.sin(math.pi / n) > clear else None)
    if why is not None:
        problems.append(f"--stage = {text}: {why}")
        return None
    return vals  # type: ignore[return-value]


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


def _collect(problems: list[str], fn, *args, options: dict[str, str] | None = None,
             **kwargs):
    """``fn(*args, **kwargs)``, or None with its :class:`InputError` added to ``problems``
    (under the option the user typed when ``options`` maps the parameter to it)."""
    try:
        return fn(*args, **kwargs)
    except InputError as exc:
        name = (options or {}).get(exc.parameter, exc.parameter)
        problems.append(str(InputError(name, exc.value, exc.limit)))
        return None


#: Fields of AnalysisSettings -> the options of ``analyze`` that set them.
SETTINGS_OPTIONS = {"analysis.orders": "--max-order", "analysis.n_sidebands": "--sidebands",
                    "analysis.window": "--window", "analysis.emd_method": "--emd",
                    "analysis.emd_threshold": "--emd-threshold",
                    "analysis.pulses_per_rev": "--pulses-per-rev"}


def _separability_text(rep: dict) -> str:
    c = rep["classifier"]
    lines = ["separability of " + ", ".join(f"{k} ({n})" for k, n in rep["counts"].items())
             + (f"; AUC of {rep['positive']} against {rep['reference']}" if rep["positive"]
                else "; AUC of each class against the rest")
             + f" (reference {rep['reference']}: {rep['reference_reason']})"]
    for r in rep["indicators"][:10]:
        lines.append(f"  {r['indicator']:<28} AUC {r['auc']:.3f}  {r['class']} {r['direction']}")
    if rep["left_out"]:
        lines.append("  left out (operating point, not condition): "
                     + ", ".join(r["indicator"] for r in rep["left_out"]))
    acc, auc = c["accuracy"], c["auc"]
    grouped = f" grouped by {c['grouped_by']}" if c["grouped_by"] else ""
    lines.append(f"  classifier ({c['n_features']} indicators, {c['folds']}-fold CV{grouped}): "
                 + ("n/a (too few rows per class)" if acc != acc else
                    f"accuracy {acc:.3f}, AUC {auc:.3f}"))
    return "\n".join(lines)


def _write_report(rep: dict, folder: Path) -> None:
    import csv
    import io

    from gearsim.io.jsonout import strict_json
    from gearsim.io.targets import atomic_folder

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["indicator", "class", "auc", "direction", "n"])
    for r in rep["indicators"]:
        w.writerow([r["indicator"], r["class"], f"{r['auc']:.6g}", r["direction"], r["n"]])
    with atomic_folder(folder) as tmp:
        (tmp / "separability.csv").write_text(buf.getvalue())
        (tmp / "separability.json").write_text(strict_json(rep, indent=1))


def analyze(
    files: Annotated[list[str], typer.Argument(
        help="record files or glob patterns (CSV/TXT, WAV, MAT, TDMS, UFF, NetCDF; "
             "quote globs)", show_default=False)],
    channel: Annotated[list[str] | None, typer.Option(
        help="channel to analyse (repeat for several; any channel); default: every "
             "vibration channel: not the tachos (--tacho, a gearsim result's "
             "tacho[shaft=...]) nor angles (carrier_angle); a gearsim result's "
             "displacements q[dof=...] are included")] = None,
    fs: Annotated[float | None, typer.Option(
        help="sampling rate [Hz] if not in the file; without one, a speed given "
             "(--shaft-rpm or --config) makes an estimate from the record's mesh lines "
             "and sidebands (with teeth) or shaft lines (without), labelled estimate, or "
             "a reason when several rates fit; with no speed, frequencies are in "
             "cycles/sample")] = None,
    format_: Annotated[str | None, typer.Option(
        "--format", help="file format (csv, wav, mat, tdms, uff, netcdf) instead of the "
                         "extension")] = None,
    shaft_rpm: Annotated[float | None, typer.Option(help="speed of the measured shaft [rpm]")]
    = None,
    tacho: Annotated[str | None, typer.Option(help="tacho channel of the measured shaft "
                                              "(speed read from the file)")] = None,
    pulses_per_rev: Annotated[int, typer.Option(help="tacho pulses per revolution [-]")] = 1,
    speed_search: Annotated[str | None, typer.Option(
        help="estimate the measured shaft's speed from the signal within LO,HI: Hz when "
             "bare, or with a unit, 20,40Hz or 1200,2400rpm (labelled estimate, with the "
             "dominant mesh family's tooth count); the speed is tracked over the record "
             "and the shaft and gear lines read in the order domain")] = None,
    teeth: Annotated[list[str] | None, typer.Option(
        help="tooth counts [-], gear on the measured shaft first: --teeth 32 80, "
             "--teeth 32,80 or --teeth 32 --teeth 80")] = None,
    stages: Annotated[str | None, typer.Option(
        help="a compound train instead of --teeth: DRIVING/DRIVEN teeth [-] of each stage, "
             "stage 1's driving gear on the measured shaft, e.g. --stages 32/80,48/64; "
             "every stage's mesh is analysed; a gearsim result of a compound train "
             "brings its own")] = None,
    labels: Annotated[Path | None, typer.Option(
        help="CSV with columns file,label or file,channel,label: adds a separability "
             "report")] = None,
    label_pattern: Annotated[str | None, typer.Option(
        help="regular expression with one group giving the label from each file name, "
             "e.g. '^(healthy|faulty)_'")] = None,
    out: Annotated[str | None, typer.Option(
        help="table of indicators, rows file x channel, units in the header: .csv or "
             ".nc; finished files are kept in OUT.parts/ and skipped when an interrupted "
             "batch is run again")] = None,
    report: Annotated[str | None, typer.Option(
        help="folder for separability.csv/.json (needs labels; replaced as a whole)")] = None,
    healthy: Annotated[str | None, typer.Option(
        help="the label of the healthy (reference) class of the separability report; "
             "default: the label naming a healthy state (healthy, normal, h, ...), else "
             "the first in sorted order")] = None,
    json_: Annotated[bool, typer.Option("--json", help="print the JSON summary")] = False,
    workers: Annotated[int, typer.Option(help="local Dask worker processes [-]; 1 = serial "
                                         "in this process; at most one per file")] = 1,
    scheduler: Annotated[str | None, typer.Option(
        help="address of a running Dask scheduler (tcp://host:8786)")] = None,
    drop_nonfinite: Annotated[bool, typer.Option(
        help="drop NaN/inf samples instead of refusing the file")] = False,
    baseline: Annotated[Path | None, typer.Option(
        help="healthy record, same channel (one record only)")] = None,
    plot: Annotated[str | None, typer.Option(
        help="folder for the gear-tier figures (one record only; replaced as a whole)")]
    = None,
    max_order: Annotated[int, typer.Option(help="mesh harmonics 1..N [-]")] = 4,
    sidebands: Annotated[int, typer.Option(help="sidebands per side [-] (SER uses 6)")] = 6,
    window: Annotated[str, typer.Option(help="hann, flattop or boxcar")] = "hann",
    emd: Annotated[str | None, typer.Option(
        help="decompose by EMD first and keep IMFs by 'correlation' or 'kurtosis'")] = None,
    stage: Annotated[str | None, typer.Option(
        help="planetary stage ZS,ZP,ZR,N with the ring held: adds the planetary tier "
             "(sidebands, fault lines, separated planet and sun averages); --shaft-rpm is "
             "then the carrier speed. A gearsim stage result brings its own")] = None,
    emd_threshold: Annotated[str | None, typer.Option(
        help="IMF threshold [-]: number, or 'ayenu-prah' (correlation default); kurtosis "
             "default 3.0")] = None,
    config: Annotated[str | None, typer.Option(
        help="the gearbox measured (TOML file or example name): its teeth or stages from "
             "the input shaft (a lone planetary stage with the ring held: its stage, the "
             "carrier measured), and its input speed unless --shaft-rpm, --tacho or "
             "--speed-search gives one; labelled (config)")] = None,
) -> None:
    """Tiered analysis of records: statistics always; spectrum in Hz with a sampling rate
    (else cycles/sample); shaft orders with a speed (--shaft-rpm, --tacho or
    --speed-search); gear quantities with --teeth; planetary quantities with --stage (or
    from a gearsim stage result). Rows = file x channel."""
    problems: list[str] = []
    # every output target is checked before any work
    out_path = report_path = plot_path = None
    if out is not None:
        from gearsim.io.targets import check_output_file

        out_path = _collect(problems, check_output_file, out, "--out", (".csv", ".nc"))
    if report is not None:
        from gearsim.io.targets import check_output_folder

        report_path = _collect(problems, check_output_folder, report, "--report",
                               owned=REPORT_FILES.__contains__)
        if labels is None and label_pattern is None:
            problems.append(f"--report = {report}: needs --labels or --label-pattern")
    if healthy is not None and labels is None and label_pattern is None:
        problems.append(f"--healthy = {healthy}: needs --labels or --label-pattern")
    if plot is not None:
        from gearsim.io.targets import check_output_folder

        plot_path = _collect(problems, check_output_folder, plot, "--plot",
                             owned=_figure_files().__contains__)
    if labels is not None and label_pattern is not None:
        problems.append("--labels/--label-pattern = both: give at most one")
    n_speed = sum(v is not None for v in (shaft_rpm, tacho, speed_search))
    if n_speed > 1:
        problems.append("--shaft-rpm/--tacho/--speed-search = several: give at most one "
                        "speed source")
    elif shaft_rpm is not None:
        _collect(problems, _speed, shaft_rpm, None)
    if tacho is not None and channel and tacho in channel:
        problems.append(f"--tacho = {tacho}: is also a --channel: a tacho is not analysed as "
                        "vibration")
    if fs is not None and not (0 < fs < float("inf")):
        problems.append(f"--fs = {fs:g}: must be a finite rate > 0 Hz")
    if format_ is not None:
        from gearsim.io.measured import FORMATS

        if format_ not in FORMATS:
            problems.append(f"--format = {format_}: must be one of {sorted(FORMATS)}")
    if workers < 1:
        problems.append(f"--workers = {workers}: must be an integer >= 1")
    if scheduler is not None:
        from gearsim.studies.sweep_run import check_scheduler

        _collect(problems, check_scheduler, scheduler)
    if not 1 <= max_order <= MAX_ORDER:
        problems.append(f"--max-order = {max_order}: must be 1 to {MAX_ORDER}")
    # typer gives "--teeth 32 80" the 80 as a file: bare integers that are not files
    ints = [f for f in files if f.strip().isdigit() and not Path(f).exists()] if teeth else []
    files = [f for f in files if f not in ints]
    zs = _teeth(teeth, ints, problems)
    stg = _stages(stages, problems)
    if stages is not None and teeth:
        given = " ".join(map(str, zs)) if zs else " ".join(teeth)
        problems.append(f"--teeth/--stages = {given} / {stages}: give one, --teeth "
                        "for a simple train or --stages for a compound one")
    if stages is not None and stage is not None:
        problems.append(f"--stage/--stages = {stage} / {stages}: give one, --stage for a "
                        "planetary stage or --stages for a parallel-shaft compound train")
    stage_z = _stage(stage, problems)
    config_speed = None
    if config is not None:
        given = [o for o, v in (("--teeth", teeth), ("--stages", stages), ("--stage", stage))
                 if v]
        if given:
            problems.append(f"--config/{given[0]} = {config} / ...: give one; --config brings "
                            "the teeth, stages or stage of its gearbox")
        else:
            kin = _collect(problems, _config_kinematics, config)
            if kin is not None:
                zs, stg, stage_z, config_speed = kin
                if n_speed == 0 and stage_z is not None:
                    shaft_rpm = 60.0 * config_speed  # the carrier, as --stage wants
    if stage_z is not None and shaft_rpm is None:
        problems.append(f"--stage = {stage}: needs the carrier speed --shaft-rpm (the "
                        "measured shaft is the carrier)")
    search = _speed_search(speed_search, problems,
                           fs=fs if fs is not None and 0 < fs < float("inf") else None)
    threshold = _collect(problems, _emd_threshold, emd, emd_threshold)
    settings = None
    if 1 <= max_order <= MAX_ORDER and threshold is not None:
        from gearsim.signals.settings import AnalysisSettings

        settings = _collect(problems, AnalysisSettings, orders=tuple(range(1, max_order + 1)),
                            n_sidebands=sidebands, window=window, emd_method=emd,
                            emd_threshold=threshold, pulses_per_rev=pulses_per_rev,
                            options=SETTINGS_OPTIONS)
    from gearsim.studies import batch as bt

    n_options = len(problems)  # problems of the options: stop before reading any file
    names, more = bt.expand_inputs(files)
    problems += more
    if names and workers > len(names) and scheduler is None:
        problems.append(f"--workers = {workers}: must be <= {len(names)}, the files to "
                        "analyse (a worker more would have nothing to do)")
        n_options += 1  # an option's problem: no file is read
    lab, more = None, []  # labels from names or a CSV are known before any file is read
    if label_pattern is not None:
        lab = (_collect(more, bt.labels_from_pattern, names, label_pattern) or ({},))[0]
    elif labels is not None:
        lab = _collect(more, bt.labels_from_csv, labels)
    if lab is not None and names and not more:
        more += _label_problems(names, lab, *(("--label-pattern", label_pattern, "do not "
                                "match") if label_pattern is not None else
                                ("--labels", labels, "have no label")))
        if healthy is not None and not more:
            from gearsim.studies.diagnostic import reference_class

            _collect(more, reference_class, sorted(set(lab.values())), healthy)
    problems += more
    n_options += len(more)
    single = len(names) == 1 and (channel is None or len(channel) == 1)
    if (baseline is not None or plot is not None) and len(names) > 1:
        problems.append(f"--baseline/--plot: need exactly one record; {len(names)} files "
                        "given")
    if problems and (n_options or not names):
        raise bt.problems_error(problems)

    speed = None if shaft_rpm is None else shaft_rpm / 60.0
    if config_speed is not None and n_speed == 0:
        speed = config_speed
    options: dict[str, Any] = {"channels": channel, "fs": fs, "fmt": format_, "speed": speed,
                               "tacho": tacho, "pulses_per_rev": pulses_per_rev,
                               "speed_search": search, "teeth": zs, "settings": settings,
                               "drop_nonfinite": drop_nonfinite, "stage": stage_z}
    if stg is not None:  # only when given: the part keys of simple batches stay the same
        options["stages"] = stg
    if config is not None:  # what the configuration brought
        options["provenance"] = {k: "config" for k, v in (
            ("speed", config_speed is not None and n_speed == 0), ("teeth", zs or stg),
            ("stage", stage_z)) if v}
        options["provenance"]["config"] = config  # named in what rests on it
    with ExitStack() as stack:  # OUT's lock, from the first part to the table
        if out_path is not None:
            from gearsim.studies.sweep_run import store_lock

            stack.enter_context(store_lock(out_path, owner="batch"))
        if single and (baseline is not None or plot is not None):
            res = _one_with_baseline(names[0], baseline, options)
        else:  # with --out: resumable, a part per finished file in OUT.parts/
            res = bt.collect(names, labels=lab, workers=workers, scheduler=scheduler,
                             keep_analysis=workers == 1 and scheduler is None,
                             out=out_path, note=lambda line: typer.echo(line, err=True),
                             **options)
        res.problems[:0] = problems  # the option problems first, then those of the files
        if (baseline is not None or plot is not None) and len(res.records) > 1:
            res.problems.append(f"--baseline/--plot: need exactly one record; "
                                f"{len(res.records)} channels analysed (give --channel)")
        rep = None
        if lab is not None and not res.problems:
            rep = _collect(res.problems, bt.separability, res.records, res.labels,
                           healthy=healthy)
        res.raise_problems()

        if out_path is not None:
            bt.write_table(res.records, res.labels if lab is not None else None, out_path)
    if report_path is not None and rep is not None:
        _write_report(rep, report_path)
    figures = None
    if plot_path is not None:
        rec = res.records[0]
        if getattr(rec, "analysis", None) is not None:
            from gearsim.io.targets import atomic_folder
            from gearsim.viz import save_all

            with atomic_folder(plot_path) as tmp:
                written = save_all(rec.analysis.figures(units=rec.units), tmp)
            figures = [str(plot_path / p.name) for p in written]
    if json_:
        from gearsim.io.jsonout import strict_json

        doc: dict[str, Any] = {
            "records": [(r.to_dict() if hasattr(r, "to_dict") else r["record"])
                        for r in res.records],
            "labels": res.labels if lab is not None else None, "mode": res.mode,
            "resumed": res.resumed,
        }
        if rep is not None:
            doc["separability"] = rep
        if out_path is not None:
            doc["table"] = str(out_path)
        if figures is not None:
            doc["figures"] = figures
        typer.echo(strict_json(doc, indent=1))
        return
    from gearsim.signals.tiers import RecordAnalysis

    for r in res.records:
        typer.echo(r.text() if isinstance(r, RecordAnalysis) else _text_of(r["record"]))
    if rep is not None:
        typer.echo(_separability_text(rep))
    if out_path is not None:
        resumed = f"; {res.resumed} file{'s' if res.resumed != 1 else ''} resumed from " \
            f"{out_path.name}.parts" if res.resumed else ""
        typer.echo(f"table: {out_path} ({len(res.records)} rows; {res.mode}{resumed})")
    if report_path is not None and rep is not None:
        typer.echo(f"report: {report_path}")
    if plot_path is not None:
        typer.echo("figures: " + (", ".join(figures) if figures else
                                  "none (the gear tier was skipped)"))


def _label_problems(names: list[str], lab: dict, option: str, given: Any,
                    verb: str) -> list[str]:
    """At most one line: the files of ``names`` no label of ``lab`` names (by path or
    name; labels per channel count for the file), or a single class among them."""
    per = {f: {v for k, v in lab.items() if (k[0] if isinstance(k, tuple) else k)
               in (f, Path(f).name)} for f in names}
    missing = [Path(f).name for f, v in per.items() if not v]
    if missing:
        return [f"{option} = {given}: {len(missing)} of {len(names)} files {verb}: "
                + ", ".join(missing[:3]) + (", ..." if len(missing) > 3 else "")]
    classes = sorted(set().union(*per.values()))
    if len(classes) < 2:
        return [f"{option} = {given}: one class ({', '.join(classes)}) for the {len(names)} "
                "files: needs at least two classes to score separability"]
    return []


def _text_of(d: dict) -> str:
    """Text of a record dict (records from Dask workers come back as dicts)."""
    from gearsim.signals.tiers import RecordAnalysis

    r = RecordAnalysis(n_samples=d["n_samples"], fs=d["fs_hz"],
                       fs_provenance=d["fs_provenance"], speed=d["speed_hz"],
                       speed_provenance=d["speed_provenance"],
                       teeth=tuple(d["teeth"]) if d["teeth"] else None,
                       teeth_provenance=d["teeth_provenance"], tiers=d["tiers"],
                       skipped=d["skipped"], source=d["source"], units=d["units"],
                       stages=tuple(tuple(p) for p in d["stages"]) if d.get("stages")
                       else None, warnings=list(d.get("warnings", [])))
    return r.text()


def _config_kinematics(config: str) -> tuple:
    """``(teeth, stages, stage, speed)`` of the gearbox ``config`` for a measured record
    (:meth:`gearsim.model.Gearbox.measured_kinematics`)."""
    from gearsim.model import load

    try:
        kin = load(config).measured_kinematics("--config")
    except InputError as exc:
        if exc.parameter != "--config":
            raise
        raise InputError("--config", config, exc.limit) from None
    return kin.get("teeth"), kin.get("stages"), kin.get("stage"), kin["speed"]


def _one_with_baseline(path: str, baseline: Path | None, options: dict):
    """One record with a baseline (and arrays kept for --plot)."""
    from gearsim.io.measured import read_signal
    from gearsim.signals.tiers import analyze_record
    from gearsim.studies.batch import Batch, analyze_file

    if baseline is None:
        recs, probs = analyze_file(path, keep_analysis=True, **options)
        return Batch(records=recs, labels=[None] * len(recs), problems=probs)
    ch = options["channels"][0] if options["channels"] else None
    problems: list[str] = []
    with as_options({"channel": "--channel", "fs": "--fs"}):
        sig = _collect(problems, read_signal, path, channel=ch, fs=options["fs"],
                       fmt=options["fmt"])
    tach = b = bt = None
    if sig is not None and options["tacho"]:
        tach = _collect(problems, read_signal, path, channel=options["tacho"], fs=sig.fs).data
    if sig is not None:
        bs = _collect(problems, read_signal, baseline, channel=sig.channel, fs=sig.fs)
        if bs is not None:
            b = bs.data
            if abs(bs.fs - sig.fs) > 1e-9 * sig.fs:
                problems.append(f"--baseline fs = {bs.fs:g}: must equal the record's "
                                f"{sig.fs:g} Hz")
            if options["tacho"]:
                bt = _collect(problems, read_signal, baseline, channel=options["tacho"],
                              fs=sig.fs)
                bt = bt.data if bt is not None else None
    if problems:
        return Batch(problems=problems)
    rec = analyze_record(sig.data, sig.fs, speed=options["speed"], tacho=tach,
                         pulses_per_rev=options["pulses_per_rev"],
                         speed_search=options["speed_search"], teeth=options["teeth"],
                         stages=options.get("stages"),
                         speed_provenance=(options.get("provenance") or {}).get("speed"),
                         teeth_provenance=(options.get("provenance") or {}).get("teeth"),
                         settings=options["settings"], baseline=b, baseline_tacho=bt,
                         fs_provenance="file" if sig.fs_source == "file" else "given",
                         source={"file": sig.path, "channel": sig.channel,
                                 "baseline": str(baseline)}, units=sig.units)
    return Batch(records=[rec], labels=[None])


def compare(
    simulated: Annotated[Path, typer.Argument(help="simulated record (e.g. gearsim NetCDF)")],
    measured: Annotated[Path, typer.Argument(help="measured record")],
    shaft_rpm: Annotated[float | None, typer.Option(
        help="speed of the faulty gear's shaft in SIMULATED [rpm] (default: a gearsim "
             "SIMULATED's reference shaft, with --teeth its gear's); MEASURED's too unless "
             "--shaft-rpm-meas or --speed-search-meas")] = None,
    teeth: Annotated[int | None, typer.Option(help="teeth of the faulty gear")] = None,
    shaft_rpm_meas: Annotated[float | None, typer.Option(
        help="speed of that shaft in MEASURED [rpm] (default: SIMULATED's, checked "
             "against MEASURED's mesh line)")] = None,
    speed_search_meas: Annotated[str | None, typer.Option(
        help="estimate that shaft's speed from MEASURED within LO,HI [Hz, or with a unit: "
             "1200,2400rpm], as analyze --speed-search")] = None,
    channel_sim: Annotated[str | None, typer.Option(help="channel of the simulated file")] = None,
    channel_meas: Annotated[str | None, typer.Option(help="channel of the measured file")] = None,
    fs_sim: Annotated[float | None, typer.Option(help="fs of the simulated file [Hz]")] = None,
    fs_meas: Annotated[float | None, typer.Option(help="fs of the measured file [Hz]")] = None,
    max_order: Annotated[int, typer.Option(help="mesh harmonics 1..N (seed: 2)")] = 2,
    sidebands: Annotated[int, typer.Option(help="sidebands per side")] = 6,
    window: Annotated[str, typer.Option(help="hann, flattop or boxcar")] = "hann",
    normalize: Annotated[str, typer.Option(
        help="'mesh': amplitudes relative to n f_m of the same signal (a line above the "
             "noise floor); 'none': absolute")] = "mesh",
    plot: Annotated[str | None, typer.Option(help="figure file (.png, .pdf, .svg)")] = None,
    json_: Annotated[bool, typer.Option("--json", help="print the JSON table")] = False,
) -> None:
    """Sideband amplitudes near n f_m, simulated versus measured, with % errors (seed Table 2)."""
    from gearsim.io.jsonout import strict_json
    from gearsim.io.measured import read_signal
    from gearsim.signals import speed as sp
    from gearsim.signals.compare import compare_sidebands
    from gearsim.studies.batch import part_of, problems_error
    from gearsim.viz import check_plot_file, save
    from gearsim.viz.signals import plot_comparison

    if plot is not None:  # every output target is checked before any work
        plot = check_plot_file(plot, "--plot")
    if (shaft_rpm is None) != (teeth is None):
        raise InputError("--shaft-rpm/--teeth", "one of them", "give both (the faulty gear's "
                         "shaft speed and teeth), or neither to take a gearsim result's")
    if shaft_rpm is not None:
        _rpm("--shaft-rpm", shaft_rpm)
    if shaft_rpm_meas is not None and speed_search_meas is not None:
        raise InputError("--shaft-rpm-meas/--speed-search-meas", "both", "give at most one "
                         "source of MEASURED's speed")
    if shaft_rpm_meas is not None:
        _rpm("--shaft-rpm-meas", shaft_rpm_meas)
    problems: list[str] = []
    search = _speed_search(speed_search_meas, problems, "--speed-search-meas", fs=fs_meas
                           if fs_meas is not None and 0 < fs_meas < float("inf") else None)
    if problems:
        raise problems_error(problems)
    if teeth is not None and teeth < 1:
        raise InputError("--teeth", teeth, "must be an integer >= 1")
    if not 1 <= max_order <= MAX_ORDER:
        raise InputError("--max-order", max_order, f"must be 1 to {MAX_ORDER}")
    s = read_signal(simulated, channel=channel_sim, fs=fs_sim)
    m = read_signal(measured, channel=channel_meas, fs=fs_meas)
    given = shaft_rpm is not None
    if not given:  # the result's reference shaft and its gear, as analyze takes them
        own = part_of(s.channel, s.metadata)
        if not (own["rpm"] and own["teeth"]):
            raise InputError("--shaft-rpm/--teeth", "neither", f"give both: {s.path} "
                             "carries no speed and teeth (not a gearsim result)")
        shaft_rpm, teeth = own["rpm"], own["teeth"][0]
    f_r = f_meas = shaft_rpm / 60.0
    meas_prov = "given"
    if shaft_rpm_meas is not None:
        f_meas = shaft_rpm_meas / 60.0
    elif search is not None:  # the constant-speed estimate, as analyze --speed-search
        est = sp.estimate_constant_speed(
            m.data, m.fs, search=sp.check_speed_search(m.data.size, m.fs, search,
                                                       name="--speed-search-meas"))
        if est.confidence < sp.MIN_CONFIDENCE:
            raise InputError("--speed-search-meas", speed_search_meas, f"the estimate "
                             f"{est.frequency:.6g} Hz has confidence {est.confidence:.2f} < "
                             f"{sp.MIN_CONFIDENCE}: narrow it or give --shaft-rpm-meas")
        f_meas, meas_prov = est.frequency, "estimate"
    else:  # MEASURED at SIMULATED's speed: refused where its mesh line says otherwise
        meas_prov = "simulated"
        try:
            warn = sp.check_given_speed(m.data, m.fs, f_r, order=teeth)
        except InputError:
            warn = None  # no line to check against: the mesh-line test below decides
        if warn:
            raise InputError("--shaft-rpm-meas", "not given", f"MEASURED read at SIMULATED's "
                             f"speed: {warn}: give --shaft-rpm-meas or --speed-search-meas")
    try:
        c = compare_sidebands(
            s.data, s.fs, m.data, m.fs, mesh_frequency=f_r * teeth, shaft_frequency=f_r,
            measured_shaft_frequency=f_meas, orders=tuple(range(1, max_order + 1)),
            n_sidebands=sidebands, window=window, normalize=normalize, shaft="shaft1",
        )
    except InputError as exc:
        if not exc.parameter.endswith("mesh line"):
            raise
        raise InputError(exc.parameter, exc.value, exc.limit + (
            " (--shaft-rpm is SIMULATED's speed; MEASURED's is --shaft-rpm-meas)"
            if exc.parameter[0] == "s" else " (give --shaft-rpm-meas or --speed-search-meas)"
        )) from None
    d = c.to_dict() | {
        "teeth": teeth, "speed_teeth_provenance": "given" if given else "file",
        "simulated": {"file": s.path, "channel": s.channel, "fs_hz": s.fs,
                      "shaft_frequency_hz": f_r, "mesh_frequency_hz": f_r * teeth},
        "measured": {"file": m.path, "channel": m.channel, "fs_hz": m.fs,
                     "shaft_frequency_hz": f_meas, "mesh_frequency_hz": f_meas * teeth,
                     "speed_provenance": meas_prov},
    }
    if plot is not None:
        d["figure"] = str(save(plot_comparison(c), plot, parameter="--plot"))
    if json_:
        typer.echo(strict_json(d, indent=1))
        return
    typer.echo(f"sidebands n f_m +- k f_r, f_m = {f_r * teeth:.6g} Hz, f_r = {f_r:.5g} Hz"
               f"{'' if given else ' (file)'}; measured f_m = {f_meas * teeth:.6g} Hz, f_r = "
               f"{f_meas:.5g} Hz ({meas_prov}); normalize = {normalize}; error = |sim - meas| "
               "/ meas")
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
