"""A root crack on a ring tooth: the cracked ring tooth, the internal mesh, the stage.

Independent numbers: the cracked-section energies integrated by scipy's adaptive
``quad`` over the tooth height Y (the profile inverted by root finding), against the
model's Gauss rule over the radius; the healthy tooth as the zero-depth limit; the
carrier angles at which each planet physically passes the cracked ring tooth
(theta_c + psi_n = phi_k), against the dips of the phased ring-mesh tables.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.stage import StageDynamics, simulate_stage
from gearsim.errors import InputError
from gearsim.geometry.planetary import PlanetaryStage, RingGear
from gearsim.signals.planetary import planetary_frequencies
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.ring import RingToothModel
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.system.planetary import PlanetaryTrain, StageOperating

pytestmark = pytest.mark.filterwarnings("ignore::gearsim.errors.ModelRangeWarning")

#: Gauss rule (16 nodes on each piece) against adaptive quad across the kinks of the
#: crack line and the limiting line: measured below 2e-4.
QUADRATURE = 1e-3
#: Time resolution of the dip positions: one table sample (1/16 cycle) in 78 cycles per
#: carrier revolution, in degrees of carrier angle.
ANGLE_TOL = 360.0 / 78 / 16 * 1.5

RING = RingGear(teeth=78, normal_module=2e-3)
STAGE = PlanetaryStage(30, 24, 78, 2e-3, planets=4, face_width=0.02,
                       ring_addendum_coefficient=0.8)
SUN_IN = StageOperating(speed=18.0 * 2 * math.pi, torque=100.0)
CARRIER_IN = StageOperating(fixed="ring", input="carrier", speed=5.0 * 2 * math.pi,
                            torque=360.0)


def _by_quad(tm: RingToothModel, rc: float, q: float, gamma: float) -> float:
    """Bending + shear + axial compliance (unit width) integrated over Y with quad."""
    e, g = tm.beam_moduli
    ring = tm.ring

    def beta(rho):
        return float(tm.half_angle(rho)[0])

    def rho_of(y):  # invert Y(rho) = rho cos(beta(rho)), increasing on [r_b, r_f]
        return brentq(lambda r: r * math.cos(beta(r)) - y, ring.base_radius * (1 + 1e-12),
                      ring.root_radius * 1.001)

    bc = beta(rc)
    a1 = float(tm.load_angle(rc)[0])
    fb, fa = math.cos(a1), math.sin(a1)
    xc, yc = rc * math.sin(bc), rc * math.cos(bc)
    tf = tm.root_half_angle
    x0, y0 = ring.root_radius * math.sin(tf), ring.root_radius * math.cos(tf)
    x1, y1 = x0 - q * math.sin(gamma), y0 - q * math.cos(gamma)

    def thick(y):
        r = rho_of(y)
        h = r * math.sin(beta(r))
        if q == 0.0:
            return 2 * h
        hc = min(x0 - (y0 - y) * math.tan(gamma), h) if y >= y1 else min(h, x1)
        return h + hc

    def dens(y):
        t = thick(y)
        m = fb * (y - yc) - fa * xc
        return 12 * m * m / (e * t**3) + 1.2 * fb * fb / (g * t) + fa * fa / (e * t)

    pts = [p for p in (y1,) if yc < p < y0]
    return quad(dens, yc, y0, points=pts or None, limit=200, epsabs=0, epsrel=1e-10)[0]


@pytest.mark.parametrize("q", [0.0, 0.8e-3, 2.0e-3, 3.0e-3])
@pytest.mark.parametrize("rc", [0.0765, 0.0785, 0.0800])
def test_cracked_ring_tooth_against_quad(q: float, rc: float) -> None:
    tm = RingToothModel(RING, gauss_points=16)
    gamma = math.radians(45.0)
    ours = float(tm.compliance([rc], crack_depth=q, crack_angle=gamma)[0, :3].sum())
    assert ours == pytest.approx(_by_quad(tm, rc, q, gamma), rel=QUADRATURE)


def test_crack_depth_is_monotone_and_zero_is_healthy() -> None:
    tm = RingToothModel(RING)
    r = np.linspace(RING.tip_radius, 0.0800, 7)
    healthy = tm.compliance(r)
    np.testing.assert_array_equal(tm.compliance(r, crack_depth=0.0), healthy)
    prev = healthy[:, :3].sum(axis=1)
    for q in (0.5e-3, 1e-3, 2e-3, 3.5e-3):
        c = tm.compliance(r, crack_depth=q)[:, :3].sum(axis=1)
        assert np.all(c >= prev * (1 - 1e-12)) and np.any(c > prev * 1.01)
        prev = c
    with pytest.raises(InputError, match="before the tooth centre line"):
        tm.compliance(r, crack_depth=tm.max_crack_depth(math.radians(45.0)))


@pytest.mark.parametrize("op", [SUN_IN, CARRIER_IN], ids=["forwards", "backwards"])
def test_each_planet_meets_the_cracked_tooth_where_it_is(op) -> None:
    s = StiffnessSettings(positions_per_cycle=16)
    tr = PlanetaryTrain(STAGE, op, s, cracks=(Crack(gear="ring", tooth=10, depth=1.5e-3),))
    h = PlanetaryTrain(STAGE, op, s)
    fm, wc = tr.mesh_frequency, tr.speeds["carrier"]
    tc = 2 * math.pi / abs(wc)
    t = np.linspace(0.0, tc, 78 * 64, endpoint=False)
    when = []
    for n in range(STAGE.planets):
        d = tr.mesh_table("ring", n)(t, fm) - h.mesh_table("ring", n)(t, fm)
        on = t[d < -1e-6 * h.mesh_table("ring", n).k.mean()]
        assert on.size > 0
        when.append(np.angle(np.mean(np.exp(2j * np.pi * on / tc))) / (2 * np.pi) * tc)
    # planet n passes the ring tooth at angle phi_k when theta_c + psi_n = phi_k
    got = np.degrees((np.array(when) - when[0]) * wc) % 360.0
    psi = STAGE.planet_angles_value
    want = np.degrees(-(psi - psi[0])) % 360.0
    diff = (got - want + 180.0) % 360.0 - 180.0
    np.testing.assert_allclose(diff, 0.0, atol=ANGLE_TOL)


def test_ring_crack_raises_the_ring_fault_line() -> None:
    s = StiffnessSettings(positions_per_cycle=16)
    run = DynamicsSettings(duration=0.8, fs=5000.0, oversample=8)
    out = {}
    for key, cracks in (("healthy", ()), ("ring", (Crack(gear="ring", depth=3e-3),))):
        ds = simulate_stage(PlanetaryTrain(STAGE, SUN_IN, s, cracks=cracks),
                            StageDynamics(), run)
        f = ds["mesh_force"].sel(mesh="ring-planet-1").values
        spec = np.abs(np.fft.rfft(f - f.mean()))
        freq = np.fft.rfftfreq(f.size, 1 / run.fs)
        out[key] = (freq, spec)
    fq = planetary_frequencies(30, 24, 78, 4, sun=18.0)
    # one planet meets the cracked tooth once per carrier revolution: f_c = 5 Hz lines
    freq, spec = out["ring"]
    k = int(round(fq.carrier / (freq[1] - freq[0])))
    assert spec[k] > 20 * out["healthy"][1][k]


@pytest.mark.parametrize("cracks,parameter", [
    ((Crack(gear="ring", flank="non-working", depth=1e-3),), "crack.flank"),
    ((Crack(gear="ring", depth=1e-3), Crack(gear="planet-2", depth=1e-3)), "cracks"),
    ((Crack(gear="ring", tooth=78, depth=1e-3),), "crack.tooth"),
])
def test_refusals(cracks, parameter) -> None:
    with pytest.raises(InputError) as err:
        PlanetaryTrain(STAGE, SUN_IN, cracks=cracks)
    assert err.value.parameter == parameter


# the planet's crack: past the depth at which the far-side limiting line reaches its top
# land (3.85 mm here; a crack past the centre line but short of it is a crack, not a
# refusal: docs/fracture.md, "Stiffness along the life")
@pytest.mark.parametrize("gear,depth", [("ring", 5e-3), ("planet-1", 4e-3)])
def test_too_deep_crack_refused_where_the_stage_is_made(gear, depth) -> None:
    with pytest.raises(InputError, match="crack.depth"):
        PlanetaryTrain(STAGE, SUN_IN, cracks=(Crack(gear=gear, depth=depth),))


def test_internal_mesh_changes_only_where_the_cracked_ring_tooth_meshes() -> None:
    from gearsim.stiffness.internal import internal_mesh_stiffness
    from gearsim.stiffness.source import ToothCrack

    s = StiffnessSettings(positions_per_cycle=16)
    healthy = internal_mesh_stiffness(STAGE, settings=s, revolution_of=2)
    crack = Crack(gear="ring", tooth=7, depth=2e-3)
    cracked = internal_mesh_stiffness(STAGE, settings=s, revolution_of=2,
                                      cracks=(ToothCrack(2, crack, 1),))
    meshing = ((healthy.pair_tooth2 == 7) & (healthy.pair_k > 0)).any(axis=1)
    np.testing.assert_allclose(cracked.k[~meshing], healthy.k[~meshing], rtol=1e-12)
    assert np.all(cracked.k[meshing] < healthy.k[meshing])
    assert cracked.k.size == 78 * 16
