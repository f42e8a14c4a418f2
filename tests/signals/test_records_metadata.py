"""Sampling rate, units and channel names read from what files carry: MAT header structs of
acquisition exporters (each variable stored twice), TDMS, UFF-58, WAV and NetCDF; the rate's
provenance is ``file`` and scipy's warnings come out as one line each."""

import io
import json
import subprocess
import sys
import warnings

import numpy as np
import pytest
import pyuff
import xarray as xr
from nptdms import ChannelObject, GroupObject, TdmsWriter
from numpy.testing import assert_array_equal
from scipy.io import savemat, wavfile

from gearsim.errors import InputError
from gearsim.io.measured import read_record

RATE = 25_600.0
N = 4096


def _signals(k: int) -> list[np.ndarray]:
    rng = np.random.default_rng(7)
    return [rng.standard_normal(N) for _ in range(k)]


def _exporter_mat(path, signals, head=None, twice=True):
    """A MAT file shaped like a common acquisition exporter's: ``Data1``, ``Data2``, ...
    with header structs ``Head_1``, ``Head_2``, ...; with ``twice`` every variable is
    stored twice, the first copy of the data all zeros (as the exporter writes it)."""
    heads = {f"Head_{j}": head if head is not None else
             {"SampFreq": RATE, "XInc": 1.0 / RATE, "Unit": "m/s^2", "Name": f"acc{j}"}
             for j in range(1, len(signals) + 1)}
    full = io.BytesIO()
    savemat(full, {**{f"Data{j}": x for j, x in enumerate(signals, 1)}, **heads})
    if not twice:
        path.write_bytes(full.getvalue())
        return path
    zeros = io.BytesIO()
    savemat(zeros, {**{f"Data{j}": np.zeros(N) for j in range(1, len(signals) + 1)}, **heads})
    path.write_bytes(zeros.getvalue() + full.getvalue()[128:])  # one header, two copies
    return path


def test_exporter_mat_rate_units_names_and_the_nonzero_copy(tmp_path):
    xs = _signals(3)
    p = _exporter_mat(tmp_path / "run.mat", xs)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = read_record(p)
    assert r.fs == RATE and r.fs_source == "file"
    assert r.channels == ("acc1", "acc2", "acc3")  # the header's names; Data1.. are aliases
    assert set(r.available) >= {"Data1", "Data2", "Data3"}
    assert r.units == {f"acc{j}": "m/s^2" for j in (1, 2, 3)}
    for j, x in enumerate(xs, 1):
        assert_array_equal(r.data[f"acc{j}"], x)  # the copy holding data, not the zeros
    with pytest.warns(UserWarning, match="stored more than once"):
        assert_array_equal(read_record(p, channels=["Data2"]).data["Data2"], xs[1])
    texts = [str(w.message) for w in caught]
    assert len(texts) == 1 and "\n" not in texts[0], texts  # one line, no scipy warning
    assert texts[0].startswith("run.mat: Data1, Data2, Data3, Head_1, Head_2, Head_3 stored "
                               "more than once")


@pytest.mark.parametrize("field,value", [
    ("SampFreq", RATE), ("Fs", RATE), ("fs", RATE), ("SampleRate", RATE),
    ("sampling_rate", RATE), ("dt", 1.0 / RATE), ("XInc", 1.0 / RATE),
    ("Increment", 1.0 / RATE),
])
def test_mat_header_field_names(tmp_path, field, value):
    p = _exporter_mat(tmp_path / "h.mat", _signals(2), head={field: value}, twice=False)
    r = read_record(p)
    assert r.fs == pytest.approx(RATE, rel=1e-12) and r.fs_source == "file"
    assert r.channels == ("Data1", "Data2") and r.units == {"Data1": None, "Data2": None}


def test_mat_nested_header_and_scalar_interval(tmp_path):
    x, = _signals(1)
    p = tmp_path / "lms.mat"
    savemat(p, {"Signal_1": x, "Head_1": {"x_values": {"start_value": 0.0,
                                                        "increment": 1.0 / RATE}}})
    assert read_record(p).fs == pytest.approx(RATE, rel=1e-12)
    savemat(p, {"acc": x, "DT": 1.0 / RATE})  # a scalar variable: any case
    assert read_record(p).fs == pytest.approx(RATE, rel=1e-12)


def test_mat_headers_of_different_rates_each_to_its_channel(tmp_path):
    a, b = _signals(2)
    p = tmp_path / "two.mat"
    savemat(p, {"Data1": a, "Head_1": {"SampFreq": RATE}, "Data2": b,
                "Head_2": {"SampFreq": RATE / 2}})
    assert read_record(p, channels=["Data2"]).fs == RATE / 2
    with pytest.raises(InputError, match="have different sampling rates"):
        read_record(p)


def test_mat_zero_interval_refused(tmp_path):
    p = _exporter_mat(tmp_path / "z.mat", _signals(1), head={"XInc": 0.0}, twice=False)
    with pytest.raises(InputError, match=r"stored sampling rate inf of 'Data1' is not a "
                                         r"number in \[0.001, 1e\+09\] Hz"):
        read_record(p)


def test_every_format_gives_its_rate_from_the_file(tmp_path):
    rate = 12_345.0  # no default of any writer
    x, = _signals(1)
    wavfile.write(tmp_path / "r.wav", int(rate), (x / 8 * 32767).astype(np.int16))
    with TdmsWriter(str(tmp_path / "r.tdms")) as w:  # the rate on the group
        w.write_segment([GroupObject("g", properties={"SampleRate": rate}),
                         ChannelObject("g", "acc", x, properties={"unit_string": "g"})])
    pyuff.UFF(str(tmp_path / "r.uff")).write_sets([pyuff.prepare_58(
        binary=0, id1="acc", func_type=1, rsp_node=1, rsp_dir=3, ref_node=0, ref_dir=0,
        ord_data_type=4, num_pts=N, abscissa_spacing=1, abscissa_min=0.0,
        abscissa_inc=1.0 / rate, x=np.arange(N) / rate, data=x,
        orddenom_spec_data_type=0)], mode="add")
    # NetCDF without a time coordinate: one dimension and a rate attribute
    xr.Dataset({"acc": ("sample", x, {"units": "g"})}, attrs={"sampling_rate": rate}).to_netcdf(
        tmp_path / "r.nc", engine="h5netcdf")
    xr.Dataset({"acc": ("time", x)}, attrs={"dt": 1.0 / rate}).to_netcdf(
        tmp_path / "dt.nc", engine="h5netcdf")
    for name in ("r.wav", "r.tdms", "r.uff", "r.nc", "dt.nc"):
        r = read_record(tmp_path / name)
        assert r.fs == pytest.approx(rate, rel=1e-5) and r.fs_source == "file", name
    assert read_record(tmp_path / "r.tdms").units == {"acc": "g"}
    assert read_record(tmp_path / "r.nc").units == {"acc": "g"}


def test_cli_reads_the_exporter_file_with_one_warning_line(tmp_path):
    """The installed path: the rate from the file (provenance ``file``), the doubled
    variables said in one ``gearsim: warning:`` line, nothing of scipy's."""
    p = _exporter_mat(tmp_path / "run.mat", _signals(2))
    r = subprocess.run([sys.executable, "-m", "gearsim.cli", "analyze", str(p), "--channel",
                        "acc1", "--json"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    (rec,) = json.loads(r.stdout)["records"]
    assert rec["fs_hz"] == RATE and rec["fs_provenance"] == "file" and rec["units"] == "m/s^2"
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gearsim: warning: run.mat: Data1, Data2"), \
        r.stderr
