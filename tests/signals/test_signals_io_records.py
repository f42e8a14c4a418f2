"""Records as they come: compressed files, CSV dialects and metadata, all channels, problems
reported together, non-finite samples dropped and reported."""

import bz2
import gzip
import lzma
import zipfile

import numpy as np
import pytest
import pyuff
import xarray as xr
from nptdms import ChannelObject, TdmsWriter
from numpy.testing import assert_allclose, assert_array_equal
from scipy.io import savemat, wavfile

from gearsim.errors import InputError
from gearsim.io.measured import ReadProblems, list_channels, read_record, read_signal

FS = 25_600.0
N = 512


@pytest.fixture()
def data():
    rng = np.random.default_rng(3)
    return rng.standard_normal(N), rng.standard_normal(N)


def _csv(path, a, b, header="time,acc,tacho"):
    t = np.arange(a.size) / FS
    np.savetxt(path, np.column_stack([t, a, b]), delimiter=",", header=header, comments="",
               fmt="%.17g")
    return path


def _uff(path, a, b):
    sets = [pyuff.prepare_58(
        binary=0, id1=name, id2="", id3="", id4="", id5="", func_type=1, rsp_node=1,
        rsp_dir=3, ref_node=0, ref_dir=0, ord_data_type=4, num_pts=y.size,
        abscissa_spacing=1, abscissa_min=0.0, abscissa_inc=1.0 / FS,
        x=np.arange(y.size) / FS, data=y, orddenom_spec_data_type=0)
        for name, y in (("acc", a), ("tacho", b))]
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


def _compress(plain, kind, target):
    raw = plain.read_bytes()
    if kind == "zip":
        with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as zf:
            zf.writestr(plain.name, raw)
    else:
        target.write_bytes({"gzip": gzip.compress, "bz2": bz2.compress,
                            "xz": lzma.compress}[kind](raw))
    return target


SUFFIX = {"gzip": ".gz", "bz2": ".bz2", "xz": ".xz", "zip": ".zip"}


@pytest.mark.parametrize("kind", ["gzip", "bz2", "xz", "zip"])
@pytest.mark.parametrize("text", ["csv", "uff"])
def test_compressed_text_reads_as_plain(tmp_path, data, kind, text):
    a, b = data
    plain = (_csv if text == "csv" else _uff)(tmp_path / f"rec.{text}", a, b)
    packed = _compress(plain, kind, tmp_path / ("packed" + SUFFIX[kind] if kind == "zip"
                                                 else f"rec.{text}{SUFFIX[kind]}"))
    ref = read_record(plain)
    got = read_record(packed)
    assert got.channels == ref.channels == ("acc", "tacho")
    for c in ref.channels:
        assert_array_equal(got.data[c], ref.data[c])
    assert got.fs == ref.fs and got.fmt == text and got.compression == kind
    assert ref.compression is None
    # CSV is written with %.17g (exact); ASCII UFF with 12 significant digits
    assert_allclose(got.data["acc"], a, rtol=0.0 if text == "csv" else 1e-11)


def test_gzip_stream_with_a_plain_csv_name(tmp_path, data):
    """The content decides: a gzip stream saved as rec.csv is decompressed."""
    a, b = data
    plain = _csv(tmp_path / "plain.csv", a, b)
    disguised = tmp_path / "rec.csv"
    disguised.write_bytes(gzip.compress(plain.read_bytes()))
    s = read_signal(disguised, channel="acc")
    assert_array_equal(s.data, read_signal(plain, channel="acc").data)
    assert s.compression == "gzip"
    # fmt overrides the inner format's name: a .gz without an inner extension
    bare = tmp_path / "rec.gz"
    bare.write_bytes(gzip.compress(plain.read_bytes()))
    with pytest.raises(InputError, match=r"extension '\(none\)' \(inside the gzip stream: 'rec'\)"):
        read_record(bare)
    assert_array_equal(read_record(bare, fmt="csv").data["tacho"], b)


