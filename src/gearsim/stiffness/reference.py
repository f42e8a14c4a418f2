"""Straightforward reference implementation of the tooth compliance (slow, for checks).

The same equations as :mod:`gearsim.stiffness._kernels`, written independently in plain
Python and integrated with adaptive ``scipy.integrate.quad`` over the tooth height for
every contact point. The ``contact`` closure is solved here by bisection on the extent
of the load-carrying section instead of the kernel's closed form. Used by the tests as
an oracle and by ``benchmarks/`` as the speed reference.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad

from gearsim.stiffness import _kernels as K
from gearsim.stiffness.tooth import ToothModel

__all__ = ["reference_compliance"]


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


def reference_compliance(tm: ToothModel, radius: float, record: np.ndarray | None = None,
                         *, epsrel: float = 1e-10) -> np.ndarray:
    """Compliances (bending, shear, axial, foundation) at one contact radius, L = 1 m.

    Parameters
    ----------
    tm
        Tooth model (gear, plane, closure).
    radius
        Contact radius on the involute [m].
    record
        Crack record (``K.C_*`` layout) or ``None``.
    epsrel
        Relative tolerance of ``quad``.
    """
    prof = tm.profile
    gear = tm.gear
    e_mod, g_mod = tm.beam_moduli
    rb = gear.base_radius
    xc, yc = prof.involute_point(radius)
    a1 = math.acos(rb / radius) - math.atan2(xc, yc)
    fb, fa = math.cos(a1), math.sin(a1)
    cracked_on = record is not None and record[K.C_ACTIVE] > 0
    an = gear.normal_pressure_angle
    rf = prof.form_radius

    def energies(x: float, y: float) -> tuple[float, float, float]:
        mom = fb * (yc - y) - fa * xc
        if cracked_on and record[K.C_YLO] <= y <= record[K.C_YHI]:
            hc = record[K.C_HC]
            w = hc + x
            shear = 1.2 * fb**2 / (g_mod * w)
            if tm.closure == "open":
                return mom**2 / (e_mod * w**3 / 12.0), shear, fa**2 / (e_mod * w)
            n = -fa
            ms = record[K.C_SIDE] * mom
            c = _contact_extent(x, hc, n, ms)
            we = c + x
            me = ms - 0.5 * (c - x) * n
            return me**2 / (e_mod * we**3 / 12.0), shear, n**2 / (e_mod * we)
        w = 2.0 * x
        return mom**2 / (e_mod * w**3 / 12.0), 1.2 * fb**2 / (g_mod * w), fa**2 / (e_mod * w)

    def fillet(g: float) -> tuple[float, float]:
        return prof.fillet_point(g)

    def dy(fun, p: float, h: float) -> float:
        return (fun(p + h)[1] - fun(p - h)[1]) / (2 * h)

    pieces = [(fillet, 0.5 * math.pi, an, 1e-7)]
    if radius > rf:
        pieces.append((prof.involute_point, rf, radius, 1e-7 * gear.pitch_radius))
    out = np.zeros(4)
    for fun, pa, pb, h in pieces:
        brk = []
        if cracked_on:
            for seg_key, p_key in ((K.C_SEGLO, K.C_PLO), (K.C_SEGHI, K.C_PHI)):
                seg = int(record[seg_key])
                p = record[p_key]
                if (seg == 0) == (fun is fillet) and min(pa, pb) < p < max(pa, pb):
                    brk.append(p)
        for comp in range(3):
            def integrand(p: float, comp: int = comp, fun=fun, h: float = h) -> float:
                x, y = fun(p)
                return energies(x, y)[comp] * abs(dy(fun, p, h))

            lo, hi = min(pa, pb), max(pa, pb)
            val, _ = quad(integrand, lo, hi, points=brk or None, epsabs=0.0, epsrel=epsrel,
                          limit=200)
            out[comp] += val
    # Sainsot et al. 2004 (seed eq. 7)
    sf = 2.0 * gear.root_radius * prof.root_half_angle
    uf = (yc - xc * math.tan(a1)) - prof.root_height
    lmpq = tm.sainsot
    out[3] = (fb**2 / gear.material.youngs_modulus) * (
        lmpq[0] * (uf / sf) ** 2 + lmpq[1] * (uf / sf) + lmpq[2] * (1 + lmpq[3] * math.tan(a1) ** 2))
    return out
