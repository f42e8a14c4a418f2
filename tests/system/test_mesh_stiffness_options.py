"""Stiffness options written on the mesh they belong to: a ``[[meshes]]`` table's own
``stiffness`` (issue 23: meshes between two gears, each with its own stiffness options).

Independent numbers: the same mesh of a copy of the two-stage reducer whose whole
``[stiffness]`` holds the mesh's values (keys a mesh does not give come from the file's
``[stiffness]``, so the copy names them too where the file's model would change them);
the unmodified reducer for the other mesh; a run from stiffness tables assembled by hand
from those two boxes.
"""

from __future__ import annotations

import dataclasses
import sys

import numpy as np
import pytest

import gearsim as gs
from gearsim.dynamics import build_model, simulate
from gearsim.dynamics.tables import mesh_tables
from gearsim.errors import InputError
from gearsim.model.config import example_text

REDUCER = example_text("two-stage-reducer")
MESH_II = 'gears = ["intermediate-pinion", "output-gear"]\nangle = "180 deg"\n'


def _own(table: str) -> str:
    """The reducer with mesh II's own ``stiffness = {table}``."""
    return REDUCER.replace(MESH_II, MESH_II + f"stiffness = {{ {table} }}\n")


def _everywhere(keys: str) -> str:
    """The reducer with ``keys`` in its ``[stiffness]`` (every mesh)."""
    return REDUCER.replace("[stiffness]\n", "[stiffness]\n" + keys)


# (mesh II's own table, the same options as the file's [stiffness]); the reducer's
# [stiffness] names no model: the accurate one (calibrated source, line contact, FE body
# coupling), which a mesh's "source" keeps and a [stiffness] "source" alone would not
CASES = [('model = "seed"', 'model = "seed"\n'),
         ('source = "fe"', 'source = "fe"\ncontact = "line"\ncoupling = "fe"\n'),
         ('plane = "strain", gauss_points = 8', 'plane = "strain"\ngauss_points = 8\n')]


@pytest.mark.parametrize(("own", "everywhere"), CASES)
def test_a_mesh_with_its_own_options_is_that_mesh_of_a_box_with_them_everywhere(own,
                                                                              everywhere):
    tr = gs.loads(_own(own)).train
    base, same = gs.loads(REDUCER).train, gs.loads(_everywhere(everywhere)).train
    assert tr.settings_of(1) == same.stiffness and tr.settings_of(0) == base.stiffness
    for rev in (1, 2):
        k_i, k_ii = (tr.mesh_stiffness(i, revolution_of=rev).k for i in (0, 1))
        assert np.array_equal(k_i, base.mesh_stiffness(0, revolution_of=rev).k)
        assert np.array_equal(k_ii, same.mesh_stiffness(1, revolution_of=rev).k)
        assert not np.array_equal(k_ii, base.mesh_stiffness(1, revolution_of=rev).k)


def test_the_run_takes_each_mesh_with_its_own_tables():
    gb = gs.loads(_own('model = "seed"'))
    base, same = gs.loads(REDUCER).train, gs.loads(_everywhere('model = "seed"\n')).train
    # mesh II's seed table: k_mean 352.2 MN/m against the accurate model's 278.7 MN/m
    k_base, k_same = (t.mesh_stiffness(1).k.mean() for t in (base, same))
    assert k_base == pytest.approx(2.7865e8, rel=1e-3)
    assert k_same == pytest.approx(3.5216e8, rel=1e-3)
    tables = (mesh_tables(base)[0], mesh_tables(same)[1])  # assembled by hand
    kappa = build_model(gb.train, gb.dynamics).mean_stiffness()
    np.testing.assert_array_equal(kappa, build_model(base, gb.dynamics,
                                                     tables=tables).mean_stiffness())
    assert kappa[1] / build_model(base, gb.dynamics).mean_stiffness()[1] == pytest.approx(
        k_same / k_base, rel=1e-12)
    kw = {"duration": 0.12, "transient": 0.01}
    ds = gb.simulate(**kw)
    ref = simulate(base, dataclasses.replace(gb.dynamics, **kw), tables=tables)
    np.testing.assert_array_equal(ds["mesh_force_2"].values, ref["mesh_force_2"].values)
    assert gs.loads(ds.attrs["config"]).train == gb.train  # the provenance says it


