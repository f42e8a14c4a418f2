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

The seed does not state the crack size. The reference depth is 6 mm at 45 deg from the
30 deg tangent point, about 2/3 of the deepest crack whose tip stays on the cracked side
of the tooth centre line (9.28 mm); the sensitivity covers 1 to 9 mm.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from gearsim.errors import InputError, require
from gearsim.io.atomic import atomic_write

__all__ = ["ReproduceOptions", "Reproduction", "run_reproduction", "simulate_cases"]

#: Crack depths of the sensitivity study [m] (the tooth model refuses depths past
#: 9.278 mm at 45 deg on the Table-1 input gear).
DEFAULT_DEPTHS = (1e-3, 2e-3, 4e-3, 6e-3, 8e-3, 9e-3)

#: Cases of each route: (label, flank, closure).
CASES = (
    ("healthy", "none", "contact"),
    ("working", "working", "contact"),
    ("non-working", "non-working", "contact"),
    ("working-open", "working", "open"),
    ("non-working-open", "non-working", "open"),
)


@dataclass(frozen=True)
class ReproduceOptions:
    """Options of :func:`run_reproduction` (SI units).

    Parameters
    ----------
    config
        Gear train: a TOML path or built-in example name (default the seed's Table 1).
    depth
        Reference crack depth [m] of the figures and the claims table.
    depths
        Crack depths of the sensitivity study [m].
    revolutions
        Recorded duration in revolutions of the input gear (a whole number, so that the
        mesh harmonics and the sidebands fall on spectral bins).
    fe
        Also run the FE-stiffness route and the FE check of the tooth (Figure 3).
    fe_points
        Contact positions of the FE check.
    model
        Dynamic model, ``"lta"`` or ``"seed"`` (see :mod:`gearsim.dynamics`).
    """

    config: str = "idler-table1"
    depth: float = 6e-3
    depths: tuple[float, ...] = DEFAULT_DEPTHS
    revolutions: int = 32
    fe: bool = True
    fe_points: int = 11
    model: str = "lta"

    def __post_init__(self) -> None:
        require(math.isfinite(self.depth) and self.depth > 0, "depth", self.depth,
                "must be > 0 m")
        require(len(self.depths) >= 1, "depths", self.depths, "must hold at least one depth")
        for d in self.depths:
            require(math.isfinite(d) and d > 0, "depths", d, "every depth must be > 0 m")
        require(isinstance(self.revolutions, int) and self.revolutions >= 4, "revolutions",
                self.revolutions, "must be a whole number >= 4 (impacts need repeats)")
        require(self.fe_points >= 3, "fe_points", self.fe_points, "must be >= 3")
        require(self.model in ("lta", "seed"), "model", self.model, 'must be "lta" or "seed"')


@dataclass
class CaseRun:
    """One simulated and analysed case."""

    route: str
    label: str
    train: Any
    force: np.ndarray          # mesh I dynamic load [N]
    force2: np.ndarray         # mesh II dynamic load [N]
    fs: float
    analysis: Any              # gearsim.signals.Analysis of ``force``


@dataclass
class Reproduction:
    """Everything the report shows (kept in memory for the figures)."""

    options: ReproduceOptions
    train: Any
    t1: float
    f_m: float
    contact_ratio: float
    runs: dict[str, CaseRun]
    metrics: dict[str, Any]
    stiffness: dict[str, Any]
    fe_checks: dict[str, Any]
    sensitivity: list[dict[str, Any]]
    claims: list[dict[str, Any]]
    findings: dict[str, list[dict[str, Any]]]
    timings: dict[str, float]


def _variant(base, *, depth: float, flank: str, closure: str, source: str):
    """The base train with one crack of ``depth`` on ``flank`` (or none), closure, source."""
    from gearsim.stiffness.crack import Crack

    stiff = dataclasses.replace(base.stiffness, closure=closure, source=source)
    tr = dataclasses.replace(base, stiffness=stiff)
    if flank == "none":
        return tr.with_cracks(())
    cracks = base.cracks or (Crack(gear=base.gears[0].name, tooth=0, depth=depth,
                                   angle=math.radians(45.0)),)
    return tr.with_cracks(tuple(dataclasses.replace(c, flank=flank, depth=depth)
                                for c in cracks))


