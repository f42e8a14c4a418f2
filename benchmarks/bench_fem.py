"""Finer FE study (not run in CI): convergence to level 3-4, FE vs PE at level 2,
sector-boundary sensitivity, and timing. Prints the numbers quoted in docs/fem.md.

Run: ``.venv/bin/python benchmarks/bench_fem.py [--quick]``.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from gearsim.fem.cantilever import convergence_rate, solve_cantilever
from gearsim.fem.check import compare_gear, contact_radii
from gearsim.fem.geometry import SectorOptions
from gearsim.fem.tooth import fe_tooth_compliance
from gearsim.model import load


def cantilever() -> None:
    print("== cantilever L = 50 mm, H = 10 mm, plane stress, exact clamp ==")
    for order in (1, 2):
        hs = np.array([2.5e-3, 1.25e-3, 0.625e-3, 0.3125e-3])
        errs = []
        for h in hs:
            r = solve_cantilever(h=h, order=order)
            errs.append(r.error)
            print(f"P{order} h = {h * 1e3:.4f} mm: dofs {r.ndofs:6d}, error {r.error:+.3e}, "
                  f"vs alpha=1.2 beam {(r.fe / r.timoshenko_12 - 1):+.3e}")
        print(f"P{order} fitted rate {convergence_rate(hs, errs):.2f}")


def convergence(levels) -> None:
    print("== mesh convergence, healthy tooth, whole gear ==")
    for name in ("idler-table1", "spur-19-48"):
        train = load(name).train
        gear = train.gears[0]
        r = contact_radii(train, gear.name, 3)
        rows = []
        for k in levels:
            t0 = time.perf_counter()
            res = fe_tooth_compliance(gear, r, options=SectorOptions(level=k))
            rows.append(res.compliance)
            print(f"{name} level {k}: h {res.h * 1e3:.4f} mm, dofs {res.dofs:7d}, "
                  f"{time.perf_counter() - t0:6.2f} s, c = {np.array2string(res.compliance, precision=6)}")
        c = np.array(rows)
        for i in range(len(levels) - 2):
            p = np.log2(np.abs(c[i + 1] - c[i]) / np.abs(c[i + 2] - c[i + 1]))
            print(f"  observed order (levels {levels[i]}-{levels[i + 2]}): {np.round(p, 2)}")


def comparison(level: int, points: int) -> None:
    print(f"== FE vs PE, level {level}, {points} points: (k_PE - k_FE)/k_FE max/min/mean % ==")
    for name in ("idler-table1", "spur-19-48"):
        train = load(name).train
        gear = train.gears[0]
        radii = contact_radii(train, gear.name, points)
        for label, crack, side, closure in (("healthy", None, 0, "open"),
                                            ("working-open", train.cracks[0], 1, "open"),
                                            ("working-contact", train.cracks[0], 1, "contact"),
                                            ("non-working-open", train.cracks[0], -1, "open"),
                                            ("non-working-contact", train.cracks[0], -1,
                                             "contact")):
            chk = compare_gear(gear, radii, crack=crack, side=side, closure=closure,
                               options=SectorOptions(level=level), label=label)
            d = chk.differences()
            cf = chk.fe_result.closed_fraction
            print(f"{name:13s} {label:20s} {d['max']:+7.2f} {d['min']:+7.2f} {d['mean']:+7.2f}"
                  f"   FE/PE compliance {np.round(chk.fe / chk.pe, 3)}"
                  + (f" closed {np.round(cf, 2)}" if closure == "contact" and side else ""))


def sectors(level: int) -> None:
    print("== body model: whole gear vs sectors with fixed / free sides (compliance e-11) ==")
    for name in ("idler-table1", "spur-19-48"):
        train = load(name).train
        gear = train.gears[0]
        r = contact_radii(train, gear.name, 3)
        for opt in (SectorOptions(level=level), SectorOptions(level=level, n_teeth=5),
                    SectorOptions(level=level, n_teeth=5, sides="free"),
                    SectorOptions(level=level, n_teeth=11),
                    SectorOptions(level=level, n_teeth=11, sides="free")):
            c = fe_tooth_compliance(gear, r, options=opt).compliance
            lab = "whole gear" if opt.n_teeth is None else f"{opt.n_teeth} teeth, {opt.sides}"
            print(f"{name:13s} {lab:18s} {np.round(c * 1e11, 3)}")


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    cantilever()
    convergence((0, 1, 2) if quick else (0, 1, 2, 3, 4))
    comparison(1 if quick else 2, 7 if quick else 11)
    sectors(1 if quick else 2)
