"""Crack growth life of a gear of a gearbox, stiffness along it, run-to-failure records.

The chain of issue 27 from the grown crack to vibration (docs/fracture.md, sections
"Life of a gear", "Stiffness along the life" and "Run-to-failure data set"):

1. :func:`gear_life`: the configured crack of a gear is the initial crack; at every
   increment K_I, K_II at the tip are computed for the loads of a whole mesh cycle
   (:func:`gearsim.fracture.tooth.cycle_intensity`: the contact positions of the
   tooth's engagement with the PE load sharing of the healthy mesh, times the static
   mesh force per unit face width), the crack grows by the maximum tangential stress
   criterion at the position of the largest K_eq (:func:`gearsim.fracture.path.
   grow_cycle_path`), and the Paris law is integrated along the path
   (:func:`gearsim.fracture.path.path_life`) with dK = K_eq,max x DLF, DLF the dynamic
   load factor peak / mean mesh force of a short simulation of the healthy gearbox.
   Cycles are turned into hours with the gear's speed (the tooth is loaded once per
   revolution).
2. :func:`equivalent_crack` maps the polyline to the straight crack of the
   potential-energy model with the same limiting line (start on the fillet to the
   path's leftmost point, the tip of a grown path: depth and angle), past the tooth
   centre line too; a crack whose line cuts the tooth off is the tooth loss.
   :func:`stiffness_along_life` computes the TVMS of each state (PE) and compares it with
   the FE tooth route (before the centre line) and the FE fracture sector (any path).
3. :func:`life_records`: at chosen life fractions and seeds, the gearbox with the
   equivalent crack is simulated, the default record selected, seeded noise added and
   the record analysed; features and ground truth go into an xarray Dataset
   (:func:`write_store`, NetCDF, atomic). :func:`indicator_trends` adds NA4 with the run
   history (the residuals of the earlier records of the same seed, Zakrajsek et al.
   1993), FM4, the first-order sideband energy and the residual kurtosis.

The fracture model is the 2-D transverse section (plane stress) of :mod:`gearsim.fracture`:
a helical gear is treated in its transverse section, the crack uniform along the face.

References
----------
.. [Barsom1999] J. M. Barsom, S. T. Rolfe, Fracture and Fatigue Control in Structures,
   3rd ed., ASTM, 1999, ch. 9 (Paris constants of martensitic steels; threshold
   5.5 ksi sqrt(in) = 6.0 MPa sqrt(m) for R < 0.1).
.. [Zakrajsek1993] J. J. Zakrajsek, D. P. Townsend, H. J. Decker, An analysis of gear
   fault detection methods as applied to pitting fatigue failure data, NASA TM-105950,
   1993 (NA4, FM4; alarm level 3 for a kurtosis-type indicator).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from gearsim.errors import InputError, require
from gearsim.fracture.mesh import CrackPath
from gearsim.fracture.paris import MPA_SQRT_M, LifeResult, ParisLaw, steel_class_law
from gearsim.fracture.path import CyclePath, grow_cycle_path, largest_increment, path_life
from gearsim.fracture.tooth import initial_crack
from gearsim.geometry.profile import ToothProfile
from gearsim.model.gearbox import Gearbox
from gearsim.stiffness.crack import cuts_tooth_off, path_leftmost

__all__ = ["DEFAULT_THRESHOLD_MPA", "DEFAULT_TOUGHNESS_MPA", "ALARM_LEVELS", "GearLife",
           "CrackState", "default_law", "mesh_cycle_loads", "gear_life", "life_fractions",
           "LifeStiffness", "equivalent_crack", "stiffness_along_life",
           "DEFAULT_NOISE", "record_duration", "operating_conditions", "life_records",
           "write_store", "record_condition", "indicator_trends", "alarm_fractions",
           "FRACTURE_ENDS", "sideband_feature", "MIN_INCREMENT", "MAX_NOISE",
           "increment_range"]

#: dK_th of the default law [MPa sqrt(m)]: Barsom & Rolfe (1999, ch. 9), lower bound
#: for steels at R < 0.1, 5.5 ksi sqrt(in).
DEFAULT_THRESHOLD_MPA = 6.0
#: K_IC of the default law [MPa sqrt(m)]: an assumed value for a through-hardened gear
#: steel core (not a grade value; give the grade's K_IC).
DEFAULT_TOUGHNESS_MPA = 80.0

#: Alarm level of each trended indicator and its source.
ALARM_LEVELS: dict[str, tuple[float, str]] = {
    "na4": (3.0, "NA4 > 3: Zakrajsek, Townsend & Decker, NASA TM-105950 (1993)"),
    "fm4": (3.0, "FM4 > 3: Stewart (1977); Zakrajsek et al., NASA TM-105950 (1993)"),
    "residual_kurtosis": (3.0, "kurtosis > 3 of the residual (Gaussian 3): Decker, "
                               "NASA TM-2002-211492"),
    "sideband_energy": (2.0, "first-order sideband energy ratio twice its healthy value "
                             "(a relative alarm, this module's choice)"),
}


#: Smallest crack increment over the normal module [-]. The FE resolves an increment da
#: with tip elements of da / 75 (ring 0.4 da, 30 divisions) graded to the sector's m_n / 4:
#: at m_n / 1000 the ratio is 1 : 18 750, and K at the next tip has converged (Table-1
#: input gear, 2 mm crack, HPSTC load: K_I = 1.7404 / 1.6726 / 1.6642 / 1.6629 MPa sqrt(m)
#: per 1e5 N/m for da = m_n / 12, / 100, / 1000, / 10 000, at 26k / 61k / 185k / 360k
#: dofs). A smaller increment only costs; at 1e-9 mm round-off gave K = 0.0005 MPa sqrt(m)
#: at the second tip, an "arrest" of a growing crack.
MIN_INCREMENT = 1e-3
#: Largest noise RMS over the record's standard deviation of the run-to-failure records
#: [-]: 100, SNR -40 dB. A synchronous average over the record's few revolutions gains
#: 10 log10(revolutions) dB, far from 40 dB: above it every record is its noise (and at
#: 1e300 the noisy record overflows).
MAX_NOISE = 100.0


def default_law() -> ParisLaw:
    """The default Paris law: Barsom & Rolfe's martensitic steels.

    Returns
    -------
    ParisLaw
        C = 1.36e-10 (m/cycle)/(MPa sqrt(m))^2.25, m = 2.25 (Barsom & Rolfe 1999, ch. 9),
        dK_th = :data:`DEFAULT_THRESHOLD_MPA`, K_IC = :data:`DEFAULT_TOUGHNESS_MPA`
        (assumed) [MPa sqrt(m)].
    """
    return steel_class_law("martensitic", threshold=DEFAULT_THRESHOLD_MPA * MPA_SQRT_M,
                           toughness=DEFAULT_TOUGHNESS_MPA * MPA_SQRT_M)


def _crack_of(gb: Gearbox, gear: str | None):
    tr = gb.gears_only("gearbox", gb.name, "crack growth")
    names = [g.name for g in tr.gears]
    if gear is None:
        require(bool(tr.cracks), "crack", "none",
                f"{gb.name} has no crack: give one in [[cracks]] (the initial crack of the life)")
        gear = tr.cracks[0].gear
    require(gear in names, "gear", gear, "must be one of " + ", ".join(names))
    cracks = [c for c in tr.cracks if c.gear == gear]
    require(bool(cracks), "gear", gear,
            "has no crack: give one in [[cracks]] (the initial crack of the life)")
    c = cracks[0]
    require(c.depth > 0.0, "crack.depth", c.depth, "must be > 0 m for a life (the initial crack)")
    require(c.flank == "working", "crack.flank", c.flank,
            'must be "working": the path model grows an open crack on the loaded (tensile) '
            "fillet; a non-working-flank crack closes under the load")
    require(c.start_radius is None, "crack.start_radius", c.start_radius,
            "must be the default (30 deg tangent point) for a life")
    return tr.gears[names.index(gear)], c


def increment_range(gb: Gearbox, gear: str | None = None) -> tuple[float, float]:
    """Range of the crack increment of :func:`gear_life` [m], from geometry only.

    Parameters
    ----------
    gb : Gearbox
        The gearbox.
    gear : str, optional
        The cracked gear (default: the gear of the first crack).

    Returns
    -------
    lo, hi : float
        :data:`MIN_INCREMENT` x m_n, and half the distance from the initial crack's tip
        to the tooth outline ahead of it
        (:func:`gearsim.fracture.path.largest_increment`; a larger first increment would
        leave no ligament to grow in).
    """
    g, crack = _crack_of(gb, gear)
    start = initial_crack(g, crack.depth, angle=crack.angle)
    return MIN_INCREMENT * g.normal_module, largest_increment(g, start)


def _mesh_of(gb: Gearbox, gear: str) -> tuple[int, int]:
    """Index of the first mesh of ``gear`` and its side (1 driver, 2 driven)."""
    for i, p in enumerate(gb.train.pairs):
        if p.driver.name == gear:
            return i, 1
        if p.driven.name == gear:
            return i, 2
    raise InputError("gear", gear, "is in no mesh")


def mesh_cycle_loads(gb: Gearbox, gear: str, positions: int = 7
                     ) -> tuple[np.ndarray, np.ndarray, float]:
    """Contact radii and load shares of one tooth's engagement in its first mesh.

    The PE TVMS of the healthy mesh (:meth:`Gearbox.mesh_stiffness`) gives the load share
    of the pair holding tooth 0 at each position of its engagement; the contact point
    moves along the line of action from the start of contact A to the end E (ISO 21771)
    over the engagement, radius sqrt(r_b^2 + l^2) on the driver, sqrt(r_b^2 +
    (T1T2 - l)^2) on the driven gear. For a helical gear this is the 2-D transverse
    model: the tooth's share spread evenly over the face width, its contact at the
    middle of its contact line (the engagement then spans eps_alpha + eps_beta base
    pitches and the share stays below 1).

    Parameters
    ----------
    gb : Gearbox
        The gearbox.
    gear : str
        Gear name.
    positions : int
        Positions kept (3 to 41): evenly spaced over the engagement, plus the one of the
        largest share x lever (the highest point of single-tooth contact, HPSTC).

    Returns
    -------
    radii : ndarray
        Contact radii on the gear [m], inside its involute.
    shares : ndarray
        Load share of the tooth [-] (1 in single-tooth contact).
    face_width : float
        Engaged face width [m].
    """
    require(isinstance(positions, int) and 3 <= positions <= 41, "positions", positions,
            "must be an integer in [3, 41]")
    i, side = _mesh_of(gb, gear)
    healthy = gb.healthy()
    ds = healthy.mesh_stiffness(i, revolution_of=side)
    pair = gb.train.pairs[i]
    tooth = np.asarray(ds[f"pair_tooth{side}"].values)
    share = np.asarray(ds["load_share"].values)
    s = np.where(tooth == 0, share, 0.0).sum(axis=1)
    on = s > 1e-3
    n = on.size
    start = next(k for k in range(n) if on[k] and not on[k - 1])
    order = (start + np.arange(n)) % n
    run = order[on[order].cumsum() == np.arange(1, n + 1)]
    # the contact moves from A to E over the engagement (a helical tooth: the middle of
    # its contact line, the engagement spanning eps_alpha + eps_beta pitches)
    ls = pair.start_of_contact + (pair.end_of_contact - pair.start_of_contact) * (
        np.arange(run.size) / max(run.size - 1, 1))
    radius = (np.array([pair.radius_on_driver(v) for v in ls]) if side == 1
              else np.array([pair.radius_on_driven(v) for v in ls]))
    g = pair.driver if side == 1 else pair.driven
    lo = max(ToothProfile(g).form_radius, g.base_radius)
    radius = np.clip(radius, lo * (1 + 1e-6), g.tip_radius * (1 - 1e-6))
    sh = s[run]
    pick = set(np.linspace(0, run.size - 1, positions - 1).round().astype(int).tolist())
    pick.add(int(np.argmax(sh * (radius - lo))))
    idx = np.array(sorted(pick))
    return radius[idx], sh[idx], pair.face_width


@dataclass(frozen=True)
class GearLife:
    """Crack growth life of a gear (:func:`gear_life`).

    Parameters
    ----------
    gear : str
        Gear name.
    flank : str
        Cracked flank (``"working"``).
    path : CyclePath
        Grown path with K over the mesh cycle at each analysed tip (static load).
    life : LifeResult
        Paris life from the initial crack (cycles against polyline length).
    end : str
        ``"K_max >= K_IC"``, ``"tooth loss"`` (the path ran through the tooth),
        ``"no growth"`` (dK below the threshold at the initial crack), ``"arrest"``
        or ``"path end"`` (the increments ran out before either).
    law : ParisLaw
        The Paris law.
    static_force : float
        Static mesh force per unit face width [N/m] (mean of the simulated force).
    dynamic_load_factor : float
        Peak / mean mesh force of the healthy gearbox's short simulation [-].
    shaft_frequency : float
        Speed of the gear [Hz] (cycles per second of the cracked tooth).
    radii, shares : ndarray
        Contact radii [m] and load shares [-] of the mesh cycle.
    seconds : float
        Wall time [s].
    """

    gear: str
    flank: str
    path: CyclePath
    life: LifeResult
    end: str
    law: ParisLaw
    static_force: float
    dynamic_load_factor: float
    shaft_frequency: float
    radii: np.ndarray
    shares: np.ndarray
    seconds: float

    @property
    def cycles_end(self) -> float:
        """Cycles to the end of life [cycles] (inf for ``"no growth"``/``"arrest"``)."""
        return float(self.life.cycles_end)

    @property
    def hours_end(self) -> float:
        """Hours to the end of life [h]."""
        return self.cycles_end / self.shaft_frequency / 3600.0

    def hours(self, cycles) -> np.ndarray:
        """Hours of running for ``cycles`` load cycles of the cracked tooth [h].

        Parameters
        ----------
        cycles : array_like
            Cycles [-].

        Returns
        -------
        ndarray
            cycles / f_gear / 3600 [h].
        """
        return np.asarray(cycles, dtype=float) / self.shaft_frequency / 3600.0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (SI units, K in MPa sqrt(m), lengths in mm).

        Returns
        -------
        dict
        """
        p = self.path
        fin = math.isfinite(self.cycles_end)
        return {
            "gear": self.gear, "flank": self.flank, "end": self.end,
            "law": {"name": self.law.name, "c_si": self.law.c, "m": self.law.m,
                    "threshold_mpa": self.law.threshold / MPA_SQRT_M,
                    "toughness_mpa": self.law.toughness / MPA_SQRT_M,
                    "source": self.law.source},
            "static_force_n_per_m": self.static_force,
            "dynamic_load_factor": self.dynamic_load_factor,
            "shaft_frequency_hz": self.shaft_frequency,
            "cycle_radii_mm": (self.radii * 1e3).round(4).tolist(),
            "cycle_shares": self.shares.round(4).tolist(),
            "increments": int(p.lengths.size),
            "path_status": p.status, "path_message": p.message,
            "path_mm": (p.crack.array * 1e3).round(5).tolist(),
            "lengths_mm": (p.lengths * 1e3).round(5).tolist(),
            "delta_k_mpa": (p.keq * self.dynamic_load_factor / MPA_SQRT_M).round(5).tolist(),
            "life_a_mm": (self.life.a * 1e3).round(5).tolist(),
            "life_cycles": [float(c) for c in self.life.cycles],
            "a_end_mm": self.life.a_end * 1e3,
            "cycles_end": self.cycles_end if fin else None,
            "hours_end": self.hours_end if fin else None,
            "fe_seconds_per_increment": (p.seconds_per_step.round(3).tolist()),
            "seconds": self.seconds,
        }


