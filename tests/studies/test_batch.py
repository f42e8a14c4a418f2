"""Batches: many files x channels in one process, labels, separability, one error message."""

import gzip
import json
import os
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from gearsim import cli
from gearsim.errors import InputError
from gearsim.studies.batch import run_batch
from gearsim.studies.diagnostic import indicator_auc, separability_report

FS = 5000.0
N = 4000


def _signal(rng, impacted):
    x = np.sin(2 * np.pi * 300 * np.arange(N) / FS) + 0.2 * rng.standard_normal(N)
    if impacted:
        x[::250] += 4.0
    return x


def _write(folder, n_files=20, channels=4, gz_every=5):
    rng = np.random.default_rng(0)
    paths = []
    for i in range(n_files):
        kind = "impacted" if i % 2 else "healthy"
        cols = np.column_stack([_signal(rng, kind == "impacted") for _ in range(channels)])
        text = f"# fs = {FS:g}\n" + ",".join(f"a{j}" for j in range(channels)) + "\n" + "\n".join(
            ",".join(f"{v:.6g}" for v in row) for row in cols) + "\n"
        p = folder / f"{kind}_{i:02d}.csv"
        if gz_every and i % gz_every == 0:
            p = p.with_name(p.name + ".gz")
            p.write_bytes(gzip.compress(text.encode()))
        else:
            p.write_text(text)
        paths.append(p)
    return paths


def test_batch_20_files_4_channels_in_one_process(tmp_path):
    _write(tmp_path)
    ds = run_batch([str(tmp_path / "*.csv*")], label_pattern=r"^(healthy|impacted)_")
    assert ds.sizes["record"] == 80
    assert ds.attrs["mode"] == "serial"
    assert ds["kurtosis"].attrs["units"] == "1" and ds["rms"].attrs["units"] == "signal"
    assert set(ds["fs_provenance"].values) == {"file"}
    rep = json.loads(ds.attrs["separability"])
    top = {r["indicator"]: r for r in rep["indicators"]}
    assert top["kurtosis"]["auc"] == 1.0 and top["kurtosis"]["direction"] == "higher"
    assert rep["classifier"]["auc"] == pytest.approx(1.0)


def test_indicator_auc_and_report_on_any_table():
    y = np.array(["a"] * 5 + ["b"] * 5)
    x = np.arange(10.0)
    r = indicator_auc(x, y == "b")
    assert r == {"auc": 1.0, "direction": "higher", "raw_auc": 1.0}
    assert indicator_auc(-x, y == "b")["direction"] == "lower"
    rep = separability_report({"x": x, "noise": [1, 2, 1, 2, 1, 2, 1, 2, 1, 2]}, y, folds=2)
    assert rep["indicators"][0]["indicator"] == "x" and rep["classifier"]["n"] == 10
    with pytest.raises(InputError, match="two classes"):
        separability_report({"x": x}, ["a"] * 10)


def _run(monkeypatch, capsys, *args):
    monkeypatch.setattr(sys, "argv", ["gearsim", *map(str, args)])
    code = 0
    try:
        cli.main()
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_batch_table_and_report(tmp_path, monkeypatch, capsys):
    _write(tmp_path, n_files=6, channels=2, gz_every=0)
    code, out, err = _run(monkeypatch, capsys, "analyze", tmp_path / "healthy_*.csv",
                          tmp_path / "impacted_*.csv", "--label-pattern",
                          r"^(healthy|impacted)_", "--out", tmp_path / "t.nc", "--report",
                          tmp_path / "rep", "--teeth", 32, 80)
    assert code == 0, err
    ds = xr.open_dataset(tmp_path / "t.nc", engine="h5netcdf")
    assert ds.sizes["record"] == 12 and "kurtosis" in ds
    assert (tmp_path / "rep" / "separability.json").exists()
    assert "AUC" in out and "skipped shaft" in out


def test_cli_bad_file_among_many_one_message_nothing_written(tmp_path, monkeypatch, capsys):
    paths = _write(tmp_path, n_files=4, channels=2, gz_every=0)
    paths[1].write_text("a0,a1\n1,2\nx,y\n")
    code, out, err = _run(monkeypatch, capsys, "analyze", *paths, tmp_path / "missing.csv",
                          "--fs", FS, "--out", tmp_path / "t.csv")
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gearsim: error: input = 2 problems")
    assert "missing.csv" in lines[0] and paths[1].name in lines[0]
    assert not (tmp_path / "t.csv").exists()


def test_cli_more_workers_than_files_one_line_nothing_read(tmp_path, monkeypatch, capsys):
    paths = _write(tmp_path, n_files=2, channels=2, gz_every=0)
    code, out, err = _run(monkeypatch, capsys, "analyze", *paths, "--fs", FS, "--workers",
                          "3", "--out", tmp_path / "t.csv")
    assert code == 2
    assert err.strip() == ("gearsim: error: --workers = 3: must be <= 2, the files to "
                           "analyse (a worker more would have nothing to do)")
    assert not (tmp_path / "t.csv").exists() and not (tmp_path / "t.csv.parts").exists()


