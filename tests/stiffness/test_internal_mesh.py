"""Internal (ring-planet) mesh stiffness: geometry, pairs in contact, cracks, FE and ISO.

Independent numbers: the contact path from an explicit intersection of the line of
action with the tip circles; the contact ratio from ISO 21771's closed form (in
:class:`PlanetaryStage`, itself tested in tests/planetary); the FE ring tooth on its rim
(:mod:`gearsim.fem.ring`, gmsh + scikit-fem); ISO 6336-1 method B with z_n2 = infinity.
Numbers measured for three stages (30/24/78 m 2, 21/39/99 m 10 (NREL GRC),
20/25/70 m 3; ring addendum 0.8 m) are in docs/planetary.md section 4.3.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.fem.ring import fe_ring_tooth_compliance
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.internal import InternalMesh, internal_mesh_stiffness
from gearsim.stiffness.iso6336 import internal_mean_mesh_stiffness
from gearsim.stiffness.ring import RingToothModel
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import ToothCrack

#: Positions per mesh cycle: coarse, the tests compare means and zone lengths.
NPC = 40
#: Geometry identities (floating point only).
EXACT = 1e-9
#: PE internal mesh (ring tooth clamped on its root circle) against the same mesh with
#: the FE ring tooth on its 3.5 m_n rim: the PE tooth leaves out the rim and root-fillet
#: deflection (3-10e-12 m/N per metre of width, measured), which is 11-14 % of the mesh
#: compliance on the three stages; 15 % is that with a margin for the FE's 0.2 %
#: discretisation error. The PE mesh must be the stiffer.
FE_BAND = 0.15
#: ISO 6336-1 method B against the mesh with the FE ring tooth: ISO treats the internal
#: gear as a rack (z_n2 = infinity) and so the ring tooth as more compliant than the FE
#: shows; measured +25 to +33 % (the external sun-planet mesh of the same stages is
#: +11 to +15 % over ISO). 35 % bounds it; the issue's 25 % is the xfail below.
ISO_FE_BAND = 0.35
#: The issue's ISO 6336-1 band for the default PE mesh.
ISO_BAND = 0.25

STAGES = {
    "30-24-78": dict(sun_teeth=30, planet_teeth=24, ring_teeth=78, normal_module=2e-3,
                     face_width=0.02),
    "grc-21-39-99": dict(sun_teeth=21, planet_teeth=39, ring_teeth=99, normal_module=10e-3,
                         face_width=0.2275),
    "20-25-70": dict(sun_teeth=20, planet_teeth=25, ring_teeth=70, normal_module=3e-3,
                     face_width=0.03),
}


def _stage(key: str, **kw) -> PlanetaryStage:
    return PlanetaryStage(**STAGES[key], planets=3, ring_addendum_coefficient=0.8, **kw)


def _fe_ring_tooth(stage: PlanetaryStage, plane: str):
    """Ring-tooth compliance from the FE segment, interpolated over the contact radii."""
    geo = InternalMesh(stage)
    rr = geo.radii(np.array([geo.start, geo.end]))[1]
    grid = np.linspace(rr.min(), rr.max(), 15)
    fe = np.asarray(fe_ring_tooth_compliance(
        stage.ring, grid, youngs_modulus=stage.material.youngs_modulus,
        poisson_ratio=stage.material.poisson_ratio, plane=plane, level=2))
    pe = RingToothModel(stage.ring, material=stage.material, plane=plane)

    def tooth(r: np.ndarray) -> np.ndarray:
        c = pe.compliance(r)
        # the FE total; its excess over the PE beam terms goes in the foundation column
        c[:, 3] = np.interp(r, grid, fe) - c[:, :3].sum(axis=1)
        return c

    return tooth, fe, pe.compliance(grid).sum(axis=1)


# -------------------------------------------------------------------------- geometry
@pytest.mark.parametrize("key", list(STAGES))
def test_path_of_contact_from_explicit_construction(key: str) -> None:
    st = _stage(key)
    geo = InternalMesh(st)
    p, r = st.planet, st.ring
    # planet centre at the origin, ring centre C_r = (-a, 0): the line of action touches
    # both base circles on the same side, normal n = (cos a_w, sin a_w); s runs from the
    # planet's tangent point T_p along t, away from the ring's tangent point T_r
    a, aw = st.ring_planet_centre_distance, st.ring_planet_pressure_angle
    n = np.array([math.cos(aw), math.sin(aw)])
    tp = p.base_radius * n
    t = np.array([math.sin(aw), -math.cos(aw)])
    c_ring = np.array([-a, 0.0])
    tr = tp - a * math.sin(aw) * t
    assert np.linalg.norm(tr - c_ring) == pytest.approx(r.base_radius, rel=EXACT)
    assert (tr - c_ring) @ t == pytest.approx(0.0, abs=EXACT * a)

    def on(s: float) -> np.ndarray:
        return tp + s * t

    assert np.linalg.norm(on(geo.end)) == pytest.approx(p.tip_radius, rel=EXACT)
    assert np.linalg.norm(on(geo.start) - c_ring) == pytest.approx(r.tip_radius, rel=EXACT)
    assert (geo.end - geo.start) / st.base_pitch == pytest.approx(
        st.ring_planet_contact_ratio, rel=EXACT)
    rp, rr = geo.radii(np.array([geo.start, geo.pitch_point, geo.end]))
    assert rp[2] == pytest.approx(p.tip_radius, rel=EXACT)
    assert rr[0] == pytest.approx(r.tip_radius, rel=EXACT)
    # at the pitch point the radii are in the ratio of the tooth counts
    assert rr[1] / rp[1] == pytest.approx(r.teeth / p.teeth, rel=EXACT)


@pytest.mark.parametrize("key", list(STAGES))
def test_two_pair_zone_is_contact_ratio_minus_one(key: str) -> None:
    st = _stage(key)
    ms = internal_mesh_stiffness(st, settings=StiffnessSettings(positions_per_cycle=NPC))
    pairs = (ms.pair_k > 0).sum(axis=1)
    eps = st.ring_planet_contact_ratio
    assert set(np.unique(pairs)) == {1, 2}
    # share of positions with two pairs = eps - 1, to a sample at each end of the zone
    # (a pair whose sampling cell straddles an end of the path counts with its share)
    assert np.mean(pairs == 2) == pytest.approx(eps - 1, abs=2.0 / NPC)
    # two pairs are stiffer than one
    assert ms.k[pairs == 2].min() > ms.k[pairs == 1].max()


def test_planet_crack_acts_while_its_tooth_meshes_and_follows_the_flank() -> None:
    st = _stage("30-24-78")
    s = StiffnessSettings(positions_per_cycle=NPC)
    healthy = internal_mesh_stiffness(st, settings=s)
    crack = Crack(gear="planet", tooth=5, depth=1.5e-3)
    tens = internal_mesh_stiffness(st, settings=s, cracks=(ToothCrack(1, crack, +1),))
    comp = internal_mesh_stiffness(st, settings=s, cracks=(ToothCrack(1, crack, -1),))
    meshing = (healthy.pair_tooth1 == 5) & (healthy.pair_k > 0)
    on = meshing.any(axis=1)
    # unchanged wherever tooth 5 is out of mesh, lower wherever it meshes
    np.testing.assert_allclose(tens.k[~on], healthy.k[~on], rtol=1e-12)
    assert np.all(tens.k[on] < healthy.k[on])
    # the crack on the flank this mesh loads (tension side) costs more than on the other
    assert (healthy.k - tens.k).max() > (healthy.k - comp.k).max() > 0


def test_mean_converges_with_positions() -> None:
    st = _stage("30-24-78")
    means = [internal_mesh_stiffness(st, settings=StiffnessSettings(positions_per_cycle=n)).mean
             for n in (20, 40, 80)]
    assert abs(means[1] / means[2] - 1) < 2e-3
    assert abs(means[1] / means[2] - 1) < abs(means[0] / means[2] - 1)


def test_helical_mesh_fluctuates_less_than_spur() -> None:
    s = StiffnessSettings(positions_per_cycle=NPC)
    spur = internal_mesh_stiffness(_stage("30-24-78"), settings=s)
    hel = internal_mesh_stiffness(_stage("30-24-78", helix_angle=math.radians(20)), settings=s)
    assert np.ptp(hel.k) / hel.mean < 0.5 * np.ptp(spur.k) / spur.mean


# ----------------------------------------------------------------- FE and ISO 6336
@pytest.fixture(scope="module")
def measured() -> dict:
    out = {}
    for key in STAGES:
        st = _stage(key)
        s = StiffnessSettings(positions_per_cycle=20, plane="strain")
        tooth, fe, pe = _fe_ring_tooth(st, "strain")
        out[key] = dict(
            pe=internal_mesh_stiffness(st, settings=s).mean,
            fe=internal_mesh_stiffness(st, settings=s, ring_tooth=tooth).mean,
            iso=internal_mean_mesh_stiffness(st), fe_tooth=fe, pe_tooth=pe)
    return out


@pytest.mark.parametrize("key", list(STAGES))
def test_ring_tooth_between_clamped_pe_and_sainsot(measured, key: str) -> None:
    m = measured[key]
    st = _stage(key)
    geo = InternalMesh(st)
    rr = geo.radii(np.array([geo.start, geo.end]))[1]
    grid = np.linspace(rr.min(), rr.max(), 15)
    sainsot = RingToothModel(st.ring, material=st.material, plane="strain",
                             foundation="sainsot-solid").compliance(grid).sum(axis=1)
    # the FE ring tooth on its rim is more compliant than the PE tooth clamped on the
    # root circle and (much) less than with Sainsot's solid-body foundation
    assert np.all(m["fe_tooth"] > m["pe_tooth"])
    assert np.all(m["fe_tooth"] < sainsot)


@pytest.mark.parametrize("key", list(STAGES))
def test_internal_mesh_against_fe_ring_tooth(measured, key: str) -> None:
    m = measured[key]
    assert 1.0 < m["pe"] / m["fe"] < 1.0 + FE_BAND


@pytest.mark.parametrize("key", list(STAGES))
def test_fe_ring_mesh_against_iso6336(measured, key: str) -> None:
    m = measured[key]
    assert abs(m["fe"] / m["iso"] - 1) < ISO_FE_BAND


@pytest.mark.xfail(strict=True, reason="finding: the PE internal mesh is 42-47 % over "
                   "ISO 6336-1 (rack-like ring tooth in ISO; docs/planetary.md 4.3)")
@pytest.mark.parametrize("key", list(STAGES))
def test_pe_internal_mesh_within_iso_band(measured, key: str) -> None:
    m = measured[key]
    assert abs(m["pe"] / m["iso"] - 1) < ISO_BAND


# ---------------------------------------------------------------------- refusals
def test_refusals() -> None:
    st = _stage("30-24-78")
    ring_crack = ToothCrack(2, Crack(gear="ring", depth=1e-3), +1)
    with pytest.raises(InputError, match="revolution_of = 2"):
        internal_mesh_stiffness(st, cracks=(ring_crack,))
    with pytest.raises(InputError, match="the flank the planets load"):
        internal_mesh_stiffness(st, cracks=(ToothCrack(2, ring_crack.crack, -1),),
                                revolution_of=2)
    with pytest.raises(InputError, match="must be < 24"):
        internal_mesh_stiffness(st, cracks=(ToothCrack(1, Crack(gear="p", tooth=24,
                                                                depth=1e-3), 1),))
    with pytest.raises(InputError, match="force"):  # the line contact needs the load
        internal_mesh_stiffness(st, settings=StiffnessSettings(contact="line"))
    with pytest.raises(InputError, match="ring_tooth"):
        internal_mesh_stiffness(st, ring_tooth=lambda r: np.zeros((r.size, 3)))
