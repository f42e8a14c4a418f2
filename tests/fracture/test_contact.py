"""Crack-face contact: a closed crack under compression is pure mode II."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.fem.solve import ElasticModel
from gearsim.fracture.contact import closed_crack_intensity
from gearsim.fracture.mesh import CrackPath, mesh_cracked_polygon
from gearsim.fracture.sif import interaction_integral

#: As the open inclined crack (test_sif_plates.INCLINED_TOL): plate of half size 20 a
#: against the infinite plate, relative to |sigma| sqrt(pi a); measured +0.16 to +0.2 %.
CLOSED_TOL = 0.01

A = 1e-3
L = 20 * A


def _plate(beta_deg: float, stress: float):
    beta = math.radians(beta_deg)
    d = np.array([math.cos(beta), math.sin(beta)])
    outline = np.array([[-L, -L], [L, -L], [L, L], [-L, L]])
    crack = CrackPath(points=(tuple(-A * d), tuple(A * d)), tips=(True, True))
    r_out = 0.5 * A
    cm = mesh_cracked_polygon(outline, crack, h=L / 3, h_tip=r_out / 50, growth=0.3)
    model = ElasticModel(cm.p, cm.t, 206e9, 0.3, plane="strain")
    top = model.mesh.facets_satisfying(lambda x: np.isclose(x[1], L), True)
    bot = model.mesh.facets_satisfying(lambda x: np.isclose(x[1], -L), True)
    f = model.traction_load(top, (0.0, stress)) + model.traction_load(bot, (0.0, -stress))
    c1 = int(np.argmin(np.hypot(cm.p[0] + L, cm.p[1] + L)))
    c2 = int(np.argmin(np.hypot(cm.p[0] - L, cm.p[1] + L)))
    fixed = np.concatenate([model.node_dofs(c1), model.node_dofs(c2)[1:]])
    return cm, model, f, fixed, r_out


@pytest.mark.parametrize("beta_deg", [30.0, 60.0])
def test_closed_inclined_crack_is_pure_mode_two(beta_deg: float) -> None:
    stress = -100e6
    cm, model, f, fixed, r_out = _plate(beta_deg, stress)
    res = closed_crack_intensity(model, cm, f, fixed, r_out=r_out)
    beta = math.radians(beta_deg)
    k0 = abs(stress) * math.sqrt(math.pi * A)
    assert res.tip_closed and res.closed_fraction == pytest.approx(1.0)
    assert res.sif.k1 == 0.0 and res.k1_exact
    want = stress * math.sqrt(math.pi * A) * math.sin(beta) * math.cos(beta)
    assert (res.sif.k2 - want) / k0 == pytest.approx(0.0, abs=CLOSED_TOL)
    # the faces carry the normal stress: without contact they would overlap (K_I < 0)
    u = model.solve(f, fixed)
    free = interaction_integral(model, u, *cm.crack.tip_frame(1), r_out=r_out)
    assert free.k1 / k0 == pytest.approx(stress / abs(stress) * math.cos(beta) ** 2,
                                         abs=CLOSED_TOL)


def test_open_crack_unchanged_by_contact() -> None:
    cm, model, f, fixed, r_out = _plate(30.0, 100e6)
    res = closed_crack_intensity(model, cm, f, fixed, r_out=r_out)
    u = model.solve(f, fixed)
    free = interaction_integral(model, u, *cm.crack.tip_frame(1), r_out=r_out)
    assert not res.tip_closed and res.closed_fraction == 0.0
    assert res.sif.k1 == pytest.approx(free.k1, rel=1e-9)
    assert res.sif.k2 == pytest.approx(free.k2, rel=1e-6)


def test_contact_needs_a_straight_crack() -> None:
    outline = np.array([[0.0, -1.0], [2.0, -1.0], [2.0, 1.0], [0.0, 1.0], [0.0, 0.0]]) * 1e-2
    crack = CrackPath(points=((0.0, 0.0), (0.5e-2, 0.0), (0.8e-2, 0.2e-2)))
    cm = mesh_cracked_polygon(outline, crack, h=0.4e-2, h_tip=0.05e-2)
    model = ElasticModel(cm.p, cm.t, 206e9, 0.3)
    with pytest.raises(InputError, match="straight crack") as err:
        closed_crack_intensity(model, cm, np.zeros(model.ndofs), np.arange(4), r_out=1e-3)
    assert "\n" not in str(err.value)
