"""Cracked plates with known handbook K: the FE stress-intensity check specimens.

* Single edge crack of length ``a`` in a strip of width ``b`` and height ``2 H`` under
  uniform end tension ``sigma`` or pure bending (end traction
  ``sigma (1 - 2 x / b)``, x from the cracked edge; ``sigma = 6 M / b^2``), compared
  with :func:`gearsim.fracture.closed_forms.edge_crack_tension` and
  :func:`~gearsim.fracture.closed_forms.edge_crack_bending_polynomial` (Tada, Paris &
  Irwin).
* Centre crack of half length ``a`` inclined at ``beta`` in a square plate of
  half size ``L >> a`` under uniaxial tension ``sigma`` (normal to the x axis),
  compared with :func:`~gearsim.fracture.closed_forms.inclined_centre_crack`.

The plates carry self-equilibrated end tractions; rigid-body motion is removed by
three displacement components at two corner nodes (no reaction). Plane strain or
plane stress, P2 triangles (:class:`gearsim.fem.solve.ElasticModel`), meshed by
:func:`gearsim.fracture.mesh.mesh_cracked_polygon`, K by
:func:`gearsim.fracture.sif.interaction_integral`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require
from gearsim.fem.solve import ElasticModel
from gearsim.fracture.mesh import CrackPath, mesh_cracked_polygon
from gearsim.fracture.sif import StressIntensity, interaction_integral

__all__ = ["PlateResult", "edge_crack_plate", "inclined_crack_plate"]

#: Steel for the specimens (K of these traction problems does not depend on E, nu).
STEEL_E = 206e9
STEEL_NU = 0.3

#: Outer ring radius of the interaction integral over the tip element size [-]. The
#: error of K is dominated by the tip singularity, so the mesh is strongly graded
#: (tip size r_out / 50, growth 0.25): 12 divisions gave -1.1 %, 40 gave -0.5 %,
#: 120 gave -0.36 % against Tada at a/b = 0.6 in tension (docs/fracture.md).
TIP_DIVISIONS = 50.0


@dataclass(frozen=True)
class PlateResult:
    """FE stress intensity of a plate specimen.

    Parameters
    ----------
    sif
        K_I, K_II at the (right) tip.
    nodes, elements, dofs
        Mesh and problem size.
    h_tip
        Element size at the tip [m].
    seconds
        Wall time of mesh, solve and integral [s].
    """

    sif: StressIntensity
    nodes: int
    elements: int
    dofs: int
    h_tip: float
    seconds: float


def _plate(outline: np.ndarray, crack: CrackPath, hh: float, tractions: tuple,
           corners: list[tuple[tuple[float, float], tuple[int, ...]]], *, h: float,
           growth: float, r_out: float, refinement: float, plane: str,
           t0: float) -> PlateResult:
    """K at the end 1 of ``crack`` in the steel plate ``outline``, pulled by
    ``tractions`` (on y = hh, on y = -hh; :meth:`ElasticModel.traction_load`), the nodes
    nearest ``corners`` held in the listed components."""
    h_tip = r_out / (TIP_DIVISIONS * refinement)
    cm = mesh_cracked_polygon(outline, crack, h=h, h_tip=h_tip, growth=growth)
    model = ElasticModel(cm.p, cm.t, STEEL_E, STEEL_NU, plane=plane, order=2)
    top = model.mesh.facets_satisfying(lambda x: np.isclose(x[1], hh), True)
    bot = model.mesh.facets_satisfying(lambda x: np.isclose(x[1], -hh), True)
    f = model.traction_load(top, tractions[0]) + model.traction_load(bot, tractions[1])
    fixed = []
    for (x, y), comps in corners:
        node = int(np.argmin(np.hypot(cm.p[0] - x, cm.p[1] - y)))
        fixed.append(model.node_dofs(node)[list(comps)])
    u = model.solve(f, np.concatenate(fixed))
    tip, d = crack.tip_frame(1)
    sif = interaction_integral(model, u, tip, d, r_out=r_out)
    return PlateResult(sif=sif, nodes=cm.p.shape[1], elements=cm.t.shape[1], dofs=model.ndofs,
                       h_tip=h_tip, seconds=time.perf_counter() - t0)


def edge_crack_plate(a_over_b: float, *, load: str = "tension", width: float = 0.01,
                     height_ratio: float = 2.0, stress: float = 100e6,
                     refinement: float = 1.0, plane: str = "strain") -> PlateResult:
    """K_I of a single edge crack in a finite strip by FE.

    Parameters
    ----------
    a_over_b
        Crack length over width a / b [-] (0.05 to 0.8).
    load
        ``"tension"`` (uniform end stress) or ``"bending"`` (pure bending, outer-fibre
        stress ``stress`` on the cracked edge).
    width
        b [m].
    height_ratio
        Half height over width H / b [-] (>= 1; the handbook strip is infinitely long).
    stress
        Remote (or outer-fibre bending) stress sigma [Pa].
    refinement
        Mesh refinement factor: all element sizes are divided by it [-] (0.25 to 8).
    plane
        ``"strain"`` or ``"stress"`` (K does not depend on it here).

    Returns
    -------
    PlateResult
        K at the tip; compare with sigma sqrt(pi a) F(a/b).

    Raises
    ------
    InputError
        Parameters out of range.
    """
    require(0.05 <= a_over_b <= 0.8, "a_over_b", a_over_b, "must be in [0.05, 0.8]")
    require(load in ("tension", "bending"), "load", load, 'must be "tension" or "bending"')
    require(math.isfinite(width) and width > 0.0, "width", width, "must be > 0 m")
    require(1.0 <= height_ratio <= 10.0, "height_ratio", height_ratio, "must be in [1, 10]")
    require(math.isfinite(stress) and stress != 0.0, "stress", stress, "must be non-zero Pa")
    require(0.25 <= refinement <= 8.0, "refinement", refinement, "must be in [0.25, 8]")
    t0 = time.perf_counter()
    b = width
    a = a_over_b * b
    hh = height_ratio * b
    outline = np.array([[0.0, -hh], [b, -hh], [b, 0.0], [b, hh], [0.0, hh], [0.0, 0.0]])
    crack = CrackPath(points=((0.0, 0.0), (a, 0.0)), tips=(False, True))
    if load == "tension":
        def prof(x):
            return stress + 0.0 * x
    else:
        def prof(x):
            return stress * (1.0 - 2.0 * x / b)
    return _plate(outline, crack, hh, (lambda x, y: (0.0 * x, prof(x)),
                                       lambda x, y: (0.0 * x, -prof(x))),
                  [((b, -hh), (0, 1)), ((b, hh), (0,))], h=b / (6.0 * refinement),
                  growth=0.25, r_out=0.5 * min(a, b - a), refinement=refinement, plane=plane,
                  t0=t0)


def inclined_crack_plate(beta_deg: float, *, half_length: float = 1e-3,
                         size_ratio: float = 20.0, stress: float = 100e6,
                         refinement: float = 1.0, plane: str = "strain") -> PlateResult:
    """K_I, K_II of an inclined centre crack in a large square plate by FE.

    Parameters
    ----------
    beta_deg
        Angle between the crack line and the x axis [deg] (0 to 80); the tension acts
        along y, so beta = 0 is pure mode I.
    half_length
        Crack half length a [m].
    size_ratio
        Plate half size over a, L / a [-] (>= 5; the closed form is for an infinite
        plate).
    stress
        Remote tension sigma_yy [Pa].
    refinement
        Mesh refinement factor [-] (0.25 to 8).
    plane
        ``"strain"`` or ``"stress"``.

    Returns
    -------
    PlateResult
        K at the tip a (cos beta, sin beta); compare with sigma sqrt(pi a) (cos^2 beta,
        sin beta cos beta).

    Raises
    ------
    InputError
        Parameters out of range.
    """
    require(0.0 <= beta_deg <= 80.0, "beta_deg", beta_deg, "must be in [0, 80] deg")
    require(math.isfinite(half_length) and half_length > 0.0, "half_length", half_length,
            "must be > 0 m")
    require(5.0 <= size_ratio <= 100.0, "size_ratio", size_ratio, "must be in [5, 100]")
    require(math.isfinite(stress) and stress != 0.0, "stress", stress, "must be non-zero Pa")
    require(0.25 <= refinement <= 8.0, "refinement", refinement, "must be in [0.25, 8]")
    t0 = time.perf_counter()
    a = half_length
    ll = size_ratio * a
    beta = math.radians(beta_deg)
    d = np.array([math.cos(beta), math.sin(beta)])
    outline = np.array([[-ll, -ll], [ll, -ll], [ll, ll], [-ll, ll]])
    crack = CrackPath(points=(tuple(-a * d), tuple(a * d)), tips=(True, True))
    return _plate(outline, crack, ll, ((0.0, stress), (0.0, -stress)),
                  [((-ll, -ll), (0, 1)), ((ll, -ll), (1,))], h=ll / (3.0 * refinement),
                  growth=0.3, r_out=0.5 * a, refinement=refinement, plane=plane, t0=t0)
