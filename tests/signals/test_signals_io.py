"""Readers of measured files: round trips through the writing library, and bad files."""

import numpy as np
import pytest
import pyuff
import xarray as xr
from nptdms import ChannelObject, TdmsWriter
from numpy.testing import assert_allclose
from scipy.io import savemat, wavfile

from gearsim.errors import InputError
from gearsim.io.measured import list_channels, read_signal

#: Data written in float64 and read back: bit-exact; text (CSV, %.17g) is also exact.
RTOL_DATA = 0.0
#: UFF stores the abscissa increment with 6 significant digits: fs to 5e-6 relative.
RTOL_FS_UFF = 1e-5

FS = 48_000.0


@pytest.fixture()
def data():
    rng = np.random.default_rng(12)
    return rng.standard_normal(4800), rng.standard_normal(4800)


def _truncate(path, fraction=0.5):
    b = path.read_bytes()
    path.write_bytes(b[: int(len(b) * fraction)])


def test_csv_with_time_column(tmp_path, data):
    a, b = data
    t = np.arange(a.size) / FS
    p = tmp_path / "rec.csv"
    np.savetxt(p, np.column_stack([t, a, b]), delimiter=",", header="time,acc,tacho",
               comments="", fmt="%.17g")
    s = read_signal(p, channel="acc")
    assert_allclose(s.data, a, rtol=RTOL_DATA)
    assert_allclose(s.fs, FS, rtol=1e-9)
    assert s.fs_source == "file" and s.channels == ("acc", "tacho")


def test_csv_without_fs_needs_user_rate(tmp_path, data):
    a, _ = data
    p = tmp_path / "rec.csv"
    np.savetxt(p, a, fmt="%.17g")
    with pytest.raises(InputError, match="fs = None: must be given"):
        read_signal(p)
    s = read_signal(p, fs=FS)
    assert s.fs == FS and s.fs_source == "user" and s.channel == "0"
    assert_allclose(s.data, a, rtol=RTOL_DATA)