@pytest.mark.parametrize("names, labels, expected", [
    (["b30.csv", "h30.csv", "x1.csv", "x2.csv", "x3.csv", "x4.csv"], "^(b|h)30",
     "--label-pattern = ^(b|h)30: 4 of 6 files do not match: x1.csv, x2.csv, x3.csv, ..."),
    (["h30.csv", "h31.csv"], "^(h)3", "--label-pattern = ^(h)3: one class (h) for the 2 "
     "files: needs at least two classes to score separability"),
    (["b30.csv", "h30.csv"], "file,channel,label\nb30.csv,,b\nh30.csv,a1,b\n",
     "--labels = LAB: one class (b) for the 2 files: needs at least two classes to score "
     "separability"),
    (["b30.csv", "h30.csv"], "file,label\nb30.csv,b\n",
     "--labels = LAB: 1 of 2 files have no label: h30.csv")])
def test_cli_label_problems_refused_before_any_file_is_read(tmp_path, monkeypatch, capsys,
                                                            names, labels, expected):
    """Labels from names or a CSV are known before any file is read: one short line, exit
    2, no OUT.parts made, although no file is even a record (before: the whole batch was
    analysed first, then 'input = N problems', each file's mismatch once per channel)."""
    for n in names:
        (tmp_path / n).write_text("not a record\n")
    option = ["--label-pattern", labels]
    if labels.startswith("file,"):  # a labels CSV, by name and by channel
        (tmp_path / "lab.csv").write_text(labels)
        option = ["--labels", tmp_path / "lab.csv"]
        expected = expected.replace("LAB", str(tmp_path / "lab.csv"))
    code, _, err = _run(monkeypatch, capsys, "analyze", *(tmp_path / n for n in names),
                        *option, "--out", tmp_path / "t.csv")
    assert code == 2
    assert err.strip() == f"gearsim: error: {expected}"
    assert not (tmp_path / "t.csv.parts").exists()


def test_cli_csv_table_columns_with_units(tmp_path, monkeypatch, capsys):
    _write(tmp_path, n_files=2, channels=2, gz_every=0)
    code, _, err = _run(monkeypatch, capsys, "analyze", tmp_path / "*.csv", "--out",
                        tmp_path / "t.csv")
    assert code == 0, err
    head, *rows = (tmp_path / "t.csv").read_text().splitlines()
    assert len(rows) == 4 and "rms [signal]" in head and "kurtosis [1]" in head