def _dynamic_load(gb: Gearbox, mesh: int, duration: float | None) -> tuple[float, float]:
    """Mean and peak of the mesh force of the healthy gearbox [N]."""
    healthy = gb.healthy()
    _, f_slow = healthy.slowest_shaft()
    d = 1.2 / f_slow if duration is None else float(duration)
    ds = healthy.simulate(duration=d)
    x = healthy.select(ds, f"mesh_force_{mesh + 1}")
    return float(np.mean(x)), float(np.max(x))


def gear_life(gb: Gearbox, gear: str | None = None, *, increment: float | None = None,
              steps: int = 20, positions: int = 7, law: ParisLaw | None = None,
              refinement: float = 1.0, duration: float | None = None) -> GearLife:
    """Crack growth life of a gear from its configured crack to the end of life.

    Parameters
    ----------
    gb : Gearbox
        A gearbox of gears; its operating point sets the load and the speed.
    gear : str, optional
        The cracked gear (default: the gear of the first crack).
    increment : float, optional
        Crack extension per increment [m]; default m_n / 12 (0.5 mm for m_n = 6 mm);
        in :func:`increment_range`.
    steps : int
        Largest number of increments (1 to 500).
    positions : int
        Contact positions of the mesh cycle (:func:`mesh_cycle_loads`).
    law : ParisLaw, optional
        Paris law; default :func:`default_law`.
    refinement : float
        FE mesh refinement (:func:`gearsim.fracture.tooth.tooth_crack_sif`).
    duration : float, optional
        Duration of the healthy simulation for the dynamic load factor [s]; default 1.2
        revolutions of the slowest shaft.

    Returns
    -------
    GearLife

    Raises
    ------
    InputError
        No crack on the gear, a non-working-flank crack, bad numbers; ``"no growth"`` is
        a result, not an error.
    """
    t0 = time.perf_counter()
    g, crack = _crack_of(gb, gear)
    law = default_law() if law is None else law
    da = g.normal_module / 12.0 if increment is None else float(increment)
    lo, hi = increment_range(gb, g.name)
    require(math.isfinite(da) and lo <= da <= hi, "increment", da,
            f"must be in [{lo:.4g}, {hi:.4g}] m: at least m_n / {1 / MIN_INCREMENT:.0f} (the "
            "FE's tip elements, da / 75, against its m_n / 4 elements) and at most half the "
            "distance from the initial crack's tip to the outline ahead of it")
    mesh, _ = _mesh_of(gb, g.name)
    radii, shares, width = mesh_cycle_loads(gb, g.name, positions)
    mean, peak = _dynamic_load(gb, mesh, duration)
    static = mean / width
    dlf = peak / mean
    start = initial_crack(g, crack.depth, angle=crack.angle)
    path = grow_cycle_path(g, start, radii, shares * static, da, steps=steps,
                           refinement=refinement, min_keq=law.threshold / dlf)
    if path.lengths.size >= 2:
        life = path_life(path, law, dlf * path.force, force_max=dlf * path.force)
    else:
        life = _one_point_life(path, law, dlf)
    end = {"fracture": "K_max >= K_IC", "no growth": "no growth", "arrest": "arrest"}.get(
        life.status, "tooth loss" if path.status == "broken" else "path end")
    tr = gb.train
    f_gear = abs(tr.shaft_frequency(tr.gear_index(g.name)))
    return GearLife(gear=g.name, flank=crack.flank, path=path, life=life, end=end, law=law,
                    static_force=static, dynamic_load_factor=dlf, shaft_frequency=f_gear,
                    radii=radii, shares=shares, seconds=time.perf_counter() - t0)


