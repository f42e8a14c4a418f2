"""The calibrated tooth (``stiffness.source = "calibrated"``): cost and accuracy.

Cost (default): a full revolution of the Table-1 mesh I (40 slices, 40 positions per
cycle, the train's crack) with the seed model (PE tooth, Yang-Lin contact, independent
pairs) and with the calibrated model (PE tooth x FE/PE ratio x the measured crack
correction, line contact, FE body coupling) after its one-time cost, and the one-time
cost itself (FE tooth table, FE body coupling and ratio of both gears, then the crack
correction of the train's crack: FE tooth at the CRACK_GRID depths; computed in an empty
cache), printed as ratios to the seed model's time in one run.

Accuracy (``--accuracy``): transverse sections against the FE gear pair
(:func:`gearsim.studies.fe_pair_check.fe_pair_check`, FE pair level 1, 20 positions per
cycle, 4 cycles from the one before the cracked tooth enters): max / min / mean of the
window and pointwise inside the contact zones and at the zone ends (positions on a
nominal transition or where the FE pair touches outside the nominal path, tip corners),
healthy, working-flank crack and closed non-working crack, at two torques a factor 4
apart; the numbers of docs/stiffness.md section 4c. Row ``calibrated`` is the model
(tip-corner contacts under load, measured crack correction on the loaded flank); the
rows before: ``cal_path`` the calibrated table on the path of contact only
(``corner_contact = False``: the tables before the tip-corner contacts under load),
and for the cracked cases ``cal_pe_crack`` the model before the crack correction (the
PE section reduction), ``cal_before`` before both (path of contact only, PE section
reduction), ``cal_q_both`` the correction on both crack sides, ``cal_healthy_x`` the
crack correction with the healthy body's coupling beside the cracked tooth (the model
before the cracked body's coupling factors G). ``--extra`` adds the
17/60 pair with x1 = +0.3 and the 25/25 pair at 25 deg; ``--healthy`` runs the healthy
case only; ``--level N`` takes the FE pair (and the healthy FE pair of the zone
classification) at mesh level N instead of level 1.

Run: ``.venv/bin/python benchmarks/bench_calibrated.py [--accuracy] [--extra] [--healthy]
[--level N]``.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import tempfile
import time

import numpy as np

from gearsim.model import load
from gearsim.stiffness.mesh import mesh_stiffness
from gearsim.stiffness.settings import MODELS
from gearsim.studies.fe_pair_check import PE_POSITIONS, fe_pair_check
from gearsim.system.fe_pair import FE_PAIR_LEVEL
from gearsim.system.train import body_coupling, tooth_compliance

#: The calibrated curves of the accuracy rows: (tip-corner contacts, crack sides of the
#: correction or None for the model's, cracked cases only, the cracked body's coupling):
#: the model, on the path of contact only, before the crack correction (PE section
#: reduction), before both, with the correction on both crack sides, with the crack
#: correction but the healthy body's coupling (the model before the crack's coupling).
CALIBRATED = {"calibrated": (True, None, False, True), "cal_path": (False, None, False, True),
              "cal_pe_crack": (True, (), True, True), "cal_before": (False, (), True, True),
              "cal_q_both": (True, (1, -1), True, True),
              "cal_healthy_x": (True, None, True, False)}
#: Curves of the accuracy rows: the calibrated ones, the FE tooth, the PE tooth with line
#: contact and coupling, the seed model.
CURVES = (*CALIBRATED, "fe_tooth", "pe_line", "pe")
#: Share of the torque above which a tip-corner contact of the FE pair (outside the
#: nominal path of contact: no Hertz width) makes a position a "zone end" [-].
CORNER_SHARE = 1e-3


def _revolution(train, settings) -> float:
    """Seconds of one full revolution table of mesh I (best of 5)."""
    best = np.inf
    for _ in range(5):
        t0 = time.perf_counter()
        mesh_stiffness(train.pairs[0], cracks=train.mesh_cracks(0), settings=settings,
                       compliance=tooth_compliance(settings.source),
                       force=train.static_mesh_force(0), coupling=body_coupling(settings))
        best = min(best, time.perf_counter() - t0)
    return best


def cost() -> None:
    """Seed vs calibrated per revolution and the one-time cost, as ratios."""
    from gearsim.fem import calibration

    train = load("idler-table1").train
    seed = dataclasses.replace(train.stiffness, slices=40, positions_per_cycle=40,
                               **MODELS["seed"])
    cal = dataclasses.replace(seed, source="calibrated", contact="line", coupling="fe")
    pe_line = dataclasses.replace(seed, contact="line", coupling="fe")
    cal_path = dataclasses.replace(cal, corner_contact=False)
    _revolution(train, seed)  # compile the kernels
    old = os.environ.get("GEARSIM_CACHE")
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["GEARSIM_CACHE"] = tmp
        calibration._MEMO.clear()
        calibration._CRACK_MEMO.clear()
        try:
            once = {}
            crack_once = {}
            for gear in (train.pairs[0].driver, train.pairs[0].driven):
                t0, c0 = time.perf_counter(), time.process_time()
                calibration.calibration_ratio(gear, plane=cal.plane,
                                              gauss_points=cal.gauss_points)
                body_coupling(cal).cross(gear, np.array([gear.pitch_radius]),
                                         np.array([gear.pitch_radius]))
                once[gear.name] = (time.perf_counter() - t0, time.process_time() - c0)
            for tc in train.mesh_cracks(0):  # the measured crack correction of the crack
                gear = train.pairs[0].driver if tc.gear == 1 else train.pairs[0].driven
                t0, c0 = time.perf_counter(), time.process_time()
                if tc.side in calibration.CORRECTED_SIDES:
                    calibration.crack_factor_table(gear, tc.crack, tc.side,
                                                   closure=cal.closure, plane=cal.plane)
                crack_once[gear.name] = (time.perf_counter() - t0, time.process_time() - c0)
            t_seed = _revolution(train, seed)
            t_line = _revolution(train, pe_line)
            t_cal = _revolution(train, cal)
            t_path = _revolution(train, cal_path)
        finally:
            if old is None:
                os.environ.pop("GEARSIM_CACHE", None)
            else:
                os.environ["GEARSIM_CACHE"] = old
            calibration._MEMO.clear()
            calibration._CRACK_MEMO.clear()
    print("== Table-1 mesh I, full revolution, 40 slices x 40 positions per cycle ==")
    print(f"seed PE (yang-lin, no coupling):   {t_seed:8.3f} s   1.00 x")
    print(f"PE + line + FE coupling:           {t_line:8.3f} s   {t_line / t_seed:5.2f} x")
    print(f"calibrated (after one-time cost):  {t_cal:8.3f} s   {t_cal / t_seed:5.2f} x")
    print(f"calibrated, path of contact only:  {t_path:8.3f} s   {t_path / t_seed:5.2f} x")
    for name, (t, cpu) in once.items():
        print(f"one-time cost, gear {name:8s}      {t:8.3f} s   {t / t_seed:5.1f} x "
              f"(CPU {cpu:.1f} s; FE tooth table + FE coupling + ratio, level 2, empty "
              "cache)")
    for name, (t, cpu) in crack_once.items():
        print(f"crack correction, gear {name:8s}   {t:8.3f} s   {t / t_seed:5.1f} x "
              f"(CPU {cpu:.1f} s; FE tooth and its neighbours at "
              f"{len(calibration.CRACK_GRID)} crack depths, once per gear and crack family)")
    print(f"load average during the run: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


def _zones(pair, torque: float, u: np.ndarray, npc: int, level: int = FE_PAIR_LEVEL,
           plane: str = "stress") -> tuple[np.ndarray, np.ndarray]:
    """Inside-zone and double-contact flags of the positions ``u``.

    A position is a zone end when it is within half a sample spacing of a nominal
    transition (u = 0 or eps_alpha - 1) or when the healthy FE pair (mesh level
    ``level``, default 1, in the train's ``plane``, as :func:`fe_pair_check` builds it)
    carries more than :data:`CORNER_SHARE` of the torque on a tip-corner contact outside
    the nominal path of contact (extended contact under load, docs/fem.md).
    """
    from gearsim.fem.pair import FEPairModel

    eps = pair.transverse_contact_ratio
    frac = np.round(np.mod(u, 1.0) * npc) / npc
    model = FEPairModel(pair, torque=torque, level=level, plane=plane)
    corner = {}
    for f in np.unique(frac):
        res = model.solve(float(f))
        corner[f] = bool(np.any((res.load_share > CORNER_SHARE)
                                & ~np.isfinite(res.hertz_half_width)))
    dist = np.minimum.reduce([frac, np.abs(frac - (eps - 1.0)), 1.0 - frac])
    ends = (dist < 0.5 / npc) | np.array([corner[f] for f in frac])
    return ~ends, frac < eps - 1.0


def calibrated_curve(train, mesh: int, crack: str, depth: float | None, u: np.ndarray,
                     corner: bool = True, corrected_sides: tuple[int, ...] | None = None,
                     crack_coupling: bool = True) -> np.ndarray:
    """The calibrated section TVMS at the FE-pair positions ``u`` [N/m].

    ``corner``: with the tip-corner contacts under load (the default), else the path of
    contact only (the tables before issue 25 item 2). ``corrected_sides``: the crack
    sides the measured crack correction applies to (default the model's,
    :data:`gearsim.fem.calibration.CORRECTED_SIDES`; ``()``: the PE section reduction
    alone, the model before the correction). ``crack_coupling``: the cracked body's
    factors on the coupling beside the cracked tooth (the model's); False: the healthy
    body's coupling there (the model before them).
    """
    from gearsim.fem.calibration import CORRECTED_SIDES, CalibratedCompliance
    from gearsim.studies.fe_pair_check import SECTION

    class HealthyCoupling(CalibratedCompliance):
        def cross_factor(self, *args, **kwargs):  # the healthy body's coupling
            return None

    if crack == "none":
        tr = train.with_cracks(())
    else:
        kw = {} if depth is None else {"depth": depth}
        tr = train.with_crack(crack, closure="contact", source="pe", **kw)
    cracks = tr.mesh_cracks(mesh)
    rev = cracks[0].gear if cracks else 1
    pair = tr.pairs[mesh]
    z_rev = pair.driver.teeth if rev == 1 else pair.driven.teeth
    st = dataclasses.replace(tr.stiffness, source="calibrated", contact="line", coupling="fe",
                             corner_contact=corner, slices=1,
                             positions_per_cycle=PE_POSITIONS)
    # studies.fe_pair_check.section_tvms with the calibrated model of these sides
    kind = CalibratedCompliance if crack_coupling else HealthyCoupling
    model = kind(corrected_sides=CORRECTED_SIDES if corrected_sides is None
                 else corrected_sides)
    thin = dataclasses.replace(pair, driver=dataclasses.replace(
        pair.driver, face_width=pair.driver.face_width * SECTION), driven=dataclasses.replace(
        pair.driven, face_width=pair.driven.face_width * SECTION))
    ms = mesh_stiffness(thin, cracks=cracks, settings=st, compliance=model,
                        force=tr.static_mesh_force(mesh) * SECTION,
                        coupling=body_coupling(st), revolution_of=rev)
    return np.interp(u, ms.cycles, ms.k / SECTION, period=float(z_rev))


def accuracy_case(name: str, train, torque: float, depth: float | None,
                  cracks: tuple[str, ...] = ("none", "working", "non-working"),
                  level: int = FE_PAIR_LEVEL) -> list[dict]:
    """The crack cases of one train at one input torque; prints and returns rows.

    ``level``: FE mesh level of the FE pair and of the zone classification.
    """
    tr = dataclasses.replace(train, operating=dataclasses.replace(train.operating,
                                                                  torque=torque))
    rows = []
    inside = double = None
    for crack in cracks:
        t0 = time.perf_counter()
        chk = fe_pair_check(tr, 0, crack=crack, depth=depth, level=level)
        for c, (corner, sides, cracked, cross) in CALIBRATED.items():
            if cracked and crack == "none":
                continue
            chk.curves[c] = calibrated_curve(tr, 0, crack, depth, chk.cycles, corner, sides,
                                             cross)
        if inside is None:  # the same positions in every case
            inside, double = _zones(tr.pairs[0], tr.torque(0), chk.cycles, 20, level,
                                   tr.stiffness.plane)
        row = {"case": name, "torque": torque, "crack": crack,
               "seconds": time.perf_counter() - t0}
        for c in CURVES:
            if c not in chk.curves:
                continue
            d = chk.differences(c)
            p = 100.0 * (chk.curves[c] / chk.k_fe - 1.0)
            row[c] = {**d,
                      "double": (p[inside & double].min(), p[inside & double].max()),
                      "single": (p[inside & ~double].min(), p[inside & ~double].max()),
                      "ends": (p[~inside].min(), p[~inside].max())}
        rows.append(row)
        _print_row(row)
    return rows


def _print_row(row: dict) -> None:
    head = f"{row['case']:14s} {row['torque']:7.0f} N m  {row['crack']:12s}"
    for c in CURVES:
        if c not in row:
            continue
        d = row[c]
        print(f"{head} {c:12s} max {d['max']:+6.1f} min {d['min']:+6.1f} mean "
              f"{d['mean']:+6.1f} | double {d['double'][0]:+6.1f}..{d['double'][1]:+6.1f}"
              f" single {d['single'][0]:+6.1f}..{d['single'][1]:+6.1f}"
              f" ends {d['ends'][0]:+6.1f}..{d['ends'][1]:+6.1f}")
        head = " " * len(head)
    print(f"{'':14s} ({row['seconds']:.0f} s)", flush=True)


def _extra_train(teeth: tuple[int, int], shift: float, alpha_deg: float, torque: float,
                 rho: float = 0.38):
    """A spur pair like the 19/48 example with other teeth, shift, pressure angle, rack
    tip round ``rho`` (0.38 does not fit the rack tooth at 25 deg, and the FE
    mesher finds the outline at 0.3 self-intersecting: 0.25 there)."""
    import math

    from gearsim.geometry.gear import Gear
    from gearsim.system.train import GearTrain, Operating

    base = load("spur-19-48").train
    g0 = base.gears[0]
    gears = tuple(dataclasses.replace(g0, name=n, teeth=z, profile_shift=x,
                                      normal_pressure_angle=math.radians(alpha_deg),
                                      fillet_radius_coefficient=rho)
                  for n, z, x in (("pinion", teeth[0], shift), ("gear", teeth[1], 0.0)))
    assert all(isinstance(g, Gear) for g in gears)
    return GearTrain(gears=gears, operating=Operating(speed=base.operating.speed,
                                                      torque=torque),
                     stiffness=base.stiffness, cracks=base.cracks)


def accuracy(extra: bool, healthy: bool = False, level: int = FE_PAIR_LEVEL) -> None:
    """The accuracy tables of docs/stiffness.md section 4c (FE pair at mesh ``level``)."""
    spur = load("spur-19-48").train
    table1 = load("idler-table1").train
    print(f"FE pair level {level}")
    print("100 (k - k_FE pair) / k_FE pair [%]; double/single: pointwise inside the zones, "
          "ends: positions on a nominal transition or with tip-corner contact in the FE pair")
    cases = [("19/48", lambda: spur, 100.0, None), ("19/48", lambda: spur, 400.0, None),
             ("Table-1 I", lambda: table1, 4876.0, 6e-3),
             ("Table-1 I", lambda: table1, 1219.0, 6e-3)]
    if extra:
        p17 = (17, 60), 0.3, 20.0, 100.0
        p25 = (25, 25), 0.0, 25.0, 100.0, 0.25
        cases += [("17/60 x1=+0.3", lambda: _extra_train(*p17), t, None) for t in (100., 400.)]
        cases += [("25/25 25deg", lambda: _extra_train(*p25), t, None) for t in (100., 400.)]
    for name, make, torque, depth in cases:
        accuracy_case(name, make(), torque, depth, ("none",) if healthy else
                      ("none", "working", "non-working"), level)


def _level(argv: list[str]) -> int:
    """The FE pair level of ``--level N`` (default :data:`FE_PAIR_LEVEL`)."""
    if "--level" not in argv:
        return FE_PAIR_LEVEL
    i = argv.index("--level")
    if i + 1 >= len(argv) or not argv[i + 1].isdigit():
        sys.exit("--level needs an integer mesh level, e.g. --level 2")
    return int(argv[i + 1])


if __name__ == "__main__":
    if "--accuracy" in sys.argv:
        accuracy("--extra" in sys.argv, "--healthy" in sys.argv, _level(sys.argv))
    else:
        cost()
