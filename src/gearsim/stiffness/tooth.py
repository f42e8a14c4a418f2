"""Single-tooth compliance by the potential energy method (Python layer over the kernels).

Equations: see :mod:`gearsim.stiffness._kernels` and ``docs/stiffness.md``.

References
----------
.. [Yang1987] D. C. H. Yang, J. Y. Lin, Hertzian damping, tooth friction and bending
   elasticity in gear impact dynamics, J. Mech. Trans. Autom. Des. 109 (1987) 189-196.
.. [Tian2004] X. Tian, Dynamic simulation for system response of gearbox including
   localized gear faults, M.Sc. thesis, University of Alberta, 2004.
.. [Chen2011] Z. Chen, Y. Shao, Dynamic simulation of spur gear with tooth root crack
   propagating along tooth width and crack depth, Eng. Fail. Anal. 18 (2011) 2149-2164.
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, Contribution of gear body to tooth
   deflections - a new bidimensional analytical formula, J. Mech. Des. 126 (2004) 748-752.
.. [YangSun1985] D. C. H. Yang, Z. S. Sun, A rotary model for spur gear dynamics,
   J. Mech. Trans. Autom. Des. 107 (1985) 529-535 (Hertzian line-contact stiffness).
.. [Johnson1985] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985,
   ch. 4 and 5 (two-dimensional Hertz contact of cylinders).
.. [Seed] H. Shi, W. Li, W. Zhou, Actuators 14 (2025) 292, eqs. 3-11.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numba
import numpy as np

from gearsim.errors import require, warn_model_range
from gearsim.geometry.gear import Gear, Material
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness import _kernels as K

__all__ = [
    "SAINSOT",
    "SAINSOT_RANGE",
    "ToothModel",
    "beam_moduli",
    "gauss_rule",
    "edge_truncation",
    "hertz_stiffness",
    "line_contact_compliance",
    "sainsot_coefficients",
    "sainsot_range_check",
]

# Sainsot, Velex & Duverger (2004), Table 1: X = A/th^2 + B h^2 + C h/th + D/th + E h + F
SAINSOT: dict[str, tuple[float, float, float, float, float, float]] = {
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}


#: Range of the FE gears Sainsot et al. (2004) fitted their coefficients on:
#: h_f = r_f / r_int in [1.4, 7], theta_f in [0.01, 0.12] rad (as transcribed with the
#: coefficient table in ROSS, petrobras/ross, ``ross/gear_element.py``; docs/references.md
#: "Sainsot foundation coefficients"). Outside it the fit is extrapolated: a
#: :class:`gearsim.errors.ModelRangeWarning` names the gear and the quantity.
SAINSOT_RANGE = {"h_f": (1.4, 7.0), "theta_f": (0.01, 0.12)}


def sainsot_range_check(name: str, h_f: float, theta_f: float) -> list[str]:
    """Warn when the Sainsot formula is used outside its fitted range.

    Parameters
    ----------
    name
        Gear name (for the message).
    h_f
        r_f / r_int [-].
    theta_f
        Half angle of the tooth at the root circle [rad].

    Returns
    -------
    list of str
        The messages warned (empty inside the range); each is also issued as a
        :class:`gearsim.errors.ModelRangeWarning`.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     msgs = sainsot_range_check("pinion", 2.0, 0.1586)
    >>> print(msgs[0])  # doctest: +NORMALIZE_WHITESPACE
    Sainsot foundation of gear pinion: theta_f = 0.1586 rad outside the fitted range
    [0.01, 0.12] rad (the fit is extrapolated)
    """
    out = []
    for key, value, unit in (("h_f", h_f, ""), ("theta_f", theta_f, " rad")):
        lo, hi = SAINSOT_RANGE[key]
        if not lo <= value <= hi:
            out.append(f"Sainsot foundation of gear {name}: {key} = {value:.4g}{unit} outside "
                       f"the fitted range [{lo:g}, {hi:g}]{unit} (the fit is extrapolated)")
    for msg in out:
        warn_model_range(msg)
    return out


def sainsot_coefficients(h_f: float, theta_f: float) -> np.ndarray:
    """L*, M*, P*, Q* of the fillet-foundation formula [-].

    Each coefficient is the polynomial fit of Sainsot et al.
    X = A/theta_f^2 + B h_f^2 + C h_f/theta_f + D/theta_f + E h_f + F with the
    (A .. F) rows of :data:`SAINSOT`.

    Parameters
    ----------
    h_f
        Ratio of root radius to bore radius r_f / r_int [-].
    theta_f
        Half angle of the tooth at the root circle [rad].

    Returns
    -------
    ndarray, shape (4,)
        (L*, M*, P*, Q*) [-].

    References
    ----------
    Sainsot, Velex & Duverger (2004), eq. (6) and Table 1; seed eq. (7). Table
    reproduced in docs/references.md, "Sainsot foundation coefficients".

    Examples
    --------
    At h_f = 2, theta_f = 0.1 rad, by hand from the table:
    L* = -5.574e-3 - 7.9944e-3 - 4.603e-3 + 0.047702 + 0.0542 + 6.8045 = 6.88823.

    >>> [round(float(v), 5) for v in sainsot_coefficients(2.0, 0.1)]
    [6.88823, 1.13979, 2.72676, 0.49626]
    """
    out = np.empty(4)
    for i, key in enumerate("LMPQ"):
        a, b, c, d, e, f = SAINSOT[key]
        out[i] = a / theta_f**2 + b * h_f**2 + c * h_f / theta_f + d / theta_f + e * h_f + f
    return out


def hertz_stiffness(m1: Material, m2: Material, length: float) -> float:
    """Hertzian contact stiffness of a line contact.

    k_h = pi L / (2 [(1 - nu1^2)/E1 + (1 - nu2^2)/E2]); for equal materials this is the
    seed's k_h = pi E L / (4 (1 - nu^2)) (Yang & Sun 1985; seed section 2). It does
    not depend on the load or the curvature radii (the linearised Hertz line contact).

    Parameters
    ----------
    m1, m2
        Materials of the two gears (:class:`~gearsim.geometry.gear.Material`).
    length
        Contact line length L [m].

    Returns
    -------
    float
        k_h [N/m].

    References
    ----------
    Yang & Sun (1985); Johnson (1985), ch. 5 (Hertz contact of cylinders).

    Examples
    --------
    Steel (E 206 GPa, nu 0.3) over the Table-1 face width 150 mm:
    pi 206e9 0.15 / (4 x 0.91) = 2.6669e10 N/m.

    >>> from gearsim.geometry.gear import Material
    >>> steel = Material()
    >>> round(hertz_stiffness(steel, steel, 0.15) / 1e10, 4)
    2.6669
    """
    s = (1 - m1.poisson_ratio**2) / m1.youngs_modulus + (1 - m2.poisson_ratio**2) / m2.youngs_modulus
    return math.pi * length / (2.0 * s)


def edge_truncation(offset: np.ndarray) -> np.ndarray:
    """Extra approach of a 2D Hertz line contact cut off by a tooth's tip edge [-].

    Two bodies with relative radius R pressed by w per unit length, one of whose
    surfaces ends at a sharp edge beyond which it falls away (the tip corner: the tip
    land meets the involute at 90 deg + the tip pressure angle). The gap is
    h(x) = ((x - e)^2 - max(e, 0)^2) / (2 R) for x <= 0 (edge at x = 0, pressure only
    there): e < 0 is an involute contact whose Hertz centre lies -e inside the edge,
    e > 0 the tip corner itself touching a flank tilted by theta = e / R against it (no
    gap at the edge). Both bodies are taken as half-planes, as in the untruncated
    contact (Johnson 1985, ch. 2 and 5). In units of the untruncated half width
    a = sqrt(4 w R / (pi E*)) (``offset`` = e / a), the pressure solving the contact
    equations (finite Hilbert transform, bounded at the far end, square-root singular
    at the edge; Muskhelishvili 1953, section 88) is

        p(x) = (2 w / (pi a)) sqrt((x + L) / -x) (L / 2 + e - x),  -L <= x <= 0,
        L = (2 / 3) (sqrt(e^2 + 3) - e)   (from the total load w),

    which is Hertz's at e = -1 (L = 2) and exists for e > -1; for e <= -1 the whole
    Hertz strip lies inside the edge. The approach of two points deep inside the bodies
    then exceeds the untruncated one (:func:`line_contact_compliance`) by
    (2 / (pi E*)) w G with

        G(e) = lambda(e) - max(e, 0)^2 - (1/2 + ln 2),
        lambda(e) = (L + e)^2 - ln L - L^2 (5/8 - (3/2) ln 2) - L e (1 - 2 ln 2),

    lambda being the constant of the integrated contact equation
    int p ln|x - s| ds / w = (x - e)^2 - lambda on the contact (the Beta-function
    integrals of sqrt(t / (1 - t)) ln t); G(-1) = 0, G(0) = ln sqrt(3), G grows like
    ln(e) for large e (the contact shrinks to the edge). A derivation, and a check
    against a numerical solution of the contact problem, are in docs/stiffness.md,
    section 4c ("The tip edge").

    Parameters
    ----------
    offset : ndarray
        Signed offset of the untruncated Hertz centre beyond the edge over the
        untruncated half width, e / a [-].

    Returns
    -------
    ndarray
        G [-] (0 where ``offset`` <= -1), the shape of ``offset``.

    References
    ----------
    K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, ch. 2 (line
    loading of a half-plane) and ch. 5 (non-Hertzian contact); N. I. Muskhelishvili,
    Singular Integral Equations, Noordhoff, 1953, section 88 (inversion of the finite
    Hilbert transform).

    Examples
    --------
    >>> round(float(edge_truncation(0.0)), 6), round(math.log(math.sqrt(3.0)), 6)
    (0.549306, 0.549306)
    >>> float(edge_truncation(-1.5))
    0.0
    """
    e = np.maximum(np.asarray(offset, dtype=float), -1.0)
    big_l = (2.0 / 3.0) * (np.sqrt(e * e + 3.0) - e)
    ln2 = math.log(2.0)
    lam = ((big_l + e) ** 2 - np.log(big_l) - big_l**2 * (0.625 - 1.5 * ln2)
           - big_l * e * (1.0 - 2.0 * ln2))
    return np.maximum(lam - np.maximum(e, 0.0) ** 2 - (0.5 + ln2), 0.0)


def line_contact_compliance(load: np.ndarray, rho1: np.ndarray, rho2: np.ndarray,
                            depth1: np.ndarray, depth2: np.ndarray, m1: Material,
                            m2: Material, plane: str = "stress",
                            edge: np.ndarray | None = None) -> np.ndarray:
    """Compliance of a 2D Hertz line contact up to points inside both bodies [m/(N/m)].

    The approach of two points at depths d_1, d_2 below the contact of two cylinders
    pressed by a load w per unit length is the integral of the axis strain of the Hertz
    line contact (Johnson 1985, section 5.6, eq. 5.79; the local term of Weber &
    Banaschek 1953): per body, in plane strain

        delta_i / w = 2 (1 - nu_i^2) / (pi E_i) [ln(2 d_i / a) - nu_i / (2 (1 - nu_i))],

    in plane stress (the plane of the PE slice model) 2 / (pi E_i) [ln(2 d_i / a) - nu_i / 2],
    with the half width a = sqrt(4 w R / (pi E*)), 1/R = 1/rho_1 + 1/rho_2,
    1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2 (plane strain) or 1/E_1 + 1/E_2 (plane
    stress). Unlike the load-independent k_h of :func:`hertz_stiffness`, it grows with
    ln(1 / w) and with the depth of the points: it is the contact compliance of the same
    2D problem the FE gear pair solves (docs/fem.md, "Gear pair in contact"), which puts
    it at 3.8-4.4 times 1 / k_h per unit width on the 19/48 pair.

    Parameters
    ----------
    load
        Normal load per unit contact length w > 0 [N/m].
    rho1, rho2
        Radii of curvature of the two profiles at the contact [m] (on the line of action:
        l and L - l).
    depth1, depth2
        Distance from the contact to the point of each tooth where its deflection is
        taken [m] (the PE beam: the tooth centre line along the load line).
    m1, m2
        Materials.
    plane
        ``"stress"`` or ``"strain"``.
    edge : ndarray, optional
        Signed offset of the Hertz centre beyond the nearer tip edge of either profile
        [m] (negative: the edge lies inside the contact's reach from the centre; see
        :func:`edge_truncation`). Adds (2 / (pi E*)) G(edge / a): the contact cut off by
        the tip corner. None: no edge (the profiles continue).

    Returns
    -------
    ndarray
        Approach per unit load per unit length [m/(N/m)], broadcast shape.

    References
    ----------
    K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, ch. 4-5;
    C. Weber, K. Banaschek, Formanderung und Profilruecknahme bei gerad- und
    schraegverzahnten Raedern, Schriftenreihe Antriebstechnik 11, Vieweg, 1953.

    Examples
    --------
    Steel discs in plane stress, w = 200 kN/m, rho 20 mm and 30 mm, depths 2.5 mm:
    R = 12 mm, E* = 103 GPa, a = sqrt(4 x 2e5 x 0.012 / (pi x 1.03e11)) = 172.2 um,
    per body 2 / (pi x 2.06e11) (ln(5e-3 / 1.7224e-4) - 0.15) = 0.9946e-11, both 1.989e-11.

    >>> from gearsim.geometry.gear import Material
    >>> st = Material()
    >>> c = line_contact_compliance(2e5, 0.02, 0.03, 2.5e-3, 2.5e-3, st, st)
    >>> round(float(c) * 1e11, 3)
    1.989
    """
    require(plane in ("stress", "strain"), "stiffness.plane", plane,
            'must be "stress" or "strain"')
    w = np.asarray(load, dtype=float)
    r = 1.0 / (1.0 / np.asarray(rho1, dtype=float) + 1.0 / np.asarray(rho2, dtype=float))
    out = 0.0
    e_inv = 0.0
    terms = []
    for m, d in ((m1, depth1), (m2, depth2)):
        e, nu = m.youngs_modulus, m.poisson_ratio
        if plane == "strain":
            e_inv += (1 - nu**2) / e
            terms.append((2 * (1 - nu**2) / (math.pi * e), nu / (2 * (1 - nu)), d))
        else:
            e_inv += 1.0 / e
            terms.append((2 / (math.pi * e), 0.5 * nu, d))
    a = np.sqrt(4.0 * w * r * e_inv / math.pi)
    for scale, shift, d in terms:
        out = out + scale * (np.log(2.0 * np.asarray(d, dtype=float) / a) - shift)
    if edge is not None:
        out = out + (2.0 / math.pi) * e_inv * edge_truncation(np.asarray(edge, dtype=float) / a)
    return out


@lru_cache(maxsize=16)
def gauss_rule(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1] (numpy.polynomial.legendre).

    Parameters
    ----------
    n
        Number of nodes.

    Returns
    -------
    nodes, weights : ndarray
        Shape (n,) each; the weights sum to 2.
    """
    x, w = np.polynomial.legendre.leggauss(n)
    return x, w