def _one_point_life(path: CyclePath, law: ParisLaw, dlf: float) -> LifeResult:
    """Life of a path with K at one length: only the start can be judged."""
    a0 = float(path.lengths[0])
    k = float(path.keq[0]) * dlf
    one = np.array([a0])
    if k >= law.toughness:
        return LifeResult(a=one, cycles=np.zeros(1), status="fracture", a_end=a0, cycles_end=0.0)
    if k < law.threshold:
        return LifeResult(a=one, cycles=np.zeros(1), status="no growth", a_end=a0,
                          cycles_end=math.inf)
    raise InputError("steps", 1, "a growing crack needs K at >= 2 lengths: give steps >= 2 "
                     "or a smaller increment")


@dataclass(frozen=True)
class CrackState:
    """The crack at a fraction of the life (:func:`life_fractions`).

    Parameters
    ----------
    fraction : float
        Life fraction N / N_end [-].
    cycles, hours : float
        Load cycles [-] and hours [h] from the initial crack.
    length : float
        Crack length along the path [m].
    crack : CrackPath
        The path cut at that length.
    """

    fraction: float
    cycles: float
    hours: float
    length: float
    crack: CrackPath


def _cut(crack: CrackPath, length: float) -> CrackPath:
    pts = crack.array
    seg = np.hypot(*np.diff(pts, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    length = min(max(length, 1e-12), cum[-1])
    k = int(np.searchsorted(cum, length, side="left"))
    k = max(k, 1)
    t = (length - cum[k - 1]) / seg[k - 1]
    tip = pts[k - 1] + t * (pts[k] - pts[k - 1])
    keep = [tuple(p) for p in pts[:k]]
    if np.hypot(*(tip - pts[k - 1])) > 1e-9 * cum[-1]:
        keep.append((float(tip[0]), float(tip[1])))
    elif len(keep) < 2:
        keep.append((float(pts[1, 0]), float(pts[1, 1])))
    return CrackPath(points=tuple(keep), tips=crack.tips)


def life_fractions(result: GearLife, fractions: Sequence[float]) -> list[CrackState]:
    """Crack states at fractions of the life.

    The length at N = f N_end is interpolated (linear in cycles) on the life curve
    a(N) of the Paris integration (50 points, :func:`gearsim.fracture.paris.paris_life`)
    and the path cut at that length.

    Parameters
    ----------
    result : GearLife
        A life with a finite end (not ``"no growth"`` or ``"arrest"``).
    fractions : sequence of float
        Life fractions in [0, 1].

    Returns
    -------
    list of CrackState

    Raises
    ------
    InputError
        A fraction outside [0, 1] or a life without a finite end.
    """
    f = np.asarray(list(fractions), dtype=float)
    require(f.size >= 1 and bool(np.all(np.isfinite(f)) and np.all((f >= 0) & (f <= 1))),
            "fractions", list(fractions), "must be numbers in [0, 1]")
    require(math.isfinite(result.cycles_end), "life", result.end,
            "has no finite end: no crack states to record")
    n_end = result.cycles_end
    out = []
    for fi in f:
        n = float(fi) * n_end
        a = float(np.interp(n, result.life.cycles, result.life.a))
        out.append(CrackState(fraction=float(fi), cycles=n, hours=float(result.hours(n)),
                              length=a, crack=_cut(result.path.crack, a)))
    return out


def _chord(path: CrackPath) -> tuple[float, float]:
    """Depth and angle of the chord start -> tip."""
    pts = path.array
    (xs, ys), (xt, yt) = pts[0], pts[-1]
    return math.hypot(xt - xs, yt - ys), math.atan2(xs - xt, ys - yt)


def _rises(path: CrackPath) -> bool:
    """Whether the chord leaves the angles of the PE crack, (0, 90] deg."""
    _, nu = _chord(path)
    return not 0.0 < nu <= 0.5 * math.pi


def equivalent_crack(crack, path: CrackPath, *, gear=None):
    """The straight crack of the potential-energy model equivalent to a grown polyline.

    The PE crack section keeps, at each height, the part of the section left of a
    vertical limiting line (Tian 2004; past the tooth centre line, h_c < 0, the crack
    through the centre line of Wu, Zuo & Parey 2008: width h - h_q). For a polyline the
    line of every path point gives h_c(y) = min {x(s) : y(s) <= y}
    (:func:`gearsim.stiffness.crack.path_limiting_line`), one constant line from the
    leftmost point of the path when that point lies at or below the root circle or is
    the path's lowest point. The equivalent crack is the straight crack from the start
    to that point (the tip for a path that runs across the tooth, as the grown paths
    do): depth q = |point - start|, angle nu = atan2(x_s - x_p, y_s - y_p) (the
    convention of :class:`gearsim.stiffness.crack.Crack`, Chen & Shao 2011); its kernel
    record is the polyline's (tested). Past the centre line the crack is kept as it is
    (no saturation).

    **Tooth loss**: when the limiting line meets the far flank below the tip circle
    (:func:`gearsim.stiffness.crack.cuts_tooth_off`) the model's tooth is cut off: the
    state is the tooth loss and the equivalent crack is ``None`` (the callers put the
    broken tooth, :class:`gearsim.stiffness.faults.BrokenTooth`, in its place).

    ``clipped`` marks the two cases a single straight PE crack does not represent: a
    path that turns back up above the root circle (more than one limiting line: the
    chord to the tip is used), and a chord rising above its start (angle outside (0, 90]
    deg: the chord of the longest part of the path with an admissible angle is used,
    found by bisection on the length along the path). The part of a path below the root
    circle (in the rim) is seen only through h_c: the PE sections start at the root
    circle and the fillet-foundation term is the healthy body's (not flagged: the
    initial crack of the Table-1 gear already ends 35 um below the root circle).

    Parameters
    ----------
    crack : gearsim.stiffness.crack.Crack
        The configured crack (gear, tooth, flank, extent, profile are kept).
    path : CrackPath
        The grown path, start on the +x fillet (:mod:`gearsim.fracture.tooth` frame,
        tooth centre line on +y) [m].
    gear : gearsim.geometry.gear.Gear, optional
        The cracked gear: with it the limiting line's point, the turning-back check and
        the tooth loss; without it the chord to the leftmost point (the train refuses a
        crack that cuts the tooth off when the crack is put in it).

    Returns
    -------
    equivalent : gearsim.stiffness.crack.Crack or None
        Depth [m] and angle [rad] of the equivalent straight crack; ``None``: tooth loss.
    clipped : bool
        Whether the path leaves what one straight PE crack represents (above).
    """
    pts = path.array
    i = int(np.argmin(pts[:, 0]))
    clipped = False
    if gear is not None:
        prof = ToothProfile(gear)
        if cuts_tooth_off(prof, float(pts[i, 0])):
            return None, False
        if path_leftmost(prof, pts)[1]:  # more than one limiting line: the chord to the tip
            clipped, i = True, pts.shape[0] - 1
    p = CrackPath(points=path.points[:i + 1], tips=path.tips) if i >= 1 else path
    if _rises(p):
        first = CrackPath(points=path.points[:2], tips=path.tips)
        lo, hi = (first.length if not _rises(first) else 1e-9 * p.length), p.length
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if _rises(_cut(p, mid)):
                hi = mid
            else:
                lo = mid
        p, clipped = _cut(p, lo), True
    depth, nu = _chord(p)
    return dataclasses.replace(crack, depth=depth, angle=nu), clipped


@dataclass(frozen=True)
class LifeStiffness:
    """Mesh stiffness along a life (:func:`stiffness_along_life`).

    Parameters
    ----------
    fraction, length : ndarray
        Life fraction [-] and crack length along the path [m] of each state.
    depth, angle : ndarray
        Equivalent straight crack [m], [rad] (NaN at a tooth-loss state).
    clipped : ndarray of bool
        The path leaves what one straight PE crack represents (:func:`equivalent_crack`).
    tooth_loss : ndarray of bool
        The equivalent crack cuts the model's tooth off: the state is the broken tooth.
    k_min, k_mean : ndarray
        Minimum and mean of the PE TVMS over a revolution of the gear [N/m] (with the
        broken tooth at a tooth-loss state).
    tooth_pe, tooth_fe : ndarray, shape (states, radii)
        Tooth compliance (Hertz excluded, face width 1 m) of the equivalent crack, PE
        and FE (:func:`gearsim.fem.check.compare_gear`) [m/N]; empty without FE. The FE
        tooth route refuses a crack line across the centre line: NaN there; PE inf at
        a tooth-loss state (no tooth).
    dc_path, dc_chord : ndarray, shape (states, radii)
        Added compliance of the polyline and of its chord on the fracture sector
        (:func:`gearsim.fracture.compliance.sector_compliance`, free crack faces) [m/N];
        empty without FE.
    dc_pe : ndarray, shape (states, radii)
        Added compliance of the equivalent crack in the PE model with open crack faces
        (the sector's), c_PE(crack) - c_PE(healthy), L = 1 m [m/N] (inf at tooth loss);
        empty without FE.
    radii : ndarray
        Contact radii of the compliance comparisons [m].
    healthy_tooth_pe, healthy_tooth_fe : ndarray
        Healthy tooth compliances at ``radii`` [m/N].
    seconds : float
        Wall time [s].
    """

    fraction: np.ndarray
    length: np.ndarray
    depth: np.ndarray
    angle: np.ndarray
    clipped: np.ndarray
    tooth_loss: np.ndarray
    k_min: np.ndarray
    k_mean: np.ndarray
    tooth_pe: np.ndarray
    tooth_fe: np.ndarray
    dc_path: np.ndarray
    dc_chord: np.ndarray
    dc_pe: np.ndarray
    radii: np.ndarray
    healthy_tooth_pe: np.ndarray
    healthy_tooth_fe: np.ndarray
    seconds: float

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (mm, deg, N/m, percent; NaN as None).

        Returns
        -------
        dict
        """
        def clean(a) -> list:
            return [float(v) if math.isfinite(v) else None
                    for v in np.asarray(a, dtype=float).ravel()]

        out: dict[str, Any] = {
            "fraction": self.fraction.tolist(), "length_mm": (self.length * 1e3).tolist(),
            "depth_mm": clean(self.depth * 1e3), "angle_deg": clean(np.degrees(self.angle)),
            "clipped": self.clipped.tolist(), "tooth_loss": self.tooth_loss.tolist(),
            "k_min": self.k_min.tolist(), "k_mean": self.k_mean.tolist(),
        }
        if self.dc_path.size:
            shape = self.dc_path.shape
            with np.errstate(invalid="ignore", divide="ignore"):
                k_err = 100.0 * (self.tooth_fe / self.tooth_pe - 1.0)
                loss = 100.0 * ((self.tooth_pe / self.healthy_tooth_pe)
                                / (self.tooth_fe / self.healthy_tooth_fe) - 1.0)
                dc_pe_fe = self.dc_pe / self.dc_chord
            for key, v in (("pe_vs_fe_tooth_stiffness_pct", k_err),
                           ("pe_vs_fe_crack_loss_pct", loss),
                           ("path_vs_chord_added_compliance", self.dc_path / self.dc_chord),
                           ("pe_vs_fe_added_compliance", dc_pe_fe)):
                out[key] = np.asarray(clean(np.round(v, 4)), dtype=object).reshape(
                    shape).tolist()  # NaN: no FE tooth route past the centre line
        return out


def stiffness_along_life(gb: Gearbox, result: GearLife, states: Sequence[CrackState], *,
                         fe: bool = True, radii: int = 3, refinement: float = 1.0
                         ) -> LifeStiffness:
    """Mesh stiffness of the grown crack at each state, PE, and against FE.

    For each state the polyline is mapped to its equivalent straight crack
    (:func:`equivalent_crack`: the PE limiting line of the path, past the tooth centre
    line too) and the PE TVMS of the gear's first mesh is computed over a revolution of
    the gear (:meth:`Gearbox.mesh_stiffness`, the gearbox's stiffness settings); at a
    tooth-loss state (the crack cuts the model's tooth off) with the broken tooth
    (:class:`gearsim.stiffness.faults.BrokenTooth`). With ``fe``: the PE and FE tooth
    compliance of that straight crack (:func:`gearsim.fem.check.compare_gear`, the FE
    tooth route of :mod:`gearsim.fem`, which takes a straight crack line before the
    centre line only), the added compliance of the polyline and of its chord on the
    fracture sector (:func:`gearsim.fracture.compliance.sector_compliance`, any path)
    and the PE added compliance of the equivalent crack with open faces, to set against
    them.

    Parameters
    ----------
    gb : Gearbox
        The gearbox of the life.
    result : GearLife
        The life.
    states : sequence of CrackState
        Crack states (:func:`life_fractions`).
    fe : bool
        Also the FE comparisons.
    radii : int
        Contact radii of the comparisons (2 to 11), from the lowest of the cycle to the
        highest.
    refinement : float
        Mesh refinement of the fracture sector.

    Returns
    -------
    LifeStiffness
    """
    from gearsim.fem.check import compare_gear
    from gearsim.fracture.compliance import sector_compliance
    from gearsim.stiffness.crack import crack_record
    from gearsim.stiffness.tooth import ToothModel

    t0 = time.perf_counter()
    require(isinstance(radii, int) and 2 <= radii <= 11, "radii", radii,
            "must be an integer in [2, 11]")
    g, crack = _crack_of(gb, result.gear)
    mesh, side = _mesh_of(gb, g.name)
    r = np.linspace(float(result.radii.min()), float(result.radii.max()), radii)
    rows = []
    tooth_pe, tooth_fe, dc_p, dc_c, dc_e = [], [], [], [], []
    h_pe = h_fe = np.zeros(0)
    base = None
    st = gb.train.settings_of(mesh)
    if fe:
        chk = compare_gear(g, r, closure=st.closure, plane=st.plane,
                           gauss_points=st.gauss_points)
        h_pe, h_fe = chk.pe, chk.fe
        base = sector_compliance(g, r, start=result.path.crack.array[0],
                                 refinement=refinement).compliance
        pe_open = ToothModel(g, plane=st.plane, closure="open", gauss_points=st.gauss_points)
        pe_open_healthy = pe_open.compliance(r, width=1.0).sum(axis=1)
        pe_model = ToothModel(g, plane=st.plane, closure=st.closure,
                              gauss_points=st.gauss_points)
    for s in states:
        eq, clipped = equivalent_crack(crack, s.crack, gear=g)
        if eq is None:
            k = _lost_tooth_k(gb, crack, mesh, side)
        else:
            tr = gb.train.with_cracks(tuple(eq if c is crack else c for c in gb.train.cracks))
            k = tr.mesh_stiffness(mesh, revolution_of=side).to_dataset()["k"].values
        rows.append((s.fraction, s.length, np.nan if eq is None else eq.depth,
                     np.nan if eq is None else eq.angle, clipped, eq is None,
                     float(k.min()), float(k.mean())))
        if fe:
            nan = np.full(r.shape, np.nan)
            if eq is None:
                tooth_pe.append(np.full(r.shape, np.inf))
                tooth_fe.append(nan)
                dc_e.append(np.full(r.shape, np.inf))
            else:
                rec = crack_record(ToothProfile(g), eq, eq.depth, 1)
                if rec[2] > 0.0:  # K.C_HC: the FE tooth route takes the crack line
                    chk = compare_gear(g, r, crack=eq, side=1, closure=st.closure,
                                       plane=st.plane, gauss_points=st.gauss_points)
                    tooth_pe.append(chk.pe)
                    tooth_fe.append(chk.fe)
                else:
                    tooth_pe.append(pe_model.compliance(r, rec, width=1.0).sum(axis=1))
                    tooth_fe.append(nan)
                dc_e.append(pe_open.compliance(r, rec, width=1.0).sum(axis=1)
                            - pe_open_healthy)
            chord = CrackPath(points=(tuple(s.crack.array[0]), tuple(s.crack.array[-1])),
                              tips=s.crack.tips)
            dc_p.append(sector_compliance(g, r, crack=s.crack, refinement=refinement)
                        .compliance - base)
            dc_c.append(sector_compliance(g, r, crack=chord, refinement=refinement)
                        .compliance - base)
    cols = list(zip(*rows, strict=True))
    return LifeStiffness(
        fraction=np.asarray(cols[0]), length=np.asarray(cols[1]), depth=np.asarray(cols[2]),
        angle=np.asarray(cols[3]), clipped=np.asarray(cols[4], dtype=bool),
        tooth_loss=np.asarray(cols[5], dtype=bool),
        k_min=np.asarray(cols[6]), k_mean=np.asarray(cols[7]),
        tooth_pe=np.asarray(tooth_pe), tooth_fe=np.asarray(tooth_fe),
        dc_path=np.asarray(dc_p), dc_chord=np.asarray(dc_c), dc_pe=np.asarray(dc_e), radii=r,
        healthy_tooth_pe=np.asarray(h_pe), healthy_tooth_fe=np.asarray(h_fe),
        seconds=time.perf_counter() - t0)


def _lost_tooth_k(gb: Gearbox, crack, mesh: int, side: int) -> np.ndarray:
    """PE TVMS of the mesh with the cracked tooth gone (tooth loss) [N/m].

    The TVMS tables carry no broken tooth (:class:`gearsim.stiffness.faults.BrokenTooth`
    acts in the mesh of contacts), so the pairs of the tooth are taken out of the mesh
    without it: k = sum of the pair stiffnesses of the other pairs. Exact for
    ``coupling = "none"`` (independent pairs, k = sum of pair stiffnesses); with a body
    coupling the other pairs keep their stiffness in the mesh with the tooth.
    """
    tr = gb.train.with_cracks(tuple(c for c in gb.train.cracks if c is not crack))
    ds = tr.mesh_stiffness(mesh, revolution_of=side).to_dataset()
    tooth = ds["pair_tooth1" if side == 1 else "pair_tooth2"].values
    pair_k = ds["pair_k"].values
    return np.where(tooth == crack.tooth, 0.0, pair_k).sum(axis=1)


#: Noise RMS / RMS of the noise-free record of the run-to-failure records (SNR 20 dB).
DEFAULT_NOISE = 0.1


def _cracked_box(gb: Gearbox, crack, eq) -> Gearbox:
    tr = gb.train.with_cracks(tuple(eq if c is crack else c for c in gb.train.cracks))
    return dataclasses.replace(gb, train=tr)


def record_duration(gb: Gearbox) -> float:
    """Default record duration: 4.2 revolutions of the slowest shaft [s].

    The sideband analysis needs 4 frequency bins per sideband spacing with a Hann window
    (:func:`gearsim.signals.analysis.analyze` refuses shorter records); 5 % margin.

    Parameters
    ----------
    gb : Gearbox
        The gearbox.

    Returns
    -------
    float
        Duration [s].
    """
    return 4.2 / gb.slowest_shaft()[1]


#: Ends of a life after which the tooth is gone (:attr:`GearLife.end`).
FRACTURE_ENDS = ("K_max >= K_IC", "tooth loss")


def _broken_box(gb: Gearbox, crack) -> Gearbox:
    """The gearbox after the tooth fracture: the crack replaced by the whole tooth gone."""
    from gearsim.stiffness.faults import BrokenTooth

    tr = gb.train.with_cracks(tuple(c for c in gb.train.cracks if c is not crack))
    tr = tr.with_faults((*tr.faults, BrokenTooth(gear=crack.gear, tooth=crack.tooth)),
                        tr.modifications)
    return dataclasses.replace(gb, train=tr)


def operating_conditions(gb: Gearbox, loads: Sequence[float] | None = None,
                         speeds: Sequence[float] | None = None, *,
                         duration: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The loads and speeds of the records, checked before any work.

    Each load and speed is checked as the model checks an operating point
    (:class:`gearsim.system.train.Operating`: finite, > 0, at most ``MAX_TORQUE`` N m and
    ``MAX_SPEED`` rad/s), and the record at each speed as a simulation is
    (:meth:`Gearbox.check_run`: the output rate against the mesh frequency, the cost
    bounds), with the record duration of that speed.

    Parameters
    ----------
    gb : Gearbox
        The gearbox of the life (its operating point is the default).
    loads : sequence of float, optional
        Input torques [N m]; default the gearbox's own.
    speeds : sequence of float, optional
        Input shaft speeds [rad/s]; default the gearbox's own.
    duration : float, optional
        Record duration [s]; default :func:`record_duration` at each speed.

    Returns
    -------
    loads : ndarray
        Input torques [N m], ascending.
    speeds : ndarray
        Input speeds [rad/s], ascending.

    Raises
    ------
    InputError
        ``loads`` or ``speeds``: empty, repeated, not finite, <= 0 or above the model's
        ceiling; a speed whose record the simulation refuses (``dynamics.fs`` aliasing,
        cost bounds; the limit of that check, the parameter ``speeds``); ``duration``
        shorter than a record needs at the slowest speed.
    """
    from gearsim.system import Operating

    own_speed, own_torque = gb.operating()
    out = []
    for name, given, own in (("loads", loads, own_torque), ("speeds", speeds, own_speed)):
        vals = [own] if given is None else list(given)
        require(len(vals) >= 1, name, vals, "must list at least one value")
        for v in vals:
            try:
                if name == "loads":
                    Operating(speed=own_speed, torque=v)
                else:
                    Operating(speed=v, torque=own_torque)
            except InputError as exc:
                raise InputError(name, v, exc.limit) from None
        arr = np.asarray(vals, dtype=float)
        require(np.unique(arr).size == arr.size, name, vals, "must not repeat a value")
        out.append(np.sort(arr))
    for s in out[1]:
        box = gb.at(speed=float(s), torque=own_torque)
        d = record_duration(box) if duration is None else float(duration)
        try:
            dataclasses.replace(box, dynamics=dataclasses.replace(
                box.dynamics, duration=d)).check_run()
        except InputError as exc:
            if duration is not None and exc.parameter == "dynamics.duration":
                raise InputError("duration", duration, exc.limit) from None
            raise InputError("speeds", float(s), f"its record is refused: {exc}") from None
    return out[0], out[1]


def _record_task(box: Gearbox, duration: float, spec: str, noise: float, seeds: int,
                 ) -> tuple[list[dict], list[np.ndarray], float]:
    """One simulation of the records (a Dask task): the features of each seed's noisy
    record (``residual_kurtosis`` too), the residuals, the simulation's wall time."""
    from gearsim.signals import analyze
    from gearsim.signals.tsa import na4
    from gearsim.studies.sweep_case import add_noise, features

    train = box.analysis_train()  # every stage's mesh of a compound train
    fs = float(box.dynamics.fs)
    t1 = time.perf_counter()
    x = box.select(box.simulate(duration=duration), spec)
    seconds = time.perf_counter() - t1
    feats, residuals = [], []
    for k in range(seeds):
        a = analyze(add_noise(x, noise, k), fs, settings=box.analysis, **train)
        f = features(a.to_dict())
        f["residual_kurtosis"] = na4([a.residual])
        feats.append(f)
        residuals.append(np.asarray(a.residual))
    return feats, residuals, seconds


def life_records(gb: Gearbox, result: GearLife, fractions: Sequence[float], seeds: int, *,
                 duration: float | None = None, noise: float = DEFAULT_NOISE,
                 signal: str | None = None, broken: bool = True,
                 loads: Sequence[float] | None = None, speeds: Sequence[float] | None = None,
                 workers: int = 1, scheduler: str | None = None,
                 cluster_kwargs: dict | None = None,
                 note: Callable[[str], None] | None = None, adaptive: bool = True) -> Any:
    """Vibration records with ground truth at fractions of a life, loads and speeds.

    **The crack states are those of the one life** ``result``, computed at the
    gearbox's operating point: the life is the crack's history. The records are what a
    test rig measures at each of those crack states when it is run at several loads and
    speeds (``loads`` x ``speeds``); the crack does not grow differently at another
    load here.

    For each fraction (sorted ascending), load and speed the gearbox with the equivalent
    straight crack of the state (:func:`equivalent_crack`) at that input torque and
    speed (:meth:`Gearbox.at`) is simulated once (:meth:`Gearbox.simulate`,
    deterministic; record duration :func:`record_duration` at that speed unless
    ``duration`` is given); for each seed white noise of RMS ``noise`` x std(record) is
    added (:func:`gearsim.studies.sweep_case.add_noise`, seed = seed index) and the
    record is analysed (:func:`gearsim.signals.analyze`, the reference shaft and teeth
    at that speed and the ``[analysis]`` settings). Besides the features of
    :func:`gearsim.studies.sweep_case.features`: ``na4_history``, NA4 of the residual
    normalised by the mean residual variance of the records of the same load, speed and
    seed up to this fraction (the run history of Zakrajsek et al. 1993), and
    ``residual_kurtosis`` (NA4 of the record alone).

    The simulations (one per fraction x load x speed, with the noise and analysis of
    every seed) run on Dask when ``workers`` > 1 or a ``scheduler`` is given
    (:func:`gearsim.studies.sweep_run.cluster_client`; a local cluster of at most one
    worker per task and CPU core, :func:`gearsim.studies.sweep_run.plan_workers`), in
    this process otherwise; the numbers are the same either way. ``na4_history`` is
    formed here from the tasks' residuals.

    When the life ends in fracture (:data:`FRACTURE_ENDS`) and ``broken`` is true, the
    records end with the **broken tooth**: one more row at fraction 1 (coordinate
    ``broken`` = 1; the cracked rows have 0) where the cracked tooth is gone over the
    whole face (:class:`gearsim.stiffness.faults.BrokenTooth`, simulated on the mesh of
    contacts), the crack length that of the end of life and the equivalent crack NaN;
    every record of such a life is then simulated on the mesh of contacts (one model
    along the life: the tables lack the tip-corner contacts). A state whose equivalent
    crack cuts the model's tooth off (:func:`equivalent_crack`: tooth loss) is recorded
    with the broken tooth too (``broken`` = 1, equivalent crack NaN), on the mesh of
    contacts, whatever ``broken``.

    Parameters
    ----------
    gb : Gearbox
        The gearbox of the life (its operating point: that of the life).
    result : GearLife
        The life (a finite end).
    fractions : sequence of float
        Life fractions in [0, 1].
    seeds : int
        Noise seeds per fraction, load and speed (>= 1).
    duration : float, optional
        Record duration [s]; default :func:`record_duration` at each speed (4.2
        revolutions of the slowest shaft).
    noise : float
        Noise RMS over the record's standard deviation [-], in [0, :data:`MAX_NOISE`].
    signal : str, optional
        Record to analyse (:meth:`Gearbox.signals`); default :attr:`Gearbox.default_signal`.
    broken : bool
        End with the broken tooth's record after a fracture (see above).
    loads : sequence of float, optional
        Input torques [N m] of the records; default the gearbox's own (checked by
        :func:`operating_conditions`).
    speeds : sequence of float, optional
        Input shaft speeds [rad/s] of the records; default the gearbox's own.
    workers : int
        Local Dask worker processes (>= 1); 1 and no ``scheduler``: this process.
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``).
    cluster_kwargs : dict, optional
        Extra keyword arguments of the local ``LocalCluster``.
    note : callable, optional
        Called with a one-line note when fewer local workers than asked are started.
    adaptive : bool
        With local workers: the first simulation runs in this process, timed, and the
        rest too when a local cluster would save less than its start-up
        (:data:`gearsim.studies.sweep_run.CLUSTER_START_S`), as ``gearsim sweep`` decides;
        ``False``: the cluster whenever ``workers`` > 1. The records are the same either
        way.

    Returns
    -------
    xarray.Dataset
        Features over dims ``fraction``, ``load``, ``speed``, ``seed``; ``vertex`` (the
        grown path) and ``life_point`` (the life curve); coordinates ``load`` [N*m] and
        ``speed`` [rad/s], along ``speed`` ``reference_shaft_frequency`` [Hz] (the
        analysis' f_r1), ``mesh_frequency`` [Hz] (of the cracked gear's first mesh) and
        ``duration`` [s]; ground truth as coordinates along ``fraction``:
        ``crack_length`` [m], ``equivalent_depth`` [m], ``equivalent_angle`` [rad],
        ``clipped``, ``broken``, ``cycles``, ``hours`` [h]; ``simulation_seconds`` over
        (fraction, load, speed); attributes gear, flank, end, law, the life's operating
        point (``speed_rad_s``, ``torque_n_m``), signal, noise, ``dask_workers`` (0: run
        in this process) (``duration_s`` and ``reference_shaft_hz`` when one value holds
        for every speed).

    Raises
    ------
    InputError
        Bad ``seeds``, ``noise``, ``fractions``, ``loads``, ``speeds``, ``workers`` or
        scheduler address; a scheduler that cannot be reached.
    SimulationError
        The local cluster's workers did not start
        (:func:`gearsim.studies.sweep_run.cluster_client`); a task's own exception is
        raised as it is, after the Dask retries.
    """
    import xarray as xr

    from gearsim.signals.tsa import na4
    from gearsim.studies.sweep_run import check_scheduler, plan_workers

    require(isinstance(seeds, int) and not isinstance(seeds, bool) and seeds >= 1, "seeds",
            seeds, "must be an integer >= 1")
    require(math.isfinite(noise) and 0.0 <= noise <= MAX_NOISE, "noise", noise,
            f"must be in [0, {MAX_NOISE:g}] (noise RMS / record standard deviation; "
            f"{MAX_NOISE:g}: SNR {-20 * math.log10(MAX_NOISE):g} dB, past which every record "
            "is its noise)")
    plan_workers(workers, 1)  # the type and sign of workers, before any work
    if scheduler is not None:
        scheduler = check_scheduler(scheduler)
    t0 = time.perf_counter()
    states = sorted(life_fractions(result, fractions), key=lambda s: s.fraction)
    g, crack = _crack_of(gb, result.gear)
    mesh, _ = _mesh_of(gb, g.name)
    spec = gb.default_signal if signal is None else signal
    fs = float(gb.dynamics.fs)
    rows = [(s, *equivalent_crack(crack, s.crack, gear=g)) for s in states]
    gone = broken and result.end in FRACTURE_ENDS
    # a state whose crack cuts the model's tooth off is the broken tooth too (tooth loss)
    if gone or any(eq is None for _, eq, _ in rows):
        # every record on the mesh of contacts, which the broken tooth needs: the tables
        # lack the tip-corner contacts that engage under load (at 4x the Table-1 torque
        # the table path's RMS is twice the contacts' for the same healthy mesh), so
        # mixing the two paths would show the change of model as a change of damage
        gb = dataclasses.replace(gb, dynamics=dataclasses.replace(gb.dynamics,
                                                                  contact_mesh=True))
    if gone:  # the tooth is lost at the end of the life
        rows.append((CrackState(fraction=1.0, cycles=result.cycles_end,
                                hours=float(result.hours(result.cycles_end)),
                                length=float(result.life.a_end), crack=result.path.crack),
                     None, False))
    load_v, speed_v = operating_conditions(gb, loads, speeds, duration=duration)
    at_speed = [gb.at(speed=float(s), torque=float(load_v[0])) for s in speed_v]
    d_v = np.array([record_duration(b) if duration is None else float(duration)
                    for b in at_speed])
    ref_v = np.array([b.reference()[1] for b in at_speed])
    fm_v = np.array([b.train.mesh_frequencies[mesh] for b in at_speed])
    tasks = []  # (fraction row, load, speed) in this order
    for _, eq, _ in rows:
        for t in load_v:
            for j, s in enumerate(speed_v):
                at = gb.at(speed=float(s), torque=float(t))
                box = _cracked_box(at, crack, eq) if eq is not None else _broken_box(at, crack)
                tasks.append((box, float(d_v[j]), spec, noise, seeds))
    n_workers, msg = plan_workers(workers, len(tasks), "simulation")
    if msg is not None and scheduler is None and note is not None:
        note(msg)
    done: list = []
    if scheduler is None and n_workers > 1 and adaptive:
        # the cluster only when it pays (as run_study): the first simulation here, timed;
        # the rest here too when a local cluster's start-up would not be won back
        from gearsim.studies.sweep_run import cluster_pays

        t1 = time.perf_counter()
        done.append(_record_task(*tasks[0]))
        left = (time.perf_counter() - t1) * (len(tasks) - 1)
        if not cluster_pays(left, len(tasks) - 1, n_workers):
            n_workers = 1
    rest = tasks[len(done):]
    dask_workers = 0
    if scheduler is None and n_workers == 1:
        done += [_record_task(*task) for task in rest]
    elif rest:
        from gearsim.studies.sweep_run import RETRIES, cluster_client

        with cluster_client(min(n_workers, len(rest)) if scheduler is None else n_workers,
                            scheduler, cluster_kwargs) as client:
            dask_workers = len(client.scheduler_info().get("workers", {}))
            futures = [client.submit(_record_task, *task, pure=False, retries=RETRIES)
                       for task in rest]
            done += client.gather(futures)
    nf, nl, ns = len(rows), load_v.size, speed_v.size
    grid = np.empty((nf, nl, ns), dtype=object)
    for i, out in enumerate(done):
        grid[np.unravel_index(i, (nf, nl, ns))] = out
    for il in range(nl):  # NA4 with the run history of each load, speed and seed
        for js in range(ns):
            for k in range(seeds):
                history: list[np.ndarray] = []
                for i in range(nf):
                    feats, residuals, _ = grid[i, il, js]
                    history.append(residuals[k])
                    feats[k]["na4_history"] = na4(history)
    names = sorted({n for out in done for f in out[0] for n in f})
    dims = ("fraction", "load", "speed", "seed")
    data = {n: (dims, np.array([[[[f.get(n, np.nan) for f in grid[i, il, js][0]]
                                  for js in range(ns)] for il in range(nl)]
                                for i in range(nf)], dtype=float)) for n in names}
    sim_seconds = np.array([[[grid[i, il, js][2] for js in range(ns)] for il in range(nl)]
                            for i in range(nf)])
    truth = [(s.fraction, s.length, eq.depth if eq is not None else np.nan,
              eq.angle if eq is not None else np.nan, clipped, int(eq is None),
              s.cycles, s.hours) for s, eq, clipped in rows]
    cols = list(zip(*truth, strict=True))
    pts = result.path.crack.array
    ds = xr.Dataset(
        data,
        coords={
            "fraction": ("fraction", np.asarray(cols[0])),
            "load": ("load", load_v, {"units": "N*m", "long_name": "input torque"}),
            "speed": ("speed", speed_v, {"units": "rad/s", "long_name": "input shaft speed"}),
            "seed": ("seed", np.arange(seeds)),
            "crack_length": ("fraction", np.asarray(cols[1]), {"units": "m"}),
            "equivalent_depth": ("fraction", np.asarray(cols[2]), {"units": "m"}),
            "equivalent_angle": ("fraction", np.asarray(cols[3]), {"units": "rad"}),
            "clipped": ("fraction", np.asarray(cols[4], dtype=np.int8)),
            "broken": ("fraction", np.asarray(cols[5], dtype=np.int8)),
            "cycles": ("fraction", np.asarray(cols[6]), {"units": "1"}),
            "hours": ("fraction", np.asarray(cols[7]), {"units": "h"}),
            "reference_shaft_frequency": ("speed", ref_v, {"units": "Hz"}),
            "mesh_frequency": ("speed", fm_v, {"units": "Hz"}),
            "duration": ("speed", d_v, {"units": "s"}),
        })
    ds["path_x"] = ("vertex", pts[:, 0], {"units": "m"})
    ds["path_y"] = ("vertex", pts[:, 1], {"units": "m"})
    ds["life_a"] = ("life_point", result.life.a, {"units": "m"})
    ds["life_cycles"] = ("life_point", result.life.cycles, {"units": "1"})
    ds["simulation_seconds"] = (("fraction", "load", "speed"), sim_seconds, {"units": "s"})
    law = result.law
    ds.attrs.update({
        "gearbox": gb.name, "gear": result.gear, "flank": result.flank, "end": result.end,
        "cycles_end": result.cycles_end, "hours_end": result.hours_end,
        "law": law.name, "paris_c_si": law.c, "paris_m": law.m,
        "threshold_pa_sqrt_m": law.threshold, "toughness_pa_sqrt_m": law.toughness,
        "law_source": law.source, "static_force_n_per_m": result.static_force,
        "dynamic_load_factor": result.dynamic_load_factor,
        "speed_rad_s": gb.operating()[0], "torque_n_m": gb.operating()[1],
        "operating_point": "speed_rad_s and torque_n_m: the life's (the crack states); "
                           "the records at the coordinates load and speed",
        "signal": spec, "noise": noise, "fs_hz": fs,
        "contact_mesh": int(bool(gb.dynamics.contact_mesh)), "dask_workers": dask_workers,
        "seconds": time.perf_counter() - t0,
        "sideband_feature": sideband_feature(gb, g.name),
        "ground_truth": "crack_length along the grown path; equivalent_depth/angle: the "
                        "straight crack simulated (docs/fracture.md); broken = 1: the "
                        "tooth gone after the fracture",
    })
    if np.all(d_v == d_v[0]):
        ds.attrs["duration_s"] = float(d_v[0])
    if np.all(ref_v == ref_v[0]):
        ds.attrs["reference_shaft_hz"] = float(ref_v[0])
    return ds


def write_store(ds: Any, path: str | Path) -> Path:
    """Write a records Dataset to NetCDF (h5netcdf) atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`life_records`.
    path : str or Path
        Target ``.nc`` file.

    Returns
    -------
    Path
    """
    from gearsim.io.results import write_results

    return write_results(ds, path)


def sideband_feature(gb: Gearbox, gear: str) -> str:
    """Name of the first-order sideband energy ratio of the shaft carrying ``gear``.

    The family of the gear's own shaft around the harmonics of the gear's mesh
    (:func:`gearsim.studies.sweep_case.features`): ``sb_ser_o1_shaft{j}`` for a simple
    train (shaft j = gear j); for a compound train (:meth:`Gearbox.analysis_stages`) the
    mesh of stage k joins shafts k and k + 1, its names prefixed ``stage{k}_`` for k >= 2.

    Parameters
    ----------
    gb : Gearbox
        A gearbox of gears (no planetary stage).
    gear : str
        Name of one of its gears.

    Returns
    -------
    str

    Examples
    --------
    >>> import gearsim as gs
    >>> sideband_feature(gs.example("two-stage-reducer"), "intermediate-pinion")
    'stage2_sb_ser_o1_shaft2'
    >>> sideband_feature(gs.example("idler-table1"), "output")
    'sb_ser_o1_shaft3'
    """
    i = gb.train.gear_index(gear)
    if gb.analysis_stages() is None:
        return f"sb_ser_o1_shaft{i + 1}"
    for k, (a, b) in enumerate(gb.train.flow.meshes, start=1):
        if gear in (a, b):
            prefix = "" if k == 1 else f"stage{k}_"
            return f"{prefix}sb_ser_o1_shaft{k if gear == a else k + 1}"
    raise InputError("gear", gear, "meshes no gear of the train")


def _sideband_name(ds: Any, shaft: str | None = None) -> str | None:
    names = [str(n) for n in ds.data_vars if "sb_ser_o1_" in str(n)]
    want = (f"sb_ser_o1_{shaft}" if shaft is not None
            else ds.attrs.get("sideband_feature"))
    if want in names:
        return want
    return names[0] if names else None


def record_condition(ds: Any, load: float | None = None, speed: float | None = None) -> Any:
    """The records of one load and speed (the ``load`` and ``speed`` dims dropped).

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`life_records` (a store without ``load``/``speed`` dims is returned as is).
    load : float, optional
        Input torque [N m], one of the coordinate ``load`` (relative tolerance 1e-9);
        default: the only load, else the life's (attribute ``torque_n_m``) if recorded.
    speed : float, optional
        Input speed [rad/s], likewise (attribute ``speed_rad_s``).

    Returns
    -------
    xarray.Dataset
        Features over ``fraction`` and ``seed``.

    Raises
    ------
    InputError
        ``load``/``speed`` not among the recorded values, or no default (several values,
        the life's not among them).
    """
    for dim, value, attr, unit in (("load", load, "torque_n_m", "N*m"),
                                   ("speed", speed, "speed_rad_s", "rad/s")):
        if dim not in ds.dims:
            continue
        vals = np.asarray(ds[dim].values, dtype=float)
        if value is None and vals.size == 1:
            want = float(vals[0])
        else:
            want = float(ds.attrs.get(attr, np.nan) if value is None else value)
        hit = np.nonzero(np.isclose(vals, want, rtol=1e-9, atol=0.0))[0]
        listed = ", ".join(f"{v:g}" for v in vals)
        require(hit.size == 1, dim, "the life's" if value is None else value,
                f"is not recorded: give one of {listed} {unit}")
        ds = ds.isel({dim: int(hit[0])}, drop=True)
    return ds


def indicator_trends(ds: Any, shaft: str | None = None, *, load: float | None = None,
                     speed: float | None = None) -> dict[str, np.ndarray]:
    """Health indicators over the life at one load and speed, mean over seeds.

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`life_records`.
    shaft : str, optional
        Shaft label of the first-order sideband energy ratio (``sb_ser_o1_<shaft>``, the
        analysis labels ``shaft1``, ``shaft2``, ... in gear order); default the cracked
        gear's (attribute ``sideband_feature``).
    load, speed : float, optional
        The records' input torque [N m] and speed [rad/s] (:func:`record_condition`;
        default the only one, else the life's operating point).

    Returns
    -------
    dict of str to ndarray
        ``na4`` (with run history), ``fm4``, ``residual_kurtosis``, ``sideband_energy``
        (first-order sideband energy ratio of mesh order 1), each over ``fraction``.

    Raises
    ------
    InputError
        A load or speed not recorded (:func:`record_condition`).
    """
    ds = record_condition(ds, load, speed)
    out = {"na4": ds["na4_history"], "fm4": ds["tsa_fm4"],
           "residual_kurtosis": ds["residual_kurtosis"]}
    sb = _sideband_name(ds, shaft)
    if sb is not None:
        out["sideband_energy"] = ds[sb]
    return {k: np.asarray(v.mean("seed").values, dtype=float) for k, v in out.items()}


def alarm_fractions(ds: Any, shaft: str | None = None, *, load: float | None = None,
                    speed: float | None = None) -> dict[str, float | None]:
    """Life fraction at which each indicator's seed mean first crosses its alarm level,
    at one load and speed.

    Levels and sources: :data:`ALARM_LEVELS` (the sideband energy relative to its value
    at the first fraction). Linear interpolation between the recorded fractions.

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`life_records`.
    shaft : str, optional
        As :func:`indicator_trends`.
    load, speed : float, optional
        As :func:`indicator_trends`.

    Returns
    -------
    dict of str to float or None
        ``None``: not crossed within the recorded fractions.

    Raises
    ------
    InputError
        A load or speed not recorded (:func:`record_condition`).
    """
    f = np.asarray(ds["fraction"].values, dtype=float)
    out: dict[str, float | None] = {}
    for name, y in indicator_trends(ds, shaft, load=load, speed=speed).items():
        level = ALARM_LEVELS[name][0] * (y[0] if name == "sideband_energy" else 1.0)
        above = np.nonzero(y > level)[0]
        if above.size == 0:
            out[name] = None
        elif above[0] == 0:
            out[name] = float(f[0])
        else:
            i = int(above[0])
            out[name] = float(f[i - 1] + (level - y[i - 1]) / (y[i] - y[i - 1])
                              * (f[i] - f[i - 1]))
    return out