def test_csv_fs_comment_and_truncated_row(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.csv"
    np.savetxt(p, np.column_stack([a, b]), delimiter=",", header="# fs = 48000\nacc,tacho",
               comments="", fmt="%.17g")
    assert read_signal(p, channel="tacho").fs == FS
    with open(p, "a") as fh:
        fh.write("0.5,")  # a last row cut in the middle
    with pytest.raises(InputError, match="row 4801"):
        read_signal(p, channel="tacho")


def test_wav_round_trip_and_int_scaling(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.wav"
    wavfile.write(p, int(FS), np.column_stack([a, b]).astype(np.float32))
    s = read_signal(p, channel="1")
    assert_allclose(s.data, b.astype(np.float32), rtol=RTOL_DATA)
    assert s.fs == FS
    q = tmp_path / "int.wav"
    wavfile.write(q, int(FS), np.array([0, 16384, -32768], dtype=np.int16))
    assert_allclose(read_signal(q).data, [0.0, 0.5, -1.0])


def test_mat_round_trip(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.mat"
    savemat(p, {"acc": a, "block": np.column_stack([a, b]), "fs": FS})
    s = read_signal(p, channel="block:1")
    assert_allclose(s.data, b, rtol=RTOL_DATA)
    assert s.fs == FS
    assert set(list_channels(p)) == {"acc", "block:0", "block:1"}
    q = tmp_path / "time.mat"
    savemat(q, {"acc": a, "t": np.arange(a.size) / 25_000.0})
    assert_allclose(read_signal(q).fs, 25_000.0, rtol=1e-9)


def test_tdms_round_trip(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.tdms"
    props = {"wf_increment": 1.0 / FS, "unit_string": "m/s^2"}
    with TdmsWriter(str(p)) as w:
        w.write_segment([ChannelObject("bench", "acc", a, properties=props),
                         ChannelObject("bench", "tacho", b, properties={"wf_increment": 1 / FS})])
    s = read_signal(p, channel="bench/acc")
    assert_allclose(s.data, a, rtol=RTOL_DATA)
    assert_allclose(s.fs, FS, rtol=1e-12)
    assert s.units == "m/s^2"
    assert_allclose(read_signal(p, channel="tacho").data, b, rtol=RTOL_DATA)


def _uff_set(name, y):
    return pyuff.prepare_58(
        binary=1, id1=name, id2="", id3="", id4="", id5="", func_type=1, rsp_node=1,
        rsp_dir=3, ref_node=0, ref_dir=0, ord_data_type=4, num_pts=y.size,
        abscissa_spacing=1, abscissa_min=0.0, abscissa_inc=1.0 / FS, x=np.arange(y.size) / FS,
        data=y, orddenom_spec_data_type=0,
    )


def test_uff_type58_round_trip(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.uff"
    pyuff.UFF(str(p)).write_sets([_uff_set("acc", a), _uff_set("tacho", b)], mode="add")
    s = read_signal(p, channel="acc")
    assert_allclose(s.data, a, rtol=RTOL_DATA)
    assert_allclose(s.fs, FS, rtol=RTOL_FS_UFF)
    assert_allclose(read_signal(p, channel="1", fs=FS).data, b, rtol=RTOL_DATA)


def test_netcdf_simulator_output(tmp_path, data):
    a, b = data
    p = tmp_path / "sim.nc"
    t = np.arange(a.size) / FS
    xr.Dataset({"mesh_force_1": ("time", a, {"units": "N"}), "mesh_force_2": ("time", b)},
               coords={"time": t}, attrs={"fs": FS}).to_netcdf(p, engine="h5netcdf")
    s = read_signal(p, channel="mesh_force_1")
    assert_allclose(s.data, a, rtol=RTOL_DATA)
    assert_allclose(s.fs, FS, rtol=1e-9)
    assert s.units == "N"
    q = tmp_path / "noattr.nc"
    xr.Dataset({"mesh_force_1": ("time", a)}, coords={"time": t}).to_netcdf(q, engine="h5netcdf")
    assert_allclose(read_signal(q).fs, FS, rtol=1e-9)


def test_netcdf_simulator_layout(tmp_path, data):
    """Layout of gearsim.dynamics output: time offset by the transient, 3-D variables."""
    a, b = data
    t = 0.25 + np.arange(a.size) / FS
    acc = np.stack([np.column_stack([a, b]), np.column_stack([b, a])], axis=1)
    ds = xr.Dataset(
        {"mesh_force_1": ("time", a, {"units": "N"}),
         "acceleration": (("time", "gear", "axis"), acc, {"units": "m/s^2"})},
        coords={"time": ("time", t, {"units": "s"}), "gear": ["G1", "G2"], "axis": ["x", "y"]},
        attrs={"fs": FS, "mesh_frequency": 1235.0})
    p = tmp_path / "dyn.nc"
    ds.to_netcdf(p, engine="h5netcdf")
    s = read_signal(p, channel="acceleration[gear=G2,axis=x]")
    assert_allclose(s.data, b, rtol=RTOL_DATA)
    assert s.units == "m/s^2"
    assert_allclose(s.fs, FS, rtol=1e-9)
    assert "acceleration[gear=G1,axis=y]" in s.channels


def test_missing_channel(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.mat"
    savemat(p, {"acc": a, "tacho": b, "fs": FS})
    with pytest.raises(InputError, match=r"channel = speed: not in rec.mat; available") as e:
        read_signal(p, channel="speed")
    assert "\n" not in str(e.value)
    with pytest.raises(InputError, match="must be given"):
        read_signal(p)


def test_fs_disagreement_refused(tmp_path, data):
    a, _ = data
    p = tmp_path / "rec.wav"
    wavfile.write(p, int(FS), a.astype(np.float32))
    with pytest.raises(InputError, match="disagrees"):
        read_signal(p, fs=44_100.0)


@pytest.mark.parametrize("kind", ["wav", "mat", "tdms", "uff", "nc"])
def test_truncated_files_refused(tmp_path, data, kind):
    a, b = data
    p = tmp_path / f"rec.{kind}"
    if kind == "wav":
        wavfile.write(p, int(FS), a.astype(np.float32))
    elif kind == "mat":
        savemat(p, {"acc": a, "fs": FS})
    elif kind == "tdms":
        with TdmsWriter(str(p)) as w:
            w.write_segment([ChannelObject("g", "acc", a, properties={"wf_increment": 1 / FS})])
    elif kind == "uff":
        pyuff.UFF(str(p)).write_sets([_uff_set("acc", a)], mode="add")
    else:
        xr.Dataset({"acc": ("time", a)}, coords={"time": np.arange(a.size) / FS}).to_netcdf(
            p, engine="h5netcdf")
    _truncate(p)
    with pytest.raises(InputError, match="^file = .*cannot be read as") as e:
        read_signal(p, channel="acc" if kind != "wav" else None)
    assert "\n" not in str(e.value)


def test_missing_empty_and_unknown_files(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        read_signal(tmp_path / "nope.wav")
    (tmp_path / "empty.csv").write_text("")
    with pytest.raises(InputError, match="is empty"):
        read_signal(tmp_path / "empty.csv")
    (tmp_path / "x.bin").write_bytes(b"1234")
    with pytest.raises(InputError, match="extension"):
        read_signal(tmp_path / "x.bin")
    (tmp_path / "junk.wav").write_bytes(b"not a wav file at all")
    with pytest.raises(InputError, match="cannot be read as WAV"):
        read_signal(tmp_path / "junk.wav")


def test_nan_samples_refused(tmp_path, data):
    a, _ = data
    a = a.copy()
    a[10] = np.nan
    p = tmp_path / "nan.mat"
    savemat(p, {"acc": a, "fs": FS})
    with pytest.raises(InputError, match=r"acc\[10\]"):
        read_signal(p)