def beam_moduli(material, plane: str) -> tuple[float, float]:
    """(E_eff, G) of the beam energies of a tooth [Pa].

    Parameters
    ----------
    material : Material
        The tooth's material.
    plane : {"stress", "strain"}
        Plane assumption: E, or E / (1 - nu^2) in plane strain.

    Returns
    -------
    tuple of float
        E_eff and the shear modulus G [Pa].
    """
    e = material.youngs_modulus
    if plane == "strain":
        e = e / (1.0 - material.poisson_ratio**2)
    return e, material.shear_modulus

@dataclass(frozen=True)
class ToothModel:
    """Everything the compliance kernel needs for one gear.

    Parameters
    ----------
    gear
        The gear.
    plane
        ``"stress"`` (beam terms with E, as the seed) or ``"strain"`` (E / (1 - nu^2)).
    gauss_points
        Nodes of the Gauss-Legendre rule on each integration piece.
    closure
        ``"open"`` or ``"contact"`` crack-face model.

    Raises
    ------
    InputError
        If ``plane``, ``closure`` or ``gauss_points`` (2 .. 200) is invalid.

    References
    ----------
    Yang & Lin (1987), Tian (2004) and Chen & Shao (2011) for the beam terms; Sainsot,
    Velex & Duverger (2004) for the foundation; seed eqs. 3-8.

    Examples
    --------
    Plane strain divides E of the beam terms by 1 - nu^2 and leaves shear and
    foundation alone, so the bending compliance ratio is 1 - 0.3^2 = 0.91:

    >>> from gearsim.geometry.gear import Gear
    >>> g = Gear(teeth=19, normal_module=3.2e-3, face_width=0.016)
    >>> c_stress = ToothModel(g, plane="stress").compliance([0.031])
    >>> c_strain = ToothModel(g, plane="strain").compliance([0.031])
    >>> round(float(c_strain[0, 0] / c_stress[0, 0]), 12)
    0.91
    """

    gear: Gear
    plane: str = "stress"
    gauss_points: int = 16
    closure: str = "contact"

    def __post_init__(self) -> None:
        require(self.plane in ("stress", "strain"), "stiffness.plane", self.plane,
                'must be "stress" or "strain"')
        require(self.closure in ("open", "contact"), "stiffness.closure", self.closure,
                'must be "open" or "contact"')
        require(isinstance(self.gauss_points, int) and 2 <= self.gauss_points <= 200,
                "stiffness.gauss_points", self.gauss_points, "must be an integer in [2, 200]")

    @cached_property
    def profile(self) -> ToothProfile:
        """Tooth outline of the gear (:class:`ToothProfile`)."""
        return ToothProfile(self.gear)

    @property
    def beam_moduli(self) -> tuple[float, float]:
        """(E_eff, G) of the beam terms [Pa]."""
        return beam_moduli(self.gear.material, self.plane)

    @cached_property
    def sainsot(self) -> np.ndarray:
        """(L*, M*, P*, Q*) of this gear, h_f = r_f / bore radius [-]."""
        prof = self.profile
        h_f = self.gear.root_radius / self.gear.bore_radius_value
        sainsot_range_check(self.gear.name, h_f, prof.root_half_angle)
        return sainsot_coefficients(h_f, prof.root_half_angle)

    @property
    def model_code(self) -> int:
        """Closure code of the kernel (``MODEL_OPEN`` or ``MODEL_CONTACT``)."""
        return K.MODEL_OPEN if self.closure == "open" else K.MODEL_CONTACT

    def compliance(self, radii: np.ndarray, crack_records: np.ndarray | None = None,
                   *, width: float = 1.0) -> np.ndarray:
        """Tooth compliances at contact radii, columns (bending, shear, axial, foundation).

        Parameters
        ----------
        radii
            Contact radii on the involute [m], shape (n,).
        crack_records
            Crack records, shape (n, C_SIZE) or (C_SIZE,) for all; ``None`` = healthy.
        width
            Face width L carried by the tooth [m].

        Returns
        -------
        ndarray, shape (n, 4)
            Compliances [m/N] (seed eqs. 4-7), each 1/k for the given width.
        """
        r = np.ascontiguousarray(np.atleast_1d(radii), dtype=float)
        if crack_records is None:  # a healthy tooth: the same for every case of a study
            return _healthy_compliance(self, r.tobytes()) / width
        return self._batch(r, _broadcast_records(crack_records, r.shape[0])) / width

    def _batch(self, r: np.ndarray, records: np.ndarray) -> np.ndarray:
        """The compiled kernel at radii ``r`` (n,) with crack records (n, C_SIZE), L = 1 m."""
        e, g = self.beam_moduli
        nodes, weights = gauss_rule(self.gauss_points)
        out = np.empty((r.shape[0], 4))
        args = (self.profile.packed, r, records, self.model_code, e, g,
                self.gear.material.youngs_modulus, self.sainsot, nodes, weights, out)
        threads = numba.get_num_threads()
        if threads > 1 and r.shape[0] >= THREADED_MIN_RADII:
            return K.tooth_compliance_batch_threads(*args, threads)
        return K.tooth_compliance_batch(*args)


