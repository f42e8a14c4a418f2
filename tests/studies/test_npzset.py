"""The part-file codec (gearsim.io.npzset): a dataset round-trips exactly, nothing is
pickled, and bytes that are not a part are refused (a part that cannot be read is
recomputed by the sweep, never used)."""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest
import xarray as xr

from gearsim.io.npzset import FORMAT, FORMAT_V1, from_bytes, to_bytes
from gearsim.studies.sweep_run import read_part


def _table() -> xr.Dataset:
    """A group table shaped like a sweep's: case coordinates with units, text status,
    float features, a record over (case, sample_time), dataset attributes."""
    rng = np.random.default_rng(3)
    return xr.Dataset(
        {"status": ("case", np.array(["ok", "failed"])),
         "error": ("case", np.array(["", "a crack too deep: 9 mm"], dtype=object)),
         "td_rms": ("case", rng.normal(size=2)),
         "record": (("case", "sample_time"), rng.normal(size=(2, 5)).astype(np.float32),
                    {"units": "m/s^2"}),
         "count": ("case", np.array([3, -1], dtype=np.int64)),
         "flag": ("case", np.array([True, False]))},
        coords={"case": [4, 9], "crack_depth": ("case", [1e-3, 2.5e-3], {"units": "m"}),
                "flank": ("case", ["working", "non-working"]),
                "sample_time": ("sample_time", np.arange(5) / 2e4, {"units": "s"})},
        attrs={"warnings": "UserWarning\tsomething", "n": np.int64(2), "fs": np.float64(2e4),
               "list": np.array([1.5, 2.0])})


def test_round_trip_is_exact():
    ds = _table()
    back = from_bytes(to_bytes(ds))
    expected = ds.assign(error=ds["error"].astype(str))  # object text comes back as U
    expected.attrs.update(n=2, fs=2e4, list=[1.5, 2.0])
    xr.testing.assert_identical(back, expected)
    assert back["record"].dtype == np.float32 and back["count"].dtype == np.int64
    assert list(back.indexes) == ["case", "sample_time"]
    # bit-exact floats (no text round trip)
    assert back["td_rms"].values.tobytes() == ds["td_rms"].values.tobytes()


def test_nothing_is_pickled():
    with zipfile.ZipFile(io.BytesIO(to_bytes(_table()))) as z:
        for name in z.namelist():
            head = z.read(name)[:128]
            assert b"'descr': '|O'" not in head and b"descr': '|O" not in head, name
    with np.load(io.BytesIO(to_bytes(_table())), allow_pickle=False) as z:
        assert str(z["__meta__"][()]).count(FORMAT) == 1


def test_unstorable_values_are_refused():
    bad = xr.Dataset({"x": ("case", np.array([{"a": 1}], dtype=object))})
    with pytest.raises(TypeError, match="'x'"):
        to_bytes(bad)


@pytest.mark.parametrize("data", [b"", b"not a zip", to_bytes(_table())[:200]])
def test_broken_bytes_are_not_a_part(data, tmp_path):
    with pytest.raises(ValueError, match="not a gearsim part"):
        from_bytes(data)
    path = tmp_path / "k.npz"
    path.write_bytes(data)
    assert read_part(path) is None  # the sweep recomputes it


def test_another_format_is_not_a_part(tmp_path):
    buf = io.BytesIO()
    np.savez(buf, __meta__=np.array('{"format": "other", "attrs": {}, "variables": []}'))
    with pytest.raises(ValueError, match="format 'other'"):
        from_bytes(buf.getvalue())
    assert read_part(tmp_path / "missing.npz") is None


def _version1(ds: xr.Dataset) -> bytes:
    """``ds`` as a version-1 archive (one member per variable), written out by hand from
    the format's description, as parts written before version 2 are on disk."""
    arrays, meta = {}, []
    for i, name in enumerate([*ds.data_vars, *ds.coords]):
        var = ds.variables[name]
        values = var.values.astype(str) if var.dtype.kind == "O" else var.values
        arrays[f"v{i}"] = values
        meta.append({"name": name, "dims": list(var.dims), "coord": name in ds.coords,
                     "attrs": dict(var.attrs)})
    head = {"format": FORMAT_V1, "attrs": {"warnings": ds.attrs["warnings"]},
            "variables": meta}
    buf = io.BytesIO()
    np.savez(buf, __meta__=np.array(__import__("json").dumps(head)), **arrays)
    return buf.getvalue()


def test_version_1_parts_are_still_read():
    """A study interrupted before the packed format resumes from its parts."""
    ds = _table().drop_attrs()
    ds.attrs["warnings"] = "UserWarning\tsomething"
    back = from_bytes(_version1(ds))
    xr.testing.assert_identical(back, ds.assign(error=ds["error"].astype(str)))


def test_packed_blocks_one_member_per_dtype():
    with zipfile.ZipFile(io.BytesIO(to_bytes(_table()))) as z:
        names = sorted(z.namelist())
    # ten variables of seven dtypes (f8, f4, i8, b1 and text of widths 6, 11, 22)
    assert names == ["__meta__.npy", *(f"d{i}.npy" for i in range(7))]


def test_a_variable_outside_its_block_is_not_a_part():
    buf = io.BytesIO(to_bytes(_table()))
    with np.load(buf, allow_pickle=False) as z:
        members = {k: z[k] for k in z.files}
    head = __import__("json").loads(str(members["__meta__"][()]))
    head["variables"][0]["offset"] = 10**6
    members["__meta__"] = np.array(__import__("json").dumps(head))
    out = io.BytesIO()
    np.savez(out, **members)
    with pytest.raises(ValueError, match="not a gearsim part"):
        from_bytes(out.getvalue())