def test_cli_startup_and_run_time(tmp_path):
    """One 100k-sample CSV, statistics and spectrum: the wall-clock time is reported."""
    p = tmp_path / "one.csv"
    rng = np.random.default_rng(3)
    p.write_text("acc\n" + "\n".join(f"{v:.5g}" for v in rng.standard_normal(100_000)) + "\n")
    r = subprocess.run([sys.executable, "-m", "gearsim.cli", "analyze", str(p), "--fs",
                        "25600"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "statistics" in r.stdout


# -- resumable batches (OUT.parts) -------------------------------------------------------

def _counting(monkeypatch, fail_at=None):
    """Count the calls of ``analyze_file``; the call number ``fail_at`` is a Ctrl-C."""
    from gearsim.studies import batch

    calls = []
    real = batch.analyze_file

    def counted(path, **kw):
        calls.append(path)
        if len(calls) == fail_at:
            raise KeyboardInterrupt
        return real(path, **kw)

    monkeypatch.setattr(batch, "analyze_file", counted)
    return calls


def _mtimes(folder):
    return {p.name: p.stat().st_mtime_ns for p in folder.glob("*.json")}


def test_cli_interrupted_serial_batch_resumes_to_the_same_table(tmp_path, monkeypatch, capsys):
    """Ctrl-C in the 4th of 8 files: exit 130, one line, 3 parts kept, no table, no lock;
    the rerun analyses only the 5 others (parts untouched) and writes the table of an
    uninterrupted run, byte for byte."""
    from gearsim.studies.sweep_run import lock_path, parts_dir

    data = tmp_path / "data"
    data.mkdir()
    _write(data, n_files=8, channels=1, gz_every=0)
    ref = tmp_path / "ref.csv"
    code, _, err = _run(monkeypatch, capsys, "analyze", data / "*.csv", "--out", ref)
    assert code == 0, err

    out = tmp_path / "t.csv"
    parts = parts_dir(out)
    calls = _counting(monkeypatch, fail_at=4)
    code, stdout, err = _run(monkeypatch, capsys, "analyze", data / "*.csv", "--out", out)
    assert code == 130 and err.strip().splitlines() == ["gearsim: interrupted"]
    assert stdout == "" and not out.exists() and not lock_path(out).exists()
    finished = _mtimes(parts)
    assert len(finished) == 3 and not list(tmp_path.rglob(".*.tmp"))

    calls = _counting(monkeypatch)
    code, stdout, err = _run(monkeypatch, capsys, "analyze", data / "*.csv", "--out", out)
    assert code == 0, err
    assert len(calls) == 5 and "(8 rows; serial; 3 files resumed from t.csv.parts)" in stdout
    assert {k: v for k, v in _mtimes(parts).items() if k in finished} == finished
    assert len(_mtimes(parts)) == 8 and not lock_path(out).exists()
    assert out.read_text() == ref.read_text()


def test_dask_batch_interrupted_resumes_serially_identical_netcdf(tmp_path):
    """A Ctrl-C on the client after the first part of a 2-worker batch keeps the parts;
    a serial rerun (same keys) computes only the rest; the NetCDF table equals a fresh
    serial one."""
    from gearsim.studies.sweep_run import lock_path, parts_dir

    _write(tmp_path, n_files=8, channels=1, gz_every=0)
    files = [str(tmp_path / "*.csv")]
    ref = run_batch(files, out=tmp_path / "ref.nc")
    assert ref.attrs["resumed"] == 0 and ref.sizes["record"] == 8

    out = tmp_path / "t.nc"
    written = []

    def interrupt(file, part):
        written.append(part)
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_batch(files, out=out, workers=2, hook=interrupt)
    parts = parts_dir(out)
    finished = _mtimes(parts)
    assert len(finished) == 1 and written[0].name in finished
    assert not out.exists() and not lock_path(out).exists()

    ds = run_batch(files, out=out, hook=lambda f, p: written.append(p))
    assert ds.attrs["resumed"] == 1 and len(written) == 1 + 7
    assert {k: v for k, v in _mtimes(parts).items() if k in finished} == finished
    a = xr.load_dataset(out, engine="h5netcdf")
    b = xr.load_dataset(tmp_path / "ref.nc", engine="h5netcdf")
    xr.testing.assert_identical(a, b)


def test_changed_file_is_recomputed_others_resumed(tmp_path, monkeypatch):
    paths = _write(tmp_path, n_files=4, channels=1, gz_every=0)
    out = tmp_path / "out" / "t.csv"
    run_batch([str(tmp_path / "*.csv")], out=out)
    parts = _mtimes(out.parent / "t.csv.parts")
    calls = _counting(monkeypatch)
    st = paths[1].stat()
    os.utime(paths[1], ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))  # touched, same size
    ds = run_batch([str(tmp_path / "*.csv")], out=out)
    assert calls == [str(paths[1])] and ds.attrs["resumed"] == 3
    st = paths[2].stat()  # new content of another size, the old mtime
    paths[2].write_text(paths[2].read_text().replace("# fs = 5000", "# fs = 2500.0"))
    os.utime(paths[2], ns=(st.st_atime_ns, st.st_mtime_ns))
    ds = run_batch([str(tmp_path / "*.csv")], out=out)
    assert calls[1:] == [str(paths[2])] and ds.attrs["resumed"] == 3
    peak = ds["spectrum_peak_frequency_hz"].values[list(ds["file"].values).index(
        str(paths[2]))]
    assert peak == pytest.approx(150, rel=0.02)  # the 300 Hz tone read at half the rate
    now = _mtimes(out.parent / "t.csv.parts")
    assert len(now) == 6 and all(now[k] == v for k, v in parts.items())  # stale ones kept
    calls.clear()  # other options: every file again
    run_batch([str(tmp_path / "*.csv")], out=out, speed=25.0)
    assert len(calls) == 4


def test_lock_refuses_a_second_batch_on_the_same_out(tmp_path, monkeypatch, capsys):
    from gearsim.studies.sweep_run import lock_path, parts_dir, store_lock

    _write(tmp_path, n_files=2, channels=1, gz_every=0)
    out = tmp_path / "t.csv"
    with store_lock(out, owner="batch"):
        code, _, err = _run(monkeypatch, capsys, "analyze", tmp_path / "*.csv", "--out", out)
        assert code == 2
        assert err.strip().splitlines() == [
            f"gearsim: error: --out = {out}: is being written by another batch (pid "
            f"{os.getpid()}; lock file {lock_path(out)})"]
        with pytest.raises(InputError, match="another batch"):
            run_batch([str(tmp_path / "*.csv")], out=out)
    assert not out.exists() and not parts_dir(out).exists()
    code, _, err = _run(monkeypatch, capsys, "analyze", tmp_path / "*.csv", "--out", out)
    assert code == 0, err
