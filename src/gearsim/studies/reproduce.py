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
* the crack depth sensitivity (PE, both flanks and closures) over several depths;
* the claims table and the qualitative findings (:mod:`gearsim.studies.claims`);
* figures (:mod:`gearsim.viz.reproduce`), ``claims.json``, ``dynamic_load.nc`` and a
  self-contained ``report.html`` (:mod:`gearsim.studies.report`).

:func:`compute_reproduction` computes everything into a
:class:`~gearsim.studies.reproduction.Reproduction` (no files);
:func:`write_reproduction` writes the files; :func:`run_reproduction` does both.

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
from gearsim.errors import InputError, require
from gearsim.fem.check import fe_check
from gearsim.io.atomic import atomic_write
from gearsim.io.jsonout import strict_json
from gearsim.model import load
from gearsim.signals import analyze
from gearsim.studies.claims import case_metrics, claims_table, qualitative_findings
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

__all__ = ["DEFAULT_DEPTHS", "ReproduceOptions", "Reproduction", "compute_reproduction",
           "run_reproduction", "simulate_cases", "write_reproduction"]

#: Cases of each route: (label, flank, closure).
CASES = (
    ("healthy", "none", "contact"),
    ("working", "working", "contact"),
    ("non-working", "non-working", "contact"),
    ("working-open", "working", "open"),
    ("non-working-open", "non-working", "open"),
)


def simulate_cases(base: GearTrain, cases: dict[str, tuple[str, str, GearTrain]],
                   settings: DynamicsSettings, *,
                   progress: Callable[[str], None] | None = None) -> dict[str, CaseRun]:
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
        ds = simulate(train, settings)
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


def compute_reproduction(options: ReproduceOptions | None = None, *,
                         progress: Callable[[str], None] | None = None) -> Reproduction:
    """Run the seed's study and return every number of the report (no files written).

    Parameters
    ----------
    options : ReproduceOptions, optional
        Default the full study.
    progress : callable, optional
        Called with a short message before each step.

    Returns
    -------
    Reproduction

    Raises
    ------
    InputError
        Before any simulation: a configuration that is not a train, too few revolutions
        for the sideband analysis, a crack depth that does not fit the tooth.
    """
    opt = options or ReproduceOptions()
    say = progress or (lambda _m: None)
    timings: dict[str, float] = {}
    t_all = time.perf_counter()

    gb = load(opt.config)
    base = gb.train
    require(len(base.gears) >= 2, "config", opt.config, "must define a train of >= 2 gears")
    f_r1 = base.shaft_frequency(0)
    t1 = 1.0 / f_r1
    f_m = base.mesh_frequency
    pair = base.pairs[0]
    eps = pair.transverse_contact_ratio + pair.overlap_ratio
    settings = replace(gb.dynamics, duration=opt.revolutions * t1, model=opt.model)
    # The sideband analysis of every shaft needs 4 Hann bins per spacing of the slowest
    # shaft (gearsim.signals.analyze): refuse too short a record before any work.
    f_slow = min(base.shaft_frequency(i) for i in range(len(base.gears)))
    need = math.ceil(4.0 / f_slow * f_r1)
    require(opt.revolutions >= need, "revolutions", opt.revolutions,
            f"must be >= {need} input revolutions (4 spectral bins per {f_slow:.4g} Hz "
            "sideband spacing of the slowest shaft)")
    # Every crack variant is made (and so checked) before the long part.
    for d in sorted(set(opt.depths) | {opt.depth}):
        base.with_crack("working", depth=d)

    routes = ["PE"] + (["FE"] if opt.fe else [])
    t0 = time.perf_counter()
    cases = {}
    for route in routes:
        for label, flank, closure in CASES:
            cases[f"{route}/{label}"] = (route, label, base.with_crack(
                flank, depth=opt.depth, closure=closure, source=route.lower()))
    runs = simulate_cases(base, cases, settings, progress=say)
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
    if opt.fe:
        t0 = time.perf_counter()
        for crack in ("none", "working", "non-working"):
            say(f"FE check of the input tooth, crack {crack}")
            tr = base.with_crack("working", depth=opt.depth, closure="contact", source="pe")
            fe_checks[crack] = fe_check(tr, tr.gears[0].name, crack=crack,
                                        points=opt.fe_points)
        timings["fe_check"] = time.perf_counter() - t0

    say("crack-depth sensitivity")
    t0 = time.perf_counter()
    sensitivity = _sensitivity(base, opt, settings, runs["PE/healthy"], eps, say)
    timings["sensitivity"] = time.perf_counter() - t0

    claims = claims_table(metrics, t1=t1, depth=opt.depth)
    findings = {route: qualitative_findings(metrics, t1=t1, route=route) for route in routes}
    timings["compute"] = time.perf_counter() - t_all
    return Reproduction(options=opt, train=base, t1=t1, f_m=f_m, contact_ratio=eps, runs=runs,
                        metrics=metrics, stiffness=stiffness, fe_checks=fe_checks,
                        sensitivity=sensitivity, claims=claims, findings=findings,
                        timings=timings)


