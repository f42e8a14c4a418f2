"""Lin & Parker (1999) planetary model: mode types, multiplicities and independent checks.

References used by the checks (none restates the assembly in gearsim.dynamics.planetary):

* the structure theorems of Lin & Parker (1999): for equally spaced planets every mode is
  rotational (multiplicity 1, central members only rotate, all planets move alike),
  translational (multiplicity 2, central members only translate) or a planet mode
  (multiplicity N - 3, central members still; sum_n w_n = sum_n w_n cos psi_n =
  sum_n w_n sin psi_n = 0);
* the stiffness sub-matrices printed in Lin & Parker (1999) (K_c1, K_c2, K_r1,
  K_r2, K_r3, K_s1, K_s2, K_s3), transcribed here block by block;
* a purely torsional model derived by hand for infinitely stiff translations;
* the rigid-body mode of the example system (ring held, sun and carrier free), whose sun
  to carrier motion must follow the Willis ratio 1 + z_r/z_s = 2 cos(alpha) in the
  model's arc-length coordinates.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.dynamics.planetary import LinParkerModel
from gearsim.errors import InputError

#: Share of modal kinetic energy that counts as "no motion": eigh leaves ~1e-15 relative
#: residues; 1e-8 is the classification threshold of the module, tested independently here.
NO_MOTION = 1e-8
#: Matrix entries of K assembled two ways (N/m, entries up to ~1e9): double-precision sums.
MATRIX_RTOL = 1e-12
#: Frequencies of the stiff-translation limit vs. the torsional model: translations
#: 2e5 times stiffer than the meshes leave a relative error of order 1e-5.
TORSIONAL_RTOL = 2e-4
#: Eigenvalue comparisons of the same physical system solved two ways.
EIG_RTOL = 1e-9


def _energy(shapes: np.ndarray, mass: np.ndarray, rows: list[int]) -> float:
    md = np.diag(mass)
    e = shapes**2 * md[:, None]
    return float(e[rows].sum() / e.sum())


CENTRAL_TRANS = [0, 1, 3, 4, 6, 7]
CENTRAL_ROT = [2, 5, 8]


@pytest.mark.parametrize("n", [3, 4, 5, 6])
def test_mode_types_and_multiplicities(n: int) -> None:
    model = LinParkerModel.lin_parker_example(planets=n)
    res = model.modes()
    m = model.mass_matrix()
    kinds = [g.kind for g in res.groups]
    assert "mixed" not in kinds
    rot, trans, planet = (res.of_kind(k) for k in ("rotational", "translational", "planet"))
    # Lin & Parker (1999): 6 rotational, 6 translational pairs, 3 planet-mode frequencies
    assert len(rot) == 6 and all(g.multiplicity == 1 for g in rot)
    assert len(trans) == 6 and all(g.multiplicity == 2 for g in trans)
    assert len(planet) == (3 if n >= 4 else 0)
    assert all(g.multiplicity == n - 3 for g in planet)
    assert sum(g.multiplicity for g in res.groups) == 3 * (n + 3)
    psi = model.angles
    for g in rot:
        assert _energy(g.shapes, m, CENTRAL_TRANS) < NO_MOTION
        w = g.shapes[9:, 0].reshape(n, 3)
        np.testing.assert_allclose(w, np.broadcast_to(w[0], w.shape), atol=1e-9 * np.abs(w).max())
    for g in trans:
        assert _energy(g.shapes, m, CENTRAL_ROT) < NO_MOTION
    for g in planet:
        assert _energy(g.shapes, m, CENTRAL_TRANS + CENTRAL_ROT) < NO_MOTION
        for k in range(g.multiplicity):
            w = g.shapes[9:, k].reshape(n, 3)
            scale = np.abs(w).max()
            for weight in (np.ones(n), np.cos(psi), np.sin(psi)):
                np.testing.assert_allclose(weight @ w, 0.0, atol=1e-9 * scale)


def _printed_stiffness(model: LinParkerModel) -> np.ndarray:
    """K_b + K_m of Lin & Parker (1999) assembled from the printed blocks (as transcribed
    in a public MATLAB implementation, class Lin_Parker_99)."""
    n = model.planets
    a_s, a_r = model.sun_pressure_angle, model.ring_pressure_angle
    kp, ksp, krp = model.planet_bearing, model.sun_mesh, model.ring_mesh
    ss, cs, sr, cr = math.sin(a_s), math.cos(a_s), math.sin(a_r), math.cos(a_r)
    K = np.zeros((3 * (n + 3),) * 2)
    kc3 = kp * np.diag([1.0, 1.0, 0.0])
    kr3 = krp * np.array([[sr**2, -sr * cr, -sr], [-sr * cr, cr**2, cr], [-sr, cr, 1.0]])
    ks3 = ksp * np.array([[ss**2, ss * cs, -ss], [ss * cs, cs**2, -cs], [-ss, -cs, 1.0]])
    for j, psi in enumerate(model.angles):
        s_, c_ = math.sin(psi), math.cos(psi)
        sr_, cr_ = math.sin(psi + a_r), math.cos(psi + a_r)
        ss_, cs_ = math.sin(psi - a_s), math.cos(psi - a_s)
        kc1 = kp * np.array([[1.0, 0.0, -s_], [0.0, 1.0, c_], [-s_, c_, 1.0]])
        kc2 = kp * np.array([[-c_, s_, 0.0], [-s_, -c_, 0.0], [0.0, -1.0, 0.0]])
        kr1 = krp * np.array([[sr_**2, -sr_ * cr_, -sr_], [-sr_ * cr_, cr_**2, cr_], [-sr_, cr_, 1.0]])
        kr2 = krp * np.array([[-sr_ * sr, sr_ * cr, sr_], [cr_ * sr, -cr_ * cr, -cr_], [sr, -cr, -1.0]])
        ks1 = ksp * np.array([[ss_**2, -ss_ * cs_, -ss_], [-ss_ * cs_, cs_**2, cs_], [-ss_, cs_, 1.0]])
        ks2 = ksp * np.array([[ss_ * ss, ss_ * cs, -ss_], [-cs_ * ss, -cs_ * cs, cs_], [-ss, -cs, 1.0]])
        p = slice(9 + 3 * j, 12 + 3 * j)
        for blk, k1, k2 in ((slice(0, 3), kc1, kc2), (slice(3, 6), kr1, kr2), (slice(6, 9), ks1, ks2)):
            K[blk, blk] += k1
            K[blk, p] += k2
            K[p, blk] += k2.T
        K[p, p] += kc3 + kr3 + ks3
    K[0:3, 0:3] += np.diag([model.carrier_bearing, model.carrier_bearing, model.carrier_torsional])
    K[3:6, 3:6] += np.diag([model.ring_bearing, model.ring_bearing, model.ring_torsional])
    K[6:9, 6:9] += np.diag([model.sun_bearing, model.sun_bearing, model.sun_torsional])
    return K


@pytest.mark.parametrize("angles", [None, (0.0, 1.4, 3.3, 4.5)])
def test_stiffness_matches_printed_blocks(angles: tuple[float, ...] | None) -> None:
    model = LinParkerModel.lin_parker_example(planets=4, planet_angles=angles)
    K = model.stiffness_matrix()
    ref = _printed_stiffness(model)
    np.testing.assert_allclose(K, ref, rtol=0.0, atol=MATRIX_RTOL * np.abs(ref).max())
    np.testing.assert_allclose(K, K.T, rtol=0.0, atol=MATRIX_RTOL * np.abs(ref).max())


def test_planet_modes_are_one_planet_on_fixed_centre() -> None:
    # Lin & Parker (1999): planet-mode frequencies solve (K_p - w^2 M_p) w = 0 for one planet
    # with carrier, ring and sun held; K_p = K_c3 + K_r3 + K_s3 (printed blocks)
    model = LinParkerModel.lin_parker_example(planets=5)
    kp = _printed_stiffness(model)[9:12, 9:12]
    mp = np.diag([model.planet_mass, model.planet_mass, model.planet_inertia])
    ref = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(mp, kp)).real)) / (2 * math.pi)
    got = [g.frequency for g in model.modes().of_kind("planet")]
    np.testing.assert_allclose(got, ref, rtol=EIG_RTOL)


def test_stiff_translations_give_the_torsional_model() -> None:
    n = 4
    big = 1e14
    base = LinParkerModel.lin_parker_example(planets=n)
    kw = {f: getattr(base, f) for f in base.__dataclass_fields__}
    kw.update(carrier_bearing=big, ring_bearing=big, sun_bearing=big, planet_bearing=big)
    stiff = LinParkerModel(**kw)
    f_full = np.sort(stiff.modes().frequencies)[: n + 3]
    # torsional model by hand: x, y, xi -> 0 and eta_n -> u_c; coordinates (u_c, u_r, u_s,
    # u_1..u_N); delta_sn = u_s + u_n - u_c cos a_s, delta_rn = u_r - u_n - u_c cos a_r; the
    # planets' tangential mass rides on the carrier
    a_s, a_r = base.sun_pressure_angle, base.ring_pressure_angle
    M = np.diag([base.carrier_inertia + n * base.planet_mass, base.ring_inertia, base.sun_inertia]
                + [base.planet_inertia] * n)
    K = np.diag([base.carrier_torsional, base.ring_torsional, base.sun_torsional] + [0.0] * n)
    for j in range(n):
        bs = np.zeros(n + 3)
        bs[[0, 2, 3 + j]] = [-math.cos(a_s), 1.0, 1.0]
        br = np.zeros(n + 3)
        br[[0, 1, 3 + j]] = [-math.cos(a_r), 1.0, -1.0]
        K += base.sun_mesh * np.outer(bs, bs) + base.ring_mesh * np.outer(br, br)
    lam = np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)
    f_tors = np.sqrt(np.clip(lam, 0.0, None)) / (2 * math.pi)
    np.testing.assert_allclose(f_full[1:], f_tors[1:], rtol=TORSIONAL_RTOL)
    # rigid rolling mode: zero up to the eigensolver noise eps * lambda_max ~ (0.02 Hz)^2 here
    assert f_full[0] < 1e-4 * f_full[1] and f_tors[0] < 1e-6 * f_tors[1]


def test_rigid_mode_follows_willis_ratio() -> None:
    model = LinParkerModel.lin_parker_example(planets=4)
    res = model.modes()
    assert res.frequencies[0] < 1e-4 * res.frequencies[1]
    phi = res.shapes[:, 0]
    # u_s / u_c = (r_bs theta_s) / (r_c theta_c) = cos(a) 2 r_s (1 + z_r/z_s) / (r_s + r_r)
    #           = 2 cos(a) for r ~ z; ring held (u_r = 0), u_n = -u_c cos(a)
    a = model.sun_pressure_angle
    assert phi[8] / phi[2] == pytest.approx(2.0 * math.cos(a), rel=1e-9)
    assert abs(phi[5]) < 1e-9 * abs(phi[2])
    np.testing.assert_allclose(phi[11::3] / phi[2], -math.cos(a), rtol=1e-9)


def test_example_frequencies_record() -> None:
    """Frequencies of the example system (N = 4) as computed; see docs/planetary.md.

    Not a validation: the published table could not be retrieved to compare with. The
    values guard against unnoticed changes; they agree with the independent checks above.
    """
    res = LinParkerModel.lin_parker_example(planets=4).modes()
    by_kind = {k: [round(g.frequency, 1) for g in res.of_kind(k)]
               for k in ("rotational", "translational", "planet")}
    assert by_kind["rotational"] == pytest.approx([0.0, 1536.5, 1970.6, 2625.7, 7773.6, 13071.1], abs=0.1)
    assert by_kind["translational"] == pytest.approx([727.3, 1091.2, 1892.8, 2342.5, 7189.9, 10437.6],
                                                     abs=0.1)
    assert by_kind["planet"] == pytest.approx([1808.2, 5963.8, 6981.7], abs=0.1)


def test_unequal_spacing_mixes_modes() -> None:
    res = LinParkerModel.lin_parker_example(planets=4, planet_angles=(0.0, 1.4, 3.3, 4.5)).modes()
    assert any(g.kind == "mixed" for g in res.groups)


@pytest.mark.parametrize(("change", "pattern"), [
    (dict(planets=0), "planets"), (dict(sun_mass=0.0), "sun_mass"),
    (dict(ring_mesh=-1.0), "ring_mesh"), (dict(sun_pressure_angle=0.0), "sun_pressure_angle"),
    (dict(planet_angles=(0.0, 1.0)), "one angle per planet"),
])
def test_refusals(change: dict, pattern: str) -> None:
    base = LinParkerModel.lin_parker_example(planets=4)
    kw = {f: getattr(base, f) for f in base.__dataclass_fields__}
    kw.update(change)
    with pytest.raises(InputError, match=pattern):
        LinParkerModel(**kw)