@pytest.mark.parametrize("kind", ["wav", "mat", "tdms", "nc"])
def test_compressed_binary_formats(tmp_path, data, kind):
    a, _ = data
    p = tmp_path / f"rec.{kind}"
    if kind == "wav":
        wavfile.write(p, int(FS), a)
        name = "0"
    elif kind == "mat":
        savemat(p, {"acc": a, "fs": FS})
        name = "acc"
    elif kind == "tdms":
        with TdmsWriter(str(p)) as w:
            w.write_segment([ChannelObject("g", "acc", a, properties={"wf_increment": 1 / FS})])
        name = "acc"
    else:
        xr.Dataset({"acc": ("time", a)}, coords={"time": np.arange(a.size) / FS}).to_netcdf(
            p, engine="h5netcdf")
        name = "acc"
    for comp in ("gzip", "zip"):
        q = _compress(p, comp, tmp_path / f"rec.{kind}{SUFFIX[comp]}")
        s = read_signal(q, channel=name)
        assert_array_equal(s.data, a)
        assert s.fs == pytest.approx(FS, rel=1e-9)
    assert sorted(x.name for x in tmp_path.iterdir()) == sorted(
        [p.name, f"rec.{kind}.gz", f"rec.{kind}.zip"])  # no temporary copy left behind


def test_zip_with_several_members_refused(tmp_path, data):
    a, b = data
    p = tmp_path / "two.zip"
    with zipfile.ZipFile(p, "w") as zf:
        zf.writestr("run1.csv", "acc\n1\n2\n")
        zf.writestr("run2.csv", "acc\n3\n4\n")
    with pytest.raises(InputError, match=r"holds 2 members \['run1.csv', 'run2.csv'\]") as e:
        read_record(p, fs=FS)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize("damage", ["truncated", "garbage"])
