"""Batches: many files x channels in one process, labels, separability, one error message."""

import gzip
import json
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
