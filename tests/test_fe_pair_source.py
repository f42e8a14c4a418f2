"""The FE gear pair as the stiffness source of a train (``stiffness.source = "fe-pair"``).

The slicing of the FE section's TVMS over a helical face width is checked against a
closed form with a synthetic section; the FE pair itself is checked in
tests/fem/test_fem_pair.py.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import gearsim.system.fe_pair as fps
from gearsim.errors import InputError
from gearsim.stiffness.faults import Spall
from gearsim.stiffness.mesh import MeshStiffness

#: Closed-form slicing of a harmonic section: the average of N phase-shifted cosines is
#: exact up to the linear interpolation of the section table (200 positions per cycle:
#: 1 - cos(pi / 200) ~ 1.2e-4 of the amplitude).
SLICING_TOL = 3e-4


def _harmonic_section(a0, a1):
    def fake(pair, *, torque, cracks, positions_per_cycle, plane, revolution_of, **_):
        z = pair.driver.teeth if revolution_of == 1 else pair.driven.teeth
        cycles = np.arange(z * positions_per_cycle) / positions_per_cycle
        k = a0 + a1 * np.cos(2 * math.pi * cycles)
        return MeshStiffness(name=pair.name, revolution_of="x", cycles=cycles,
                             theta1=cycles, theta2=cycles, k=k, components={},
                             pair_k=k[:, None], pair_tooth1=np.zeros((k.size, 1), int),
                             pair_tooth2=np.zeros((k.size, 1), int),
                             attrs={"torque": torque})
    return fake


def test_helical_slicing_of_the_section_is_the_phase_average(table1, monkeypatch):
    """k(u) = mean_j k_2D(u - s_j), s_j = z_j tan(beta_b) / p_b: for a cosine section the
    mean is the closed form Re(exp(2 pi i u) mean_j exp(-2 pi i s_j))."""
    a0, a1 = 3e9, 2e8
    monkeypatch.setattr(fps, "fe_pair_mesh_stiffness", _harmonic_section(a0, a1))
    st = dataclasses.replace(table1.stiffness, source="fe-pair", fe_pair_positions=200)
    tr = dataclasses.replace(table1.with_cracks(()), stiffness=st)
    ms = tr.mesh_stiffness(0)
    pair = tr.pairs[0]
    ns = st.slices
    s = (np.arange(ns) + 0.5) / ns * pair.face_width * math.tan(
        pair.driver.base_helix_angle) / pair.base_pitch
    phasor = np.mean(np.exp(-2j * math.pi * s))
    expected = a0 + a1 * np.real(np.exp(2j * math.pi * ms.cycles) * phasor)
    np.testing.assert_allclose(ms.k, expected, atol=SLICING_TOL * a1)
    # the overlap ratio 1.79 averages the harmonic down to |phasor| = 0.17 of it
    assert abs(phasor) < 0.2
    assert ms.attrs["source"] == "fe-pair" and ms.components == {}


def test_spur_section_is_used_as_is(spur, monkeypatch):
    """A spur mesh: no slicing; positions interpolated from the FE positions."""
    monkeypatch.setattr(fps, "fe_pair_mesh_stiffness", _harmonic_section(3e8, 1e7))
    st = dataclasses.replace(spur.stiffness, source="fe-pair", fe_pair_positions=200)
    ms = dataclasses.replace(spur, stiffness=st).mesh_stiffness(0)
    np.testing.assert_allclose(ms.k, 3e8 + 1e7 * np.cos(2 * math.pi * ms.cycles),
                               atol=SLICING_TOL * 1e7)


def test_fe_pair_source_refuses_what_it_cannot_model(spur, table1):
    """Faults other than cracks, and a crack that is not uniform over the face: refused
    when the train is made, one line naming stiffness.source."""
    st = dataclasses.replace(spur.stiffness, source="fe-pair")
    with pytest.raises(InputError, match="stiffness.source"):
        dataclasses.replace(spur, stiffness=st).with_faults(
            (Spall(gear="pinion", tooth=1, radius=0.031, length=1e-3, width=5e-3,
                   depth=1e-4),))
    crack = dataclasses.replace(table1.cracks[0], profile="linear")
    with pytest.raises(InputError, match="uniform"):
        dataclasses.replace(table1, cracks=(crack,),
                            stiffness=dataclasses.replace(table1.stiffness, source="fe-pair"))


#: The reducer with a 0.5 mm crack over half the face width of its output gear (mesh 1).
HALF_CRACK = '\n[[cracks]]\ngear = "output-gear"\ntooth = 2\ndepth = "0.5 mm"\nextent = 0.5\n'


@pytest.mark.parametrize(("mesh", "refused"), [(1, "meshes[1].stiffness.source"), (0, None)])
def test_a_mesh_own_fe_pair_source_is_named_by_its_mesh(mesh, refused):
    """A mesh's own ``stiffness = {source = "fe-pair"}`` refused a crack that is not
    uniform over the face as ``stiffness.source`` (the file's [stiffness], which does not
    say it); it names the mesh's key. A mesh reads only its own gears' cracks (mesh
    0's FE pair never sees the output gear's), so there it is not refused."""
    from importlib.resources import files

    from gearsim.model import loads

    base = (files("gearsim.data") / "two-stage-reducer.toml").read_text()
    pair = ('gears = ["input-pinion", "intermediate-gear"]',
            'gears = ["intermediate-pinion", "output-gear"]')[mesh]
    text = base.replace(pair, pair + '\nstiffness = {source = "fe-pair"}') + HALF_CRACK
    if refused is None:
        assert loads(text).train.cracks[0].extent == 0.5
        return
    with pytest.raises(InputError) as err:
        loads(text)
    assert str(err.value) == (
        f"{refused} = fe-pair: models one transverse section: the crack on output-gear must "
        "be uniform over the face width (extent 0.5, profile 'uniform')")


#: Mean dynamic transmission error at the low speed of the 19/48 example against the FE
#: pair's own loaded TE (mean over the cycle): the dynamic part averages out; the
#: table is interpolated linearly between the 20 FE positions per cycle.
MEAN_TE_TOL = 0.02
#: Mean mesh force against the static force T / r_b1 (equilibrium of the input shaft).
MEAN_FORCE_TOL = 0.005


@pytest.fixture(scope="module")
def fe_pair_cache(tmp_path_factory):
    """A cache folder of this module's own, holding the 19/48 FE pair table (computed
    once here: ~9 s of FE solves), so that both tests below share one computation."""
    return tmp_path_factory.mktemp("fe-pair-cache")


@pytest.fixture(scope="module")
def fe_pair_train(spur, fe_pair_cache):
    st = dataclasses.replace(spur.stiffness, source="fe-pair")
    tr = dataclasses.replace(spur.with_cracks(()), stiffness=st)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("GEARSIM_CACHE", str(fe_pair_cache))
        tr.mesh_stiffness(0)  # the table into the module's cache
    return tr


def test_fe_pair_table_is_cached(fe_pair_train, fe_pair_cache, monkeypatch):
    """The table computed by the fixture is written to the cache and a second call is
    served from it (the FE model may not be built) in < 1 s, with the same numbers."""
    import time

    import gearsim.fem.pair_table as pt
    import gearsim.system.train as train_module

    monkeypatch.setenv("GEARSIM_CACHE", str(fe_pair_cache))
    first = fe_pair_train.mesh_stiffness(0)
    # from the disk: the in-memory tables emptied, the FE model refused
    monkeypatch.setattr(train_module, "_TABLES", type(train_module._TABLES)(1))

    def refuse(*a, **k):
        raise AssertionError("FE model built although the table is cached")

    monkeypatch.setattr(pt, "FEPairModel", refuse)
    t0 = time.perf_counter()
    again = fe_pair_train.mesh_stiffness(0)
    assert time.perf_counter() - t0 < 1.0
    np.testing.assert_array_equal(again.k, first.k)
    assert list(fe_pair_cache.glob("fe/pair-*.npz"))


def test_simulation_on_the_fe_pair_source(fe_pair_train, fe_pair_cache, monkeypatch):
    """A 0.1 s run on the FE-pair stiffness: mean mesh force = T / r_b1, mean dynamic TE
    = the FE pair's mean loaded TE (quasi-static at the example's speed)."""
    from gearsim.dynamics import DynamicsSettings, simulate
    from gearsim.fem.pair import FEPairModel
    from gearsim.system.fe_pair import FE_PAIR_LEVEL

    monkeypatch.setenv("GEARSIM_CACHE", str(fe_pair_cache))
    ds = simulate(fe_pair_train, DynamicsSettings(duration=0.1, fs=20_000.0))
    n = ds.sizes["time"]
    tail = slice(n // 2, None)  # after the start-up transient
    force = fe_pair_train.static_mesh_force(0)
    assert float(ds["mesh_force_1"][tail].mean()) == pytest.approx(force, rel=MEAN_FORCE_TOL)
    pair = fe_pair_train.pairs[0]
    model = FEPairModel(pair, torque=fe_pair_train.torque(0), level=FE_PAIR_LEVEL)
    te = np.mean([model.solve(i / 20).transmission_error for i in range(20)])
    assert float(ds["dte_1"][tail].mean()) == pytest.approx(te, rel=MEAN_TE_TOL)