def write_reproduction(rep: Reproduction, out: str | Path, *,
                       progress: Callable[[str], None] | None = None) -> Path:
    """Write ``dynamic_load.nc``, ``figures/``, ``claims.json`` and ``report.html``.

    Parameters
    ----------
    rep : Reproduction
        The result of :func:`compute_reproduction`.
    out : str or Path
        Output folder (created); every file is written atomically.
    progress : callable, optional
        Called with a short message before each step.

    Returns
    -------
    Path
        The report, ``out/report.html``.
    """
    say = progress or (lambda _m: None)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    say("writing results")
    _write_loads(rep, out / "dynamic_load.nc")
    say("figures")
    t0 = time.perf_counter()
    paths = save_all(rep.plot(), out / "figures")
    figures = [{"name": p.stem, "path": p, "caption": CAPTIONS[p.stem]} for p in paths]
    rep.timings["figures"] = time.perf_counter() - t0
    _write_claims(rep, out / "claims.json")
    return write_report(rep, figures, out / "report.html")


def run_reproduction(out: str | Path, options: ReproduceOptions | None = None, *,
                     progress: Callable[[str], None] | None = None) -> Reproduction:
    """Run the seed's study and write report, figures and ``claims.json`` into ``out``.

    Parameters
    ----------
    out : str or Path
        Output folder (created). Files are written atomically.
    options : ReproduceOptions, optional
        Default the full study.
    progress : callable, optional
        Called with a short message before each step.

    Returns
    -------
    Reproduction
        All numbers; ``out/report.html`` is the report.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "must be a folder (a file of that name exists)")
    t0 = time.perf_counter()
    rep = compute_reproduction(options, progress=progress)
    rep.timings["total"] = time.perf_counter() - t0  # written before the files, as before
    write_reproduction(rep, out, progress=progress)
    return rep


def _sensitivity(base: GearTrain, opt: ReproduceOptions, settings: DynamicsSettings,
                 healthy: CaseRun, eps: float,
                 say: Callable[[str], None]) -> list[dict[str, Any]]:
    """Claims measures and TVMS drop versus crack depth (PE route)."""
    k_h = base.with_cracks(()).mesh_stiffness(0, revolution_of=1).k
    rows = []
    variants = (("working", "working", "contact"), ("non-working", "non-working", "contact"),
                ("open", "working", "open"))
    for d in opt.depths:
        cases = {}
        for label, flank, closure in variants:
            tr = base.with_crack(flank, depth=d, closure=closure, source="pe")
            cases[f"{label}@{d * 1e3:g}mm"] = ("PE", label, tr)
        runs = simulate_cases(base, cases, settings, progress=say)
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


def _pct(v: float) -> float | None:
    return float(100 * v) if math.isfinite(v) else None


def _finite(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


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
    atomic_write(path, lambda p: ds.to_netcdf(p, engine="h5netcdf"))


def _write_claims(rep: Reproduction, path: Path) -> None:
    text = strict_json(rep.to_dict())
    atomic_write(path, lambda p: p.write_text(text))
