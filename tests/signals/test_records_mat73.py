"""MAT v7.3 files (MATLAB's ``save -v7.3``: HDF5 behind a 512-byte MATLAB header).

The files are written here with h5py in the layout MATLAB documents for v7.3 (one
dataset or group per variable, ``MATLAB_class`` attributes, arrays stored transposed,
char arrays as uint16 codes, structs as groups), shaped like a common acquisition
exporter's: ``Data1``, ``Data2`` and header structs ``Head_1``, ``Head_2`` whose
``SampFreq`` gives the rate.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from numpy.testing import assert_array_equal

from gearsim.errors import InputError
from gearsim.io.measured import read_record

RATE = 25600.0
N = 5120


def _header(text: str) -> bytes:
    return text.encode().ljust(116, b" ") + b"\x00" * 8 + b"\x00\x02" + b"IM"


def _char(group, name: str, text: str) -> None:
    d = group.create_dataset(name, data=np.array([[ord(c)] for c in text], dtype=np.uint16))
    d.attrs["MATLAB_class"] = np.bytes_("char")


def _double(group, name: str, value) -> None:
    # MATLAB is column-major: a 1 x n row vector is the HDF5 dataset (n, 1)
    d = group.create_dataset(name, data=np.atleast_2d(np.asarray(value, dtype=float)).T)
    d.attrs["MATLAB_class"] = np.bytes_("double")


def _v73(path, signals, heads):
    with h5py.File(path, "w", userblock_size=512) as f:
        for j, x in enumerate(signals, 1):
            _double(f, f"Data{j}", x[None, :])
        for name, fields in heads.items():
            g = f.create_group(name)
            g.attrs["MATLAB_class"] = np.bytes_("struct")
            for k, v in fields.items():
                (_char if isinstance(v, str) else _double)(g, k, v)
        cell = f.create_group("#refs#")  # where MATLAB keeps what cells point to
        cell.create_dataset("a", data=np.zeros(3))
    with open(path, "r+b") as fh:
        fh.write(_header("MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Thu Nov 26 "
                         "2026 HDF5 schema 1.00 ."))
    return path


def _signals(k: int) -> list[np.ndarray]:
    t = np.arange(N) / RATE
    return [np.sin(2 * np.pi * (100.0 * (j + 1)) * t) for j in range(k)]


def test_v73_rate_units_and_names_from_the_header_structs(tmp_path):
    xs = _signals(2)
    heads = {f"Head_{j}": {"SampFreq": RATE, "XInc": 1 / RATE, "Unit": "m/s^2",
                           "Name": f"acc{j}"} for j in (1, 2)}
    p = _v73(tmp_path / "run.mat", xs, heads)
    assert p.read_bytes()[:19] == b"MATLAB 7.3 MAT-file"
    r = read_record(p)
    assert r.fs == RATE and r.fs_source == "file"
    assert r.channels == ("acc1", "acc2")
    assert r.units == {"acc1": "m/s^2", "acc2": "m/s^2"}
    for j, x in enumerate(xs, 1):
        assert_array_equal(r.data[f"acc{j}"], x)


def test_v73_interval_only_and_disagreeing_headers(tmp_path):
    """``XInc`` alone gives the rate (1 / XInc); two channels at different rates are
    each read at their own, and a record of one of them says which."""
    xs = _signals(2)
    p = _v73(tmp_path / "xinc.mat", xs, {"Head_1": {"XInc": 1 / RATE},
                                          "Head_2": {"XInc": 1 / RATE}})
    assert read_record(p).fs == pytest.approx(RATE, rel=1e-12)
    q = _v73(tmp_path / "two.mat", xs, {"Head_1": {"SampFreq": RATE},
                                         "Head_2": {"SampFreq": RATE / 2}})
    assert read_record(q, channels="Data2").fs == RATE / 2
    with pytest.raises(InputError, match="rate"):
        read_record(q)  # both: channels of different rates


def test_v73_without_a_rate_is_read_and_refuses_only_what_needs_one(tmp_path):
    p = _v73(tmp_path / "bare.mat", _signals(1), {})
    r = read_record(p)
    assert r.fs is None and r.channels == ("Data1",)


def test_v73_that_is_not_hdf5_is_one_clear_error(tmp_path):
    p = tmp_path / "broken.mat"
    p.write_bytes(_header("MATLAB 7.3 MAT-file, Platform: GLNXA64") + b"\x00" * 600)
    with pytest.raises(InputError, match="broken.mat"):
        read_record(p)


@pytest.mark.parametrize("rate", [np.inf, np.nan, 0.0, -RATE, 1e300, 1e-300, 1e10, 1e-4])
def test_v73_impossible_stored_rate_is_refused(tmp_path, rate):
    """A stored rate outside [1e-3 Hz, 1 GHz] (gearsim.io.record) is a unit or exponent
    mistake: one error naming the file, the rate as stored and the range."""
    p = _v73(tmp_path / "bad.mat", _signals(1), {"Head_1": {"SampFreq": rate}})
    with pytest.raises(InputError) as exc:
        read_record(p)
    text = str(exc.value)
    assert len(text.splitlines()) == 1 and "bad.mat" in text and "[0.001, 1e+09] Hz" in text
    assert repr(float(rate)) in text


@pytest.mark.parametrize("given", ["1e300", "1e-300", "0", "-25600", "inf", "nan"])
def test_impossible_given_rate_is_refused_in_one_line(tmp_path, given, capsys):
    from gearsim.cli import run

    p = _v73(tmp_path / "bare.mat", _signals(1), {})
    assert run(["analyze", str(p), "--fs", given]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("gearsim: error:") and "--fs" in err[0], err
