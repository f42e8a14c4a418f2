"""``gearsim reproduce``: the seed's study on the built-in Table-1 idler train.

Shi, Li & Zhou (2025) simulate the helical idler train of their Table 1 healthy, with a
root crack on the working flank and with one on the non-working flank of an input-gear
tooth, and describe the dynamic load of the input mesh in the time domain (Figure 5),
the spectrum (Figure 6), zooms around ``n f_m`` (Figure 7) and the STFT (Figure 8),
after checking their stiffness against FE (Figure 3). This module runs the same cases
through gearsim:

* routes: ``PE`` (potential-energy tooth compliance) and, unless disabled, ``FE``
  (tooth compliance from the finite-element model, :mod:`gearsim.fem.tables`: the
  seed's rigid-flexible route);
* cases per route: healthy; working-flank and non-working-flank crack with the
  ``contact`` closure model; the same with the ``open`` closure model (as printed in
  the seed, blind to the flank);
* the FE gear pair in contact (:mod:`gearsim.fem.pair`) against the PE mesh stiffness
  on the transverse section of mesh I, healthy and with the working and the closed
  non-working crack (seed Figure 3);
* the crack depth sensitivity (PE, both flanks and closures) over several depths;
* the fault magnitudes: every fault class of :mod:`gearsim.model.variants` (cracks,
  spall, pitting, chipped and broken tooth, pitch error, eccentricity) at several
  severities, each against the healthy train on the same contact-mesh model, and
  whether it reaches the seed's impact amplitude (about 200 % of healthy) and RMS rise
  (132 %);
* the claims table and the qualitative findings (:mod:`gearsim.studies.claims`);
* figures (:mod:`gearsim.viz.reproduce`), ``claims.json``, ``dynamic_load.nc`` and a
  self-contained ``report.html`` (:mod:`gearsim.studies.report`).

:func:`compute_reproduction` computes everything into a
:class:`~gearsim.studies.reproduction.Reproduction` (no files);
:func:`write_reproduction` writes the files; :func:`run_reproduction` does both.

Before any work, :func:`run_reproduction` checks the output folder (a new one, an
empty one or an earlier output of ``reproduce``: it is replaced as a whole) and
:func:`compute_reproduction` the options, including the cost of the whole study
(:func:`gearsim.dynamics.simulate.check_cost` per case, and at most
:data:`gearsim.dynamics.simulate.MAX_STEPS` integration steps over all cases, unless
forced). The files are written into a temporary folder beside the output folder and
swapped in at the end (:func:`gearsim.io.targets.atomic_folder`): a run killed at any
point leaves the old folder whole or the new one whole. The FE cache
(``$GEARSIM_CACHE``) is not part of the output folder.

The seed does not state the crack size. The reference depth is 6 mm at 45 deg from the
30 deg tangent point, about 2/3 of the deepest crack whose tip stays on the cracked side
of the tooth centre line (9.28 mm); the sensitivity covers 1 to 9 mm.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from gearsim._version import __version__
from gearsim.dynamics import DynamicsSettings, simulate
from gearsim.dynamics.simulate import (
    FORCE_ENV,
    MAX_STEPS,
    MEMORY_FRACTION,
    check_cost,
    cost_bounds_lifted,
    physical_memory,
)
from gearsim.errors import InputError, require
from gearsim.fem.check import MAX_POINTS, fe_check
from gearsim.io.atomic import atomic_write
from gearsim.io.jsonout import strict_json
from gearsim.io.results import write_results
from gearsim.io.targets import atomic_folder, check_output_folder
from gearsim.model import load
from gearsim.model.variants import FAULT_CLASSES, fault_variant
from gearsim.signals import analyze
from gearsim.signals.settings import AnalysisSettings
from gearsim.studies.claims import case_metrics, claims_table, qualitative_findings
from gearsim.studies.fe_pair_check import fe_pair_check
from gearsim.studies.report import write_report
from gearsim.studies.reproduction import (
    DEFAULT_DEPTHS,
    CaseRun,
    ReproduceOptions,
    Reproduction,
)
from gearsim.system import GearTrain
from gearsim.viz import save_all
from gearsim.viz.reproduce import CAPTIONS

__all__ = ["DEFAULT_DEPTHS", "OUTPUT_NAMES", "ReproduceOptions", "Reproduction",
           "check_output", "compute_reproduction", "fault_magnitudes", "run_reproduction",
           "simulate_cases", "write_reproduction"]

#: Cases of each route: (label, flank, closure).
CASES = (
    ("healthy", "none", "contact"),
    ("working", "working", "contact"),
    ("non-working", "non-working", "contact"),
    ("working-open", "working", "open"),
    ("non-working-open", "non-working", "open"),
)
#: Cases of the crack-depth sensitivity, per depth (label, flank, closure).
SENSITIVITY = (("working", "working", "contact"), ("non-working", "non-working", "contact"),
               ("open", "working", "open"))
#: Entries of an output folder; an existing folder may hold only these.
OUTPUT_NAMES = frozenset({"report.html", "claims.json", "dynamic_load.nc", "figures"})
#: Highest mesh harmonic of the analysis of every case (the default ``orders``): the
#: sampling rate must keep it free of aliasing.
HARMONICS = max(AnalysisSettings().orders)


def check_output(out: str | Path, parameter: str = "--out") -> Path:
    """Check the output folder before any work.

    Parameters
    ----------
    out : str or Path
        The output folder: a new folder, an empty one or an earlier output of
        ``reproduce`` (it is replaced as a whole, see :func:`write_reproduction`).
    parameter : str
        Name of the option, for the message.

    Returns
    -------
    Path

    Raises
    ------
    InputError
        An empty path, a file, the working folder, a folder holding entries other than
        :data:`OUTPUT_NAMES`, or one that cannot be written.
    """
    return check_output_folder(out, parameter, owned=OUTPUT_NAMES.__contains__)


def simulate_cases(base: GearTrain, cases: dict[str, tuple[str, str, GearTrain]],
                   settings: DynamicsSettings, *,
                   progress: Callable[[str], None] | None = None,
                   force: bool | None = None) -> dict[str, CaseRun]:
    """Simulate and analyse ``cases`` = ``{key: (route, label, train)}``.

    The recorded signal is the mesh force of mesh I (the cracked input gear's mesh);
    the analysis uses the tooth counts of the train and the input shaft frequency.

    Parameters
    ----------
    base : GearTrain
        The base train (tooth counts and input shaft frequency of the analysis).
    cases : dict
        Key -> (route, label, train variant).
    settings : DynamicsSettings
        Simulation settings, the same for every case.
    progress : callable, optional
        Called with a short message before each case.
    force : bool, optional
        Lift the cost bounds of :func:`gearsim.dynamics.simulate.check_cost`.

    Returns
    -------
    dict
        Key -> :class:`CaseRun`.
    """
    teeth = [g.teeth for g in base.gears]
    f_r1 = base.shaft_frequency(0)
    out = {}
    for key, (route, label, train) in cases.items():
        if progress:
            progress(f"simulating {key}")
        ds = simulate(train, settings, harmonics=HARMONICS, force=force)
        x = np.asarray(ds["mesh_force_1"].values, dtype=np.float64)
        x2 = np.asarray(ds["mesh_force_2"].values, dtype=np.float64) if "mesh_force_2" in ds \
            else np.zeros_like(x)
        fs = float(ds.attrs["fs"])
        a = analyze(x, fs, teeth=teeth, shaft_frequency=f_r1)
        out[key] = CaseRun(route=route, label=label, train=train, force=x, force2=x2, fs=fs,
                           analysis=a)
    return out


def _tvms(flank_cases: dict[str, GearTrain]) -> dict[str, Any]:
    """Mesh-I TVMS over one input revolution for each ``label -> train``."""
    out = {}
    for label, tr in flank_cases.items():
        r = tr.mesh_stiffness(0, revolution_of=1)
        out[label] = {"theta_deg": np.degrees(r.theta1), "k": np.asarray(r.k)}
    return out


def _check_cost(base: GearTrain, settings: DynamicsSettings, opt: ReproduceOptions,
                n_cases: int, force: bool | None) -> None:
    """Refuse a study whose simulations would take too long or too much memory."""
    try:  # the checks that always apply (duration, aliasing), and the estimate
        cost = check_cost(base, settings, harmonics=HARMONICS, force=True)
    except InputError as exc:
        if exc.parameter == "dynamics.duration":
            raise InputError("revolutions", opt.revolutions, exc.limit) from None
        raise
    if cost_bounds_lifted(force):
        return
    override = f"or override with --force ({FORCE_ENV}=1)"
    total = cost.steps * n_cases
    if total > MAX_STEPS:
        raise InputError("revolutions", opt.revolutions,
                         f"the study runs {n_cases} simulations of {cost.steps:.3g} "
                         f"integration steps each ({total:.3g} in all), above the limit of "
                         f"{MAX_STEPS:.0e} (hours of computing): fewer --revolutions or "
                         f"--depths, {override}")
    # one case's arrays at a time, plus the kept mesh forces of every case
    memory = cost.memory + n_cases * cost.samples * 2 * 8 * 4
    ram = physical_memory()
    if ram is not None and memory > MEMORY_FRACTION * ram:
        raise InputError("revolutions", opt.revolutions,
                         f"the study needs about {memory / 1e9:.3g} GB of memory, above "
                         f"half of this machine's {ram / 1e9:.3g} GB: fewer --revolutions, "
                         f"{override}")


def compute_reproduction(options: ReproduceOptions | None = None, *,
                         progress: Callable[[str], None] | None = None,
                         force: bool | None = None) -> Reproduction:
    """Run the seed's study and return every number of the report (no files written).

    Parameters
    ----------
    options : ReproduceOptions, optional
        Default the full study.
    progress : callable, optional
        Called with a short message before each step.
    force : bool, optional
        Lift the bounds on the cost (integration steps over all cases, memory); default
        the environment variable ``GEARSIM_FORCE``.

    Returns
    -------
    Reproduction

    Raises
    ------
    InputError
        Before any simulation: a configuration that is not a parallel-axis train, too few revolutions
        for the sideband analysis, a crack depth that does not fit the tooth, too many
        FE points, a sampling rate that aliases the analysed mesh harmonics, a study
        above the cost bounds.
    """
    opt = options or ReproduceOptions()
    say = progress or (lambda _m: None)
    timings: dict[str, float] = {}
    t_all = time.perf_counter()

    gb = load(opt.config)
    base = gb.gears_only("config", opt.config, "the seed's study (e.g. idler-table1)")
    require(len(base.gears) >= 2, "config", opt.config, "must define a train of >= 2 gears")
    f_r1 = base.shaft_frequency(0)
    t1 = 1.0 / f_r1
    f_m = base.mesh_frequency
    pair = base.pairs[0]
    eps = pair.transverse_contact_ratio + pair.overlap_ratio
    try:
        settings = replace(gb.dynamics, duration=opt.revolutions * t1, model=opt.model)
    except InputError as exc:
        if exc.parameter != "dynamics.duration":
            raise
        raise InputError("revolutions", opt.revolutions,
                         f"gives {opt.revolutions * t1:.4g} s per case; the duration {exc.limit}"
                         ) from None
    # The sideband analysis of every shaft needs 4 Hann bins per spacing of the slowest
    # shaft (gearsim.signals.analysis): refuse too short a record before any work.
    f_slow = min(base.shaft_frequency(i) for i in range(len(base.gears)))
    need = math.ceil(4.0 / f_slow * f_r1)
    require(opt.revolutions >= need, "revolutions", opt.revolutions,
            f"must be >= {need} input revolutions (4 spectral bins per {f_slow:.4g} Hz "
            "sideband spacing of the slowest shaft)")
    # Every crack variant is made (and so checked) before the long part; a depth that
    # does not fit is reported under the option that gave it.
    for name, values in (("depth", (opt.depth,)), ("depths", opt.depths)):
        for d in values:
            try:
                base.with_crack("working", depth=d)
            except InputError as exc:
                raise InputError(name, f"{d * 1e3:.6g} mm", exc.limit) from None
    if opt.fe:
        require(opt.fe_points <= MAX_POINTS, "fe_points", opt.fe_points,
                f"must be <= {MAX_POINTS} (each point is one FE solve)")

    routes = ["PE"] + (["FE"] if opt.fe else [])
    n_faults = (len(FAULT_CLASSES) - 1) * len(opt.fault_severities) + bool(opt.fault_severities)
    _check_cost(base, settings, opt, len(routes) * len(CASES)
                + len(SENSITIVITY) * len(opt.depths) + n_faults, force)
    t0 = time.perf_counter()
    cases = {}
    for route in routes:
        for label, flank, closure in CASES:
            cases[f"{route}/{label}"] = (route, label, base.with_crack(
                flank, depth=opt.depth, closure=closure, source=route.lower()))
    runs = simulate_cases(base, cases, settings, progress=say, force=force)
    timings["cases"] = time.perf_counter() - t0

    metrics = {}
    for key, run in runs.items():
        if run.label == "healthy":
            continue
        h = runs[f"{run.route}/healthy"]
        metrics[key] = case_metrics(run.label, run.force, run.analysis, h.force, h.analysis,
                                    contact_ratio=eps)

    say("stiffness curves")
    t0 = time.perf_counter()
    stiffness = {route: _tvms({label: runs[f"{route}/{label}"].train
                               for label, _, _ in CASES}) for route in routes}
    timings["stiffness"] = time.perf_counter() - t0

    fe_checks: dict[str, Any] = {}
    fe_pair: dict[str, Any] = {}
    if opt.fe:
        t0 = time.perf_counter()
        for crack in ("none", "working", "non-working"):
            say(f"FE check of the input tooth, crack {crack}")
            tr = base.with_crack("working", depth=opt.depth, closure="contact", source="pe")
            fe_checks[crack] = fe_check(tr, tr.gears[0].name, crack=crack,
                                        points=opt.fe_points)
        timings["fe_check"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        for crack in ("none", "working", "non-working"):
            say(f"FE gear pair of mesh I against the PE stiffness, crack {crack}")
            fe_pair[crack] = fe_pair_check(base, 0, crack=crack, depth=opt.depth)
        timings["fe_pair"] = time.perf_counter() - t0

    say("crack-depth sensitivity")
    t0 = time.perf_counter()
    sensitivity = _sensitivity(base, opt, settings, runs["PE/healthy"], eps, say, force)
    timings["sensitivity"] = time.perf_counter() - t0

    faults: list[dict[str, Any]] = []
    if opt.fault_severities:
        say("fault magnitudes")
        t0 = time.perf_counter()
        faults = fault_magnitudes(replace(gb, dynamics=settings), opt.fault_severities,
                                  eps, progress=say, force=force)
        timings["fault_magnitudes"] = time.perf_counter() - t0

    claims = claims_table(metrics, t1=t1, depth=opt.depth)
    findings = {route: qualitative_findings(metrics, t1=t1, route=route) for route in routes}
    timings["compute"] = time.perf_counter() - t_all
    return Reproduction(options=opt, train=base, t1=t1, f_m=f_m, contact_ratio=eps, runs=runs,
                        metrics=metrics, stiffness=stiffness, fe_checks=fe_checks,
                        sensitivity=sensitivity, claims=claims, findings=findings,
                        timings=timings, fault_magnitudes=faults, fe_pair=fe_pair)


def write_reproduction(rep: Reproduction, out: str | Path, *,
                       progress: Callable[[str], None] | None = None) -> Path:
    """Write ``dynamic_load.nc``, ``figures/``, ``claims.json`` and ``report.html``.

    Everything is written into a temporary folder beside ``out`` (``.NAME.*.tmp``),
    which then replaces ``out`` in one step (:func:`gearsim.io.targets.atomic_folder`):
    a run killed while writing leaves an earlier ``out`` whole and unchanged. Entries of
    an existing ``out`` other than :data:`OUTPUT_NAMES` are carried over (hard links);
    :func:`run_reproduction` refuses such a folder before any work.

    Parameters
    ----------
    rep : Reproduction
        The result of :func:`compute_reproduction`.
    out : str or Path
        Output folder (created, or replaced as a whole).
    progress : callable, optional
        Called with a short message before each step.

    Returns
    -------
    Path
        The report, ``out/report.html``.
    """
    say = progress or (lambda _m: None)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "must be a folder (a file of that name exists)")
    with atomic_folder(out, keep=lambda name: name not in OUTPUT_NAMES) as tmp:
        say("writing results")
        _write_loads(rep, tmp / "dynamic_load.nc")
        say("figures")
        t0 = time.perf_counter()
        paths = save_all(rep.plot(), tmp / "figures")
        figures = [{"name": p.stem, "path": p, "caption": CAPTIONS[p.stem]} for p in paths]
        rep.timings["figures"] = time.perf_counter() - t0
        _write_claims(rep, tmp / "claims.json")
        write_report(rep, figures, tmp / "report.html")
    return out / "report.html"


def run_reproduction(out: str | Path, options: ReproduceOptions | None = None, *,
                     progress: Callable[[str], None] | None = None,
                     force: bool | None = None) -> Reproduction:
    """Run the seed's study and write report, figures and ``claims.json`` into ``out``.

    Parameters
    ----------
    out : str or Path
        Output folder: new, empty, or an earlier output of ``reproduce`` (checked
        before any work by :func:`check_output`; replaced as a whole at the end, see
        :func:`write_reproduction`).
    options : ReproduceOptions, optional
        Default the full study.
    progress : callable, optional
        Called with a short message before each step.
    force : bool, optional
        Lift the cost bounds (see :func:`compute_reproduction`).

    Returns
    -------
    Reproduction
        All numbers; ``out/report.html`` is the report.

    Raises
    ------
    InputError
        A bad output folder or bad options, before any work.
    """
    out = check_output(out)
    t0 = time.perf_counter()
    rep = compute_reproduction(options, progress=progress, force=force)
    rep.timings["total"] = time.perf_counter() - t0  # written before the files, as before
    write_reproduction(rep, out, progress=progress)
    return rep


def _sensitivity(base: GearTrain, opt: ReproduceOptions, settings: DynamicsSettings,
                 healthy: CaseRun, eps: float, say: Callable[[str], None],
                 force: bool | None = None) -> list[dict[str, Any]]:
    """Claims measures and TVMS drop versus crack depth (PE route: the cracked trains
    against the healthy PE case ``healthy``, simulation and stiffness alike)."""
    k_h = healthy.train.mesh_stiffness(0, revolution_of=1).k
    rows = []
    variants = SENSITIVITY
    for d in opt.depths:
        cases = {}
        for label, flank, closure in variants:
            tr = base.with_crack(flank, depth=d, closure=closure, source="pe")
            cases[f"{label}@{d * 1e3:g}mm"] = ("PE", label, tr)
        runs = simulate_cases(base, cases, settings, progress=say, force=force)
        for (label, _, _), run in zip(variants, runs.values(), strict=True):
            m = case_metrics(label, run.force, run.analysis, healthy.force, healthy.analysis,
                             contact_ratio=eps)
            k = run.train.mesh_stiffness(0, revolution_of=1).k
            rows.append({
                "depth_m": d, "case": label,
                "tvms_min_drop_percent": float(100 * (k_h.min() - k.min()) / k_h.min()),
                "tvms_max_local_drop_percent": float(100 * np.max((k_h - k) / k_h)),
                "tvms_mean_drop_percent": float(100 * (k_h.mean() - k.mean()) / k_h.mean()),
                "impact_percent": _pct(m.impact_ratio),
                "far_field_percent": _pct(m.far_field_ratio),
                "rms_percent": _pct(m.rms_ratio),
                "peak_percent": _pct(m.peak_ratio),
                "impact_period_s": _finite(m.impact_period),
                "ser_1fm": m.sideband_ser[1], "ser_2fm": m.sideband_ser[2],
                "ser_3fm": m.sideband_ser[3], "ser_4fm": m.sideband_ser[4],
                "sideband_mean_1fm_N": m.sideband_mean[1],
                "sideband_mean_2fm_N": m.sideband_mean[2],
            })
    return rows


def _fault_size(train: GearTrain, runout: float) -> str:
    """Short description of the one fault of a variant (SI values shown in mm / um)."""
    if train.cracks:
        c = train.cracks[0]
        return f"crack {c.depth * 1e3:.3g} mm, {c.flank} flank"
    if train.faults:
        f = train.faults[0]
        if f.kind == "spall":
            return (f"spall {f.length * 1e3:.3g} x {f.width * 1e3:.3g} mm, "
                    f"{f.depth * 1e3:.3g} mm deep")
        if f.kind == "pitting":
            return f"pits over {100 * f.area_fraction:.3g} % of the dedendum band"
        if f.kind == "chip":
            return f"chip {f.length * 1e3:.3g} mm x {f.width * 1e3:.3g} mm"
        if f.kind == "broken":
            w = train.gears[0].face_width if f.width is None else f.width
            return f"broken over {w * 1e3:.3g} mm of the face"
    for m in train.modifications:
        if any(m.pitch_errors):
            return f"pitch error {max(m.pitch_errors) * 1e6:.3g} um on one tooth"
    if runout > 0:
        return f"runout {runout * 1e6:.3g} um"
    return "healthy"


def fault_magnitudes(gearbox, severities: tuple[float, ...], contact_ratio: float, *,
                     progress: Callable[[str], None] | None = None,
                     force: bool | None = None) -> list[dict[str, Any]]:
    """Impact amplitude and RMS of every fault class against healthy, as the claims.

    Each class of :data:`gearsim.model.variants.FAULT_CLASSES` at each severity
    (:func:`gearsim.model.variants.fault_variant`: tooth 0 of the input gear) is
    simulated with ``gearbox.dynamics`` and measured against the healthy variant (on the
    same contact-mesh model) with :func:`gearsim.studies.claims.case_metrics`: the
    impact amplitude near the damaged tooth's engagement and the RMS of the dynamic load
    of mesh I, in per cent of healthy. ``reaches_impact``: at least the lower of the
    seed's two impact amplitudes (non-working flank, 203.1 %; working 209.8 %);
    ``reaches_rms``: at least the seed's RMS rise (working flank, 132.4 %)
    (:data:`gearsim.studies.claims.SEED`).

    Parameters
    ----------
    gearbox : Gearbox
        The seed's train and the dynamics settings of the reproduction.
    severities : tuple of float
        Severities in (0, 1].
    contact_ratio : float
        Total contact ratio of mesh I (impact window).
    progress : callable, optional
        Called with a short message before each case.
    force : bool, optional
        Lift the cost bounds of the simulations.

    Returns
    -------
    list of dict
        One row per class and severity: fault, severity, size, impact_percent,
        rms_percent, peak_percent, impact_period_s, reaches_impact, reaches_rms.
    """
    from gearsim.studies.claims import SEED

    base = gearbox.train
    cases = {}
    settings = {}
    for kind in FAULT_CLASSES:
        for s in (severities if kind != "none" else (1.0,)):
            v = fault_variant(gearbox, kind, s)
            key = f"{kind}@{s:g}"
            cases[key] = ("PE", kind, v.train)
            settings[key] = v.dynamics
    runs = {}
    for key, case in cases.items():  # per-case settings (runout of the eccentricity class)
        runs.update(simulate_cases(base, {key: case}, settings[key], progress=progress,
                                   force=force))
    healthy = runs["none@1"]
    rows = []
    for key, run in runs.items():
        if run.label == "none":
            continue
        kind, sev = key.split("@")
        m = case_metrics(run.label, run.force, run.analysis, healthy.force, healthy.analysis,
                         contact_ratio=contact_ratio)
        impact, rms = _pct(m.impact_ratio), _pct(m.rms_ratio)
        rows.append({
            "fault": kind, "severity": float(sev),
            "size": _fault_size(run.train, max(settings[key].runout)),
            "impact_percent": impact, "rms_percent": rms, "peak_percent": _pct(m.peak_ratio),
            "impact_period_s": _finite(m.impact_period),
            "reaches_impact": impact is not None and impact >= 100 * min(
                SEED["impact_working"], SEED["impact_non_working"]),
            "reaches_rms": rms is not None and rms >= 100 * SEED["rms_working"],
        })
    return rows


def _pct(v: float) -> float | None:
    return float(100 * v) if math.isfinite(v) else None


def _finite(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def _write_loads(rep: Reproduction, path: Path) -> None:
    """Mesh forces of every case as one NetCDF file (dims case, time)."""
    import xarray as xr

    keys = list(rep.runs)
    first = rep.runs[keys[0]]
    t = np.arange(first.force.size) / first.fs
    ds = xr.Dataset(
        {
            "mesh_force_1": (("case", "time"), np.stack([rep.runs[k].force for k in keys]),
                             {"units": "N", "long_name": "dynamic mesh force, mesh I "
                              "(input -> idler), transverse line of action"}),
            "mesh_force_2": (("case", "time"), np.stack([rep.runs[k].force2 for k in keys]),
                             {"units": "N", "long_name": "dynamic mesh force, mesh II"}),
        },
        coords={"case": keys, "time": ("time", t, {"units": "s"})},
        attrs={"title": "gearsim reproduce: dynamic loads of the seed study",
               "crack_depth_m": rep.options.depth, "fs": first.fs,
               "gearsim_version": __version__},
    )
    write_results(ds, path)


def _write_claims(rep: Reproduction, path: Path) -> None:
    text = strict_json(rep.to_dict())
    atomic_write(path, lambda p: p.write_text(text))
