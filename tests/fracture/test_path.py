"""Crack path driver and the Paris life along a path."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from gearsim.errors import InputError
from gearsim.fracture.closed_forms import edge_crack_tension
from gearsim.fracture.mesh import CrackPath
from gearsim.fracture.paris import ParisLaw
from gearsim.fracture.path import GrowthPath, grow_path, path_life
from gearsim.fracture.tooth import initial_crack
from gearsim.geometry.gear import Gear

#: Life along a path with K = Y F sqrt(pi a) at 31 lengths against the closed form: the
#: log-log PCHIP is exact for a power law, the rest is the quadrature (1e-11).
POWER_LAW_RTOL = 1e-8
#: Life along a path with the finite-width K of Tada's edge crack (a/b 0.08 to 0.67) at
#: 31 lengths against adaptive quadrature of the exact K: the interpolation error
#: (measured 5.3e-5; 2.3e-4 with 21 lengths, 3.9e-6 with 61) with a margin.
PATH_LIFE_RTOL = 2e-4

Y_PER_FORCE = 1.12 * 2e3  # K / (F sqrt(pi a)) [1/m]: a stress of 2e3 Pa per N/m of force


def _synthetic_path(lengths: np.ndarray, force: float) -> GrowthPath:
    k1 = Y_PER_FORCE * force * np.sqrt(np.pi * lengths)
    pts = tuple((0.0, -float(a)) for a in np.concatenate([[0.0], lengths]))
    return GrowthPath(crack=CrackPath(points=pts), lengths=lengths, k1=k1,
                      k2=np.zeros_like(k1), kink=np.zeros_like(k1), force=force,
                      status="steps done", message="", seconds=0.0)


def test_path_life_matches_closed_form() -> None:
    lengths = np.linspace(1e-3, 10e-3, 31)
    path = _synthetic_path(lengths, force=1e5)
    law = ParisLaw.from_mpa(1e-11, 3.0, 3.0, 100.0)
    f = 1e5
    res = path_life(path, law, f)
    assert res.status == "length limit"
    k = law.c * (Y_PER_FORCE * f * math.sqrt(math.pi)) ** 3
    want = (lengths[-1] ** -0.5 - lengths[0] ** -0.5) / (-0.5 * k)
    assert res.cycles_end == pytest.approx(want, rel=POWER_LAW_RTOL)
    # K scales with the force: twice the force range, 8 times fewer cycles (m = 3)
    res2 = path_life(path, law, 2 * f)
    assert res2.cycles_end == pytest.approx(want / 8.0, rel=POWER_LAW_RTOL)
    # below the threshold: no growth
    assert path_life(path, law, 1e3).status == "no growth"
    # K_max of a larger peak force reaches K_IC inside the path
    res3 = path_life(path, law, f, force_max=3 * f)
    assert res3.status == "fracture" and res3.a_end < lengths[-1]


def test_path_life_interpolates_a_finite_width_k() -> None:
    b, f, stress_per_force = 12e-3, 1e5, 2e3
    lengths = np.linspace(1e-3, 8e-3, 31)
    k1 = np.array([edge_crack_tension(a, b, stress_per_force * f) for a in lengths])
    pts = tuple((0.0, -float(a)) for a in np.concatenate([[0.0], lengths]))
    path = GrowthPath(crack=CrackPath(points=pts), lengths=lengths, k1=k1,
                      k2=np.zeros_like(k1), kink=np.zeros_like(k1), force=f,
                      status="steps done", message="", seconds=0.0)
    law = ParisLaw.from_mpa(1e-11, 3.0, 3.0, 300.0)
    res = path_life(path, law, f)
    want = quad(lambda a: 1.0 / (law.c * edge_crack_tension(a, b, stress_per_force * f) ** 3),
                lengths[0], lengths[-1], epsrel=1e-12, limit=200)[0]
    assert res.status == "length limit"
    assert res.cycles_end == pytest.approx(want, rel=PATH_LIFE_RTOL)


def test_grow_path_records_k_along_the_crack() -> None:
    gear = Gear(teeth=39, normal_module=6e-3, name="input")
    crack = initial_crack(gear, 1e-3)
    path = grow_path(gear, crack, gear.tip_radius, 0.5e-3, steps=2, force=1e5)
    assert path.status == "steps done" and len(path.crack.points) == 4
    np.testing.assert_allclose(path.lengths, [1e-3, 1.5e-3], rtol=1e-12)
    assert np.all(np.diff(path.k1) > 0.0) and np.all(path.keq >= path.k1)


def test_path_refusals() -> None:
    path = _synthetic_path(np.array([1e-3]), force=1e5)
    law = ParisLaw.from_mpa(1e-11, 3.0, 3.0, 100.0)
    with pytest.raises(InputError, match="path.lengths"):
        path_life(path, law, 1e5)
    path = _synthetic_path(np.array([1e-3, 2e-3]), force=1e5)
    with pytest.raises(InputError, match="force_range"):
        path_life(path, law, -1.0)
    with pytest.raises(InputError, match="force_max"):
        path_life(path, law, 1e5, force_max=1e4)
    gear = Gear(teeth=39, normal_module=6e-3, name="input")
    with pytest.raises(InputError, match="steps"):
        grow_path(gear, initial_crack(gear, 1e-3), gear.tip_radius, 0.5e-3, steps=0)