#: Radii from which a batch runs on numba's threads: a thread's share of a smaller batch
#: (about 5 us a radius) is not worth waking the others for.
THREADED_MIN_RADII = 256

#: Healthy-tooth compliance tables kept per process (:func:`_healthy_compliance`).
HEALTHY_CACHE_SIZE = 32


@lru_cache(maxsize=HEALTHY_CACHE_SIZE)
def _healthy_compliance(model: ToothModel, radii: bytes) -> np.ndarray:
    """Compliances of the healthy tooth of ``model`` at the radii packed in ``radii``.

    The cases of a study crack one gear at different depths; the healthy teeth of every
    gear (and of the cracked gear) load at the same radii in each case, so their tables
    are computed once per process. The key is the model's value (gear, plane, quadrature,
    closure, all frozen) and the radii's bytes; the array is read-only (callers get
    ``table / width``, a new array).

    Parameters
    ----------
    model : ToothModel
        The tooth.
    radii : bytes
        ``float64`` contact radii [m] (``ndarray.tobytes()``).

    Returns
    -------
    ndarray, shape (n, 4)
        As :meth:`ToothModel.compliance` with ``width = 1``.
    """
    r = np.frombuffer(radii, dtype=float).copy()  # writeable: the kernel's compiled signature
    out = model._batch(r, np.zeros((r.shape[0], K.C_SIZE)))
    out.flags.writeable = False
    return out


def _broadcast_records(records: np.ndarray | None, n: int) -> np.ndarray:
    if records is None:
        return np.zeros((n, K.C_SIZE))
    rec = np.asarray(records, dtype=float)
    if rec.ndim == 1:
        rec = np.broadcast_to(rec, (n, K.C_SIZE))
    return np.ascontiguousarray(rec)
