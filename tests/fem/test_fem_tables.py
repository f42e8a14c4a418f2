"""FE compliance as stiffness table: convention, interpolation, disk cache, hook, CLI."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from numpy.testing import assert_allclose
from typer.testing import CliRunner

import gearsim.fem.tables as tables
from gearsim.errors import InputError
from gearsim.fem.geometry import SectorOptions
from gearsim.fem.tables import FiniteElementCompliance
from gearsim.fem.tooth import fe_tooth_compliance
from gearsim.stiffness.mesh import StiffnessSettings, mesh_stiffness

OPT = SectorOptions(level=1)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("GEARSIM_CACHE", str(tmp_path))
    return tmp_path / "fe"


def test_fem_table_convention_interpolation_and_cache(spur, cache, monkeypatch):
    gear = spur.gears[0]
    nodes = tables.fe_nodes(gear)
    r = np.array([0.5 * (nodes[3] + nodes[4]), 0.5 * (nodes[8] + nodes[9])])
    settings = StiffnessSettings(closure="open")
    out = tables.fe_compliance(gear, r, settings=settings, options=OPT)
    assert out.shape == (2, 4)
    assert np.all(out[:, 1:] == 0.0) and np.all(out[:, 0] > 0)
    files = list(cache.glob("*.npz"))
    assert len(files) == 1 and not list(cache.glob("*.tmp"))
    # cubic interpolation between 13 nodes: within 0.2 % of a direct FE run
    direct = fe_tooth_compliance(gear, r, closure="open", options=OPT).compliance
    assert_allclose(out[:, 0], direct, rtol=2e-3)

    def boom(*a, **k):
        raise AssertionError("FE recomputed although cached")

    monkeypatch.setattr(tables, "fe_tooth_compliance", boom)
    again = tables.fe_compliance(gear, r, settings=settings, options=OPT)
    assert_allclose(again, out, rtol=0, atol=0)
    # a different crack side is another key: computed, so it must call the FE model
    with pytest.raises(AssertionError, match="recomputed"):
        tables.fe_compliance(gear, r, crack=spur.cracks[0], depth=1e-3, side=-1,
                             settings=settings, options=OPT)


def test_fem_table_refines_level_for_shallow_crack(spur, cache):
    gear = spur.gears[0]
    assert tables._level_for(gear, 1e-3, 0) == 1  # 0.8 mm > 0.5 mm -> 0.4 mm
    assert tables._level_for(gear, 0.0, 0) == 0


def test_fem_table_as_mesh_stiffness_source(spur, cache):
    pair = spur.pairs[0]
    pe = mesh_stiffness(pair, settings=StiffnessSettings(positions_per_cycle=8))
    s = StiffnessSettings(positions_per_cycle=8, source="fe")
    with pytest.raises(InputError, match="stiffness.source"):  # never a silent PE answer
        mesh_stiffness(pair, settings=s)
    fe = mesh_stiffness(pair, settings=s, compliance=FiniteElementCompliance())
    # the train chooses the model from its settings (one layer up)
    via_train = dataclasses.replace(spur.with_crack("none"), stiffness=s).mesh_stiffness(0)
    np.testing.assert_array_equal(via_train.k, fe.k)
    # FE teeth are stiffer (see test_fem_tooth); with Hertz in series the mesh
    # stiffness rises by less than the tooth stiffness difference (< 15 %)
    ratio = fe.mean / pe.mean
    assert 1.0 < ratio < 1.15, ratio
    assert fe.k.shape == pe.k.shape


def test_fem_cli_fe_check_json(tmp_path):
    from gearsim.cli import app

    runner = CliRunner()
    res = runner.invoke(app, ["fe-check", "spur-19-48", "--crack", "working", "--closure",
                              "open", "--level", "1", "--points", "5", "--json", "--plot",
                              str(tmp_path)])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert doc["mesh"]["level"] == 1 and doc["crack"] == "working"
    assert set(doc["difference_percent"]) == {"max", "min", "mean"}
    assert len(doc["compliance_fe_m_per_N_per_m"]) == 5
    assert list(tmp_path.glob("*.png"))
    res = runner.invoke(app, ["fe-check", "spur-19-48", "--level", "1", "--points", "4"])
    assert res.exit_code == 0, res.output
    assert "difference (k_PE - k_FE)/k_FE" in res.output and "level 1" in res.output


def test_fem_check_needs_crack_in_config(spur):
    from gearsim.errors import InputError
    from gearsim.fem.check import fe_check

    train = dataclasses.replace(spur, cracks=())
    with pytest.raises(InputError, match="no \\[\\[cracks\\]\\]"):
        fe_check(train, "pinion", crack="working", level=1)
