"""FE stress intensity factors (interaction integral) against handbook closed forms.

Issue 27, "Must show": K_I of a single edge crack in a finite plate under tension and
under pure bending within 2 % of Tada, Paris & Irwin for a/b <= 0.6; K_II of an
inclined crack against its closed form; mesh convergence of K.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.fem.solve import ElasticModel
from gearsim.fracture.closed_forms import (
    edge_crack_bending_polynomial,
    edge_crack_tension,
    edge_crack_tension_polynomial,
    inclined_centre_crack,
)
from gearsim.fracture.plate import edge_crack_plate, inclined_crack_plate
from gearsim.fracture.sif import (
    interaction_integral,
    kolosov_constant,
    williams_displacement_gradient,
    williams_stress,
)

#: Edge crack, FE against handbook: the handbook formulas are good to 0.5 % (tension,
#: any a/b) and 0.2 % (bending fit, a/b <= 0.6); the FE error of the default mesh was
#: measured at <= 0.5 % (-0.49 % at a/b = 0.6 in tension, converging towards -0.2 %);
#: the issue asks for 2 %, which leaves a margin for gmsh versions.
EDGE_TOL = 0.02
#: Inclined centre crack in a plate of half size 20 a against the infinite-plate
#: closed form, relative to sigma sqrt(pi a): the finite plate raises K_I by about
#: 0.2-0.35 % (measured +0.35 % at beta = 0; Feddersen's width factor for a/W = 0.05 is
#: +0.15 %), the discretisation adds < 0.1 %; 1 % keeps a margin.
INCLINED_TOL = 0.01
#: The two handbook forms of the tension case (trigonometric, polynomial) are each good
#: to 0.5 % for a/b <= 0.6, so they agree to 1 %.
HANDBOOK_TOL = 0.01

WIDTH = 0.01
STRESS = 100e6


@pytest.mark.parametrize("a_over_b", [0.2, 0.4, 0.6])
def test_edge_crack_tension_against_tada(a_over_b: float) -> None:
    res = edge_crack_plate(a_over_b, load="tension", width=WIDTH, stress=STRESS)
    ref = edge_crack_tension(a_over_b * WIDTH, WIDTH, STRESS)
    assert res.sif.k1 / ref - 1.0 == pytest.approx(0.0, abs=EDGE_TOL)
    assert abs(res.sif.k2) < 1e-3 * ref  # symmetric problem: no mode II


@pytest.mark.parametrize("a_over_b", [0.2, 0.4, 0.6])
def test_edge_crack_bending_against_tada(a_over_b: float) -> None:
    res = edge_crack_plate(a_over_b, load="bending", width=WIDTH, stress=STRESS)
    ref = edge_crack_bending_polynomial(a_over_b * WIDTH, WIDTH, STRESS)
    assert res.sif.k1 / ref - 1.0 == pytest.approx(0.0, abs=EDGE_TOL)
    assert abs(res.sif.k2) < 1e-3 * ref


@pytest.mark.parametrize("a_over_b", [0.2, 0.4, 0.6])
def test_tada_tension_forms_agree(a_over_b: float) -> None:
    a = a_over_b * WIDTH
    ratio = edge_crack_tension_polynomial(a, WIDTH, 1.0) / edge_crack_tension(a, WIDTH, 1.0)
    assert ratio - 1.0 == pytest.approx(0.0, abs=HANDBOOK_TOL)


@pytest.mark.parametrize("beta_deg", [30.0, 45.0])
def test_inclined_crack_mixed_mode(beta_deg: float) -> None:
    a = 1e-3
    res = inclined_crack_plate(beta_deg, half_length=a, stress=STRESS)
    k1, k2 = inclined_centre_crack(a, math.radians(beta_deg), STRESS)
    k0 = STRESS * math.sqrt(math.pi * a)
    assert (res.sif.k1 - k1) / k0 == pytest.approx(0.0, abs=INCLINED_TOL)
    assert (res.sif.k2 - k2) / k0 == pytest.approx(0.0, abs=INCLINED_TOL)
    assert res.sif.k2 > 0.0  # the sign convention of the closed form


def test_mesh_convergence_of_k() -> None:
    """Two uniform refinements (all sizes / 2): the change of K shrinks."""
    ab = 0.6
    ref = edge_crack_tension(ab * WIDTH, WIDTH, STRESS)
    ks = [edge_crack_plate(ab, refinement=r).sif.k1 / ref for r in (0.5, 1.0, 2.0)]
    d1, d2 = abs(ks[1] - ks[0]), abs(ks[2] - ks[1])
    assert d2 < 0.75 * d1
    assert abs(ks[2] - 1.0) < abs(ks[0] - 1.0)


def test_williams_gradient_gives_williams_stress() -> None:
    """The differentiated auxiliary displacement, through Hooke's law, is the stress
    table of the near-tip field (independent closed form)."""
    rng = np.random.default_rng(1)
    r = rng.uniform(1e-4, 1e-2, 20)
    th = rng.uniform(-3.0, 3.0, 20)
    x1, x2 = r * np.cos(th), r * np.sin(th)
    e, nu = 206e9, 0.3
    for plane in ("strain", "stress"):
        mu = e / (2 * (1 + nu))
        lam = e * nu / ((1 + nu) * (1 - 2 * nu))
        if plane == "stress":
            lam = 2 * lam * mu / (lam + 2 * mu)
        kap = kolosov_constant(nu, plane)
        for mode in (1, 2):
            g = williams_displacement_gradient(x1, x2, mode, mu, kap)
            eps = 0.5 * (g + np.swapaxes(g, 0, 1))
            tr = eps[0, 0] + eps[1, 1]
            s11 = lam * tr + 2 * mu * eps[0, 0]
            s22 = lam * tr + 2 * mu * eps[1, 1]
            s12 = 2 * mu * eps[0, 1]
            ref = williams_stress(x1, x2, mode)
            scale = np.abs(ref).max(axis=0)
            for got, want in zip((s11, s22, s12), ref, strict=True):
                np.testing.assert_allclose(got / scale, want / scale, atol=1e-12)


def test_interaction_integral_refuses_bad_ring() -> None:
    p = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    t = np.array([[0], [1], [2]])
    model = ElasticModel(p, t, 206e9, 0.3)
    u = np.zeros(model.ndofs)
    with pytest.raises(InputError, match="sif.r_in"):
        interaction_integral(model, u, (0.0, 0.0), (1.0, 0.0), r_out=0.1, r_in=0.2)
    with pytest.raises(InputError, match="sif.r_out"):
        interaction_integral(model, u, (0.0, 0.0), (1.0, 0.0), r_out=-1.0)
    with pytest.raises(InputError, match="sif.direction"):
        interaction_integral(model, u, (0.0, 0.0), (0.0, 0.0), r_out=0.1)


def test_plate_refuses_out_of_range() -> None:
    with pytest.raises(InputError, match="a_over_b") as err:
        edge_crack_plate(0.95)
    assert "\n" not in str(err.value)
    with pytest.raises(InputError, match="load"):
        edge_crack_plate(0.3, load="torsion")


def test_interaction_integral_is_domain_independent() -> None:
    """The same FE field integrated over three rings gives the same K (the domain
    integral is path independent for traction-free straight faces)."""
    from gearsim.fracture.mesh import CrackPath, mesh_cracked_polygon

    b, a, hh = WIDTH, 0.4 * WIDTH, 2.0 * WIDTH
    outline = np.array([[0.0, -hh], [b, -hh], [b, 0.0], [b, hh], [0.0, hh], [0.0, 0.0]])
    crack = CrackPath(points=((0.0, 0.0), (a, 0.0)))
    cm = mesh_cracked_polygon(outline, crack, h=b / 6, h_tip=a / 200, growth=0.25)
    model = ElasticModel(cm.p, cm.t, 206e9, 0.3, plane="strain")
    top = model.mesh.facets_satisfying(lambda x: np.isclose(x[1], hh), True)
    bot = model.mesh.facets_satisfying(lambda x: np.isclose(x[1], -hh), True)
    f = model.traction_load(top, (0.0, STRESS)) + model.traction_load(bot, (0.0, -STRESS))
    corner = int(np.argmin(np.hypot(cm.p[0] - b, cm.p[1] + hh)))
    corner2 = int(np.argmin(np.hypot(cm.p[0] - b, cm.p[1] - hh)))
    fixed = np.concatenate([model.node_dofs(corner), model.node_dofs(corner2)[:1]])
    u = model.solve(f, fixed)
    tip, d = crack.tip_frame(1)
    ks = [interaction_integral(model, u, tip, d, r_out=r).k1 for r in (0.1 * a, 0.2 * a, 0.4 * a)]
    assert max(ks) / min(ks) - 1.0 < 1e-3  # measured 1.5e-4 (0.1 to 0.8 a: 2e-4)
    ref = edge_crack_tension(a, b, STRESS)
    assert ks[1] / ref - 1.0 == pytest.approx(0.0, abs=EDGE_TOL)
