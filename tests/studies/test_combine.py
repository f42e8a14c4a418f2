"""A study's store from its group tables: ``combine`` against ``xarray.concat``.

``combine`` joins the parts array by array (``xarray.concat`` cost ~6 ms a part, 12 s
for a 2000-case study). The reference is xarray's own join of the same tables along
``case`` and ``sortby("case")``, with the missing variables filled as documented; the
two must be identical: values, dtypes (text widths), attributes and variable order.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from gearsim.studies.sweep import loads_study
from gearsim.studies.sweep_run import combine

STUDY = loads_study("""
[study]
name = "combine"
config = "spur-19-48"
[parameters]
crack_depth = ["1 mm", "2 mm"]
noise = [0.0, 0.1]
""")


def _part(cases: list[int], *, failed: bool = False, signal: bool = False) -> xr.Dataset:
    """A group table shaped as ``run_group`` makes it (parameters as coordinates)."""
    rng = np.random.default_rng(cases[0])
    n = len(cases)
    coords = {"case": ("case", cases),
              "case_key": ("case", [f"{c:016x}" for c in cases]),
              "crack_depth": ("case", [1e-3 * (1 + c % 2) for c in cases], {"units": "m"}),
              "flank": ("case", ["working"] * n)}
    data = {"status": ("case", ["failed" if failed else "ok"] * n),
            "error": ("case", ["dynamics.fs = 1: must be > 2 f_m" if failed else ""] * n)}
    if not failed:
        data |= {"td_rms": ("case", rng.normal(size=n)),
                 "tsa_fm4": ("case", rng.normal(size=n), {"long_name": "FM4"})}
        if signal:
            data["signal"] = (("case", "sample"), rng.normal(size=(n, 5)))
            coords["sample_time"] = ("sample", np.arange(5) / 10.0, {"units": "s"})
    return xr.Dataset(data, coords=coords)


def _reference(parts: list[xr.Dataset]) -> xr.Dataset:
    """xarray's join: missing variables filled (NaN, empty text), concat, sortby."""
    names: dict = {}
    for p in parts:
        for k, v in p.data_vars.items():
            names.setdefault(k, (v.dims, v.dtype, v.shape[1:]))
    filled = []
    sample_time = next((p["sample_time"] for p in parts if "sample_time" in p.coords), None)
    for p in parts:
        p = p.drop_vars([c for c in ("sample_time",) if c in p.coords])
        for k, (dims, dtype, tail) in names.items():
            if k not in p:
                p[k] = (dims, np.full((p.sizes["case"], *tail),
                                      np.nan if dtype.kind == "f" else "", dtype=dtype))
        filled.append(p)
    ds = xr.concat(filled, dim="case", data_vars="all", coords="minimal",
                   compat="override", join="outer").sortby("case")
    return ds if sample_time is None else ds.assign_coords(sample_time=sample_time)


@pytest.mark.parametrize("layout", ["ok", "failed-first", "failed-middle", "signals",
                                    "shuffled"])
def test_combine_equals_xarray_concat(layout):
    parts = [_part([0, 1]), _part([2]), _part([3, 4, 5]), _part([6, 7])]
    if layout == "failed-first":
        parts[0] = _part([0, 1], failed=True)
    elif layout == "failed-middle":
        parts[2] = _part([3, 4, 5], failed=True)
    elif layout == "signals":
        parts = [_part([0, 1], signal=True), _part([2], failed=True),
                 _part([3, 4, 5], signal=True)]
    elif layout == "shuffled":
        parts = [parts[2], parts[0], parts[3], parts[1]]
    got = combine(STUDY, parts)
    want = _reference(parts)
    want.attrs = got.attrs
    xr.testing.assert_identical(got, want)
    assert list(got.data_vars) == list(want.data_vars)
    for k in got.variables:
        assert got[k].dtype == want[k].dtype, k
        assert got[k].attrs == want[k].attrs, k
    assert got["case"].values.tolist() == sorted(got["case"].values.tolist())
    assert got.attrs["n_failed"] == int(np.sum(got["status"].values != "ok"))


@pytest.mark.parametrize("kind,match", [("record", "shape of 'signal'"),
                                        ("coordinate", "coordinates")])
def test_parts_of_unequal_layout_are_refused_as_xarray_refuses_them(kind, match):
    """Records of different lengths, or a coordinate only some parts carry: xarray's
    join refuses them, and so does combine, naming what differs (a study's groups share
    both)."""
    if kind == "record":
        parts = [_part([0, 1], signal=True), _part([2], signal=True).isel(sample=slice(0, 4))]
    else:
        parts = [_part([0, 1]), _part([3]).assign_coords(fault=("case", ["spall"]))]
    with pytest.raises(ValueError):
        _reference(parts)
    with pytest.raises(ValueError, match=match):
        combine(STUDY, parts)