def simulate_cases(base, cases, settings, *, progress: Callable[[str], None] | None = None
                   ) -> dict[str, CaseRun]:
    """Simulate and analyse ``cases`` = ``{key: (route, label, train)}``.

    The recorded signal is the mesh force of mesh I (the cracked input gear's mesh);
    the analysis uses the tooth counts of the train and the input shaft frequency.
    """
    from gearsim.dynamics import simulate
    from gearsim.signals import analyze

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


def _tvms(train, flank_cases) -> dict[str, Any]:
    """Mesh-I TVMS over one input revolution for each ``label -> train``."""
    out = {}
    for label, tr in flank_cases.items():
        r = tr.mesh_stiffness(0, revolution_of=1)
        out[label] = {"theta_deg": np.degrees(r.theta1), "k": np.asarray(r.k)}
    return out


def run_reproduction(out: str | Path, options: ReproduceOptions | None = None, *,
                     progress: Callable[[str], None] | None = None) -> Reproduction:
    """Run the seed's study and write report, figures and ``claims.json`` into ``out``.

    Parameters
    ----------
    out
        Output folder (created). Files are written atomically.
    options
        :class:`ReproduceOptions`; default the full study.
    progress
        Called with a short message before each step.

    Returns
    -------
    Reproduction
        All numbers; ``out/report.html`` is the report.
    """
    from gearsim.dynamics import DynamicsSettings
    from gearsim.io.config import load
    from gearsim.studies.claims import case_metrics, claims_table, qualitative_findings
    from gearsim.studies.report import write_report

    opt = options or ReproduceOptions()
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "must be a folder (a file of that name exists)")
    say = progress or (lambda _m: None)
    timings: dict[str, float] = {}
    t_all = time.perf_counter()

    base = load(opt.config)
    require(len(base.gears) >= 2, "config", opt.config, "must define a train of >= 2 gears")
    f_r1 = base.shaft_frequency(0)
    t1 = 1.0 / f_r1
    f_m = base.mesh_frequency
    pair = base.pairs[0]
    eps = pair.transverse_contact_ratio + pair.overlap_ratio
    settings = dataclasses.replace(base.extra.get("dynamics") or DynamicsSettings(),
                                   duration=opt.revolutions * t1, model=opt.model)
    # The sideband analysis of every shaft needs 4 Hann bins per spacing of the slowest
    # shaft (gearsim.signals.analyze): refuse too short a record before any work.
    f_slow = min(base.shaft_frequency(i) for i in range(len(base.gears)))
    need = math.ceil(4.0 / f_slow * f_r1)
    require(opt.revolutions >= need, "revolutions", opt.revolutions,
            f"must be >= {need} input revolutions (4 spectral bins per {f_slow:.4g} Hz "
            "sideband spacing of the slowest shaft)")
    # Validate every crack depth before the long part (the tooth model names the limit).
    for d in sorted(set(opt.depths) | {opt.depth}):
        _variant(base, depth=d, flank="working", closure="contact",
                 source="pe").mesh_stiffness(0, revolution_of=1)
    out.mkdir(parents=True, exist_ok=True)

    routes = ["PE"] + (["FE"] if opt.fe else [])
    t0 = time.perf_counter()
    cases = {}
    for route in routes:
        for label, flank, closure in CASES:
            cases[f"{route}/{label}"] = (route, label, _variant(
                base, depth=opt.depth, flank=flank, closure=closure, source=route.lower()))
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
    stiffness = {route: _tvms(base, {label: runs[f"{route}/{label}"].train
                                     for label, _, _ in CASES}) for route in routes}
    timings["stiffness"] = time.perf_counter() - t0

    fe_checks: dict[str, Any] = {}
    if opt.fe:
        from gearsim.fem.check import fe_check

        t0 = time.perf_counter()
        for crack in ("none", "working", "non-working"):
            say(f"FE check of the input tooth, crack {crack}")
            tr = _variant(base, depth=opt.depth, flank="working", closure="contact",
                          source="pe")
            fe_checks[crack] = fe_check(tr, tr.gears[0].name, crack=crack,
                                        points=opt.fe_points)
        timings["fe_check"] = time.perf_counter() - t0

    say("crack-depth sensitivity")
    t0 = time.perf_counter()
    sensitivity = _sensitivity(base, opt, settings, runs["PE/healthy"], eps, say)
    timings["sensitivity"] = time.perf_counter() - t0

    per_route = {k: v for k, v in metrics.items()}
    claims = claims_table(per_route, t1=t1, depth=opt.depth)
    findings = {route: qualitative_findings(metrics, t1=t1, route=route) for route in routes}
    rep = Reproduction(options=opt, train=base, t1=t1, f_m=f_m, contact_ratio=eps, runs=runs,
                       metrics=metrics, stiffness=stiffness, fe_checks=fe_checks,
                       sensitivity=sensitivity, claims=claims, findings=findings,
                       timings=timings)

    say("writing results")
    _write_loads(rep, out / "dynamic_load.nc")
    say("figures")
    t0 = time.perf_counter()
    from gearsim.viz.reproduce import plot_all

    figures = plot_all(rep, out / "figures")
    timings["figures"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_all
    _write_claims(rep, out / "claims.json")
    write_report(rep, figures, out / "report.html")
    return rep


def _sensitivity(base, opt: ReproduceOptions, settings, healthy: CaseRun, eps: float,
                 say: Callable[[str], None]) -> list[dict[str, Any]]:
    """Claims measures and TVMS drop versus crack depth (PE route)."""
    from gearsim.studies.claims import case_metrics

    k_h = base.with_cracks(()).mesh_stiffness(0, revolution_of=1).k
    rows = []
    variants = (("working", "working", "contact"), ("non-working", "non-working", "contact"),
                ("open", "working", "open"))
    for d in opt.depths:
        cases = {}
        for label, flank, closure in variants:
            tr = _variant(base, depth=d, flank=flank, closure=closure, source="pe")
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


def _write_loads(rep: Reproduction, path: Path) -> None:
    """Mesh forces of every case as one NetCDF file (dims case, time)."""
    import xarray as xr

    import gearsim

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
               "gearsim_version": gearsim.__version__},
    )
    atomic_write(path, lambda p: ds.to_netcdf(p, engine="h5netcdf"))


