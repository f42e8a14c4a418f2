"""Faults and modifications of a train's gears: their checks and what each mesh sees.

A train carries its surface faults (:mod:`gearsim.stiffness.faults`) and per-gear
modifications and errors (:mod:`gearsim.stiffness.modifications`). This module checks
them against the gears where the train is made (a spall on the active flank, a break
line on the fillet, wear that leaves material, a relief shorter than the profile, ...)
and turns them, for each mesh, into the :class:`~gearsim.stiffness.contacts.FlankState`
of its two gears: which flank a mesh loads follows the power flow as for cracks (an
idler's second mesh loads the other flank); a broken tooth is gone on both flanks.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from gearsim.errors import InputError, require
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.contacts import FlankState
from gearsim.stiffness.faults import (
    MAX_PITS,
    BrokenTooth,
    ChippedTip,
    Pitting,
    Spall,
    Wear,
    arc_at_radius,
)
from gearsim.stiffness.modifications import MAX_DEVIATION_MODULES

if TYPE_CHECKING:
    from gearsim.system.train import GearTrain

__all__ = ["active_roll_range", "check_faults", "flank_side", "mesh_flanks"]


def flank_side(train: GearTrain, gear: str, flank: str, mesh: int) -> int:
    """+1 if mesh ``mesh`` loads ``flank`` of ``gear``, -1 if it loads the other flank.

    The working flank is the one loaded in the gear's first mesh of the power flow
    (:meth:`gearsim.system.graph.PowerFlow.flank_side`).

    Parameters
    ----------
    train : GearTrain
        The train.
    gear : str
        Gear name.
    flank : {"working", "non-working"}
        The flank asked about.
    mesh : int
        Mesh index (0 = mesh I).

    Returns
    -------
    int
    """
    return train.flow.flank_side(gear, flank, mesh)


def active_roll_range(train: GearTrain, gear: str, flank: str | None = None
                      ) -> tuple[float, float]:
    """Roll lengths bounding the active flank of ``gear`` over its meshes [m].

    Parameters
    ----------
    train : GearTrain
        The train.
    gear : str
        Gear name.
    flank : str, optional
        Only the meshes that load this flank; default every mesh.

    Returns
    -------
    (float, float)
        Smallest and largest roll length sqrt(r^2 - r_b^2) in contact [m].
    """
    lo, hi = math.inf, -math.inf
    for mesh, which in train.flow.meshes_of(gear):
        if flank is not None and flank_side(train, gear, flank, mesh) != 1:
            continue
        p = train.pairs[mesh]
        if which == 1:
            a, b = p.start_of_contact, p.end_of_contact
        else:
            a, b = p.line_length - p.end_of_contact, p.line_length - p.start_of_contact
        lo, hi = min(lo, a), max(hi, b)
    return lo, hi


def _radius(rb: float, roll: float) -> float:
    return math.hypot(rb, roll)


def _check_patch_fault(train: GearTrain, f, name: str) -> None:
    g = train.gear(f.gear)
    rb, b = g.base_radius, g.face_width
    lo, hi = active_roll_range(train, f.gear, f.flank)
    if not math.isfinite(lo):
        lo, hi = active_roll_range(train, f.gear)
    s_lo, s_hi = lo * lo / (2 * rb), hi * hi / (2 * rb)
    r_lo, r_hi = _radius(rb, lo), _radius(rb, hi)
    prof = ToothProfile(g)
    if isinstance(f, Spall):
        sc = arc_at_radius(f.radius, rb)
        require(f.radius >= rb and s_lo <= sc - 0.5 * f.length and sc + 0.5 * f.length <= s_hi,
                f"{name}.radius", f"{f.radius * 1e3:.4g} mm",
                f"the spall (length {f.length * 1e3:.4g} mm along the profile) must lie on "
                f"the active flank of {f.gear}, radii {r_lo * 1e3:.4g} .. {r_hi * 1e3:.4g} mm "
                f"(profile arc {(s_hi - s_lo) * 1e3:.4g} mm)")
        zc = f.centre_z(b)
        require(zc - 0.5 * f.width >= -1e-12 and zc + 0.5 * f.width <= b + 1e-12,
                f"{name}.width", f"{f.width * 1e3:.4g} mm",
                f"the spall centred at z = {zc * 1e3:.4g} mm must lie inside the face "
                f"width {b * 1e3:.4g} mm")
        half = 0.5 * prof.thickness_at_radius(f.radius)
        require(f.depth < half, f"{name}.depth", f"{f.depth * 1e3:.4g} mm",
                f"must be < half the tooth thickness at r = {f.radius * 1e3:.4g} mm "
                f"({half * 1e3:.4g} mm)")
    elif isinstance(f, Pitting):
        require(r_lo * (1 - 1e-9) <= f.radius_min and f.radius_max <= r_hi * (1 + 1e-9),
                f"{name}.radius_min", f"{f.radius_min * 1e3:.4g} mm",
                f"the pitted band {f.radius_min * 1e3:.4g} .. {f.radius_max * 1e3:.4g} mm "
                f"must lie on the active flank of {f.gear}, radii {r_lo * 1e3:.4g} .. "
                f"{r_hi * 1e3:.4g} mm")
        require(f.pit_diameter < min(b, f.radius_max - f.radius_min) * 4,
                f"{name}.pit_diameter", f"{f.pit_diameter * 1e3:.4g} mm",
                "must be smaller than the pitted band")
        n = f.count(b, rb)
        require(n <= MAX_PITS, f"{name}.pit_diameter", f"{f.pit_diameter * 1e3:.4g} mm",
                f"makes {n:.3g} pits (area_fraction x band / pit area), above {MAX_PITS:g}: "
                "give larger pits")
        half = 0.5 * prof.thickness_at_radius(f.radius_max)
        require(f.depth < half, f"{name}.depth", f"{f.depth * 1e3:.4g} mm",
                f"must be < half the tooth thickness ({half * 1e3:.4g} mm)")
    elif isinstance(f, ChippedTip):
        s_tip = arc_at_radius(g.tip_radius, rb)
        require(f.length < s_tip - s_lo, f"{name}.length", f"{f.length * 1e3:.4g} mm",
                f"must be < the active profile of {f.gear} ({(s_tip - s_lo) * 1e3:.4g} mm "
                "of involute arc): a longer chip is a broken tooth")
        require(f.width <= b * (1 + 1e-12), f"{name}.width", f"{f.width * 1e3:.4g} mm",
                f"must be <= the face width {b * 1e3:.4g} mm")
    elif isinstance(f, BrokenTooth):
        if f.width is not None:
            require(f.width <= b * (1 + 1e-12), f"{name}.width", f"{f.width * 1e3:.4g} mm",
                    f"must be <= the face width {b * 1e3:.4g} mm")
        if f.break_radius is not None:
            require(g.root_radius * (1 - 1e-12) <= f.break_radius <= prof.form_radius,
                    f"{name}.break_radius", f"{f.break_radius * 1e3:.4g} mm",
                    f"the break line must start on the fillet of {f.gear}: radius "
                    f"{g.root_radius * 1e3:.4g} .. {prof.form_radius * 1e3:.4g} mm")
    elif isinstance(f, Wear) and not f.grown:
        for r, d in zip(f.radii, f.depths, strict=True):
            require(r <= g.tip_radius * (1 + 1e-12) and r >= rb, f"{name}.radii",
                    f"{r * 1e3:.4g} mm", f"must lie on the involute of {f.gear}: "
                    f"{rb * 1e3:.4g} .. {g.tip_radius * 1e3:.4g} mm")
            half = 0.5 * prof.thickness_at_radius(r)
            require(d < half, f"{name}.depths", f"{d * 1e3:.4g} mm",
                    f"must be < half the tooth thickness at r = {r * 1e3:.4g} mm "
                    f"({half * 1e3:.4g} mm)")


def check_faults(train: GearTrain) -> None:
    """Check every fault and modification of ``train`` against its gears.

    Parameters
    ----------
    train : GearTrain
        The train.

    Raises
    ------
    InputError
        Naming the table entry (``faults[i].*``, ``modifications[i].*``), the value and
        the limit: unknown gear or tooth, a patch off the active flank or outside the face,
        a spall, pit or wear deeper than half the tooth, a chip as long as the profile, a
        break line off the fillet, a relief longer than the active profile, pitch errors
        not one per tooth, or faults on a tooth already broken over the whole face.
    """
    names = [g.name for g in train.gears]
    whole = set()
    for i, f in enumerate(train.faults):
        name = f"faults[{i}]"
        require(f.gear in names, f"{name}.gear", f.gear, f"must be one of {names}")
        z = train.gear(f.gear).teeth
        if f.tooth is not None:
            require(f.tooth < z, f"{name}.tooth", f.tooth, f"must be < {z} (teeth of {f.gear})")
        _check_patch_fault(train, f, name)
        if isinstance(f, BrokenTooth) and f.width is None:
            whole.add((f.gear, f.tooth))
    for i, f in enumerate(train.faults):
        if (f.gear, f.tooth) in whole and not (isinstance(f, BrokenTooth) and f.width is None):
            raise InputError(f"faults[{i}].tooth", f.tooth,
                             f"tooth {f.tooth} of {f.gear} is broken over the whole face "
                             "by another fault: nothing is left to damage")
    seen = set()
    for i, f in enumerate(train.faults):
        if isinstance(f, BrokenTooth) and f.width is None:
            require((f.gear, f.tooth) not in seen, f"faults[{i}].tooth", f.tooth,
                    f"tooth {f.tooth} of {f.gear} is already broken")
            seen.add((f.gear, f.tooth))
    mod_gears = set()
    for i, m in enumerate(train.modifications):
        name = f"modifications[{i}]"
        require(m.gear in names, f"{name}.gear", m.gear, f"must be one of {names}")
        require(m.gear not in mod_gears, f"{name}.gear", m.gear,
                "give one [[modifications]] table per gear")
        mod_gears.add(m.gear)
        g = train.gear(m.gear)
        lo, hi = active_roll_range(train, m.gear)
        span = hi - lo
        for which in ("tip", "root"):
            length = getattr(m, f"{which}_relief_length")
            if getattr(m, f"{which}_relief") > 0:
                require(length <= span, f"{name}.{which}_relief_length",
                        f"{length * 1e3:.4g} mm", f"must be <= the active profile of "
                        f"{m.gear} ({span * 1e3:.4g} mm of roll length)")
        require(m.tip_relief_length * (m.tip_relief > 0) + m.root_relief_length
                * (m.root_relief > 0) <= span, f"{name}.root_relief_length",
                f"{m.root_relief_length * 1e3:.4g} mm",
                f"tip and root relief together must fit the active profile of {m.gear} "
                f"({span * 1e3:.4g} mm of roll length)")
        lim = MAX_DEVIATION_MODULES * g.normal_module
        for key in ("tip_relief", "root_relief", "crowning", "helix_slope", "pitch_errors"):
            v = max(np.atleast_1d(getattr(m, key)), key=abs, default=0.0)
            require(abs(v) <= lim, f"{name}.{key}", f"{v * 1e3:.4g} mm", f"must be <= "
                    f"{MAX_DEVIATION_MODULES:g} x the module of {m.gear} = {lim * 1e3:.4g} mm")
        if m.pitch_errors:
            require(len(m.pitch_errors) == g.teeth, f"{name}.pitch_errors",
                    f"{len(m.pitch_errors)} values", f"need one per tooth ({g.teeth} teeth "
                    f"of {m.gear})")


def _wear_profile(train: GearTrain, f: Wear, mesh: int, which: int):
    """(roll lengths, depths) of a wear fault on gear ``which`` of mesh ``mesh``."""
    g = train.pairs[mesh].driver if which == 1 else train.pairs[mesh].driven
    if not f.grown:
        rr = np.sqrt(np.maximum(np.asarray(f.radii) ** 2 - g.base_radius ** 2, 0.0))
        return rr, np.asarray(f.depths, dtype=float)
    return grown_wear(train, f, mesh, which)


def grown_wear(train: GearTrain, f: Wear, mesh: int, which: int):
    """Archard wear profile of ``f`` grown under the load of mesh ``mesh``.

    The load per unit face width along the line of action comes from the loaded contact
    analysis of the unworn mesh at the train's torque (:mod:`gearsim.stiffness.ltca`);
    the depth from :func:`gearsim.stiffness.wear.archard_wear`.

    Parameters
    ----------
    train : GearTrain
        The train.
    f : Wear
        A wear fault with ``coefficient`` and ``cycles``.
    mesh : int
        Mesh index.
    which : {1, 2}
        The worn gear in that mesh (driver / driven).

    Returns
    -------
    (ndarray, ndarray)
        Roll lengths on the worn gear [m] and wear depths [m].

    Raises
    ------
    InputError
        If the grown depth exceeds half the tooth thickness.
    """
    from gearsim.stiffness.contacts import contact_grid
    from gearsim.stiffness.ltca import loaded_contact
    from gearsim.stiffness.wear import archard_wear
    from gearsim.system.train import body_coupling, tooth_compliance

    pair = train.pairs[mesh]
    st = train.settings_of(mesh)
    force = train.static_mesh_force(mesh)
    grid = contact_grid(pair, settings=st, compliance=tooth_compliance(st.source), force=force,
                        coupling=body_coupling(st))
    lc = loaded_contact(grid, force)
    ll = lc.line_load.ravel()
    lpos = grid.l.ravel()
    on = ll > 0
    edges = np.linspace(pair.start_of_contact, pair.end_of_contact, 81)
    mid = 0.5 * (edges[1:] + edges[:-1])
    idx = np.clip(np.searchsorted(edges, lpos[on]) - 1, 0, 79)
    tot = np.bincount(idx, weights=ll[on], minlength=80)
    cnt = np.bincount(idx, minlength=80)
    load = np.where(cnt > 0, tot / np.maximum(cnt, 1), 0.0)
    depth = archard_wear(pair, which, mid, load, coefficient=f.coefficient, cycles=f.cycles)
    roll = mid if which == 1 else pair.line_length - mid
    order = np.argsort(roll)
    roll, depth = roll[order], np.asarray(depth)[order]
    g = pair.driver if which == 1 else pair.driven
    prof = ToothProfile(g)
    r = np.hypot(g.base_radius, roll)
    half = np.array([0.5 * prof.thickness_at_radius(float(x)) for x in r])
    bad = depth >= half
    if bad.any():
        j = int(np.argmax(bad))
        raise InputError("wear.cycles", f.cycles,
                         f"grows {depth[j] * 1e3:.4g} mm of wear at r = {r[j] * 1e3:.4g} mm "
                         f"on {g.name}, more than half the tooth thickness "
                         f"({half[j] * 1e3:.4g} mm): use fewer cycles or a smaller coefficient")
    return roll, depth


def mesh_flanks(train: GearTrain, mesh: int) -> tuple[FlankState, FlankState]:
    """What mesh ``mesh`` sees of the loaded flanks of its driver and driven gear.

    Parameters
    ----------
    train : GearTrain
        The train.
    mesh : int
        Mesh index (0 = mesh I).

    Returns
    -------
    (FlankState, FlankState)
        Driver, driven.
    """
    out = []
    for which, g in ((1, train.pairs[mesh].driver), (2, train.pairs[mesh].driven)):
        mod = next((m for m in train.modifications if m.gear == g.name), None)
        positions = None
        if mod is not None and mod.has_pitch_errors:
            positions = mod.tooth_positions(g.teeth, 2 * g.pitch_radius, g.normal_module)
        patches: dict[int, tuple] = {}
        wear: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        for f in train.faults:
            if f.gear != g.name:
                continue
            loaded = isinstance(f, BrokenTooth) or flank_side(train, f.gear, f.flank, mesh) == 1
            if not loaded:
                continue
            if isinstance(f, Wear):
                key = -1 if f.tooth is None else f.tooth
                wear[key] = _wear_profile(train, f, mesh, which)
                continue
            if isinstance(f, ChippedTip):
                new = f.patches(g.face_width, g.base_radius, tip_radius=g.tip_radius)
            else:
                new = f.patches(g.face_width, g.base_radius)
            patches[f.tooth] = patches.get(f.tooth, ()) + new
        out.append(FlankState(modification=mod, positions=positions, patches=patches,
                              wear=wear))
    return out[0], out[1]