def test_corrupt_gzip_refused_nothing_written(tmp_path, data, damage):
    a, b = data
    packed = gzip.compress(_csv(tmp_path / "plain.csv", a, b).read_bytes())
    p = tmp_path / "rec.csv.gz"
    p.write_bytes(packed[: len(packed) // 2] if damage == "truncated"
                  else packed[:10] + b"\x00garbage" * 50)
    before = sorted(tmp_path.iterdir())
    with pytest.raises(InputError, match=r"^file = .*rec\.csv\.gz: cannot be decompressed as "
                       "gzip") as e:
        read_record(p)
    assert "\n" not in str(e.value)
    assert sorted(tmp_path.iterdir()) == before


@pytest.mark.parametrize("sep", [",", ";", "\t", " ", "   "])
def test_headerless_csv_keeps_its_first_row(tmp_path, sep):
    p = tmp_path / "rec.txt"
    p.write_text(sep.join(["1.5", "-2"]) + "\n" + sep.join(["3", "4e-3"]) + "\n"
                 + sep.join(["5", "6"]) + "\n")
    r = read_record(p, fs=FS)
    assert r.channels == ("0", "1")
    assert_array_equal(r.data["0"], [1.5, 3.0, 5.0])
    assert_array_equal(r.data["1"], [-2.0, 4e-3, 6.0])


def test_delimiters_and_decimal_comma(tmp_path, data):
    a, b = data
    rows = np.column_stack([a, b])
    for name, sep in (("semi.csv", ";"), ("tab.txt", "\t"), ("ws.txt", " ")):
        p = tmp_path / name
        np.savetxt(p, rows, delimiter=sep, header=f"acc{sep}tacho", comments="", fmt="%.17g")
        r = read_record(p, fs=FS)
        assert r.channels == ("acc", "tacho"), name
        assert_array_equal(r.data["acc"], a)
        assert_array_equal(r.data["tacho"], b)
    p = tmp_path / "euro.csv"
    p.write_text("Zeit [s];Beschl. [m/s^2]\n0;1,25\n0,001;-2,5\n0,002;3\n")
    r = read_record(p)
    assert r.channels == ("Beschl.",)
    assert_array_equal(r.data["Beschl."], [1.25, -2.5, 3.0])
    assert r.units == {"Beschl.": "m/s^2"}
    assert r.fs == pytest.approx(1000.0)


def test_comment_metadata(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.csv"
    body = "\n".join(f"{float(x)!r},{float(y)!r}" for x, y in zip(a, b, strict=True))
    p.write_text(f"# bench: FZG back-to-back\n# fs: 25.6 kHz\n# rpm = 1480\n"
                 f"# units = m/s^2\nacc,tacho\n{body}\n")
    r = read_record(p)
    assert r.fs == FS and r.fs_source == "file"
    assert r.metadata["rpm"] == 1480.0
    assert r.metadata["fs"] == "25.6 kHz"
    assert r.metadata["bench"] == "FZG back-to-back"
    assert r.units == {"acc": "m/s^2", "tacho": "m/s^2"}
    assert read_signal(p, channel="acc").metadata["rpm"] == 1480.0
    # a rate in samples per second, one unit per column, a numpy-style commented header
    q = tmp_path / "daq.txt"
    np.savetxt(q, np.column_stack([a, b]), header="sample_rate = 25600 S/s\nunits = g, V\n"
               "acc tacho", fmt="%.17g")
    r = read_record(q)
    assert r.fs == FS and r.channels == ("acc", "tacho")
    assert r.units == {"acc": "g", "tacho": "V"}
    assert_array_equal(r.data["tacho"], b)
    # a rate that is not a frequency is refused by name
    bad = tmp_path / "bad.csv"
    bad.write_text("# fs = 3 mm\nacc\n1\n2\n")
    with pytest.raises(InputError, match="comment fs"):
        read_record(bad)


def test_all_channels_by_default_and_a_chosen_subset(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.mat"
    savemat(p, {"acc": a, "tacho": b, "mic": a + b, "fs": FS})
    r = read_record(p)
    assert set(r.channels) == {"acc", "tacho", "mic"} and r.fs == FS
    sub = read_record(p, channels=["mic", "acc"])
    assert sub.channels == ("mic", "acc")
    assert_array_equal(sub.data["mic"], a + b)
    # TDMS: the unique short names, without the "group/channel" aliases
    q = tmp_path / "rec.tdms"
    props = {"wf_increment": 1 / FS, "unit_string": "m/s^2"}
    with TdmsWriter(str(q)) as w:
        w.write_segment([ChannelObject("bench", "acc", a, properties=props),
                         ChannelObject("bench", "tacho", b,
                                       properties={"wf_increment": 1 / FS})])
    r = read_record(q)
    assert r.channels == ("acc", "tacho")
    assert r.units == {"acc": "m/s^2", "tacho": None}
    assert "bench/acc" in list_channels(q)
    assert_array_equal(read_record(q, channels=["bench/tacho"]).data["bench/tacho"], b)


def test_one_message_lists_every_problem(tmp_path, data):
    a, _ = data
    p = tmp_path / "rec.csv"
    np.savetxt(p, np.column_stack([a, a]), delimiter=",", header="acc,tacho", comments="")
    with pytest.raises(ReadProblems) as e:
        read_record(p, channels=["acc", "speed", "rpm"])
    msg = str(e.value)
    assert "\n" not in msg
    parts = msg.split("; ")
    assert parts[0] == "channel = speed: not in rec.csv"
    assert parts[1] == "channel = rpm: not in rec.csv (available: ['acc', 'tacho'])"
    assert isinstance(e.value, InputError)
    assert [q.parameter for q in e.value.problems] == ["channel", "channel"]
    # a record needs no rate (fs None); one signal does, reported with the other problems
    assert read_record(p).fs is read_record(p).fs_source is None
    with pytest.raises(ReadProblems, match=r"^channel = speed: .*; fs = None: must be given: "
                       r"rec.csv stores no sampling rate$"):
        read_signal(p, channel="speed")
    # bad user values are reported with the file's problems
    with pytest.raises(ReadProblems, match=r"^fs = -1: must be a number in \[0.001, 1e\+09\] Hz; "
                       r"channel = x: not in rec.csv; available"):
        read_record(p, channels=["x"], fs=-1)
    with pytest.raises(ReadProblems, match=r"fmt = xls: must be one of .*; file = .*nope"):
        read_record(tmp_path / "nope.csv", fmt="xls")
    # one problem alone stays a plain InputError with its own parameter
    with pytest.raises(InputError) as one:
        read_signal(p, channel="speed", fs=FS)
    assert type(one.value) is InputError and one.value.parameter == "channel"


def test_short_records_read_zero_samples_refused(tmp_path):
    p = tmp_path / "one.csv"
    p.write_text("acc,tacho\n0.5,1\n")
    r = read_record(p, fs=FS)
    assert_array_equal(r.data["acc"], [0.5])
    q = tmp_path / "one.wav"
    wavfile.write(q, int(FS), np.array([0.25], dtype=np.float32))
    assert read_signal(q).data.tolist() == [0.25]
    e = tmp_path / "header_only.csv"
    e.write_text("# fs = 100\nacc\n")
    with pytest.raises(InputError, match="no data row"):
        read_record(e)
    z = tmp_path / "zero.nc"
    xr.Dataset({"acc": ("time", np.zeros(0))}, coords={"time": np.zeros(0)},
               attrs={"fs": FS}).to_netcdf(z, engine="h5netcdf")
    with pytest.raises(InputError, match=r"zero.nc: acc = 0 samples: must hold >= 1 sample"):
        read_record(z)


def test_drop_nonfinite_reports_leading_and_trailing_runs(tmp_path, data):
    a, b = data
    p = tmp_path / "rec.csv"
    _csv(p, a, b)
    with open(p, "a") as fh:
        fh.write(f"{N / FS!r},0.5,\n")  # the last row cut short: tacho missing
    lines = p.read_text().splitlines()
    lines[1] = lines[1].rsplit(",", 2)[0] + ",nan," + lines[1].rsplit(",", 1)[1]  # acc[0]
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(ReadProblems) as e:
        read_record(p)
    assert "column 'acc' data row 1 = missing/NaN" in str(e.value)
    assert f"column 'tacho' data row {N + 1} = missing/NaN" in str(e.value)
    r = read_record(p, drop_nonfinite=True)
    assert_array_equal(r.data["acc"], a[1:])  # both channels cut to rows 1..N-1: aligned
    assert_array_equal(r.data["tacho"], b[1:])
    d = r.dropped["acc"]
    assert (d.count, d.nonfinite, d.first, d.last, d.kept) == (2, 1, 0, N, (1, N))
    assert r.dropped["tacho"].nonfinite == 1 and r.dropped["tacho"].first == 0
    assert r.to_dict()["channels"]["acc"]["dropped"]["kept"] == [1, N]
    assert read_signal(p, channel="tacho", drop_nonfinite=True).dropped.last == N


def test_drop_nonfinite_refuses_interior_gaps(tmp_path, data):
    a, _ = data
    a = a.copy()
    a[[0, 100, 200]] = np.nan
    p = tmp_path / "gap.mat"
    savemat(p, {"acc": a, "fs": FS})
    with pytest.raises(InputError, match=r"gap.mat: acc\[100\] = nan: must be finite: "
                       r"drop_nonfinite drops only leading and trailing runs \(2 non-finite"):
        read_record(p, drop_nonfinite=True)
    with pytest.raises(InputError, match=r"acc\[0\]"):
        read_record(p)
    a[:] = np.nan
    savemat(p, {"acc": a, "fs": FS})
    with pytest.raises(InputError, match="no finite sample left"):
        read_record(p, drop_nonfinite=True)


def test_csv_row_errors_name_the_line(tmp_path):
    p = tmp_path / "rec.csv"
    p.write_text("# fs = 100\nacc,tacho\n1,2\n3,4,5\n")
    with pytest.raises(InputError, match="line 4 holds 3 fields, the rows above 2"):
        read_record(p)
    p.write_text("# fs = 100\nacc,tacho\n1,2\n3,oops\n")
    with pytest.raises(InputError, match=r"column 'tacho' data row 2 = oops: must be a number "
                       r"\(line 4\)"):
        read_record(p)
    p.write_text("# fs = 100\nacc,tacho\n1,2,\n3,4,\n")  # a delimiter closing every row
    assert read_record(p).channels == ("acc", "tacho")


def test_mixed_rates_need_a_choice(tmp_path, data):
    a, b = data
    q = tmp_path / "rec.tdms"
    with TdmsWriter(str(q)) as w:
        w.write_segment([ChannelObject("g", "acc", a, properties={"wf_increment": 1 / FS}),
                         ChannelObject("g", "tacho", b[:64], properties={"wf_increment": 1e-3})])
    with pytest.raises(InputError, match="have different sampling rates"):
        read_record(q)
    r = read_record(q, channels=["tacho"])
    assert r.fs == pytest.approx(1000.0) and r.data["tacho"].size == 64


def _analyze(capsys, *args) -> tuple[int, str, str]:
    from gearsim import cli

    code = cli.run(["analyze", *map(str, args)])
    got = capsys.readouterr()
    return code, got.out, got.err.strip()


def test_analyze_a_record_without_a_rate(tmp_path, capsys, data):
    """Statistics need nothing, the spectrum is in cycles/sample: no --fs is no refusal."""
    a, b = data
    p = tmp_path / "rec.csv"
    np.savetxt(p, np.column_stack([a, b]), delimiter=",", header="acc,tacho", comments="")
    code, out, err = _analyze(capsys, p, "--channel", "acc")
    assert code == 0, err
    assert "fs unknown (frequencies in cycles/sample)" in out and "skipped shaft: needs a " \
        "sampling rate" in out
    assert f"RMS {np.sqrt(np.mean((a - a.mean()) ** 2)):.5g}" in out


@pytest.mark.parametrize("args,message", [
    (["--tacho", "speed"], "--tacho = speed: not in rec.csv; available: ['acc', 'tacho']"),
    (["--tacho", "speed", "--channel", "acc"], "--tacho = speed: not in rec.csv; available"),
    (["--tacho", "acc", "--channel", "acc"], "--tacho = acc: is also a --channel"),
    (["--max-order", "1001"], "--max-order = 1001: must be 1 to 1000"),
    (["--format", "xls"], "--format = xls: must be one of ['csv', 'mat', 'netcdf'"),
])
def test_analyze_bad_tacho_and_orders_refused_in_one_line(tmp_path, capsys, data, args, message):
    a, b = data
    p = tmp_path / "rec.csv"
    np.savetxt(p, np.column_stack([a, b]), delimiter=",", header="acc,tacho", comments="")
    out = tmp_path / "t.csv"
    code, text, err = _analyze(capsys, p, "--fs", FS, *args, "--out", out)
    assert code == 2 and text == "" and not out.exists()
    assert err.startswith(f"gearsim: error: {message}") and "\n" not in err, err


def test_analyze_tacho_as_the_only_channel_refused(tmp_path, capsys, data):
    p = tmp_path / "one.csv"
    np.savetxt(p, data[1], header="tacho", comments="")
    code, text, err = _analyze(capsys, p, "--fs", FS, "--tacho", "tacho")
    assert code == 2 and text == ""
    assert err == "gearsim: error: --tacho = tacho: is the only channel of one.csv: no " \
        "vibration channel is left to analyse"


def test_unit_in_the_header_is_not_part_of_the_channel_name(tmp_path):
    # "a1 [g]" and "a2 (V)" are channels a1 and a2 in g and V; the time column "t [ms]"
    # in milliseconds gives fs = 1 / 0.5 ms = 2000 Hz
    p = tmp_path / "units.csv"
    p.write_text("t [ms],a1 [g],a2 (V)\n0,1,4\n0.5,2,5\n1.0,3,6\n")
    r = read_record(p)
    assert r.channels == ("a1", "a2")
    assert_array_equal(r.data["a1"], [1.0, 2.0, 3.0])
    assert r.units == {"a1": "g", "a2": "V"}
    assert r.fs == pytest.approx(2000.0)
