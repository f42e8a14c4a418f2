"""FE gear pair in contact: timings and the numbers quoted in docs/fem.md.

One solve at the default level (meshing and factorising included), then a mesh cycle of
N positions of the 19/48 spur pair at 100 N m against the potential-energy TVMS; with
``--full`` also the Hertz check of two discs, the mesh convergence (levels 1-3), the
torque dependence of the FE stiffness and the transverse section of the Table-1 mesh I.

Run: ``.venv/bin/python benchmarks/bench_fem_pair.py [--quick | --full] [--positions N]``.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from gearsim.fem.geometry import FlankRefinement, SectorOptions, element_size, mesh_sector
from gearsim.fem.pair import (
    DEFAULT_LEVEL,
    FEPairModel,
    fe_cylinder_contact,
    fe_pair_solve,
    pe_slice_stiffness,
)
from gearsim.fem.solve import ElasticModel
from gearsim.fem.tooth import PATCH_HALF_LENGTH, _patch, load_geometry
from gearsim.geometry.profile import ToothProfile
from gearsim.model import load
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import PotentialEnergyCompliance
from gearsim.stiffness.tooth import hertz_stiffness

TORQUE = 100.0  # N m on the 19/48 pinion (example config)


def single_solve(pair, level: int) -> None:
    print(f"== one solve, level {level}, u = 0.5 (mesh + factorise + contact) ==")
    t0 = time.perf_counter()
    r = fe_pair_solve(pair, 0.5, torque=TORQUE, level=level)
    print(f"k = {r.stiffness:.5e} N/m, TE = {r.transmission_error * 1e6:.3f} um, "
          f"dofs {r.dofs}, h_contact {r.h_contact * 1e6:.1f} um, "
          f"{time.perf_counter() - t0:.2f} s")


def cycle(pair, level: int, n: int) -> None:
    print(f"== mesh cycle, level {level}, {n} positions, {TORQUE:g} N m ==")
    t0 = time.perf_counter()
    model = FEPairModel(pair, torque=TORQUE, level=level)
    print(f"set-up (mesh both gears, factorise): {model.setup_seconds:.2f} s, dofs "
          f"{[b.model.ndofs for b in model.bodies]}, refined teeth {model.teeth}")
    u = (np.arange(n) + 0.5) / n
    pe = pe_slice_stiffness(pair, u)
    res = []
    print("   u     k_FE [N/m]   k_PE [N/m]  PE-FE %  TE [um]  pairs  share        "
          "b_FE/b_H        p_max [MPa]    root 1 / 2 [MPa]   s")
    for i, v in enumerate(u):
        r = model.solve(float(v))
        res.append(r)
        print(f"{v:6.4f} {r.stiffness:11.5e} {pe[i]:11.5e} {100 * (pe[i] / r.stiffness - 1):+7.1f}"
              f" {r.transmission_error * 1e6:8.3f}  {str(r.pair_teeth):6s} "
              f"{np.array2string(r.load_share, precision=3):12s} "
              f"{np.array2string(r.contact_half_width / r.hertz_half_width, precision=3):14s} "
              f"{np.array2string(r.peak_pressure / 1e6, precision=0):14s} "
              f"{np.array2string(r.root_stress_driver / 1e6, precision=0)} / "
              f"{np.array2string(r.root_stress_driven / 1e6, precision=0)} {r.seconds:5.2f}")
    k = np.array([r.stiffness for r in res])
    d = 100 * (pe - k) / k
    print(f"(k_PE - k_FE)/k_FE: max {d.max():+.1f} %, min {d.min():+.1f} %, mean {d.mean():+.1f} %;"
          f" mean k: FE {k.mean():.4e}, PE {pe.mean():.4e} ({100 * (pe.mean() / k.mean() - 1):+.1f} %)")
    print(f"cycle total {time.perf_counter() - t0:.1f} s, "
          f"{np.mean([r.seconds for r in res]):.2f} s per position")


def hertz() -> None:
    print("== two discs R1 20 mm, R2 30 mm, 200 kN/m: FE / Hertz ==")
    for plane in ("strain", "stress"):
        for frac in (8, 16, 32):
            b = fe_cylinder_contact(0.02, 0.03, 2e5, plane=plane).hertz_half_width
            t0 = time.perf_counter()
            r = fe_cylinder_contact(0.02, 0.03, 2e5, plane=plane, h_contact=b / frac)
            ph = r.hertz_peak_pressure * np.sqrt(np.clip(1 - (r.x / b) ** 2, 0, None))
            rms = np.sqrt(np.mean((r.pressure - ph) ** 2)) / r.hertz_peak_pressure
            print(f"{plane:6s} h = b/{frac:2d}: b {r.half_width / b - 1:+.2e}, p_max "
                  f"{r.peak_pressure / r.hertz_peak_pressure - 1:+.2e}, profile rms {rms:.3f},"
                  f" approach {r.approach * 1e6:.4f} um, {time.perf_counter() - t0:.2f} s")


def convergence(pair, levels, n: int) -> None:
    print(f"== convergence in the level, {n} positions ==")
    u = (np.arange(n) + 0.5) / n
    rows = []
    for lev in levels:
        m = FEPairModel(pair, torque=TORQUE, level=lev)
        t0 = time.perf_counter()
        rows.append([m.solve(float(v)).stiffness for v in u])
        print(f"level {lev}: h_c {m.h_contact * 1e6:5.1f} um, dofs "
              f"{sum(b.model.ndofs for b in m.bodies):7d}, set-up {m.setup_seconds:5.1f} s, "
              f"{(time.perf_counter() - t0) / n:5.2f} s per position, "
              f"k = {np.array2string(np.array(rows[-1]), precision=5)}", flush=True)
        del m
    k = np.array(rows)
    for i in range(len(levels) - 2):
        d1, d2 = k[i + 1] - k[i], k[i + 2] - k[i + 1]
        p = np.log2(np.abs(d1 / d2))
        print(f"levels {levels[i]}-{levels[i + 2]}: order {np.round(p, 2)}, changes "
              f"{np.round(100 * d1 / k[i + 1], 3)} / {np.round(100 * d2 / k[i + 2], 3)} %")
        ext = k[i + 2] + d2 / (2.0 ** np.clip(p, 0.3, None) - 1)
        print(f"  extrapolated error of level {levels[i + 1]}: "
              f"{np.round(100 * (k[i + 1] / ext - 1), 3)} %")


def torque_dependence(pair, level: int) -> None:
    print(f"== torque dependence, level {level}: k_FE, (k_PE - k_FE)/k_FE ==")
    for torque in (50.0, 100.0, 200.0, 400.0):
        m = FEPairModel(pair, torque=torque, level=level)
        out = []
        for v in (0.3125, 0.8125):
            r = m.solve(v)
            d = 100 * (pe_slice_stiffness(pair, [v])[0] / r.stiffness - 1)
            out.append(f"u {v}: {r.stiffness:.4e} ({d:+.1f} %, TE {r.transmission_error * 1e6:.2f} um)")
        print(f"{torque:5.0f} N m: " + ", ".join(out))


def _gear_compliance(gear, teeth, radii, level):
    """FE single-gear compliance matrix at the points Q of fem.tooth (cross terms)."""
    prof = ToothProfile(gear)
    pitch = 2 * math.pi / gear.teeth
    sm = mesh_sector(gear, options=SectorOptions(level=level),
                     refine=FlankRefinement(teeth=tuple(sorted(set(teeth))), sides=(1,),
                                            size=element_size(gear, level) / 4))
    model = ElasticModel(sm.p, sm.t, gear.material.youngs_modulus,
                         gear.material.poisson_ratio, plane="stress")
    fixed = model.dofs_on_facets(model.facets_on_nodes(sm.bore))
    half = PATCH_HALF_LENGTH * gear.normal_module
    loads, dirs, qs = [], [], []
    for k, r in zip(teeth, radii, strict=True):
        pt, d, q = load_geometry(prof, r)
        c, s_ = math.cos(-k * pitch), math.sin(-k * pitch)
        rot = np.array([[c, -s_], [s_, c]])
        pt, d, q = rot @ pt, rot @ d, rot @ q
        facets = _patch(model, model.facets_on_nodes(sm.parts[(k, 1, "involute")]), pt, half)

        def bell(x, y, point=pt, d=d):
            s2 = ((x - point[0]) ** 2 + (y - point[1]) ** 2) / half**2
            w = np.where(s2 < 1, (1 - s2) ** 2, 0.0)
            return d[0] * w, d[1] * w

        f = model.traction_load(facets, bell, intorder=12)
        loads.append(f / float(np.dot(d, [f[0::2].sum(), f[1::2].sum()])))
        dirs.append(d)
        qs.append(q)
    u = model.solve(np.column_stack(loads), fixed)
    vals = model.probe(np.array(qs).T) @ u
    n = len(teeth)
    return np.array([[dirs[i] @ vals[[i, n + i], j] for j in range(n)] for i in range(n)])


def decomposition(pair, level: int) -> None:
    """FE pair against FE teeth (+ cross terms) + 2D Hertz approach; PE terms."""
    print(f"== decomposition per unit face width [1e-11 m/(N/m)], level {level} ==")
    g1, g2 = pair.driver, pair.driven
    e, nu = g1.material.youngs_modulus, g1.material.poisson_ratio
    b = pair.face_width
    m = FEPairModel(pair, torque=TORQUE, level=level)
    settings = StiffnessSettings(plane="stress")
    pe_model = PotentialEnergyCompliance()
    ch = 1.0 / hertz_stiffness(g1.material, g2.material, 1.0)
    for v in (0.3125, 0.8125):
        r = m.solve(v)
        ks = [int(k) for k in r.pair_teeth]
        ls = [m.roll_position(v, k) for k in ks]
        r1 = [math.hypot(g1.base_radius, lv) for lv in ls]
        r2 = [math.hypot(g2.base_radius, pair.line_length - lv) for lv in ls]
        c1 = _gear_compliance(g1, ks, r1, level)
        c2 = _gear_compliance(g2, [-k for k in ks], r2, level)
        hz = []
        for j in range(len(ks)):
            d = 0.0
            for gear, rr in ((g1, r1[j]), (g2, r2[j])):
                p, _, q = load_geometry(ToothProfile(gear), rr)
                dist = float(np.hypot(*(p - q)))
                d += 2 / (math.pi * e) * (math.log(2 * dist / r.hertz_half_width[j]) - nu / 2)
            hz.append(d)
        c = c1 + c2 + np.diag(hz)
        f = np.linalg.solve(c, np.ones(len(ks)))
        unc = np.linalg.solve(np.diag(np.diag(c1 + c2)) + np.diag(hz), np.ones(len(ks)))
        pe1 = [pe_model.compliance(g1, np.array([[x]]), None, np.array([0.5]), settings).sum()
               for x in r1]
        pe2 = [pe_model.compliance(g2, np.array([[x]]), None, np.array([0.5]), settings).sum()
               for x in r2]
        print(f"u {v}: pairs {ks}, FE tooth diag 1 {np.round(np.diag(c1) * 1e11, 3)}, "
              f"2 {np.round(np.diag(c2) * 1e11, 3)}, cross 1/2 "
              f"{np.round((c1 - np.diag(np.diag(c1))).max() * 1e11, 3)} / "
              f"{np.round((c2 - np.diag(np.diag(c2))).max() * 1e11, 3)}; 2D Hertz "
              f"{np.round(np.array(hz) * 1e11, 3)} (PE Hertz {ch * 1e11:.3f}); PE teeth 1 "
              f"{np.round(np.array(pe1) * 1e11, 3)}, 2 {np.round(np.array(pe2) * 1e11, 3)}")
        print(f"   k/b: FE pair {r.stiffness / b:.4e}, superposition {f.sum():.4e} "
              f"({100 * (r.stiffness / b / f.sum() - 1):+.1f} %), without cross terms "
              f"{unc.sum():.4e} ({100 * (r.stiffness / b / unc.sum() - 1):+.1f} %), PE "
              f"{pe_slice_stiffness(pair, [v])[0] / b:.4e}; share FE {np.round(r.load_share, 3)}"
              f" superposition {np.round(f / f.sum(), 3)}")


def table1(level: int) -> None:
    print(f"== Table-1 mesh I, transverse section, 4876 N m, level {level} ==")
    pair = load("idler-table1").train.pairs[0]
    m = FEPairModel(pair, torque=4876.0, level=level)
    print(f"set-up {m.setup_seconds:.1f} s, dofs {[b.model.ndofs for b in m.bodies]}")
    u = (np.arange(6) + 0.5) / 6
    pe = pe_slice_stiffness(pair, u)
    for i, v in enumerate(u):
        r = m.solve(float(v))
        print(f"u {v:.4f}: k_FE {r.stiffness:.4e}, k_PE(slice) {pe[i]:.4e} "
              f"({100 * (pe[i] / r.stiffness - 1):+.1f} %), pairs {r.pair_teeth}, share "
              f"{np.round(r.load_share, 3)}, b/b_H {np.round(r.contact_half_width / r.hertz_half_width, 3)}")


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    full = "--full" in sys.argv
    n = 16
    if "--positions" in sys.argv:
        n = int(sys.argv[sys.argv.index("--positions") + 1])
    spur = load("spur-19-48").train.pairs[0]
    level = 1 if quick else DEFAULT_LEVEL
    single_solve(spur, level)
    cycle(spur, level, 8 if quick else n)
    if full:
        hertz()
        convergence(spur, (1, 2, 3), 8)
        torque_dependence(spur, DEFAULT_LEVEL)
        decomposition(spur, DEFAULT_LEVEL)
        table1(DEFAULT_LEVEL)
    if not full:
        print(f"(level {level}; --full adds Hertz, convergence, torque and Table-1 runs)")