def claims_document(rep: Reproduction) -> dict[str, Any]:
    """The JSON content of ``claims.json``."""
    import gearsim

    c = rep.train.cracks[0] if rep.train.cracks else None
    return {
        "gearsim_version": gearsim.__version__,
        "system": rep.train.name,
        "seed": "Shi, Li & Zhou, Actuators 14 (2025) 292, doi:10.3390/act14060292",
        "crack": {"gear": c.gear if c else rep.train.gears[0].name,
                  "tooth": c.tooth if c else 0,
                  "depth_m": rep.options.depth,
                  "angle_deg": math.degrees(c.angle) if c else 45.0,
                  "profile": c.profile if c else "uniform"},
        "T1_s": rep.t1, "mesh_frequency_hz": rep.f_m, "total_contact_ratio": rep.contact_ratio,
        "options": dataclasses.asdict(rep.options),
        "claims": rep.claims,
        "findings": rep.findings,
        "cases": {k: m.to_dict() for k, m in rep.metrics.items()},
        "fe_check": {k: v.differences() for k, v in rep.fe_checks.items()},
        "sensitivity": rep.sensitivity,
        "timings_s": rep.timings,
    }


def _write_claims(rep: Reproduction, path: Path) -> None:
    from gearsim.io.jsonout import strict_json

    text = strict_json(claims_document(rep))
    atomic_write(path, lambda p: p.write_text(text))