@pytest.mark.parametrize(("table", "parameter", "words"), [
    ("slices = 0", "meshes[1].stiffness.slices", "in [1, 2000]"),
    ("positions_per_cycle = -40", "meshes[1].stiffness.positions_per_cycle",
     "in [4, 10000]"),
    ('slices = "nan"', "meshes[1].stiffness.slices", "must be an integer"),
    ("gauss_points = nan", "meshes[1].stiffness.gauss_points", "must be an integer"),
    ("slice = 3", "meshes[1].stiffness.slice", "unknown key"),
    ("corner_contact = 1", "meshes[1].stiffness.corner_contact", "true or false"),
    ("slices = 2.5", "meshes[1].stiffness.slices", "must be an integer"),
    ('closure = "shut"', "meshes[1].stiffness.closure", '"open" or "contact"'),
    ('contact = "yang-lin"', "meshes[1].stiffness.source", 'needs contact = "line"'),
    ('model = "seed", source = "fe"', "meshes[1].stiffness.model", "either model"),
])
def test_bad_mesh_values_are_named_where_written(table, parameter, words):
    with pytest.raises(InputError) as e:
        gs.loads(_own(table))
    assert e.value.parameter == parameter and words in str(e.value), str(e.value)


def test_not_a_table_and_the_command_line_exit_2(tmp_path, monkeypatch, capsys):
    with pytest.raises(InputError, match=r"^meshes\[0\]\.stiffness = 40: must be a table"):
        gs.loads(REDUCER.replace('gears = ["input-pinion", "intermediate-gear"]\n',
                                 'gears = ["input-pinion", "intermediate-gear"]\n'
                                 "stiffness = 40\n"))
    from gearsim.cli import main

    cfg, out = tmp_path / "box.toml", tmp_path / "run.nc"
    cfg.write_text(_own("slices = 0"))
    monkeypatch.setattr(sys, "argv", ["gearsim", "simulate", str(cfg), "--out", str(out)])
    with pytest.raises(SystemExit) as exc:
        main()
    assert exc.value.code == 2 and not out.exists()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "meshes[1].stiffness.slices = 0" in err[0], err


def test_written_back_only_what_differs_and_read_back_equal():
    gb = gs.loads(_own('model = "seed", positions_per_cycle = 20, corner_contact = false'))
    text = gb.to_toml()
    own = text[text.index("[meshes.stiffness]"):text.index("[operating]")].split()
    assert own == ["[meshes.stiffness]", "positions_per_cycle", "=", "20", 'source', "=",
                   '"pe"', "corner_contact", "=", "false", "contact", "=", '"yang-lin"',
                   "coupling", "=", '"none"']
    assert text.count("[meshes.stiffness]") == 1 and gs.loads(text) == gb
    # the same options as the file's: nothing of its own
    same = gs.loads(_own("positions_per_cycle = 40"))
    assert same.train == gs.loads(REDUCER).train
    assert "[meshes.stiffness]" not in same.to_toml()


def test_beside_a_stage_the_gears_take_their_own_and_write_them_back():
    mesh = 'gears = ["intermediate-gear", "high-speed-pinion"]\nangle = "180 deg"\n'
    gb = gs.loads(example_text("wind-turbine-grc").replace(mesh, mesh + "stiffness = "
                                                           "{ slices = 5 }\n"))
    assert [gb.train.settings_of(i).slices for i in (0, 1)] == [10, 5]
    assert gs.loads(gb.to_toml()) == gb


def test_a_variant_switches_every_mesh():
    gb = gs.loads(_own('model = "seed", closure = "contact"'))
    for v in (gb.with_crack("working", closure="open"), gb.replace(stiffness={
            "closure": "open"})):
        assert [v.train.settings_of(i).closure for i in (0, 1)] == ["open", "open"]
        assert v.train.settings_of(1).source == "pe"  # its own options otherwise kept
    pe = gb.with_crack(None, source="pe").train
    assert [pe.settings_of(i).source for i in (0, 1)] == ["pe", "pe"]
    assert pe.settings_of(1).contact == "yang-lin" and pe.settings_of(0).contact == "line"


@pytest.mark.parametrize("key,choices", [("plane", "stress, strain"),
                                         ("model", "seed, accurate"),
                                         ("closure", "contact, open")])
def test_a_choice_written_as_a_number_lists_the_choices(key, choices):
    # it said "must be a string" alone (probe round 9)
    text = example_text("two-stage-reducer").replace(
        '[[meshes]]\ngears = ["intermediate-pinion", "output-gear"]',
        f'[[meshes]]\ngears = ["intermediate-pinion", "output-gear"]\nstiffness = {{ {key} = 1 }}')
    with pytest.raises(InputError, match=rf"^meshes\[1\]\.stiffness\.{key} = 1: must be one of "
                       rf"{choices} \(a string\)$"):
        gs.loads(text)
