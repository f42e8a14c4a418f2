"""Straightforward reference implementation of the tooth compliance (slow, for checks).

The equations of :mod:`gearsim.stiffness._kernels`, written independently in plain
Python and integrated with adaptive ``scipy.integrate.quad`` over the tooth height for
every contact point. It shares with the kernel only the tooth outline
(:class:`~gearsim.geometry.profile.ToothProfile`, checked on its own against the
analytic involute and ISO 21771 thicknesses in ``tests/test_geometry.py``) and the
published Sainsot table (:data:`gearsim.stiffness.tooth.SAINSOT`, checked against the
paper in ``tests/test_sainsot.py``). Computed here independently of the kernel and of
:mod:`gearsim.stiffness.crack`:

* the crack geometry (start point on the fillet by root finding on the fillet slope,
  tip, and the limiting-line range of seed eqs. 10-11: the sections from the tip height
  up to g_c, the first height above the tip where the outline's half width falls to
  h_c, found by scanning the outline and ``brentq``; the half width is not monotone
  on teeth whose root lies below the base circle, so the first crossing matters);
* the ``contact`` closure, by bisection on the extent of the load-carrying section
  instead of the kernel's closed form;
* the Sainsot foundation term, with the root half angle theta_f from the rack in
  closed form (below) instead of the generated outline.

theta_f in closed form: the lowest point of the rack tip round (normal-section abscissa
``u_C = p_n/4 + (h_fP - rho) tan(alpha_n) + rho / cos(alpha_n)`` from the middle of the
rack space) generates the root-circle end of the fillet when it crosses the pitch
point, so ``theta_f = u_C / (r cos(beta))`` (Litvin & Fuentes 2004, ch. 10: the
generated point is the one whose normal passes through the pitch point; at the lowest
point of the round the normal is the rack's depth direction).

Used by the tests as an oracle and by ``benchmarks/`` as the speed reference.

References
----------
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, J. Mech. Des. 126 (2004) 748-752.
.. [Tian2004] X. Tian, M.Sc. thesis, University of Alberta, 2004 (limiting line).
.. [Seed] H. Shi, W. Li, W. Zhou, Actuators 14 (2025) 292, eqs. 4-7 and 10-11.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from gearsim.errors import InputError
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.tooth import SAINSOT, ToothModel

__all__ = ["ReferenceCrack", "reference_compliance", "reference_crack", "root_half_angle"]

# indices of the kernel's crack record, only to read a record passed by old callers
_REC_ACTIVE, _REC_SIDE, _REC_HC, _REC_YLO, _REC_YHI = 0, 1, 2, 3, 4


@dataclass(frozen=True)
class ReferenceCrack:
    """Crack of one transverse section, as the reference uses it.

    Parameters
    ----------
    start
        Start point (x, y) on the fillet of the cracked flank [m].
    tip
        Tip (x, y) [m]; ``h_c = tip[0]``.
    side
        +1 if the cracked flank is the loaded one, -1 otherwise.
    top
        g_c, upper end of the cut sections [m].
    """

    start: tuple[float, float]
    tip: tuple[float, float]
    side: int
    top: float

    @property
    def h_c(self) -> float:
        """Distance of the limiting line from the tooth centre line [m]."""
        return self.tip[0]

    def cracked(self, x: float, y: float) -> bool:
        """Whether the section at height ``y`` with half width ``x`` is cut.

        Parameters
        ----------
        x
            Outline half width at that height [m].
        y
            Height on the centre line [m].

        Returns
        -------
        bool
            ``y_tip <= y <= g_c`` (limiting-line model, seed eqs. 10-11); ``x`` is not
            needed, it is accepted to keep the signature of a section test.
        """
        return self.tip[1] <= y <= self.top


def _fillet_tangent_angle(prof: ToothProfile, g: float) -> float:
    """Angle between the fillet tangent at ``g`` and the tooth centre line [rad]."""
    d = 1e-6
    x1, y1 = prof.fillet_point(g + d)
    x0, y0 = prof.fillet_point(g - d)
    return math.atan2(abs(x1 - x0), abs(y1 - y0))


def reference_crack(prof: ToothProfile, crack: Crack, depth: float, side: int
                    ) -> ReferenceCrack:
    """Crack start, tip and limiting line computed from the outline (no kernel helpers).

    Parameters
    ----------
    prof
        Outline of the cracked gear.
    crack
        The crack (angle ``nu`` to the centre line, start point).
    depth
        Crack depth q of this section [m] (> 0).
    side
        +1 crack on the loaded flank, -1 on the other one.

    Returns
    -------
    ReferenceCrack
        Start on the fillet (the 30 degree tangent point of ISO 6336-3 unless
        ``crack.start_radius`` is set), tip ``(x_s - q sin nu, y_s - q cos nu)``.

    Raises
    ------
    InputError
        If the tip would cross the tooth centre line.
    """
    an = prof.gear.normal_pressure_angle
    lo, hi = an + 1e-9, 0.5 * math.pi - 1e-9
    if crack.start_radius is None:
        target = math.radians(30.0)
        g = brentq(lambda s: _fillet_tangent_angle(prof, s) - target, lo, hi, xtol=1e-15)
    else:
        g = brentq(lambda s: math.hypot(*prof.fillet_point(s)) - crack.start_radius, lo, hi,
                   xtol=1e-15)
    xs, ys = prof.fillet_point(g)
    xt = xs - depth * math.sin(crack.angle)
    yt = ys - depth * math.cos(crack.angle)
    if xt <= 0.0:
        raise InputError("crack.depth", depth, "the crack tip crosses the tooth centre line")
    return ReferenceCrack(start=(xs, ys), tip=(xt, yt), side=int(side),
                          top=_limiting_top(prof, yt, xt))


def _limiting_top(prof: ToothProfile, y_tip: float, h_c: float) -> float:
    """First height above ``y_tip`` where the outline half width falls to ``h_c`` [m]."""
    gear = prof.gear
    pieces = ((prof.fillet_point, 0.5 * math.pi, gear.normal_pressure_angle),
              (prof.involute_point, prof.form_radius, gear.tip_radius))
    for fun, pa, pb in pieces:
        ps = np.linspace(pa, pb, 3001)
        prev = None
        for p in ps:
            x, y = fun(p)
            if y > y_tip and x <= h_c:
                if prev is None:  # already at or below h_c at the piece start
                    return y
                p_cut = brentq(lambda s, f=fun: f(s)[0] - h_c, prev, p, xtol=1e-15)
                return fun(p_cut)[1]
            prev = p if y > y_tip else None
    return prof.involute_point(gear.tip_radius)[1]


def root_half_angle(tm: ToothModel) -> float:
    """Half angle theta_f of the tooth at the root circle, closed form [rad].

    Parameters
    ----------
    tm
        Tooth model (its gear's rack and pitch radius are used).

    Returns
    -------
    float
        theta_f = u_C / (r cos(beta)) (module docstring).

    Examples
    --------
    z 19, m 3.2 mm, standard rack: u_C = 2.5133 + 1.0133 + 1.2941 = 4.8206 mm,
    theta_f = 4.8206 / 30.4 = 0.15857 rad.

    >>> from gearsim.geometry.gear import Gear
    >>> round(root_half_angle(ToothModel(Gear(teeth=19, normal_module=3.2e-3))), 5)
    0.15857
    """
    g = tm.gear
    m = g.normal_module
    an = g.normal_pressure_angle
    rho = g.fillet_radius_coefficient * m
    u_c = math.pi * m / 4.0 + (g.dedendum_coefficient * m - rho) * math.tan(an) + rho / math.cos(an)
    return u_c / (g.pitch_radius * math.cos(g.helix_angle))


def _foundation(tm: ToothModel, a1: float, yq: float) -> float:
    """Sainsot et al. (2004) fillet-foundation compliance, L = 1 m [m/N]."""
    gear = tm.gear
    th = root_half_angle(tm)
    rf = gear.root_radius
    h_f = rf / gear.bore_radius_value
    lmpq = []
    for key in "LMPQ":
        a, b, c, d, e, f = SAINSOT[key]
        lmpq.append(a / th**2 + b * h_f**2 + c * h_f / th + d / th + e * h_f + f)
    sf = 2.0 * rf * th
    uf = yq - rf * math.cos(th)
    ratio = uf / sf
    return (math.cos(a1) ** 2 / gear.material.youngs_modulus) * (
        lmpq[0] * ratio**2 + lmpq[1] * ratio + lmpq[2] * (1.0 + lmpq[3] * math.tan(a1) ** 2))


def _contact_extent(h: float, hc: float, n: float, ms: float) -> float:
    """Extent c of the load-carrying section [-h, c] by bisection on sigma(c) = 0."""

    def sigma_at_edge(c: float) -> float:
        w = c + h
        s0 = 0.5 * (c - h)
        return n / w + (ms - s0 * n) * (c - s0) / (w**3 / 12.0)

    if sigma_at_edge(h) <= 0.0:
        return h
    if sigma_at_edge(hc) >= 0.0:
        return hc
    lo, hi = hc, h
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if sigma_at_edge(mid) < 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _from_record(prof: ToothProfile, record: np.ndarray) -> ReferenceCrack | None:
    """A kernel record (old calling convention) as a :class:`ReferenceCrack`."""
    if record is None or record[_REC_ACTIVE] <= 0:
        return None
    return ReferenceCrack(start=(math.nan, math.nan),
                          tip=(float(record[_REC_HC]), float(record[_REC_YLO])),
                          side=int(record[_REC_SIDE]), top=float(record[_REC_YHI]))


def reference_compliance(tm: ToothModel, radius: float, record: np.ndarray | None = None,
                         *, crack: Crack | None = None, depth: float | None = None,
                         side: int = 1, epsrel: float = 1e-10) -> np.ndarray:
    """Compliances (bending, shear, axial, foundation) at one contact radius, L = 1 m.

    Parameters
    ----------
    tm
        Tooth model (gear, plane, closure).
    radius
        Contact radius on the involute [m].
    record
        Kernel crack record (``_kernels.C_*`` layout) or ``None``: the old calling
        convention, kept for the benchmarks; only its h_c, tip height and side are
        read. For an independent check pass ``crack`` instead.
    crack
        The crack, whose geometry is then computed here (:func:`reference_crack`).
    depth
        Crack depth of this section [m]; default ``crack.depth``.
    side
        +1 crack on the loaded flank, -1 on the other flank.
    epsrel
        Relative tolerance of ``quad``.

    Returns
    -------
    ndarray, shape (4,)
        Compliances [m/N] for a face width of 1 m (seed eqs. 4-7).

    References
    ----------
    Seed eqs. 4-7 (beam terms; axial term with E, see :mod:`gearsim.stiffness._kernels`),
    Sainsot, Velex & Duverger (2004) for the foundation, seed eqs. 10-11 for the crack.
    """
    prof = tm.profile
    gear = tm.gear
    e_mod, g_mod = tm.beam_moduli
    rb = gear.base_radius
    xc, yc = prof.involute_point(radius)
    a1 = math.acos(rb / radius) - math.atan2(xc, yc)
    fb, fa = math.cos(a1), math.sin(a1)
    if crack is not None:
        q = crack.depth if depth is None else depth
        rc = reference_crack(prof, crack, q, side) if q > 0 else None
    else:
        rc = _from_record(prof, record)
    an = gear.normal_pressure_angle
    rf = prof.form_radius

    def energies(x: float, y: float) -> tuple[float, float, float]:
        mom = fb * (yc - y) - fa * xc
        if rc is not None and rc.cracked(x, y):
            hc = rc.h_c
            w = hc + x
            shear = 1.2 * fb**2 / (g_mod * w)
            if tm.closure == "open":
                return mom**2 / (e_mod * w**3 / 12.0), shear, fa**2 / (e_mod * w)
            n = -fa
            ms = rc.side * mom
            c = _contact_extent(x, hc, n, ms)
            we = c + x
            me = ms - 0.5 * (c - x) * n
            return me**2 / (e_mod * we**3 / 12.0), shear, n**2 / (e_mod * we)
        w = 2.0 * x
        return mom**2 / (e_mod * w**3 / 12.0), 1.2 * fb**2 / (g_mod * w), fa**2 / (e_mod * w)

    def dy(fun, p: float, h: float) -> float:
        return (fun(p + h)[1] - fun(p - h)[1]) / (2 * h)

    pieces = [(prof.fillet_point, 0.5 * math.pi, an, 1e-7)]
    if radius > rf:
        pieces.append((prof.involute_point, rf, radius, 1e-7 * gear.pitch_radius))
    out = np.zeros(4)
    for fun, pa, pb, h in pieces:
        lo, hi = min(pa, pb), max(pa, pb)
        brk = []
        if rc is not None:
            # where the piece crosses the tip height and g_c (height grows along a piece)
            for value in (rc.tip[1], rc.top):
                f_lo = fun(lo)[1] - value
                f_hi = fun(hi)[1] - value
                if f_lo * f_hi < 0.0:
                    brk.append(brentq(lambda p, v=value, f=fun: f(p)[1] - v, lo, hi,
                                      xtol=1e-15))
        for comp in range(3):
            def integrand(p: float, comp: int = comp, fun=fun, h: float = h) -> float:
                x, y = fun(p)
                return energies(x, y)[comp] * abs(dy(fun, p, h))

            val, _ = quad(integrand, lo, hi, points=brk or None, epsabs=0.0, epsrel=epsrel,
                          limit=200)
            out[comp] += val
    out[3] = _foundation(tm, a1, yc - xc * math.tan(a1))
    return out
